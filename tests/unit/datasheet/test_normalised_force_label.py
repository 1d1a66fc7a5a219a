"""The pantographs' force rows at the GII's normalisation ``[actuators] torque_max_Nm`` (1 N m
per joint: not a force the device delivers) say so in their label (a tester's finding: "force
available in every direction" beside the real continuous force was misread); the JSON keys stay
(``force_any_dir_N``, ``force_best_dir_N``: [targets] keys); the verdict is the continuous
force's.

Reference: sigma(J^T S_J) is linear in S_J = tau I (two motors alike, direct drive), so the
continuous force is the normalised one times tau_cont / torque_max_Nm (the RE 35's data-sheet
continuous torque from the motor catalog), and halving torque_max_Nm halves the normalised rows.
"""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]


def _rows(raw):
    from cad.datasheet import datasheet
    from cad.design import parse_design

    d = parse_design(copy.deepcopy(raw), "p.toml")
    ds = datasheet(d, {})
    return {r["key"]: r for r in ds["rows"]}, d


def test_normalised_force_rows_say_so_and_the_verdict_is_the_continuous_force():
    from cad.data.catalog import get_motor

    raw = tomllib.loads((ROOT / "designs" / "pantograph.toml").read_text())
    rows, d = _rows(raw)
    tau = raw["actuators"]["torque_max_Nm"]
    assert tau == 1.0
    a, b, c = rows["force_any_dir_N"], rows["force_best_dir_N"], rows["continuous_force_N"]
    norm = "normalised to 1 N m per joint (GII scale, not the motors' force)"
    assert a["figure"] == f"force in every direction {norm}"
    assert b["figure"] == f"largest force (best direction) {norm}"
    assert c["figure"] == "continuous force in every direction" and "normalised" not in c["figure"]
    # the verdict: a limit on the continuous force only
    assert c["limit"] is not None and c["verdict"] in ("ok", "miss")
    assert a["limit"] is None and b["limit"] is None and a["verdict"] == b["verdict"] == "info"
    # linear in the torque: continuous = normalised x tau_cont / torque_max_Nm
    tc = get_motor(d.parts.motor).torque_continuous_mNm * 1e-3  # the bundled 5-bar: the RE 35
    assert c["value"] == pytest.approx(a["value"] * tc / tau, rel=1e-9)
    half = copy.deepcopy(raw)
    half["actuators"]["torque_max_Nm"] = 0.5
    h, _ = _rows(half)
    assert h["force_any_dir_N"]["value"] == pytest.approx(0.5 * a["value"], rel=1e-12)
    assert h["force_any_dir_N"]["figure"] == "force in every direction normalised to 0.5 N m per joint " \
                                             "(GII scale, not the motors' force)"
    assert h["continuous_force_N"]["value"] == pytest.approx(c["value"], rel=1e-12)
