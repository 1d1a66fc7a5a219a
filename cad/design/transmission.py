"""The ``[transmission]`` table of a design: direct drive or a capstan (cable) reduction on an
actuated joint (issue 35, a public contract)::

    [transmission]          # per motor; omitted = direct drive
    kind = "capstan"        # "direct" | "capstan"
    capstan_diameter_mm = 10.0
    drum_diameter_mm = 120.0   # or ratio = 12.0 (exactly one of the two)
    cable = "steel-7x19-0.6"   # a key of cad.data.cables.CABLES
    wraps = 3.0                # optional: turns of rope on the capstan (default DEFAULT_WRAPS)
    pretension_N = 40.0        # optional: the tensioner's setting (default: none stated)
    cable_EA_N = 20000.0       # optional: the rope's axial stiffness E A when its maker states it

:func:`parse_transmission` validates one such table and returns a frozen :class:`Transmission`.
Bad input is a one-line :class:`cad.errors.DesignError` naming the field, the value, the reason
and the likely unit slip ("did you give metres?"). The parser is pure (no CAD import); a family
schema calls it on its ``transmission`` table (not wired into the families yet).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from cad.actuators.capstan import bend_ratio_warning
from cad.actuators.capstan_geometry import check_centre_distance
from cad.data.cables import CABLES, get_cable
from cad.design.bounds import Bound, check_number
from cad.design.fields import check_unknown
from cad.errors import DesignError

KINDS = ("direct", "capstan")
KEYS = ("kind", "capstan_diameter_mm", "drum_diameter_mm", "ratio", "cable", "wraps",
        "pretension_N", "cable_EA_N", "centre_distance_mm")
_CAPSTAN_ONLY = KEYS[1:]
_LEN_SLIPS = (("metres", 1000.0), ("cm", 10.0), ("inches", 25.4))

#: A capstan carries a rope wrapped round it: below 1 mm no catalog rope bends round it; over
#: 100 mm it is no longer the small pulley of a reduction. Plausible: 3-40 mm (haptic kits use
#: 5-20 mm; WoodenHaptics 10 mm, cad.data.cables.WOODENHAPTICS_SOURCE).
CAPSTAN_DIAMETER_MM = Bound(
    "mm", 1.0, 100.0, "a capstan is a pulley of 1 to 100 mm on the motor shaft", 3.0, 40.0,
    "haptic capstans are 3 to 40 mm", _LEN_SLIPS)
#: The drum (or sector) on the link: up to 1 m (the desktop-device part bound of
#: cad.design.bounds.PART_MM); plausible up to 400 mm.
DRUM_DIAMETER_MM = Bound(
    "mm", 1.0, 1000.0, "a drum on a desktop device's link is 1 mm to 1 m", 10.0, 400.0,
    "haptic drums are 10 to 400 mm", _LEN_SLIPS)
#: Drum / capstan: a reduction (> 1); beyond 50 the reflected rotor inertia n^2 J_m of any
#: catalog motor dwarfs the links (the RE 35's 79.2 g cm^2 becomes 20 g m^2 at n = 50).
RATIO = Bound("", 1.0, 50.0, "the ratio is drum / capstan diameter, a reduction in (1, 50]",
              2.0, 25.0, "haptic capstan ratios are 2 to 25 (WoodenHaptics: 12 and 16)",
              lo_open=True)


#: Turns of rope on the capstan when the design states none: a tool default, not data. At
#: mu = 0.12 (cad.actuators.capstan.MU_STEEL_ROPE_ON_STEEL) 3 turns hold T_t / T_s up to
#: e^(0.12 * 6 pi) = 9.6, so the pretension at peak load is 0.62 of the rope load.
DEFAULT_WRAPS = 3.0
WRAPS = Bound("turns", 0.25, 20.0, "rope turns on a capstan are 0.25 to 20", 1.0, 10.0,
              "capstan drives wrap 1 to 10 turns")
#: The tensioner's pretension: a rope of a desktop device carries up to a few hundred N.
PRETENSION_N = Bound("N", 0.0, 5000.0, "a rope pretension is 0 to 5 kN", 1.0, 500.0,
                     "haptic capstan pretensions are 1 to 500 N", lo_open=True)
#: Axial stiffness E A of a sub-millimetre to 2 mm steel rope: E ~ 100-200 GPa on a metallic
#: area of 0.05-2 mm^2 gives 5 kN .. 400 kN; the bound allows 0.1 kN .. 10 MN.
CABLE_EA_N = Bound("N", 100.0, 1.0e7, "a rope's E A is 100 N to 10 MN", 1.0e3, 1.0e6,
                   "steel ropes of 0.3 to 2 mm have E A of 1 kN to 1 MN")
#: Distance between the drum's and the capstan's axes: at most the desktop part bound (1 m);
#: the smallest that fits is checked against the two pitch radii
#: (:func:`cad.actuators.capstan_geometry.check_centre_distance`).
CENTRE_DISTANCE_MM = Bound(
    "mm", 1.0, 1000.0, "the drum-to-capstan centre distance is 1 mm to 1 m", 5.0, 300.0,
    "haptic capstan drives sit 5 to 300 mm apart", _LEN_SLIPS)


@dataclass(frozen=True)
class Transmission:
    """A validated ``[transmission]`` table.

    kind : "direct" or "capstan". ratio : n = drum / capstan diameter (1 for direct drive;
    joint torque = n * motor torque, joint angle = motor angle / n). capstan_diameter_mm :
    the capstan on the motor shaft; drum_diameter_mm : the drum or sector on the link (given,
    or n * capstan when the design gave ``ratio``). cable : key of
    :data:`cad.data.cables.CABLES`. The three are None for direct drive. centre_distance_mm :
    the drum's axis to the capstan's (mm); None: the pitch circles
    :data:`cad.actuators.capstan.CAPSTAN_GAP_MM` apart."""

    kind: str = "direct"
    ratio: float = 1.0
    capstan_diameter_mm: float | None = None
    drum_diameter_mm: float | None = None
    cable: str | None = None
    wraps: float | None = None
    pretension_N: float | None = None
    cable_EA_N: float | None = None
    centre_distance_mm: float | None = None

    @property
    def is_capstan(self) -> bool:
        return self.kind == "capstan"


DIRECT = Transmission()


def parse_transmission(tab: dict[str, Any] | None, prefix: str = "transmission") -> Transmission:
    """Validate one ``[transmission]`` table (None or absent: direct drive).

    Raises DesignError(``<prefix>.<key>``) for an unknown key, a kind other than
    :data:`KINDS`, capstan keys on a direct drive, a missing capstan key, both or neither of
    ``drum_diameter_mm`` / ``ratio``, a number out of its bound (with the unit slip), a drum
    not larger than its capstan, or a cable not in the catalog.
    """
    if tab is None:
        return DIRECT
    if not isinstance(tab, dict):
        raise DesignError(prefix, f"must be a table, got {tab!r}")
    check_unknown(tab, KEYS, prefix)
    kind = tab.get("kind", "direct")
    if kind not in KINDS:
        raise DesignError(f"{prefix}.kind", f"must be one of {', '.join(KINDS)}, got {kind!r}")
    if kind == "direct":
        extra = [k for k in _CAPSTAN_ONLY if k in tab]
        if extra:
            raise DesignError(f"{prefix}.{extra[0]}",
                              f"only for kind = \"capstan\" (kind is {kind!r}); remove it or "
                              "set kind = \"capstan\"")
        return DIRECT
    return _parse_capstan(tab, prefix)


def _parse_capstan(tab: dict[str, Any], prefix: str) -> Transmission:
    if "capstan_diameter_mm" not in tab:
        raise DesignError(f"{prefix}.capstan_diameter_mm", "missing (the capstan on the motor "
                          "shaft, mm)")
    dc = check_number(f"{prefix}.capstan_diameter_mm", tab["capstan_diameter_mm"],
                      CAPSTAN_DIAMETER_MM)
    has_drum, has_ratio = "drum_diameter_mm" in tab, "ratio" in tab
    if has_drum == has_ratio:
        raise DesignError(f"{prefix}.drum_diameter_mm",
                          ("give drum_diameter_mm or ratio, not both" if has_drum else
                           "missing: give drum_diameter_mm (mm) or ratio (drum / capstan)"))
    if has_drum:
        dd = check_number(f"{prefix}.drum_diameter_mm", tab["drum_diameter_mm"],
                          DRUM_DIAMETER_MM)
        if dd <= dc:
            raise DesignError(f"{prefix}.drum_diameter_mm",
                              f"{dd:g} mm must be larger than capstan_diameter_mm = {dc:g} mm "
                              "(a capstan reduces: drum / capstan > 1)")
        n = dd / dc
    else:
        n = _ratio(tab["ratio"], f"{prefix}.ratio")
        dd = n * dc
        if dd > DRUM_DIAMETER_MM.hi:  # the drum it implies, held to the drum's own bound
            raise DesignError(f"{prefix}.ratio", f"{n:g} on a {dc:g} mm capstan asks for a {dd:g} mm drum, "
                              f"above {DRUM_DIAMETER_MM.hi:g} mm ({DRUM_DIAMETER_MM.reason}): a smaller "
                              "ratio or capstan")
    if "cable" not in tab:
        raise DesignError(f"{prefix}.cable", f"missing (a catalog key: {', '.join(CABLES)})")
    cable = tab["cable"]
    if not isinstance(cable, str):
        raise DesignError(f"{prefix}.cable", f"must be a catalog key (a string), got {cable!r}")
    get_cable(cable, f"{prefix}.cable")
    wraps = (check_number(f"{prefix}.wraps", tab["wraps"], WRAPS) if "wraps" in tab
             else DEFAULT_WRAPS)
    t0 = (check_number(f"{prefix}.pretension_N", tab["pretension_N"], PRETENSION_N)
          if "pretension_N" in tab else None)
    ea = (check_number(f"{prefix}.cable_EA_N", tab["cable_EA_N"], CABLE_EA_N)
          if "cable_EA_N" in tab else None)
    C = _centre_distance(tab, prefix, dc, dd, cable)
    return Transmission("capstan", n, dc, dd, cable, float(wraps), t0, ea, C)


def _centre_distance(tab: dict[str, Any], prefix: str, dc: float, dd: float,
                     cable: str) -> float | None:
    """``centre_distance_mm`` when given, refused when the pitch circles overlap (the rims then
    stand less than one rope diameter apart: the rope is pinched between them)."""
    if "centre_distance_mm" not in tab:
        return None
    field = f"{prefix}.centre_distance_mm"
    C = check_number(field, tab["centre_distance_mm"], CENTRE_DISTANCE_MM)
    return check_centre_distance(C, dc, dd, get_cable(cable).diameter_mm, 0.0, field)


def _ratio(value: Any, field: str) -> float:
    """The ratio with its slip: below 1 it is likely capstan / drum given the wrong way up; at
    or below 0 the same lower bound (> 1) is named, not the generic "> 0"."""
    if isinstance(value, (int, float)) and not isinstance(value, bool) and value < 1:
        slip = (f"; did you give capstan / drum? (1 / {value:g} = {1 / value:g})" if value > 0 else "")
        raise DesignError(field, f"must be > 1 (drum / capstan), got {value!r}{slip}")
    return check_number(field, value, RATIO)


def parse_transmissions(value: Any, n_motors: int,
                        prefix: str = "transmission") -> tuple[Transmission, ...]:
    """One :class:`Transmission` per motor: ``value`` None (direct drive on every motor), one
    table (``[transmission]``: the same on every motor) or an array of ``n_motors`` tables
    (``[[transmission]]``, in the family's motor order; field ``transmission.<n>.<key>``, n
    counted from 1 for the first table, as the capstan rows' and BOM lines' suffixes ``_n``
    count the motors). Raises DesignError(prefix) when the array's length is not ``n_motors``."""
    if value is None or isinstance(value, dict):
        return (parse_transmission(value, prefix),) * n_motors
    if not isinstance(value, list):
        raise DesignError(prefix, f"must be a table or an array of {n_motors} tables (one per "
                          f"motor), got {value!r}")
    if len(value) != n_motors:
        k = len(value)
        raise DesignError(prefix, f"must be one table or {n_motors} (one per motor), got an array of "
                          f"{k} table{'' if k == 1 else 's'}")
    return tuple(parse_transmission(t, f"{prefix}.{n}") for n, t in enumerate(value, 1))


def warn_transmissions(transmissions: tuple[Transmission, ...], warn) -> None:
    """The capstans' load-time warning, once per distinct rope and capstan: a rope below its
    bend ratio, naming the rope, the ratio and the capstan diameter or rope that fixes it
    (:func:`cad.actuators.capstan.bend_ratio_warning`); ``warn(text)`` records it. Every family
    calls it through :func:`cad.design.parse_design`."""
    seen = set()
    for t in transmissions:
        key = (t.cable, t.capstan_diameter_mm)
        if not t.is_capstan or key in seen:
            continue
        seen.add(key)
        bend = bend_ratio_warning(get_cable(t.cable), t.capstan_diameter_mm)
        if bend is not None:
            warn(f"transmission: {bend}")
