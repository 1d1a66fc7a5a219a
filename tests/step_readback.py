"""Reading a build's ``assembly.step`` back with OCCT (a second tool beside the build's own
interference check): the solids by instance name, the volume two solids share and their
distance. Shared by the capstan build tests (5-bar, twin, pen)."""

from __future__ import annotations

from pathlib import Path


def step_solids(step_path: Path) -> dict:
    """``{instance name ('.' as '_'): solid}`` of ``assembly.step`` read with build123d."""
    from build123d import import_step

    return {c.label: c for c in import_step(str(step_path)).children}


def common_mm3(a, b) -> float:
    """The volume (mm^3) solids ``a`` and ``b`` share (OCCT Boolean common)."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Common
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    op = BRepAlgoAPI_Common(a.wrapped, b.wrapped)
    g = GProp_GProps()
    BRepGProp.VolumeProperties_s(op.Shape(), g)
    return g.Mass()


def dist_mm(a, b) -> float:
    """The least distance (mm) between solids ``a`` and ``b`` (OCCT BRepExtrema; 0 when they meet)."""
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape

    return BRepExtrema_DistShapeShape(a.wrapped, b.wrapped).Value()
