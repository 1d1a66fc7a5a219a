"""The capstan transmission's made parts and the rope as solids (issue 35): the drum sector on
the link, the capstan on the motor shaft, a free run of rope. Part scripts only: parameters in,
an OCP solid out; where they sit is :mod:`cad.actuators.capstan_geometry`.

Frames (mm): drum sector -- its centre (the joint axis) at the origin, z 0..thickness, the arc
counter-clockwise from ``start_deg`` about +z; capstan -- the shaft axis z, z 0..length, the
set screw's radial hole along +x at ``set_screw_z_mm``; rope run -- world coordinates (the run
is placed by its end points).
"""

from __future__ import annotations

import math

from cad.data.catalog import tap_drill_mm


def drum_sector_shape(r_rim_mm: float, r_bore_mm: float, start_deg: float, span_deg: float,
                      thickness_mm: float, radial_holes=()):
    """Annular sector plate: radii ``r_bore_mm``..``r_rim_mm``, arc ``span_deg`` from
    ``start_deg``, z 0..``thickness_mm``. Volume (span / 2)(r_rim^2 - r_bore^2) t
    (:func:`cad.actuators.capstan_geometry.sector_mass_kg`) without ``radial_holes``:
    ``((angle_deg, diameter_mm, depth_mm), ...)`` drilled from the rim towards the centre at
    mid-thickness (the rope anchors' tapped holes)."""
    from build123d import Align, Cylinder, Line, Pos, Rot, ThreePointArc, extrude, make_face

    a0, a1 = math.radians(start_deg), math.radians(start_deg + span_deg)

    def p(r, a):
        return (r * math.cos(a), r * math.sin(a))

    am = 0.5 * (a0 + a1)
    edges = [Line(p(r_bore_mm, a0), p(r_rim_mm, a0)),
             ThreePointArc(p(r_rim_mm, a0), p(r_rim_mm, am), p(r_rim_mm, a1)),
             Line(p(r_rim_mm, a1), p(r_bore_mm, a1)),
             ThreePointArc(p(r_bore_mm, a1), p(r_bore_mm, am), p(r_bore_mm, a0))]
    part = extrude(make_face(edges), thickness_mm)
    a = (Align.CENTER, Align.CENTER, Align.MIN)
    tools = [Rot(0, 0, ang) * Pos(r_rim_mm - depth, 0, thickness_mm / 2) * Rot(0, 90, 0)
             * Cylinder(dia / 2, depth + 1.0, align=a) for ang, dia, depth in radial_holes]
    if tools:
        part = part.cut(*tools)
    return part.solids()[0].wrapped


def capstan_shape(r_rim_mm: float, bore_diameter_mm: float, length_mm: float,
                  set_screw_z_mm: float, set_screw: str = "M3-0.5"):
    """Capstan on the motor shaft: a tube ``bore_diameter_mm``..2 ``r_rim_mm``, z 0..``length_mm``,
    with the radial tap-drill hole of ``set_screw`` (ISO 4026) along +x through one wall at
    ``set_screw_z_mm``."""
    from build123d import Align, Cylinder, Pos, Rot

    a = (Align.CENTER, Align.CENTER, Align.MIN)
    body = Cylinder(r_rim_mm, length_mm, align=a)
    bore = Cylinder(bore_diameter_mm / 2, length_mm, align=a)
    hole = (Pos(0, 0, set_screw_z_mm) * Rot(0, 90, 0)
            * Cylinder(tap_drill_mm(set_screw) / 2, r_rim_mm + 1.0, align=a))
    return body.cut(bore, hole).solids()[0].wrapped


def rope_run_shape(p0_mm, p1_mm, rope_diameter_mm: float):
    """A free run of rope: a cylinder of ``rope_diameter_mm`` from ``p0_mm`` to ``p1_mm``
    ((3,), mm, world)."""
    from build123d import Align, Cylinder, Location, Plane, Vector

    p0, p1 = Vector(*p0_mm), Vector(*p1_mm)
    d = p1 - p0
    cyl = Cylinder(rope_diameter_mm / 2, d.length, align=(Align.CENTER, Align.CENTER, Align.MIN))
    return cyl.moved(Location(Plane(origin=p0, z_dir=d.normalized()))).solids()[0].wrapped
