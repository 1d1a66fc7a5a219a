"""The knee of a delta with Stamper's joint offset g > 0 (the Novint Falcon model,
:mod:`cad.kinematics.delta`): how far it folds over the workspace, and where its cross bar
meets the upper arm's fork plates (numpy, no CAD).

The knee link (length g, from the elbow's knee pin to the parallelogram's top cross bar)
turns about the knee pin, parallel to the motor axis. Its fold angle psi is the angle at the
elbow between the arm (elbow -> motor axis) and the knee link (elbow -> top bar): 180 deg
straight on, 0 deg folded back onto the arm. The cross bar (diameter d_c, along the motor
axis) crosses the planes of both fork plates (width w_a in the arm's plane, from the motor
axis to the knee pin, :mod:`cad.families.delta.hardware`); its axis is g sin(psi) from the
arm's centre line, so it clears the plates while

    g sin(psi) >= w_a / 2 + d_c / 2,   i.e.   psi >= psi_min = asin((w_a + d_c) / (2 g))   (1)

(for psi > 90 deg the bar is past the plates' rounded end, g >= w_a / 2 + d_c / 2 from the
pin). A g shorter than w_a / 2 + d_c / 2 always puts the bar into the plates.
"""

from __future__ import annotations

import math

import numpy as np

from cad.families.delta import hardware as hw
from cad.families.delta.layout import ARMS, arm_points_mm
from cad.kinematics.delta import Delta, ik, require_ok


def fold_limit_deg(joint_offset_mm: float) -> float:
    """psi_min of eq (1) (deg) for the family's arm plate and cross bar; 180 when the knee
    link is too short for its bar ever to clear the plates; 0 for g = 0 (no knee)."""
    if joint_offset_mm <= 0:
        return 0.0
    s = (hw.ARM_WIDTH_MM + hw.CROSS_BAR_D_MM) / (2 * joint_offset_mm)
    return 180.0 if s > 1 else math.degrees(math.asin(s))


def fold_deg(d: Delta, P_mm) -> np.ndarray:
    """psi (N, 3) deg, the knee's fold angle of each arm at effector points ``P_mm`` (N, 3) mm
    (elbow-out IK). Raises KinematicsError naming the first point that is not ok."""
    pose = ik(d, P_mm)
    require_ok(pose)
    pts = arm_points_mm(d, pose.P_mm, pose.theta_rad)
    out = []
    for i in ARMS:
        back = pts["axis"][i] - pts["elbow"][i]
        back /= np.linalg.norm(back, axis=1, keepdims=True)
        out.append(np.degrees(np.arccos(np.clip(np.sum(back * pts["knee_dir"][i], axis=1), -1, 1))))
    return np.stack(out, axis=1)


def knee_clash(design) -> str | None:
    """One line naming the workspace point, arm and fold angle where the knee's cross bar
    meets the fork plates (eq 1) and how many points do; None when every point clears (or
    g = 0)."""
    d = design.mechanism
    if d.joint_offset_mm <= 0:
        return None
    X = design.workspace_points()
    psi = fold_deg(d, X)
    lim = fold_limit_deg(d.joint_offset_mm)
    bad = np.any(psi < lim, axis=1)
    if not bad.any():
        return None
    n, i = divmod(int(np.argmin(psi)), 3)
    return (f"at P = {np.round(X[n], 2).tolist()} mm knee {i} folds to {psi[n, i]:.1f} deg and "
            f"its cross bar meets the fork plates below {lim:.1f} deg (eq 1 of "
            f"cad/families/delta/knee.py), {int(bad.sum())} of {len(X)} workspace points; the "
            f"highest clear layer is z = {_highest_clear_z(X, bad)}")


def _highest_clear_z(X: np.ndarray, bad: np.ndarray) -> str:
    clear = [z for z in np.unique(X[:, 2]) if not bad[X[:, 2] == z].any()]
    return "none" if not clear else f"{max(clear):g} mm"
