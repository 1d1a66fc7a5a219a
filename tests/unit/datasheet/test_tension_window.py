"""The winding step's tension window (a tester's finding: assembly.md gave a minimum pretension
only, and a rope tensioned to twice it missed its safety factor): at least the pretension the
capstan equation asks, at most MBL / 5 - dT/2, checked by hand from the catalogs (the motor's
peak torque over the capstan's pitch radius, the rope's breaking load)."""

from __future__ import annotations

import re
from pathlib import Path

from cad.data.cables import get_cable
from cad.data.catalog import get_motor
from cad.datasheet import capstan_rows as cr
from cad.design import load_design
from cad.families.pen import capstan as pen_capstan

ROOT = Path(__file__).resolve().parents[3]


def _window(text: str) -> tuple[float, float]:
    m = re.search(r"holds at least ([\d.]+) N \(datasheet [^)]*\) and at most ([\d.]+) N", text)
    assert m, text
    return float(m.group(1)), float(m.group(2))


def test_the_pen_waists_tension_window_by_hand():
    """designs/haptic_pen_capstan.toml's waists: RE 40 peak torque over the 40 mm capstan's
    20 mm radius, dT = 2.56 / 0.020 = 128 N; 1 mm 7x7 rope; at most MBL / 5 - 64 N."""
    design = load_design(ROOT / "designs" / "haptic_pen_capstan.toml")
    j = pen_capstan.capstan_joints(design)[0]
    t = j.transmission
    dT = get_motor(design.parts.waist_motor).torque_peak_mNm * 1e-3 / (t.capstan_diameter_mm / 2 * 1e-3)
    hi = get_cable(t.cable.key).min_breaking_load_N / 5.0 - dT / 2
    lo_text, hi_text = _window(cr.winding_steps(j)[1])
    assert hi_text == round(hi, 1)
    assert lo_text == round(cr.figures(j).pretension_N, 1) < hi_text
    assert f"{get_cable(t.cable.key).min_breaking_load_N:.0f} N breaking load" in cr.winding_steps(j)[1]


def test_a_window_that_closes_is_said(tmp_path):
    """A rope so thin that its minimum pretension already misses the safety factor: no 'at most',
    the step says it misses (the shoulders' 0.8 mm rope swapped for a 0.45 mm one)."""
    text = (ROOT / "designs" / "haptic_pen_capstan.toml").read_text(encoding="utf-8")
    thin = text.replace('cable = "steel-7x7-0.8"', 'cable = "steel-7x7-0.45"')
    assert thin != text
    (tmp_path / "thin.toml").write_text(thin, encoding="utf-8")
    design = load_design(tmp_path / "thin.toml")
    j = pen_capstan.capstan_joints(design)[1]
    step = cr.winding_steps(j)[1]
    assert "at most" not in step and "already misses the safety factor 5" in step, step
