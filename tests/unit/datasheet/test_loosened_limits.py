"""A [targets] bound looser than a default limit (a tester found it silent): the verdict,
the datasheet's notes, report.html and the terminal table say which default it loosens;
a tighter or equal bound says nothing more."""

from __future__ import annotations

import json
from pathlib import Path

from cli_helpers import hapticad

from cad.datasheet import judge, row, verdict_text
from cad.datasheet.limits import FIRST_MODE_MIN_HZ, MODE_REASON, Limit, loosened_notes, with_targets
from cad.design.targets import Target

ROOT = Path(__file__).resolve().parents[3]


def _limits(bound: float) -> dict[str, Limit]:
    lim = {"first_mode_Hz": Limit(">=", FIRST_MODE_MIN_HZ, MODE_REASON, "parts.bar_material")}
    return with_targets(lim, [Target("first_mode_Hz", min=bound)])


def test_a_looser_target_is_said_beside_its_verdict():
    rows = [row("first_mode_Hz", "first structural mode", 120.0, "Hz", "frame model")]
    assert judge(rows, _limits(100.0)) == []  # met: the design's own requirement
    assert verdict_text(rows[0]) == "ok (>= 100; [targets], looser than the default >= 150)"
    assert loosened_notes(rows) == [
        f"first structural mode: judged against [targets] >= 100 Hz, looser than the default limit "
        f">= 150 ({MODE_REASON})"]


def test_a_tighter_or_equal_target_adds_nothing():
    for bound in (150.0, 200.0):
        rows = [row("first_mode_Hz", "first structural mode", 120.0, "Hz", "frame model")]
        judge(rows, _limits(bound))
        assert "loosens" not in rows[0]["limit"] and loosened_notes(rows) == []
        assert verdict_text(rows[0]) == f"MISS (>= {bound:.4g})"


def test_build_says_it_in_the_table_and_report_html(tmp_path):
    """A Hoeken whose [targets] lowers the first mode to 100 Hz (preview build): a note line on
    stderr and report.html's notes at the top of its datasheet name the default."""
    text = (ROOT / "designs" / "hoeken.toml").read_text().replace(
        "[targets]", "[targets]\nfirst_mode_Hz = { min = 100.0 }", 1)
    (tmp_path / "d.toml").write_text(text)
    code, out, err = hapticad("build", tmp_path / "d.toml", "--out", tmp_path / "b", "--fidelity", "preview")
    assert code == 0, err
    notes = [ln for ln in err.splitlines() if ln.startswith("hapticad: note: datasheet:")]
    assert notes == ["hapticad: note: datasheet: first structural mode: judged against [targets] >= 100 Hz, "
                     f"looser than the default limit >= 150 ({MODE_REASON})"], err
    page = (tmp_path / "b" / "report.html").read_text()
    head = page[page.index("<h2>Datasheet</h2>"):page.index("<table", page.index("<h2>Datasheet</h2>"))]
    assert "judged against [targets] &gt;= 100 Hz, looser than the default limit &gt;= 150" in head
    rep = json.loads((tmp_path / "b" / "report.json").read_text())
    mode = next(r for r in rep["datasheet"]["rows"] if r["key"] == "first_mode_Hz")
    assert mode["limit"]["value"] == 100.0 and mode["limit"]["loosens"].startswith(">= 150")


def test_a_unitless_figure_has_no_stray_space():
    """A tester found ``= 1.91 , limit >= 3  (...)`` on the rod buckling margin's warning."""
    from cad.datasheet import warning_line

    r = row("rod_buckling_margin", "rod buckling margin", 1.91, "", "Euler")
    line = warning_line(r, Limit(">=", 3.0, "why", "parts.motor"))
    assert line == "rod buckling margin = 1.91, limit >= 3 (why); change parts.motor"
