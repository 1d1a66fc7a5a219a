"""Culling optimizer (Stocco, Salcudean & Sassani 1998) against brute force (isotropy paper eq 6)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cad.errors import DesignError
from cad.isotropy import fig2_study
from cad.isotropy.culling import brute_force, culling, optimize
from cad.isotropy.gii import fivebar_gii, square_grid_mm
from cad.isotropy.problems import FiveBarProblem, candidate_grid
from cad.kinematics.fivebar import FiveBar


class TableProblem:
    """A problem given by tables of sigma_min / sigma_max: tests the algorithm alone."""

    def __init__(self, smin, smax, rng):
        self.smin, self.smax = smin, smax
        self.n_candidates, self.n_points = smin.shape
        self._order = rng.permutation(self.n_points)
        self._seed = rng.integers(0, self.n_points, size=rng.integers(0, 3))
        self.calls = 0

    def sigma(self, c, p):
        self.calls += c.size
        return self.smin[c, p], self.smax[c, p]

    def point_order(self):
        return self._order

    def seed_points(self):
        return self._seed


@settings(max_examples=150, deadline=None)
@given(
    st.integers(1, 40),
    st.integers(1, 30),
    st.floats(0.0, 0.3),
    st.booleans(),
    st.integers(0, 2**31 - 1),
)
def test_culling_equals_brute_force_on_random_tables(M, N, p_fail, small_ints, seed):
    """Small integer sigmas force many ties; zeros stand for failed samples. Same index, same GII."""
    rng = np.random.default_rng(seed)
    if small_ints:
        a = rng.integers(1, 4, size=(M, N)).astype(float)
        b = a + rng.integers(0, 3, size=(M, N))
    else:
        a = rng.uniform(0.1, 1.0, size=(M, N))
        b = a * rng.uniform(1.0, 5.0, size=(M, N))
    fail = rng.random((M, N)) < p_fail
    a[fail] = 0.0
    b[fail] = 0.0
    pb = TableProblem(a, b, np.random.default_rng(seed))
    pc = TableProblem(a, b, np.random.default_rng(seed))
    rb, rc = brute_force(pb), culling(pc)
    assert rc.best_index == rb.best_index
    assert rc.gii == rb.gii
    # independent reference: eq (5) per candidate, first argmax
    with np.errstate(invalid="ignore", divide="ignore"):
        ref = np.where(b.max(axis=1) > 0, a.min(axis=1) / b.max(axis=1), 0.0)
    assert rb.best_index == int(np.argmax(ref)) and rb.gii == ref.max()
    assert rc.jacobian_evaluations == pc.calls <= M * N
    assert rb.jacobian_evaluations == pb.calls == M * N


@settings(max_examples=25, deadline=None)
@given(
    st.floats(-250.0, 250.0),
    st.tuples(st.floats(0.0, 100.0), st.floats(10.0, 300.0), st.integers(1, 6)),
    st.tuples(st.floats(30.0, 200.0), st.floats(10.0, 300.0), st.integers(1, 6)),
    st.tuples(st.floats(30.0, 200.0), st.floats(10.0, 300.0), st.integers(1, 6)),
    st.sampled_from([3, 5, 6]),
)
def test_culling_equals_brute_force_on_random_fivebar_sets(yc, ra, r2, r3, grid):
    rng = {
        "base_mm": (ra[0], ra[0] + ra[1], ra[2]),
        "proximal_mm": (r2[0], r2[0] + r2[1], r2[2]),
        "distal_mm": (r3[0], r3[0] + r3[1], r3[2]),
    }
    _, params = candidate_grid(rng, {})
    pr = FiveBarProblem(params, square_grid_mm([0.0, yc], 100.0, grid), grid)
    rb, rc = brute_force(pr), culling(pr)
    assert (rc.best_index, rc.gii) == (rb.best_index, rb.gii)
    # the optimum's GII is the one fivebar_gii computes for that geometry
    best = pr.candidate(rb.best_index)
    direct = fivebar_gii(FiveBar.symmetric(**best), (0.0, yc), 100.0, grid).gii
    assert rb.gii == pytest.approx(direct, rel=1e-12, abs=0.0)


@pytest.mark.parametrize("yc", [-200.0, 200.0])
def test_culling_needs_ten_times_fewer_evaluations_on_fig2_problem(yc):
    _, params = candidate_grid(
        {
            "base_mm": (0.0, 400.0, 9),
            "proximal_mm": (25.0, 500.0, 11),
            "distal_mm": (25.0, 500.0, 11),
        },
        {},
    )
    pr = FiveBarProblem(params, square_grid_mm([0.0, yc], 100.0, 11), 11)
    rb, rc = brute_force(pr), culling(pr)
    assert (rc.best_index, rc.gii) == (rb.best_index, rb.gii)
    assert rb.jacobian_evaluations == 1089 * 121
    assert rb.jacobian_evaluations >= 10 * rc.jacobian_evaluations


def test_fig2_study_quick_matches_brute_force_everywhere(tmp_path):
    out = fig2_study.run(tmp_path, quick=True)
    assert out["all_same_optimum"]
    assert out["min_evaluation_ratio"] >= 10
    assert [r["center_y_mm"] for r in out["rows"]] == [-300, -200, -100, 0, 100, 200, 300]
    assert all(0 < r["gii"] < 1 for r in out["rows"])
    assert (tmp_path / "fig2_study.png").stat().st_size > 0


def test_all_candidates_failing_gives_first_index_and_zero():
    _, params = candidate_grid(
        {"base_mm": (0.0, 50.0, 3), "proximal_mm": (20.0, 40.0, 3), "distal_mm": (20.0, 40.0, 2)},
        {},
    )
    pr = FiveBarProblem(params, square_grid_mm([0.0, 500.0], 100.0, 5), 5)  # far out of reach
    rb, rc = brute_force(pr), culling(pr)
    assert (rb.best_index, rb.gii) == (rc.best_index, rc.gii) == (0, 0.0)
    assert rc.jacobian_evaluations <= rb.jacobian_evaluations


def test_bad_optimizer_inputs():
    _, params = candidate_grid(
        {"base_mm": (0.0, 50.0, 2)}, {"proximal_mm": 100.0, "distal_mm": 150.0}
    )
    pr = FiveBarProblem(params, square_grid_mm([0.0, 150.0], 50.0, 3), 3)
    with pytest.raises(DesignError, match="method"):
        optimize(pr, "genetic")
    with pytest.raises(DesignError, match="optimize.base_mm"):
        candidate_grid({"base_mm": (0.0, 50.0, 0)}, {})
    with pytest.raises(DesignError, match="optimize.base_mm"):
        candidate_grid({"base_mm": (60.0, 50.0, 2)}, {})
    with pytest.raises(DesignError, match="optimize.proximal_mm"):
        FiveBarProblem(
            {"base_mm": [1.0], "proximal_mm": [-1.0], "distal_mm": [1.0]}, np.zeros((1, 2)), 1
        )
