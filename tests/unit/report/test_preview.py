"""preview.png's outlines (cad.report.preview) against closed-form areas.

* a box turned 30 deg about z: its top-view outline is the box's w x d rectangle (area
  w d), its side-view outline the x-z box of the turned rectangle
  ((w cos + d sin) x h);
* a plate (drawn by its upward faces) with a through hole: area w d - pi r^2 (the hole
  shows), to the polygonal approximation of the coarse mesh (< 1 %);
* a fixed ("ground") part wholly below the hiding height is left out of the top view only;
* the PNG is written and read back by Pillow at the figure's size.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest


def _area(poly: np.ndarray) -> float:
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * abs(np.dot(x, np.roll(y, 1)) - np.dot(y, np.roll(x, 1)))


@pytest.fixture(scope="module")
def scene():
    from build123d import Box, Cylinder, Pos

    box = Box(40, 20, 10).wrapped
    plate = (Box(60, 30, 5) - Pos(10, 0, 0) * Cylinder(6, 10)).solids()[0].wrapped
    leg = Box(5, 5, 30).wrapped

    def inst(name, body, shape, T, plate=False):
        kind = SimpleNamespace(name=name, shape=shape, plate=plate, listed=True)
        return SimpleNamespace(name=name, body=body, kind=kind, tf_body_part=T)

    a = math.radians(30)
    turn = np.eye(4)
    turn[:3, :3] = [[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]]
    turn[:3, 3] = (5, 7, 20)
    low = np.eye(4)
    low[2, 3] = -20  # z -35 .. -5: wholly below the plate
    items = [
        inst("plate", "ground", plate, np.eye(4), plate=True),
        inst("leg", "ground", leg, low),
        inst("box", "crank", box, turn),
    ]
    tf = {"ground": np.eye(4), "crank": np.eye(4)}
    return items, tf, a


def test_outline_areas_match_closed_forms(scene):
    from cad.report.preview import projection_polygons

    items, tf, a = scene
    top, side = projection_polygons(items, tf, hide_ground_below_mm=-1.0)
    (box_top,) = top["crank"]
    assert _area(box_top) == pytest.approx(40 * 20, rel=1e-9)
    (box_side,) = side["crank"]
    assert _area(box_side) == pytest.approx((40 * math.cos(a) + 20 * math.sin(a)) * 10, rel=1e-9)
    plate_top = sum(_area(t) for t in top["ground"])
    assert plate_top == pytest.approx(60 * 30 - math.pi * 36, rel=0.01)
    assert plate_top < 60 * 30 - 0.9 * math.pi * 36  # the hole is not filled in
    assert len(side["ground"]) == 2  # the leg is in the side view ...
    top_all, _ = projection_polygons(items, tf)
    leg_area = sum(_area(t) for t in top_all["ground"]) - plate_top
    assert leg_area == pytest.approx(25, rel=1e-9)  # ... and hidden only when asked


def test_preview_png_is_written(scene, tmp_path):
    from PIL import Image

    from cad.report.preview import write_preview

    items, tf, _ = scene
    out = write_preview(
        items, tf, tmp_path / "preview.png", "t", marks=[("path", [[0, 0], [9, 9]])]
    )
    with Image.open(out) as im:
        assert im.size == (1100, 500)  # 11 x 5 in at 100 dpi
        assert len(np.unique(np.asarray(im.convert("RGB")).reshape(-1, 3), axis=0)) > 20
