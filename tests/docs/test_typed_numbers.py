"""Typed numbers in the documentation (issue 34 §4): every number with a unit that README.md or a
page under docs/ states outside a generated block (``<!-- generated: ... -->``, rendered from a
committed JSON by ``cad.bench.readme``), a fenced code block or an inline code span must be in
the ledger ``tests/docs/typed_numbers.json`` with the reason it may be typed: ``paper:`` (a
figure of the two papers or a cited source), ``input:`` (a design value, a flag, a limit or a
tolerance the reader sets), ``closed form:`` (arithmetic the page shows), ``checked:`` (a
test that computes it), or ``unreviewed:`` (a number from a run that is not yet generated or
checked; the count of these is the work left). A new typed number fails this test until it
is generated from a run or given its reason; a ledger entry whose number left the page fails
too, so the ledger cannot go stale."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
LEDGER = ROOT / "tests" / "docs" / "typed_numbers.json"
REASONS = ("paper:", "input:", "closed form:", "checked:", "unreviewed:")
BLOCK = re.compile(r"<!-- generated:.*?<!-- end generated -->", re.S)
FENCE = re.compile(r"```.*?```", re.S)
CODE = re.compile(r"`[^`\n]*`")
UNITS = r"g|Hz|kHz|kN/m|N/m|mN·m|mN m|N·m|MPa|GPa|%|s|ms|µs|min|mm|N|µm|um|kg|g/cm³|K/W|mA|A|Ω|V|W|°"
_N = r"(?:\d{1,3}(?:[ \u202f\u00a0]\d{3})+|\d+)(?:[.,]\d+)*"
NUMBER = re.compile(r"(?<![\w.#/@-])(" + _N + r"(?:\s?[–-]\s?" + _N + r")?)\s?(" + UNITS + r")(?![\w/])")


def pages() -> list[Path]:
    return [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


def typed_numbers(text: str) -> set[str]:
    """``"<number> <unit>"`` of every typed number with a unit outside generated blocks,
    fenced code and inline code (a range ``a–b`` counts as one)."""
    prose = CODE.sub(" ", FENCE.sub(" ", BLOCK.sub(" ", text)))
    return {"".join(n.split()) + " " + u for n, u in NUMBER.findall(prose)}


def _ledger() -> dict[str, dict[str, str]]:
    return json.loads(LEDGER.read_text(encoding="utf-8"))


def test_extraction_by_hand():
    text = ("M11 24.3 g and 15 000 N/m; `code 5 mm` skipped\n```\n7 Hz\n```\n<!-- generated: x -->\n"
            "9 g\n<!-- end generated -->\nrange 13.9–17.6 kN/m, 0.33 ms, v1.2 g2 M3")
    assert typed_numbers(text) == {"24.3 g", "15000 N/m", "13.9–17.6 kN/m", "0.33 ms"}


@pytest.mark.parametrize("page", pages(), ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_typed_number_has_a_reason(page):
    name = page.relative_to(ROOT).as_posix()
    entries = _ledger().get(name, {})
    found = typed_numbers(page.read_text(encoding="utf-8"))
    new = sorted(found - set(entries))
    assert not new, (f"{name}: typed numbers with no backing: {new[:8]}; generate them from a run "
                     f"(a generated block) or add them to {LEDGER.name} with a reason {REASONS}")
    gone = sorted(set(entries) - found)
    assert not gone, f"{name}: ledger entries no longer on the page: {gone[:8]}"
    bad = {k: v for k, v in entries.items() if not v.startswith(REASONS) or len(v) < len("input: x")}
    assert not bad, f"{name}: entries without a reason: {list(bad)[:5]}"


def test_ledger_names_only_pages():
    names = {p.relative_to(ROOT).as_posix() for p in pages()}
    assert set(_ledger()) <= names


def test_unreviewed_count_only_falls():
    """The numbers from runs not yet generated or checked: their count is the work left, and a
    change may only lower it (raise UNREVIEWED_MAX never; lower it when entries are resolved)."""
    n = sum(v.startswith("unreviewed:") for e in _ledger().values() for v in e.values())
    assert n <= UNREVIEWED_MAX


#: Unreviewed ledger entries when this test was written (issue 34 §4); only ever lowered.
UNREVIEWED_MAX = 0
