"""The 5-bar's identification model (:mod:`cad.identify.joint2`) against independent methods:

* the joint-space mass matrix of the tree closed by virtual work equals the library's
  (:func:`cad.kinematics.fivebar.mass_matrix_kg`: each link's COM velocity by its twist map,
  T = 1/2 sum m v_G^2 + Izz w^2) mapped to joint space, and the datasheet's effective mass at
  home (:func:`cad.families.pantograph.dynamics.effective_mass`);
* d psi / dq equals central finite differences of the closure;
* the regressor's velocity terms equal the Christoffel symbols of M(q) (central differences
  of the mass matrix): the Lagrangian written out by hand is the one of M;
* the +y hand move turns each joint the way the plan says (inverse kinematics, finite steps).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from cad.identify import joint2
from cad.kinematics import fivebar as fb5
from cad.sim.identify_fivebar import jacobian


def _poses(pred, n, seed=0):
    rng = np.random.default_rng(seed)
    lo, hi = np.array(pred.q_min_rad), np.array(pred.q_max_rad)
    home = np.array(pred.q_home_rad)
    # around home, inside the ranges (the workspace's joint box holds poses that do not close)
    return home + (rng.uniform(-0.5, 0.5, (n, 2)) * (hi - lo) * 0.6)


def _fb(panto):
    return panto.mechanism


def test_mass_matrix_equals_the_twist_map_mass_matrix(panto, panto_pred, bars):
    pred = panto_pred
    rep = bars(panto)
    q = _poses(pred, 25)
    g = pred.geom
    E, _, _, ok = joint2.closure(g, q)
    assert ok.all()
    b = rep["bodies"]

    def lm(n):
        return fb5.LinkMass(b[n]["mass_kg"], (b[n]["com_mm"][0] * 1e-3, b[n]["com_mm"][1] * 1e-3),
                            b[n]["inertia_com_kg_m2"][2][2])

    mass = fb5.FiveBarMass(lm("proximal_left"), lm("proximal_right"), lm("distal_left"), lm("distal_right"),
                           pred.rotor_kg_m2)
    Mt = fb5.mass_matrix_kg(_fb(panto), E * 1e3, mass) + b["handle"]["mass_kg"] * np.eye(2)
    Jq, _ = fb5.jacobian_rad_per_m(_fb(panto), E * 1e3)  # dq/dE
    Jx = np.linalg.inv(Jq)
    want = np.einsum("nki,nkl,nlj->nij", Jx, Mt, Jx)
    got = joint2.mass_matrix(g, pred.beta_links, (pred.rotor_kg_m2,) * 2, q)
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(jacobian(g, q), Jx, rtol=1e-9, atol=1e-12)


def test_prediction_is_the_datasheets_effective_mass(panto, panto_pred, bars):
    from cad.families.pantograph.dynamics import effective_mass

    def mp(e):
        c = np.array(e["com_mm"]) * 1e-3
        return SimpleNamespace(mass_kg=e["mass_kg"], com_m=c, inertia_com_kg_m2=np.array(e["inertia_com_kg_m2"]))

    bodies = {k: mp(v) for k, v in bars(panto)["bodies"].items()}
    E0 = joint2.closure(panto_pred.geom, np.array([panto_pred.q_home_rad]))[0][0] * 1e3
    em, _ = effective_mass(panto, bodies, E0)
    got = 1e3 * panto_pred.task_mass_kg(np.array([panto_pred.q_home_rad]))
    np.testing.assert_allclose(got, em["mass_matrix_g"], rtol=1e-9, atol=1e-9)
    assert abs(got[0, 1]) > 1e-3  # the unequal offsets couple x and y


def test_distal_rates_are_finite_differences(panto_pred):
    g = panto_pred.geom
    q = _poses(panto_pred, 10, seed=1)
    _, psi, Psi, _ = joint2.closure(g, q)
    h = 1e-6
    for k in range(2):
        dq = np.zeros(2)
        dq[k] = h
        fd = (joint2.closure(g, q + dq)[1] - joint2.closure(g, q - dq)[1]) / (2 * h)
        np.testing.assert_allclose(Psi[:, :, k], fd, rtol=1e-6, atol=1e-8)


def test_velocity_terms_are_the_christoffel_symbols_of_M(panto_pred):
    g, beta = panto_pred.geom, panto_pred.beta_links
    rng = np.random.default_rng(3)
    q = _poses(panto_pred, 8, seed=2)
    v = rng.normal(0, 3.0, q.shape)
    a = rng.normal(0, 30.0, q.shape)
    _, psi, Psi, _ = joint2.closure(g, q)
    vpsi = np.einsum("nij,nj->ni", Psi, v)
    # psi'' = Psi q'' + d/dt(Psi) q', the second term by a central difference along q'
    h = 1e-6
    dPsi = (joint2.closure(g, q + h * v)[2] - joint2.closure(g, q - h * v)[2]) / (2 * h)
    apsi = np.einsum("nij,nj->ni", Psi, a) + np.einsum("nij,nj->ni", dPsi, v)
    tau = joint2.joint_regressor(g, q, v, a, psi, vpsi, apsi, Psi) @ beta
    M = joint2.mass_matrix(g, beta, (0.0, 0.0), q)
    dM = []
    for k in range(2):
        e = np.zeros(2)
        e[k] = h
        dM.append((joint2.mass_matrix(g, beta, (0, 0), q + e) - joint2.mass_matrix(g, beta, (0, 0), q - e)) / (2 * h))
    dM = np.stack(dM, axis=-1)  # (N, i, j, k) = dM_ij / dq_k
    # Gamma_ijk = 1/2 (dM_ij/dq_k + dM_ik/dq_j - dM_jk/dq_i)
    gam = 0.5 * (dM + np.einsum("nikj->nijk", dM) - np.einsum("njki->nijk", dM))
    want = np.einsum("nij,nj->ni", M, a) + np.einsum("nijk,nj,nk->ni", gam, v, v)
    np.testing.assert_allclose(tau, want, rtol=1e-6, atol=1e-9)


def test_hand_move_signs(panto, panto_pred):
    """Moving E by +1 mm along y from home turns each joint the way ``plan.hand_sign`` says
    (inverse kinematics of the design, no Jacobian)."""
    E0 = joint2.closure(panto_pred.geom, np.array([panto_pred.q_home_rad]))[0][0] * 1e3
    ik = fb5.ik(_fb(panto), np.array([E0, E0 + [0.0, 1.0]]))
    dq = ik.q_rad[1] - ik.q_rad[0]
    np.testing.assert_allclose(ik.q_rad[0], panto_pred.q_home_rad, atol=1e-9)
    assert tuple(np.sign(dq).astype(int)) == panto_pred.plan.hand_sign
    assert min(abs(dq)) > 1e-3


@pytest.mark.parametrize("j", [0, 1])
def test_plan_ranges_hold_the_workspace(panto, panto_pred, j):
    """The joint ranges are those of the workspace rectangle's corners and edges (IK)."""
    from cad.isotropy.gii import workspace_half_mm

    (cx, cy), (hx, hy) = panto.workspace["center_mm"], workspace_half_mm(panto.workspace)
    pts = np.array([[cx + sx * hx, cy + sy * hy] for sx in (-1, 0, 1) for sy in (-1, 0, 1)])
    q = fb5.ik(_fb(panto), pts).q_rad[:, j]
    assert panto_pred.q_min_rad[j] <= q.min() + 1e-12 and q.max() <= panto_pred.q_max_rad[j] + 1e-12
    assert panto_pred.q_min_rad[j] == pytest.approx(q.min(), abs=0.02)
