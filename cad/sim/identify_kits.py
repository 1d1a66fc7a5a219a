"""What ``hapticad identify`` and ``hapticad bench-log`` need of a kinematic layout (issue 37):
one :class:`IdentifyKit` per layout, given by its :class:`cad.firmware.model.KinematicModel`
(``identification``), so that :mod:`cad.api` dispatches without naming a family.

* :data:`ONE_MOTOR` -- the four-bars (:mod:`cad.sim.identify_device`, :mod:`cad.sim.bench`);
* :data:`FIVEBAR` -- the 5-bar pantograph (:mod:`cad.sim.identify_fivebar`,
  :mod:`cad.sim.bench_fivebar`);
* :func:`joint_kit` and :func:`routine_files` -- the kit and the firmware routine of a family
  identified by the n-motor run (:mod:`cad.sim.identify_joints`): the delta, the twin
  pantograph, the pen; the family gives its ``predict`` and its bench's ``simulate``.

"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np

from cad.design import bounds
from cad.errors import DesignError
from cad.firmware import identify2_c
from cad.isotropy.gii import workspace_half_mm
from cad.sim import bench, bench_fivebar, identify_device, identify_fivebar, identify_joints
from cad.sim.device import device_build

Hook = Callable[..., Any]


@dataclass(frozen=True)
class IdentifyKit:
    """The hooks of one layout.

    n_joints : motors (the log's ``counts_i`` / ``current_A_i`` columns).
    models : the bench's device models, the default first (``bench-log --model``).
    check_build_dir : ``(design, build_dir) -> None``; DesignError naming ``--build-dir``.
    predict_from_build : ``(design, build_dir | None) -> prediction`` (``design_hash``, ``Te_s``).
    identify : ``(prediction, log, path) -> (result dict, plot view | None)``: the view has
        ``t_s`` (N,), ``mask`` (N,), ``tau_meas`` and ``tau_fit`` (N,) or (N, n_joints) N m.
    bench : ``(design, perturb, seed, build_dir | None, model) -> (prediction, t_s, counts,
        currents, truth, extra truth)``.
    """

    n_joints: int
    models: tuple[str, ...]
    check_build_dir: Hook
    predict_from_build: Hook
    identify: Hook
    bench: Hook


# ------------------------------------------------------------------ one motor (four-bars)
def _check_build_dir_1(design, build_dir: Path) -> None:
    device_build(design, Path(build_dir))


def _bench_1(design, p: dict, seed: int, build_dir, model: str):
    folder = device_build(design, None if build_dir is None else Path(build_dir))
    pred = identify_device.predict_from_build(design, folder)
    mjcf = folder / f"{design.name}.xml" if model == "mujoco" else None
    t, counts, cmd, tr = bench.simulate(pred, p, seed, mjcf)
    q_poses = [float(np.quantile(pred.angles(counts), x)) for x in (0.05, 0.5, 0.95)] if len(counts) else []
    extra = {"M11_g_at": {f"{math.degrees(q):.1f}": float(bench.true_apparent_mass_g(pred, tr, q)) for q in q_poses}}
    return pred, t, counts, cmd, tr, extra


ONE_MOTOR = IdentifyKit(1, ("mujoco", "reduced"), _check_build_dir_1, identify_device.predict_from_build,
                        identify_device.identify, _bench_1)


# ------------------------------------------------------------------ the 5-bar
def _check_build_dir_5(design, build_dir: Path) -> None:
    identify_fivebar.build_report(design, Path(build_dir))


def _identify_5(pred, log, path):
    res, f = identify_fivebar.identify(pred, log, path)
    if f is None:
        return res, None
    # the report's plots take one mask per row: rows where a joint was fitted (the other
    # joint's column is NaN where it was not)
    return res, SimpleNamespace(t_s=f.t_s, mask=f.mask.any(axis=1), tau_meas=f.tau_meas, tau_fit=f.tau_fit)


def _bench_5(design, p: dict, seed: int, build_dir, model: str):
    folder, rep = identify_fivebar.build_folder(design, None if build_dir is None else Path(build_dir))
    pred = identify_fivebar.predict(design, rep)
    half_y_m = 1e-3 * workspace_half_mm(design.workspace)[1]
    mjcf = folder / f"{design.name}.xml" if model == "mujoco" else None
    t, counts, cmd, tr = bench_fivebar.simulate(pred, p, seed, half_y_m, mjcf)
    return pred, t, counts, cmd, tr, {}


FIVEBAR = IdentifyKit(2, ("mujoco", "reduced"), _check_build_dir_5, identify_fivebar.predict_from_build, _identify_5,
                      _bench_5)


# ------------------------------------------------------------------ n motors (delta, twin, pen)
def joint_kit(n: int, predict: Hook, simulate: Hook, labels=None, ylabel: str | None = None) -> IdentifyKit:
    """The :class:`IdentifyKit` of an n-motor family benched on its MJCF in MuJoCo:
    ``predict(design, report)`` its prediction, ``simulate(design, pred, perturb, seed, mjcf)``
    its bench run; ``labels``/``ylabel`` name the plots' columns (an over-actuated device's
    independent coordinates; None: per motor)."""
    def check(design, build_dir: Path) -> None:
        identify_fivebar.build_folder(design, Path(build_dir))

    def from_build(design, build_dir=None):
        return predict(design, identify_fivebar.build_folder(design, None if build_dir is None else Path(build_dir))[1])

    def ident(pred, log, path):
        res, f = identify_joints.identify(pred, log, path)
        if f is None:
            return res, None
        return res, SimpleNamespace(t_s=f.t_s, mask=f.mask.any(axis=1), tau_meas=f.tau_meas, tau_fit=f.tau_fit,
                                    labels=labels, ylabel=ylabel)

    def run(design, p: dict, seed: int, build_dir, model: str):
        folder, rep = identify_fivebar.build_folder(design, None if build_dir is None else Path(build_dir))
        pred = predict(design, rep)
        t, counts, cmd, tr = simulate(design, pred, p, seed, folder / f"{design.name}.xml")
        return pred, t, counts, cmd, tr, {}

    return IdentifyKit(n, ("mujoco",), check, from_build, ident, run)


def routine_files(predict: Hook) -> Hook:
    """The firmware model's ``identify`` hook ``(design, report, spec) -> {file: text}``: the
    n-motor routine (:mod:`cad.firmware.identify2_c`) with the plan of ``predict(design,
    report)``; none, with a warning, when the design cannot run it (DesignError)."""
    def files(design, report: dict, spec) -> dict[str, str]:
        try:
            pred = predict(design, report)
        except DesignError as exc:
            bounds.warn(f"firmware: no identify/ routine: {exc}")
            return {}
        return identify2_c.files(spec, pred.plan)

    return files
