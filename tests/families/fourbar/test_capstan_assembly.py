"""The capstan Hoeken's transmission drawn in the assembly (issue 35): the drum sector, the
capstan, the moved motor, the rope's runs and anchors are instances of the one model, so the
interference check over the crank range, the mass properties (H11), the BOM and assembly.step
all carry them. References: the rope's tangent points by the homothety construction of two
circles' external tangents; the drum's mass and inertia about A1 in closed form (annular sector,
(theta / 2)(r_o^2 - r_i^2) t rho and m (r_o^2 + r_i^2) / 2, minus the anchors' radial holes by
quadrature); the BOM's quantities against the instances read back from assembly.step."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from cad.actuators import capstan_geometry as cg
from cad.data.catalog import tap_drill_mm
from cad.data.materials import get_material
from tests.capstan_ref import radial_hole_mm3

ROOT = Path(__file__).resolve().parents[3]
DESIGN = ROOT / "designs" / "hoeken_capstan.toml"


@pytest.fixture(scope="module")
def design():
    from cad.design import load_design

    return load_design(DESIGN)


@pytest.fixture(scope="module")
def built(design, tmp_path_factory):
    """hoeken_capstan built in-process (inertia fidelity: exact interference, STEP)."""
    from cad.pipeline import build_design

    out = tmp_path_factory.mktemp("capstan") / "b"
    rep = build_design(design, out, {"step"}, fidelity="inertia", use_cache=False)
    return rep, out


def _placement(design):
    from cad.device import resolve_device
    from cad.families.fourbar.capstan_solids import placement
    from cad.families.fourbar.layout import assemble

    model = assemble(design, "preview")
    t = resolve_device(design).transmission("crank")
    return model, t, placement(design, t, model.extra.joints_mm, model.extra.plan)


def test_no_clash_over_the_crank_range_with_drum_rope_and_capstan(built):
    rep, _ = built
    assert rep["interference"]["collisions"] == [] and rep["overlap_volume_mm3"] == 0.0
    placed = rep["placement"]["instances"]
    assert placed["capstan_drum"]["body"] == "crank"
    assert {placed[n]["body"] for n in ("capstan", "capstan_rope_run_1", "capstan_rope_run_2",
                                        "capstan_motor_shaft", "motor")} == {"ground"}


def _homothety_points(c1, r1, c2, r2):
    H = (r1 * c2 - r2 * c1) / (r1 - r2)
    pts = []
    for c, r in ((c1, r1), (c2, r2)):
        e = H - c
        dist = np.linalg.norm(e)
        w, wp = e / dist, np.array([-e[1], e[0]]) / dist
        pts.append([c + r * r / dist * w + s * r * math.sqrt(1 - (r / dist) ** 2) * wp for s in (1, -1)])
    return pts


def test_rope_runs_lie_between_the_closed_form_tangent_points(design):
    from cad.massprops.occt import volume_props_mm

    model, t, pl = _placement(design)
    C = pl.centre_distance_mm
    assert C == 85.0 and np.hypot(*pl.motor_xy_mm) == pytest.approx(C)
    motor = next(i for i in model.instances if i.name == "motor")
    np.testing.assert_allclose(motor.tf_body_part[:2, 3], pl.motor_xy_mm, atol=1e-12)
    on_drum, on_capstan = _homothety_points(np.zeros(2), 32.0, np.asarray(pl.motor_xy_mm), 16.0)
    kinds = model.kinds()
    # the drawn run stops where it meets the capstan's crests, 0.35 d = 0.28 mm above the groove's
    # bottom: its axis sqrt(16^2 + s^2) = 16.28 mm from the capstan's axis
    s_c = math.sqrt(16.28 ** 2 - 16.0 ** 2)
    for k in (1, 2):
        vol, com, _ = volume_props_mm(kinds[f"capstan_rope_run_{k}"].shape)
        # each run joins one drum tangent point to the capstan tangent point on the same side
        ends = min(((a, b) for a in on_drum for b in on_capstan),
                   key=lambda ab: np.linalg.norm((ab[0] + ab[1]) / 2 - com[:2]))
        L = np.linalg.norm(ends[1] - ends[0])
        u = (ends[1] - ends[0]) / L
        np.testing.assert_allclose(com[:2], (ends[0] + ends[1] - s_c * u) / 2, atol=1e-9)
        assert L == pytest.approx(math.sqrt(C ** 2 - 16.0 ** 2), rel=1e-12)
        assert vol == pytest.approx(math.pi * 0.4 ** 2 * (L - s_c), rel=1e-9)
        assert com[2] == pytest.approx(pl.rope_z_mm)


def test_drum_mass_and_inertia_about_A1_closed_form(design, built):
    """The drum sector to its crests (groove bottom 31.6 mm + 0.35 x 0.8 mm), less its rope groove
    between the anchors (Pappus: the groove section's area round its centroid's arc, section and
    centroid by quadrature here) and the two anchor holes drilled 9 mm below the groove's bottom
    out through the crests."""
    rep, _ = built
    _, t, pl = _placement(design)
    r_b, r_i, th = cg.rim_radius_mm(64.0, 0.8), design.parts.hub_diameter_mm / 2, 10.0
    r_o = r_b + 0.28
    rho = get_material("aluminium-6061").density_kg_m3
    hole = radial_hole_mm3(tap_drill_mm("M3-0.5") / 2, r_o, 9.0 + 0.28)
    # groove section: the part of the 0.4 mm circle centred at 32 mm inside r_o, by quadrature
    x, w = np.polynomial.legendre.leggauss(400)
    u = -0.4 + 0.5 * 0.28 * (x + 1.0)  # radial offset from the circle's centre, -0.4 .. -0.12
    chord = 2.0 * np.sqrt(0.16 - u * u)
    area = 0.5 * 0.28 * np.sum(w * chord)
    rbar = 0.5 * 0.28 * np.sum(w * chord * (32.0 + u)) / area
    lo, hi = sorted(pl.anchors_deg)
    land = math.degrees((tap_drill_mm("M3-0.5") + 0.8) / r_b)
    groove = area * rbar * math.radians(hi - lo - 2 * land)
    assert groove == pytest.approx(cg.ring_groove_volume_mm3(64.0, 0.8, hi - lo - 2 * land), rel=1e-6)
    m_ref = cg.sector_mass_kg(pl.arc_span_deg, r_o, r_i, th, rho) - (2 * hole + groove) * 1e-9 * rho
    # the build integrates in OCCT's default Gauss mode, which is off by ~0.07 mm^3 per hole on
    # the holes' B-spline faces (1e-5 of the part); the adaptive mode matches the closed form
    assert rep["part_masses_g"]["capstan_drum"] == pytest.approx(m_ref * 1e3, rel=2e-5)
    from cad.families.fourbar.layout import assemble
    from cad.massprops.occt import volume_props_mm

    shape = assemble(design, "preview").kinds()["capstan_drum"].shape
    assert volume_props_mm(shape, eps=1e-9)[0] * 1e-9 * rho == pytest.approx(m_ref, rel=1e-9)
    from cad.families.fourbar.inertia import inertia_model

    row = next(r for r in inertia_model(design)["budget"] if r["kind"] == "capstan_drum")
    # the sector's inertia about its centre is m (r_o^2 + r_i^2) / 2 whatever its arc, less the
    # two holes as point masses at their mid-depth r_o - 4.5 mm (their own inertia, ~1e-9 kg m^2,
    # and the Gauss-mode error bound the tolerance)
    I_sector = 0.5 * cg.sector_mass_kg(pl.arc_span_deg, r_o, r_i, th, rho) * (r_o ** 2 + r_i ** 2) * 1e-6
    I_holes = 2 * hole * 1e-9 * rho * ((r_o - 4.64) * 1e-3) ** 2
    I_groove = groove * 1e-9 * rho * (rbar * 1e-3) ** 2
    assert row["link"] == "crank"
    assert row["H11_kg_m2"] == pytest.approx(I_sector - I_holes - I_groove, rel=1e-4)


def test_capstan_inertia_in_h11_is_its_solids(design, built):
    """The motor side's inertia at the crank, n^2 (J_m + J_capstan), takes the capstan's
    closed form (:meth:`cad.device.Transmission.capstan_inertia_kg_m2`); checked here against
    the capstan's solid (OCCT, adaptive integration: its set-screw hole included) and read back
    from the MJCF armature and report.json's Jm."""
    from cad.device import resolve_device
    from cad.families.fourbar.layout import assemble
    from cad.massprops.occt import volume_props_mm

    dev = resolve_device(design)
    t, m = dev.transmission("crank"), dev.motor
    shape = assemble(design, "preview").kinds()["capstan"].shape
    vol_mm3, _, inertia_mm5 = volume_props_mm(shape, eps=1e-9)
    rho = get_material("steel-1018").density_kg_m3
    izz_solid = inertia_mm5[2][2] * rho * 1e-15  # about the capstan's own axis (its frame's z)
    closed = t.capstan_inertia_kg_m2(m.spec.shaft_diameter_mm)
    # the closed form leaves out the set screw's radial tap-drill hole (M3: 2.5 mm) through the
    # wall, bore 3 mm to the crests 15.6 + 0.28 mm: rho pi r_h^2 int r^2 dr (0.6 % of the capstan)
    r_h, r0, r1 = tap_drill_mm("M3-0.5") / 2, 3.0, (32.0 - 0.8) / 2 + 0.28
    hole = rho * math.pi * r_h ** 2 * (r1 ** 3 - r0 ** 3) / 3 * 1e-15
    assert closed - hole == pytest.approx(izz_solid, rel=1e-3)
    jm = (m.rotor_inertia_kg_m2 + closed) * 4.0
    rep, _ = built
    assert rep["Jm_kg_m2"] == pytest.approx(jm, rel=1e-12)


def test_bom_quantities_equal_the_instances_in_assembly_step(built):
    from cad.device.readback import step_instances

    rep, out = built
    placed = rep["placement"]["instances"]
    count: dict[str, int] = {}
    for name in step_instances(out / "assembly.step"):
        if name in placed:
            count[placed[name]["kind"]] = count.get(placed[name]["kind"], 0) + 1
    with open(out / "bom.csv", newline="", encoding="utf-8") as f:
        rows = [r for r in csv.DictReader(f) if r["part"].startswith("capstan")]
    parts = [r["part"] for r in rows]
    assert len(parts) == len(set(parts))  # one line each
    assert set(parts) == {"capstan_drum", "capstan_anchor_screw", "capstan", "capstan_set_screw",
                          "capstan_cable", "capstan_tensioner_screw", "capstan_tensioner_nut"}
    for r in rows:
        if r["part"] == "capstan_cable":  # the rope: its runs are drawn
            continue
        assert int(float(r["quantity"])) == count[r["part"]], r["part"]
    assert count["capstan_anchor_screw"] == 1 and count["capstan_rope_run_1"] == 1
    assert count["capstan_tensioner_screw"] == 1 and count["capstan_tensioner_nut"] == 1


def test_assembly_md_has_the_winding_and_tensioning_steps(built):
    from cad.actuators import capstan as cap

    rep, out = built
    text = (out / "assembly.md").read_text(encoding="utf-8")
    cut = next(r for r in rep["datasheet"]["rows"] if r["key"] == "cable_cut_length_mm")["value"]
    T0 = next(r for r in rep["datasheet"]["rows"] if r["key"] == "cable_pretension_N")["value"]
    # the smallest pretension that holds the peak load, by hand: (dT / 2)(e + 1)/(e - 1)
    e = math.exp(cap.MU_STEEL_ROPE_ON_STEEL * 2 * math.pi * 3)
    assert T0 == pytest.approx(0.5 * 0.9725 / 0.016 * (e + 1) / (e - 1), rel=1e-9)
    assert f"wind the rope: cut {cut:.0f} mm of steel-7x7-0.8" in text
    assert f"until the rope holds at least {T0:.1f} N" in text
    assert "`capstan_drum`" in text and "`capstan_cable`" in text  # the runs belong to the rope's line


def test_crank_axle_turns_in_two_bearings_in_the_a1_block(design, built):
    """The crank's support at A1 (the motor is moved away): the axle is the crank's and passes
    through both bearings, whose outer rings sit in the ground's block and inner rings turn
    with the crank; the block's solid is its closed form (a square flange and a boss, less the
    seats, the lip's bore and the corner holes: prisms and cylinders by hand); the BOM orders
    two 626 bearings and the block's four screws (read back from assembly.step's instances)."""
    from cad.data import catalog as cat
    from cad.families.fourbar.capstan_solids import A1_LIP_MM, A1_WALL_MM
    from cad.families.fourbar.layout import assemble
    from cad.massprops.occt import volume_props_mm
    from cad.parts import motor

    rep, out = built
    placed = rep["placement"]["instances"]
    assert placed["crank_axle"]["body"] == "crank" and "motor_shaft" not in placed
    model = assemble(design, "preview")
    inst = {i.name: i for i in model.instances}
    for k in (1, 2):
        b = inst[f"a1_bearing_{k}"]
        assert (b.body, b.other_body) == ("ground", "crank")
    brg, m = cat.get_bearing("626"), cat.get_motor(design.parts.motor)
    h = 2 * brg.B_mm + A1_LIP_MM
    z_axle = inst["crank_axle"].tf_body_part[2, 3]
    z_block = inst["a1_bearing_block"].tf_body_part[2, 3]
    assert z_block == pytest.approx(-design.parts.base_thickness_mm - h)  # its top under the base plate
    for k, z in ((1, z_block + h - brg.B_mm), (2, z_block)):  # both bearings on the axle
        assert inst[f"a1_bearing_{k}"].tf_body_part[2, 3] == pytest.approx(z)
        assert z_axle <= z
    side, fl = motor.mount_side_mm(m), design.parts.motor_mount_thickness_mm
    r_boss = brg.D_mm / 2 + A1_WALL_MM
    v_ref = (side * side * fl + math.pi * r_boss ** 2 * (h - fl)
             - math.pi * (brg.Da_mm / 2) ** 2 * h
             - 2 * math.pi * ((brg.D_mm / 2) ** 2 - (brg.Da_mm / 2) ** 2) * brg.B_mm
             - 4 * math.pi * (cat.clearance_hole_mm("M3-0.5") / 2) ** 2 * fl)
    shape = model.kinds()["a1_bearing_block"].shape
    assert volume_props_mm(shape, eps=1e-9)[0] == pytest.approx(v_ref, rel=1e-9)
    axle = model.kinds()["crank_axle"].shape
    L = m.shaft_length_mm - (design.parts.motor_mount_thickness_mm + design.parts.base_thickness_mm) - z_axle
    assert volume_props_mm(axle, eps=1e-9)[0] == pytest.approx(math.pi * (m.shaft_diameter_mm / 2) ** 2 * L, rel=1e-9)
    with open(out / "bom.csv", newline="", encoding="utf-8") as f:
        bom = {r["part"]: r for r in csv.DictReader(f)}
    assert int(float(bom["bearing_M6-19-6"]["quantity"])) == 2 and "626" in bom["bearing_M6-19-6"]["designation"]
    assert "bearing seat 19 J7" in bom["a1_bearing_block"]["fits"] and "bearing journal 6 js5" in bom["crank_axle"]["fits"]
    screws = [n for n in placed if n.startswith("a1_block_screw_")]
    assert len(screws) == 4 and {placed[n]["kind"] for n in screws} == {placed["mount_screw_1"]["kind"]}


def test_tensioner_screw_winds_the_rope_and_holds_in_the_anchor_hole(design):
    """The tensioner at anchor 2: the shortest ISO 4762 M3 length that stands out of the rim by
    the lock nut (ISO 4032 M3: m = 2.4 mm) and three rope diameters and still engages 1.5 d in
    the anchor's tapped hole (8 mm of full thread): 2.4 + 2.4 + 4.5 = 9.3 -> 10 mm."""
    from cad.device import resolve_device
    from cad.families.fourbar.capstan_solids import tensioner_screw_mm
    from cad.families.fourbar.layout import assemble

    L, out = tensioner_screw_mm(resolve_device(design).transmission("crank"))
    assert (L, out) == (10.0, pytest.approx(2.4 + 3 * 0.8))
    assert 1.5 * 3 <= L - out <= 8.0
    inst = {i.name: i for i in assemble(design, "preview").instances}
    nut, screw = inst["capstan_tensioner_nut"], inst["capstan_tensioner"]
    assert nut.body == screw.body == "crank"
    # the head's face stands `out` further out along the hole's axis than the nut's (on the rim)
    axis = nut.tf_body_part[:3, 2]
    assert (screw.tf_body_part[:3, 3] - nut.tf_body_part[:3, 3]) @ axis == pytest.approx(out)


RE25_TABLE = """
[motor]
torque_continuous_mNm = 28.0
torque_peak_mNm = 200.0
current_continuous_A = 1.2
mass_g = 130.0
"""


def _re25(tmp_path, text: str):
    from cad.design import load_design

    p = tmp_path / "re25.toml"
    p.write_text(text.replace("[parts]\n", '[parts]\nmotor = "maxon-re25"\n', 1) + RE25_TABLE)
    return load_design(p)


def test_a_short_motor_shaft_does_not_limit_the_crank_on_its_made_axle(tmp_path):
    """A tester's finding: the capstan Hoeken with the RE 25 (12 mm shaft; a [motor] table
    with illustrative values for what the catalog lacks) was refused because the shaft
    reached 0 mm into the crank hub, though with a capstan the crank turns on a made axle at
    A1, not on the motor's shaft. The axle now reaches the hub's top (the hub's full height
    engaged: hub top - hub bottom of the layer plan), its solid is that cylinder (closed form
    pi r^2 L), and the direct-drive RE 25 Hoeken is still refused for its short shaft."""
    from cad.data import catalog as cat
    from cad.errors import DesignError
    from cad.families.fourbar.layout import assemble
    from cad.massprops.occt import volume_props_mm

    d = _re25(tmp_path, DESIGN.read_text())
    model = assemble(d, "preview")
    plan = model.extra.plan
    m = cat.get_motor("maxon-re25")
    flange = -(d.parts.base_thickness_mm + d.parts.motor_mount_thickness_mm)
    assert flange + m.shaft_length_mm < plan.hub_z_mm[1]  # the motor's own shaft falls short
    assert plan.shaft_top_mm == pytest.approx(plan.hub_z_mm[1])
    z_axle = {i.name: i for i in model.instances}["crank_axle"].tf_body_part[2, 3]
    L = plan.hub_z_mm[1] - z_axle
    v = volume_props_mm(model.kinds()["crank_axle"].shape, eps=1e-9)[0]
    assert v == pytest.approx(math.pi * (m.shaft_diameter_mm / 2) ** 2 * L, rel=1e-9)
    direct = _re25(tmp_path, (ROOT / "designs" / "hoeken.toml").read_text())
    with pytest.raises(DesignError, match="maxon-re25 shaft reaches only"):
        assemble(direct, "preview")
