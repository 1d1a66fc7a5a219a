"""Twin-pantograph haptic pen (isotropy paper §4.2, Table 2): Jacobian, GII trend, optimizer."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cad.errors import DesignError
from cad.isotropy import pen_study
from cad.isotropy.culling import brute_force, culling
from cad.isotropy.problems import PenProblem, candidate_grid
from cad.kinematics import haptic_pen as hp

PEN = hp.HapticPen(24.0, 145.0, 200.0, 70.0, None, 1.7)  # Table 2, 20 cm row


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**31 - 1))
def test_jacobian_matches_central_differences(seed):
    rng = np.random.default_rng(seed)
    n = 12
    X = np.c_[
        rng.uniform(-80, 80, n),
        rng.uniform(150, 250, n),
        rng.uniform(-50, 50, n),
        rng.uniform(-0.7, 0.7, n),
        rng.uniform(-0.7, 0.7, n),
    ]
    J, status = hp.jacobian_si(PEN, X)
    assert np.all(status == 0)
    for k, h in enumerate((1e-5, 1e-5, 1e-5, 1e-8, 1e-8)):
        d = np.zeros(5)
        d[k] = h
        fd = (hp.ik(PEN, X + d)[0] - hp.ik(PEN, X - d)[0]) / (2 * h)
        if k < 3:
            ref = J[:, :, k] / 1e3  # rad/m -> rad/mm
        elif k == 3:
            ref = J[:, :, 3] * np.cos(X[:, 4])[:, None]  # d/dyaw = cos(pitch) * w_yaw column
        else:
            ref = J[:, :, 4]
        np.testing.assert_allclose(fd, ref, rtol=1e-5, atol=1e-7)


def test_pen_ends_are_one_pen_length_apart_and_arms_see_them():
    X = np.array([[10.0, 200.0, 5.0, 0.4, -0.3]])
    u, ea, eb = hp.pen_directions(X[:, 3], X[:, 4])
    np.testing.assert_allclose(np.linalg.norm(u, axis=-1), 1.0)
    np.testing.assert_allclose(np.einsum("ni,ni->n", u, ea), 0.0, atol=1e-15)
    np.testing.assert_allclose(np.einsum("ni,ni->n", u, eb), 0.0, atol=1e-15)
    q, status = hp.ik(PEN, X)
    assert status[0] == 0
    # waist angle of arm A = azimuth of its pen end about x = -l4/2
    PA = X[0, :3] - 35.0 * u[0]
    assert q[0, 0] == pytest.approx(np.arctan2(PA[1], PA[0] + 35.0))


def test_table2_geometries_gii_rises_with_distance_like_table2():
    """Table 2's trend: the GII of its own optimal geometries rises with distance and flattens.
    Our absolute values differ (arm reading and moment scaling are ours); the trend must hold."""
    g = []
    for d_cm, (l1, l2, l3, l6, q1, _) in sorted(hp.TABLE2.items()):
        pen = hp.HapticPen(l1 * 10, l2 * 10, l3 * 10, l6 * 10, None, q1)
        g.append(
            hp.pen_gii(pen, (0.0, d_cm * 10.0, 0.0), (160.0, 100.0, 100.0), (5, 3, 3), 45.0, 3).gii
        )
    g = np.array(g)
    assert np.all(np.diff(g) > 0)
    paper = np.array([v[5] for _, v in sorted(hp.TABLE2.items())])
    assert np.all(np.diff(paper) > 0)
    # both flatten: the last step gains less than the first
    assert g[-1] - g[-2] < g[1] - g[0]
    assert paper[-1] - paper[-2] < paper[1] - paper[0]


def test_pen_problem_culling_equals_brute_and_direct_gii():
    _, params = candidate_grid(
        {
            "shoulder_base_mm": (24.0, 48.0, 2),
            "proximal_mm": (120.0, 180.0, 3),
            "distal_mm": (160.0, 240.0, 3),
            "waist_torque_ratio": (1.0, 2.0, 3),
        },
        {"pen_mm": 70.0},
    )
    X = hp.workspace_grid((0.0, 200.0, 0.0), (160.0, 100.0, 100.0), (3, 2, 2), 45.0, 2)
    pr = PenProblem(params, X, (3, 2, 2, 2, 2))
    rb, rc = brute_force(pr), culling(pr)
    assert (rc.best_index, rc.gii) == (rb.best_index, rb.gii)
    b = pr.candidate(rb.best_index)
    pen = hp.HapticPen(
        b["shoulder_base_mm"],
        b["proximal_mm"],
        b["distal_mm"],
        b["pen_mm"],
        None,
        b["waist_torque_ratio"],
    )
    direct = hp.pen_gii(pen, (0.0, 200.0, 0.0), (160.0, 100.0, 100.0), (3, 2, 2), 45.0, 2).gii
    assert rb.gii == pytest.approx(direct, rel=1e-12)


def test_pen_study_quick_rises_with_distance():
    out = pen_study.run(None, quick=True)
    assert out["gii_increases_with_distance"]
    assert [r["distance_mm"] for r in out["rows"]] == [150.0, 200.0, 250.0, 300.0, 350.0, 400.0]
    for r in out["rows"]:
        assert r["brute_force_evaluations"] >= 10 * r["jacobian_evaluations"]


def test_on_waist_axis_and_bad_inputs():
    # pen end on arm A's waist axis: (x, y) = (-l4/2, 0)
    X = np.array([[0.0, 0.0, 0.0, 0.0, 0.0]])
    _, status = hp.ik(PEN, X)
    assert status[0] == hp.STATUS_ON_WAIST_AXIS
    J, st_ = hp.jacobian_si(PEN, X)
    assert st_[0] == hp.STATUS_ON_WAIST_AXIS and np.all(J[0, :3] == 0)
    with pytest.raises(DesignError, match="pen_mm"):
        hp.HapticPen(24.0, 145.0, 200.0, 0.0)
    with pytest.raises(DesignError, match="workspace"):
        hp.workspace_grid((0.0, 200.0, 0.0), (160.0, 100.0, 100.0), (1, 3, 3), 45.0, 3)
    with pytest.raises(DesignError, match="X"):
        hp.jacobian_si(PEN, np.zeros((1, 3)))


def test_table2_moment_arm_reading():
    """One moment-to-force ratio near 86-88 mm reproduces Table 2's 20-40 cm GII within 7 %;
    the 15 cm row stays about 1.7-1.8x above the paper at that ratio, and no ratio that
    matches the 15 cm row keeps the 40 cm row within 7 % (a single scaling cannot fit all)."""
    from cad.isotropy.pen_study import fit_moment_arm, table2_gii

    fit = fit_moment_arm()
    assert 80.0 < fit["moment_arm_mm"] < 95.0
    assert fit["max_rel_error_fitted_rows"] < 0.07
    assert 1.6 < fit["ratio_ours_to_paper"][15] < 1.9
    paper = np.array([v[5] for _, v in sorted(hp.TABLE2.items())])
    g = table2_gii(160.0)  # about where the 15 cm row matches
    assert abs(g[0] / paper[0] - 1) < 0.1 and g[-1] / paper[-1] < 0.8
