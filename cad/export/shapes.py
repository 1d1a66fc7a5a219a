"""Turn build123d, cadquery or OCP objects into OCP ``TopoDS_Shape`` (imports lazily).

Accepted: an OCP ``TopoDS_Shape``; any build123d ``Shape`` (``.wrapped``); a build123d
builder (``BuildPart``: ``.part``); a cadquery ``Shape`` (``.wrapped``), ``Workplane``
(its solids, fused into one compound) or ``Assembly`` (``toCompound()``). Anything else
is a :class:`cad.errors.GeometryError` naming the type received.
"""

from __future__ import annotations

from cad.errors import GeometryError
from cad.io.derived_cache import register_placed


def to_topods(obj, what: str = "shape"):
    """Return the OCP ``TopoDS_Shape`` of ``obj`` (see module docstring)."""
    from OCP.TopoDS import TopoDS_Shape

    if isinstance(obj, TopoDS_Shape):
        shape = obj
    elif isinstance(getattr(obj, "wrapped", None), TopoDS_Shape):
        shape = obj.wrapped
    elif hasattr(obj, "part") and isinstance(getattr(obj.part, "wrapped", None), TopoDS_Shape):
        shape = obj.part.wrapped  # build123d BuildPart
    elif hasattr(obj, "toCompound") and callable(obj.toCompound):
        shape = obj.toCompound().wrapped  # cadquery Assembly
    elif hasattr(obj, "vals") and callable(obj.vals):  # cadquery Workplane
        vals = [v for v in obj.vals() if isinstance(getattr(v, "wrapped", None), TopoDS_Shape)]
        if not vals:
            raise GeometryError(f"{what}: the cadquery Workplane holds no shape")
        shape = vals[0].wrapped if len(vals) == 1 else make_compound([v.wrapped for v in vals])
    else:
        raise GeometryError(
            f"{what}: expected a build123d or cadquery object or an OCP TopoDS_Shape, got {type(obj).__name__}"
        )
    if shape.IsNull():
        raise GeometryError(f"{what}: the shape is empty")
    return shape


def make_compound(shapes):
    """An OCP compound of the given ``TopoDS_Shape`` objects."""
    from OCP.BRep import BRep_Builder
    from OCP.TopoDS import TopoDS_Compound

    comp = TopoDS_Compound()
    b = BRep_Builder()
    b.MakeCompound(comp)
    for s in shapes:
        b.Add(comp, s)
    return comp


def in_own_frame(shape):
    """``shape`` with every placement of its solids, shells and sub-compounds applied to
    their geometry: the same solid at the same place, whose coordinates are those of the
    part frame without any location (a STEP file of it has no nested placement, which a
    reader may drop). A shape that carries none is returned as it is.

    Rigid locations only (what the part scripts make); the geometry is copied and moved
    (``BRepBuilderAPI_Transform`` with copy), exact to round-off.
    """
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Transform
    from OCP.TopAbs import TopAbs_COMPOUND, TopAbs_COMPSOLID
    from OCP.TopLoc import TopLoc_Location
    from OCP.TopoDS import TopoDS_Iterator

    if not _has_location(shape):
        return shape
    if shape.ShapeType() in (TopAbs_COMPOUND, TopAbs_COMPSOLID):
        it = TopoDS_Iterator(shape, True, True)  # children with the parent's location applied
        children = []
        while it.More():
            children.append(in_own_frame(it.Value()))
            it.Next()
        return make_compound(children)
    trsf = shape.Location().Transformation()
    return BRepBuilderAPI_Transform(shape.Located(TopLoc_Location()), trsf, True).Shape()


def _has_location(shape) -> bool:
    """True when ``shape`` or a compound / solid / shell level under it has a location."""
    from OCP.TopAbs import TopAbs_COMPOUND, TopAbs_COMPSOLID
    from OCP.TopoDS import TopoDS_Iterator

    if not shape.Location().IsIdentity():
        return True
    if shape.ShapeType() not in (TopAbs_COMPOUND, TopAbs_COMPSOLID):
        return False
    it = TopoDS_Iterator(shape, False, False)
    while it.More():
        if _has_location(it.Value()):
            return True
        it.Next()
    return False


def count_solids(shape) -> int:
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    n = 0
    exp = TopExp_Explorer(shape, TopAbs_SOLID)
    while exp.More():
        n += 1
        exp.Next()
    return n


def is_valid(shape) -> bool:
    """BRepCheck_Analyzer verdict on a shape."""
    from OCP.BRepCheck import BRepCheck_Analyzer

    return bool(BRepCheck_Analyzer(shape).IsValid())


def placed(shape, tf_world_part):
    """``shape`` moved by a 4x4 homogeneous transform (mm), as a new located shape.

    ``tf_world_part`` maps part coordinates into world coordinates. Only rigid
    transforms are accepted (the located shape shares geometry with ``shape``).
    """
    import numpy as np
    from OCP.gp import gp_Trsf
    from OCP.TopLoc import TopLoc_Location

    T = np.asarray(tf_world_part, dtype=float)
    tr = gp_Trsf()
    tr.SetValues(*(float(T[r, c]) for r in range(3) for c in range(4)))
    out = shape.Moved(TopLoc_Location(tr))
    register_placed(out, shape, T)  # its digest, for what is derived from it (cheap)
    return out
