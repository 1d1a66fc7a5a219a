"""Twin-pantograph haptic mouse (isotropy paper §4.1): eq 7, 4x3 Jacobian, GII, mass matrix."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cad.errors import DesignError
from cad.isotropy.culling import brute_force, culling
from cad.isotropy.gii import singular_value_extremes
from cad.isotropy.problems import TwinPantographProblem, candidate_grid
from cad.kinematics import fivebar as f
from cad.kinematics import twin_pantograph as tw

TP = tw.TwinPantograph.symmetric(75.0, 125.0, 175.0, knob_diameter_mm=12.5)


def test_eq7_crank_length():
    """Eq (7): l6 = 1.6 l5; a 12.5 mm knob gives a 20 mm crank."""
    assert tw.crank_length_mm(12.5) == pytest.approx(20.0)
    assert TP.crank_mm == pytest.approx(20.0)
    with pytest.raises(DesignError, match="knob_diameter_mm"):
        tw.crank_length_mm(0.0)


def test_journals_are_one_crank_apart():
    X = np.array([[0.0, 200.0, 0.3], [20.0, 180.0, 4.0]])
    pk, pc = tw.journals_mm(TP, X)
    np.testing.assert_allclose(np.linalg.norm(pc - pk, axis=1), 20.0, rtol=1e-14)
    np.testing.assert_allclose(pk, X[:, :2])


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**31 - 1))
def test_jacobian_matches_central_differences(seed):
    rng = np.random.default_rng(seed)
    X = np.c_[rng.uniform(-50, 50, 15), rng.uniform(150, 250, 15), rng.uniform(0, 2 * np.pi, 15)]
    J, status = tw.jacobian_si(TP, X)
    assert np.all(status == 0)
    steps = (1e-5, 1e-5, 1e-8)
    for k, h in enumerate(steps):
        d = np.zeros(3)
        d[k] = h
        fd = (tw.ik(TP, X + d).q_rad - tw.ik(TP, X - d).q_rad) / (2 * h)
        if k < 2:
            fd = fd * 1e3  # per mm -> per m
        np.testing.assert_allclose(fd, J[:, :, k], rtol=1e-5, atol=1e-6)


def test_jacobian_block_structure():
    """Knob rows do not see theta; crank rows see it through l6 (cos, sin) rotated by 90 deg."""
    X = np.array([[10.0, 190.0, 1.1]])
    J, _ = tw.jacobian_si(TP, X)
    assert np.all(J[0, 0:2, 2] == 0)
    Jc, _ = f.jacobian_rad_per_m(TP.crank, tw.journals_mm(TP, X)[1])
    np.testing.assert_allclose(
        J[0, 2:4, 2], Jc[0] @ (0.02 * np.array([-np.sin(1.1), np.cos(1.1)])), rtol=1e-13
    )


def test_gii_of_bundled_geometry_and_redundancy():
    r = tw.twin_gii(TP, (0.0, 200.0), 100.0, 7, 8)
    assert 0.0 < r.gii < 1.0 and r.failure is None
    # with the default S_T (F, F, F l6 / 2) the GII equals eq (5) evaluated with LAPACK directly
    X = tw.workspace_grid((0.0, 200.0), 100.0, 7, 8)
    J, _ = tw.jacobian_si(TP, X)
    s = np.linalg.svd(J / np.array([1.0, 1.0, 0.01]), compute_uv=False)
    assert r.gii == pytest.approx(s[:, -1].min() / s[:, 0].max(), rel=1e-12)
    # removing the redundant actuator (row 4) cannot improve the worst sigma_min
    s3 = np.linalg.svd(J[:, :3, :] / np.array([1.0, 1.0, 0.01]), compute_uv=False)
    assert s3[:, -1].min() <= s[:, -1].min()


def test_unreachable_crank_workspace_names_the_crank_pantograph():
    small = tw.TwinPantograph.symmetric(60.0, 100.0, 150.0, crank_mm=30.0)
    # knob journal reachable at y = 240 (< 250) but the crank pin at y = 270 is not
    r = tw.twin_gii(small, (0.0, 215.0), 50.0, 3, 4)
    assert r.gii == 0.0
    assert r.failure.startswith("crank pantograph") and "unreachable" in r.failure


def test_twin_problem_culling_equals_brute_and_gii():
    _, params = candidate_grid(
        {
            "base_mm": (0.0, 150.0, 4),
            "proximal_mm": (75.0, 200.0, 4),
            "distal_mm": (100.0, 250.0, 4),
        },
        {"crank_mm": 20.0},
    )
    X = tw.workspace_grid((0.0, 200.0), 100.0, 5, 6)
    pr = TwinPantographProblem(params, X, (5, 5, 6))
    assert sorted(pr.point_order().tolist()) == list(range(pr.n_points))
    rb, rc = brute_force(pr), culling(pr)
    assert (rc.best_index, rc.gii) == (rb.best_index, rb.gii)
    best = pr.candidate(rb.best_index)
    tp = tw.TwinPantograph.symmetric(
        best["base_mm"], best["proximal_mm"], best["distal_mm"], crank_mm=20.0
    )
    assert tw.twin_gii(tp, (0.0, 200.0), 100.0, 5, 6).gii == pytest.approx(rb.gii, rel=1e-12)


def _mass():
    link = f.LinkMass(0.03, (0.06, 0.002), 4e-5)
    fm = f.FiveBarMass(
        link,
        link,
        f.LinkMass(0.04, (0.09, 0.0), 8e-5),
        f.LinkMass(0.04, (0.09, 0.0), 8e-5),
        1.05e-6,
    )
    return tw.TwinMass(fm, fm, f.LinkMass(0.05, (0.008, 0.001), 3e-6))


def test_task_mass_matrix_equals_sum_of_journal_mass_matrices_and_crankshaft():
    """Independent assembly: journal velocities by finite differences of journals_mm."""
    m = _mass()
    X = np.array([[0.0, 200.0, np.pi / 2], [30.0, 170.0, 2.5]])
    M = tw.task_mass_matrix(TP, X, m)
    rng = np.random.default_rng(5)
    v = rng.normal(size=(2, 3)) * np.array([1.0, 1.0, 20.0])  # m/s, m/s, rad/s
    h = 1e-7
    Xp = X + h * v * np.array([1e3, 1e3, 1.0])
    Xm = X - h * v * np.array([1e3, 1e3, 1.0])
    pkp, pcp = tw.journals_mm(TP, Xp)
    pkm, pcm = tw.journals_mm(TP, Xm)
    vk = (pkp - pkm) * 1e-3 / (2 * h)
    vc = (pcp - pcm) * 1e-3 / (2 * h)
    pk, pc = tw.journals_mm(TP, X)
    Mk = f.mass_matrix_kg(TP.knob, pk, m.knob)
    Mc = f.mass_matrix_kg(TP.crank, pc, m.crank)
    T = 0.5 * np.einsum("ni,nij,nj->n", vk, Mk, vk) + 0.5 * np.einsum("ni,nij,nj->n", vc, Mc, vc)
    # crankshaft: COM velocity from finite differences of its COM position
    cs = m.crankshaft

    def com(Xq):
        th = Xq[:, 2]
        c = np.asarray(cs.com_link_m)
        return (
            Xq[:, :2] * 1e-3
            + np.c_[np.cos(th) * c[0] - np.sin(th) * c[1], np.sin(th) * c[0] + np.cos(th) * c[1]]
        )

    vg = (com(Xp) - com(Xm)) / (2 * h)
    T += 0.5 * cs.mass_kg * np.sum(vg**2, axis=1) + 0.5 * cs.izz_com_kg_m2 * v[:, 2] ** 2
    np.testing.assert_allclose(0.5 * np.einsum("ni,nij,nj->n", v, M, v), T, rtol=1e-6)


def test_effective_mass_of_a_lone_crankshaft_is_its_mass():
    zero = f.LinkMass(0.0)
    fm = f.FiveBarMass(zero, zero, zero, zero, 0.0)
    cs = f.LinkMass(0.1, (0.0, 0.0), 2e-5)
    e = tw.effective_mass_home(TP, (0.0, 200.0, np.pi / 2), tw.TwinMass(fm, fm, cs))
    assert e["mass_x_g_diag"] == pytest.approx(100.0)
    assert e["mass_y_g_apparent"] == pytest.approx(100.0)
    assert e["inertia_theta_g_cm2_diag"] == pytest.approx(200.0)  # 2e-5 kg m^2 = 200 g cm^2


def test_singular_value_helper_handles_4x3():
    J, _ = tw.jacobian_si(TP, [[0.0, 200.0, 0.0]])
    smin, smax = singular_value_extremes(J)
    s = np.linalg.svd(J[0], compute_uv=False)
    assert (smin[0], smax[0]) == pytest.approx((s[-1], s[0]))


def test_bad_twin_inputs():
    with pytest.raises(DesignError, match="crank_mm"):
        tw.TwinPantograph.symmetric(75.0, 125.0, 175.0, crank_mm=-1.0)
    with pytest.raises(DesignError, match="theta_grid"):
        tw.workspace_grid((0.0, 200.0), 100.0, 3, 0)
    with pytest.raises(DesignError, match="X"):
        tw.jacobian_si(TP, np.zeros((2, 2)))
    with pytest.raises(DesignError, match="force_max_N"):
        tw.task_scale(0.0, 20.0)
