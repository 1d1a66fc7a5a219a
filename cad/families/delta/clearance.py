"""Clearances of the delta's layout before any CAD (numpy): the knee of a delta with
Stamper's joint offset g > 0 (the Novint Falcon model, :mod:`cad.kinematics.delta`) -- how
far it folds over the workspace and where its cross bar meets the upper arm's fork plates --
and each parallelogram's inner rod against its motor bracket.

The knee link (length g, from the elbow's knee pin to the parallelogram's top cross bar)
turns about the knee pin, parallel to the motor axis. Its fold angle psi is the angle at the
elbow between the arm (elbow -> motor axis) and the knee link (elbow -> top bar), signed:
positive on the side the knee folds to (body -z of upper_i, below the arm line), negative
across it; 180 deg straight on, 0 deg folded back onto the arm line. The cross bar
(diameter d_c, along the motor axis) and the hinge clevises on its ends cross the planes of
both fork plates (width w_a in the arm's plane, :mod:`cad.families.delta.hardware`); r_k is
their outline, the largest radius about the bar's axis
(:func:`cad.families.delta.hardware.knee_outline_radius_mm`: the clevis's corner, d_c / 2
without a clevis). The plates are cranked away from the knee's side: from the knee pin each
runs out at beta = ``CRANK_ANGLE_DEG`` off the arm line to a vertex g + w_a / 2 + r_k away
(:func:`cad.families.delta.hardware.crank_vertex_mm`), then back to the hub. The bar's axis
is g sin(psi + beta) from that leg's centre line, so the knee clears the plates while

    g sin(psi + beta) >= w_a / 2 + r_k,
    i.e.   psi >= psi_min = asin((w_a / 2 + r_k) / g) - beta                         (1)

(for psi + beta > 90 deg the bar is past the plates' rounded end at the pin, g >= w_a / 2 +
r_k from it; the leg from the vertex to the hub lies beyond the knee's reach g + r_k from
the pin on the crank's side). A g shorter than w_a / 2 + r_k always puts the knee into the
plates. beta = 0 is a straight fork.

The inner rod (side a, towards the motor) against the bracket: the bracket is a box in arm
i's frame (u_i, t_i, z about the motor axis point): |u| <= s/2, t in [t_b - T_b, t_b], z in
[-s/2, z_plate] (s the motor's mount side, t_b the bracket's near face, T_b its thickness,
z_plate the base plate's underside, :func:`cad.families.delta.assembly.stack_mm`); the rod
tube (radius r_t) between its ball centres clears it while the distance from the segment to
the box exceeds r_t (the distance is convex along the segment: its minimum by ternary
search to 1e-9 of the length).
"""

from __future__ import annotations

import math

import numpy as np

from cad.device import parts_motor
from cad.families.delta import hardware as hw
from cad.families.delta.assembly import stack_mm
from cad.families.delta.layout import ARMS, arm_points_mm
from cad.kinematics.delta import Delta, ik, require_ok
from cad.parts.motor import mount_side_mm


def fold_limit_deg(joint_offset_mm: float) -> float:
    """psi_min of eq (1) (deg) for the family's cranked fork and the knee's outline r_k (cross
    bar and clevises); 180 when the knee link is too short for the knee ever to clear the
    plates; -180 for g = 0 (no knee)."""
    if joint_offset_mm <= 0:
        return -180.0
    s = (hw.ARM_WIDTH_MM / 2 + hw.knee_outline_radius_mm()) / joint_offset_mm
    return 180.0 if s > 1 else math.degrees(math.asin(s)) - hw.CRANK_ANGLE_DEG


def fold_deg(d: Delta, P_mm) -> np.ndarray:
    """psi (N, 3) deg, the knee's signed fold angle of each arm at effector points ``P_mm``
    (N, 3) mm (elbow-out IK; module docstring). Raises KinematicsError naming the first point
    that is not ok."""
    pose = ik(d, P_mm)
    require_ok(pose)
    pts = arm_points_mm(d, pose.P_mm, pose.theta_rad)
    out = []
    for i in ARMS:
        back = pts["axis"][i] - pts["elbow"][i]
        back /= np.linalg.norm(back, axis=1, keepdims=True)
        k = pts["knee_dir"][i]
        side = np.where(np.cross(back, k) @ d.tangential[i] > 0, -1.0, 1.0)
        out.append(side * np.degrees(np.arccos(np.clip(np.sum(back * k, axis=1), -1, 1))))
    return np.stack(out, axis=1)


def _box_distance(a, b, f, lo, hi) -> np.ndarray:
    """Distance (N,) from the points a + f (b - a) to the box [lo, hi]."""
    p = a + f[:, None] * (b - a)
    return np.linalg.norm(np.maximum(np.maximum(lo - p, p - hi), 0.0), axis=1)


def rod_bracket_gap_mm(design, P_mm) -> np.ndarray:
    """(N, 3) mm: the gap between arm i's inner rod tube (side a) and its motor bracket at
    effector points ``P_mm`` (N, 3) (negative: they overlap; module docstring)."""
    d, w = design.mechanism, design.parallelogram_width_mm
    pose = ik(d, P_mm)
    require_ok(pose)
    pts = arm_points_mm(d, pose.P_mm, pose.theta_rad)
    sd = hw.design_ball_joint(design).socket_d_mm
    st = stack_mm(w, d.joint_offset_mm > 0, sd)
    s = mount_side_mm(parts_motor(design)[0])
    zb = hw.base_plate_z_mm(d.upper_arm_mm, d.theta_min_rad, d.joint_offset_mm, sd)
    lo = np.array([-s / 2, st["bracket_near"] - hw.BRACKET_THICKNESS_MM, -s / 2])
    hi = np.array([s / 2, st["bracket_near"], zb])
    out = []
    for i in ARMS:
        R = np.stack([d.radial[i], d.tangential[i], np.array([0.0, 0.0, 1.0])])  # rows
        a = (pts["top"][i] - w / 2 * d.tangential[i] - pts["axis"][i]) @ R.T
        b = (pts["bottom"][i] - w / 2 * d.tangential[i] - pts["axis"][i]) @ R.T

        f0, f1 = np.zeros(len(a)), np.ones(len(a))
        for _ in range(60):
            m0, m1 = f0 + (f1 - f0) / 3, f1 - (f1 - f0) / 3
            left = _box_distance(a, b, m0, lo, hi) <= _box_distance(a, b, m1, lo, hi)
            f0, f1 = np.where(left, f0, m0), np.where(left, m1, f1)
        out.append(_box_distance(a, b, (f0 + f1) / 2, lo, hi) - hw.ROD_OD_MM / 2)
    return np.stack(out, axis=1)


def knee_clash(design) -> str | None:
    """One line naming the workspace point, arm and fold angle where the knee's cross bar or
    its clevises meet the fork plates (eq 1) and how many points do; None when every point
    clears (or g = 0)."""
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
            f"its cross bar and clevises meet the fork plates below {lim:.1f} deg (eq 1 of "
            f"cad/families/delta/clearance.py), {int(bad.sum())} of {len(X)} workspace points")


def rod_bracket_clash(design) -> str | None:
    """One line naming the workspace point and arm where the inner rod meets its motor
    bracket (the deepest) and how many (point, arm) pairs do; None when every one clears."""
    X = design.workspace_points()
    gap = rod_bracket_gap_mm(design, X)
    if not (gap < 0).any():
        return None
    n, i = divmod(int(np.argmin(gap)), 3)
    return (f"at P = {np.round(X[n], 2).tolist()} mm the inner rod of arm {i} meets its motor "
            f"bracket (gap {gap[n, i]:.2f} mm), {int((gap < 0).sum())} of {gap.size} (point, arm) "
            "pairs")


def layout_clashes(design) -> list[str]:
    """The clashes of the layout over the workspace this module predicts before any CAD
    (:func:`knee_clash`, :func:`rod_bracket_clash`), one line each."""
    return [m for m in (knee_clash(design), rod_bracket_clash(design)) if m]
