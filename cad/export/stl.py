"""Binary STL with a controlled absolute tolerance and a watertight check before writing.

The mesh comes from OCCT's ``BRepMesh_IncrementalMesh`` on a fresh copy of the shape
with an ABSOLUTE chordal deflection (:func:`cad.massprops.occt.triangulate`), because
build123d's ``export_stl`` uses a relative tolerance with a fixed 0.1 rad angle and
reuses any mesh already on the shape (SPEC "Measured pitfalls"). Meshing is serial
(``parallel=False``), so the triangle order, hence the file, is the same every run.

Before a file is written its merged mesh must pass two independent checks:

1. every undirected edge is used by exactly two triangles, once in each direction
   (closed and consistently wound; pure numpy);
2. manifold3d accepts it (``Manifold(Mesh64(...)).status() == NoError``).

An STL is a triangle soup, so vertices are merged first (coordinates equal to
:data:`MERGE_GRID_MM`), otherwise manifold3d reports NotManifold.
"""

from __future__ import annotations

import numpy as np

from cad.errors import MeshError
from cad.io import derived_cache
from cad.massprops.occt import as_topods, extract_arrays, triangulate

#: Vertices closer than this grid (mm) are merged. OCCT computes the nodes of a shared
#: edge once per face from the same edge discretization: they agree to ~1e-12 mm.
MERGE_GRID_MM = 1e-6
#: Modules whose source a cached mesh depends on (:func:`mesh_shape`).
MESH_CODE = ("cad.export.stl", "cad.massprops.mesh")


def merge_vertices(vertices_mm: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Merge coincident vertices; drop triangles that became degenerate.

    Returns ``(vertices (K, 3) float64, faces (M', 3) int64)``.
    """
    v = np.asarray(vertices_mm, dtype=float)
    key = np.round(v / MERGE_GRID_MM).astype(np.int64)
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    f = inverse.reshape(-1)[np.asarray(faces, dtype=np.int64)]
    ok = (f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])
    return v[first], f[ok]


def open_edge_count(faces: np.ndarray) -> int:
    """Directed edges without their opposite twin (0 for a closed, consistently wound mesh)."""
    f = np.asarray(faces, dtype=np.int64)
    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    n = int(e.max()) + 1 if len(e) else 1
    fwd = e[:, 0] * n + e[:, 1]
    rev = e[:, 1] * n + e[:, 0]
    fwd_u, counts = np.unique(fwd, return_counts=True)
    dup = int((counts > 1).sum())
    missing = int((~np.isin(rev, fwd_u)).sum())
    return dup + missing


def manifold_status(vertices_mm: np.ndarray, faces: np.ndarray) -> str:
    """manifold3d's verdict on a merged mesh: ``"NoError"`` or the error name."""
    import manifold3d

    mesh = manifold3d.Mesh64(
        vert_properties=np.ascontiguousarray(vertices_mm, dtype=np.float64),
        tri_verts=np.ascontiguousarray(faces, dtype=np.uint64),
    )
    return manifold3d.Manifold(mesh).status().name


def mesh_shape(
    shape, tolerance_mm: float, angular_tolerance_rad: float
) -> tuple[np.ndarray, np.ndarray]:
    """Merged triangle mesh ``(vertices_mm, faces)`` of a ``TopoDS_Shape`` at an absolute tolerance.

    Cached on disk by the solid's digest and both tolerances (:mod:`cad.io.derived_cache`;
    the meshing is serial and deterministic, so a hit is the same arrays bit for bit).
    """
    def make():
        v, f = extract_arrays(triangulate(shape, tolerance_mm, angular_tolerance_rad))
        return merge_vertices(v, f)

    if not derived_cache.enabled():
        return make()

    key = [derived_cache.shape_digest(as_topods(shape)), float(tolerance_mm), float(angular_tolerance_rad)]
    v, f = derived_cache.cached_arrays("mesh", key, make, code=MESH_CODE)
    return v, f


def check_watertight(vertices_mm: np.ndarray, faces: np.ndarray, name: str) -> None:
    """Raise :class:`MeshError` unless the merged mesh is closed and manifold (both checks)."""
    if len(faces) == 0:
        raise MeshError(f"{name}: the mesh has no triangles")
    n_open = open_edge_count(faces)
    if n_open:
        raise MeshError(f"{name}: mesh is not watertight ({n_open} open or non-manifold edges)")
    status = manifold_status(vertices_mm, faces)
    if status != "NoError":
        raise MeshError(f"{name}: manifold3d rejects the mesh ({status})")


def stl_bytes(vertices_mm: np.ndarray, faces: np.ndarray, name: str) -> bytes:
    """Binary STL (mm, little endian) of a mesh; the 80-byte header names the part."""
    v = np.asarray(vertices_mm, dtype=np.float64)
    tri = v[np.asarray(faces, dtype=np.int64)]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    norm = np.linalg.norm(n, axis=1)
    n = np.divide(n, norm[:, None], out=np.zeros_like(n), where=norm[:, None] > 0)
    rec = np.zeros(len(tri), dtype=[("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["n"] = n
    rec["v"] = tri
    header = f"hapticad binary STL {name} mm".encode("ascii", "replace")[:80].ljust(80, b" ")
    return header + np.uint32(len(tri)).tobytes() + rec.tobytes()


def read_stl_arrays(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    """Parse binary STL bytes back into a merged ``(vertices_mm, faces)`` mesh."""
    if len(data) < 84:
        raise MeshError("not a binary STL (shorter than 84 bytes)")
    n = int(np.frombuffer(data[80:84], dtype="<u4")[0])
    rec = np.frombuffer(
        data[84 : 84 + 50 * n], dtype=[("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")]
    )
    if len(rec) != n:
        raise MeshError(f"binary STL truncated: {len(rec)} of {n} triangles")
    v = rec["v"].reshape(-1, 3).astype(np.float64)
    return merge_vertices(v, np.arange(3 * n).reshape(n, 3))
