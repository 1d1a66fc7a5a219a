"""Link-length synthesis: the optimum satisfies its constraints and beats the paper's start."""

import math

import numpy as np
import pytest

from cad.errors import DesignError
from cad.kinematics.families import family_linkage
from cad.kinematics.metrics import compute_metrics
from cad.kinematics.synthesis import synthesize


def test_max_stroke_over_crank_range_hoeken():
    """Longest Hoeken segment with dy_max <= 0.2 mm: longer than the paper's 84 deg choice
    (whose dy_max is 0.21 mm), and no feasible neighbour range is longer."""
    fb, lo, hi = family_linkage("hoeken")
    r = synthesize(fb, lo, hi, "max-stroke", free="range", dy_tol_mm=0.2, samples=121, restarts=1)
    assert r.feasible
    m = compute_metrics(fb, r.phi1_min_rad, r.phi1_max_rad, samples=4001)
    assert m.dy_max_mm <= 0.2 * 1.002
    assert m.stroke_mm > r.start_metrics.stroke_mm
    # local optimality: widening the range by 1 deg on either side violates the tolerance
    for dlo, dhi in ((-1, 0), (0, 1)):
        m2 = compute_metrics(fb, r.phi1_min_rad + math.radians(dlo), r.phi1_max_rad + math.radians(dhi),
                             samples=4001)
        assert m2.dy_max_mm > 0.2 or m2.stroke_mm <= m.stroke_mm


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


def test_bad_objective_names_the_flag():
    fb, lo, hi = family_linkage("hoeken")
    with pytest.raises(DesignError, match="--objective"):
        synthesize(fb, lo, hi, "fastest")
    with pytest.raises(DesignError, match="--dy-tol-mm"):
        synthesize(fb, lo, hi, dy_tol_mm=-1.0)
    assert np.isfinite(lo)
