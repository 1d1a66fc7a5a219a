"""The twin pantograph's capstan solids (issue 35 §1): designs/twin_pantograph_capstan.toml, the
bundled mouse's linkage with a 4.25:1 capstan (32 mm capstan, 136 mm drum, 0.8 mm 7x7 rope, 3
turns) on all four motors. The knob pantograph's drums in one band under the bridge, its motors
moved on the bridge; the crank pantograph's drums in two bands (they meet in one), its right
motor raised with its mount plate on the base plate's top so its shaft reaches band 2's capstan;
the bridge posts stepped back out of every drum's sweep.

References, each independent of the code under test:

* the mirror onto the knob side: the explicit reflection of points (seeded rigid transforms),
  not the code's matrix product;
* the layout: the direct mouse's layout (designs/haptic_mouse.toml, the same linkage) and the
  drum bands, motor places, shaft reach and bridge extent by hand from the design's and the
  catalog's numbers;
* the posts: the exact distance from each post's centre to each drum's widened annular sector at
  every workspace pose (a second method; the layout samples the post's circle against the arcs);
* the build (slow): its own every-pair check over the motion, and assembly.step read back with
  OCCT (the common volume of each drum, capstan and rope run with every plate, post, motor, mount,
  bearing block and link part at home, and of the raised motor with the base plate); the drum's
  volume in closed form (annular sector less the anchors' radial holes and the groove by
  Pappus); the rope run's as a cylinder on the two pitch circles' external tangent,
  sqrt(C^2 - (R - r)^2); the rope BOM lines and winding steps against the shared capstan
  functions.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from tests.capstan_ref import sector_distance_mm
from tests.step_readback import common_mm3
from tests.step_readback import step_solids as read_step_solids

ROOT = Path(__file__).resolve().parents[3]
DESIGN = ROOT / "designs" / "twin_pantograph_capstan.toml"
MOUSE = ROOT / "designs" / "haptic_mouse.toml"
#: The drum's reach by hand: crests (136 - 0.8) / 2 + 0.35 x 0.8 = 67.88 mm, and the tensioner out
#: of them: ISO 4032 M3 nut 2.4 mm + 3 rope diameters 2.4 mm + ISO 4762 M3 head 3 mm.
REACH_MM = 67.88 + 2.4 + 2.4 + 3.0
MARGIN_DEG = 2.0  # cad.tolerances.CAPSTAN_RANGE_MARGIN_DEG
#: Centre distance by hand: the pitch circles 136 / 2 + 32 / 2 = 84 mm plus the 2 mm rim gap.
C_MM = 86.0


@pytest.fixture(scope="module")
def design():
    from cad.design import load_design

    return load_design(DESIGN)


@pytest.fixture(scope="module")
def lay(design):
    from cad.families.pantograph.layout import layout

    return layout(design)


def _angles(design, cols):
    from cad.kinematics import twin_pantograph as ktwin

    return np.degrees(np.unwrap(ktwin.ik(design.mechanism, design.workspace_points()).q_rad, axis=0))[:, cols]


def _sector_distance(p, s, q) -> float:
    """:func:`tests.capstan_ref.sector_distance_mm` with this design's reach and margin."""
    return sector_distance_mm(p, s, q, REACH_MM, MARGIN_DEG)


# ----------------------------------------------------------------------------- fast: layout
def test_mirrored_places_a_part_as_its_mirror_image_about_the_bridge_plane():
    """For seeded planar placements (a turn about z and a shift), where the crank side's
    placement puts a point (x, y, z) of a part at (X, Y, Z) (Z above the base plate's top), the
    knob side's puts the part's mirror point (x, -y, z) at (X, Y, z_b - Z) (Z under the bridge's
    bottom z_b): a part symmetric about its x-z plane lands as its mirror image; the placement
    stays a rotation."""
    from cad.families.pantograph.capstan_solids import mirrored

    rng = np.random.default_rng(35)
    for _ in range(20):
        a, zb = rng.uniform(-math.pi, math.pi), rng.uniform(50.0, 150.0)
        tf = np.eye(4)
        tf[:2, :2] = [[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]]
        tf[:3, 3] = rng.uniform(-100.0, 100.0, 3)
        up = mirrored(tf, zb)
        assert np.linalg.det(up[:3, :3]) == pytest.approx(1.0, abs=1e-12)
        for p in rng.uniform(-20.0, 20.0, (5, 3)):
            lo = tf @ np.append(p, 1.0)
            got = up @ np.array([p[0], -p[1], p[2], 1.0])
            np.testing.assert_allclose(got[:3], [lo[0], lo[1], zb - lo[2]], atol=1e-9)
    assert np.array_equal(mirrored(tf, None), tf)


def test_the_drum_bands_lift_the_layers_and_move_the_motors(design, lay):
    """Against the direct mouse (the same linkage): the crank pantograph's two bands lift every
    layer by 2 x (10 mm drum + 3 mm gap) = 26 mm, the knob's band lifts the bridge 13 mm more;
    the crank's rope planes 3 + 10 / 2 = 8 mm (band 1, left) and 8 + 13 = 21 mm (band 2, right)
    over the base plate, the knob's 8 mm under the bridge; each knob motor at B + 86 mm
    (cos a, sin a), a = -175 / -5 deg, each crank motor at -165 / -15 deg (mirrored about the y
    axis); the bridge grows to the knob motors' 55 mm mount plates plus 5 mm:
    x = +-(37.5 + 86 cos 5 deg + 27.5 + 5); no motor shaft in a hub (each link on its own axle)."""
    from cad.design import load_design
    from cad.families.pantograph.layout import layout

    ref = layout(load_design(MOUSE))
    np.testing.assert_allclose(lay["lower_layers_z_mm"], np.add(ref["lower_layers_z_mm"], 26.0), atol=1e-12)
    np.testing.assert_allclose(lay["upper_layers_z_mm"], np.add(ref["upper_layers_z_mm"], 26.0), atol=1e-12)
    zb = lay["bridge_bottom_z_mm"]
    assert zb == pytest.approx(ref["bridge_bottom_z_mm"] + 26.0 + 13.0, abs=1e-12)
    knob, crank = lay["twin_capstan"]["knob"], lay["twin_capstan"]["crank"]
    assert knob["bands"] == (1, 1) and crank["bands"] == (1, 2)
    assert knob["side_z_mm"] == ((zb - 8.0, (zb - 13.0, zb - 3.0)),) * 2
    assert crank["side_z_mm"] == ((8.0, (3.0, 13.0)), (21.0, (16.0, 26.0)))
    for grp, angles in ((knob, (-175.0, -5.0)), (crank, (-165.0, -15.0))):
        for s, bx, a in zip(grp["sides"], (-37.5, 37.5), angles, strict=True):
            assert s.alpha_deg == a
            np.testing.assert_allclose(s.motor_xy_mm, (bx + C_MM * math.cos(math.radians(a)),
                                                       C_MM * math.sin(math.radians(a))), atol=1e-9)
    x_edge = 37.5 + C_MM * math.cos(math.radians(5.0)) + 27.5 + 5.0
    np.testing.assert_allclose(lay["bridge_x_mm"], (-x_edge, x_edge), atol=1e-9)
    assert "upper_shaft_engagement_mm" not in lay and "lower_shaft_engagement_mm" not in lay


def test_the_raised_motor_reaches_band_2s_capstan(design, lay):
    """Band 2's capstan (3 turns of 0.8 mm rope at 1.5 d pitch above an 8 mm hub, its turns'
    middle in the 21 mm rope plane): bottom 21 - 8 - 1.8 = 11.2 mm, hub top 19.2 mm over the base
    plate. A motor under the plate has its 22 mm shaft's tip at 22 - 6 - 5 = 11 mm (8.2 mm short);
    raised by the plate and its mount plate, 6 + 5 = 11 mm, the tip is at 22 mm (2.8 mm over the
    hub's top) and the face screws' heads (M3, 3 mm) on the 5 mm mount plate end at 8 mm, under
    the capstan's bottom."""
    from cad.device import resolve_device
    from cad.families.pantograph import twin_placement as tp
    from cad.families.pantograph.capstan_solids import capstan_z_mm

    crank = lay["twin_capstan"]["crank"]
    assert crank["raise_mm"] == (0.0, 11.0) and tp.motor_raise_mm(design) == 11.0
    t = resolve_device(design).transmission("crank_q_right")
    zc = capstan_z_mm(design, t, crank["side_z_mm"][1][0])
    assert zc == pytest.approx(11.2, abs=1e-12) and zc + 8.0 == pytest.approx(19.2, abs=1e-12)
    assert tp.shaft_shortfall_mm(design, t, 2) == pytest.approx(8.2, abs=1e-12)
    tip = -6.0 - 5.0 + 22.0 + crank["raise_mm"][1]
    assert tip - (zc + 8.0) == pytest.approx(2.8, abs=1e-12) and 5.0 + 3.0 < zc


def test_the_bridge_posts_stand_clear_of_every_drum_at_every_pose(design, lay):
    """Each post (12 mm, the 1 mm clearance) on the layout's line stays more than 6 + 1 mm from
    each of the four drums' widened sectors at every workspace pose (the exact point-to-sector
    distance), where the direct mouse's line (y = -41.5 mm) is inside a sweep; the layout's line
    is the numpy search's first clear y (0.05 mm step), -79.7 mm, taken back to its own 0.5 mm
    step from -41.5 mm: -80.0 mm."""
    from cad.families.pantograph import twin_placement as tp

    cap = lay["twin_capstan"]
    q = _angles(design, [0, 1, 2, 3])
    sides = [(s, q[:, c]) for g, cols in (("knob", (0, 1)), ("crank", (2, 3)))
             for s, c in zip(cap[g]["sides"], cols, strict=True)]
    posts = lay["posts_xy_mm"]
    assert len({y for _, y in posts}) == 1
    for p in posts:
        near = min(_sector_distance(p, s, qk) for s, qs in sides for qk in qs)
        assert near > 6.0 + 1.0, (p, near)
    old = [(x, -41.5) for x, _ in posts]
    assert any(_sector_distance(p, s, qk) == 0.0 for p in old for s, qs in sides for qk in qs)
    both = {g: cap[g]["sides"] for g in cap}
    fine = min(tp.clear_post_y_mm(design, x, both) for x in sorted({x for x, _ in posts}))
    y = posts[0][1]
    assert fine - 0.5 < y <= fine + 1e-9
    assert fine == pytest.approx(-79.7, abs=1e-6)
    assert y == pytest.approx(-41.5 - 0.5 * 77, abs=1e-9)


def _crank_drum(design, drum_mm: float):
    """The bundled design with the crank pantograph's two motors through a ``drum_mm`` drum on
    the same 32 mm capstan."""
    import copy
    import tomllib

    from cad.design import parse_design

    raw = tomllib.loads(DESIGN.read_text())
    t = raw.pop("transmission")
    raw["transmission"] = [t, t] + [dict(t, drum_diameter_mm=drum_mm)] * 2
    return parse_design(copy.deepcopy(raw), "v.toml")


def test_a_64_mm_crank_drum_puts_a_mount_plate_on_a_block_in_every_direction(design):
    """A smaller drum does not clear the crank pantograph in one band: a 64 mm drum's motor sits
    64 / 2 + 32 / 2 + 2 = 50 mm from its joint, under the RE 35's 55 mm mount plate plus 1 mm
    from its own joint's block along the joints' line, and for every one of the 360 / 5 = 72
    mirrored directions (by hand below: the two mount squares and the two blocks, 55 mm squares
    at B and at the motors) a mount meets a block or the other mount; the search says the same."""
    from cad.families.pantograph import twin_placement as tp

    d = _crank_drum(design, 64.0)
    sides, why = tp.group_directions(d, "crank")
    assert sides is None and why == {"mounts": 72}
    B = [np.array((-37.5, 0.0)), np.array((37.5, 0.0))]
    for al in np.arange(-180.0, 180.0, 5.0):
        ar = (180.0 - al + 180.0) % 360.0 - 180.0
        m = [b + 50.0 * np.array((math.cos(math.radians(a)), math.sin(math.radians(a)))) for b, a in zip(B, (al, ar),
                                                                                                     strict=True)]
        squares = B + m
        assert any(np.abs(mk - q).max() < 55.0 + 1.0 for k, mk in enumerate(m) for j, q in enumerate(squares)
                   if j != 2 + k), al


@pytest.mark.slow
@pytest.mark.parametrize("drum_mm", [80.0, 96.0, 112.0])
def test_crank_drums_of_80_to_112_mm_still_meet_in_one_band(design, drum_mm):
    """80, 96 and 112 mm crank drums: no mirrored pair of directions clears in one band (the
    direction search; tests/families/pantograph/test_twin_placement.py checks its 136 mm answer
    against polar samples), some directions' swept drums meeting."""
    from cad.families.pantograph import twin_placement as tp

    sides, why = tp.group_directions(_crank_drum(design, drum_mm), "crank")
    assert sides is None and None not in why and why.get("drums", 0) > 0


def test_one_capstan_and_one_direct_motor_on_a_5bar_of_the_twin_is_refused(design):
    """The knob pantograph with a capstan on its left motor only: refused before any search,
    naming ``transmission`` and both joints."""
    import copy
    import tomllib

    from cad.design import parse_design
    from cad.errors import DesignError
    from cad.families.pantograph import twin_placement as tp

    raw = tomllib.loads(DESIGN.read_text())
    t = raw.pop("transmission")
    raw["transmission"] = [t, {"kind": "direct"}, t, t]
    with pytest.raises(DesignError, match=r"^transmission: the twin's knob pantograph with one motor through a "
                       r"capstan and one direct is not built .* give knob_q_left and knob_q_right both"):
        tp.group_sides(parse_design(copy.deepcopy(raw), "v.toml"), "knob")


# ----------------------------------------------------------------------------- slow: the build
@pytest.fixture(scope="module")
def built(tmp_path_factory, design):
    """The bundled design built once (preview fidelity: the bearings as plain rings, the
    capstan parts as fabricated)."""
    import json

    from cad.pipeline import build_design

    out = tmp_path_factory.mktemp("twincap") / "out"
    build_design(design, out, {"step"}, fidelity="preview", use_cache=False)
    return out, json.loads((out / "report.json").read_text())


@pytest.fixture(scope="module")
def step_solids(built):
    """assembly.step read back: {instance name ('.' as '_'): solid}."""
    return read_step_solids(built[0] / "assembly.step")



@pytest.mark.slow
def test_the_build_checks_every_pair_of_solids_with_the_capstan_parts(built):
    """The build's one check over the motion (every pair of bodies at every pose: home and the
    5 x 5 square x 8 crank angles, cad.families.pantograph.motion) finds no collision and no overlap; its parts include the drums
    on the knob links, the capstans, the rope runs, the tensioners and the bearing blocks."""
    out, rep = built
    itf = rep["interference"]
    assert itf["collisions"] == [] and rep["overlap_volume_mm3"] == 0.0
    assert itf["n_poses"] == 1 + 5 * 5 * 8 and itf["min_clearance_mm"] >= 1.0 - 1e-9
    names = set(rep["placement"]["instances"])
    for grp in ("knob", "crank"):
        for side in ("left", "right"):
            assert f"{grp}_proximal_{side}.capstan_drum" in names
    for i in (1, 2, 3, 4):
        for n in (f"capstan_{i}", f"capstan_rope_run_{i}_1", f"capstan_rope_run_{i}_2", f"capstan_tensioner_{i}",
                  f"bearing_block_{i}"):
            assert n in names, n
    for n in ("upper_motor_1.shaft", "upper_motor_2.shaft", "lower_motor_1.shaft", "lower_motor_2.shaft", "post_1"):
        assert n in names, n


@pytest.mark.slow
def test_assembly_step_read_back_shares_no_volume_between_the_capstan_parts_and_the_frame(step_solids):
    """assembly.step read back with OCCT: each drum, capstan and rope run has no common volume
    (OCCT Boolean common, above 1e-4 mm^3) with any plate, post, motor, mount plate, bearing
    block, link part or another capstan drive's part at the exported pose; its own rope on its
    own drum and capstan is the rope's contact, not checked."""
    cap = {k: v for k, v in step_solids.items()
           if k.endswith("capstan_drum") or k in ("capstan_1", "capstan_2", "capstan_3", "capstan_4")
           or k.startswith("capstan_rope_run_")}
    frame = {k: v for k, v in step_solids.items()
             if k in ("bridge_plate", "base_plate") or k.startswith(("post_", "upper_motor", "lower_motor",
                                                                      "bearing_block_"))
             or ("proximal_" in k or "distal_" in k) and ("clevis" in k or "tube" in k)}
    assert len(cap) == 4 + 4 + 8 and len(frame) > 40
    drum = {"1": "knob_proximal_left", "2": "knob_proximal_right", "3": "crank_proximal_left",
            "4": "crank_proximal_right"}

    def rope(k):
        return k.split("_")[3] if k.startswith("capstan_rope_run_") else None

    def own(a, b):  # a rope run and its own drum or capstan
        r = rope(a) or rope(b)
        other = b if rope(a) else a
        return r is not None and other in (f"capstan_{r}", f"{drum[r]}_capstan_drum")

    pairs = [(a, b) for a in cap for b in {**frame, **cap} if a < b or b not in cap]
    checked = 0
    for a, b in pairs:
        if a == b or own(a, b):
            continue
        A, B = cap[a], step_solids[b]
        if A.bounding_box().overlaps(B.bounding_box(), tolerance=0.0) is False:
            continue
        checked += 1
        assert common_mm3(A, B) <= 1e-4, (a, b)
    assert checked > 0
    # the raised motor's body passes the base plate's opening; its mount plate lies on the plate
    assert common_mm3(step_solids["lower_motor_2"], step_solids["base_plate"]) <= 1e-4
    assert common_mm3(step_solids["lower_motor_mount_2"], step_solids["base_plate"]) <= 1e-4
    z0 = step_solids["lower_motor_mount_2"].bounding_box().min.Z
    assert z0 == pytest.approx(0.0, abs=1e-6)  # on the base plate's top (the other at -6 - 5 mm)
    assert step_solids["lower_motor_mount_1"].bounding_box().min.Z == pytest.approx(-11.0, abs=1e-6)


@pytest.mark.slow
def test_drum_and_rope_run_volumes_against_closed_forms(design, step_solids):
    """Each drum read back: the annular sector from the 6 mm axle bore to the crests
    (136 - 0.8) / 2 + 0.28 = 67.88 mm over its arc, 10 mm thick, less the two anchors' radial
    M3 tap holes (9 mm below the groove's bottom out through the crests) and the groove (Pappus:
    the 0.4 mm circle's segment under the crests, by quadrature, round the arc between the
    anchors less a land of one tap drill and one rope diameter each side). Each rope run: a
    0.8 mm cylinder along the external tangent of the pitch circles, sqrt(86^2 - (68 - 16)^2) mm,
    less its trim at the capstan's crests (the shared run_trim_mm)."""
    from cad.assembly.capstan_hardware import run_trim_mm
    from cad.data.catalog import tap_drill_mm
    from cad.families.pantograph.layout import layout
    from tests.capstan_ref import radial_hole_mm3

    lay = layout(design)
    r_b, r_o, r_i = (136.0 - 0.8) / 2, (136.0 - 0.8) / 2 + 0.28, 6.0 / 2
    x, w = np.polynomial.legendre.leggauss(400)
    u = -0.4 + 0.5 * 0.28 * (x + 1.0)  # radial offset from the section circle's centre at 68 mm
    chord = 2.0 * np.sqrt(0.16 - u * u)
    area = 0.5 * 0.28 * np.sum(w * chord)
    rbar = 0.5 * 0.28 * np.sum(w * chord * (68.0 + u)) / area
    hole = radial_hole_mm3(tap_drill_mm("M3-0.5") / 2, r_o, 9.0 + 0.28)
    land = math.degrees((tap_drill_mm("M3-0.5") + 0.8) / r_b)
    sides = [(g, sd) for g in ("knob", "crank") for sd in lay["twin_capstan"][g]["sides"]]
    for grp, sd in sides:
        side = sd.joint.split("_")[-1]
        lo, hi = sorted(sd.anchors_deg)
        groove = area * rbar * math.radians(hi - lo - 2 * land)
        sector = 0.5 * math.radians(sd.arc_span_deg) * (r_o ** 2 - r_i ** 2) * 10.0
        # the exported solid's volume by OCCT's default integration (~1e-5 on the holes' faces)
        assert step_solids[f"{grp}_proximal_{side}_capstan_drum"].volume == pytest.approx(
            sector - 2 * hole - groove, rel=2e-5)
    tangent = math.sqrt(C_MM ** 2 - (68.0 - 16.0) ** 2)
    from cad.actuators.capstan_geometry import groove_depth_mm

    drawn = tangent - run_trim_mm(16.0, groove_depth_mm(0.8))
    for k in (f"{i}_{j}" for i in (1, 2, 3, 4) for j in (1, 2)):
        assert step_solids[f"capstan_rope_run_{k}"].volume == pytest.approx(math.pi * 0.4 ** 2 * drawn, rel=1e-6)


@pytest.mark.slow
def test_bundled_design_figures_regression_pin(built):
    """Regression pin (values recorded from our own build, 2026-12, preview fidelity: the
    bearings' plain rings carry the catalog masses, so the masses and modes are the fabrication
    build's): the datasheet's continuous force in every direction 4.089 N (ok against 4 N), first
    mode 35.0 Hz (MISS against 150 Hz), moving mass 1171.3 g, the drum arc the rope needs
    89.6 deg (knob) and 113.0 deg (crank), the smallest clearance 1.16 mm (a rope run's envelope
    to its drum: two different parts; the distal bearings' own 1.15 mm ring gap is the maker's,
    reported apart); docs/families/pantograph-powermouse.md states them."""
    _, rep = built
    rows = {r["key"]: r for r in rep["datasheet"]["rows"]}
    assert round(rows["continuous_force_N"]["value"], 3) == 4.089
    assert round(rows["first_mode_Hz"]["value"], 1) == 35.0
    assert round(rep["moving_mass_g"], 1) == 1171.3
    assert round(rows["drum_sector_deg_1"]["value"], 1) == 89.6
    assert round(rows["drum_sector_deg_3"]["value"], 1) == 113.0
    assert round(rep["min_clearance_mm"], 2) == 1.16
    assert rep["interference"]["closest"]["parts"] == ["capstan_rope_run_1_2", "knob_proximal_left.capstan_drum"]
    assert rep["interference"]["own_part_gaps"]["min_gap_mm"] == pytest.approx(1.15, abs=1e-9)
    assert rows["continuous_force_N"]["verdict"] == "ok" and rows["first_mode_Hz"]["verdict"] == "miss"
    assert all(rows[f"{k}_{i}"]["verdict"] == "ok" for k in ("cable_safety_factor", "cable_slip_margin",
                                                                "drum_sector_deg") for i in (1, 2, 3, 4))


@pytest.mark.slow
def test_rope_bom_lines_and_winding_steps_come_from_the_shared_capstan_functions(design, built, step_solids):
    """bom.csv's rope lines are :func:`cad.datasheet.capstan_rows.cable_bom_line` of the
    four capstan joints (cut length, description); every
    anchor, tensioner and lock nut assembly.md's winding steps name is an instance of
    assembly.step."""
    import re

    from cad.families.pantograph.capstan import bom_lines

    out, _ = built
    with open(out / "bom.csv", newline="", encoding="utf-8") as f:
        rows = {r["part"]: r for r in csv.DictReader(f)}
    want = bom_lines(design)
    assert [r["part"] for r in want] == ["capstan_cable_1", "capstan_cable_2", "capstan_cable_3", "capstan_cable_4"]
    for r in want:
        assert rows[r["part"]]["description"] == r["description"]
    text = (out / "assembly.md").read_text(encoding="utf-8")
    named = set(re.findall(r"capstan_(?:anchor_\d_1|tensioner_\d|tensioner_nut_\d)\b", text))
    assert named == {f"capstan_{k}" for i in (1, 2, 3, 4) for k in (f"anchor_{i}_1", f"tensioner_{i}",
                                                                       f"tensioner_nut_{i}")}
    assert named <= set(step_solids)


def test_part_descriptions_say_where_the_clevis_sits_and_the_raised_motor(design, lay):
    """A tester's finding: the twin capstan's BOM said the hub clevis and its set screw sit
    "on the motor shaft" (they sit on the link's own axle: the capstan turns the link) and the
    base plate had "motors under" with one motor on its top. The descriptions follow the
    layout: the capstan twin (raise_mm > 0 on the crank side) against the direct mouse."""
    from cad.design import load_design
    from cad.families.pantograph.kinds import hub_seat, raised_note
    from cad.families.pantograph.layout import layout

    assert lay["twin_capstan"]["crank"]["raise_mm"][1] > 0
    assert hub_seat(lay) == "link axle" and raised_note(lay) == ", one on its top through its opening"
    direct = layout(load_design(ROOT / "designs" / "haptic_mouse.toml"))
    assert hub_seat(direct) == "motor shaft" and raised_note(direct) == ""
    mixed = {**lay, "twin_capstan": {"knob": lay["twin_capstan"]["knob"]}}
    assert "or motor shaft (direct 5-bar)" in hub_seat(mixed)
