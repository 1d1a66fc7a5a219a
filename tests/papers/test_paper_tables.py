"""Reproduction of the Hoeken paper's Fig. 2 / Tables I and II at the paper's own dimensions.

Each Table cell is compared with the paper **at its printed rounding** (Table I: <tau> to
1 mN.m, Delta tau/<tau> to 3 decimals; Table II: (Delta y)max to 0.1 mm, slope to 3 decimals,
linearity to 0.1 %). Cells that do not reproduce are strict expected failures whose reason
names the explanation (docs/papers.md "Reproducing the Hoeken paper"); our own values are pinned
separately as regression values.
"""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from cad.kinematics.families import FAMILIES, PAPER_TABLES, family_linkage, paper_stroke_mm
from cad.kinematics.fourbar import jacobian_mm_per_rad, solve
from cad.kinematics.metrics import compute_metrics, path_frame


def metrics(name, **kw):
    fb, lo, hi = family_linkage(name)
    return compute_metrics(fb, lo, hi, force_N=5.0, **kw)


#: Decimals the paper prints for each Table cell (Tables I and II).
PRINTED_DECIMALS = {"torque_mean_mNm": 0, "torque_variation": 3, "dy_max_mm": 1, "slope_max": 3,
                    "linearity": 3}

_SLOPE_END = ("the max |dy/dx| of this family sits at an END of the crank range, where the "
              "tangent slope changes fast; the paper's (Delta y/Delta x)max reads lower, as a "
              "discrete ratio between crank samples does (test_paper_slope_is_a_discrete_ratio)")
_CHORD = ("Table I's <tau> = F x chord / Delta phi1 exactly (test_mean_torque_is_force_times_"
          "chord_over_crank_span); the paper's value implies a chord of {c} mm where Fig. 2's "
          "printed dimensions give {o} mm: the table was not computed from the printed dimensions")
_CHEB = ("Chebyshev's Fig. 2 dimensions give a 38.5 mm stroke, not the table's 50 mm "
         "(its <tau> implies 39.3 mm): the row was computed for other dimensions")
_LIN = "Table II's defining figure for linearity is lost; 'linearity_velocity_mean' is the closest reading"
_XFAIL = {
    ("hoeken", "torque_mean_mNm"): _CHORD.format(c=48.1, o=48.9),
    ("roberts", "torque_mean_mNm"): _CHORD.format(c=52.7, o=50.7),
    ("chebyshev", "torque_mean_mNm"): _CHORD.format(c=39.3, o=38.5),
    ("roberts", "torque_variation"): "unexplained: Roberts' torque rises steeply at the range end "
                                     "(297 -> 531 mN.m); no +-2 deg range change gives 0.271",
    ("chebyshev", "torque_variation"): _CHEB,
    ("roberts", "slope_max"): _SLOPE_END,
    ("chebyshev", "slope_max"): _SLOPE_END + "; " + _CHEB,
    ("chebyshev-v", "slope_max"): _SLOPE_END,
    ("chebyshev-v", "dy_max_mm"): "unexplained: 2.495 mm prints as 2.5, the paper 2.4 (4 % lower)",
    **{(f, "linearity"): _LIN for f in FAMILIES},
}


def _ours(m, key):
    return m.linearity_velocity_mean if key == "linearity" else getattr(m, key)


def _cells():
    for f in FAMILIES:
        for key in PRINTED_DECIMALS:
            reason = _XFAIL.get((f, key))
            marks = [pytest.mark.xfail(strict=True, reason=reason)] if reason else []
            yield pytest.param(f, key, marks=marks, id=f"{f}-{key}")


@pytest.mark.parametrize("family, key", list(_cells()))
def test_table_cell_at_printed_rounding(family, key):
    """Tables I and II, every numeric cell: ours rounded as the paper prints equals the paper."""
    d = PRINTED_DECIMALS[key]
    assert round(_ours(metrics(family), key), d) == pytest.approx(PAPER_TABLES[family][key], abs=1e-9)


#: Regression pin (our own run), not the paper: the values the table in docs/papers.md quotes.
OURS = {
    "hoeken": (48.874, 0.21203, 0.013737, 166.682, 0.012255),
    "roberts": (50.709, 0.28143, 0.067446, 382.305, 0.38876),
    "chebyshev": (38.506, 0.10939, 0.019313, 408.575, 0.22795),
    "chebyshev-v": (52.758, 2.49458, 0.18237, 116.262, 0.014694),
}


@pytest.mark.parametrize("family", list(FAMILIES))
def test_regression_pin_our_own_run(family):
    """Regression pin (our own run), not the paper: stroke, dy, slope, <tau>, Delta tau/<tau>."""
    m = metrics(family)
    got = (m.stroke_mm, m.dy_max_mm, m.slope_max, m.torque_mean_mNm, m.torque_variation)
    assert got == pytest.approx(OURS[family], rel=1e-4)


@pytest.mark.parametrize("family", list(FAMILIES))
def test_mean_torque_is_force_times_chord_over_crank_span(family):
    """Closed form: <tau> = mean over phi1 of F dx/dphi1 = F * stroke / (phi1_max - phi1_min)."""
    fb, lo, hi = family_linkage(family)
    m = metrics(family)
    assert m.torque_mean_mNm == pytest.approx(5.0 * m.stroke_mm / (hi - lo), rel=1e-4)


def test_paper_mean_torque_implies_the_quoted_chords():
    """The chords the xfail reasons and docs/papers.md quote: Table I <tau> x Delta phi1 / F."""
    chords = {f: PAPER_TABLES[f]["torque_mean_mNm"] * (FAMILIES[f].phi1_range_rad[1]
              - FAMILIES[f].phi1_range_rad[0]) / 5.0 for f in FAMILIES}
    assert {f: round(c, 1) for f, c in chords.items()} == {
        "hoeken": 48.1, "roberts": 52.7, "chebyshev": 39.3, "chebyshev-v": 52.6}
    assert {f: round(paper_stroke_mm(FAMILIES[f]), 1) for f in FAMILIES} == {
        "hoeken": 48.9, "roberts": 50.7, "chebyshev": 38.5, "chebyshev-v": 52.8}


def _secant_slope_max(family, samples):
    fb, lo, hi = family_linkage(family)
    xy = path_frame(fb, lo, hi).to_path(solve(fb, np.linspace(lo, hi, samples)).P_mm)
    d = np.diff(xy, axis=0)
    return float(np.abs(d[:, 1] / d[:, 0]).max())


def test_paper_slope_is_a_discrete_ratio():
    """Why three slope cells miss: the tangent max sits at an end of the range (Roberts at
    phi1_min, Chebyshev and Chebyshev-V at phi1_max; Hoeken's is inside), and the paper's
    (Delta y / Delta x)max read as a ratio between 16 equally spaced crank samples (the sample
    count that fits best: a reading, not the paper's stated method) lands within one printed
    unit (0.001) of Table II for Hoeken, Roberts and Chebyshev-V."""
    for f, at_end in (("hoeken", None), ("roberts", 0), ("chebyshev", -1), ("chebyshev-v", -1)):
        fb, lo, hi = family_linkage(f)
        phi = np.linspace(lo, hi, 2001)
        J = path_frame(fb, lo, hi).rotate(jacobian_mm_per_rad(fb, solve(fb, phi)))
        i = int(np.argmax(np.abs(J[:, 1] / J[:, 0])))
        assert (0 < i < 2000) if at_end is None else i == (at_end % 2001)
    for f in ("hoeken", "roberts", "chebyshev-v"):
        assert _secant_slope_max(f, 16) == pytest.approx(PAPER_TABLES[f]["slope_max"], abs=0.001)
    assert _secant_slope_max("chebyshev", 16) > PAPER_TABLES["chebyshev"]["slope_max"] + 0.002


def test_table1_torque_variation_ranking():
    """Table I: Hoeken and Chebyshev-V are far below Roberts and Chebyshev (the underlined pair)."""
    v = {f: metrics(f).torque_variation for f in FAMILIES}
    assert max(v["hoeken"], v["chebyshev-v"]) < min(v["roberts"], v["chebyshev"]) / 5


def test_hoeken_text_torque_band():
    """§II.C: torque variations below 2 mN.m for a mean of 164 mN.m (Hoeken, 5 N)."""
    m = metrics("hoeken")
    assert m.torque_variation * m.torque_mean_mNm < 2.5


def test_fig2_strokes_are_50mm_class():
    """Fig. 2: dimensions chosen for a ~50 mm range of motion (Chebyshev: see module doc)."""
    for f, lo_mm in (("hoeken", 48), ("roberts", 49), ("chebyshev-v", 50)):
        assert lo_mm < paper_stroke_mm(FAMILIES[f]) < 54
    assert paper_stroke_mm(FAMILIES["chebyshev"]) == pytest.approx(38.5, abs=0.1)


def test_hoeken_moves_along_minus_x0():
    """Eq (20): for the Hoeken mechanism the end effector translates along -x0."""
    from cad.kinematics.fourbar import solve

    fb, lo, hi = family_linkage("hoeken")
    P = solve(fb, np.array([lo, hi])).P_mm
    d = (P[1] - P[0]) / np.linalg.norm(P[1] - P[0])
    assert d[0] < -0.999


def test_exact_extremum_matches_dense_sampling():
    """The refined max |y| equals a brute 200k-sample maximum (and bounds it from above)."""
    coarse = metrics("hoeken", samples=51)
    dense = metrics("hoeken", samples=200001, refine=False)
    assert coarse.dy_max_mm == pytest.approx(dense.dy_max_mm, rel=1e-6)
    assert coarse.dy_max_mm >= dense.dy_max_mm - 1e-12


@given(st.sampled_from(list(FAMILIES)), st.floats(5.0, 500.0))
def test_dimensionless_metrics_invariant_to_scale(family, stroke):
    """Scaling every length: stroke and dy scale by k; slope, linearity, torque variation,
    transmission angle are unchanged; torque scales by k."""
    fb, lo, hi = family_linkage(family)
    k = stroke / paper_stroke_mm(FAMILIES[family])
    a = compute_metrics(fb, lo, hi, samples=301)
    b = compute_metrics(fb.scaled(k), lo, hi, samples=301)
    assert b.stroke_mm == pytest.approx(stroke, rel=1e-9)
    assert b.dy_max_mm == pytest.approx(k * a.dy_max_mm, rel=1e-6)
    assert b.torque_mean_mNm == pytest.approx(k * a.torque_mean_mNm, rel=1e-9)
    for f in ("slope_max", "linearity", "torque_variation", "min_transmission_angle_deg"):
        assert getattr(b, f) == pytest.approx(getattr(a, f), rel=1e-6, abs=1e-12)
    assert math.isclose(b.bbox_mm[0], k * a.bbox_mm[0], rel_tol=1e-9)
