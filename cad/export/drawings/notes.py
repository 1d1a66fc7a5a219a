"""What a sheet writes beside each feature: the fit, the thread with its depth, the stock.

Pure functions on :class:`cad.export.drawings.features.Cylinder` records and the part's data.
"""

from __future__ import annotations

from cad.data.fits import fmt_mm, metric_thread, parse_fit
from cad.tolerances import MATCH_MM, STOCK_MARGIN_MM

#: General tolerance for untoleranced dimensions when the design states none.
GENERAL_TOLERANCE = "ISO 2768-m"


def callout(c, fits: tuple[str, ...], threads=(), extent_mm: float | None = None) -> str:
    """The text of one feature: ``"Ø8 H7 thru"``, ``"M4 tap drill Ø3.3, thread 6 deep,
    drill 8 deep"``, ``"Ø16 J7, 4 deep"``, ``"R10"``.

    c : :class:`cad.export.drawings.features.Cylinder`. fits : the part's fit texts
    (:func:`cad.data.fits.fit`). threads : ``(size, depth mm or None)`` of its tapped
    holes. extent_mm : the part's size along ``c.axis`` (a hole that long is ``thru``).
    """
    from cad.data.catalog import tap_drill_mm

    if not c.full:
        return f"R{fmt_mm(c.d_mm / 2)}"
    length = c.hi_mm - c.lo_mm
    thru = extent_mm is not None and abs(length - extent_mm) < 1e-6
    deep = "thru" if thru else f"{fmt_mm(length)} deep"
    if c.internal:
        for size, depth in threads:
            key = metric_thread(size)
            if key is not None and abs(tap_drill_mm(key) - c.d_mm) < MATCH_MM:
                thread = f", thread {fmt_mm(depth)} deep" if depth is not None else ""
                return f"{key} tap drill Ø{fmt_mm(c.d_mm)}{thread}, drill {deep}"
    for text in fits:
        parsed = parse_fit(text)
        if parsed is None:  # a printed part's stated hole: no ISO fit to print
            continue
        label, d, cls = parsed
        if abs(d - c.d_mm) < MATCH_MM and cls[:1].isupper() == c.internal:
            return f"Ø{fmt_mm(d)} {cls} ({label}), {deep if c.internal else fmt_mm(length) + ' long'}"
    return f"Ø{fmt_mm(c.d_mm)}, {deep if c.internal else fmt_mm(length) + ' long'}"


def stock(process: str, size_mm: tuple[float, float, float], plate: bool,
          round_d_mm: float | None) -> str:
    """The stock to cut a part from: a plate of its thickness with a blank
    :data:`STOCK_MARGIN_MM` larger each side, round bar for a turned part (its largest
    boss diameter, the length with facing stock), else a block."""
    m = 2 * STOCK_MARGIN_MM
    x, y, z = size_mm
    if plate:
        return f"plate {fmt_mm(z)} mm, blank {fmt_mm(x + m)} x {fmt_mm(y + m)}"
    if process.startswith("turned") and round_d_mm is not None:
        return f"round bar Ø{fmt_mm(round_d_mm + m)}, length {fmt_mm(z + m)}"
    return f"block {fmt_mm(x + m)} x {fmt_mm(y + m)} x {fmt_mm(z + m)}"
