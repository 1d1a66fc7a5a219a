"""Read solids for ``hapticad massprops``: STEP through OCP, STL through trimesh (lazy imports).

Both readers assume the file's length unit is the millimetre (STEP files written by
build123d/cadquery are; an STL carries no unit, mm is the 3D-printing convention).
"""

from __future__ import annotations

import contextlib
import os
import sys
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from cad.errors import DesignError, GeometryError, MeshError

STEP_SUFFIXES = (".step", ".stp")
STL_SUFFIXES = (".stl",)


def file_kind(path: str | Path, field: str = "FILE") -> str:
    """``"step"`` or ``"stl"`` from the file suffix; DesignError for a missing file or other suffix."""
    p = Path(path)
    if not p.is_file():
        raise DesignError(field, f"file not found: {p}")
    suffix = p.suffix.lower()
    if suffix in STEP_SUFFIXES:
        return "step"
    if suffix in STL_SUFFIXES:
        return "stl"
    raise DesignError(
        field, f"unsupported file type {p.suffix!r} for {p.name} (expected .step, .stp or .stl)"
    )


@contextlib.contextmanager
def _quiet_stdout() -> Iterator[None]:
    """Silence C++ writes to file descriptor 1 (OCCT's STEP parser prints errors there).

    Keeps stdout clean for ``--json`` output; our own error message says what failed.
    """
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        with open(os.devnull, "wb") as null:
            os.dup2(null.fileno(), 1)
            try:
                yield
            finally:
                os.dup2(saved, 1)
    finally:
        os.close(saved)


def read_step(path: str | Path):
    """Read a STEP file (mm) and return its shape as one OCP ``TopoDS_Shape``.

    Raises :class:`GeometryError` when the file cannot be read or holds no solid.
    """
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPControl import STEPControl_Reader
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    p = Path(path)
    reader = STEPControl_Reader()
    with _quiet_stdout():
        status = reader.ReadFile(str(p))
        n_roots = reader.TransferRoots() if status == IFSelect_RetDone else 0
    if status != IFSelect_RetDone:
        raise GeometryError(f"{p.name}: not a readable STEP file (reader status {status.name})")
    if n_roots == 0:
        raise GeometryError(f"{p.name}: STEP file has no transferable shape")
    shape = reader.OneShape()
    if shape.IsNull() or not TopExp_Explorer(shape, TopAbs_SOLID).More():
        raise GeometryError(f"{p.name}: STEP file holds no solid (only surfaces or curves?)")
    return shape


def read_stl(path: str | Path) -> tuple[np.ndarray, np.ndarray]:
    """Read an STL (ASCII or binary, mm) as a triangle soup ``(vertices_mm (N, 3), faces (M, 3))``.

    Vertices are not merged here (see :func:`cad.massprops.mesh.mesh_arrays_mass_props`).
    Raises :class:`MeshError` for an unreadable or empty file.
    """
    import trimesh

    p = Path(path)
    try:
        tm = trimesh.load_mesh(str(p), file_type="stl", process=False)
    except Exception as exc:  # trimesh raises assorted errors on malformed files
        raise MeshError(
            f"{p.name}: not a readable STL file ({type(exc).__name__}: {exc})"
        ) from None
    if not isinstance(tm, trimesh.Trimesh) or len(tm.faces) == 0:
        raise MeshError(f"{p.name}: STL file holds no triangles")
    return np.asarray(tm.vertices, dtype=float), np.asarray(tm.faces, dtype=np.int64)
