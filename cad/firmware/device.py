"""The :class:`~cad.firmware.spec.DeviceSpec` of a built design (design + report.json + catalog).

Four-bars: the design's linkage, crank range and branch; H11..H33 and the link masses and
COMs of report.json (``links``, from the solids). Pantograph / twin pantograph: the design's
5-bar(s), the working modes read off the home pose (FK assembly mode, elbow signs) and the
body masses and COMs of report.json ``bodies``. Lengths leave in metres.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from cad import tolerances as tol
from cad.errors import DesignError
from cad.firmware import reference as ref
from cad.firmware.spec import (
    DeviceSpec,
    body_from_report,
    encoder_zero,
    gravity_vector,
    motor_data,
)
from cad.kinematics import fivebar as fb5


def _fourbar_params(design, report: dict) -> dict:
    fb = design.linkage
    mm = 1e-3
    return {"l1": fb.l1_mm * mm, "l2": fb.l2_mm * mm, "l3": fb.l3_mm * mm, "l4": fb.l4_mm * mm,
            "l5": fb.l5_mm * mm, "le": fb.le_mm * mm, "phi_e": fb.phi_e_rad,
            "branch": float(fb.branch), "q_min": design.phi1_min_rad,
            "q_max": design.phi1_max_rad, "H11": report["H11_kg_m2"],
            "H12": report["H12_kg_m2"], "H22": report["H22_kg_m2"], "H33": report["H33_kg_m2"],
            "beta2": math.radians(report["beta2_deg"])}


def _fivebar_params(fb: fb5.FiveBar, home_mm, pre: str = "") -> tuple[dict, np.ndarray]:
    """SI parameters of one 5-bar with the working modes of its pose at ``home_mm``."""
    ik = fb5.ik(fb, np.asarray(home_mm, dtype=float)[None, :])
    fb5.require_ok(ik)
    pose = fb5.fk(fb, ik.q_rad, int(fb5.assembly_mode(ik)[0]))
    asm, ml, mr = ref.working_modes(fb, pose)
    p = {"b1x": fb.base_left_mm[0], "b1y": fb.base_left_mm[1], "b2x": fb.base_right_mm[0],
         "b2y": fb.base_right_mm[1], "l2l": fb.proximal_left_mm, "l2r": fb.proximal_right_mm,
         "l3l": fb.distal_left_mm, "l3r": fb.distal_right_mm}
    out = {pre + k: v * 1e-3 for k, v in p.items()}
    out.update({pre + "assembly": float(asm), pre + "mode_l": float(ml), pre + "mode_r": float(mr)})
    return out, ik.q_rad[0]


def _kind(design) -> str:
    if design.family == "pantograph":
        return "fivebar"
    if design.family == "twin-pantograph":
        return "twin"
    if hasattr(design, "linkage"):
        return "fourbar"
    raise DesignError("--formats", f"firmware is generated for four-bars, the pantograph, "
                      f"the twin pantograph and the PowerMouse, not {design.family!r}")


def device_spec(design, report: dict, design_hash: str, version: str, device=None) -> DeviceSpec:
    """The DeviceSpec of ``design`` built into ``report`` (module docstring). The motor
    constants, rotor inertia and encoder count are the resolved device's
    (:func:`cad.device.resolve_device`; resolved here when ``device`` is None)."""
    from cad.device import resolve_device

    kind = _kind(design)
    opts = design.firmware
    device = device if device is not None else resolve_device(design)
    motor = motor_data(device.motor.spec)
    if device.motor.from_motor_table:  # the header names the motor the device uses
        motor = replace(motor, key=device.motor.name)
    rotor = device.motor.rotor_inertia_kg_m2
    if kind == "fourbar":
        params = _fourbar_params(design, report)
        params["q_slack"] = math.pi / device.encoder.counts_per_rev  # half a count at the range ends
        q_home = (0.5 * (design.phi1_min_rad + design.phi1_max_rad),)
        bodies = {k: body_from_report(report["links"][k]) for k in ("crank", "coupler", "rocker")}
        n_joints, n_task = 1, 2
    else:
        bodies = {k: body_from_report(v) for k, v in report["bodies"].items()}
        home = design.workspace.get("home_mm", design.workspace["center_mm"])
        if kind == "fivebar":
            params, q = _fivebar_params(design.mechanism, home)
            n_joints, n_task = 2, 2
        else:
            tp = design.mechanism
            th = math.radians(design.workspace["home_theta_deg"])
            pin = np.asarray(home) + tp.crank_mm * np.array([math.cos(th), math.sin(th)])
            params, qk = _fivebar_params(tp.knob, home, "knob_")
            pc, qc = _fivebar_params(tp.crank, pin, "crank_")
            params.update(pc, l6=tp.crank_mm * 1e-3, crank_tol=tol.FIRMWARE_CRANK_TOL_M)
            q = np.concatenate([qk, qc])
            n_joints, n_task = 4, 3
        q_home = tuple(float(v) for v in q)
    return DeviceSpec(
        kind=kind, name=design.name, family=design.family, design_hash=design_hash,
        version=version, n_joints=n_joints, n_task=n_task, params=params, q_home_rad=q_home,
        encoder_counts_per_rev=device.encoder.counts_per_rev,
        encoder_direction=tuple(opts.encoder_direction), encoder_zero_rad=encoder_zero(opts, q_home),
        motor=motor, gravity_m_s2=gravity_vector(opts), bodies=bodies, rotor_kg_m2=rotor,
    )
