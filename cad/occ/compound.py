"""build123d compounds of several shapes (imports build123d on first use)."""

from __future__ import annotations


def deep_copy(shape):
    """An independent copy of an OCP ``TopoDS_Shape`` (``BRepBuilderAPI_Copy``: its own
    geometry, no mesh copied), so that a STEP writer does not merge it with the original."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Copy

    return BRepBuilderAPI_Copy(shape, True, False).Shape()


def labelled_compound(children: list, label: str):
    """A build123d ``Compound`` of ``children`` (build123d shapes, in order) named ``label``."""
    from build123d import Compound

    return Compound(children=children, label=label)
