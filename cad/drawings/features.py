"""The dimensioned features of a part's solid: cylindrical faces grouped into holes and
bosses, with their ISO 286 fit or thread, measured from one datum.

Frame: the part's own frame (mm). Datum: the corner of the part's exact bounding box with
the smallest x, y and z (datum planes A: x = x_min, B: y = y_min, C: z = z_min); every
position on a sheet is measured from it. OCP is imported inside the functions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: Two faces belong to one feature when axis, centre and diameter agree this closely (mm):
#: faces of one boolean share the same circle up to round-off.
SAME_FEATURE_MM = 1e-6
#: A face is aligned with a part axis when its direction is within this of it (cosine slack).
AXIS_SLACK = 1e-9


@dataclass(frozen=True)
class Cylinder:
    """A group of coaxial cylindrical faces of one diameter: a hole (``internal``) or a boss.

    axis : ``"x"``, ``"y"`` or ``"z"`` (the part axis it is parallel to).
    u_mm, v_mm : centre in the two other axes (``x y`` for z, ``y z`` for x, ``x z`` for y),
        from the datum.
    d_mm : diameter. lo_mm, hi_mm : extent along the axis, from the datum.
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

    @property
    def full(self) -> bool:
        return self.span_deg > 359.999

    @property
    def plane(self) -> tuple[str, str]:
        """Names of the two centre coordinates."""
        return {"z": ("x", "y"), "x": ("y", "z"), "y": ("x", "z")}[self.axis]


def bbox_mm(shape) -> tuple[float, float, float, float, float, float]:
    """Exact (optimal) bounding box ``(x0, y0, z0, x1, y1, z1)`` of a ``TopoDS_Shape`` (mm)."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    box = Bnd_Box()
    BRepBndLib.AddOptimal_s(shape, box, False)
    return box.Get()


def _face_cylinder(face, datum):
    """(axis, u, v, d, lo, hi, internal, span_deg) of a cylindrical face, or None when its
    axis is oblique to the part axes."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.TopAbs import TopAbs_REVERSED

    srf = BRepAdaptor_Surface(face)
    cyl = srf.Cylinder()
    ax = cyl.Axis()
    dr, loc = ax.Direction(), ax.Location()
    comp = (dr.X(), dr.Y(), dr.Z())
    k = max(range(3), key=lambda i: abs(comp[i]))
    if abs(abs(comp[k]) - 1.0) > AXIS_SLACK:
        return None
    p = [loc.X() - datum[0], loc.Y() - datum[1], loc.Z() - datum[2]]
    w0, w1 = srf.FirstVParameter(), srf.LastVParameter()
    s = math.copysign(1.0, comp[k])
    ends = sorted((p[k] + s * w0, p[k] + s * w1))
    others = [i for i in range(3) if i != k]
    span = math.degrees(srf.LastUParameter() - srf.FirstUParameter())
    # the surface normal points away from the axis for a right-handed (direct) frame; a
    # reversed face or a left-handed frame turns it towards the axis: material outside, a hole
    internal = (face.Orientation() == TopAbs_REVERSED) == cyl.Position().Direct()
    return ("xyz"[k], p[others[0]], p[others[1]], 2.0 * cyl.Radius(), *ends, internal, span)


def cylinders(shape) -> list[Cylinder]:
    """Every cylindrical face of ``shape`` (a ``TopoDS_Shape``, mm) parallel to a part axis,
    grouped by axis, centre, diameter and side (hole or boss), measured from the datum
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
        got = _face_cylinder(face, datum)
        if got is None:
            continue
        axis, u, v, d, lo, hi, internal, span = got
        key = _group_key(groups, axis, u, v, d, internal)
        if key in groups:
            g = groups[key]
            groups[key] = (min(g[0], lo), max(g[1], hi), g[2] + span if (lo, hi) == g[3] else
                           max(g[2], span), (lo, hi))
        else:
            groups[key] = (lo, hi, span, (lo, hi))
    out = [Cylinder(a, u, v, d, lo, hi, i, min(span, 360.0))
           for (a, u, v, d, i), (lo, hi, span, _) in groups.items()]
    return sorted(out, key=lambda c: (c.axis, round(c.u_mm, 3), round(c.v_mm, 3), c.d_mm,
                                      c.lo_mm))


def _group_key(groups, axis, u, v, d, internal):
    """The existing key of ``groups`` this face belongs to, else a new one."""
    for key in groups:
        a, u0, v0, d0, i0 = key
        if (a == axis and i0 == internal and abs(u - u0) < SAME_FEATURE_MM
                and abs(v - v0) < SAME_FEATURE_MM and abs(d - d0) < SAME_FEATURE_MM):
            return key
    return (axis, u, v, d, internal)
