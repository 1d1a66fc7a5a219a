"""The terminal table of `hapticad identify` (a tester found per-motor keys cut at an 80-column
terminal): every figure's key is printed whole at 80 columns."""

from __future__ import annotations

from rich.console import Console

from cad.cli.cmd_identify import figures_table

#: keys as the n-motor identification writes them (cad/sim/identify_joints.py), with the
#: longest units and descriptions of its rows
FIGURES = [
    {"key": "current_gain_sign_5", "value": "+", "verdict": "ok"},
    {"key": "encoder_direction_5", "value": "as configured", "verdict": "ok"},
    {"key": "gravity_load5_mNm", "value": 12.3456, "sigma": 0.0123, "unit": "mN m",
     "predicted": 11.9876, "verdict": "ok"},
    {"key": "b5_mNm_s_per_rad", "value": 0.0123456, "sigma": 0.000123, "unit": "mN m s/rad",
     "predicted": None, "verdict": "n/a"},
    {"key": "apparent_mass_Mzz_g", "value": 110.37, "sigma": 0.52, "unit": "g",
     "predicted": 96.4, "verdict": "MISS"},
]


def test_every_key_whole_at_80_columns():
    c = Console(width=80, record=True, color_system=None)
    c.print(figures_table({"design": "delta", "figures": FIGURES}))
    text = c.export_text()
    for r in FIGURES:
        assert r["key"] in text, r["key"]
    assert max(len(line) for line in text.splitlines()) <= 80
