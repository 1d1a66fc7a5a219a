"""Task-space mass matrix Lambda(x) of a delta from its bodies' mass properties (numpy).

Each body b of :mod:`cad.families.delta.layout` moves, at an effector velocity x_dot (m/s),
with its frame origin at v_o = Jo_b x_dot and its angular velocity w = Jw_b x_dot; with m
its mass, c its centre (body frame) and I its inertia about the centre (body axes, rotated
into the base frame by R_b), the kinetic energy is

    T = 1/2 x_dot^T Lambda x_dot,
    Lambda = sum_b m (Jo - [R c]x Jw)^T (Jo - [R c]x Jw) + Jw^T R I R^T Jw
             + sum_i n^2 J_m J_i^T J_i                                             (1)

(rigid-body kinetic energy, Koenig's theorem; the last term the rotors through the
transmission ratio n; J_i row i of the delta's Jacobian, theta_dot = J x_dot). The
Jacobians, with theta_dot_i = J_i x_dot and e_i = dE_i/dtheta_i:

* upper_i: Jo = 0, Jw = t_i J_i (it turns about the motor axis t_i);
* knee_i: Jo = e_i J_i, Jw = (w_p x D_p) / |w_p|^2 with w_p the in-plane vector elbow ->
  effector joint and D_p = (1 - t t^T)(1 - e_i J_i) its rate;
* lower_i_s: Jo = rate of the rod's top end (e_i J_i + g (1 - k k^T) D_p / |w_p|, k the
  knee direction), rod direction rate D_u = (1 - u u^T)(1 - Jo) / L_b, and
  Jw = u x D_u - ((t.u) / |t - (t.u) u|) u (z_rod^T D_u) (the spin that keeps the
  rod's y axis in the parallelogram's plane, :mod:`.layout`);
* effector: Jo = 1, Jw = 0.

Reduces to :func:`cad.dynamics.delta.mass_matrix_kg` for slender uniform rods and a point
effector (the test checks it), and equals twice the kinetic energy of the posed bodies
differentiated numerically (the test checks that too).
"""

from __future__ import annotations

import numpy as np

from cad.dynamics.delta import G_M_S2, DeltaMass
from cad.errors import DesignError
from cad.families.delta.layout import ARMS, arm_points_mm, poses_at
from cad.kinematics.delta import Delta, ik, jacobian_rad_per_m, require_ok

MM = 1e-3


def _skew(v: np.ndarray) -> np.ndarray:
    """(N, 3, 3) [v]x of v (N, 3)."""
    S = np.zeros((*v.shape[:-1], 3, 3))
    S[..., 0, 1], S[..., 0, 2], S[..., 1, 2] = -v[..., 2], v[..., 1], -v[..., 0]
    return S - np.swapaxes(S, -1, -2)


def _outer(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.einsum("ni,nj->nij", a, b)


def _elbow_rate_m(d: Delta, theta: np.ndarray, i: int) -> np.ndarray:
    """e_i (N, 3) = dE_i/dtheta_i, m/rad."""
    e = -d.upper_arm_mm * np.sin(theta[:, i])[:, None] * d.radial[i]
    e[:, 2] = -d.upper_arm_mm * np.cos(theta[:, i])
    return e * MM


def body_jacobians(d: Delta, P_mm, theta_rad, J: np.ndarray) -> dict[str, tuple]:
    """``{body: (Jo, Jw)}`` (N, 3, 3) each: the velocity of the body frame's origin (m/s per
    m/s) and its angular velocity (rad/s per m/s), base frame, at consistent effector
    points ``P_mm`` (N, 3), joint angles ``theta_rad`` (N, 3) and Jacobian ``J`` (N, 3, 3)
    rad/m. Ground is left out (it does not move)."""
    P = np.asarray(P_mm, float)
    n = P.shape[0]
    eye = np.broadcast_to(np.eye(3), (n, 3, 3))
    pts = arm_points_mm(d, P, theta_rad)
    out: dict[str, tuple] = {}
    for i in ARMS:
        t = d.tangential[i]
        Jc = _outer(_elbow_rate_m(d, theta_rad, i), J[:, i, :])
        out[f"upper_{i}"] = (np.zeros((n, 3, 3)), _outer(np.broadcast_to(t, (n, 3)), J[:, i, :]))
        w = (pts["bottom"][i] - pts["elbow"][i]) * MM
        wp = w - (w @ t)[:, None] * t
        wp2 = np.sum(wp * wp, axis=1)
        Dp = (np.eye(3) - np.outer(t, t)) @ (eye - Jc)
        k = pts["knee_dir"][i]
        Jo_top = Jc + d.joint_offset_mm * MM * (eye - _outer(k, k)) @ Dp / np.sqrt(wp2)[:, None, None]
        if d.joint_offset_mm > 0:
            out[f"knee_{i}"] = (Jc, _skew(wp) @ Dp / wp2[:, None, None])
        u = (pts["bottom"][i] - pts["top"][i]) / d.lower_arm_mm
        Du = (eye - _outer(u, u)) @ (eye - Jo_top) / (d.lower_arm_mm * MM)
        tu = u @ t
        wlen = np.linalg.norm(t - tu[:, None] * u, axis=1)
        z_rod = np.cross(u, (t - tu[:, None] * u) / wlen[:, None])
        spin = _outer(u * (tu / wlen)[:, None], np.einsum("ni,nij->nj", z_rod, Du))
        Jw = _skew(u) @ Du - spin
        out[f"lower_{i}_a"] = out[f"lower_{i}_b"] = (Jo_top, Jw)
    out["effector"] = (eye.copy(), np.zeros((n, 3, 3)))
    return out



def mass_matrix_from_bodies_kg(d: Delta, P_mm, width_mm: float, props: dict,
                               rotor_kg_m2: float = 0.0, ratio: float = 1.0) -> np.ndarray:
    """Lambda(x) (N, 3, 3) kg at effector points ``P_mm`` (N, 3) mm, base frame, eq (1).

    props : ``{body: cad.massprops.props.MassProps}`` in each body's frame of
        :mod:`cad.families.delta.layout` (SI: com_m in m, inertia about the centre in
        kg m^2), as :func:`cad.pipeline.family.body_props` returns; a moving body missing
        from it counts as massless. rotor_kg_m2 : each motor's rotor inertia about its axis
        (one value, or (3,) one per motor in joint order); ratio : motor turns per arm turn
        (1 = direct drive; one value or (3,)): Lambda += J^T diag(n_i^2 J_m,i) J.
    Raises :class:`cad.errors.KinematicsError` naming the first point that is unreachable,
    singular or outside the joint limits; DesignError for a negative rotor or ratio <= 0.
    """
    rotor, n = (np.broadcast_to(np.asarray(v, float), (3,)) for v in (rotor_kg_m2, ratio))
    if not np.all(np.isfinite(rotor) & (rotor >= 0)):
        raise DesignError("rotor_kg_m2", f"must be finite and >= 0, got {rotor_kg_m2!r}")
    if not np.all(np.isfinite(n) & (n > 0)):
        raise DesignError("ratio", f"must be finite and > 0, got {ratio!r}")
    J, bodies = com_jacobians(d, P_mm, width_mm, props)
    Lam = np.einsum("nik,i,nil->nkl", J, n**2 * rotor, J)
    for mp, Jcom, Jw, I_w in bodies:
        Lam += mp.mass_kg * np.swapaxes(Jcom, 1, 2) @ Jcom + np.swapaxes(Jw, 1, 2) @ I_w @ Jw
    return Lam


def com_jacobians(d: Delta, P_mm, width_mm: float, props: dict) -> tuple[np.ndarray, list[tuple]]:
    """(J (N, 3, 3) rad/m, [(MassProps, Jcom (N, 3, 3), Jw (N, 3, 3), I about the centre in the
    base frame (N, 3, 3))] per moving body with mass): each body centre's velocity and angular
    velocity per effector velocity, base frame, at effector points ``P_mm`` (N, 3).
    KinematicsError naming the first point not ok."""
    pose = ik(d, P_mm)
    require_ok(pose)
    J, _ = jacobian_rad_per_m(d, pose.P_mm)
    tfs = poses_at(d, pose.P_mm, pose.theta_rad, width_mm)
    out = []
    for body, (Jo, Jw) in body_jacobians(d, pose.P_mm, pose.theta_rad, J).items():
        mp = props.get(body)
        if mp is None or mp.mass_kg == 0 and not np.any(mp.inertia_com_kg_m2):
            continue
        R = tfs[body][:, :3, :3]
        Jcom = Jo - _skew(R @ np.asarray(mp.com_m)) @ Jw
        out.append((mp, Jcom, Jw, R @ np.asarray(mp.inertia_com_kg_m2) @ np.swapaxes(R, 1, 2)))
    return J, out


def gravity_hold_torques_Nm(d: Delta, P_mm, width_mm: float, props: dict,
                            g_m_s2=(0.0, 0.0, -G_M_S2)) -> np.ndarray:
    """Joint torques (N, 3) N m holding the solids still at effector points ``P_mm`` (N, 3)
    mm: J^-T grad_x V with grad_x V = -sum_b m_b Jcom_b^T g (every body's weight at its
    centre, :func:`com_jacobians`; the point-mass model's
    :func:`cad.dynamics.delta.gravity_torques_Nm` for slender rods and a point effector)."""
    J, bodies = com_jacobians(d, P_mm, width_mm, props)
    g = np.asarray(g_m_s2, float)
    grad = np.zeros((J.shape[0], 3))
    for mp, Jcom, _, _ in bodies:
        grad -= mp.mass_kg * np.einsum("nji,j->ni", Jcom, g)
    return np.linalg.solve(np.swapaxes(J, -1, -2), grad[..., None])[..., 0]


def delta_mass_from_bodies(d: Delta, props: dict, rotor_kg_m2: float = 0.0,
                           ratio: float = 1.0) -> DeltaMass:
    """The :class:`cad.dynamics.delta.DeltaMass` (gravity, firmware) of body mass properties
    ``props`` ({body: MassProps}, body frames of :mod:`.layout`, SI), from arm 0 (the three
    arms are alike): the upper arm's inertia about its motor axis (parallel axes), its mass
    and its centre's distance along the arm; both rods of parallelogram 0; the effector; with
    Stamper's knee (g > 0) knee_0's mass, its centre's distance along the knee link and its
    inertia about the knee pin (body y = t_0, parallel axes). The lumped model drops each
    centre's offset across its link and the rods' shape (uniform slender rods)."""
    arm = props["upper_0"]
    c = np.asarray(arm.com_m)
    y = np.array([0.0, 1.0, 0.0])  # the motor axis (knee pin axis) in the body frame
    I_axis = float(y @ np.asarray(arm.inertia_com_kg_m2) @ y + arm.mass_kg * (c[0] ** 2 + c[2] ** 2))
    rods = sum(props[b].mass_kg for b in ("lower_0_a", "lower_0_b") if b in props)
    knee = {}
    if d.joint_offset_mm > 0 and "knee_0" in props:
        k = props["knee_0"]
        ck = np.asarray(k.com_m)
        knee = {"knee_kg": k.mass_kg, "knee_com_mm": float(ck[0]) / MM,
                "knee_kg_m2": float(y @ np.asarray(k.inertia_com_kg_m2) @ y
                                    + k.mass_kg * (ck[0] ** 2 + ck[2] ** 2))}
    return DeltaMass(upper_arm_kg_m2=I_axis, upper_arm_kg=arm.mass_kg,
                     upper_arm_com_mm=float(c[0]) / MM, lower_arm_kg=rods,
                     effector_kg=props["effector"].mass_kg, rotor_kg_m2=rotor_kg_m2, ratio=ratio,
                     **knee)
