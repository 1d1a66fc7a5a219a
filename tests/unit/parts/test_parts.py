"""Part scripts against closed-form volumes; bad part parameters; catalog data; joint stacks.

References: plane geometry (stadium, circle, slot and convex-hull-of-discs areas),
bd_warehouse's own part classes for the catalog numbers, OCCT integration of a ring
for the bearing inertia model.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from cad.data import catalog
from cad.design.parts import ALLOWED_KEYS, PartsSpec, parse_parts
from cad.errors import DesignError

T = 6.0


def vol(shape) -> float:
    from cad.massprops.occt import volume_mm3

    return volume_mm3(shape)


def spec(**kw) -> PartsSpec:
    return parse_parts(kw)


# ----------------------------------------------------------------- bars
def test_plain_bar_is_a_stadium_minus_two_holes():
    from cad.parts.bars import Feature, bar_shape

    p = spec(bar_pockets=False, bar_thickness_mm=T)
    L, r, d = 62.5, p.bar_end_radius_mm, 8.0
    joints = {
        "A": (np.array([0.0, 0.0]), Feature("pin", d_mm=d)),
        "B": (np.array([L, 0.0]), Feature("pin", d_mm=d)),
    }
    expected = (2 * r * L + math.pi * r * r - 2 * math.pi * (d / 2) ** 2) * T
    assert vol(bar_shape(joints, p)) == pytest.approx(expected, rel=1e-9)


def test_bearing_seat_is_a_counterbore_over_a_lip_hole():
    from cad.parts.bars import Feature, bar_shape

    p = spec(bar_pockets=False)
    b = catalog.get_bearing(p.bearing)
    L, r = 40.0, p.bar_end_radius_mm
    seat = Feature("seat", d_mm=b.Da_mm, cb_d_mm=b.D_mm, cb_depth_mm=b.B_mm)
    joints = {"A": (np.zeros(2), seat), "B": (np.array([L, 0.0]), Feature("pin", d_mm=8.0))}
    removed = (
        math.pi * (b.Da_mm / 2) ** 2 * T
        + math.pi * ((b.D_mm / 2) ** 2 - (b.Da_mm / 2) ** 2) * b.B_mm
    )
    expected = (2 * r * L + math.pi * r * r) * T - removed - math.pi * 16.0 * T
    assert vol(bar_shape(joints, p)) == pytest.approx(expected, rel=1e-9)


def test_lightening_pocket_is_a_slot_with_the_stated_webs():
    from cad.parts.bars import Feature, bar_shape, pocket_segments

    p = spec(bar_pockets=True, bar_pocket_web_mm=3.0)
    L, r, d = 80.0, p.bar_end_radius_mm, 8.0
    joints = {
        "A": (np.zeros(2), Feature("pin", d_mm=d)),
        "B": (np.array([L, 0.0]), Feature("pin", d_mm=d)),
    }
    ((a, b, w),) = pocket_segments(joints, p)
    assert w == pytest.approx(p.bar_width_mm - 2 * 3.0)
    # the slot stops web mm short of each hole: hole radius + web + slot half-width
    assert a[0] == pytest.approx(d / 2 + 3.0 + w / 2)
    c2c = float(np.linalg.norm(b - a))
    slot = c2c * w + math.pi * (w / 2) ** 2
    expected = (2 * r * L + math.pi * r * r - 2 * math.pi * (d / 2) ** 2 - slot) * T
    assert vol(bar_shape(joints, p)) == pytest.approx(expected, rel=1e-9)


def test_ternary_coupler_plate_is_the_hull_of_three_discs():
    """Roberts-like coupler (phi_e != 0): area = triangle + r * perimeter + pi r^2."""
    from cad.parts.bars import Feature, bar_shape, outline_area_mm2

    p = spec(bar_pockets=False)
    pts = [
        np.array([0.0, 0.0]),
        np.array([38.46, 0.0]),
        46.15 * np.array([math.cos(math.radians(-65.7)), math.sin(math.radians(-65.7))]),
    ]
    joints = {n: (q, Feature("keep")) for n, q in zip(("A2", "A3", "P"), pts, strict=True)}
    r = p.bar_end_radius_mm
    u, v = pts[1] - pts[0], pts[2] - pts[0]
    tri = 0.5 * abs(u[0] * v[1] - u[1] * v[0])
    per = sum(float(np.linalg.norm(pts[(i + 1) % 3] - pts[i])) for i in range(3))
    expected = tri + r * per + math.pi * r * r
    assert outline_area_mm2(np.array(pts), r) == pytest.approx(expected, rel=1e-12)
    assert vol(bar_shape(joints, p)) == pytest.approx(expected * T, rel=1e-9)


def test_collinear_coupler_is_one_stadium_from_A2_to_P():
    """Hoeken coupler (phi_e = 0, le = 2 l2): A3 lies on the segment A2-P."""
    from cad.parts.bars import Feature, bar_shape, hull_points

    p = spec(bar_pockets=False)
    pts = {"A2": np.zeros(2), "A3": np.array([62.5, 0.0]), "P": np.array([125.0, 0.0])}
    h = hull_points(np.array(list(pts.values())))
    assert len(h) == 2
    r = p.bar_end_radius_mm
    joints = {n: (q, Feature("keep")) for n, q in pts.items()}
    assert vol(bar_shape(joints, p)) == pytest.approx(
        (2 * r * 125.0 + math.pi * r * r) * T, rel=1e-9
    )


def test_dog_bone_bar_with_wider_ends():
    """end radius > width / 2: two discs joined by a strip of the bar width."""
    from cad.parts.bars import Feature, bar_shape

    p = spec(bar_pockets=False, bar_width_mm=12.0, bar_end_radius_mm=11.0)
    L, r, w = 50.0, 11.0, 12.0
    joints = {"A": (np.zeros(2), Feature("keep")), "B": (np.array([L, 0.0]), Feature("keep"))}
    # the strip between the centres overlaps each disc in half of the band |y| <= w/2:
    # integral_0^(w/2) 2 sqrt(r^2 - y^2) dy = (w/2) sqrt(r^2 - w^2/4) + r^2 asin(w / 2r)
    half_band = (w / 2) * math.sqrt(r * r - w * w / 4) + r * r * math.asin(w / (2 * r))
    expected = (2 * math.pi * r * r + w * L - 2 * half_band) * T
    assert vol(bar_shape(joints, p)) == pytest.approx(expected, rel=1e-9)


# ----------------------------------------------------------------- plates and turned parts
def test_motor_mount_plate_closed_form():
    from cad.parts import motor

    m = catalog.get_motor("maxon-re35")
    t = 5.0
    s = motor.mount_side_mm(m)
    r_b = catalog.clearance_hole_mm(m.bolt_size) / 2
    r_m = catalog.clearance_hole_mm(motor.MOUNT_SCREW) / 2
    area = (
        s * s
        - math.pi * (m.pilot_diameter_mm / 2) ** 2
        - m.bolt_count * math.pi * r_b**2
        - 4 * math.pi * r_m**2
    )
    assert vol(motor.motor_mount_shape(m, t)) == pytest.approx(area * t, rel=1e-9)


def test_ring_spacer_and_knob_closed_forms():
    from cad.parts.handle import handle_params, knob_shape
    from cad.parts.joints import ring_shape

    assert vol(ring_shape(4.0, 4.95, 3.5)) == pytest.approx(
        math.pi * (4.95**2 - 16.0) * 3.5, rel=1e-12
    )
    p = spec()
    floor = 10.0
    hp = handle_params(p, floor)
    R, h = p.handle_diameter_mm / 2, p.handle_height_mm
    rc, rcb = hp["screw_clearance_mm"] / 2, hp["counterbore_mm"] / 2
    expected = math.pi * R * R * h - math.pi * rc * rc * floor - math.pi * rcb * rcb * (h - floor)
    assert vol(knob_shape(p, floor, cosmetic=False)) == pytest.approx(expected, rel=1e-9)
    # the cosmetic round only removes material
    assert vol(knob_shape(p, floor, cosmetic=True)) < expected


def test_bearing_ring_inertia_matches_occt_integration():
    """The catalog-mass ring model equals OCCT's integration of a uniform ring of that mass."""
    from cad.massprops.occt import solid_mass_props, volume_mm3
    from cad.parts.joints import ring_shape

    b = catalog.get_bearing("M8-16-4")
    ring = ring_shape(b.d_mm / 2, b.D_mm / 2, b.B_mm)
    rho = b.mass_kg / (volume_mm3(ring) * 1e-9)
    mp = solid_mass_props(ring, rho)
    ia, it = catalog.ring_inertia_kg_m2(b.mass_kg, b.d_mm / 2, b.D_mm / 2, b.B_mm)
    assert mp.inertia_com_kg_m2[2, 2] == pytest.approx(ia, rel=1e-9)
    assert mp.inertia_com_kg_m2[0, 0] == pytest.approx(it, rel=1e-9)


# ----------------------------------------------------------------- catalog vs bd_warehouse
def test_catalog_reads_the_same_numbers_as_bd_warehouse():
    from bd_warehouse.bearing import SingleRowDeepGrooveBallBearing
    from bd_warehouse.fastener import ShoulderScrew

    b = catalog.get_bearing("M8-16-4")
    bw = SingleRowDeepGrooveBallBearing("M8-16-4")
    assert (b.d_mm, b.D_mm, b.B_mm) == (bw.bore_diameter, bw.outer_diameter, bw.thickness)
    s = catalog.get_shoulder_screw("M6-1")
    sw = ShoulderScrew("M6-1", 12)
    assert (
        s.ds_mm == sw.screw_data["ds"]
        and s.dk_mm == sw.screw_data["dk"]
        and s.b_mm == sw.screw_data["b"]
    )


def test_motor_catalog_default_is_the_papers_re35():
    m = catalog.get_motor(PartsSpec().motor)
    assert m.key == "maxon-re35"
    assert 65.2 <= m.rotor_inertia_g_cm2 <= 79.2  # maxon RE 35 catalog range over windings
    assert m.rotor_inertia_kg_m2 == pytest.approx(m.rotor_inertia_g_cm2 * 1e-7)


# ----------------------------------------------------------------- bad parameters
def test_empty_table_gives_complete_defaults():
    p = parse_parts({})
    assert p == PartsSpec()
    assert set(p.as_dict()) == set(ALLOWED_KEYS)
    assert p.bar_end_radius_mm == p.bar_width_mm / 2


@pytest.mark.parametrize(
    ("table", "field", "words"),
    [
        ({"bar_width_mm": 14.0}, "parts.bar_width_mm", "bearing seat"),
        (
            {"bar_width_mm": 10.0, "bar_end_radius_mm": 9.0},
            "parts.bar_end_radius_mm",
            "bearing seat",
        ),
        ({"bar_end_radius_mm": 5.0}, "parts.bar_end_radius_mm", ">= bar_width_mm"),
        ({"bar_thickness_mm": -2.0}, "parts.bar_thickness_mm", "> 0"),
        ({"bar_thickness_mm": 0}, "parts.bar_thickness_mm", "> 0"),
        ({"bar_thickness_mm": 4.5}, "parts.bar_thickness_mm", "lip"),
        ({"bar_material": "unobtainium"}, "parts.bar_material", "unknown material"),
        ({"bearing": "M5-13-4"}, "parts.pin", "bearing bore"),
        ({"bearing": "M99-1-1"}, "parts.bearing", "unknown bearing"),
        ({"motor": "nema17"}, "parts.motor", "unknown motor"),
        ({"layer_order": ["crank", "crank", "rocker"]}, "parts.layer_order", "once each"),
        ({"fidelity": "draft"}, "parts.fidelity", "one of"),
        ({"handle_script": "knob.txt"}, "parts.handle_script", "Python"),
        ({"bar_pockets": 1}, "parts.bar_pockets", "true or false"),
        ({"hub_diameter_mm": 12.0}, "parts.hub_diameter_mm", "hub"),
        ({"bar_widht_mm": 20.0}, "parts.bar_widht_mm", "unknown key"),
    ],
)
def test_bad_part_parameters_name_the_field(table, field, words):
    with pytest.raises(DesignError) as ei:
        parse_parts(table)
    assert ei.value.field == field
    assert words in str(ei.value)


# ----------------------------------------------------------------- joint stacks (no CAD)
@pytest.mark.parametrize("fam", ["hoeken", "roberts", "chebyshev", "chebyshev-v"])
def test_joint_stacks_are_consistent_and_use_catalog_lengths(fam):
    from cad.families.fourbar.layers import choose_layers
    from cad.families.fourbar.pose import planar_transforms
    from cad.kinematics.families import family_linkage
    from cad.kinematics.linkgeom import link_joints_mm

    p = PartsSpec()
    fb, lo, hi = family_linkage(fam)
    plan = choose_layers(link_joints_mm(fb), p, planar_transforms(fb, np.linspace(lo, hi, 40)))
    assert plan.conflicts == ()
    b = catalog.get_bearing(p.bearing)
    pin = catalog.get_shoulder_screw(p.pin)
    for s in plan.joints.values():
        assert s.clamp_mm == pytest.approx(s.shim_mm + b.B_mm + s.spacer_mm)
        assert s.pin_length_mm in pin.lengths_mm
        assert s.spacer_mm >= p.layer_gap_mm - 1e-9
        # the shoulder ends inside the lower link (or the post)
        assert s.pin_length_mm - s.clamp_mm >= 1.0 - 1e-9
        if s.nut:
            assert s.pin_length_mm - s.clamp_mm <= p.bar_thickness_mm - 0.5 + 1e-9
        # head face sits pin_head_clearance (or more) above the upper bar
        assert (
            s.head_face_mm - (s.z_upper_mm + p.bar_thickness_mm) >= p.pin_head_clearance_mm - 1e-9
        )
