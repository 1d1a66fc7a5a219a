"""Z-buffer triangle rasterizer in plain numpy (no GPU, no Python loop over triangles).

Screen frame: pixel coordinates ``x`` to the right and ``y`` down, in pixels; the pixel of
column ``i`` and row ``j`` is sampled at its centre ``(i + 0.5, j + 0.5)``. Depth is
given per vertex, normalized to ``0..1``, **larger is nearer** the viewer; it is
interpolated linearly over each triangle (exact for an orthographic view) and compared
per pixel, so occlusion is right wherever triangles overlap or cross.

How, vectorized: every triangle is cut into the pixel rows whose centres it spans; each
(triangle, row) pair gets the span of columns inside all three edges (half-planes of the
edge functions); the spans are expanded into fragments ``(pixel, depth)`` and each pixel
keeps the nearest by ``numpy.maximum.at`` on one packed integer key per fragment: the
depth quantized to :data:`DEPTH_BITS` bits above the triangle's index + 1
(:data:`ID_BITS` bits; 0 = empty). Ties (equal quantized depth) go to the higher index.

A pixel centre on an edge shared by two triangles is inside both (the test is inclusive
by :data:`EDGE_EPS_PX`), so a closed surface shows no cracks.
"""

from __future__ import annotations

import numpy as np

from cad.tolerances import EDGE_EPS_PX, MIN_HEIGHT_PX

#: Bits of the triangle index in a key (up to 16.7 M triangles per picture).
ID_BITS = 24
#: Bits of the quantized depth (2**-32 of the scene's depth range: far below any gap).
DEPTH_BITS = 32
#: Fragments expanded at once (bounds the memory to ~ 40 bytes x this).
CHUNK_FRAGMENTS = 1 << 21
#: Key of a pixel no triangle covers (triangle ``t`` is stored as ``t + 1``).
EMPTY = 0


def empty_keys(height_px: int, width_px: int) -> np.ndarray:
    """A blank key buffer: (height_px * width_px,) int64 of :data:`EMPTY`."""
    return np.full(height_px * width_px, EMPTY, dtype=np.int64)


def _edge_bounds(px: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Per triangle and edge, the column bound of the inside as a line in the row centre
    ``y``: ``x <= a_hi * y + b_hi`` (right edges) and ``x >= a_lo * y + b_lo`` (left edges),
    each (T, 3); an edge that does not bound that side has ``a = 0, b = -+inf``.

    Inside means every edge function ``E(x, y) = s ((b - a) x (p - a))``, with ``s`` the
    triangle's orientation, is at least ``-EDGE_EPS_PX * |b - a|``. A horizontal edge
    bounds no column: the rows scanned already lie on its inner side.
    """
    T = len(px)
    a_hi, a_lo = np.zeros((T, 3)), np.zeros((T, 3))
    b_hi, b_lo = np.full((T, 3), np.inf), np.full((T, 3), -np.inf)
    d1, d2 = px[:, 1] - px[:, 0], px[:, 2] - px[:, 0]
    s = np.sign(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
    for e, (i, j) in enumerate(((0, 1), (1, 2), (2, 0))):
        ax, ay = px[:, i, 0], px[:, i, 1]
        dx, dy = px[:, j, 0] - ax, px[:, j, 1] - ay
        # E = s (dx (y - ay) - dy (x - ax)) >= -eps |d|  <=>  m x <= s dx (y - ay) + m ax + eps |d|
        m = s * dy
        hi, lo = m > 0, m < 0
        with np.errstate(divide="ignore", invalid="ignore"):
            slope = s * dx / m
            icpt = ax - slope * ay + EDGE_EPS_PX * np.hypot(dx, dy) / m
        a_hi[hi, e], b_hi[hi, e] = slope[hi], icpt[hi]
        a_lo[lo, e], b_lo[lo, e] = slope[lo], icpt[lo]
    return a_hi, b_hi, a_lo, b_lo


def _row_spans(px: np.ndarray, height_px: int, width_px: int):
    """For every (triangle, pixel row) pair: triangle index, row, first and last column.

    px : (T, 3, 2) vertex pixel coordinates. Returns ``(tri, row, c0, c1)``, int64 arrays
    of equal length, only non-empty spans (``c0 <= c1``), clipped to the picture.
    """
    y0, y1, y2 = px[:, 0, 1], px[:, 1, 1], px[:, 2, 1]
    r0 = np.ceil(np.minimum(np.minimum(y0, y1), y2) - 0.5)
    r1 = np.floor(np.maximum(np.maximum(y0, y1), y2) - 0.5)
    r0 = np.clip(r0, 0, height_px).astype(np.int64)
    r1 = np.clip(r1, -1, height_px - 1).astype(np.int64)
    n = np.maximum(r1 - r0 + 1, 0)
    rows = np.nonzero(n)[0]  # most small triangles span no pixel centre row
    px, r0, n = px[rows], r0[rows], n[rows]
    tri = np.repeat(np.arange(len(px)), n)
    row = np.arange(len(tri)) + np.repeat(r0 - (np.cumsum(n) - n), n)
    yc = row + 0.5
    a_hi, b_hi, a_lo, b_lo = (np.ascontiguousarray(a.T) for a in _edge_bounds(px))
    hi = np.minimum(
        np.minimum(a_hi[0][tri] * yc + b_hi[0][tri], a_hi[1][tri] * yc + b_hi[1][tri]),
        a_hi[2][tri] * yc + b_hi[2][tri],
    )
    lo = np.maximum(
        np.maximum(a_lo[0][tri] * yc + b_lo[0][tri], a_lo[1][tri] * yc + b_lo[1][tri]),
        a_lo[2][tri] * yc + b_lo[2][tri],
    )
    tri = rows[tri]
    c0 = np.clip(np.ceil(lo - 0.5), 0, width_px).astype(np.int64)
    c1 = np.clip(np.floor(hi - 0.5), -1, width_px - 1).astype(np.int64)
    keep = c0 <= c1
    return tri[keep], row[keep], c0[keep], c1[keep]


def _depth_planes(px: np.ndarray, depth: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per triangle ``(z0, gx, gy)``: depth = z0 + gx * x + gy * y over its plane."""
    d1, d2 = px[:, 1] - px[:, 0], px[:, 2] - px[:, 0]
    z1, z2 = depth[:, 1] - depth[:, 0], depth[:, 2] - depth[:, 0]
    det = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    gx = (z1 * d2[:, 1] - z2 * d1[:, 1]) / det
    gy = (d1[:, 0] * z2 - d2[:, 0] * z1) / det
    z0 = depth[:, 0] - gx * px[:, 0, 0] - gy * px[:, 0, 1]
    return z0, gx, gy


def rasterize(
    px: np.ndarray, depth: np.ndarray, keys: np.ndarray, width_px: int, id_offset: int = 0
) -> np.ndarray:
    """Draw triangles into a key buffer (in place) and return it.

    px : (T, 3, 2) float, vertex pixel coordinates (x right, y down).
    depth : (T, 3) float in 0..1, larger is nearer (clipped to 0..1).
    keys : (H * W,) int64 from :func:`empty_keys` (or an earlier call: drawing adds).
    id_offset : index of the first triangle; triangle ``t`` is stored as ``id_offset + t``.
    Triangles thinner than :data:`MIN_HEIGHT_PX` are skipped. Raises ValueError
    from ``2**ID_BITS - 1`` triangles on.
    """
    px = np.asarray(px, dtype=float)
    depth = np.asarray(depth, dtype=float)
    if id_offset + len(px) >= 1 << ID_BITS:
        raise ValueError(f"{id_offset + len(px)} triangles: fewer than {1 << ID_BITS} per picture")
    height_px = len(keys) // width_px
    idx = np.nonzero(_min_height_px(px) > MIN_HEIGHT_PX)[0]
    px, depth = px[idx], depth[idx]
    z0, gx, gy = _depth_planes(px, depth)
    tri, row, c0, c1 = _row_spans(px, height_px, width_px)
    # per span: first pixel, depth there and its step along the row, stored id
    width = c1 - c0 + 1
    base = row * width_px + c0
    z_first = z0[tri] + gx[tri] * (c0 + 0.5) + gy[tri] * (row + 0.5)
    z_step = gx[tri]
    ident = idx[tri] + (id_offset + 1)
    ends = np.cumsum(width)
    scale = float(1 << DEPTH_BITS)
    first = 0
    while first < len(tri):
        last = int(np.searchsorted(ends, ends[first] - width[first] + CHUNK_FRAGMENTS, "right"))
        last = max(last, first + 1)
        w = width[first:last]
        span = np.repeat(np.arange(first, last), w)  # the span of each fragment
        k = np.arange(len(span)) - (np.cumsum(w) - w).take(span - first)  # column in span
        z = z_first.take(span) + z_step.take(span) * k
        np.clip(z, 0.0, 1.0, out=z)
        key = (z * scale).astype(np.int64) << ID_BITS
        key |= ident.take(span)
        np.maximum.at(keys, base.take(span) + k, key)
        first = last
    return keys


def _min_height_px(px: np.ndarray) -> np.ndarray:
    """Smallest height of each triangle (px): twice its area over its longest edge."""
    d1, d2, d3 = px[:, 1] - px[:, 0], px[:, 2] - px[:, 0], px[:, 2] - px[:, 1]
    area2 = np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])
    longest2 = np.maximum(
        np.maximum(d1[:, 0] ** 2 + d1[:, 1] ** 2, d2[:, 0] ** 2 + d2[:, 1] ** 2),
        d3[:, 0] ** 2 + d3[:, 1] ** 2,
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(longest2 > 0, area2 / np.sqrt(longest2), 0.0)


def triangle_ids(keys: np.ndarray) -> np.ndarray:
    """Index + 1 of the nearest triangle at each pixel (0 where empty), shape of ``keys``:
    ``palette[triangle_ids(keys)]`` colours a picture whose ``palette[0]`` is the
    background."""
    return keys & ((1 << ID_BITS) - 1)
