"""Both optimisers honour ``parts.process`` (issue 32 item 4): under ``"laser"`` they propose
only sheets the laser process cuts (and holds a thread in) at their stock thicknesses, under
``"printed"`` only printing filaments; the written design builds with its process.

References: the laser process's own acceptance (:func:`cad.design.laser.check_laser` at
design load, and a build of the optimiser's written design), the sheet table
(:data:`cad.data.materials.SHEETS`) and the filament table (:data:`cad.printing.FILAMENTS`)
read directly.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
from cli_helpers import hapticad

from cad.data.materials import SHEETS
from cad.design import load_design
from cad.printing import FILAMENTS

DESIGNS = Path(__file__).resolve().parents[3] / "designs"


def test_bar_stock_per_process():
    from cad.studies.codesign.search import STOCK_THICKNESS_MM, bar_stock, handle_materials

    laser = bar_stock("laser")
    assert set(laser) == {k for k, s in SHEETS.items() if s.tappable} and "carbon-fibre" not in laser
    for mat, ts in laser.items():
        assert ts == tuple(SHEETS[mat].thicknesses_mm)
    assert set(bar_stock("printed")) == set(STOCK_THICKNESS_MM) & set(FILAMENTS) == {"pla", "petg"}
    assert bar_stock("machined") == STOCK_THICKNESS_MM
    assert set(handle_materials("printed")) <= set(FILAMENTS)


@pytest.mark.parametrize("process", ["laser", "printed"])
def test_starting_guesses_are_made_by_the_process(process):
    from cad.studies.codesign.search import bar_stock, handle_materials, starts_for

    for s in starts_for(process):
        mat = s["bar_material"]
        assert mat in bar_stock(process) and s[f"thickness_{mat}"] in bar_stock(process)[mat]
        assert s["handle_material"] in handle_materials(process)


def test_fit_material_choices_follow_the_process(tmp_path):
    from cad.studies.fit import parse_free

    laser = load_design(DESIGNS / "hoeken_laser.toml")
    got = parse_free("parts.bar_material", laser.parts).choices
    assert set(got) == {"aluminium-5083", "aluminium-6061"}  # the tappable sheets; no carbon-fibre
    mm = set(parse_free("parts.motor_mount_material", laser.parts).choices)
    assert mm == set(SHEETS)  # the mount plate holds no thread: every sheet
    printed = load_design(DESIGNS / "hoeken_printed.toml")
    assert set(parse_free("parts.bar_material", printed.parts).choices) == set(FILAMENTS)


def test_optimize_laser_returns_a_design_the_laser_build_accepts(tmp_path):
    out = tmp_path / "opt.toml"
    code, _, err = hapticad("optimize", DESIGNS / "hoeken_laser.toml", "--trials", "30", "--exact-top", "1",
                            "--out", out)
    assert code in (0, 1), err
    parts = tomllib.loads(out.read_text())["parts"]
    assert parts["process"] == "laser" and parts["bar_material"] in SHEETS
    assert parts["bar_thickness_mm"] in SHEETS[parts["bar_material"]].thicknesses_mm
    code, _, err = hapticad("build", out, "--fidelity", "preview", "--formats", "dxf", "--out", tmp_path / "b")
    assert code == 0, err
    bom = (tmp_path / "b" / "bom.csv").read_text()
    assert "laser" in bom and "carbon-fibre" not in bom


def _warnings(err: str) -> list[str]:
    """The design warnings of a command's stderr; the datasheet's verdicts (check's
    ``warning: datasheet:`` lines, optimize's ``the optimum misses a default datasheet
    limit`` lines) are each command's own report and left out."""
    return [s for s in err.splitlines() if s.startswith("hapticad: warning:")
            and not s.startswith(("hapticad: warning: datasheet:",
                                  "hapticad: warning: the optimum misses"))]


def test_optimize_says_the_written_designs_warnings_only(tmp_path):
    """The exact re-evaluations build several candidates (laser bars, different pins and
    handles); what optimize warns about is the source design and the one design it writes,
    nothing a rejected candidate would have said: its design warnings are those ``check``
    gives for the source design and the written design, together (a second reader:
    ``check``)."""
    src = tmp_path / "laser.toml"
    src.write_text((DESIGNS / "hoeken_laser.toml").read_text() + "\n[targets]\nM11_max_g = { max = 25.0 }\n")
    out = tmp_path / "opt.toml"
    code, _, err = hapticad("optimize", src, "--trials", "60", "--exact-top", "2", "--out", out)
    assert code == 1, err  # 25 g is out of reach: said, exit 1
    said = set(_warnings(err))
    expected = set()
    for design in (src, out):
        c, _, e = hapticad("check", design)
        expected |= set(_warnings(e))
    assert said == expected, (said ^ expected)
