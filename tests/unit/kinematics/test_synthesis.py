"""Link-length synthesis: the optimum satisfies its constraints and beats the paper's start."""

import math

import numpy as np
import pytest

from cad.errors import DesignError
from cad.kinematics.families import family_linkage
from cad.kinematics.metrics import compute_metrics
from cad.kinematics.synthesis import synthesize


def test_max_stroke_over_crank_range_hoeken():
    """Longest Hoeken segment with dy_max <= 0.2 mm over every crank window (the global
    branch and bound): longer than the paper's 84 deg choice, with a proven bound, and no
    window of an independent brute force over every window is longer."""
    fb, lo, hi = family_linkage("hoeken")
    r = synthesize(fb, lo, hi, "max-stroke", free="range", dy_tol_mm=0.2, samples=121, restarts=1)
    assert r.feasible
    m = compute_metrics(fb, r.phi1_min_rad, r.phi1_max_rad, samples=4001)
    assert m.dy_max_mm <= 0.2 * 1.002 and m.min_transmission_angle_deg >= 30.0
    assert m.stroke_mm > r.start_metrics.stroke_mm
    # the proof: no window is longer than the bound, which sits within 0.05 mm of the answer
    assert m.stroke_mm <= r.upper_bound_mm <= m.stroke_mm + 0.05
    # docs/synthesis.md: 110.2 mm, 76.7 - 283.3 deg, 47.6 deg (regression pin, our run)
    assert (round(m.stroke_mm, 1), round(math.degrees(r.phi1_min_rad), 1),
            round(math.degrees(r.phi1_max_rad), 1)) == (110.2, 76.7, 283.3)
    assert round(m.min_transmission_angle_deg, 1) == 47.6
    # independent of the answer: every window of a 0.5 deg grid over the whole turn
    b_stroke, b_lo, b_hi = _brute_max_stroke(fb, 0.2, 30.0)
    assert m.stroke_mm >= b_stroke - 0.5  # the grid's resolution: ~2 x 30 mm/rad x 0.25 deg
    ref = compute_metrics(fb, b_lo, b_hi, samples=4001)
    if ref.dy_max_mm <= 0.2:  # the grid's best window, truly feasible, is under the bound
        assert ref.stroke_mm <= r.upper_bound_mm


def _brute_max_stroke(fb, dy_tol_mm, mu_min_deg, step_deg=0.5):
    """(stroke, lo, hi) of the longest chord over every crank window of a ``step_deg`` grid
    (a full turn of starts, every length up to a turn) whose deviation from the chord at the
    grid's angles stays <= ``dy_tol_mm`` and whose transmission angle stays >= mu_min_deg."""
    from cad.kinematics.fourbar import solve, transmission_angle_rad

    phi = np.radians(np.arange(0.0, 360.0, step_deg))
    pose = solve(fb, phi)
    P, mu = pose.P_mm, np.degrees(transmission_angle_rad(pose))
    n = phi.size
    P2, mu2 = np.concatenate([P, P]), np.concatenate([mu, mu])
    best = (0.0, 0.0, 0.0)
    for i in range(n):
        c = P2[i:i + n] - P2[i]
        L = np.maximum(np.linalg.norm(c, axis=1), 1e-12)
        u = c / L[:, None]
        y = np.abs(u[:, 0, None] * c[None, :, 1] - u[:, 1, None] * c[None, :, 0])
        dy = np.where(np.arange(n)[None, :] <= np.arange(n)[:, None], y, 0.0).max(axis=1)
        ok = (dy <= dy_tol_mm) & (np.minimum.accumulate(mu2[i:i + n]) >= mu_min_deg)
        if ok.any():
            j = int(np.flatnonzero(ok)[np.argmax(L[ok])])
            if L[j] > best[0]:
                best = (float(L[j]), float(phi[i]), float(phi[i] + np.radians(step_deg) * j))
    return best


def test_min_torque_variation_improves_and_keeps_constraints():
    fb, lo, hi = family_linkage("hoeken")
    r = synthesize(fb, lo, hi, "min-torque-variation", free="all", stroke_mm=50.0, samples=121, restarts=0)
    assert r.feasible
    assert r.metrics.stroke_mm == pytest.approx(50.0, rel=1e-9)
    assert r.metrics.torque_variation < r.start_metrics.torque_variation
    s0 = r.start_metrics
    assert r.metrics.dy_max_mm / r.metrics.stroke_mm <= s0.dy_max_mm / s0.stroke_mm * 1.01
    assert r.phi1_max_rad - r.phi1_min_rad >= (hi - lo) * 0.999
    assert r.metrics.min_transmission_angle_deg >= 30.0
    # regression pin (our own run) at this cheap setting; docs/synthesis.md's 0.0020 is the default
    # setting's, pinned in test_min_torque_variation_readme_value (slow)
    assert r.metrics.torque_variation == pytest.approx(0.0021008, rel=1e-3)


@pytest.mark.slow
def test_min_torque_variation_readme_value():
    """docs/synthesis.md (``synth --objective min-torque-variation --free all``,
    default samples/restarts, ~25 s): torque variation 0.0020, dy 0.094 mm, stroke 50.0 mm
    (regression pin, our own run)."""
    fb, lo, hi = family_linkage("hoeken")
    r = synthesize(fb, lo, hi, "min-torque-variation", free="all", stroke_mm=50.0)
    m = compute_metrics(r.linkage, r.phi1_min_rad, r.phi1_max_rad, samples=4001)
    assert (round(m.torque_variation, 4), round(m.dy_max_mm, 3), round(m.stroke_mm, 1)) == (0.0020, 0.094, 50.0)


def test_bad_objective_names_the_flag():
    fb, lo, hi = family_linkage("hoeken")
    with pytest.raises(DesignError, match="--objective"):
        synthesize(fb, lo, hi, "fastest")
    with pytest.raises(DesignError, match="--dy-tol-mm"):
        synthesize(fb, lo, hi, dy_tol_mm=-1.0)
    assert np.isfinite(lo)


def _chord_and_dy_mm(fb, lo, hi, n=20001):
    """Stroke and max |y| of the output range from a dense pose grid: the chord of the end
    points and the largest distance of P from it (independent of the metrics' root refinement)."""
    from cad.kinematics.fourbar import solve

    P = solve(fb, np.linspace(lo, hi, n)).P_mm
    chord = P[-1] - P[0]
    stroke = float(np.linalg.norm(chord))
    normal = np.array([-chord[1], chord[0]]) / stroke
    return stroke, float(np.max(np.abs((P - P[0]) @ normal)))


def test_max_stroke_holds_a_given_stroke_with_the_straightest_segment():
    """Issue 21 §3: --stroke-mm under the default objective is a constraint, not ignored.
    The stroke is the asked one; the segment is the straightest of that length (moving
    phi1_min by 1 deg either way, with phi1_max re-found by bisection for 60 mm, is not straighter)."""
    from scipy.optimize import brentq

    from cad import tolerances as tol

    fb, lo, hi = family_linkage("hoeken")
    r = synthesize(fb, lo, hi, "max-stroke", free="range", stroke_mm=60.0, samples=121, restarts=0)
    assert r.feasible and r.linkage == fb  # l2 and every length kept under free=range
    stroke, dy = _chord_and_dy_mm(fb, r.phi1_min_rad, r.phi1_max_rad)
    assert stroke == pytest.approx(60.0, rel=tol.SYNTH_STROKE_REL)
    assert dy <= 0.2
    for dlo in (-1.0, 1.0):
        a = r.phi1_min_rad + math.radians(dlo)
        b = brentq(lambda b, a=a: _chord_and_dy_mm(fb, a, b, 3)[0] - 60.0, a + 1.0, r.phi1_max_rad + 0.2)
        assert _chord_and_dy_mm(fb, a, b)[1] >= dy * (1 - 1e-3)


def test_synth_cli_stroke_under_default_objective(tmp_path):
    """README first session: `synth hoeken.toml --stroke-mm 60` writes a 60 mm design,
    re-evaluated from the written file's own lengths and range."""
    from cad import tolerances as tol
    from cad.design import load_design
    from tests.cli_helpers import assert_one_line_error, hapticad

    out = tmp_path / "hoeken_60.toml"
    code, _, err = hapticad("synth", "designs/hoeken.toml", "--stroke-mm", "60", "--out", out)
    assert code == 0, err
    d = load_design(out)
    stroke, dy = _chord_and_dy_mm(d.linkage, d.phi1_min_rad, d.phi1_max_rad)
    assert stroke == pytest.approx(60.0, rel=tol.SYNTH_STROKE_REL)
    assert dy <= 0.2
    code, _, err = hapticad("synth", "designs/hoeken.toml", "--stroke-mm", "900", "--out", tmp_path / "x.toml")
    assert_one_line_error(code, err, "--stroke-mm", "900", "--objective")
    assert not (tmp_path / "x.toml").exists()


def test_synth_cli_mu_min_deg_binds(tmp_path):
    """``synth --mu-min-deg 50``: the Hoeken max-stroke optimum at the default 30 deg has a
    47.6 deg transmission angle (docs/synthesis.md), so a 50 deg floor must bind: the result keeps
    mu >= 50 deg (recomputed here on its own linkage) and is shorter than 110.2 mm, and its
    proven bound is below the 30 deg optimum."""
    import json
    from pathlib import Path

    from cad.design import load_design
    from tests.cli_helpers import hapticad

    out = tmp_path / "mu50.toml"
    code, o, err = hapticad("synth", Path(__file__).resolve().parents[3] / "designs" / "hoeken.toml",
                            "--objective", "max-stroke", "--mu-min-deg", "50", "--out", out, "--json")
    assert code == 0, err
    res = json.loads(o)["result"]
    d = load_design(out)
    m = compute_metrics(d.linkage, d.phi1_min_rad, d.phi1_max_rad, samples=4001)
    assert m.min_transmission_angle_deg >= 50.0 - 1e-6
    assert res["min_transmission_angle_deg"] == pytest.approx(m.min_transmission_angle_deg, abs=1e-3)
    assert m.dy_max_mm <= 0.2 * 1.002
    assert 48.9 < m.stroke_mm < 110.19  # longer than the paper's range, shorter than at 30 deg
    assert m.stroke_mm <= json.loads(o)["stroke_upper_bound_mm"] < 110.19
