"""Faults an independent trial of issue 32 found (tester41): ``parts.process = "printed"`` with
metal parts said nothing, the pantographs' eq (25) row printed its two sides as a range over
the workspace (inverted when the encoder is coarse), and a pantograph's ``[motor]`` table was
named by the catalog key it replaces in the datasheet and in report.json."""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path

from tests.cli_helpers import hapticad

ROOT = Path(__file__).resolve().parents[2]


def _printed_warning(err: str) -> str:
    lines = [ln for ln in err.splitlines() if "are not in a printing filament" in ln]
    assert len(lines) == 1, err
    return lines[0]


def test_printed_process_names_the_metal_parts_the_bom_machines(tmp_path):
    """The reference is the written BOM: every part group the warning names is made and not
    FDM printed there, and every FDM-printed line is of a filament."""
    text = (ROOT / "designs" / "hoeken_printed.toml").read_text()
    d = tmp_path / "d.toml"
    d.write_text(text.replace('bar_material = "pla"', 'bar_material = "aluminium-6061"', 1)
                 .replace('hub_material = "pla"', 'hub_material = "aluminium-6061"', 1))
    code, _, err = hapticad("build", str(d), "--fidelity", "preview", "--formats", "step",
                            "--out", str(tmp_path / "o"))
    assert code == 0, err
    line = _printed_warning(err)
    named = dict(re.findall(r"([a-z ,]+?) \(([a-z0-9-]+)\)", line.split(": ", 2)[2].split(" are not")[0]))
    assert {k.strip(", ") for k in named} == {"crank, coupler, rocker", "hub"}
    assert set(named.values()) == {"aluminium-6061"}
    with open(tmp_path / "o" / "bom.csv", encoding="utf-8") as fh:
        rows = {r["part"]: r for r in csv.DictReader(fh)}
    for part in ("crank", "coupler", "rocker", "crank_hub"):
        assert rows[part]["material"] == "aluminium-6061"
        assert not rows[part]["process"].startswith("FDM"), rows[part]
    printed = [r for r in rows.values() if r["process"].startswith("FDM")]
    assert printed and all(r["material"] == "pla" for r in printed)


def test_printed_process_all_filament_adds_no_such_warning():
    code, _, err = hapticad("check", str(ROOT / "designs" / "hoeken_printed.toml"))
    assert code in (0, 1), err
    assert "are not in a printing filament" not in err


def test_machined_process_with_metal_parts_adds_no_such_warning():
    code, _, err = hapticad("check", str(ROOT / "designs" / "hoeken.toml"))
    assert code in (0, 1), err
    assert "are not in a printing filament" not in err
