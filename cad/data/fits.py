"""ISO 286 tolerance classes of the seats, bores and turned journals the workshop makes.

One table for every family (four-bar, pantograph, twin pantograph, PowerMouse): a part
kind states its fits as ``"<feature> <diameter mm> <class>"`` (:func:`fit`, e.g.
``"bearing seat 16 J7"``) in :attr:`cad.parts.PartKind.fits`; the BOM's ``fits`` column,
report.json's ``fits`` key and the DXF's ``NOTES`` layer all read that tuple
(:mod:`cad.pipeline.family`). Bore classes are upper case, shaft classes lower case; the
limits of each class are those of ISO 286-2's tables. Pure data: no CAD import.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from cad.data.catalog import tap_drill_mm

#: Class of each feature (bore, or shaft where lower case), with the fit it makes:
#:
#: * ``bearing seat`` J7 -- housing bore of a ball bearing's outer ring: direction of load
#:   indeterminate (a pivot), light load, outer ring free to move axially (the SKF
#:   housing-fit table's "J7" row);
#: * ``pin bore`` H7 -- reamed bore of a pin: the four-bar's ISO 7379 shoulder (f9, a
#:   running fit), the pantograph's ground dowels (``pin`` m6: H7/m6, the dowel press fit of
#:   the ISO 286-2 preferred-fit table); the knob's bore on its pin or journal;
#: * ``spacer bore``, ``post shoulder bore`` H7 -- on the ISO 7379 shoulder (f9);
#: * ``hub shaft bore`` H7 -- the hub's / hub clevis's bore on the motor shaft (maxon
#:   shafts are ground to an h-class: H7/h6 location clearance, locked by a set screw);
#: * ``pilot bore`` H7 -- the motor mount plate's centring bore on the motor's pilot
#:   collar (taken as h-class like the shaft: H7/h location clearance fit);
#: * ``journal`` js5 -- the twin pantograph's crankshaft journals in the bearings' inner
#:   rings: direction of load indeterminate, light load, d <= 17 mm (the SKF shaft-fit
#:   table's "js5 (h5)" row);
#: * ``pin`` m6 -- the ground dowel stock of the elbow and handle pins (ISO 2338 / ISO
#:   8734 dowels are m6): pressed into an H7 pin bore, through the bearings' inner rings;
#: * ``post bore`` H7 / ``post`` g6 -- the PowerMouse housing collar's bore on the stator
#:   post: H7/g6, the sliding fit of the ISO 286-2 preferred-fit table (the post slides in
#:   on assembly and is then locked by the collar's set screw);
#: * ``handle socket`` H7 / ``handle stem`` g6 -- the PowerMouse flotor's socket on the
#:   handle stem: H7/g6 sliding fit (the stem's tip is screwed into the corner boss).
FITS = {
    "bearing seat": "J7",
    "pin bore": "H7",
    "spacer bore": "H7",
    "hub shaft bore": "H7",
    "post shoulder bore": "H7",
    "pilot bore": "H7",
    "journal": "js5",
    "pin": "m6",
    "post bore": "H7",
    "post": "g6",
    "handle socket": "H7",
    "handle stem": "g6",
}


def fmt_mm(x: float) -> str:
    """A diameter as the fit text writes it: at most 2 decimals, no trailing zeros."""
    return f"{x:.2f}".rstrip("0").rstrip(".")


def fit(key: str, diameter_mm: float, label: str | None = None) -> str:
    """``"<label> <diameter> <class>"`` of feature ``key`` of :data:`FITS` (``label``
    defaults to ``key``), e.g. ``fit("bearing seat", 16.0) == "bearing seat 16 J7"``.

    diameter_mm : nominal diameter of the seat, bore or journal (mm), from the catalog or
        the design. KeyError for a feature not in :data:`FITS`.
    """
    return f"{label or key} {fmt_mm(diameter_mm)} {FITS[key]}"


# --- what a shop leaves on a profile for the finishing operation (issue 25 section 2) ------

#: Stock left on the diameter for reaming, by hole size: ``(up to d mm, allowance mm)``, the
#: low end of each row of the workshop-technology "undersize of reaming" table (0-5 mm:
#: 0.1-0.2; 5-20 mm: 0.2-0.3; 21-50 mm: 0.3-0.5; over 50 mm: 0.5-1 mm), source
#: :data:`REAM_ALLOWANCE_SOURCE`. The 5-20 mm row agrees with model-engineering practice
#: (an 8 mm reamer after a 7.8 mm drill). The low end is taken because a profile cut by
#: waterjet or laser is already round and on size within a few hundredths.
REAM_ALLOWANCE_MM = ((5.0, 0.1), (20.0, 0.2), (50.0, 0.3), (float("inf"), 0.5))
REAM_ALLOWANCE_SOURCE = (
    "undersize of reaming table (0-5 mm 0.1-0.2, 5-20 mm 0.2-0.3, 21-50 mm 0.3-0.5, "
    ">50 mm 0.5-1 mm; low end used), https://eventexam.blogspot.com/2023/09/"
    "under-sizes-of-reaming.html; the same rows (steel, up to 5 mm 0.1-0.2, 5-20 mm 0.2-0.3) "
    "in 'Manual Reaming', Technique for manual working of materials, trainees' handbook, "
    "Institut fuer Berufliche Entwicklung (GTZ), section 5.3; not checked against "
    "Machinery's Handbook"
)
#: Rule for the tap drill of an ISO metric coarse thread (:func:`cad.data.catalog.tap_drill_mm`).
TAP_DRILL_SOURCE = "tap drill = d - P (ISO 2306 drill sizes for ISO metric coarse threads)"


def ream_allowance_mm(d_mm: float) -> float:
    """Stock left on the diameter of a bore of nominal ``d_mm`` (mm) for reaming
    (:data:`REAM_ALLOWANCE_MM`)."""
    for upto, a in REAM_ALLOWANCE_MM:
        if d_mm <= upto:
            return a
    raise AssertionError("unreachable: the last row has no upper bound")


_ISO_FIT = re.compile(r"(.*\S) (\d+(?:\.\d+)?) ([A-Za-z]{1,2}\d{1,2})")


def parse_fit(text: str) -> tuple[str, float, str] | None:
    """``"bearing seat 16 J7"`` -> ``("bearing seat", 16.0, "J7")`` (the inverse of :func:`fit`);
    None for a text that states no ISO 286 fit (a printed part's "slip fit, not H7")."""
    m = _ISO_FIT.fullmatch(text)
    return None if m is None else (m[1], float(m[2]), m[3])


def metric_thread(size: str) -> str | None:
    """``"M4-0.7"`` -> ``"M4"``; None for a hole record that is no thread (a pressed dowel's)."""
    base = size.split("-")[0]
    return base if re.fullmatch(r"M\d+(?:\.\d+)?", base) else None


def finish(label: str, cls: str) -> str:
    """How the shop finishes a feature of :func:`fit` text: ``"mill"`` (a bearing seat, a
    counterbore milled to depth), ``"bore"`` (the motor pilot seat, bored), ``"ream"`` (every
    other bore class, upper case) or ``"shaft"`` (a turned or ground shaft, lower case)."""
    if "seat" in label and "pilot" not in label:
        return "mill"
    if "pilot" in label:
        return "bore"
    return "ream" if cls[:1].isupper() else "shaft"


@dataclass(frozen=True)
class ShopHole:
    """One kind of hole of a made part as the shop makes it.

    finish : ``"ream"``, ``"bore"``, ``"mill"`` or ``"tap"``.
    d_mm : its diameter in the solid (the nominal bore or seat; a tapped hole's tap drill).
    cut_d_mm : the diameter a profile is cut at (the bore less the stock left for reaming or
        boring, :func:`ream_allowance_mm`; else ``d_mm``).
    spec : the finished size, ``"8 H7"``, ``"16 J7"`` or ``"M4"``.
    label : the feature (``"pin bore"``, ``"bearing seat"``, ``"thread"``).
    depth_mm : a tapped hole's full-thread depth (None otherwise).
    """

    finish: str
    d_mm: float
    cut_d_mm: float
    spec: str
    label: str
    depth_mm: float | None = None

    def note(self) -> str:
        """The shop note: ``"ream to 8 H7"``, ``"mill bearing seat 16 J7"``, ``"tap M4"``."""
        if self.finish == "tap":
            return f"tap {self.spec}"
        if self.finish == "mill":
            return f"mill {self.label} {self.spec}"
        return f"{self.finish} to {self.spec}"


def shop_holes(fits: tuple[str, ...], threads=()) -> tuple[ShopHole, ...]:
    """The holes of a part from its :func:`fit` texts and its ``threads`` (``(size, full
    thread depth mm)`` pairs, e.g. ``("M4", 8.0)``); shafts are left out. Tap drills by
    :data:`TAP_DRILL_SOURCE`; reaming stock by :data:`REAM_ALLOWANCE_SOURCE`."""
    out = []
    for text in fits:
        parsed = parse_fit(text)
        if parsed is None:  # no ISO fit: nothing for the shop to finish
            continue
        label, d, cls = parsed
        how = finish(label, cls)
        if how == "shaft":
            continue
        cut = d - ream_allowance_mm(d) if how in ("ream", "bore") else d
        out.append(ShopHole(how, d, cut, f"{fmt_mm(d)} {cls}", label))
    seen = set()
    for size, depth in threads:
        base = metric_thread(size)
        if base is None:  # a pressed dowel's hole is no thread
            continue
        key = (base, None if depth is None else round(depth, 6))
        if key in seen:
            continue
        seen.add(key)
        dr = tap_drill_mm(key[0])
        out.append(ShopHole("tap", dr, dr, key[0], "thread", depth))
    return tuple(out)
