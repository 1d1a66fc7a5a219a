"""ISO 286 tolerance classes of the seats, bores and turned journals the workshop makes.

One table for every family (four-bar, pantograph, twin pantograph, PowerMouse): a part
kind states its fits as ``"<feature> <diameter mm> <class>"`` (:func:`fit`, e.g.
``"bearing seat 16 J7"``) in :attr:`cad.parts.PartKind.fits`; the BOM's ``fits`` column,
report.json's ``fits`` key and the DXF's ``NOTES`` layer all read that tuple
(:mod:`cad.build.family`). Bore classes are upper case, shaft classes lower case; the
limits of each class are those of ISO 286-2's tables. Pure data: no CAD import.
"""

from __future__ import annotations

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
