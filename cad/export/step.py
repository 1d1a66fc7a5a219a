"""STEP export with a fixed header so that the same model gives the same bytes.

What the format forces and how it is handled (measured with OCCT 7.9.3 / build123d 0.12):

* ``FILE_NAME`` carries a time stamp: we write the fixed :data:`STEP_TIMESTAMP`
  and the part name (never the temporary path used for the atomic write: the file is
  written to memory first).
* ``NEXT_ASSEMBLY_USAGE_OCCURRENCE`` ids of an assembly come from a counter that
  OCCT keeps for the whole process, so a second export in the same process numbers
  them differently; :func:`_normalise_nauo` renumbers them 1, 2, ... in file order.

With both, a part or an assembly STEP is byte-identical run to run (tests/test_export.py).
"""

from __future__ import annotations

import io
import re

#: Fixed ISO 8601 time stamp written in every STEP header.
STEP_TIMESTAMP = "2000-01-01T00:00:00"

_NAUO = re.compile(rb"NEXT_ASSEMBLY_USAGE_OCCURRENCE\('(\d+)'")


def _normalise_nauo(data: bytes) -> bytes:
    counter = iter(range(1, 1 << 30))
    return _NAUO.sub(lambda m: b"NEXT_ASSEMBLY_USAGE_OCCURRENCE('%d'" % next(counter), data)


def _labelled(shape, name: str, color):
    """A build123d Solid/Compound wrapping ``shape`` with a label (and colour)."""
    from build123d import Color, Compound, Solid
    from OCP.TopAbs import TopAbs_SOLID

    from cad.export.shapes import count_solids

    if shape.ShapeType() == TopAbs_SOLID:
        obj = Solid(shape)
    elif count_solids(shape) == 1:
        from OCP.TopExp import TopExp_Explorer
        from OCP.TopoDS import TopoDS

        obj = Solid(TopoDS.Solid_s(TopExp_Explorer(shape, TopAbs_SOLID).Current()))
    else:
        obj = Compound(shape)
    obj.label = name
    if color is not None:
        obj.color = Color(*(float(c) for c in color))
    return obj


def _write(obj) -> bytes:
    from build123d import export_step

    buf = io.BytesIO()
    export_step(obj, buf, timestamp=STEP_TIMESTAMP)
    return _normalise_nauo(buf.getvalue())


def step_bytes(shape, name: str, color: tuple[float, float, float] | None = None) -> bytes:
    """STEP (AP214, mm) of one part as bytes; ``shape`` is a ``TopoDS_Shape``."""
    return _write(_labelled(shape, name, color))


def assembly_step_bytes(items, name: str) -> bytes:
    """STEP of an assembly: one named, coloured solid (or compound) per item.

    ``items`` : sequence of ``(part_name, TopoDS_Shape placed in the world, rgb 0..1)``.
    """
    from build123d import Compound

    children = [_labelled(shape, pname, color) for pname, shape, color in items]
    return _write(Compound(children=children, label=name))
