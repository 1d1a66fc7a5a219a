"""Issue 33 items 1 and 4 for printed parts: the wall offset is bounded and every wall count in
the bound builds.

* A contour OCCT returns as a B-spline (a turned knob cut through its fillet) that is a
  circle is offset as that circle: area pi (r - w)^2 (closed form). Any other B-spline is
  offset as a polygon of bounded size: an ellipse (a = 6, b = 4 mm, w = 0.9 mm, smallest
  radius of curvature b^2/a > w) against Steiner's formula A - P w + pi w^2 with P from
  Ramanujan's second approximation.
* Walls thick enough to close a contour (seeded wall widths on a square plate with a round
  hole) give the closed-form area (a - 2w)^2 - pi (r + w)^2 while the grown hole stays inside,
  and 0 once the square closes (print_walls 10 used to crash on 'region - hole').
* At the top of the bound (print_walls 50) a part is all wall: its printed mass is density x
  volume (closed form), whatever the infill.
* The 12 x 14 mm knob on M3 (../shared/cases/hangs/printed-knob-12mm) builds: it hung for 20
  minutes in OCCT's offset of its B-spline section.
"""

from __future__ import annotations

import math
import random
import re
from pathlib import Path

import pytest

from cad.parts import printed as P
from cad.printing import PrintSettings
from tests.cli_helpers import hapticad

ROOT = Path(__file__).resolve().parents[3]


def _spline(points):
    from build123d import Edge, Vector, Wire

    return Wire([Edge.make_spline([Vector(*p, 0) for p in points], periodic=True)])


def test_bspline_circle_is_offset_as_the_circle():
    r, w = 5.0, 0.9
    wire = _spline([(r * math.cos(t), r * math.sin(t)) for t in (2 * math.pi * k / 200 for k in range(200))])
    assert wire.edges()[0].geom_type.name == "BSPLINE"
    assert P._bounded_wire(wire).edges()[0].geom_type.name == "CIRCLE"
    assert P._offset_face(wire, w, grow=False).area == pytest.approx(math.pi * (r - w) ** 2, rel=1e-7)
    assert P._offset_face(wire, w, grow=True).area == pytest.approx(math.pi * (r + w) ** 2, rel=1e-7)


def test_other_bspline_is_offset_as_a_bounded_polygon():
    from cad.tolerances import PRINT_CONTOUR_MAX_POINTS

    a, b, w = 6.0, 4.0, 0.9
    wire = _spline([(a * math.cos(t), b * math.sin(t)) for t in (2 * math.pi * k / 400 for k in range(400))])
    poly = P._bounded_wire(wire)
    assert 16 <= len(poly.edges()) <= PRINT_CONTOUR_MAX_POINTS
    h = (a - b) ** 2 / (a + b) ** 2
    perimeter = math.pi * (a + b) * (1 + 3 * h / (10 + math.sqrt(4 - 3 * h)))  # Ramanujan II
    steiner = math.pi * a * b - perimeter * w + math.pi * w * w
    assert P._offset_face(wire, w, grow=False).area == pytest.approx(steiner, rel=1e-3)


def _plate_section(a: float, r: float):
    from build123d import Face, Plane, Wire

    outer = Wire.make_rect(a, a, Plane.XY)
    hole = Wire.make_circle(r, Plane.XY)
    return Face(outer, [hole])


def test_walls_that_close_the_part_give_the_closed_form_area():
    rng = random.Random(33)
    a, r = 20.0, 3.0
    face = _plate_section(a, r)
    ws = [rng.uniform(0.05, 3.4) for _ in range(6)] + [rng.uniform(10.0, 30.0) for _ in range(3)]
    for w in ws:
        got = P._shrunk_area_mm2([face], w)
        want = (a - 2 * w) ** 2 - math.pi * (r + w) ** 2 if w < 3.5 else 0.0
        assert got == pytest.approx(want, rel=1e-9, abs=1e-9), w
    for w in (rng.uniform(3.6, 9.9) for _ in range(4)):  # the grown hole crosses the shrunk square
        got = P._shrunk_area_mm2([face], w)
        assert 0.0 <= got <= max(0.0, a - 2 * w) ** 2 + 1e-9, w  # inside the shrunk square


@pytest.mark.parametrize("infill", [0.0, 20.0, 100.0])
def test_all_wall_part_weighs_density_times_volume(infill):
    from build123d import Box, Cylinder

    part = Box(20, 20, 6) - Cylinder(3, 6)
    s = PrintSettings(0.2, 0.45, 50, 4, infill)  # 50 walls of 0.45 mm: 22.5 mm, the part closes
    rho = 1240.0
    assert P.printed_mass_kg(part, rho, s) == pytest.approx(rho * part.volume * 1e-9, rel=1e-12)


def test_printed_knob_12mm_builds(tmp_path):
    text = (ROOT / "designs" / "hoeken_printed.toml").read_text()
    text = re.sub(r'^name = "[^"]*"', 'name = "hp_knob12"', text, count=1, flags=re.M)
    text = text.replace("[parts]\n", '[parts]\nhandle_diameter_mm = 12.0\nhandle_height_mm = 14.0\n'
                        'handle_screw = "M3-0.5"\n', 1)
    assert "handle_diameter_mm = 12.0" in text
    (tmp_path / "d.toml").write_text(text)
    code, _, err = hapticad("build", str(tmp_path / "d.toml"), "--formats", "step", "--out", str(tmp_path / "o"))
    assert code == 0, err


def test_too_many_layers_is_refused_before_the_work():
    from build123d import Box

    from cad.errors import DesignError
    from cad.tolerances import PRINT_LAYERS_MAX

    s = PrintSettings(0.05, 0.45, 2, 4, 20.0)
    tall = Box(10, 10, 0.05 * (PRINT_LAYERS_MAX + 10))
    with pytest.raises(DesignError, match=rf"parts.print_layer_height_mm: .* {PRINT_LAYERS_MAX + 10} layers"):
        P.printed_core_mm3(tall, s)


def test_seeded_knobs_give_a_core_inside_the_solid():
    """Property over the knob keys (diameter, height, fillet, screw hole, walls): a turned knob
    with a filleted top (every layer in the fillet is its own B-spline section) and a blind
    hole; the core is finite and lies in [0, volume] for every seeded sample, and is 0 when the
    walls alone are wider than the knob's radius."""
    from build123d import Axis, Cylinder, fillet

    rng = random.Random(3312)
    for _ in range(4):
        d, h = rng.uniform(8.0, 30.0), rng.uniform(5.0, 14.0)
        knob = Cylinder(d / 2, h)
        knob = fillet(knob.edges().sort_by(Axis.Z)[-1], rng.uniform(0.5, min(3.0, d / 2 - 0.5)))
        knob -= Cylinder(rng.uniform(1.2, min(3.0, d / 2 - 2.0)), h / 2).translate((0, 0, -h / 4))
        walls = rng.randint(1, 50)
        s = PrintSettings(0.2, 0.45, walls, 3, 20.0)
        core = P.printed_core_mm3(knob, s)
        assert math.isfinite(core) and 0.0 <= core <= knob.volume
        if walls * 0.45 >= d / 2:
            assert core == 0.0
