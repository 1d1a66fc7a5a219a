"""Smallest stock sheet (issue 34 §5): without ``parts.laser_sheet_mm`` the laser-cut parts are
nested on every stock size of their material that holds the largest part, and the sheets are
ordered in the size needing the least sheet area; the BOM row says so and names the sizes'
source. References: areas and fits worked by hand from the part boxes (below)."""

from __future__ import annotations

import math

import pytest

from cad import tolerances as tol
from cad.data.materials import LASER_CUT_SIZES_MM, SHEETS
from cad.export.nesting import Sheet, _candidate_sizes, _smallest_stock
from cad.pipeline.family import sheet_rows

QUARTER, HALF = (304.8, 609.6), (609.6, 609.6)  # 12 x 24 in, 24 x 24 in


def test_stock_sizes_are_the_cut_pieces_then_the_mill_sheets():
    assert LASER_CUT_SIZES_MM == (QUARTER, HALF)
    for mat, st in SHEETS.items():
        sizes = st.stock_sizes_mm
        assert sizes[:2] == (QUARTER, HALF) or sizes[0] == (1000.0, 600.0), mat
        areas = [w * h for w, h in sizes]
        assert areas == sorted(areas) and set(st.sizes_mm) <= set(sizes)


def _choose(material, boxes):
    cands = _candidate_sizes(material, None, max(boxes, key=max))
    return _smallest_stock(boxes, [f"p{i}" for i in range(len(boxes))], cands)


def test_a_60_mm_device_is_ordered_on_one_quarter_sheet():
    """The Hoeken-sized plates (base 153 x 168, three bars 80 x 20, mount 60 x 60 mm): the
    largest plus two margins (153 + 2m, 168 + 2m) fits the 304.8 x 609.6 quarter sheet, and
    their area (25,704 + 4,800 + 3,600 mm^2) is a tenth of it: one quarter sheet, not a
    1000 x 2000 mm mill sheet."""
    boxes = [(153.0, 168.0), (80.0, 20.0), (80.0, 20.0), (80.0, 20.0), (60.0, 60.0)]
    m = 2 * tol.NEST_EDGE_MARGIN_MM
    assert 168.0 + m <= QUARTER[0] or 168.0 + m <= QUARTER[1]
    size, spots = _choose("aluminium-5083", boxes)
    assert size == QUARTER
    assert {b for b, *_ in spots} == {0}


def test_a_part_over_the_quarter_sheet_goes_on_the_half_sheet():
    """A 400 x 500 mm plate: 400 + 2m > 304.8 (the quarter's short side), 500 + 2m <= 609.6:
    the half sheet, one of it."""
    size, spots = _choose("aluminium-6061", [(400.0, 500.0), (50.0, 50.0)])
    assert size == HALF and {b for b, *_ in spots} == {0}


def test_equal_area_prefers_fewer_sheets():
    """Two 280 x 580 mm plates: each fills a quarter sheet (two quarters = 2 x 185,806 mm^2),
    or both fit one half sheet side by side (280 + 280 + gap + 2m <= 609.6): the same ordered
    area, so the one half sheet."""
    g, m = tol.NEST_GAP_MM, 2 * tol.NEST_EDGE_MARGIN_MM
    assert 2 * 280.0 + g + m <= HALF[0] and 280.0 + m <= QUARTER[0] and 580.0 + m <= QUARTER[1]
    assert 2 * QUARTER[0] * QUARTER[1] == pytest.approx(HALF[0] * HALF[1])
    size, spots = _choose("aluminium-5083", [(280.0, 580.0), (280.0, 580.0)])
    assert size == HALF and {b for b, *_ in spots} == {0}


def test_many_parts_take_the_size_with_the_least_ordered_area():
    """40 plates of 250 x 250 mm: a quarter sheet holds 2 (one row of 2 along 609.6, one
    column across 304.8), a half sheet 4 (2 x 2), a 1000 x 2000 sheet 3 x 7 = 21: 20 quarters
    (3.72 m^2), 10 halves (3.72 m^2, fewer sheets) or 2 mill sheets (4.0 m^2): 10 half sheets."""
    g, m = tol.NEST_GAP_MM, 2 * tol.NEST_EDGE_MARGIN_MM
    per = {s: math.floor((s[0] - m + g) / (250 + g)) * math.floor((s[1] - m + g) / (250 + g))
           for s in (QUARTER, HALF, (1000.0, 2000.0))}
    assert per == {QUARTER: 2, HALF: 4, (1000.0, 2000.0): 21}
    size, spots = _choose("aluminium-5083", [(250.0, 250.0)] * 40)
    assert size == HALF and 1 + max(b for b, *_ in spots) == 10


def test_the_design_sheet_is_kept():
    assert _candidate_sizes("aluminium-5083", (400.0, 300.0), (153.0, 168.0)) == [(400.0, 300.0)]


def test_bom_row_says_why_this_size():
    auto = Sheet("aluminium-5083", 6.0, QUARTER, tried_mm=(QUARTER, HALF, (1000.0, 2000.0)))
    given = Sheet("aluminium-5083", 6.0, (400.0, 300.0))
    a, b = sheet_rows([auto]), sheet_rows([given])
    assert "least sheet area" in a[0]["description"] and "a-e-mag.com" in a[0]["description"]
    assert "304.8 x 609.6, 609.6 x 609.6, 1000 x 2000" in a[0]["description"]
    assert "parts.laser_sheet_mm" in b[0]["description"] and "least" not in b[0]["description"]


def test_a_nested_part_names_its_sheet_as_the_dxf_and_the_order_line_do():
    """One name per sheet in every file: the part's stock names the sheet (``sheet_02``), its
    DXF (``sheets/sheet_02.dxf``) and the order line by that line's own designation, which
    is the sheet BOM row's designation (thickness x width x length mm material, by hand)."""
    from cad.export.nesting import nested_stock, sheet_designation, sheet_file, sheet_name
    from cad.export.order import NESTED_STOCK

    s = Sheet("aluminium-5083", 6.0, (500.0, 300.0))
    assert sheet_designation(s) == "sheet 6 x 500 x 300 mm aluminium-5083"
    assert (sheet_name(1), sheet_file(1)) == ("sheet_02", "sheets/sheet_02.dxf")
    text = nested_stock(1, s)
    assert text == ("nested on sheet_02, ordered as "
                    "sheet 6 x 500 x 300 mm aluminium-5083") and text.startswith(NESTED_STOCK)
    row = sheet_rows([Sheet("aluminium-5083", 6.0, (500.0, 300.0)), s])[0]
    assert row["designation"] == sheet_designation(s) and row["quantity"] == 2
    assert "sheet_01, sheet_02" in row["description"]
