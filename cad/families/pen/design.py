"""Design schema of the haptic pen with parts: ``[parts]`` of a ``haptic-pen`` design.

The mechanism, workspace, actuators and optimize tables are those of
:mod:`cad.design.pantograph` (isotropy paper §4.2, Table 2); this module adds the
``[parts]`` table the pen's layout needs and is the ``design_module`` of the
``haptic-pen`` registry row (:mod:`cad.data.families`).

``[parts]`` keys (mm; every key optional):

* the link hardware of the twin pantograph (:class:`cad.design.pantograph.PantographParts`:
  ``tube_od_mm``, ``tube_id_mm``, ``tube_material``, ``clevis_*``, ``socket_depth_mm``,
  ``bearing``, ``pin_material``, ``motor`` (the four shoulder motors),
  ``motor_mount_thickness_mm`` (the waist bracket's motor plate), ``plate_material``,
  ``plate_thickness_mm`` (base plate), ``layer_gap_mm``), validated by
  :func:`cad.design.pantograph.parse_parts`;
* ``waist_motor`` (``"maxon-re40"``: "larger actuators are used at the waist joints",
  §4.2), ``pen_diameter_mm`` (10), ``pen_material`` (``"delrin"``),
  ``gimbal_ring_mm`` (inner diameter of the gimbal ring, 30), ``gimbal_material``
  (``"aluminium-7075"``).

The mouse-only keys (``crank_*``, ``knob_*``, ``post_diameter_mm``) are refused. Every number
is checked against the part-size bound of :mod:`cad.design.bounds` (``PART_MM``). No CAD
import.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

from cad.data.catalog import get_bearing, get_motor
from cad.data.materials import get_material
from cad.design import pantograph as _pg
from cad.design.bounds import PART_MM, check_number
from cad.design.fields import check_unknown, optional_table
from cad.errors import DesignError

#: PantographParts keys the pen has no part for (the mouse's crankshaft, knob and posts).
MOUSE_ONLY = ("crank_material", "crank_thickness_mm", "knob_material", "knob_height_mm",
              "post_diameter_mm")
#: Pen-only keys, their defaults and kinds.
PEN_KEYS: dict[str, Any] = {
    "waist_motor": "maxon-re40",
    "pen_diameter_mm": 10.0,
    "pen_material": "delrin",
    "gimbal_ring_mm": 30.0,
    "gimbal_material": "aluminium-7075",
}


@dataclass(frozen=True)
class PenParts:
    """Part parameters of the haptic pen (mm; catalog and material keys named).

    links : :class:`cad.design.pantograph.PantographParts` -- tubes, clevises, bearings,
        pins, shoulder motors, plates (the twin pantograph's hardware, §4.2: "motors,
        clevises, bearings, linkage material ... similar to those used in the previous
        design").
    waist_motor : key of :data:`cad.data.catalog.MOTORS` turning each arm's waist bracket.
    pen_diameter_mm, pen_material : the pen rod (l6 long between its gimbal centres).
    gimbal_ring_mm, gimbal_material : inner diameter and material of the two gimbal rings.
    """

    links: _pg.PantographParts
    waist_motor: str = PEN_KEYS["waist_motor"]
    pen_diameter_mm: float = PEN_KEYS["pen_diameter_mm"]
    pen_material: str = PEN_KEYS["pen_material"]
    gimbal_ring_mm: float = PEN_KEYS["gimbal_ring_mm"]
    gimbal_material: str = PEN_KEYS["gimbal_material"]

    def __getattr__(self, name: str):
        # the link hardware reads like the twin pantograph's parts (p.bearing, p.motor ...)
        if name.startswith("__") or name == "links":
            raise AttributeError(name)
        return getattr(self.links, name)


def parse_pen_parts(table: dict[str, Any], prefix: str = "parts") -> PenParts:
    """Validate the ``[parts]`` table of a haptic pen (empty: the defaults); DesignError
    naming the key otherwise."""
    allowed = [k for k in _pg.PantographParts.__dataclass_fields__ if k not in MOUSE_ONLY]
    for key in MOUSE_ONLY:
        if key in table:
            raise DesignError(f"{prefix}.{key}", "the haptic pen has no crankshaft, knob or posts")
    check_unknown(table, [*allowed, *PEN_KEYS], prefix)
    links = _pg.parse_parts({k: v for k, v in table.items() if k in allowed}, prefix)
    kw: dict[str, Any] = {}
    for key, default in PEN_KEYS.items():
        if key not in table:
            continue
        v = table[key]
        if isinstance(default, str):
            if not isinstance(v, str) or not v:
                raise DesignError(f"{prefix}.{key}", f"must be a non-empty string, got {v!r}")
            kw[key] = v
        else:
            kw[key] = check_number(f"{prefix}.{key}", v, PART_MM)
    p = PenParts(links, **kw)
    get_motor(p.waist_motor, f"{prefix}.waist_motor")
    get_material(p.pen_material, f"{prefix}.pen_material")
    get_material(p.gimbal_material, f"{prefix}.gimbal_material")
    b = get_bearing(links.bearing, f"{prefix}.bearing")
    # the ring holds the pen hub (bearings at its ends) inside, its pins pressed in
    if p.gimbal_ring_mm < 2 * b.D_mm + 4.0:
        raise DesignError(f"{prefix}.gimbal_ring_mm",
                          f"must hold the pen hub with two {links.bearing} bearings "
                          f"(>= 2 D + 4 = {2 * b.D_mm + 4.0:g} mm), got {p.gimbal_ring_mm!r}")
    if p.pen_diameter_mm > p.gimbal_ring_mm - 2.0:
        raise DesignError(f"{prefix}.pen_diameter_mm",
                          f"must pass inside the gimbal ring ({p.gimbal_ring_mm:g} mm), "
                          f"got {p.pen_diameter_mm!r}")
    return p


def parse(raw: dict[str, Any], source: str = "<design>"):
    """A validated haptic-pen design (:class:`cad.design.pantograph.PantographDesign`) whose
    ``parts`` is a :class:`PenParts`; every problem is a DesignError."""
    rest = {k: v for k, v in raw.items() if k != "parts"}
    design = _pg.parse(rest, source)
    if design.family != "haptic-pen":
        raise DesignError("mechanism.family", f"must be 'haptic-pen', got {design.family!r}")
    parts = parse_pen_parts(optional_table(raw, "parts", ""))
    return replace(design, parts=parts, raw=raw)


