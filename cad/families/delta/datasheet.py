"""Datasheet rows of the delta (issue 36 §4): the continuous and peak force in the worst
direction over the workspace grid from the catalog motor's data-sheet torques (f = J^T tau,
eq 2: the force every direction gets with |tau|_2 at the motor limit is tau sigma_min(J^T)),
the apparent mass (eigenvalues of Lambda(x) from the solids), the first structural mode and
the effector compliance at the workspace centre, the moving mass, the largest solid overlap
over the workspace; with the default first-mode limit and, from ``[actuators]
force_max_N``, the force limit (:func:`cad.families.pantograph.limits.pantograph_limits`). No CAD
import."""

from __future__ import annotations

import numpy as np

from cad.data.catalog import get_motor
from cad.datasheet import row
from cad.datasheet.limits import FIRST_MODE_MIN_HZ, MODE_REASON, Limit, with_targets
from cad.families.delta import hardware as hw
from cad.kinematics.delta import jacobian_rad_per_m

#: What changes the delta's force and first mode (the motor and sections are the family's
#: fixed choices in cad/families/delta/hardware.py until the design takes [parts]).
CHANGE = ("mechanism.upper_arm_mm (shorter: more force, stiffer) or the workspace; the motor "
          "and sections: cad/families/delta/hardware.py")


def force_in_every_direction_N(design, torque_Nm: float) -> tuple[float, list[float]]:
    """(the force the effector exerts in every direction at every workspace point with each
    joint torque vector bounded by |tau|_2 <= ``torque_Nm``: min over the grid of
    torque_Nm * sigma_min(J^T) (J: theta_dot = J x_dot, rad/m, f = J^T tau), the point
    where it is smallest (mm)). Raises KinematicsError naming a point out of reach."""
    X = design.workspace_points()
    J, status = jacobian_rad_per_m(design.mechanism, X)
    if np.any(status != 0):
        from cad.kinematics.delta import ik, require_ok

        require_ok(ik(design.mechanism, X))
    s_min = np.linalg.svd(np.swapaxes(J, 1, 2), compute_uv=False)[:, -1]
    i = int(np.argmin(s_min))
    return float(torque_Nm * s_min[i]), X[i].tolist()


def rows_and_limits(design, report: dict, out_dir=None, simulate_wall: bool = True):
    """(rows, limits, notes) of a delta build report (module docstring)."""
    m = get_motor(hw.MOTOR)
    src = f"{m.description} data sheet (cad.data.catalog: {m.key})"
    fc, at_c = force_in_every_direction_N(design, m.torque_continuous_mNm * 1e-3)
    fp, _ = force_in_every_direction_N(design, m.torque_peak_mNm * 1e-3)
    a, s = report.get("apparent_mass") or {}, report.get("structure") or {}
    itf = report.get("interference") or {}
    rows = [
        row("continuous_force_N", "continuous force in every direction", fc, "N",
            f"min over the workspace grid of T_cont sigma_min(J^T) (eq 2), at {at_c} mm; "
            f"T_cont {m.torque_continuous_mNm:g} mN m, {src}"),
        row("peak_force_N", "peak force in every direction", fp, "N",
            f"as the continuous force with the peak torque {m.torque_peak_mNm:g} mN m, {src}"),
        row("apparent_mass_max_g", "apparent mass, worst direction", a.get("Lambda_max_eig_g"), "g",
            f"largest eigenvalue of Lambda(x) from the solids and the rotors over the grid, at "
            f"{a.get('at_max_mm')} mm (eq 1)"),
        row("apparent_mass_min_g", "apparent mass, best direction", a.get("Lambda_min_eig_g"), "g",
            "smallest eigenvalue of Lambda(x) over the grid"),
        row("first_mode_Hz", "first structural mode (workspace centre)", s.get("first_mode_Hz"), "Hz",
            "3-D beam and truss frame of the solids' sections: " + str(s.get("boundary", ""))),
        row("compliance_max_um_per_N", "effector compliance, worst direction",
            s.get("compliance_max_um_per_N"), "um/N", "the same frame model, static"),
        row("moving_mass_g", "moving mass", report.get("moving_mass_g"), "g",
            "every body but the base, from the solids"),
        row("overlap_volume_mm3", "largest solid overlap over the workspace",
            itf.get("overlap_volume_mm3"), "mm^3",
            f"every pair of solids at {itf.get('n_poses')} workspace points"),
    ]
    return rows, delta_limits(design), []


def delta_limits(design) -> dict:
    """The default first-mode limit and, with ``[actuators] force_max_N``, the force limit
    (the force asked for in every direction at every workspace point), then ``[targets]``."""
    lim = {"first_mode_Hz": Limit(">=", FIRST_MODE_MIN_HZ, MODE_REASON, CHANGE)}
    force = design.actuators.get("force_max_N")
    if force is not None:
        lim["continuous_force_N"] = Limit(
            ">=", float(force), "[actuators] force_max_N: the force asked for in every direction "
            "at every workspace point, from the continuous torque of the motors the BOM orders",
            CHANGE)
    return with_targets(lim, design.targets)
