"""The closed shells of a triangle mesh, each checked on its own (issue 21 §4).

A mesh file is a soup of triangles; a solid with a cavity is two closed shells, the outer
one wound outwards and the inner one inwards. Integrating the whole soup at once takes the
windings at face value: two nested shells both wound outwards add the cavity instead of
removing it (9000 mm^3 for a 20 mm cube with a 10 mm cavity, above its convex hull's 8000),
and every facet written twice doubles the volume. These functions, plain numpy on merged
``(vertices (N, 3), faces (M, 3))`` arrays, find and fix or name such faults:

* :func:`drop_duplicate_faces` -- the same triangle written twice (same vertices, same
  winding) is dropped.
* :func:`shell_labels` -- connected shells (triangles sharing an edge).
* :func:`winding_numbers` -- generalized winding number of points about a closed shell
  (Jacobson et al., "Robust Inside-Outside Segmentation using Generalized Winding
  Numbers", SIGGRAPH 2013, eq. 3 with the Van Oosterom-Strackee solid angle): +1 inside a
  shell wound outwards, -1 inside one wound inwards, 0 outside.
* :func:`orient_shells` -- nests the shells by winding number: a shell inside an odd
  number of others is a cavity and must be wound inwards; one wound outwards there is
  flipped with a note; a shell inside an even number (0: the outermost) wound inwards is
  inside-out and refused; shells that cross each other (vertices on both sides, or a
  manifold3d intersection volume other than the nesting implies) are refused.
"""

from __future__ import annotations

import numpy as np

from cad.errors import MeshError
from cad.tolerances import SHELL_OVERLAP_REL_EPS

#: Vertices of a shell tested against each other shell for nesting. Nested shells that do
#: not cross have every vertex on the same side, so one suffices; 256, spread over the
#: shell, find crossing shells (vertices on both sides) without an O(N x M) cost.
NEST_SAMPLES = 256

#: Triangles per block of the winding-number sum (memory: samples x block x 3 floats).
_BLOCK = 4096


def drop_duplicate_faces(faces: np.ndarray) -> tuple[np.ndarray, int]:
    """``(faces without repeats, number dropped)``: a triangle equal to an earlier one up to
    a cyclic rotation of its vertices (same winding) is dropped; order otherwise kept.

    faces : (M, 3) int vertex indices of a MERGED mesh (coincident vertices one index).
    """
    f = np.asarray(faces, dtype=np.int64)
    rot = np.argmin(f, axis=1)[:, None]
    canon = np.take_along_axis(f, (rot + np.arange(3)) % 3, axis=1)
    _, first = np.unique(canon, axis=0, return_index=True)
    keep = np.sort(first)
    return f[keep], len(f) - len(keep)


def shell_labels(faces: np.ndarray) -> np.ndarray:
    """(M,) int label of the connected shell of every triangle (shared edge = connected)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    f = np.asarray(faces, dtype=np.int64)
    m = len(f)
    edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    tri = np.tile(np.arange(m), 3)
    order = np.lexsort((edges[:, 1], edges[:, 0]))
    e, t = edges[order], tri[order]
    same = np.all(e[1:] == e[:-1], axis=1)  # consecutive equal edges: faces that share it
    graph = coo_matrix((np.ones(int(same.sum())), (t[:-1][same], t[1:][same])), shape=(m, m))
    return connected_components(graph, directed=False)[1]


def winding_numbers(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """(P,) generalized winding numbers of ``points`` (P, 3) about ``triangles`` (T, 3, 3).

    Sum over triangles of the signed solid angle / (4 pi), with tan(Omega/2) =
    det(a, b, c) / (|a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|), a, b, c the corners
    relative to the point (Van Oosterom & Strackee, IEEE TBME 30 (1983) 125). For a closed
    shell wound outwards: 1 inside, 0 outside; -1 inside when wound inwards.
    """
    p = np.asarray(points, dtype=float)[:, None, None, :]
    total = np.zeros(len(p))
    for s in range(0, len(triangles), _BLOCK):
        d = np.asarray(triangles[s:s + _BLOCK], dtype=float)[None] - p  # (P, T, 3, 3)
        a, b, c = d[..., 0, :], d[..., 1, :], d[..., 2, :]
        la, lb, lc = (np.linalg.norm(x, axis=-1) for x in (a, b, c))
        det = np.einsum("ptk,ptk->pt", a, np.cross(b, c))
        den = (la * lb * lc + np.einsum("ptk,ptk->pt", a, b) * lc
               + np.einsum("ptk,ptk->pt", a, c) * lb + np.einsum("ptk,ptk->pt", b, c) * la)
        total += 2.0 * np.arctan2(det, den).sum(axis=1)
    return total / (4.0 * np.pi)


def _signed_volumes(tri: np.ndarray, labels: np.ndarray, n: int) -> np.ndarray:
    det = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])) / 6.0
    return np.bincount(labels, weights=det, minlength=n)


def _describe(i: int, n: int, tri: np.ndarray, origin) -> str:
    lo, hi = tri.reshape(-1, 3).min(axis=0) + origin, tri.reshape(-1, 3).max(axis=0) + origin
    box = " to ".join("(" + ", ".join(f"{x:.6g}" for x in c) + ")" for c in (lo, hi))
    return f"shell {i + 1} of {n} ({len(tri)} triangles, {box} mm)"


def _crossing(what: str, a: str, b: str, how: str) -> MeshError:
    return MeshError(f"{what}: {a} crosses {b} ({how}): their overlap would count twice; "
                     "unite them into one shell first")


def _inside(tri_by_shell: list[np.ndarray], lo, hi, what: str, names) -> np.ndarray:
    """(k, k) bool: ``inside[i, j]`` when shell i lies inside shell j; MeshError when two
    shells cross (vertices of one on both sides of the other). lo, hi: (k, 3) boxes."""
    k = len(tri_by_shell)
    inside = np.zeros((k, k), dtype=bool)
    for i in range(k):
        pts = np.unique(tri_by_shell[i].reshape(-1, 3), axis=0)
        pts = pts[np.linspace(0, len(pts) - 1, min(len(pts), NEST_SAMPLES)).astype(int)]
        for j in range(k):
            if i == j or np.any(lo[i] > hi[j]) or np.any(hi[i] < lo[j]):
                continue  # disjoint boxes: neither inside nor crossing
            w = np.abs(winding_numbers(pts, tri_by_shell[j]))
            clear = np.abs(w - np.round(w)) < 0.25  # a point ON shell j is neither side
            ins = w[clear] > 0.5
            if ins.any() and not ins.all():
                raise _crossing(what, names(i), names(j), "vertices on both sides")
            inside[i, j] = bool(ins.size and ins.all())
    return inside


def _solid(vertices: np.ndarray, faces: np.ndarray, outward: bool):
    """manifold3d solid of one closed shell (re-indexed; wound outwards for the boolean)."""
    import manifold3d

    used, local = np.unique(faces, return_inverse=True)
    f = local.reshape(-1, 3) if outward else local.reshape(-1, 3)[:, ::-1]
    return manifold3d.Manifold(manifold3d.Mesh64(
        vert_properties=np.ascontiguousarray(vertices[used], dtype=np.float64),
        tri_verts=np.ascontiguousarray(f, dtype=np.uint64)))


def _check_overlaps(vertices, faces, labels, vol, inside, lo, hi, what: str, names) -> None:
    """MeshError unless every pair of shells with overlapping boxes shares exactly the
    volume its nesting says (manifold3d intersection): all of the inner one when nested,
    none otherwise. Catches shells that cross with every vertex outside the other."""
    k = len(vol)
    solids = [None] * k
    for i in range(k):
        for j in range(i + 1, k):
            if np.any(lo[i] >= hi[j]) or np.any(hi[i] <= lo[j]) or 0 in (vol[i], vol[j]):
                continue
            for s in (i, j):
                if solids[s] is None:
                    solids[s] = _solid(vertices, faces[labels == s], bool(vol[s] > 0))
            shared = float((solids[i] ^ solids[j]).volume())
            want = abs(vol[i]) if inside[i, j] else abs(vol[j]) if inside[j, i] else 0.0
            if abs(shared - want) > SHELL_OVERLAP_REL_EPS * min(abs(vol[i]), abs(vol[j])):
                raise _crossing(what, names(i), names(j), f"{shared:.6g} mm^3 in both")


def orient_shells(vertices: np.ndarray, faces: np.ndarray, what: str = "mesh",
                  origin=0.0) -> tuple[np.ndarray, list[str]]:
    """``(faces, notes)`` of a closed, consistently wound mesh with every shell wound for
    its nesting: cavities (inside an odd number of shells) inwards, solids outwards.

    vertices : (N, 3) merged vertices, mm; faces : (M, 3) int. ``origin`` (mm) is added
    to the coordinates quoted in messages (the caller may have shifted the mesh).
    A cavity shell wound outwards is flipped and named in ``notes``; MeshError for a solid
    shell wound inwards (inside-out) and for shells that cross each other.
    """
    f = np.asarray(faces, dtype=np.int64)
    labels = shell_labels(f)
    k = int(labels.max()) + 1
    if k == 1:
        return f, []
    tri = np.asarray(vertices, dtype=float)[f]
    vol = _signed_volumes(tri, labels, k)
    tri_by_shell = [tri[labels == s] for s in range(k)]

    def names(s):
        return _describe(s, k, tri_by_shell[s], origin)

    lo = np.array([t.reshape(-1, 3).min(axis=0) for t in tri_by_shell])
    hi = np.array([t.reshape(-1, 3).max(axis=0) for t in tri_by_shell])
    inside = _inside(tri_by_shell, lo, hi, what, names)
    _check_overlaps(np.asarray(vertices, dtype=float), f, labels, vol, inside, lo, hi, what,
                    names)
    depth = inside.sum(axis=1)
    notes: list[str] = []
    flip = np.zeros(k, dtype=bool)
    for s in range(k):
        if vol[s] == 0 or (vol[s] > 0) == (depth[s] % 2 == 0):
            continue
        if depth[s] % 2 == 0:
            where = "enclosed by no other shell" if depth[s] == 0 else "inside a cavity"
            raise MeshError(
                f"{what}: {names(s)} is inside-out (wound inwards, {where}): its "
                f"{-vol[s]:.6g} mm^3 would count negative; flip its triangles"
            )
        flip[s] = True
        around = int(np.flatnonzero(inside[s])[np.argmax(depth[inside[s]])])  # innermost
        notes.append(f"{what}: {names(s)} lies inside shell {around + 1} but is wound "
                     f"outwards like a solid: read as a cavity ({vol[s]:.6g} mm^3 removed, "
                     "not added)")
    if flip.any():
        f = f.copy()
        f[flip[labels]] = f[flip[labels]][:, ::-1]
    return f, notes
