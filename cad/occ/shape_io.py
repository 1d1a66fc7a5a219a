"""Shapes to bytes: the BREP text of an OCP shape (what the derived cache hashes)."""

from __future__ import annotations

import io


def brep_bytes(shape) -> bytes:
    """BREP text (OCCT ``BRepTools::Write``, format version 1) of an OCP ``TopoDS_Shape``,
    written to memory without triangulations or normals: its full topology, geometry and
    location, so two shapes with the same bytes are the same solid."""
    from OCP.BRepTools import BRepTools
    from OCP.TopTools import TopTools_FormatVersion

    buf = io.BytesIO()
    BRepTools.Write_s(
        shape, buf, False, False, TopTools_FormatVersion.TopTools_FormatVersion_VERSION_1
    )
    return buf.getvalue()
