"""The PowerMouse's test-rig BOM is computed once per build (issue 32 §6: one writer, one
value), in the build's process before the export child forks: rig/bom.csv and report.json's
``rig_bom`` are those rows (read back from both files and compared)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

from cad.design import load_design
from cad.families.powermouse import build as pm_build
from cad.pipeline import build_design

DESIGN = Path(__file__).resolve().parents[3] / "designs" / "powermouse.toml"


def test_the_rig_bom_is_computed_once_and_both_files_hold_it(tmp_path, monkeypatch):
    monkeypatch.setenv("HAPTICAD_FORK", "0")  # the children run in this process: every call counted
    calls = []
    real = pm_build.rig_bom
    monkeypatch.setattr(pm_build, "rig_bom", lambda rig: calls.append(1) or real(rig))
    out = tmp_path / "out"
    build_design(load_design(DESIGN), out, {"step"}, fidelity="preview", use_cache=False)
    assert len(calls) == 1
    rep = json.loads((out / "report.json").read_text())["rig_bom"]
    with (out / "rig" / "bom.csv").open(newline="") as f:
        rows = list(csv.DictReader(f))
    assert [r["part"] for r in rows] == [r["part"] for r in rep] and len(rows) >= 3
    assert [int(r["quantity"]) for r in rows] == [r["quantity"] for r in rep]
