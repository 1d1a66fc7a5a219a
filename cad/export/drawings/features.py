"""The dimensioned features of a part's solid: cylindrical faces grouped into holes and
bosses, with their ISO 286 fit or thread, measured from one datum.

Frame: the part's own frame (mm). Datum: the corner of the part's exact bounding box with
the smallest x, y and z (datum planes A: x = x_min, B: y = y_min, C: z = z_min); every
position on a sheet is measured from it. OCP is imported inside the functions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from cad.tolerances import AXIS_SLACK, SAME_FEATURE_MM, SAME_POCKET_MM


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


@dataclass(frozen=True)
class Pocket:
    """A pocket or through slot: side walls (planes parallel to ``axis`` and internal
    cylinders about it) joined edge to edge around an opening, measured in its own frame.

    axis : the part axis the walls are parallel to (``"x"``, ``"y"``, ``"z"``).
    u_mm, v_mm : centre of its outline in the two other axes, from the datum.
    length_mm, width_mm : outline along and across its longest wall (``angle_deg`` from the
        first other axis, counter-clockwise about ``axis``).
    depth_mm : wall height along ``axis``; lo_mm, hi_mm : its extent from the datum.
    corner_r_mm : smallest wall radius (a slot's round ends: width / 2), None when sharp.
    through : no floor (it opens on both sides).
    """

    axis: str
    u_mm: float
    v_mm: float
    length_mm: float
    width_mm: float
    depth_mm: float
    lo_mm: float
    hi_mm: float
    angle_deg: float
    corner_r_mm: float | None
    through: bool


@dataclass(frozen=True)
class Chamfer:
    """A conical face: the chamfer of a round edge (a bore's or a boss's).

    axis : the part axis of the cone; u_mm, v_mm : its centre from the datum; lo_mm,
    hi_mm : its extent along the axis from the datum. axial_mm, radial_mm : the chamfer's
    legs; angle_deg : the cone's half angle (45 for C-chamfers); internal : on a bore.
    """

    axis: str
    u_mm: float
    v_mm: float
    lo_mm: float
    hi_mm: float
    axial_mm: float
    radial_mm: float
    angle_deg: float
    internal: bool


def _face_list(shape) -> list:
    """The faces of ``shape`` in explorer order."""
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    out = []
    exp = TopExp_Explorer(shape, TopAbs_FACE)
    while exp.More():
        out.append(TopoDS.Face_s(exp.Current()))
        exp.Next()
    return out


def _neighbours(shape, faces) -> list[set[int]]:
    """For each face (index in ``faces``), the indices of the faces sharing an edge with it."""
    from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
    from OCP.TopExp import TopExp
    from OCP.TopTools import TopTools_IndexedDataMapOfShapeListOfShape

    emap = TopTools_IndexedDataMapOfShapeListOfShape()
    TopExp.MapShapesAndAncestors_s(shape, TopAbs_EDGE, TopAbs_FACE, emap)
    index = {f.__hash__(): [] for f in faces}
    for k, f in enumerate(faces):
        index[f.__hash__()].append(k)
    out = [set() for _ in faces]
    for e in range(1, emap.Extent() + 1):
        ks = [k for f in emap.FindFromIndex(e) for k in index.get(f.__hash__(), [])
              if faces[k].IsSame(f)]
        for a in ks:
            out[a] |= {b for b in ks if b != a}
    return out


def _outward_normal(face) -> tuple[float, float, float]:
    """Unit normal of a planar face pointing out of the material (face orientation kept)."""
    from OCP.BRepGProp import BRepGProp_Face
    from OCP.gp import gp_Pnt, gp_Vec

    g = BRepGProp_Face(face)
    u0, u1, v0, v1 = g.Bounds()
    p, n = gp_Pnt(), gp_Vec()
    g.Normal(0.5 * (u0 + u1), 0.5 * (v0 + v1), p, n)
    m = n.Magnitude()
    return n.X() / m, n.Y() / m, n.Z() / m


def _centre(face) -> tuple[float, float, float]:
    """Centre of a face's exact bounding box (mm)."""
    b = bbox_mm(face)
    return 0.5 * (b[0] + b[3]), 0.5 * (b[1] + b[4]), 0.5 * (b[2] + b[5])


def _side_faces(faces, k_axis: int) -> dict[int, tuple]:
    """Faces that can wall a pocket along part axis ``k_axis``: ``{index: ("plane", outward
    normal) | ("cyl", radius mm, internal)}`` -- planes parallel to the axis and cylinders
    about a parallel axis."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAbs import GeomAbs_Cylinder, GeomAbs_Plane
    from OCP.TopAbs import TopAbs_REVERSED

    out = {}
    for k, f in enumerate(faces):
        srf = BRepAdaptor_Surface(f)
        if srf.GetType() == GeomAbs_Plane:
            n = _outward_normal(f)
            if abs(n[k_axis]) <= AXIS_SLACK:
                out[k] = ("plane", n)
        elif srf.GetType() == GeomAbs_Cylinder:
            cyl = srf.Cylinder()
            d = cyl.Axis().Direction()
            if abs(abs((d.X(), d.Y(), d.Z())[k_axis]) - 1.0) <= AXIS_SLACK:
                internal = (f.Orientation() == TopAbs_REVERSED) == cyl.Position().Direct()
                out[k] = ("cyl", cyl.Radius(), internal)
    return out


def _components(keys, neighbours) -> list[list[int]]:
    """Connected groups of ``keys`` (face indices) through ``neighbours``."""
    left, out = set(keys), []
    while left:
        stack, comp = [min(left)], []
        left.discard(stack[0])
        while stack:
            k = stack.pop()
            comp.append(k)
            nxt = neighbours[k] & left
            left -= nxt
            stack += sorted(nxt)
        out.append(sorted(comp))
    return out


def _box_in_frame(faces, frame) -> tuple[float, float, float, float, float, float]:
    """Exact box ``(x0, y0, z0, x1, y1, z1)`` of ``faces`` in ``frame`` (rows: the frame's
    unit x, y, z in part coordinates)."""
    from OCP.BRep import BRep_Builder
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Transform
    from OCP.gp import gp_Trsf
    from OCP.TopoDS import TopoDS_Compound

    comp, b = TopoDS_Compound(), BRep_Builder()
    b.MakeCompound(comp)
    for f in faces:
        b.Add(comp, f)
    t = gp_Trsf()
    (a, bb, c), (d, e, f_), (g, h, i) = frame
    t.SetValues(a, bb, c, 0.0, d, e, f_, 0.0, g, h, i, 0.0)
    return bbox_mm(BRepBuilderAPI_Transform(comp, t, True).Shape())


def _pocket(faces, comp, side, neighbours, k_axis: int, datum) -> Pocket | None:
    """The :class:`Pocket` walled by the faces ``comp`` (indices), or None when they are an
    outer boundary (a plane facing away from the group) or only cylinders (a hole)."""
    planes = [k for k in comp if side[k][0] == "plane"]
    cyls = [side[k] for k in comp if side[k][0] == "cyl"]
    if not planes or any(not c[2] for c in cyls):
        return None
    cs = [_centre(faces[k]) for k in comp]
    mid = [sum(c[q] for c in cs) / len(cs) for q in range(3)]
    for k in planes:  # every wall faces into the group: a pocket, not the outline
        n, c = side[k][1], _centre(faces[k])
        if sum(n[q] * (mid[q] - c[q]) for q in range(3)) <= 0:
            return None
    longest = max(planes, key=lambda k: _face_area(faces[k]))
    n = side[longest][1]
    az = [1.0 if q == k_axis else 0.0 for q in range(3)]
    tx = [az[1] * n[2] - az[2] * n[1], az[2] * n[0] - az[0] * n[2], az[0] * n[1] - az[1] * n[0]]
    i, j = [q for q in range(3) if q != k_axis]
    if tx[i] < -AXIS_SLACK or (abs(tx[i]) <= AXIS_SLACK and tx[j] < 0):
        tx = [-x for x in tx]  # along: pointing to +first other axis
    ty = [az[1] * tx[2] - az[2] * tx[1], az[2] * tx[0] - az[0] * tx[2], az[0] * tx[1] - az[1] * tx[0]]
    box = _box_in_frame([faces[k] for k in comp], (tx, ty, az))
    ctr = [0.5 * (box[q] + box[q + 3]) for q in range(3)]
    world = [ctr[0] * tx[q] + ctr[1] * ty[q] + ctr[2] * az[q] for q in range(3)]
    floor = _has_floor(faces, comp, neighbours, k_axis, (tx, ty, az), box)
    return Pocket("xyz"[k_axis], world[i] - datum[i], world[j] - datum[j], box[3] - box[0],
                  box[4] - box[1], box[5] - box[2], box[2] - datum[k_axis],
                  box[5] - datum[k_axis], math.degrees(math.atan2(tx[j], tx[i])),
                  min((c[1] for c in cyls), default=None), not floor)


def _face_area(face) -> float:
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    g = GProp_GProps()
    BRepGProp.SurfaceProperties_s(face, g)
    return g.Mass()


def _has_floor(faces, comp, neighbours, k_axis, frame, box) -> bool:
    """A plane across ``k_axis`` next to the walls and inside their outline: a floor."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAbs import GeomAbs_Plane

    near = set().union(*(neighbours[k] for k in comp)) - set(comp)
    for k in sorted(near):
        if BRepAdaptor_Surface(faces[k]).GetType() != GeomAbs_Plane:
            continue
        if abs(abs(_outward_normal(faces[k])[k_axis]) - 1.0) > AXIS_SLACK:
            continue
        b = _box_in_frame([faces[k]], frame)
        if (b[0] >= box[0] - SAME_POCKET_MM and b[3] <= box[3] + SAME_POCKET_MM
                and b[1] >= box[1] - SAME_POCKET_MM and b[4] <= box[4] + SAME_POCKET_MM):
            return True
    return False


def pockets(shape) -> list[Pocket]:
    """Every pocket and through slot of ``shape`` (``TopoDS_Shape``, mm) along a part axis:
    side faces joined edge to edge that all face into their group (module docstring for
    the datum); sorted by axis, then centre."""
    faces = _face_list(shape)
    neighbours = _neighbours(shape, faces)
    datum = bbox_mm(shape)[:3]
    out = []
    for k_axis in range(3):
        side = _side_faces(faces, k_axis)
        for comp in _components(side, neighbours):
            p = _pocket(faces, comp, side, neighbours, k_axis, datum)
            if p is not None:
                out.append(p)
    return sorted(out, key=lambda p: (p.axis, round(p.u_mm, 3), round(p.v_mm, 3), p.lo_mm))


def chamfers(shape) -> list[Chamfer]:
    """Every conical face of ``shape`` whose axis is a part axis, as a :class:`Chamfer`
    (legs from the cone's half angle and the face's extent along its generatrix)."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAbs import GeomAbs_Cone
    from OCP.TopAbs import TopAbs_REVERSED

    datum = bbox_mm(shape)[:3]
    out = []
    for f in _face_list(shape):
        srf = BRepAdaptor_Surface(f)
        if srf.GetType() != GeomAbs_Cone:
            continue
        cone = srf.Cone()
        d, loc = cone.Axis().Direction(), cone.Axis().Location()
        comp = (d.X(), d.Y(), d.Z())
        k = max(range(3), key=lambda q: abs(comp[q]))
        if abs(abs(comp[k]) - 1.0) > AXIS_SLACK:
            continue
        i, j = [q for q in range(3) if q != k]
        p = (loc.X(), loc.Y(), loc.Z())
        slant = abs(srf.LastVParameter() - srf.FirstVParameter())
        a = abs(cone.SemiAngle())
        b = bbox_mm(f)
        internal = (f.Orientation() == TopAbs_REVERSED) == cone.Position().Direct()
        out.append(Chamfer("xyz"[k], p[i] - datum[i], p[j] - datum[j], b[k] - datum[k],
                           b[k + 3] - datum[k], slant * math.cos(a), slant * math.sin(a),
                           math.degrees(a), internal))
    return sorted(out, key=lambda c: (c.axis, round(c.u_mm, 3), round(c.v_mm, 3), c.lo_mm))
