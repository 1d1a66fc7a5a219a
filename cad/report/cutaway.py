"""Quarter cut-away of triangle meshes for the pictures (plain numpy).

A closed housing hides what moves inside it (the PowerMouse's flotor and coils in its
magnet box). :func:`cut_quarter` removes the quarter of the given triangles that faces the
viewer: the region ``sx (x - cx) > 0 and sy (y - cy) > 0`` (world R0, ``(cx, cy)`` the cut
centre, ``sx, sy`` the signs of the view direction's x and y). Triangles crossing either
plane are split along it (:func:`split_by_plane`, winding kept, so back-face culling
still works); the cut walls are left open (no caps), as in a drawn cut-away.
"""

from __future__ import annotations

import numpy as np


def split_by_plane(tris: np.ndarray, normal, offset: float) -> tuple[np.ndarray, np.ndarray]:
    """Triangles (T, 3, 3) cut by the plane ``normal . p = offset``: every triangle with
    vertices on both sides replaced by three (one on the lone vertex's side, two on the
    other), with the same winding. Returns ``(triangles (T', 3, 3), index of the source
    triangle of each (T',))``."""
    tris = np.asarray(tris, dtype=float)
    s = tris @ np.asarray(normal, dtype=float) - offset  # (T, 3) signed distances
    pos = s > 0
    n_pos = pos.sum(axis=1)
    cross = (n_pos == 1) | (n_pos == 2)
    keep = np.nonzero(~cross)[0]
    idx = np.nonzero(cross)[0]
    lone = np.where(n_pos[idx] == 1, np.argmax(pos[idx], axis=1), np.argmin(pos[idx], axis=1))
    order = (lone[:, None] + np.arange(3)) % 3  # the lone vertex first, cyclic: winding kept
    v = np.take_along_axis(tris[idx], order[:, :, None], axis=1)
    d = np.take_along_axis(s[idx], order, axis=1)
    p01 = v[:, 0] + (v[:, 1] - v[:, 0]) * (d[:, 0] / (d[:, 0] - d[:, 1]))[:, None]
    p02 = v[:, 0] + (v[:, 2] - v[:, 0]) * (d[:, 0] / (d[:, 0] - d[:, 2]))[:, None]
    new = np.concatenate([
        np.stack([v[:, 0], p01, p02], axis=1),
        np.stack([p01, v[:, 1], v[:, 2]], axis=1),
        np.stack([p01, v[:, 2], p02], axis=1),
    ])
    return np.concatenate([tris[keep], new]), np.concatenate([keep, idx, idx, idx])


def cut_quarter(tris: np.ndarray, centre_mm, toward) -> tuple[np.ndarray, np.ndarray]:
    """World triangles (T, 3, 3) mm without the quarter facing the viewer (module doc);
    ``toward``: the unit vector towards the viewer (world). Returns ``(triangles, index
    of the source triangle of each)``."""
    cx, cy = float(centre_mm[0]), float(centre_mm[1])
    sx, sy = (1.0 if toward[0] >= 0 else -1.0), (1.0 if toward[1] >= 0 else -1.0)
    t, src = split_by_plane(tris, (1.0, 0.0, 0.0), cx)
    t, src2 = split_by_plane(t, (0.0, 1.0, 0.0), cy)
    src = src[src2]
    c = t.mean(axis=1)
    out = (sx * (c[:, 0] - cx) > 0) & (sy * (c[:, 1] - cy) > 0)
    return t[~out], src[~out]
