"""The numpy z-buffer rasterizer (cad.report.raster) against closed forms.

* two overlapping squares at different depths: the pixel counts of each are the counts of
  pixel centres inside the rectangles (closed form), whatever the drawing order;
* two squares crossing each other (depth linear in x, opposite slopes): each pixel shows
  the nearer one, switching exactly at the crossing line -- what a painter's algorithm
  sorting whole triangles cannot do;
* a triangle fan of a regular 96-gon (a closed surface of thin triangles): every pixel
  centre inside its inscribed circle is covered (no cracks between triangles), none
  outside its circumscribed circle;
* a cube turned by a seeded random rotation, all 12 triangles drawn: the covered area is
  its projected (silhouette) area ``a^2 (|d_x| + |d_y| + |d_z|)`` for the view direction
  ``d`` in the cube frame, and each visible face shows ``a^2 |d_i|`` pixels; faces turned
  away are hidden by depth alone.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from cad.report import raster


def _square(x0, y0, x1, y1, z0, z1=None):
    """Two triangles of the rectangle; depth z0 at x0 and z1 at x1 (linear in x)."""
    z1 = z0 if z1 is None else z1
    px = np.array([[[x0, y0], [x1, y0], [x1, y1]], [[x0, y0], [x1, y1], [x0, y1]]], float)
    z = np.array([[z0, z1, z1], [z0, z1, z0]], float)
    return px, z


def _centres_inside(lo: float, hi: float) -> int:
    """Pixel centres i + 0.5 in [lo, hi]."""
    return math.floor(hi - 0.5) - math.ceil(lo - 0.5) + 1


def _draw(parts, W=100, H=80):
    keys = raster.empty_keys(H, W)
    offset = 0
    for px, z in parts:
        raster.rasterize(px, z, keys, W, offset)
        offset += len(px)
    return raster.triangle_ids(keys).reshape(H, W)


@pytest.mark.parametrize("near_first", [True, False])
def test_overlapping_squares_counts_match_closed_form(near_first):
    near = _square(10.3, 12.7, 50.3, 44.2, 0.8)
    far = _square(30.6, 25.1, 71.9, 66.4, 0.2)
    parts = [near, far] if near_first else [far, near]
    ids = _draw(parts)
    near_ids = {1, 2} if near_first else {3, 4}
    n_near = int(np.isin(ids, list(near_ids)).sum())
    n_far = int(((ids > 0) & ~np.isin(ids, list(near_ids))).sum())
    a = _centres_inside(10.3, 50.3) * _centres_inside(12.7, 44.2)
    b = _centres_inside(30.6, 71.9) * _centres_inside(25.1, 66.4)
    overlap = _centres_inside(30.6, 50.3) * _centres_inside(25.1, 44.2)
    assert n_near == a
    assert n_far == b - overlap
    assert int((ids == 0).sum()) == 100 * 80 - a - b + overlap


def test_crossing_squares_switch_at_the_crossing_line():
    # A: depth 0.2 at x = 20 rising to 0.8 at x = 80; B: 0.8 falling to 0.2.
    # They cross at x = 50: left of it B is nearer, right of it A.
    a = _square(20.0, 10.0, 80.0, 70.0, 0.2, 0.8)
    b = _square(20.0, 10.0, 80.0, 70.0, 0.8, 0.2)
    ids = _draw([a, b])
    rows = slice(11, 69)
    left, right = ids[rows, 20:50], ids[rows, 50:80]  # centres 20.5..49.5 | 50.5..79.5
    assert np.isin(left, [3, 4]).all()
    assert np.isin(right, [1, 2]).all()


def test_fan_has_no_cracks():
    n, r, c = 96, 30.0, np.array([40.3, 37.8])
    t = np.linspace(0, 2 * np.pi, n + 1)
    ring = c + r * np.c_[np.cos(t), np.sin(t)]
    px = np.stack([np.broadcast_to(c, (n, 2)), ring[:-1], ring[1:]], axis=1)
    ids = _draw([(px, np.full((n, 3), 0.5))], W=80, H=80)
    yy, xx = np.mgrid[0:80, 0:80] + 0.5
    d = np.hypot(xx - c[0], yy - c[1])
    assert (ids[d < r * math.cos(math.pi / n) - 1e-9] > 0).all()
    assert (ids[d > r] == 0).all()


def _cube(a: float):
    """Vertices (8, 3) of the cube [0, a]^3 and its 12 outward triangles (CCW from outside)."""
    v = np.array([[x, y, z] for x in (0, a) for y in (0, a) for z in (0, a)], float)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    f = [t for q in quads for t in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]
    return v, np.array(f)


def test_cube_silhouette_and_face_areas():
    from scipy.spatial.transform import Rotation

    a, W = 120.0, 400
    R = Rotation.random(random_state=7).as_matrix()
    v, f = _cube(a)
    p = (v - a / 2) @ R.T  # x right, y up, z toward the viewer
    px = np.c_[W / 2 + p[:, 0], W / 2 - p[:, 1]][f]  # y down on screen
    z = (p[:, 2] + a) / (4 * a)
    ids = _draw([(px, z[f])], W=W, H=W)
    d = R.T @ np.array([0.0, 0.0, 1.0])  # the view direction in the cube frame
    silhouette = a * a * np.abs(d).sum()
    covered = int((ids > 0).sum())
    assert covered == pytest.approx(silhouette, rel=0.01)
    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])  # outward normals
    for face in range(6):
        tri = [2 * face + 1, 2 * face + 2]  # stored ids (index + 1)
        shown = int(np.isin(ids, tri).sum())
        facing = n[2 * face] @ d
        if facing <= 0:
            assert shown == 0, face
        else:
            assert shown == pytest.approx(a * a * facing / np.linalg.norm(n[2 * face]), rel=0.02)


def test_too_many_triangles_is_refused():
    px, z = _square(0, 0, 1, 1, 0.5)
    with pytest.raises(ValueError, match="triangles"):
        raster.rasterize(px, z, raster.empty_keys(4, 4), 4, id_offset=(1 << raster.ID_BITS) - 2)


def _box_instance(name, body, size_mm, at_mm):
    from types import SimpleNamespace

    v, f = _cube(1.0)
    v = v * np.asarray(size_mm, float)
    T = np.eye(4)
    T[:3, 3] = at_mm
    kind = SimpleNamespace(name=name, listed=True)
    return SimpleNamespace(name=name, body=body, kind=kind, tf_body_part=T), (v, f)


def test_stroke_frames_equal_a_full_redraw(monkeypatch):
    """The GIF path draws the fixed bodies once and redraws only the box the moving ones
    sweep: every frame must equal drawing the whole scene again (no body fixed)."""
    from cad.report import render

    base, base_mesh = _box_instance("base", "ground", (100, 80, 5), (0, 0, 0))
    post, post_mesh = _box_instance("post", "ground", (8, 8, 40), (10, 10, 5))
    link, link_mesh = _box_instance("link", "crank", (40, 10, 4), (0, 0, 0))
    meshes = {"base": base_mesh, "post": post_mesh, "link": link_mesh}
    colors = {"base": (0.6, 0.6, 0.6), "post": (0.4, 0.4, 0.4), "link": (0.2, 0.4, 0.8)}
    n = 5
    ground = np.broadcast_to(np.eye(4), (n, 4, 4))
    crank = np.repeat(np.eye(4)[None], n, axis=0)
    for k, a in enumerate(np.linspace(0, np.pi / 2, n)):  # turns about the post, above it
        crank[k, :3, :3] = [[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]]
        crank[k, :3, 3] = (14, 14, 46)
    tfs = {"ground": ground, "crank": crank}
    args = ([base, post, link], tfs, meshes, colors, list(range(n)))
    split = [np.asarray(im) for im in render.render_images(*args, size_px=(160, 120))]
    monkeypatch.setattr(render, "_static_bodies", lambda *a: set())
    full = [np.asarray(im) for im in render.render_images(*args, size_px=(160, 120))]
    for a, b in zip(split, full, strict=True):
        assert np.array_equal(a, b)
    assert not np.array_equal(split[0], split[-1])  # the link moved
