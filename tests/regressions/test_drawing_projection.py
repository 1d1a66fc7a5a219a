"""Issue 32 item 5: every view of a drawing sits where the projection its title block names puts
it (reproducer ``cases/outputs-agree/drawing-first-angle-layout``, inputs copied into
``data/drawing_first_angle/``).

Independent reference: ISO 5456-2 / ISO 128-30. First-angle: the view from above (+z) sits
BELOW the front view, the view from the right (+x) LEFT of it, the view from the left (-x)
RIGHT of it; third-angle mirrors both. Which way a view looks is read from the drawn edges,
not from the code: the case's stepped handle (16 x 20 x 12 mm, its +y end, y > 4, stepped
down to 6 mm) shows its tall end on the LEFT of a view from +x (a viewer at +x looking -x
with z up has part +y to his right) and on the RIGHT of a view from -x. The SVG is read with
xml.etree: view labels (text FRONT/TOP/SIDE), the visible edges (black 0.45 pt paths),
feature tags (blue text) and their marks.
"""

from __future__ import annotations

import re
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from tests.cli_helpers import hapticad

DATA = Path(__file__).parent / "data" / "drawing_first_angle"
NS = "{http://www.w3.org/2000/svg}"
PT_MM = 25.4 / 72.0
#: The handle's box (step_handle.py): x, y, z extents (mm) and the step at y = 4 (z > 6 removed).
HANDLE_MM = (16.0, 20.0, 12.0)
#: Matplotlib writes coordinates with 6 significant digits: a drawn point is within this (mm).
DRAWN_MM = 0.01


def _read(svg: Path):
    """(title text, scale, {label: (x, y) mm, y up}, [visible-edge polylines (mm, y up)],
    [(tag text, x, y)])."""
    root = ET.parse(svg).getroot()
    h_pt = float(root.get("height").rstrip("pt"))
    labels, tags, title, scale = {}, [], "", None
    for t in root.iter(NS + "text"):
        text = "".join(t.itertext())
        if t.get("x") is None:  # a rotated dimension text (translate + rotate)
            continue
        xy = (float(t.get("x")) * PT_MM, (h_pt - float(t.get("y"))) * PT_MM)
        if text in ("FRONT", "TOP", "SIDE"):
            labels[text] = xy
        m = re.search(r"scale (\d+(?:\.\d+)?):(\d+(?:\.\d+)?)", text)
        if m:
            title, scale = text, float(m.group(1)) / float(m.group(2))
        if "1f77b4" in (t.get("style") or ""):
            tags.append((text, *xy))
    lines = []
    for p in root.iter(NS + "path"):
        st = p.get("style", "")
        if "stroke: #000000" in st and "stroke-width: 0.45" in st and "dasharray" not in st:
            v = [float(x) for x in re.findall(r"-?\d+\.?\d*(?:e-?\d+)?", p.get("d"))]
            lines.append([(v[i] * PT_MM, (h_pt - v[i + 1]) * PT_MM) for i in range(0, len(v) - 1, 2)])
    return title, scale, labels, lines, tags


def _centres(labels: dict, s: float, ext: dict) -> dict:
    """View centres (mm): a label sits 2 mm above its view (height ``ext[label]`` at scale s)."""
    return {k: (x, y - s * ext[k] / 2 - 2) for k, (x, y) in labels.items()}


def _side_looks_from(lines, centre, s) -> str:
    """"+x" or "-x": where the drawn 12 mm tall end of the handle lies in the side view."""
    cx, cy = centre
    x_, y_, z_ = HANDLE_MM
    top = [x - cx for line in lines for x, y in line
           if abs(x - cx) <= s * y_ / 2 + DRAWN_MM and abs(y - cy - s * z_ / 2) < DRAWN_MM]
    assert top, "no edge at the handle's full height in the side view"
    # the tall end spans y in [-10, 4]: 14 of 20 mm; its top edge centre is left or right
    mid = 0.5 * (min(top) + max(top))
    assert abs(abs(mid) - s * 3.0) < DRAWN_MM, (min(top), max(top))
    return "+x" if mid < 0 else "-x"


@pytest.fixture(scope="module")
def sheet(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("first_angle")
    for f in DATA.iterdir():
        shutil.copy(f, tmp / f.name)
    code, _, err = hapticad("build", tmp / "step_handle.toml", "--fidelity", "inertia",
                            "--formats", "step,drawings", "--allow-scripts", "--out", tmp / "out")
    assert code == 0, err
    return _read(tmp / "out" / "drawings" / "handle.svg")


def test_every_view_sits_where_the_stated_projection_puts_it(sheet):
    title, s, labels, lines, _ = sheet
    assert s == 2.0  # the case's sheet: 16 x 20 x 12 mm at 2:1
    ctr = _centres(labels, s, {"FRONT": HANDLE_MM[2], "SIDE": HANDLE_MM[2], "TOP": HANDLE_MM[1]})
    looks = _side_looks_from(lines, ctr["SIDE"], s)
    side_right = ctr["SIDE"][0] > ctr["FRONT"][0]
    top_below = ctr["TOP"][1] < ctr["FRONT"][1]
    # views in line: side level with the front view, top under / over it
    assert abs(ctr["SIDE"][1] - ctr["FRONT"][1]) < DRAWN_MM
    assert abs(ctr["TOP"][0] - ctr["FRONT"][0]) < DRAWN_MM
    first = top_below and side_right == (looks == "-x")
    third = (not top_below) and side_right == (looks == "+x")
    if "first-angle" in title:
        assert first, (title, looks, side_right, top_below)
    else:
        assert "third-angle" in title and third, (title, looks, side_right, top_below)
    # this sheet: first-angle, the view from the left (-x) right of the front view
    assert "first-angle projection" in title and looks == "-x" and side_right and top_below


def test_the_side_view_tag_sits_on_its_hole(tmp_path):
    """A hole along x at y = +5 of a 30 x 20 x 10 mm block: seen from -x it is drawn LEFT of the
    side view's centre; the tag's mark (+) sits at the circle's centre."""
    import build123d as bd

    from cad.export.drawings import SheetPart, write_drawings

    box = bd.Box(30, 20, 10) - bd.Cylinder(1.5, 40, rotation=(0, 90, 0)).moved(bd.Location((0, 5, 0)))
    part = SheetPart("block", box.wrapped, "aluminium-6061", 1, "machined", False)
    svg = write_drawings([part], tmp_path, "t")[0]
    title, s, labels, lines, tags = _read(svg)
    ctr = _centres(labels, s, {"FRONT": 10.0, "SIDE": 10.0, "TOP": 20.0})
    cx, cy = ctr["SIDE"]
    circle = [(x, y) for line in lines if len(line) > 8 for x, y in line
              if abs(x - cx) < s * 10 + 1 and abs(y - cy) < s * 5]
    assert circle, "the x hole's circle is not drawn in the side view"
    ux = 0.5 * (min(x for x, _ in circle) + max(x for x, _ in circle))
    uy = 0.5 * (min(y for _, y in circle) + max(y for _, y in circle))
    assert abs(ux - (cx - s * 5.0)) < DRAWN_MM and abs(uy - cy) < DRAWN_MM  # +y runs left
    side_tags = [(x, y) for t, x, y in tags if abs(x - cx) < s * 10 + 2 and abs(y - cy) < s * 5 + 2]
    assert len(side_tags) == 1
    tx, ty = side_tags[0]
    assert abs(tx - 0.8 - ux) < DRAWN_MM and abs(ty - 0.8 - uy) < DRAWN_MM  # text at mark + 0.8 mm
