"""Turn build123d, cadquery or OCP objects into OCP ``TopoDS_Shape`` (imports lazily).

Accepted: an OCP ``TopoDS_Shape``; any build123d ``Shape`` (``.wrapped``); a build123d
builder (``BuildPart``: ``.part``); a cadquery ``Shape`` (``.wrapped``), ``Workplane``
(its solids, fused into one compound) or ``Assembly`` (``toCompound()``). Anything else
is a :class:`cad.errors.GeometryError` naming the type received.
"""

from __future__ import annotations

from cad.errors import GeometryError


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

    from cad.io.derived_cache import register_placed

    T = np.asarray(tf_world_part, dtype=float)
    tr = gp_Trsf()
    tr.SetValues(*(float(T[r, c]) for r in range(3) for c in range(4)))
    out = shape.Moved(TopLoc_Location(tr))
    register_placed(out, shape, T)  # its digest, for what is derived from it (cheap)
    return out
