"""The shoulder-screw pin of a four-bar joint: the window its shoulder may end in, in the
lower bar (read by the layer planner, :mod:`cad.families.fourbar.layers`, and the sheet
tolerance bands, :mod:`cad.families.fourbar.sheet_tolerance`). Lengths mm."""

from __future__ import annotations

import numpy as np

from cad.data import catalog
from cad.design.parts import PartsSpec
from cad.errors import DesignError

#: Shoulder must enter the lower link by at least this (mm) to locate it.
SHOULDER_MIN_ENTRY_MM = 1.0


def pin_window(parts: PartsSpec, t: float, on_post: bool) -> tuple[float, float]:
    """(lo, hi) mm: where the shoulder of ``parts.pin`` may end, measured down from the top
    of a lower bar ``t`` mm thick (on the post: at least :data:`SHOULDER_MIN_ENTRY_MM`, no
    upper bound). DesignError naming ``parts.bar_thickness_mm`` when no window is left."""
    pin = catalog.get_shoulder_screw(parts.pin)
    if on_post:
        return SHOULDER_MIN_ENTRY_MM, np.inf
    w = catalog.get_washer(parts.pin)
    nut = catalog.get_nut(parts.pin)
    lo = max(SHOULDER_MIN_ENTRY_MM, t + w.h_mm + nut.m_mm - pin.b_mm)
    hi = min(t - 0.5, t + w.h_mm - pin.g2_mm)
    if lo > hi:
        raise DesignError(
            "parts.bar_thickness_mm",
            f"a {t:g} mm bar cannot be clamped by the {parts.pin} shoulder screw and nut "
            f"(shoulder entry window {lo:g}..{hi:g} mm is empty)",
        )
    return lo, hi
