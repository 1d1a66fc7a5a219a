"""``fit`` holds every haptic-pen candidate to the pen's default datasheet limits (issue 32 §3):
the first mode (:data:`cad.datasheet.limits.FIRST_MODE_MIN_HZ`, Hoeken paper §III.B.1), the
stress of its link tubes' material (catalog strength / the safety factor) and the continuous
force of ``[actuators] force_max_N`` -- the limits its datasheet states (read from a datasheet
call on the bundled pen's build report would need a build; the references here are the
constants and the catalog values themselves)."""

from __future__ import annotations

from pathlib import Path

import pytest

import cad
from cad.datasheet.limits import FIRST_MODE_MIN_HZ, STRESS_SAFETY_FACTOR
from cad.families.pen import FAMILY
from cad.structure.elastic import get_elastic

ROOT = Path(__file__).resolve().parents[3]


def test_pen_fit_limits_are_its_default_limits(tmp_path):
    d = cad.load_design(ROOT / "designs" / "haptic_pen.toml")
    got = {t.key: (t.min, t.max) for t in FAMILY.targets.fit_limits(d)}
    strength = get_elastic(d.parts.tube_material).strength_MPa
    assert got == {"first_mode_Hz": (FIRST_MODE_MIN_HZ, None),
                   "max_stress_MPa": (None, pytest.approx(strength / STRESS_SAFETY_FACTOR)),
                   "continuous_force_N": (d.actuators["force_max_N"], None)}
    # a key the design's [targets] sets is its own, not a default limit
    p = tmp_path / "pen.toml"
    p.write_text((ROOT / "designs" / "haptic_pen.toml").read_text()
                 + "\n[targets]\nfirst_mode_Hz = {min = 40.0}\n")
    assert "first_mode_Hz" not in {t.key for t in FAMILY.targets.fit_limits(cad.load_design(p))}
