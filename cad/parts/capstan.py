"""The capstan transmission's made parts and the rope as solids (issue 35): the drum sector on
the link, the capstan on the motor shaft, a free run of rope. Part scripts only: parameters in,
an OCP solid out; where they sit is :mod:`cad.actuators.capstan_geometry`.

Frames (mm): drum sector -- its centre (the joint axis) at the origin, z 0..thickness, the arc
counter-clockwise from ``start_deg`` about +z; capstan -- the shaft axis z, z 0..length, the
set screw's radial hole along +x at ``set_screw_z_mm``; rope run -- world coordinates (the run
is placed by its end points); A1 bearing block -- the axle z, z 0..height (its top face under
the base plate), the square flange at the top; axle -- z 0..length.
"""

from __future__ import annotations

import math

from cad.actuators import capstan_geometry as cg
from cad.data.catalog import tap_drill_mm
from cad.parts.part_cache import part_cached


@part_cached
def drum_sector_shape(r_rim_mm: float, r_bore_mm: float, start_deg: float, span_deg: float,
                      thickness_mm: float, radial_holes=(), rope_diameter_mm: float | None = None,
                      groove_arc_deg: tuple[float, float] | None = None):
    """Annular sector plate: radii ``r_bore_mm``..``r_rim_mm``, arc ``span_deg`` from
    ``start_deg``, z 0..``thickness_mm``. Volume (span / 2)(r_rim^2 - r_bore^2) t
    (:func:`cad.actuators.capstan_geometry.sector_mass_kg`) without ``radial_holes``:
    ``((angle_deg, diameter_mm, depth_mm), ...)`` drilled from the rim towards the centre at
    mid-thickness (the rope anchors' tapped holes, ``depth_mm`` below ``r_rim_mm``).

    With ``rope_diameter_mm`` d the rim carries the rope's groove at mid-thickness
    (:mod:`cad.actuators.capstan_geometry`): ``r_rim_mm`` is the groove's bottom, the rim
    (the crests) stands :func:`~cad.actuators.capstan_geometry.groove_depth_mm` above it, the
    groove's section is a circle of radius d / 2 centred on the pitch radius ``r_rim_mm + d / 2``
    revolved over ``groove_arc_deg`` ``(start, span)`` (default: the whole sector), flat-ended."""
    from build123d import (
        Align,
        Axis,
        Circle,
        Cylinder,
        Line,
        Plane,
        Pos,
        Rot,
        ThreePointArc,
        extrude,
        make_face,
        revolve,
    )


    h = 0.0 if rope_diameter_mm is None else cg.groove_depth_mm(rope_diameter_mm)
    r_out = r_rim_mm + h
    a0, a1 = math.radians(start_deg), math.radians(start_deg + span_deg)

    def p(r, a):
        return (r * math.cos(a), r * math.sin(a))

    am = 0.5 * (a0 + a1)
    edges = [Line(p(r_bore_mm, a0), p(r_out, a0)),
             ThreePointArc(p(r_out, a0), p(r_out, am), p(r_out, a1)),
             Line(p(r_out, a1), p(r_bore_mm, a1)),
             ThreePointArc(p(r_bore_mm, a1), p(r_bore_mm, am), p(r_bore_mm, a0))]
    part = extrude(make_face(edges), thickness_mm)
    a = (Align.CENTER, Align.CENTER, Align.MIN)
    tools = [Rot(0, 0, ang) * Pos(r_rim_mm - depth, 0, thickness_mm / 2) * Rot(0, 90, 0)
             * Cylinder(dia / 2, depth + 1.0 + h, align=a) for ang, dia, depth in radial_holes]
    if rope_diameter_mm is not None:
        d = float(rope_diameter_mm)
        g0, gs = groove_arc_deg if groove_arc_deg is not None else (start_deg, span_deg)
        section = Plane.XZ * Pos(r_rim_mm + d / 2, thickness_mm / 2) * Circle(d / 2)
        tools.append(Rot(0, 0, g0) * revolve(section, Axis.Z, gs))
    if tools:
        part = part.cut(*tools)
    return part.solids()[0].wrapped


@part_cached
def capstan_shape(r_rim_mm: float, bore_diameter_mm: float, length_mm: float,
                  set_screw_z_mm: float, set_screw: str = "M3-0.5",
                  rope_diameter_mm: float | None = None, wraps: float | None = None):
    """Capstan on the motor shaft: a tube ``bore_diameter_mm``..2 ``r_rim_mm``, z 0..``length_mm``,
    with the radial tap-drill hole of ``set_screw`` (ISO 4026) along +x through one wall at
    ``set_screw_z_mm``.

    With ``rope_diameter_mm`` d and ``wraps`` n: the helical rope groove of the turns
    (:mod:`cad.actuators.capstan_geometry`): ``r_rim_mm`` is its bottom, the tube's outside the
    crests :func:`~cad.actuators.capstan_geometry.groove_depth_mm` above it; the groove's
    section, a circle of radius d / 2 centred on the pitch radius ``r_rim_mm + d / 2``, swept
    (Frenet frame) along a right-handed helix of axial pitch
    :data:`~cad.actuators.capstan_geometry.GROOVE_PITCH_D` d for n turns ending half a rope
    below the top face (the section's centre from z = ``length_mm`` - d / 2 - n p to
    ``length_mm`` - d / 2: the whole groove inside the capstan, above the set-screw hole)."""
    from build123d import Align, Circle, Cylinder, Helix, Plane, Pos, Rot, sweep


    grooved = rope_diameter_mm is not None and wraps is not None
    h = cg.groove_depth_mm(rope_diameter_mm) if grooved else 0.0
    a = (Align.CENTER, Align.CENTER, Align.MIN)
    body = Cylinder(r_rim_mm + h, length_mm, align=a)
    bore = Cylinder(bore_diameter_mm / 2, length_mm, align=a)
    hole = (Pos(0, 0, set_screw_z_mm) * Rot(0, 90, 0)
            * Cylinder(tap_drill_mm(set_screw) / 2, r_rim_mm + h + 1.0, align=a))
    tools = [bore, hole]
    if grooved:
        d, p = float(rope_diameter_mm), cg.GROOVE_PITCH_D * float(rope_diameter_mm)
        z0 = length_mm - d / 2 - p * wraps
        helix = Helix(p, p * wraps, r_rim_mm + d / 2, center=(0, 0, z0))
        section = Plane(origin=helix @ 0, z_dir=helix % 0) * Circle(d / 2)
        tools.append(sweep(section, path=helix, is_frenet=True))
    return body.cut(*tools).solids()[0].wrapped


@part_cached
def rope_run_shape(p0_mm, p1_mm, rope_diameter_mm: float):
    """A free run of rope: a cylinder of ``rope_diameter_mm`` from ``p0_mm`` to ``p1_mm``
    ((3,), mm, world)."""
    from build123d import Align, Cylinder, Location, Plane, Vector

    p0, p1 = Vector(*p0_mm), Vector(*p1_mm)
    d = p1 - p0
    cyl = Cylinder(rope_diameter_mm / 2, d.length, align=(Align.CENTER, Align.CENTER, Align.MIN))
    return cyl.moved(Location(Plane(origin=p0, z_dir=d.normalized()))).solids()[0].wrapped


@part_cached
def bearing_block_shape(side_mm: float, flange_mm: float, corner_xy, hole_d_mm: float,
                        seat_d_mm: float, seat_depth_mm: float, lip_mm: float, lip_bore_mm: float,
                        wall_mm: float, extra_holes=()):
    """Bearing block of a crank axle: a square flange ``side_mm`` x ``flange_mm`` at the top
    (z from height - flange to height, height = 2 seats + lip) with clearance holes
    ``hole_d_mm`` at ``corner_xy`` and ``extra_holes`` ``[(x, y, diameter)]``, a boss of
    diameter seat + 2 ``wall_mm`` down to z = 0; a bearing seat ``seat_d_mm`` x
    ``seat_depth_mm`` from each end, a lip of ``lip_mm`` between them with bore
    ``lip_bore_mm`` (the bearings' housing abutment diameter Da)."""
    from build123d import Align, Box, Cylinder, Pos

    a = (Align.CENTER, Align.CENTER, Align.MIN)
    h = 2 * seat_depth_mm + lip_mm
    fl = min(flange_mm, h)
    s = Pos(0, 0, h - fl) * Box(side_mm, side_mm, fl, align=a)
    s = s + Cylinder(seat_d_mm / 2 + wall_mm, h, align=a)
    s = s - Cylinder(lip_bore_mm / 2, h, align=a)
    for z in (0.0, h - seat_depth_mm):
        s = s - Pos(0, 0, z) * Cylinder(seat_d_mm / 2, seat_depth_mm, align=a)
    for x, y, d in [(x, y, hole_d_mm) for x, y in corner_xy] + list(extra_holes):
        s = s - Pos(x, y, h - fl) * Cylinder(d / 2, fl, align=a)
    return s.solids()[0].wrapped


@part_cached
def axle_shape(diameter_mm: float, length_mm: float):
    """Plain round axle, z 0..``length_mm``."""
    from build123d import Align, Cylinder

    return Cylinder(diameter_mm / 2, length_mm, align=(Align.CENTER, Align.CENTER, Align.MIN)).wrapped
