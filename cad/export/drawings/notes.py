"""What a sheet writes beside each feature: the fit, the thread with its depth.

Pure functions on :class:`cad.export.drawings.features.Cylinder` records and the part's data.
"""

from __future__ import annotations

import re

from cad.data.catalog import tap_drill_mm
from cad.data.fits import fmt_mm, metric_thread, parse_fit
from cad.tolerances import MATCH_MM

#: A printed part's fit text (:func:`cad.printing.printed_fit`, the printed bars' pin bores):
#: label, nominal, printed diameter (mm), how it is held.
PRINTED_FIT = re.compile(r"(.*\S) (\d+(?:\.\d+)?) printed (\d+(?:\.\d+)?) \((.*)\)")
#: General tolerance for untoleranced dimensions when the design states none.
GENERAL_TOLERANCE = "ISO 2768-m"


def callout(c, fits: tuple[str, ...], threads=(), extent_mm: float | None = None,
            datum_mm=(0.0, 0.0, 0.0)) -> str:
    """The text of one feature: ``"Ø8 H7 thru"``, ``"M4 tap drill Ø3.3, thread 6 deep,
    drill 8 deep"``, ``"Ø16 J7, 4 deep"``, ``"R10"``.

    c : :class:`cad.export.drawings.features.Cylinder`. fits : the part's fit texts
    (:func:`cad.data.fits.fit`). threads : its tapped holes, each ``(size, depth mm or None)``
    or ``(size, depth, name, axis, point_mm)`` (a :class:`cad.assembly.fasteners.TappedHole`'s
    place in the part frame, None when unstated); which record is this hole's:
    :func:`thread_depths`. extent_mm : the part's size along ``c.axis`` (a hole that long is
    ``thru``). datum_mm : the part-frame corner ``c`` is measured from.
    """
    if not c.full:
        return f"R{fmt_mm(c.d_mm / 2)}"
    length = c.hi_mm - c.lo_mm
    thru = extent_mm is not None and abs(length - extent_mm) < 1e-6
    deep = "thru" if thru else f"{fmt_mm(length)} deep"
    if c.internal:
        found = thread_depths(c, threads, datum_mm)
        if found is not None:
            key, depths = found
            return f"{key} tap drill Ø{fmt_mm(c.d_mm)}{_thread_text(depths, length)}, drill {deep}"
    for text in fits:
        parsed = parse_fit(text)
        if parsed is None:  # a printed part's stated hole: its printed size and tolerance
            printed = PRINTED_FIT.fullmatch(text)
            if printed is not None and abs(float(printed[3]) - c.d_mm) < MATCH_MM and c.internal:
                return f"Ø{printed[3]} printed ({printed[1]} {printed[2]}: {printed[4]}), {deep}"
            continue
        label, d, cls = parsed
        if abs(d - c.d_mm) < MATCH_MM and cls[:1].isupper() == c.internal:
            return f"Ø{fmt_mm(d)} {cls} ({label}), {deep if c.internal else fmt_mm(length) + ' long'}"
    return f"Ø{fmt_mm(c.d_mm)}, {deep if c.internal else fmt_mm(length) + ' long'}"


def _thread_text(depths, length: float) -> str:
    """``", thread 6 deep"``, ``", thread 12.5 deep (top), 11 deep (bottom)"`` (two records
    on one axis), ``", thread 7 deep (from the solid)"`` (no record says which)."""
    if depths == "solid":
        return f", thread {fmt_mm(length)} deep (from the solid)"
    if len(depths) == 1:
        d = depths[0][1]
        return f", thread {fmt_mm(d)} deep" if d is not None else ""
    return ", thread " + ", ".join(
        f"{fmt_mm(d)} deep ({label})" if d is not None else f"unstated ({label})"
        for label, d in depths)


def _on_axis(c, axis, point, datum) -> bool:
    """Is the record's axis (part frame) the cylinder's axis (within MATCH_MM)?"""
    if c.axis == "n":
        n, q = c.direction, c.point_mm
    else:
        k = "xyz".index(c.axis)
        i, j = [m for m in range(3) if m != k]
        n = [0.0, 0.0, 0.0]
        n[k] = 1.0
        q = [0.0, 0.0, 0.0]
        q[i], q[j] = c.u_mm, c.v_mm
    norm = sum(a * a for a in axis) ** 0.5
    a = [x / norm for x in axis]
    if abs(abs(sum(x * y for x, y in zip(a, n, strict=True))) - 1.0) > 1e-9:
        return False
    w = [p - d - qq for p, d, qq in zip(point, datum, q, strict=True)]  # record -> cylinder
    t = sum(x * y for x, y in zip(w, n, strict=True))
    return sum((x - t * y) ** 2 for x, y in zip(w, n, strict=True)) ** 0.5 < MATCH_MM


def thread_depths(c, threads, datum_mm=(0.0, 0.0, 0.0)):
    """``(thread key, [(label, depth or None), ...] or "solid")`` of the tapped hole ``c``
    (an internal :class:`cad.export.drawings.features.Cylinder` of a size's tap drill), or
    None when no record's size has this tap drill. The records of that size (``threads`` as
    in :func:`callout`) that state their place and lie on ``c``'s axis are its records (one
    label each, the name after ``:``, when their depths differ); else those that state none:
    one depth among them is it; several, the one the hole can hold (recorded depth <= its
    length), if one; still several, or none left: ``"solid"`` (print the solid's depth)."""
    key, cands = None, []
    for size, depth, *place in threads:
        k = metric_thread(size)
        if k is not None and abs(tap_drill_mm(k) - c.d_mm) < MATCH_MM:
            key = key or k
            name, axis, point = (place + [None, None, None])[:3]
            cands.append((k, (name or "").rpartition(":")[2], depth, axis, point))
    if key is None:
        return None
    on = [x for x in cands if x[3] is not None and _on_axis(c, x[3], x[4], datum_mm)]
    pool = on or [x for x in cands if x[3] is None]
    if not pool:
        return key, "solid"
    key = pool[0][0]
    depths = list(dict.fromkeys((x[1], x[2]) for x in pool))
    if len({d for _, d in depths}) == 1:
        return key, depths[:1]
    if on:
        return key, depths
    length = c.hi_mm - c.lo_mm
    fit = {d for _, d in depths if d is not None and d <= length + MATCH_MM}
    return (key, [("", fit.pop())]) if len(fit) == 1 else (key, "solid")
