"""Read solids for ``hapticad massprops``: STEP through OCP (:func:`cad.massprops.occt.read_step`,
``read_step_named``, ``split_solids``), STL through trimesh (lazy imports).

Both readers assume the file's length unit is the millimetre (STEP files written by
build123d/cadquery are; an STL carries no unit, mm is the 3D-printing convention).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from cad.errors import DesignError, MeshError
from cad.io import guard

STEP_SUFFIXES = (".step", ".stp")
STL_SUFFIXES = (".stl",)


def file_kind(path: str | Path, field: str = "FILE") -> str:
    """``"step"`` or ``"stl"`` from the file suffix; DesignError for a missing file or other
    suffix, :class:`cad.errors.FileRefused` for a FIFO, a device, a folder or a file over its
    kind's size limit (:func:`cad.io.guard.check_file`)."""
    p = Path(path)
    if not os.path.lexists(p):
        raise DesignError(field, f"file not found: {p}")
    suffix = p.suffix.lower()
    if suffix in STEP_SUFFIXES:
        kind = "step"
    elif suffix in STL_SUFFIXES:
        kind = "stl"
    else:
        raise DesignError(
            field, f"unsupported file type {p.suffix!r} for {p.name} (expected .step, .stp or .stl)"
        )
    guard.check_file(p, kind, field)
    return kind


def ignored_text(ignored: dict[str, int]) -> str:
    """``"1 face, 1 open shell"`` from :func:`split_solids` counts."""
    names = {"faces": "face", "open_shells": "open shell", "closed_shells": "closed shell"}
    return ", ".join(f"{n} {names[k]}{'s' if n > 1 else ''}" for k, n in ignored.items())


#: Bytes of the binary STL header (80) + triangle count (4), and of one record.
STL_HEADER_BYTES = 84
STL_RECORD_BYTES = 50


def _is_binary_stl(data: bytes) -> bool:
    """False for ASCII: ``solid`` first (after blanks and a UTF-8 byte-order mark, which
    Windows editors write) and ``facet`` or ``endsolid`` in the text."""
    head = data[:512].removeprefix(b"\xef\xbb\xbf").lstrip().lower()
    if not head.startswith(b"solid"):
        return True
    return b"facet" not in data[:4096].lower() and b"endsolid" not in data[-1024:].lower()


def read_binary_stl(path: str | Path, warnings: list[str] | None = None, field: str = "FILE"):
    """Triangles of a binary STL as ``(vertices_mm (3M, 3) float64, faces (M, 3))``, or ``None``
    when the file is ASCII (read through :func:`cad.io.guard.read_bytes`, kind ``stl``)."""
    p = Path(path)
    return binary_stl_arrays(guard.read_bytes(p, "stl", field), p.name, warnings)


def binary_stl_arrays(data: bytes, name: str, warnings: list[str] | None = None):
    """:func:`read_binary_stl` of the bytes ``data`` of the file ``name``.

    The triangle count in the header is checked against the file length: a file holding
    more complete records than its header says is read whole with a warning (appended to
    ``warnings``); one holding fewer (or a partial last record) is refused as truncated.
    """
    if not _is_binary_stl(data):
        return None
    if len(data) < STL_HEADER_BYTES:
        raise MeshError(f"{name}: truncated: {len(data)} bytes, shorter than the 84-byte STL header")
    n_header = int(np.frombuffer(data, "<u4", 1, 80)[0])
    body = len(data) - STL_HEADER_BYTES
    n_file, rest = divmod(body, STL_RECORD_BYTES)
    if n_header > n_file or (rest and n_header != n_file):
        raise MeshError(
            f"{name}: truncated: the header says {n_header} triangles "
            f"({STL_HEADER_BYTES + STL_RECORD_BYTES * n_header} bytes) but the file has "
            f"{len(data)} bytes ({n_file} complete records{' and a partial one' if rest else ''})"
        )
    if n_header < n_file and warnings is not None:
        warnings.append(f"{name}: the header says {n_header} triangles, the file holds "
                        f"{n_file}; read all {n_file}")
    if rest and warnings is not None:
        warnings.append(f"{name}: {rest} bytes after the last triangle ignored")
    if n_file == 0:
        raise MeshError(f"{name}: STL file holds no triangles")
    rec = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    tri = np.frombuffer(data, rec, n_file, STL_HEADER_BYTES)["v"].astype(np.float64)
    return tri.reshape(-1, 3), np.arange(3 * n_file, dtype=np.int64).reshape(-1, 3)


def read_stl(path: str | Path, warnings: list[str] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Read an STL (ASCII or binary, mm) as a triangle soup ``(vertices_mm (N, 3), faces (M, 3))``.

    Vertices are not merged here (see :func:`cad.massprops.mesh.mesh_arrays_mass_props`).
    Raises :class:`MeshError` for an unreadable or empty file; the file is read once, through
    :func:`cad.io.guard.read_bytes` (a regular file within the ``stl`` limit).
    """
    import io

    import trimesh


    p = Path(path)
    data = guard.read_bytes(p, "stl", "FILE")
    binary = binary_stl_arrays(data, p.name, warnings)
    if binary is not None:
        return binary
    try:
        tm = trimesh.load_mesh(io.BytesIO(data), file_type="stl", process=False)
    except Exception as exc:  # trimesh raises assorted errors on malformed files
        raise MeshError(
            f"{p.name}: not a readable STL file ({type(exc).__name__}: {exc})"
        ) from None
    if not isinstance(tm, trimesh.Trimesh) or len(tm.faces) == 0:
        raise MeshError(f"{p.name}: STL file holds no triangles")
    return np.asarray(tm.vertices, dtype=float), np.asarray(tm.faces, dtype=np.int64)
