"""The dimensioned features of a part's solid: cylindrical faces grouped into holes and
bosses, with their ISO 286 fit or thread, measured from one datum.

Frame: the part's own frame (mm). Datum: the corner of the part's exact bounding box with
the smallest x, y and z (datum planes A: x = x_min, B: y = y_min, C: z = z_min); every
position on a sheet is measured from it. OCP is imported inside the functions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from cad.tolerances import AXIS_SLACK, SAME_FEATURE_MM


@dataclass(frozen=True)
class Cylinder:
    """A group of coaxial cylindrical faces of one diameter: a hole (``internal``) or a boss.

    axis : ``"x"``, ``"y"`` or ``"z"`` (the part axis it is parallel to), ``"n"`` for an
        oblique axis (the PowerMouse's diagonal actuators).
    u_mm, v_mm : centre in the two other axes (``x y`` for z, ``y z`` for x, ``x z`` for y),
        from the datum (0 for an oblique axis).
    d_mm : diameter. lo_mm, hi_mm : extent along the axis, from the datum (an oblique axis:
        from ``point_mm`` along ``direction``).
    direction, point_mm : an oblique axis's unit direction (first non-zero component
        positive) and its point nearest the datum (mm); None for an aligned one.
    span_deg : angle the faces cover (360 for a full hole or boss, less for a rounded end).
    """

    axis: str
    u_mm: float
    v_mm: float
    d_mm: float
    lo_mm: float
    hi_mm: float
    internal: bool
    span_deg: float
    direction: tuple[float, float, float] | None = None
    point_mm: tuple[float, float, float] | None = None

    @property
    def full(self) -> bool:
        return self.span_deg > 359.999

    @property
    def plane(self) -> tuple[str, str]:
        """Names of the two centre coordinates."""
        return {"z": ("x", "y"), "x": ("y", "z"), "y": ("x", "z"), "n": ("", "")}[self.axis]


def bbox_mm(shape) -> tuple[float, float, float, float, float, float]:
    """Exact (optimal) bounding box ``(x0, y0, z0, x1, y1, z1)`` of a ``TopoDS_Shape`` (mm)."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    box = Bnd_Box()
    BRepBndLib.AddOptimal_s(shape, box, False)
    return box.Get()


def _face_cylinder(face, datum):
    """(axis, where, d, lo, hi, internal, span_deg) of a cylindrical face: ``where`` = the
    centre (u, v) of an aligned axis, or direction + nearest point of an oblique one."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.TopAbs import TopAbs_REVERSED

    srf = BRepAdaptor_Surface(face)
    cyl = srf.Cylinder()
    ax = cyl.Axis()
    dr, loc = ax.Direction(), ax.Location()
    comp = [dr.X(), dr.Y(), dr.Z()]
    p = [loc.X() - datum[0], loc.Y() - datum[1], loc.Z() - datum[2]]
    k = max(range(3), key=lambda i: abs(comp[i]))
    w0, w1 = srf.FirstVParameter(), srf.LastVParameter()
    span = math.degrees(srf.LastUParameter() - srf.FirstUParameter())
    # the surface normal points away from the axis for a right-handed (direct) frame; a
    # reversed face or a left-handed frame turns it towards the axis: material outside, a hole
    internal = (face.Orientation() == TopAbs_REVERSED) == cyl.Position().Direct()
    d = 2.0 * cyl.Radius()
    if abs(abs(comp[k]) - 1.0) <= AXIS_SLACK:
        s = math.copysign(1.0, comp[k])
        lo, hi = sorted((p[k] + s * w0, p[k] + s * w1))
        i, j = [q for q in range(3) if q != k]
        return "xyz"[k], (p[i], p[j]), d, lo, hi, internal, span
    first = next(c for c in comp if abs(c) > AXIS_SLACK)
    n = [c * math.copysign(1.0, first) for c in comp]
    t = sum(a * b for a, b in zip(p, n, strict=True))
    foot = [a - t * b for a, b in zip(p, n, strict=True)]
    sgn = math.copysign(1.0, first)
    lo, hi = sorted((t + sgn * w0, t + sgn * w1))
    return "n", (*n, *foot), d, lo, hi, internal, span


def cylinders(shape) -> list[Cylinder]:
    """Every cylindrical face of ``shape`` (a ``TopoDS_Shape``, mm), grouped by axis, centre, diameter and side (hole or boss), measured from the datum
    (module docstring); sorted by axis, then centre."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAbs import GeomAbs_Cylinder
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    datum = bbox_mm(shape)[:3]
    groups: dict = {}
    exp = TopExp_Explorer(shape, TopAbs_FACE)
    while exp.More():
        face = TopoDS.Face_s(exp.Current())
        exp.Next()
        if BRepAdaptor_Surface(face).GetType() != GeomAbs_Cylinder:
            continue
        axis, where, d, lo, hi, internal, span = _face_cylinder(face, datum)
        key = _group_key(groups, axis, where, d, internal)
        # the faces of one feature (a hole split by the seam or by a cross hole) add up their
        # angles: 360 deg or more is a full hole or boss (a diameter), less a radius
        g = groups.get(key, (lo, hi, 0.0))
        groups[key] = (min(g[0], lo), max(g[1], hi), g[2] + span)
    out = [_make(a, w, d, i, lo, hi, span) for (a, w, d, i), (lo, hi, span) in groups.items()]
    return sorted(out, key=lambda c: (c.axis, round(c.u_mm, 3), round(c.v_mm, 3),
                                      c.point_mm or (), c.d_mm, c.lo_mm))


def _make(axis, where, d, internal, lo, hi, span) -> Cylinder:
    if axis == "n":
        return Cylinder("n", 0.0, 0.0, d, lo, hi, internal, min(span, 360.0),
                        tuple(where[:3]), tuple(where[3:]))
    return Cylinder(axis, where[0], where[1], d, lo, hi, internal, min(span, 360.0))


def _group_key(groups, axis, where, d, internal):
    """The existing key of ``groups`` this face belongs to, else a new one."""
    for key in groups:
        a, w0, d0, i0 = key
        if (a == axis and i0 == internal and abs(d - d0) < SAME_FEATURE_MM
                and all(abs(p - q) < SAME_FEATURE_MM for p, q in zip(where, w0, strict=True))):
            return key
    return (axis, tuple(where), d, internal)
