"""Global isotropy index (isotropy paper eqs 2-5): invariances, the isotropic case, failures, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cad.errors import DesignError
from cad.isotropy import gii as g
from cad.kinematics import fivebar as f

pos = st.floats(1e-3, 1e3)


@settings(max_examples=50, deadline=None)
@given(st.integers(0, 2**31 - 1))
def test_closed_form_2x2_singular_values_equal_lapack(seed):
    A = np.random.default_rng(seed).normal(size=(64, 2, 2)) * 10.0 ** np.random.default_rng(
        seed + 1
    ).uniform(-3, 3, size=(64, 1, 1))
    smin, smax = g.singular_value_extremes(A)
    s = np.linalg.svd(A, compute_uv=False)
    np.testing.assert_allclose(smax, s[:, 0], rtol=1e-12)
    np.testing.assert_allclose(smin, s[:, 1], rtol=1e-9, atol=1e-12 * s[:, 0].max())


@settings(max_examples=40, deadline=None)
@given(
    st.floats(20.0, 150.0),
    st.floats(60.0, 200.0),
    st.floats(80.0, 250.0),
    st.floats(120.0, 250.0),
    pos,
    pos,
    st.floats(0.2, 5.0),
    st.floats(0.2, 5.0),
)
def test_gii_invariant_to_uniform_scaling_of_SJ_and_ST(a, l2, l3, yc, cj, ct, r1, r2):
    """Scaling S_J or S_T by a scalar scales every singular value alike: eq (5) is unchanged.
    Non-uniform S_J (r1, r2) is a different normalization and is allowed to change it."""
    fb = f.FiveBar.symmetric(a, l2, l3)
    base = g.fivebar_gii(fb, (0.0, yc), 60.0, 7, (r1, r2), (1.0, 1.0))
    scaled = g.fivebar_gii(fb, (0.0, yc), 60.0, 7, (cj * r1, cj * r2), (ct, ct))
    assert scaled.gii == pytest.approx(base.gii, rel=1e-12, abs=1e-300)
    assert scaled.sigma_min == pytest.approx(base.sigma_min * cj / ct, rel=1e-12)
    assert scaled.sigma_max == pytest.approx(base.sigma_max * cj / ct, rel=1e-12)


@settings(max_examples=30, deadline=None)
@given(st.floats(0.1, 10.0))
def test_gii_invariant_to_scaling_mechanism_and_workspace_together(k):
    fb = f.FiveBar.symmetric(75.0, 125.0, 175.0)
    r0 = g.fivebar_gii(fb, (0.0, 200.0), 100.0, 9)
    rk = g.fivebar_gii(fb.scaled(k), (0.0, 200.0 * k), 100.0 * k, 9)
    assert rk.gii == pytest.approx(r0.gii, rel=1e-11)


def test_gii_equals_eq5_by_lapack_on_random_jacobians():
    rng = np.random.default_rng(7)
    J = rng.normal(size=(50, 4, 3))
    sj, st_ = rng.uniform(0.5, 2, 4), rng.uniform(0.5, 2, 3)
    r = g.gii_from_jacobians(J, np.zeros(50, int), rng.normal(size=(50, 3)), sj, st_)
    s = np.linalg.svd(np.diag(sj) @ J @ np.diag(1 / st_), compute_uv=False)
    assert r.gii == pytest.approx(s[:, -1].min() / s[:, 0].max(), rel=1e-12)
    assert r.sigma_min_index == int(np.argmin(s[:, -1]))
    assert r.sigma_max_index == int(np.argmax(s[:, 0]))


def test_gii_is_one_only_for_isotropy():
    """The closed-form isotropic 5-bar point (a = 0, l2 = l3 = L, E = (0, sqrt 2 L)) gives 1;
    rotating an isotropic J keeps 1; any non-isotropic or non-uniform stack gives < 1."""
    L = 100.0
    fb = f.FiveBar.symmetric(0.0, L, L)
    pt = np.array([[0.0, math.sqrt(2) * L]])
    J, status = f.jacobian_rad_per_m(fb, pt)
    assert g.gii_from_jacobians(J, status, pt, 1.0, 1.0).gii == pytest.approx(1.0, rel=1e-12)
    rng = np.random.default_rng(0)
    Q = np.linalg.qr(rng.normal(size=(20, 3, 3)))[0] * 2.5
    assert g.gii_from_jacobians(
        Q, np.zeros(20, int), np.zeros((20, 3)), 1.0, 1.0
    ).gii == pytest.approx(1.0)
    Q2 = Q.copy()
    Q2[3] *= 1.01  # isotropic everywhere, but not with the same singular value
    assert g.gii_from_jacobians(Q2, np.zeros(20, int), np.zeros((20, 3)), 1.0, 1.0).gii < 1.0
    Q3 = Q.copy()
    Q3[5, :, 0] *= 1.001  # one point slightly anisotropic
    assert g.gii_from_jacobians(Q3, np.zeros(20, int), np.zeros((20, 3)), 1.0, 1.0).gii < 1.0
    # a real workspace around the isotropic point is < 1
    assert g.fivebar_gii(fb, (0.0, math.sqrt(2) * L), 20.0, 5).gii < 1.0


def test_unreachable_workspace_gives_zero_and_names_the_point():
    fb = f.FiveBar.symmetric(60.0, 100.0, 150.0)
    r = g.fivebar_gii(fb, (0.0, 220.0), 100.0, 5)  # top edge at 270 mm > l2 + l3 = 250
    assert r.gii == 0.0 and r.sigma_min == 0.0
    assert "unreachable" in r.failure
    # independent check: the named point is farther than l2 + l3 from the arm the message names
    arm_base = np.array([-30.0, 0.0]) if "left" in r.failure else np.array([30.0, 0.0])
    assert np.linalg.norm(r.failed_at - arm_base) > 250.0
    # and it is the first such sample in grid order
    pts = g.square_grid_mm((0.0, 220.0), 100.0, 5)
    far = np.maximum(
        np.linalg.norm(pts - [-30.0, 0.0], axis=1), np.linalg.norm(pts - [30.0, 0.0], axis=1)
    )
    np.testing.assert_array_equal(r.failed_at, pts[np.flatnonzero(far > 250.0)[0]])
    assert r.n_failed >= 1
    np.testing.assert_array_equal(r.sigma_min_at, r.failed_at)


def test_singular_workspace_gives_zero_and_names_the_point():
    l2, l3 = 100.0, 150.0
    fb = f.FiveBar.symmetric(2 * l3, l2, l3)  # distal links collinear at E = (0, l2)
    r = g.fivebar_gii(fb, (0.0, l2), 40.0, 5)  # the grid centre is exactly (0, l2)
    assert r.gii == 0.0
    assert "collinear" in r.failure
    np.testing.assert_allclose(r.failed_at, [0.0, l2])


@pytest.mark.parametrize(
    "call, field",
    [
        (lambda fb: g.fivebar_gii(fb, (0, 200), 100.0, 1), "workspace.grid"),
        (lambda fb: g.fivebar_gii(fb, (0, 200), 100.0, 2.5), "workspace.grid"),
        (lambda fb: g.fivebar_gii(fb, (0, 200), 0.0, 5), "workspace.side_mm"),
        (lambda fb: g.fivebar_gii(fb, (0, 200, 1), 10.0, 5), "workspace.center_mm"),
        (lambda fb: g.fivebar_gii(fb, (0, 200), 10.0, 5, (1.0, -1.0)), "actuator_scale"),
        (lambda fb: g.fivebar_gii(fb, (0, 200), 10.0, 5, (1.0, 1.0, 1.0)), "actuator_scale"),
        (lambda fb: g.fivebar_gii(fb, (0, 200), 10.0, 5, 1.0, 0.0), "task_scale"),
        (
            lambda fb: g.gii_from_jacobians(
                np.zeros((3, 2, 2)), np.zeros(2), np.zeros((3, 2)), 1, 1
            ),
            "jacobian",
        ),
        (
            lambda fb: g.gii_from_jacobians(
                np.zeros((0, 2, 2)), np.zeros(0), np.zeros((0, 2)), 1, 1
            ),
            "jacobian",
        ),
    ],
)
def test_bad_inputs_raise_design_errors(call, field):
    fb = f.FiveBar.symmetric(60.0, 100.0, 150.0)
    with pytest.raises(DesignError, match=field):
        call(fb)


def test_grid_includes_boundary_and_boundary_first_order():
    pts = g.square_grid_mm((10.0, 200.0), 100.0, 5)
    assert pts.shape == (25, 2)
    assert pts[:, 0].min() == -40.0 and pts[:, 0].max() == 60.0
    assert pts[:, 1].min() == 150.0 and pts[:, 1].max() == 250.0
    order = g.boundary_first_order((5, 5))
    assert sorted(order.tolist()) == list(range(25))
    first4 = {tuple(pts[i]) for i in order[:4]}
    assert first4 == {(-40.0, 150.0), (60.0, 150.0), (-40.0, 250.0), (60.0, 250.0)}
    interior = order[-9:]
    assert np.all((np.abs(pts[interior, 0] - 10) < 50) & (np.abs(pts[interior, 1] - 200) < 50))
