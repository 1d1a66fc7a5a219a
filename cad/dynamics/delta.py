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

Gravity (g along -z): the potential V(x) = g [m_e z_P + sum_i (m_arm z_G,i + m_rods
(z_E,i + z_P)/2)], and the force the motors must add at the effector to hold it is
grad_x V; the joint torques that do so are J^-T grad_x V (the gravity compensation).
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
    motor's rotor; ratio: transmission ratio n (1 = direct drive).
    """

    upper_arm_kg_m2: float
    upper_arm_kg: float
    upper_arm_com_mm: float
    lower_arm_kg: float
    effector_kg: float
    rotor_kg_m2: float = 0.0
    ratio: float = 1.0

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


def mass_matrix_kg(d: Delta, P_mm, mass: DeltaMass) -> np.ndarray:
    """Lambda (N, 3, 3) kg at effector points ``P_mm`` (N, 3) mm, base frame.

    Raises :class:`cad.errors.KinematicsError` naming the first point that is unreachable,
    singular or outside the joint limits.
    """
    pose = ik(d, P_mm)
    require_ok(pose)
    J, _ = jacobian_rad_per_m(d, pose.P_mm)
    e = _elbow_rate_m(d, pose.theta_rad)
    n = pose.P_mm.shape[0]
    arm = mass.upper_arm_kg_m2 + mass.ratio**2 * mass.rotor_kg_m2
    Lam = np.broadcast_to(mass.effector_kg * np.eye(3), (n, 3, 3)).copy()
    for i in range(3):
        Ji = J[:, i, :]
        Lam += arm * np.einsum("nk,nl->nkl", Ji, Ji)
        G = np.einsum("nk,nl->nkl", e[:, i, :], Ji)
        rod = np.einsum("nki,nkl->nil", G, G) + 0.5 * (G + np.swapaxes(G, 1, 2)) + np.eye(3)
        Lam += mass.lower_arm_kg / 3.0 * rod
    return Lam


def gravity_force_N(d: Delta, P_mm, mass: DeltaMass) -> np.ndarray:
    """grad_x V (N, 3) [N]: the force the motors must add at the effector to hold it still
    against gravity at ``P_mm`` (N, 3) mm (its z component is the weight carried)."""
    pose = ik(d, P_mm)
    require_ok(pose)
    J, _ = jacobian_rad_per_m(d, pose.P_mm)
    theta = pose.theta_rad
    dzE = -d.upper_arm_mm * np.cos(theta) * MM  # dz_E,i/dtheta_i, m/rad
    dzG = dzE * mass.upper_arm_com_mm / d.upper_arm_mm
    dV_dtheta = G_M_S2 * (mass.upper_arm_kg * dzG + 0.5 * mass.lower_arm_kg * dzE)
    direct = G_M_S2 * (mass.effector_kg + 1.5 * mass.lower_arm_kg)
    F = np.einsum("ni,nik->nk", dV_dtheta, J)
    F[:, 2] += direct
    return F


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
