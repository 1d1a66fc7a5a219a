"""The closed shells of a triangle mesh, each checked on its own (issue 21 §4).

A mesh file is a soup of triangles; a solid with a cavity is two closed shells, the outer
one wound outwards and the inner one inwards. Integrating the whole soup at once takes the
windings at face value: two nested shells both wound outwards add the cavity instead of
removing it (9000 mm^3 for a 20 mm cube with a 10 mm cavity, above its convex hull's 8000),
and every facet written twice doubles the volume. These functions, on merged
``(vertices (N, 3) mm, faces (M, 3))`` arrays, find and fix or name such faults:

* :func:`drop_duplicate_faces` -- the same triangle written twice (same vertices, same
  winding) is dropped.
* :func:`shell_labels` -- connected shells (triangles sharing an edge).
* :func:`nesting` -- which shell lies inside which, from the volume each pair shares
  (manifold3d intersection, float64): none (apart), all of the smaller (nested), anything
  else (the shells cross: refused), all of both (the same solid written twice: refused).
* :func:`orient_shells` -- a shell inside an odd number of others is a cavity and must be
  wound inwards; one wound outwards there is flipped with a note. A shell inside an even
  number (0: the outermost) wound inwards is inside-out and refused.
"""

from __future__ import annotations

import numpy as np

from cad.errors import MeshError
from cad.tolerances import SHELL_OVERLAP_REL_EPS


def _sorted_rows(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(order, same)``: a stable row sort of int array ``a`` (M, c) and, for each sorted
    row after the first, whether it equals the one before."""
    order = np.lexsort(a.T[::-1])
    s = a[order]
    return order, np.all(s[1:] == s[:-1], axis=1)


def drop_duplicate_faces(faces: np.ndarray) -> tuple[np.ndarray, int]:
    """``(faces without repeats, number dropped)``: a triangle equal to an earlier one up to
    a cyclic rotation of its vertices (same winding) is dropped; order otherwise kept.

    faces : (M, 3) int vertex indices of a MERGED mesh (coincident vertices one index).
    """
    f = np.asarray(faces, dtype=np.int64)
    rot = np.argmin(f, axis=1)[:, None]
    order, same = _sorted_rows(np.take_along_axis(f, (rot + np.arange(3)) % 3, axis=1))
    repeat = np.zeros(len(f), dtype=bool)
    repeat[order[1:][same]] = True  # stable sort: the first written of equal rows is kept
    return f[~repeat], int(repeat.sum())


def shell_labels(faces: np.ndarray) -> np.ndarray:
    """(M,) int label of the connected shell of every triangle (shared edge = connected)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    f = np.asarray(faces, dtype=np.int64)
    m = len(f)
    edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    tri = np.tile(np.arange(m), 3)
    order, same = _sorted_rows(edges)  # consecutive equal edges: triangles sharing one
    t = tri[order]
    graph = coo_matrix((np.ones(int(same.sum())), (t[:-1][same], t[1:][same])), shape=(m, m))
    return connected_components(graph, directed=False)[1]


def _groups(labels: np.ndarray, k: int) -> list[np.ndarray]:
    """Face indices of each of the ``k`` shells (one sort, not one scan per shell)."""
    order = np.argsort(labels, kind="stable")
    return np.split(order, np.cumsum(np.bincount(labels, minlength=k))[:-1])


def _solid(vertices: np.ndarray, faces: np.ndarray, outward: bool, what: str, name):
    """manifold3d solid of one closed shell (re-indexed; wound outwards for the boolean)."""
    import manifold3d

    used, local = np.unique(faces, return_inverse=True)
    f = local.reshape(-1, 3) if outward else local.reshape(-1, 3)[:, ::-1]
    solid = manifold3d.Manifold(manifold3d.Mesh64(
        vert_properties=np.ascontiguousarray(vertices[used], dtype=np.float64),
        tri_verts=np.ascontiguousarray(f, dtype=np.uint64)))
    if solid.status() != manifold3d.Error.NoError:
        raise MeshError(f"{what}: manifold3d rejects {name()} ({solid.status().name}): "
                        "its nesting with the other shells cannot be decided")
    return solid


def overlapping_pairs(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """(P, 2) int pairs ``i < j``, sorted, of the boxes whose interiors overlap
    (``lo[i] < hi[j]`` and ``hi[i] > lo[j]`` on every axis; touching boxes do not).

    lo, hi : (k, 3) box corners. A sweep along x: each box is compared only with the
    boxes that start before it ends, so k separate boxes cost O(k log k), not k^2/2.
    """
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    order = np.argsort(lo[:, 0], kind="stable")
    los, his = lo[order], hi[order]
    end = np.searchsorted(los[:, 0], his[:, 0], side="left")  # first box starting after a ends
    found = []
    for a in np.flatnonzero(end > np.arange(len(lo)) + 1):
        b = np.arange(a + 1, end[a])
        b = b[np.all(los[b] < his[a], axis=1) & np.all(his[b] > los[a], axis=1)]
        found.append(np.column_stack([np.full(len(b), order[a]), order[b]]))
    if not found:
        return np.zeros((0, 2), dtype=np.int64)
    p = np.sort(np.concatenate(found), axis=1)
    return p[np.lexsort((p[:, 1], p[:, 0]))]


def _boxes(vertices: np.ndarray, faces: np.ndarray, labels: np.ndarray, k: int):
    """(lo, hi), each (k, 3): the bounding box of every shell."""
    tri = vertices[faces]
    lo, hi = np.full((k, 3), np.inf), np.full((k, 3), -np.inf)
    np.minimum.at(lo, labels, tri.min(axis=1))
    np.maximum.at(hi, labels, tri.max(axis=1))
    return lo, hi


def nesting(vertices, faces, labels, vol, what: str, names) -> np.ndarray:
    """(P, 2) int rows ``(i, j)``: shell i lies inside shell j.

    vertices (N, 3) mm, faces (M, 3), labels (M,) shell of each face, vol (k,) signed
    volumes mm^3, ``names(s)`` a shell's description for messages. Only pairs whose
    bounding boxes overlap are intersected (:func:`overlapping_pairs`). MeshError for
    crossing or repeated shells.
    """
    size = np.abs(vol)
    groups = _groups(labels, len(vol))
    solids: dict = {}
    inside = []
    for i, j in overlapping_pairs(*_boxes(vertices, faces, labels, len(vol))).tolist():
        if 0 in (vol[i], vol[j]):
            continue
        for s in (i, j):
            if s not in solids:
                solids[s] = _solid(vertices, faces[groups[s]], bool(vol[s] > 0), what,
                                   lambda s=s: names(s))
        shared = float((solids[i] ^ solids[j]).volume())
        tol = SHELL_OVERLAP_REL_EPS * min(size[i], size[j])
        if shared <= tol:
            continue
        fills = np.abs(shared - size[[i, j]]) <= tol
        if fills.all():
            raise MeshError(f"{what}: {names(i)} and {names(j)} enclose the same "
                            f"{shared:.6g} mm^3 (the solid written twice?): drop one")
        if not fills.any():
            raise MeshError(
                f"{what}: {names(i)} crosses {names(j)} ({shared:.6g} mm^3 in both): "
                "their overlap would count twice; unite them into one shell first")
        inside.append((i, j) if fills[0] else (j, i))
    return np.array(inside, dtype=np.int64).reshape(-1, 2)


def _describe(i: int, n: int, tri: np.ndarray, origin) -> str:
    lo, hi = tri.reshape(-1, 3).min(axis=0) + origin, tri.reshape(-1, 3).max(axis=0) + origin
    box = " to ".join("(" + ", ".join(f"{x:.6g}" for x in c) + ")" for c in (lo, hi))
    return f"shell {i + 1} of {n} ({len(tri)} triangles, {box} mm)"


def orient_shells(vertices: np.ndarray, faces: np.ndarray, what: str = "mesh",
                  origin=0.0) -> tuple[np.ndarray, list[str]]:
    """``(faces, notes)`` of a closed, consistently wound mesh with every shell wound for
    its nesting: cavities (inside an odd number of shells) inwards, solids outwards.

    vertices : (N, 3) merged vertices, mm; faces : (M, 3) int. ``origin`` (mm) is added
    to the coordinates quoted in messages (the caller may have shifted the mesh).
    A cavity shell wound outwards is flipped and named in ``notes``; MeshError for a solid
    shell wound inwards (inside-out) and from :func:`nesting`.
    """
    f = np.asarray(faces, dtype=np.int64)
    labels = shell_labels(f)
    k = int(labels.max()) + 1
    if k == 1:
        return f, []
    v = np.asarray(vertices, dtype=float)
    tri = v[f]
    vol = np.bincount(labels, minlength=k, weights=np.einsum(
        "ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])) / 6.0)

    groups = _groups(labels, k)

    def names(s):
        return _describe(s, k, tri[groups[s]], origin)

    inside = nesting(v, f, labels, vol, what, names)
    depth = np.bincount(inside[:, 0], minlength=k)
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
        around_s = inside[inside[:, 0] == s, 1]
        around = int(around_s[np.argmax(depth[around_s])])  # innermost
        notes.append(f"{what}: {names(s)} lies inside shell {around + 1} but is wound "
                     f"outwards like a solid: read as a cavity ({vol[s]:.6g} mm^3 removed, "
                     "not added)")
    if flip.any():
        f = f.copy()
        f[flip[labels]] = f[flip[labels]][:, ::-1]
    return f, notes
