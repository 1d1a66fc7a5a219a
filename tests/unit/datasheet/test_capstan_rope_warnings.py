"""A thin rope on the twin pantograph's four capstans (a tester's finding: one safety warning
line for four ropes, naming no motor): each joint whose rope misses its safety factor gets its
own warning line naming the joint and its motor, the rope's breaking load, the tight run's
tension and the factor, in the datasheet's warnings (what ``build`` and ``check`` print and
report.html lists in red) and in the datasheet table's figure.

Reference: the capstan equation by hand (dT = n tau_peak / r_d = tau_peak / r_c, the smallest
pretension that holds it T0 = (dT / 2)(e^(mu theta) + 1) / (e^(mu theta) - 1), mu = 0.12 steel
rope on steel, theta = 2 pi x 3 turns) and the rope catalog's breaking load; no CAD.
"""

from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
THIN = "steel-7x7-0.45"
LABELS = ("knob left proximal link", "knob right proximal link", "crank left proximal link",
          "crank right proximal link")


def _thin_twin():
    from cad.design import parse_design

    raw = tomllib.loads((ROOT / "designs" / "twin_pantograph_capstan.toml").read_text())
    raw = copy.deepcopy(raw)
    raw["transmission"]["cable"] = THIN
    return parse_design(raw, "thin.toml")


def test_each_thin_rope_has_its_own_warning_naming_joint_motor_tension_and_load():
    from cad.data.cables import CABLES
    from cad.data.catalog import get_motor
    from cad.datasheet import judge
    from cad.design import bounds
    from cad.families.pantograph.capstan import capstan_rows
    from cad.report.html import datasheet_html

    d = _thin_twin()
    rows, lim = capstan_rows(d, None)
    warnings = judge(rows, lim)
    dc_mm = d.transmissions[0].capstan_diameter_mm
    dT = get_motor(d.parts.motor).torque_peak_mNm * 1e-3 / (dc_mm / 2e3)
    e = math.exp(0.12 * 2 * math.pi * 3.0)
    T0 = dT / 2 * (e + 1) / (e - 1)
    mbl = CABLES[THIN].min_breaking_load_N
    sf = mbl / (T0 + dT / 2)
    assert sf < 5.0  # the thin rope misses the rope sellers' 5:1
    safety = [w for w in warnings if w.startswith("rope safety factor")]
    assert len(safety) == 4 == len(set(safety))
    for i, (lab, w) in enumerate(zip(LABELS, safety, strict=True)):
        assert w.startswith(f"rope safety factor at the {lab} (peak force) = {sf:.4g}, limit >= 5 ")
        assert f"the {lab}'s (motor {i + 1}) rope ({THIN}): breaking load {mbl:.4g} N (unverified)" in w
        assert f"over the tight run's tension {T0 + dT / 2:.4g} N" in w
    # the table's figure names the joint too
    figs = {r["key"]: r["figure"] for r in rows}
    assert [figs[f"cable_safety_factor_{i}"] for i in range(1, 5)] == [
        f"rope safety factor at the {lab} (peak force)" for lab in LABELS]
    # the CLI's warnings (deduplicated by text) keep all four; report.html lists all four in red
    with bounds.muted() as said:
        for w in safety:
            bounds.warn(f"datasheet: {w}")
    assert said == [f"datasheet: {w}" for w in safety]
    page = datasheet_html({"datasheet": {"rows": rows, "warnings": warnings}})
    assert sum(f"rope safety factor at the {lab} (peak force)" in page for lab in LABELS) == 4
    assert page.count("<li class='bad'>warning: rope safety factor") == 4
