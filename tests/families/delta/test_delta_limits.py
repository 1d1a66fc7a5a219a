"""The bundled delta meets every default limit (issue 36 §6): ``designs/delta.toml``, three
maxon RE 40 direct drive on the GII-optimal lengths, over its 100 mm cube.

Independent references:

* the force in every direction by brute force: 2000 sampled unit force directions at every
  grid point, each mapped to joint torques by :func:`cad.kinematics.delta.joint_torques_Nm`
  (tau = J^-T f, eq 2) and scaled to |tau|_2 = the catalog's continuous torque of the motor
  the design names (maxon RE 40 data sheet, 187 mN m): a second path through the statics
  beside the datasheet's tau sigma_min(J^T);
* the limits are the design's ``[actuators] force_max_N`` and the default first mode
  (:data:`cad.datasheet.limits.FIRST_MODE_MIN_HZ`, Hoeken paper §III.B.1); the first mode is
  the frame model's, itself checked against an independent model in test_delta_structure.py;
* why not the RE 35: its best force over every reachable candidate of the design's
  ``[optimize]`` grid stays below 1 N (tau sigma_min(J^T), the figure the sampling checks).
"""

from __future__ import annotations

import dataclasses
import itertools
import json
from pathlib import Path

import numpy as np
import pytest

import cad
from cad.data.catalog import get_motor
from cad.datasheet.limits import FIRST_MODE_MIN_HZ
from cad.kinematics.delta import jacobian_rad_per_m, joint_torques_Nm

ROOT = Path(__file__).resolve().parents[3]


def _design():
    return cad.load_design(ROOT / "designs" / "delta.toml")


def sampled_force_in_every_direction_N(d, torque_Nm: float, n_dir: int = 2000) -> float:
    """Smallest over the grid and ``n_dir`` random directions of the force magnitude the
    effector exerts with |tau|_2 = ``torque_Nm`` (N): an upper bound of the exact minimum."""
    u = np.random.default_rng(36).normal(size=(n_dir, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    worst = np.inf
    for P in d.workspace_points():
        t = joint_torques_Nm(d.mechanism, np.repeat(P[None], n_dir, 0), u)  # per unit force
        worst = min(worst, float(np.min(torque_Nm / np.linalg.norm(t, axis=1))))
    return worst


def test_the_bundled_delta_meets_the_force_and_mode_limits_by_its_models():
    from cad.families.delta.datasheet import force_in_every_direction_N
    from cad.families.delta.structure import first_mode

    d = _design()
    tau = get_motor(d.parts.motor).torque_continuous_mNm * 1e-3
    assert tau == pytest.approx(0.187, rel=1e-12)  # maxon RE 40 data sheet, 187 mN m
    exact, _ = force_in_every_direction_N(d, tau)
    sampled = sampled_force_in_every_direction_N(d, tau)
    assert sampled >= exact * (1 - 1e-12) and sampled == pytest.approx(exact, rel=2e-3)
    assert exact >= d.actuators["force_max_N"] == 1.0
    assert exact == pytest.approx(1.2189, abs=5e-5)  # regression pin (docs/families/delta.md: 1.22 N)
    re35 = get_motor("maxon-re35").torque_continuous_mNm * 1e-3  # data sheet, 97.2 mN m
    assert force_in_every_direction_N(d, re35)[0] == pytest.approx(0.6336, abs=5e-5)  # regression pin
    st = first_mode(d.mechanism, np.asarray(d.workspace["center_mm"]), d.parallelogram_width_mm)
    assert st["first_mode_Hz"] >= FIRST_MODE_MIN_HZ == 150.0


def test_no_reachable_candidate_of_the_optimize_grid_gives_1_N_with_the_re35():
    d = _design()
    X = d.workspace_points()
    axes = {k: np.linspace(lo, hi, n) for k, (lo, hi, n) in d.optimize.items()}
    best, n_ok = 0.0, 0
    for vals in itertools.product(*axes.values()):
        J, status = jacobian_rad_per_m(dataclasses.replace(d.mechanism, **dict(zip(axes, vals))), X)
        if np.all(status == 0):
            n_ok += 1
            best = max(best, float(np.linalg.svd(np.swapaxes(J, 1, 2), compute_uv=False)[:, -1].min()))
    f_re35 = best * get_motor("maxon-re35").torque_continuous_mNm * 1e-3
    assert n_ok == 355  # regression pin: the candidates that reach the cube within the joint range
    assert f_re35 < d.actuators["force_max_N"]
    assert f_re35 == pytest.approx(0.675, abs=5e-4)  # regression pin (designs/delta.toml's comment)


@pytest.mark.slow  # a delta build (every pair of solids at 125 points); cheap share above
def test_the_built_delta_datasheet_meets_every_default_limit(tmp_path):
    d = _design()
    out = tmp_path / "delta"
    cad.build_design(d, out, formats="step", fidelity="preview")
    rep = json.loads((out / "report.json").read_text())
    ds = rep["datasheet"]
    assert ds["ok"] is True and ds["warnings"] == []
    limited = {r["key"]: r for r in ds["rows"] if r["limit"]}
    assert set(limited) == {"continuous_force_N", "first_mode_Hz", "max_stress_MPa", "rod_buckling_margin",
                            "overlap_volume_mm3",  # no two solids overlap: 0 mm^3
                            "ball_joint_tilt_max_deg"}  # the rods within the joints' range
    assert all(r["verdict"] == "ok" and r["limit"]["origin"] == "default" for r in limited.values())
    force = limited["continuous_force_N"]
    assert force["limit"]["value"] == d.actuators["force_max_N"] and force["value"] >= 1.0
    tau = get_motor(d.parts.motor).torque_continuous_mNm * 1e-3
    assert force["value"] == pytest.approx(sampled_force_in_every_direction_N(d, tau), rel=2e-3)
    assert limited["first_mode_Hz"]["value"] >= FIRST_MODE_MIN_HZ
    assert rep["overlap_volume_mm3"] == 0.0 and rep["interference"]["collisions"] == []
