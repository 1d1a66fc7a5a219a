"""5-bar kinematics: FK(IK) identity, loop closure, J vs finite differences, masks, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cad.errors import DesignError, KinematicsError
from cad.kinematics import fivebar as f

designs = st.tuples(
    st.floats(0.0, 200.0),  # base
    st.floats(40.0, 250.0),  # proximal
    st.floats(40.0, 300.0),  # distal
)


def _reachable_points(fb: f.FiveBar, rng, n=40):
    """Random points in front of the base, inside the reach of both arms."""
    r = min(fb.proximal_left_mm + fb.distal_left_mm, fb.proximal_right_mm + fb.distal_right_mm)
    E = np.c_[rng.uniform(-0.5, 0.5, n) * r, rng.uniform(0.05, 0.9, n) * r]
    return E


@settings(max_examples=40, deadline=None)
@given(designs, st.integers(0, 2**31 - 1))
def test_fk_of_ik_is_identity_and_loops_close(d, seed):
    fb = f.FiveBar.symmetric(*d)
    E = _reachable_points(fb, np.random.default_rng(seed))
    pose = f.ik(fb, E)
    ok = pose.ok
    # loop closure of the IK: |C - B| = l2, |E - C| = l3 on both arms
    for C, B in ((pose.C_left_mm, fb.base_left_mm), (pose.C_right_mm, fb.base_right_mm)):
        np.testing.assert_allclose(np.linalg.norm(C[ok] - B, axis=1), d[1], rtol=1e-12)
        np.testing.assert_allclose(np.linalg.norm(E[ok] - C[ok], axis=1), d[2], rtol=1e-9)
    # FK in the assembly mode of each pose returns E
    modes = f.assembly_mode(pose)
    for m in (1, -1):
        sel = ok & (modes == m)
        if sel.any():
            back = f.fk(fb, pose.q_rad[sel], assembly=m)
            np.testing.assert_allclose(back.E_mm, E[sel], atol=1e-7 * max(d))
            assert np.all(back.status == 0)


def test_elbow_convention_of_issue_6():
    """q1 = atan2(E - B1) + acos(...), q2 = atan2(E - B2) - acos(...), written out by hand."""
    a, l2, l3 = 80.0, 120.0, 160.0
    fb = f.FiveBar.symmetric(a, l2, l3)
    E = np.array([10.0, 170.0])
    B1, B2 = np.array([-a / 2, 0]), np.array([a / 2, 0])
    r1, r2 = np.linalg.norm(E - B1), np.linalg.norm(E - B2)
    q1 = math.atan2(*(E - B1)[::-1]) + math.acos((l2**2 + r1**2 - l3**2) / (2 * l2 * r1))
    q2 = math.atan2(*(E - B2)[::-1]) - math.acos((l2**2 + r2**2 - l3**2) / (2 * l2 * r2))
    np.testing.assert_allclose(f.ik(fb, E).q_rad[0], [q1, q2], rtol=1e-14)
    # elbows out above the base: left elbow left of B1's x-line through E, right elbow right
    pose = f.ik(fb, E)
    assert pose.C_left_mm[0, 0] < -a / 2 and pose.C_right_mm[0, 0] > a / 2


@settings(max_examples=40, deadline=None)
@given(designs, st.integers(0, 2**31 - 1))
def test_jacobian_matches_central_differences(d, seed):
    fb = f.FiveBar.symmetric(*d)
    E = _reachable_points(fb, np.random.default_rng(seed), 20)
    J, status = f.jacobian_rad_per_m(fb, E)
    h = 1e-5  # mm
    for k in range(2):
        dE = np.zeros(2)
        dE[k] = h
        qp, qm = f.ik(fb, E + dE), f.ik(fb, E - dE)
        fd = (qp.q_rad - qm.q_rad) / (2 * h * 1e-3)  # rad/m
        # well-conditioned points only: near type-1 singularities FD truncation blows up
        good = (status == 0) & qp.ok & qm.ok & (np.abs(J).max(axis=(1, 2)) < 1e3)
        np.testing.assert_allclose(fd[good], J[good][:, :, k], rtol=1e-5, atol=1e-6)


def test_isotropic_point_closed_form():
    """a = 0, l2 = l3 = L, E = (0, sqrt(2) L): J = 1/(L sin 2a) [[-s, -c], [-s, c]] with a = 45 deg,
    both singular values 1/L (derived by hand from the row formula)."""
    L = 0.1  # m
    fb = f.FiveBar.symmetric(0.0, L * 1e3, L * 1e3)
    J, status = f.jacobian_rad_per_m(fb, [0.0, math.sqrt(2) * L * 1e3])
    s = c = math.sqrt(0.5)
    expected = np.array([[-s, -c], [-s, c]]) / L
    np.testing.assert_allclose(J[0], expected, rtol=1e-12)
    np.testing.assert_allclose(np.linalg.svd(J[0], compute_uv=False), [1 / L, 1 / L], rtol=1e-12)
    assert status[0] == f.STATUS_OK


def test_unreachable_points_are_masked_and_named():
    fb = f.FiveBar.symmetric(60.0, 100.0, 150.0)
    E = np.array([[0.0, 200.0], [0.0, 400.0], [300.0, 0.0], [-30.0, 0.0]])
    pose = f.ik(fb, E)
    assert pose.status.tolist() == [
        f.STATUS_OK,
        f.STATUS_UNREACHABLE_LEFT,  # beyond l2 + l3 from both: left is reported first
        f.STATUS_UNREACHABLE_LEFT,  # 330 mm from B1 > 250
        f.STATUS_UNREACHABLE_LEFT,  # on B1 with l2 != l3 (|E - B1| = 0 < 50)
    ]
    assert pose.reachable.tolist() == [True, False, False, False]
    assert np.all(np.isfinite(pose.q_rad))
    J, st_ = f.jacobian_rad_per_m(fb, E)
    assert np.all(J[1:] == 0) and np.all(np.isfinite(J))
    assert "unreachable by the left arm" in pose.describe(1)
    with pytest.raises(KinematicsError, match="unreachable"):
        f.require_ok(pose)
    # right arm only: a point reachable from B1 but not from B2
    fb2 = f.FiveBar.symmetric(200.0, 100.0, 150.0)
    assert f.ik(fb2, [-200.0, 100.0]).status[0] == f.STATUS_UNREACHABLE_RIGHT


def test_singular_points_are_masked_and_named():
    l2, l3 = 100.0, 150.0
    # type-1: E at exactly l2 + l3 from B1 (left arm stretched); a longer right arm reaches it
    fb = f.FiveBar((-50.0, 0.0), (50.0, 0.0), l2, 150.0, l3, 200.0)
    E1 = np.array([-50.0, l2 + l3])
    # type-2: a = 2 l3, E = (0, l2): q1 = q2 = 90 deg, both distal links horizontal (collinear)
    fb2 = f.FiveBar.symmetric(2 * l3, l2, l3)
    p1 = f.ik(fb, E1)
    p2 = f.ik(fb2, [0.0, l2])
    assert p1.status[0] == f.STATUS_SINGULAR_LEFT and p1.singular[0] and p1.reachable[0]
    assert p2.status[0] == f.STATUS_SINGULAR_DISTAL
    np.testing.assert_allclose(p2.q_rad[0], [math.pi / 2, math.pi / 2], atol=1e-12)
    assert "collinear" in p2.describe(0)
    J, _ = f.jacobian_rad_per_m(fb2, [0.0, l2])
    assert np.all(J == 0)


def test_fk_reports_no_closure():
    fb = f.FiveBar.symmetric(400.0, 50.0, 60.0)
    pose = f.fk(fb, [[math.pi / 2, math.pi / 2]])  # elbows 400 mm apart > 2 l3
    assert pose.status[0] == f.STATUS_NO_CLOSURE and not pose.reachable[0]
    assert np.all(pose.E_mm == 0)


@pytest.mark.parametrize(
    "kwargs, field",
    [
        (dict(base_mm=-1.0, proximal_mm=1.0, distal_mm=1.0), "base_mm"),
        (dict(base_mm=1.0, proximal_mm=0.0, distal_mm=1.0), "proximal_left_mm"),
        (dict(base_mm=1.0, proximal_mm=1.0, distal_mm=float("nan")), "distal_left_mm"),
    ],
)
def test_bad_geometry_is_a_design_error(kwargs, field):
    with pytest.raises(DesignError, match=field):
        f.FiveBar.symmetric(**kwargs)


def test_bad_points_and_modes():
    fb = f.FiveBar.symmetric(60.0, 100.0, 150.0)
    with pytest.raises(DesignError, match="E_mm"):
        f.ik(fb, np.zeros((3, 3)))
    with pytest.raises(DesignError, match="E_mm"):
        f.ik(fb, [[0.0, np.inf]])
    with pytest.raises(DesignError, match="assembly"):
        f.fk(fb, [[0.0, 0.0]], assembly=0)
    with pytest.raises(DesignError, match="elbow_left"):
        f.FiveBar((-1.0, 0.0), (1.0, 0.0), 1.0, 1.0, 1.0, 1.0, elbow_left=0)


def test_mass_matrix_matches_kinetic_energy_by_finite_differences():
    """E_dot^T M E_dot / 2 equals the kinetic energy of every link, whose COM velocity and
    spin come from central differences of IK poses (independent of the twist maps)."""
    fb = f.FiveBar.symmetric(75.0, 125.0, 175.0)
    lm = [
        f.LinkMass(0.030, (0.05, 0.004), 2e-5),
        f.LinkMass(0.035, (0.06, -0.003), 3e-5),
        f.LinkMass(0.040, (0.09, 0.002), 6e-5),
        f.LinkMass(0.045, (0.08, 0.0), 7e-5),
    ]
    mass = f.FiveBarMass(*lm, rotor_kg_m2=1.05e-6)
    E = np.array([[10.0, 210.0], [-40.0, 160.0]])
    M = f.mass_matrix_kg(fb, E, mass)
    rng = np.random.default_rng(3)
    v = rng.normal(size=(2, 2))  # m/s
    h = 1e-6  # s

    def frames(P):
        pose = f.ik(fb, P)
        out = []
        for i, (B, C) in enumerate(
            ((fb.base_left_mm, pose.C_left_mm), (fb.base_right_mm, pose.C_right_mm))
        ):
            B = np.asarray(B) * 1e-3
            Cm = C * 1e-3
            ang_p = pose.q_rad[:, i]
            ang_d = np.arctan2(P[:, 1] * 1e-3 - Cm[:, 1], P[:, 0] * 1e-3 - Cm[:, 0])
            out.append((B, ang_p))
            out.append((Cm, ang_d))
        return out, pose.q_rad

    fp, qp = frames(E + v * h * 1e3)
    fm, qm = frames(E - v * h * 1e3)
    order = [lm[0], lm[2], lm[1], lm[3]]  # frames() yields prox L, dist L, prox R, dist R
    T = np.zeros(E.shape[0])
    for (Op, ap), (Om, am), link in zip(fp, fm, order, strict=True):
        c = np.asarray(link.com_link_m)

        def G(origin, a, c=c):
            return origin + np.stack(
                [np.cos(a) * c[0] - np.sin(a) * c[1], np.sin(a) * c[0] + np.cos(a) * c[1]], -1
            )

        vG = (G(Op, ap) - G(Om, am)) / (2 * h)
        w = (ap - am) / (2 * h)
        T += 0.5 * link.mass_kg * np.sum(vG**2, axis=1) + 0.5 * link.izz_com_kg_m2 * w**2
    T += 0.5 * mass.rotor_kg_m2 * np.sum(((qp - qm) / (2 * h)) ** 2, axis=1)
    T_M = 0.5 * np.einsum("ni,nij,nj->n", v, M, v)
    np.testing.assert_allclose(T_M, T, rtol=1e-6)
