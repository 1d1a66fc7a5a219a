"""Printed parts are ordered as filament (case outputs-agree/bom-printed-stock-filament).

Reference: docs/ordering.md's stock table ("filament / wire | printed parts | `filament 12 g
pla` | none (the part's mass)"); the process text is the one the BOM writes for a printed part
(:meth:`cad.printing.PrintSettings.describe`). The part here is an 8 x 30 x 155 mm box that the
faulty prefix match ordered as ``plate 8 x 30 x 155 mm pla``.
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from cad.export.order import stock
from cad.printing import PrintSettings


def _kind(process: str, material: str = "pla"):
    from build123d import Box

    return SimpleNamespace(shape=Box(30, 155, 8), material=material, process=process,
                           plate=True, description="crank")


@pytest.mark.parametrize("process", [PrintSettings().describe("pla"), "printed"])
def test_printed_part_is_ordered_as_filament_by_mass(process):
    assert process.startswith(("FDM print PLA: 0.2 mm layers", "printed"))
    assert stock(_kind(process), 4.4) == "filament 4.4 g pla"
    assert stock(_kind(process), 0.37) == "filament 0.4 g pla"  # a spacer: not "0 g"
    assert stock(_kind(process), 78.6) == "filament 79 g pla"


def test_machined_plate_still_ordered_as_plate():
    # 8 mm plate, 30 x 155 + 2 x STOCK_PLATE_MARGIN_MM per side, rounded up to whole mm
    from cad import tolerances as tol

    m = 2 * tol.STOCK_PLATE_MARGIN_MM
    assert stock(_kind("milled", "aluminium-6061"), 10.0) == (
        f"plate 8 x {math.ceil(30 + m)} x {math.ceil(155 + m)} mm aluminium-6061")
