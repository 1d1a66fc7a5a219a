"""Bearings by their ISO designation (issue 34 item 6): "608" is the 8 x 22 x 7 mm bearing.

Reference: ISO 15 / SKF catalog dimension series 60-, 62-, 618-: a "608" deep groove ball
bearing has bore 8 mm, outside diameter 22 mm, width 7 mm; "6200" is 10 x 30 x 9 mm;
"618/4" is 4 x 9 x 2.5 mm (numbers from the catalog, typed here, not read from our table).
"""

from __future__ import annotations

import pytest

from cad.data.catalog import get_bearing
from cad.design.parts import parse_parts
from cad.errors import DesignError


@pytest.mark.parametrize("name,d,D,B,size", [
    ("608", 8.0, 22.0, 7.0, "M8-22-7"),
    ("6200", 10.0, 30.0, 9.0, "M10-30-9"),
    ("618/4", 4.0, 9.0, 2.5, "M4-9-2.5"),
])
def test_iso_designation_gives_catalog_dimensions(name, d, D, B, size):
    b = get_bearing(name)
    assert (b.d_mm, b.D_mm, b.B_mm, b.size, b.designation) == (d, D, B, size, name)
    assert get_bearing(size) == b


def test_parts_table_keeps_catalog_form():
    """A design typing bearing = "608" loads as the M8-22-7 it names (bar wide enough for
    the 22 mm seat with 2 mm walls, thick enough for 7 mm plus a lip)."""
    t = {"bar_width_mm": 30.0, "bar_thickness_mm": 10.0}
    assert parse_parts({**t, "bearing": "608"}) == parse_parts({**t, "bearing": "M8-22-7"})
    assert parse_parts({**t, "bearing": "608"}).bearing == "M8-22-7"


def test_unknown_designation_names_field_and_value():
    with pytest.raises(DesignError) as e:
        get_bearing("6999x", "parts.bearing")
    assert "parts.bearing" in str(e.value) and "'6999x'" in str(e.value)
