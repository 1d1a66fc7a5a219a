"""Where every moving body of a 3-DOF delta is, from the kinematics only (numpy, no CAD).

Bodies (issue 36 §3): ``ground`` (base, motors), ``upper_i`` (upper arm i with its
clevis, turning about motor axis i), ``knee_i`` (only when ``joint_offset_mm`` g > 0: the
link of length g from the elbow hinge to the parallelogram's top bar, Stamper's Falcon
model, :mod:`cad.kinematics.delta`), ``lower_i_a`` / ``lower_i_b`` (the two rods of
parallelogram i, at -w/2 and +w/2 along the motor axis, w = ``parallelogram_width_mm``)
and ``effector`` (translating, with the handle).

Frames (base frame of :mod:`cad.kinematics.delta`, mm; ``tf_world_body`` maps body
coordinates into the base frame):

* ``upper_i``: origin on motor axis i at R u_i + a t_i (a = ``axis_offset_mm``), x along
  the arm towards the elbow (cos theta u_i - sin theta z), y = t_i (the motor axis),
  z = x cross y. Its angular velocity is t_i theta_dot_i.
* ``knee_i``: origin at the elbow E_i = R u_i + a t_i + L_a x_upper, x along the knee link
  (in the arm's plane, towards the effector joint), y = t_i.
* ``lower_i_s`` (s = a, b): origin at the rod's top end S_i + r u_i -+ (w/2) t_i (S_i =
  C_i + g x_knee, C_i the shifted elbow), x along the rod to its lower end at
  P + r u_i -+ (w/2) t_i (length L_b), y = the part of t_i normal to the rod (the
  parallelogram's plane; a Hooke-jointed rod), z = x cross y.
* ``effector``: origin at P, axes of the base frame (it translates).

The elbow's cross bar and the effector's stay parallel to t_i, so both rods of one
parallelogram share one direction; the effector is level at every pose.
"""

from __future__ import annotations

import math

import numpy as np

from cad.errors import DesignError
from cad.kinematics.delta import Delta, ik, require_ok

ARMS = (0, 1, 2)


def rot_x(deg: float) -> np.ndarray:
    """4 x 4 homogeneous rotation by ``deg`` degrees about x (right hand; maps part
    coordinates into the parent frame, as ``tf_body_part``)."""
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    T = np.eye(4)
    T[1, 1], T[1, 2], T[2, 1], T[2, 2] = c, -s, s, c
    return T


def rot_z(deg: float) -> np.ndarray:
    """4 x 4 homogeneous rotation by ``deg`` degrees about z (right hand), as :func:`rot_x`."""
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    T = np.eye(4)
    T[0, 0], T[0, 1], T[1, 0], T[1, 1] = c, -s, s, c
    return T


def body_names(d: Delta) -> tuple[str, ...]:
    """The moving and fixed bodies in order: ground, upper_i, [knee_i,] lower_i_a/b, effector."""
    names = ["ground"]
    for i in ARMS:
        names.append(f"upper_{i}")
        if d.joint_offset_mm > 0:
            names.append(f"knee_{i}")
        names += [f"lower_{i}_a", f"lower_{i}_b"]
    return (*names, "effector")


def _frame(x: np.ndarray, y: np.ndarray, origin: np.ndarray) -> np.ndarray:
    """(N, 4, 4) from unit x (N, 3), unit y (N, 3) normal to x, origin (N, 3)."""
    tf = np.zeros((x.shape[0], 4, 4))
    tf[:, :3, 0], tf[:, :3, 1], tf[:, :3, 2] = x, y, np.cross(x, y)
    tf[:, :3, 3], tf[:, 3, 3] = origin, 1.0
    return tf


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def arm_points_mm(d: Delta, P_mm, theta_rad) -> dict[str, np.ndarray]:
    """The joint points of arm ``i`` at consistent (P, theta) (N, 3) each, base frame, mm:
    {"axis": (3, N, 3) motor-axis origins, "elbow": (3, N, 3), "knee_dir": (3, N, 3) unit
    in-plane direction elbow -> effector joint, "top": (3, N, 3) the parallelogram's top
    bar centre S_i + r u_i, "bottom": (3, N, 3) its bottom bar centre P + r u_i}."""
    P = np.asarray(P_mm, float)
    th = np.asarray(theta_rad, float)
    u, t = d.radial, d.tangential
    out: dict[str, list] = {k: [] for k in ("axis", "elbow", "knee_dir", "top", "bottom")}
    for i in ARMS:
        axis = np.broadcast_to(d.base_radius_mm * u[i] + d.axis_offset_mm * t[i], P.shape)
        x_up = np.cos(th[:, i])[:, None] * u[i] - np.sin(th[:, i])[:, None] * np.array([0, 0, 1.0])
        elbow = axis + d.upper_arm_mm * x_up
        bottom = P + d.effector_radius_mm * u[i]
        w = bottom - elbow
        wp = w - (w @ t[i])[:, None] * t[i]
        kdir = _unit(wp)
        out["axis"].append(axis)
        out["elbow"].append(elbow)
        out["knee_dir"].append(kdir)
        out["top"].append(elbow + d.joint_offset_mm * kdir)
        out["bottom"].append(bottom)
    return {k: np.stack(v) for k, v in out.items()}


def body_poses(d: Delta, P_mm, width_mm: float) -> dict[str, np.ndarray]:
    """``{body: (N, 4, 4)}`` tf_world_body (mm) with the effector centre at ``P_mm`` (N, 3)
    (joint angles from :func:`cad.kinematics.delta.ik`, elbow out). Raises
    :class:`cad.errors.KinematicsError` naming the first point that is not ok, DesignError
    for a width <= 0."""
    if not (np.isfinite(width_mm) and width_mm > 0):
        raise DesignError("mechanism.parallelogram_width_mm", f"must be > 0, got {width_mm!r}")
    pose = ik(d, P_mm)
    require_ok(pose)
    return poses_at(d, pose.P_mm, pose.theta_rad, width_mm)


def poses_at(d: Delta, P_mm, theta_rad, width_mm: float) -> dict[str, np.ndarray]:
    """:func:`body_poses` at given consistent effector points and joint angles (N, 3) each."""
    P = np.asarray(P_mm, float).reshape(-1, 3)
    th = np.asarray(theta_rad, float).reshape(-1, 3)
    n = P.shape[0]
    pts = arm_points_mm(d, P, th)
    t = d.tangential
    out = {"ground": np.broadcast_to(np.eye(4), (n, 4, 4)).copy()}
    for i in ARMS:
        ti = np.broadcast_to(t[i], (n, 3))
        x_up = _unit(pts["elbow"][i] - pts["axis"][i])
        out[f"upper_{i}"] = _frame(x_up, ti, pts["axis"][i])
        if d.joint_offset_mm > 0:
            out[f"knee_{i}"] = _frame(pts["knee_dir"][i], ti, pts["elbow"][i])
        x_rod = _unit(pts["bottom"][i] - pts["top"][i])
        y_rod = _unit(ti - np.sum(ti * x_rod, axis=1)[:, None] * x_rod)
        for side, s in (("a", -0.5), ("b", 0.5)):
            out[f"lower_{i}_{side}"] = _frame(x_rod, y_rod, pts["top"][i] + s * width_mm * t[i])
    eff = np.broadcast_to(np.eye(4), (n, 4, 4)).copy()
    eff[:, :3, 3] = P
    out["effector"] = eff
    return out
