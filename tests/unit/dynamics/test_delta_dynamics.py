"""Delta Lambda(x) and gravity (cad/dynamics/delta.py) against an independent model.

Reference: the kinetic and potential energy of the device discretised into point masses
(each lower-arm rod as 400 points between its end joints placed by the IK, each upper arm
as its inertia about the motor axis), velocities by central finite differences of the
positions along a test velocity: no Jacobian, no closed-form rod formula.
"""

from __future__ import annotations

import numpy as np
import pytest

from cad.dynamics.delta import G_M_S2, DeltaMass, apparent_mass_extremes_kg, gravity_force_N
from cad.dynamics.delta import gravity_torques_Nm, mass_matrix_kg
from cad.errors import DesignError, KinematicsError
from cad.kinematics import delta as D

DELTA = D.Delta(60.0, 20.0, 100.0, 200.0, theta_min_rad=-1.0, theta_max_rad=1.4)
MASS = DeltaMass(upper_arm_kg_m2=2.0e-4, upper_arm_kg=0.05, upper_arm_com_mm=40.0,
                 lower_arm_kg=0.03, effector_kg=0.08, rotor_kg_m2=1.0e-6, ratio=8.0)


def _points_of(P_mm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Positions (K, 3) m of the rod point masses and the joint angles at effector P (mm)."""
    theta = D.ik(DELTA, P_mm).theta_rad[0]
    u = DELTA.radial
    E = DELTA.base_radius_mm * u + DELTA.upper_arm_mm * (
        np.cos(theta)[:, None] * u - np.sin(theta)[:, None] * np.array([0, 0, 1.0]))
    ends = P_mm + DELTA.effector_radius_mm * u
    s = (np.arange(400) + 0.5) / 400
    pts = E[:, None, :] + s[None, :, None] * (ends - E)[:, None, :]
    return pts.reshape(-1, 3) * 1e-3, theta


def _energy_reference(P_mm, v_m_s):
    h = 1e-4  # mm of effector travel per unit of the test velocity
    x1, t1 = _points_of(P_mm + h * v_m_s)
    x0, t0 = _points_of(P_mm - h * v_m_s)
    vel = (x1 - x0) / (2 * h * 1e-3)  # per (m/s) of effector speed
    dtheta = (t1 - t0) / (2 * h * 1e-3)
    m_pt = MASS.lower_arm_kg / 400
    arm = MASS.upper_arm_kg_m2 + MASS.ratio**2 * MASS.rotor_kg_m2
    T = 0.5 * m_pt * np.sum(vel**2) + 0.5 * arm * np.sum(dtheta**2)
    return T + 0.5 * MASS.effector_kg * v_m_s @ v_m_s


@pytest.mark.parametrize("theta", [[0.2, 0.5, 0.8], [0.6, 0.6, 0.6], [1.1, -0.2, 0.4]])
def test_kinetic_energy_matches_discretised_model(theta):
    P = D.fk(DELTA, theta).P_mm
    Lam = mass_matrix_kg(DELTA, P, MASS)[0]
    assert np.allclose(Lam, Lam.T)
    rng = np.random.default_rng(11)
    for v in rng.normal(size=(4, 3)):
        # midpoint rule on 400 points: relative error ~ 1/(12 * 400^2) of the rod's share
        assert 0.5 * v @ Lam @ v == pytest.approx(_energy_reference(P[0], v), rel=1e-6)


def test_gravity_force_is_the_gradient_of_the_potential():
    def V(P_mm):
        pts, theta = _points_of(P_mm)
        zG = -MASS.upper_arm_com_mm * np.sin(theta) * 1e-3
        return G_M_S2 * (MASS.lower_arm_kg / 400 * pts[:, 2].sum() + MASS.upper_arm_kg * zG.sum()
                         + MASS.effector_kg * P_mm[2] * 1e-3)

    P = D.fk(DELTA, [0.3, 0.7, 0.5]).P_mm
    F = gravity_force_N(DELTA, P, MASS)[0]
    h = 1e-3
    grad = [(V(P[0] + h * e) - V(P[0] - h * e)) / (2 * h * 1e-3) for e in np.eye(3)]
    np.testing.assert_allclose(F, grad, rtol=1e-6, atol=1e-9)
    tau = gravity_torques_Nm(DELTA, P, MASS)[0]
    np.testing.assert_allclose(tau, D.joint_torques_Nm(DELTA, P, F[None])[0], rtol=1e-12)


def test_weight_on_axis_symmetric_pose_closed_form():
    """On the axis with equal angles the x, y gravity forces vanish by symmetry; the total
    potential's z-derivative at theta equal is the whole weight shared through the arms."""
    P = D.fk(DELTA, [0.6] * 3).P_mm
    F = gravity_force_N(DELTA, P, MASS)[0]
    assert abs(F[0]) < 1e-12 and abs(F[1]) < 1e-12
    assert F[2] > G_M_S2 * (MASS.effector_kg + 1.5 * MASS.lower_arm_kg)


def test_extremes_and_failures_named():
    pts = D.box_grid_mm(D.fk(DELTA, [0.6] * 3).P_mm[0], [40, 40, 30], 3)
    ext = apparent_mass_extremes_kg(DELTA, pts, MASS)
    assert ext["max_kg"] >= ext["min_kg"] >= MASS.effector_kg
    with pytest.raises(KinematicsError, match="unreachable"):
        mass_matrix_kg(DELTA, [[0, 0, 0]], MASS)
    with pytest.raises(DesignError, match="delta_mass.ratio"):
        DeltaMass(1e-4, 0.05, 40, 0.03, 0.08, ratio=0.0)
