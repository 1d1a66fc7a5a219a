"""Deterministic figure files: same figure -> same bytes (SPEC "Trust": same design ->
byte-identical outputs).

Matplotlib stamps SVGs with a date and random element ids and PNGs with its version;
:func:`save_figure` writes without either (a fixed ``svg.hashsalt``, no ``Date``, no
``Software``), so charts can be compared and cached by hash.
"""

from __future__ import annotations

from cad.errors import FileRefused
from cad.io import guard
from cad.io.figures import NO_STAMPS, save_figure  # noqa: F401 - the writer lives in cad.io

#: Axes title height (axes fraction) given explicitly: with matplotlib's automatic one
#: (``axes.titley`` None) every draw measures the tick labels' extents to place the
#: title, a third of a chart's drawing time; 1.0 is where it lands without top ticks.
TITLE_Y = 1.0


def written_by_hapticad(path) -> bool:
    """True when the PNG or SVG chart at ``path`` carries :func:`save_figure`'s creator
    mark (PNG text ``Software: hapticad``; SVG ``dc:creator`` hapticad)."""
    from pathlib import Path

    try:  # a FIFO or a device planted as the chart is never read (cad/io/guard.py)
        data = guard.read_bytes(Path(path), "chart", "--out")
    except FileRefused:
        return False
    if data.startswith(b"\x89PNG"):
        return b"Software\x00hapticad" in data
    return b"<dc:title>hapticad</dc:title>" in data[:4096]
