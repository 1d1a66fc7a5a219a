"""Task-space mass matrix Lambda(x) and gravity load of a 3-DOF delta (issue 36 §4).

Kinetic energy T = 1/2 x_dot^T Lambda x_dot, x the effector centre (base frame, m/s), summed
over (symbols of :mod:`cad.kinematics.delta`; theta_dot = J x_dot):

* each upper arm turning about its motor axis, with the motor's rotor through the
  transmission ratio n (motor angle = n theta): (I_arm + n^2 J_m) theta_dot_i^2;
* each lower arm (parallelogram): two rods whose ends move with the elbow velocity
  v_E = e_i theta_dot_i (e_i = dE_i/dtheta_i) and the effector velocity v_P = x_dot (both
  cross bars translate: the elbow's turns about an axis parallel to itself). A uniform
  slender rod with end velocities v_a, v_b has T = (m/6)(|v_a|^2 + v_a.v_b + |v_b|^2)
  (its centre moves with (v_a + v_b)/2, it turns at |v_b - v_a|/L, I_G = m L^2/12), so with
  G_i = e_i J_i (3x3) its share of Lambda is (m/3)(G^T G + (G + G^T)/2 + I);
* the effector, translating: m_e I.

With Stamper's knee (``joint_offset_mm`` g > 0, the Falcon): the knee link turns about
t_i at the elbow with the rate w_i = q_i . x_dot, q_i = (n_i - (n_i . e_i) J_i) / rho_i
(k_i the unit in-plane direction elbow -> effector joint, n_i = t_i x k_i, rho_i that
in-plane distance: the knee stays in line with it, :mod:`cad.kinematics.delta`); its
centre at c_k along it moves with G_k = e_i J_i^T + c_k n_i q_i^T, so its share is
m_k G_k^T G_k + (I_k - m_k c_k^2) q_i q_i^T (I_k about the knee pin); the rods' top ends
move with G = e_i J_i^T + g n_i q_i^T in the rod formula above. g = 0 and no knee mass
give the Clavel model.

Gravity (g along -z): the potential V(x) = g [m_e z_P + sum_i (m_arm z_G,i + m_k z_K,i +
m_rods (z_S,i + z_P)/2)] (z_S,i the rods' top ends, z_E,i for g = 0), and the force the
motors must add at the effector to hold it is grad_x V = g [m_e z + sum_i (m_arm (c_a / L_a)
e_i,z J_i + m_k G_k[z] + (m_rods / 2) (G[z] + z))]; the joint torques that do so are
J^-T grad_x V (the gravity compensation).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cad.errors import DesignError
from cad.kinematics.delta import Delta, ik, jacobian_rad_per_m, require_ok

G_M_S2 = 9.80665  # standard gravity (ISO 80000-3), m/s^2
MM = 1e-3


@dataclass(frozen=True)
class DeltaMass:
    """Mass properties of a delta's moving parts (SI), the same for the three arms.

    upper_arm_kg_m2: an upper arm (with its elbow hardware and drum) about its motor axis;
    upper_arm_kg and upper_arm_com_mm: its mass and its centre's distance from the motor
    axis along the arm (gravity). lower_arm_kg: one parallelogram (both rods and their
    joints, as uniform slender rods). effector_kg: effector and handle. rotor_kg_m2: each
    motor's rotor; ratio: transmission ratio n (1 = direct drive). With Stamper's knee
    (g > 0): knee_kg, knee_com_mm (its centre's distance from the knee pin along the knee
    link) and knee_kg_m2 (about the knee pin's axis t_i); 0 without a knee.
    """

    upper_arm_kg_m2: float
    upper_arm_kg: float
    upper_arm_com_mm: float
    lower_arm_kg: float
    effector_kg: float
    rotor_kg_m2: float = 0.0
    ratio: float = 1.0
    knee_kg: float = 0.0
    knee_com_mm: float = 0.0
    knee_kg_m2: float = 0.0

    def __post_init__(self) -> None:
        for name, v in vars(self).items():
            if not (np.isfinite(v) and v >= 0):
                raise DesignError(f"delta_mass.{name}", f"must be finite and >= 0, got {v!r}")
        if self.ratio <= 0:
            raise DesignError("delta_mass.ratio", f"must be > 0, got {self.ratio!r}")


def _elbow_rate_m(d: Delta, theta: np.ndarray) -> np.ndarray:
    """e_i = dE_i/dtheta_i (N, 3, 3) in m/rad (rows i)."""
    e = -d.upper_arm_mm * np.sin(theta)[..., None] * d.radial
    e[..., 2] = -d.upper_arm_mm * np.cos(theta)
    return e * MM


def arm_rates(d: Delta, P_mm, theta, J: np.ndarray) -> list[tuple]:
    """Per arm i, at consistent effector points ``P_mm`` (N, 3) mm, joint angles ``theta``
    (N, 3) rad and Jacobian ``J`` (N, 3, 3) rad/m: (Ge (N, 3, 3) the elbow's velocity per
    effector velocity e_i J_i^T, n_i (N, 3) unit t_i x k_i, q_i (N, 3) the knee's rate
    rad/s per m/s; module docstring). q_i is zero for g = 0 (no knee)."""
    P = np.asarray(P_mm, float)
    e = _elbow_rate_m(d, theta)
    out = []
    for i in range(3):
        a, ei, t, u = J[:, i, :], e[:, i, :], d.tangential[i], d.radial[i]
        Ge = np.einsum("nk,nl->nkl", ei, a)
        if d.joint_offset_mm <= 0:
            out.append((Ge, np.zeros_like(P), np.zeros_like(P)))
            continue
        E = d.base_radius_mm * u + d.axis_offset_mm * t + d.upper_arm_mm * (
            np.cos(theta[:, i])[:, None] * u - np.sin(theta[:, i])[:, None] * np.array([0, 0, 1.0]))
        w = P + d.effector_radius_mm * u - E
        wp = w - (w @ t)[:, None] * t
        rho = np.linalg.norm(wp, axis=1)
        n = np.cross(t, wp / rho[:, None])
        q = (n - np.sum(n * ei, axis=1)[:, None] * a) / (rho * MM)[:, None]
        out.append((Ge, n, q))
    return out


def _pose(d: Delta, P_mm):
    pose = ik(d, P_mm)
    require_ok(pose)
    J, _ = jacobian_rad_per_m(d, pose.P_mm)
    return pose, J


def mass_matrix_kg(d: Delta, P_mm, mass: DeltaMass) -> np.ndarray:
    """Lambda (N, 3, 3) kg at effector points ``P_mm`` (N, 3) mm, base frame (module
    docstring; with the knee for g > 0).

    Raises :class:`cad.errors.KinematicsError` naming the first point that is unreachable,
    singular or outside the joint limits.
    """
    pose, J = _pose(d, P_mm)
    n = pose.P_mm.shape[0]
    arm = mass.upper_arm_kg_m2 + mass.ratio**2 * mass.rotor_kg_m2
    g, ck = d.joint_offset_mm * MM, mass.knee_com_mm * MM
    Lam = np.broadcast_to(mass.effector_kg * np.eye(3), (n, 3, 3)).copy()
    TT = lambda A: np.swapaxes(A, 1, 2)  # noqa: E731
    for i, (Ge, nv, q) in enumerate(arm_rates(d, pose.P_mm, pose.theta_rad, J)):
        Ji = J[:, i, :]
        Lam += arm * np.einsum("nk,nl->nkl", Ji, Ji)
        G = Ge + g * np.einsum("nk,nl->nkl", nv, q)
        Lam += mass.lower_arm_kg / 3.0 * (TT(G) @ G + 0.5 * (G + TT(G)) + np.eye(3))
        if mass.knee_kg > 0 or mass.knee_kg_m2 > 0:
            Gk = Ge + ck * np.einsum("nk,nl->nkl", nv, q)
            Lam += mass.knee_kg * TT(Gk) @ Gk + (mass.knee_kg_m2 - mass.knee_kg * ck**2) * \
                np.einsum("nk,nl->nkl", q, q)
    return Lam


def gravity_force_N(d: Delta, P_mm, mass: DeltaMass) -> np.ndarray:
    """grad_x V (N, 3) [N]: the force the motors must add at the effector to hold it still
    against gravity at ``P_mm`` (N, 3) mm (its z component is the weight carried; module
    docstring, with the knee for g > 0)."""
    pose, J = _pose(d, P_mm)
    g, ck = d.joint_offset_mm * MM, mass.knee_com_mm * MM
    F = np.zeros((pose.P_mm.shape[0], 3))
    F[:, 2] = mass.effector_kg + 1.5 * mass.lower_arm_kg
    for Ge, nv, q in arm_rates(d, pose.P_mm, pose.theta_rad, J):
        zE = Ge[:, 2, :]  # dz_E/dx: e_i,z J_i
        F += mass.upper_arm_kg * mass.upper_arm_com_mm / d.upper_arm_mm * zE
        F += 0.5 * mass.lower_arm_kg * (zE + g * nv[:, 2:3] * q)
        F += mass.knee_kg * (zE + ck * nv[:, 2:3] * q)
    return G_M_S2 * F


def gravity_torques_Nm(d: Delta, P_mm, mass: DeltaMass) -> np.ndarray:
    """Joint torques (N, 3) [N m] that hold the delta still at ``P_mm``: J^-T grad_x V."""
    J, _ = jacobian_rad_per_m(d, P_mm)
    F = gravity_force_N(d, P_mm, mass)
    return np.linalg.solve(np.swapaxes(J, -1, -2), F[..., None])[..., 0]


def apparent_mass_extremes_kg(d: Delta, P_mm, mass: DeltaMass) -> dict:
    """The largest and smallest eigenvalue of Lambda over ``P_mm`` (N, 3) and where they
    occur: {"max_kg", "max_at_mm", "min_kg", "min_at_mm", "eig_kg" (N, 3) ascending}."""
    P = np.asarray(P_mm, dtype=float).reshape(-1, 3)
    eig = np.linalg.eigvalsh(mass_matrix_kg(d, P, mass))
    i_max, i_min = int(np.argmax(eig[:, -1])), int(np.argmin(eig[:, 0]))
    return {"max_kg": float(eig[i_max, -1]), "max_at_mm": P[i_max].tolist(),
            "min_kg": float(eig[i_min, 0]), "min_at_mm": P[i_min].tolist(), "eig_kg": eig}
