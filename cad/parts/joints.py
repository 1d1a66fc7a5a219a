"""Joint hardware: ball bearings, ISO 7379 shoulder screws, nuts, washers, cap screws, spacers.

From bd_warehouse 0.4.0 where it has them:

* ``SingleRowDeepGrooveBallBearing`` (races and balls) -- fabrication fidelity; at
  ``inertia`` / ``preview`` fidelity a plain ring d..D x B stands in (the mass is the
  catalog mass in every case, so nothing is lost);
* ``ShoulderScrew`` (ISO 7379), ``HexNut`` (ISO 4032), ``PlainWasher`` (ISO 7089),
  ``SocketHeadCapScrew`` (ISO 4762), all with ``simple=True`` (no modelled thread).

Chosen otherwise: the two spacers on the pin are turned tubes built here, because
bd_warehouse's washers are too wide: an ISO 7089 M8 washer (16 mm) would rub the
bearing's outer ring (shoulder D1 = 13.5 mm for the 618/8); the spacers' outside
diameter lies between the bearing's shaft abutment da and inner-ring shoulder d1.

Interference envelopes (:func:`screw_envelope`, :func:`ring_shape`): plain cylinders
around the fasteners and nuts (across-corners diameter), solids of revolution about the
joint axis, slightly larger than the real parts (conservative for clearance).

Frames (mm, axis z): bearing z 0..B; screws with the under-head face at z = 0, head up,
shank down (-z); nut and washer z 0..height; spacer z 0..height. Shapes are cached per
parameter set in this process and on disk (:mod:`cad.parts.part_cache`; bd_warehouse
parts keyed by the library call and its version, :mod:`cad.parts.shape_cache`).
"""

from __future__ import annotations

from cad.data import catalog
from cad.parts import PartKind
from cad.parts.part_cache import part_cached


def _topo(obj):
    return obj.wrapped


def bearing_shape(size: str, detailed: bool = True):
    """Ball bearing ``size`` (bd_warehouse SKT), z 0..B. ``detailed=False``: plain ring."""
    b = catalog.get_bearing(size)
    if detailed:
        return _bd_bearing(size)
    return ring_shape(b.d_mm / 2.0, b.D_mm / 2.0, b.B_mm)


@part_cached(disk_key=lambda size: f"SingleRowDeepGrooveBallBearing({size!r})")
def _bd_bearing(size: str):
    from bd_warehouse.bearing import SingleRowDeepGrooveBallBearing

    return _topo(SingleRowDeepGrooveBallBearing(size))


def bearing_rings(size: str):
    """(inner ring, outer ring) envelopes of a bearing for the interference sweep.

    Inner ring d..d1 moves with the pin's link, outer ring D1..D with the seat's link;
    the balls (between d1 and D1) never touch anything outside the bearing.
    """
    b = catalog.get_bearing(size)
    return ring_shape(b.d_mm / 2.0, b.d1_mm / 2.0, b.B_mm), ring_shape(
        b.D1_mm / 2.0, b.D_mm / 2.0, b.B_mm
    )


@part_cached
def ring_shape(r_in_mm: float, r_out_mm: float, height_mm: float):
    """Tube r_in..r_out, z 0..height (turned spacer, ring envelope); a full cylinder when
    ``r_in_mm`` is 0. Made as one revolution of its rectangular section (no boolean)."""
    if r_in_mm > 0:
        return _revolved([(r_in_mm, 0.0), (r_out_mm, 0.0), (r_out_mm, height_mm), (r_in_mm, height_mm)])
    from build123d import Align, Cylinder

    return Cylinder(r_out_mm, height_mm, align=(Align.CENTER, Align.CENTER, Align.MIN)).solids()[0].wrapped


def _revolved(section_rz):
    """Solid of revolution about z of the closed polygon ``[(r, z), ...]`` (mm): one
    ``BRepPrimAPI_MakeRevol`` through build123d, ~10x cheaper than the equivalent booleans
    of cylinders and cones (same faces: planes, cylinders, cones)."""
    from build123d import Axis, Plane, Polygon, revolve

    return revolve(Plane.XZ * Polygon(*section_rz, align=None), Axis.Z).solids()[0].wrapped


#: Edge break of the turned spacers' bore, both ends (mm): clears the ISO 7379 screw's
#: under-head fillet (bd_warehouse models it r ~ 0.1 mm; a sharp 8.0 bore shares 0.014 mm^3).
SPACER_BORE_CHAMFER_MM = 0.3


@part_cached
def spacer_shape(r_in_mm: float, r_out_mm: float, height_mm: float):
    """Turned spacer: tube r_in..r_out, z 0..height, bore chamfered
    :data:`SPACER_BORE_CHAMFER_MM` x 45 deg at both ends (one revolution of its section)."""
    c = min(SPACER_BORE_CHAMFER_MM, height_mm / 3.0, (r_out_mm - r_in_mm) / 3.0)
    return _revolved([(r_in_mm + c, 0.0), (r_out_mm, 0.0), (r_out_mm, height_mm),
                      (r_in_mm + c, height_mm), (r_in_mm, height_mm - c), (r_in_mm, c)])


def shoulder_screw_shape(size: str, length_mm: float):
    """ISO 7379 shoulder screw: under-head face at z = 0, head up, shoulder to z = -length.

    A plain pin ``dowel-<d>`` (:func:`cad.data.catalog.dowel_as_shoulder_screw`): the pin
    from z = -(length + b) to z = k (its upper DIN 471 ring, d..d4 x s on z = 0, is placed as
    its own part: :func:`dowel_pin_shape`).
    """
    if catalog.is_dowel(size):
        return dowel_pin_shape(size, float(length_mm))
    return _bd_shoulder_screw(size, float(length_mm))


@part_cached(disk_key=lambda size, length_mm: f"ShoulderScrew({size!r}, {length_mm!r}, simple=True)")
def _bd_shoulder_screw(size: str, length_mm: float):
    from bd_warehouse.fastener import ShoulderScrew

    return _topo(ShoulderScrew(size, length_mm, simple=True))


def cap_screw_shape(size: str, length_mm: float):
    """ISO 4762 socket head cap screw: under-head face at z = 0, shank to z = -length."""
    return _bd_cap_screw(size, float(length_mm))


@part_cached(disk_key=lambda size, length_mm: f"SocketHeadCapScrew({size!r}, {length_mm!r}, simple=True)")
def _bd_cap_screw(size: str, length_mm: float):
    from bd_warehouse.fastener import SocketHeadCapScrew

    return _topo(SocketHeadCapScrew(size, length_mm, simple=True))


@part_cached
def screw_envelope(
    head_d_mm: float,
    head_h_mm: float,
    shank_d_mm: float,
    shank_l_mm: float,
    tip_d_mm: float = 0.0,
    tip_l_mm: float = 0.0,
):
    """Solid of revolution enclosing a screw for the interference sweep: head cylinder
    (z 0..head_h), shank (z -shank_l..0), optional thinner tip below the shank."""
    from build123d import Align, Cylinder, Pos

    a = (Align.CENTER, Align.CENTER, Align.MIN)
    s = Cylinder(head_d_mm / 2, head_h_mm, align=a) + Pos(0, 0, -shank_l_mm) * Cylinder(
        shank_d_mm / 2, shank_l_mm, align=a
    )
    if tip_l_mm > 0:
        s = s + Pos(0, 0, -shank_l_mm - tip_l_mm) * Cylinder(tip_d_mm / 2, tip_l_mm, align=a)
    return s.solids()[0].wrapped


def nut_shape(size: str):
    """ISO 4032 hexagon nut, z 0..m (a plain pin's lower DIN 471 ring, d..d4 x s)."""
    if catalog.is_dowel(size):
        ring = catalog.get_retaining_ring(catalog.dowel_diameter_mm(size))
        return ring_shape(ring.d1_mm / 2.0, ring.d4_mm / 2.0, ring.s_mm)
    return _bd_nut(size)


@part_cached(disk_key=lambda size: f"HexNut({size!r}, 'iso4032', simple=True)")
def _bd_nut(size: str):
    from bd_warehouse.fastener import HexNut

    return _topo(HexNut(size, "iso4032", simple=True))


def washer_shape(size: str):
    """ISO 7089 plain washer, z 0..h (a plain pin's washer: its metric size)."""
    if catalog.is_dowel(size):
        size = catalog.dowel_metric(size)
    return _bd_washer(size.split("-")[0])


@part_cached(disk_key=lambda metric: f"PlainWasher({metric!r}, 'iso7089')")
def _bd_washer(metric: str):
    from bd_warehouse.fastener import PlainWasher

    return _topo(PlainWasher(metric, "iso7089"))


@part_cached
def dowel_pin_shape(size: str, shoulder_length_mm: float):
    """Plain pin in the shoulder-screw frame (see :func:`shoulder_screw_shape`): the ground
    pin alone, z = -(length + b) .. k. Its upper DIN 471 ring (d..d4 x s on z = 0) is a part
    of its own in the assembly (:func:`nut_shape`, the same ring as the lower one), not fused
    into the pin: every bought part is its own instance."""
    from build123d import Align, Cylinder, Pos

    s = catalog.get_shoulder_screw(size)
    a = (Align.CENTER, Align.CENTER, Align.MIN)
    total = s.k_mm + shoulder_length_mm + s.b_mm
    pin = Pos(0, 0, -(shoulder_length_mm + s.b_mm)) * Cylinder(s.ds_mm / 2, total, align=a)
    return pin.solids()[0].wrapped


def cap_screw_kind(size: str, length_mm: float, field: str = "parts", note: str = ""):
    """The :class:`cad.parts.PartKind` of a bought ISO 4762 socket head cap screw
    ``size`` x ``length_mm`` (solid, material, BOM text, collision envelope); ``field`` is
    the design field an unknown size is blamed on (:func:`catalog.get_cap_screw`), ``note``
    is added to the BOM description in parentheses."""
    cs = catalog.get_cap_screw(size, field)
    length = f"{length_mm:.2f}".rstrip("0").rstrip(".")
    return PartKind(
        name=f"cap_screw_{size}x{length}",
        shape=cap_screw_shape(size, length_mm),
        material=catalog.FASTENER_MATERIAL,
        made=False,
        description=f"socket head cap screw ISO 4762 {size} x {length}"
        + (f" ({note})" if note else ""),
        process="bought",
        revolution=True,
        collision=(("self", screw_envelope(cs.dk_mm, cs.k_mm, cs.d_mm, length_mm)),),
    )
