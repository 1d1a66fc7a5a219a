"""An inch slip is not suggested as cm (issue 34 item 6).

Reference: 1 in = 25.4 mm exactly (international yard and pound, 1959); 1 cm = 10 mm. A
value on the 1/16 in grid that no 0.1 cm step reaches (0.375, 1.25) is inches; one that
both grids reach (3, 2.5) is named both ways; one off the 1/16 in grid (6.4, 0.35) is cm.
The converted values below are typed from those definitions, not read from the code.
"""

from __future__ import annotations

import pytest

from cad.design.bounds import PART_MM


@pytest.mark.parametrize("v,hint", [
    (0.375, "; did you give inches? (0.375 inches = 9.525 mm)"),
    (1.25, "; did you give inches? (1.25 inches = 31.75 mm)"),
    (3.0, "; did you give cm or inches? (3 cm = 30 mm; 3 inches = 76.2 mm)"),
    (2.5, "; did you give cm or inches? (2.5 cm = 25 mm; 2.5 inches = 63.5 mm)"),
    (6.4, "; did you give cm? (6.4 cm = 64 mm)"),
    (0.35, "; did you give cm? (0.35 cm = 3.5 mm)"),
])
def test_part_dimension_slip_names_the_likely_unit(v, hint):
    assert PART_MM.slip_hint(v) == hint


def test_limit_filters_before_the_unit_choice():
    """With a limit only the inch value meets (>= 50 mm), 3 is inches alone."""
    assert PART_MM.slip_hint(3.0, ok=lambda w: w >= 50.0) == (
        "; did you give inches? (3 inches = 76.2 mm)")
