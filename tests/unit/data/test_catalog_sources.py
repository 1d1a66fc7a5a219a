"""Every catalog value names its source (issue 34 §3): a walk over every entry of every catalog
in ``cad/data`` (motors, encoders, materials, sheet stock, filaments, elastic data), failing on a
value with no source, on a source that says it is not identified / not found / derived without
the value being marked unverified, and (motors) on a verified value whose source names no
fixed edition (a year, a commit, an edition). The marks then reach every output: the BOM's
motor line, report.json's device, the datasheet rows (tests beside)."""

from __future__ import annotations

import re

import pytest

from cad.data.catalog import ENCODERS, MOTOR_DATA_FIELDS, MOTORS
from cad.data.materials import LASER_CUT_SIZES_SOURCE, MATERIALS, SHEETS
from cad.printing import FILAMENTS
from cad.structure.elastic import ELASTIC

#: Words by which a source says it does not state the value as given (then: unverified).
UNSTATED = re.compile(r"not identified|no public source|not found|derived|recalled|assumed|"
                      r"no data sheet|no .{0,20}source", re.I)
#: What names a fixed edition of a source: a year, a commit, an edition or version number,
#: a standard, a section of one of the two papers.
EDITION = re.compile(r"\b(19|20)\d\d\b|commit [0-9a-f]{7}|edition \S|\bv?\d+\.\d+\.\d+\b|§", re.I)


def _unverified_if_unstated(source: str, marked: bool, what: str) -> None:
    assert source.strip(), f"{what}: no source"
    if UNSTATED.search(source):
        assert marked, f"{what}: source {source!r} does not state the value, yet it is not marked unverified"


@pytest.mark.parametrize("key", sorted(MOTORS))
def test_motor_values(key):
    m = MOTORS[key]
    for f in MOTOR_DATA_FIELDS:
        if getattr(m, f) is None:
            assert m.is_unverified(f)
            continue
        src = m.source_of(f)
        _unverified_if_unstated(src, m.is_unverified(f), f"{key}.{f}")
        if not m.is_unverified(f):
            assert EDITION.search(src), f"{key}.{f}: verified, but {src!r} names no edition"


def test_the_re40_sheet_values_without_an_edition_are_unverified():
    """The three values the issue names: the sheet copy they come from names no edition."""
    m = MOTORS["maxon-re40"]
    for f in ("torque_continuous_mNm", "no_load_current_mA", "stall_torque_mNm"):
        assert m.is_unverified(f) and "edition not identified" in m.source_of(f)
    assert "unverified data" in m.bom_description() and "no_load_current_mA" in m.bom_description()
    assert m.bom_description().startswith(m.description)


@pytest.mark.parametrize("key", sorted(ENCODERS))
def test_encoder_values(key):
    e = ENCODERS[key]
    _unverified_if_unstated(e.source, "unverified" in e.source, key)
    if e.mass_kg is None:
        assert "mass unverified" in e.source


@pytest.mark.parametrize("key", sorted(MATERIALS))
def test_material_densities(key):
    m = MATERIALS[key]
    _unverified_if_unstated(m.source, "unverified" in m.source, key)


@pytest.mark.parametrize("key", sorted(SHEETS))
def test_sheet_stock_values(key):
    st = SHEETS[key]
    for f in ("thickness_range_mm", "sizes_mm", "E_GPa", "strength_MPa", "kerf_mm", "tappable", "reamable"):
        src = st.source.get(f, "")
        _unverified_if_unstated(src, "unverified" in src or "design rule" in src, f"{key}.{f}")
    assert "unverified" in LASER_CUT_SIZES_SOURCE and EDITION.search(LASER_CUT_SIZES_SOURCE)


@pytest.mark.parametrize("table, key", [("filament", k) for k in sorted(FILAMENTS)]
                         + [("elastic", k) for k in sorted(ELASTIC)])
def test_filament_and_elastic_values(table, key):
    src = (FILAMENTS if table == "filament" else ELASTIC)[key].source
    _unverified_if_unstated(src, "unverified" in src, f"{table} {key}")


def test_the_rule_catches_an_unmarked_unstated_value():
    """The walk's rule itself: a source admitting it is not identified fails unless marked."""
    with pytest.raises(AssertionError, match="not marked unverified"):
        _unverified_if_unstated("a public copy (edition not identified)", False, "x")
    with pytest.raises(AssertionError, match="no source"):
        _unverified_if_unstated("  ", True, "x")
    _unverified_if_unstated("a public copy (edition not identified)", True, "x")
