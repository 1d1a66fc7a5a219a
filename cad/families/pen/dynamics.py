"""Effective (operational) mass of the haptic pen from its bodies' mass properties.

Task velocity ``v = (x_dot, y_dot, z_dot [m/s], w_yaw, w_pitch [rad/s])`` (the columns of
:func:`cad.kinematics.haptic_pen.jacobian_si`: ``u_dot = w_yaw e_yaw + w_pitch e_pitch``).
Kinetic energy ``T = 1/2 v^T M v`` with

    M = sum_b (m_b J_vb^T J_vb + J_wb^T R_b I_b R_b^T J_wb) + J^T diag(Jm) J

``J_vb`` (3 x 5, m per unit v) the velocity of body b's centre of mass, ``J_wb`` its angular
velocity (rad/s per unit v), both by central differences of the body poses of
:func:`cad.families.pen.layout.body_poses`; ``I_b`` its inertia about the COM in its body
frame (:class:`cad.massprops.props.MassProps`); ``J`` the pen Jacobian (6 x 5, q_dot = J v)
and ``Jm`` the rotors' inertia (waist motors on q1, q4, shoulder motors on the others), each
n^2 (J_m + J_capstan) behind a capstan of ratio n (:func:`rotor_inertias`).
No CAD import.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cad.device import resolve_device
from cad.families.pen.layout import body_poses
from cad.kinematics import haptic_pen as hp
from cad.tolerances import PEN_FD_STEP as FD_STEP


def _vee(W: np.ndarray) -> np.ndarray:
    return np.array([W[2, 1] - W[1, 2], W[0, 2] - W[2, 0], W[1, 0] - W[0, 1]]) / 2


def body_jacobians(design, X, step: float = FD_STEP) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """``{body: (J_origin (3, 5) m per unit v, J_w (3, 5) rad/s per unit v, T (4, 4) mm)}`` at
    task pose ``X`` (5,) (mm, rad), by central differences (:data:`FD_STEP`)."""
    X = np.asarray(X, float)
    # d X / d v: mm per (m/s) for translations; yaw_dot = w_yaw / cos(pitch), pitch_dot = w_pitch
    D = np.diag([1e3, 1e3, 1e3, 1.0 / math.cos(X[4]), 1.0])
    P = np.vstack([X[None], X + step * D.T, X - step * D.T])
    T = body_poses(design, P)
    out = {}
    for b, Tb in T.items():
        if b == "ground":
            continue
        Jv, Jw = np.zeros((3, 5)), np.zeros((3, 5))
        R0 = Tb[0, :3, :3]
        for i in range(5):
            Tp, Tm = Tb[1 + i], Tb[6 + i]
            Jv[:, i] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * step) * 1e-3
            Jw[:, i] = _vee((Tp[:3, :3] - Tm[:3, :3]) @ R0.T) / (2 * step)
        out[b] = (Jv, Jw, Tb[0])
    return out


def mass_matrix_si(design, bodies: dict, X, rotor_kg_m2=None) -> np.ndarray:
    """(5, 5) operational mass matrix at task pose ``X`` (module docstring): kg for the
    translations, kg m^2 for the rotations, SI mixed blocks. ``bodies``: ``{body: MassProps}``
    in the body frames of :func:`cad.families.pen.layout.body_poses`; ``rotor_kg_m2``: (6,)
    rotor inertias on the joints (default: the design's catalog motors)."""
    M = np.zeros((5, 5))
    for b, (Jv, Jw, T) in body_jacobians(design, X).items():
        mp = bodies.get(b)
        if mp is None:
            continue
        R = T[:3, :3]
        c = R @ np.asarray(mp.com_m, float)  # COM offset from the body origin, world, m
        Jc = Jv - np.cross(c[:, None].T, Jw.T).T  # v_c = v_o + w x c
        Iw = R @ np.asarray(mp.inertia_com_kg_m2, float) @ R.T
        M += mp.mass_kg * Jc.T @ Jc + Jw.T @ Iw @ Jw
    if rotor_kg_m2 is None:
        rotor_kg_m2 = rotor_inertias(design)
    J, st = hp.jacobian_si(design.mechanism, np.asarray(X, float)[None])
    if st[0] != 0:
        raise ValueError(f"pen Jacobian singular at {X}: {hp.STATUS_NAMES[int(st[0])]}")
    return M + J[0].T @ np.diag(rotor_kg_m2) @ J[0]


def rotor_inertias(design) -> np.ndarray:
    """(6,) rotor inertia (kg m^2) on the joints (q1 waist A, q2, q3, q4 waist B, q5, q6), each
    through its transmission: n^2 (J_m + J_capstan) behind a capstan, J_m for direct drive
    (:meth:`cad.device.ResolvedDevice.joint_rotor_inertia_kg_m2`)."""
    dev = resolve_device(design)
    return np.array([dev.joint_rotor_inertia_kg_m2(f"{a}_q_{j}") for a in ("A", "B") for j in ("waist", "lower", "upper")])


@dataclass(frozen=True)
class PenDynamics:
    """The pen's dynamics from the solids (``Build.dyn``): the 5 x 5 operational mass matrix
    at the home task pose ``at_task`` (x, y, z mm; yaw, pitch rad) in SI (``mass_matrix_si``:
    kg for the translations, kg m^2 for the rotations, :func:`mass_matrix_si`) and its report
    entry ``effective_mass_home`` (:func:`effective_mass`)."""

    at_task: tuple
    mass_matrix_si: np.ndarray
    effective_mass_home: dict


def dynamics(design, bodies: dict, X) -> PenDynamics:
    """:class:`PenDynamics` at task pose ``X`` from the bodies' mass properties (SI)."""
    eff = effective_mass(design, bodies, X)
    return PenDynamics(tuple(float(v) for v in X), np.asarray(eff["mass_matrix_si"]), eff)


def effective_mass(design, bodies: dict, X) -> dict:
    """Report entry: the matrix at ``X`` and its diagonal in g and g cm^2 (held: the mass felt
    moving one task axis with the others held) and apparent ``1 / (M^-1)_ii`` (others free)."""
    M = mass_matrix_si(design, bodies, X)
    Mi = np.linalg.inv(M)
    names = ("mass_x_g", "mass_y_g", "mass_z_g", "inertia_yaw_g_cm2", "inertia_pitch_g_cm2")
    scale = np.array([1e3, 1e3, 1e3, 1e7, 1e7])
    out = {"at_task": [float(v) for v in X], "mass_matrix_si": M.tolist()}
    for i, n in enumerate(names):
        out[f"{n}_diag"] = float(M[i, i] * scale[i])
        out[f"{n}_apparent"] = float(scale[i] / Mi[i, i])
    return out


#: Task axes of :func:`mass_matrix_si` by name.
TASK_AXES = ("x", "y", "z", "yaw", "pitch")


def mass_breakdown(design, parts_by_body: dict, X, axis: str = "x", rotor_kg_m2=None) -> dict:
    """Contribution of every part and every rotor to the diagonal term ``M_ii`` of the
    operational mass matrix at task pose ``X`` (the mass felt moving task axis ``axis`` with
    the others held; :func:`mass_matrix_si`): kinetic energy is additive over rigid parts,
    so ``M_ii = sum_p (m_p |J_cp e_i|^2 + (J_w e_i)^T I_p (J_w e_i)) + sum_j Jm_j J_ji^2``.

    parts_by_body : ``{body: [(label, MassProps in the body frame, SI)]}`` (a label may repeat:
        the same kind twice on one body); rotor_kg_m2 : (6,) as :func:`mass_matrix_si`.
    Returns ``{"axis", "total", "parts": [(body, label, value)], "rotors": [(joint, value)]}``,
    values in kg (translation axes) or kg m^2 (rotations), total = their sum.
    """
    i = TASK_AXES.index(axis)
    parts = []
    for b, (Jv, Jw, T) in body_jacobians(design, X).items():
        R = T[:3, :3]
        for label, mp in parts_by_body.get(b, ()):
            c = R @ np.asarray(mp.com_m, float)
            vc = Jv[:, i] - np.cross(c, Jw[:, i])  # v_c = v_o + w x c
            w = Jw[:, i]
            Iw = R @ np.asarray(mp.inertia_com_kg_m2, float) @ R.T
            parts.append((b, label, float(mp.mass_kg * vc @ vc + w @ Iw @ w)))
    if rotor_kg_m2 is None:
        rotor_kg_m2 = rotor_inertias(design)
    J, _ = hp.jacobian_si(design.mechanism, np.asarray(X, float)[None])
    joints = [f"{a}_q_{j}" for a in ("A", "B") for j in ("waist", "lower", "upper")]
    rotors = [(j, float(jm * J[0][k, i] ** 2)) for k, (j, jm) in enumerate(zip(joints, rotor_kg_m2, strict=True))]
    total = sum(v for *_, v in parts) + sum(v for _, v in rotors)
    return {"axis": axis, "total": total, "parts": parts, "rotors": rotors}


def link_mass_matrix_X(design, bodies: dict, X_si, step: float = FD_STEP) -> np.ndarray:
    """Lambda (N, 5, 5) of the solids (no rotors) over the task coordinates X = (x, y, z m,
    yaw, pitch rad) at poses ``X_si`` (N, 5): sum_b m_b Jc_b^T Jc_b + Jw_b^T I_b Jw_b with each
    body's centre and angular velocity per unit X' by central differences of
    :func:`cad.families.pen.layout.body_poses` (all poses in one batch). ``bodies``:
    ``{body: MassProps}`` in the body frames (SI). :func:`mass_matrix_si` is the same in the
    quasi-velocities v (w_yaw = cos(pitch) yaw')."""
    X = np.atleast_2d(np.asarray(X_si, float))
    n = len(X)
    Xmm = X * np.array([1e3, 1e3, 1e3, 1.0, 1.0])
    E = np.eye(5) * step
    P = np.concatenate([Xmm, *(Xmm + e for e in E), *(Xmm - e for e in E)])
    per_unit = np.array([1e3, 1e3, 1e3, 1.0, 1.0]) / (2 * step)  # d(X_mm) per unit X, over 2 step
    lam = np.zeros((n, 5, 5))
    for b, Tb in body_poses(design, P).items():
        mp = bodies.get(b)
        if b == "ground" or mp is None:
            continue
        T0 = Tb[:n]
        Jv, Jw = np.zeros((n, 3, 5)), np.zeros((n, 3, 5))
        for i in range(5):
            Tp, Tm = Tb[n * (1 + i):n * (2 + i)], Tb[n * (6 + i):n * (7 + i)]
            Jv[:, :, i] = (Tp[:, :3, 3] - Tm[:, :3, 3]) * 1e-3 * per_unit[i]
            Wk = (Tp[:, :3, :3] - Tm[:, :3, :3]) @ np.swapaxes(T0[:, :3, :3], 1, 2)
            Jw[:, :, i] = 0.5 * np.stack([Wk[:, 2, 1] - Wk[:, 1, 2], Wk[:, 0, 2] - Wk[:, 2, 0],
                                          Wk[:, 1, 0] - Wk[:, 0, 1]], axis=-1) * per_unit[i]
        R = T0[:, :3, :3]
        c = R @ np.asarray(mp.com_m, float)
        Jc = Jv - np.cross(c[:, None, :], np.swapaxes(Jw, 1, 2)).swapaxes(1, 2)
        Iw = R @ np.asarray(mp.inertia_com_kg_m2, float) @ np.swapaxes(R, 1, 2)
        lam += mp.mass_kg * np.swapaxes(Jc, 1, 2) @ Jc + np.swapaxes(Jw, 1, 2) @ Iw @ Jw
    return lam
