"""Booleans that leave their arguments as they were (OCCT ``BRepAlgoAPI`` on copies).

An OCCT Boolean may modify its arguments in place: the pave filler raises the tolerances of
the vertices and edges it intersects and stores them on the shared ``TopoDS_TShape`` (OCCT
7.x, Boolean Operations user guide, "Safe processing mode": by default the non-destructive
mode is off and "the input shapes can be modified"). A part's solid is shared by every
instance of the part, by the interference check and by the exports, so a Boolean run by one
stage (the check's common volume of two touching solids) would change what a later stage
reads from the same solid (the hidden-line projection of its drawing, its BREP digest).
Every Boolean on a part's solid outside its part script goes through here: it runs on
independent copies of the arguments (``BRepBuilderAPI_Copy``: geometry copied, no mesh), so
the caller's shapes keep their tolerances, and its result is the one the same Boolean gives
on the original (same topology order: the same edge order, the same file bytes). Serial
(``SetRunParallel(False)``): OCCT's thread pool hangs in a forked child
(:mod:`cad.pipeline.forked`).
"""

from __future__ import annotations


def _copy(shape):
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Copy

    return BRepBuilderAPI_Copy(shape, True, False).Shape()


def _run(op, a, b):
    """Set up ``op`` (a ``BRepAlgoAPI_BooleanOperation``) on copies of ``a`` and ``b``,
    serial, build it and return its result shape."""
    from OCP.TopTools import TopTools_ListOfShape

    args, tools = TopTools_ListOfShape(), TopTools_ListOfShape()
    args.Append(_copy(a))
    tools.Append(_copy(b))
    op.SetArguments(args)
    op.SetTools(tools)
    op.SetRunParallel(False)
    op.Build()
    return op.Shape()


def common(a, b):
    """``a`` ∩ ``b`` (OCP ``TopoDS_Shape`` each, mm) as a ``TopoDS_Shape``
    (``BRepAlgoAPI_Common``); neither argument is modified (module docstring)."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Common

    return _run(BRepAlgoAPI_Common(), a, b)


def section(a, b):
    """The section edges of ``a`` by ``b`` (OCP ``TopoDS_Shape`` each, e.g. a solid and a
    planar face, mm) as a compound (``BRepAlgoAPI_Section``); neither is modified."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Section

    return _run(BRepAlgoAPI_Section(), a, b)
