"""Numbers typed in README.md that come from a run, recomputed from the code's current output
at the printed rounding (issue 34 §4: a typed run number is generated or checked, never left to
drift). Pure kinematics only: no CAD build, well under a second."""

from __future__ import annotations

from pathlib import Path

import pytest

from cad.design import load_design
from cad.kinematics.metrics import compute_metrics

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text()


@pytest.fixture(scope="module")
def hoeken_metrics():
    """``hapticad analyze designs/hoeken.toml``'s kinematic metrics (cad.analysis.analyze calls
    the same compute_metrics with the design's range, force and samples)."""
    d = load_design(ROOT / "designs/hoeken.toml")
    return compute_metrics(d.linkage, d.phi1_min_rad, d.phi1_max_rad, force_N=d.force_N, samples=d.samples)


def test_analyze_sentence_matches_the_hoeken_design(hoeken_metrics):
    """README's analyze sentence: stroke, dy_max and torque variation at their printed rounding
    (the paper's 0.2 mm and 0.012 beside them are Table I values, ledger `paper:`)."""
    m = hoeken_metrics
    assert f"stroke {m.stroke_mm:.2f} mm" in README
    assert f"dy_max {m.dy_max_mm:.3f} mm against the paper's 0.2" in " ".join(README.split())
    assert f"torque variation {m.as_dict()['torque_variation']:.5f} against 0.012" in " ".join(README.split())


def test_swap_keeps_the_hoeken_stroke(hoeken_metrics):
    """`swap` keeps the source design's stroke: the README's kept stroke is hoeken's, to 3 decimals."""
    assert f"`swap` keeps the stroke ({hoeken_metrics.stroke_mm:.3f} mm)" in README
