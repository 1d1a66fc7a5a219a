"""The haptic pen's waist capstans as solids (issue 35, stage 1): the test case
tests/families/pen/designs/pen_waist_capstan.toml (the bundled capstan pen's waists, 3:1
through a 40 mm capstan, a 120 mm drum and a 1 mm 7x7 rope, 3 turns; its shoulders direct).

References, each independent of the code under test:

* the layout: the drums' band, the base plate's drop, the moved motors and the plate's extent
  by hand from the design's and the catalog's numbers (C = 60 + 20 + 2 mm rim gap = 82 mm at
  -170 / -10 deg, the layout's directions);
* the waist's range and the rope: the waist angle psi = atan2(E_y, E_x - x0) of each pen end
  E = X -+ l6 / 2 u (u = Rz(yaw) Ry(-pitch) x) over the workspace grid by hand, the drum arc
  the rope needs (range + 4 deg margin + two 10 mm anchors on the 60 mm pitch radius), the
  rope's cut length wraps pi d_c + 2 sqrt(C^2 - (R - r)^2) + pi d_d arc / 360 + two 20 mm tails
  against bom.csv;
* the build (one shared build, preview): its own every-pair check over the motion; assembly.step
  read back with OCCT (every pair of a capstan part with every other solid at home: no common
  volume); the drum's volume in closed form (annular sector less the anchors' radial holes and
  the groove by Pappus), each rope run's as a cylinder on the external tangent; the MJCF read
  back by MuJoCo (its geoms are the assembly's instances with a solid at the assembly's world
  poses; each waist actuator's gear is the ratio 3, its armature n^2 (J_m + J_capstan) with the
  capstan's inertia as a steel tube by hand).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from tests.capstan_ref import radial_hole_mm3
from tests.step_readback import common_mm3
from tests.step_readback import step_solids as read_step_solids

HERE = Path(__file__).resolve().parent
#: The test case, as ``shared_build`` reads it (a path under designs/).
CASE = "../tests/families/pen/designs/pen_waist_capstan.toml"
FORMATS = ("firmware", "mjcf", "step", "stl")
#: By hand: the drum's pitch radius, the capstan's, the centre distance (pitch radii + 2 mm rim gap).
R_D, R_C, C_MM = 60.0, 20.0, 82.0
ROPE_D, WRAPS = 1.0, 3.0


@pytest.fixture(scope="module")
def design():
    from cad.design import load_design

    return load_design(HERE / "designs" / "pen_waist_capstan.toml")


@pytest.fixture(scope="module")
def built(shared_build):
    """The test case built once per run (preview: the bearings as plain rings, the capstan
    parts as fabricated): (design, out_dir, report)."""
    return shared_build(CASE, FORMATS, "preview")


def _psi_range_deg(design) -> np.ndarray:
    """(2,) the range of each arm's waist angle (deg) over the workspace grid, by hand."""
    m = design.mechanism
    X = np.asarray(design.workspace_points(), float)
    yaw, pitch = X[:, 3], X[:, 4]
    u = np.column_stack([np.cos(pitch) * np.cos(yaw), np.cos(pitch) * np.sin(yaw), np.sin(pitch)])
    out = []
    for sign in (-1.0, 1.0):
        E = X[:, :3] + sign * m.pen_mm / 2 * u
        psi = np.degrees(np.arctan2(E[:, 1], E[:, 0] - sign * m.l4_mm / 2))
        out.append(psi.max() - psi.min())
    return np.array(out)


# ----------------------------------------------------------------------------- fast: no solids
def test_waists_build_with_direct_shoulders(design):
    """The waists' capstans with direct shoulders pass the build's pre-CAD check."""
    from cad.families.pen.build import check_options

    check_options(design, "preview", None)  # no DesignError


def test_the_ground_drops_by_the_drum_band_and_covers_the_moved_motors(design):
    """The direct pen's ground (the same arms) against the capstan pen's: the base plate, the
    bench and the legs' plane 3 mm gap + 10 mm drum lower, the hub on the same foot; the moved
    motors at x0 + 82 (cos, sin)(-170 | -10 deg) under the plate, the plate reaching their
    60 mm mount squares plus the direct pen's margin."""
    import dataclasses

    from cad.families.pen import capstan_solids as pcs
    from cad.families.pen import layout as L

    lay = L.layout(design)
    direct = L.ground_layout(design, lay, -150.0)
    gl = L.ground_layout(design, lay, -150.0, pcs.band_mm(design),
                         [pcs.stations_xy_mm(design)[a] for a in "AB"])
    assert pcs.band_mm(design) == 13.0
    assert gl["base_top_z_mm"] == pytest.approx(direct["base_top_z_mm"] - 13.0, abs=1e-12)
    assert gl["bench_z_mm"] == pytest.approx(direct["bench_z_mm"] - 13.0, abs=1e-12)
    assert gl["waist_hub_mm"] == pytest.approx(direct["waist_hub_mm"], abs=1e-12)
    st = pcs.stations_xy_mm(design)
    for arm, x0, a in (("A", -35.0, -170.0), ("B", 35.0, -10.0)):
        want = (x0 + C_MM * math.cos(math.radians(a)), C_MM * math.sin(math.radians(a)))
        assert st[arm] == pytest.approx(want, abs=1e-9)
    margin = direct["base_plate_x_mm"][1] - 35.0 - 30.0  # the direct plate's margin past a mount square
    assert gl["base_plate_x_mm"][1] == pytest.approx(st["B"][0] + 30.0 + margin, abs=1e-9)
    assert gl["base_plate_y_mm"][0] == pytest.approx(st["B"][1] - 30.0 - margin, abs=1e-9)
    assert gl["base_plate_y_mm"][1] == pytest.approx(direct["base_plate_y_mm"][1], abs=1e-12)
    assert dataclasses.asdict(design.parts)["waist_motor"] == "maxon-re40"


def test_rope_cut_length_against_the_closed_form(design):
    """Each waist rope's cut length in its BOM line: 3 turns pi 40 + two runs
    2 sqrt(82^2 - (60 - 20)^2) + the drum arc pi 120 (range + 4 + 2 deg(10 / 60)) / 360 + two
    20 mm tails, the waist's range by hand (:func:`_psi_range_deg`)."""
    import re

    from cad.families.pantograph.capstan import bom_lines

    rows = {r["part"]: r for r in bom_lines(design)}
    assert set(rows) == {"capstan_cable_1", "capstan_cable_4"}
    for (part, rng) in zip(("capstan_cable_1", "capstan_cable_4"), _psi_range_deg(design), strict=True):
        arc = rng + 4.0 + 2 * math.degrees(10.0 / R_D)
        cut = (WRAPS * math.pi * 2 * R_C + 2 * math.sqrt(C_MM ** 2 - (R_D - R_C) ** 2)
               + math.pi * 2 * R_D * arc / 360.0 + 40.0)
        got = float(re.search(r"cut length (\d+) mm", rows[part]["description"]).group(1))
        assert got == round(cut), (part, got, cut)


# ----------------------------------------------------------------------------- the build

@pytest.fixture(scope="module")
def step_solids(built):
    """assembly.step read back: {instance name ('.' as '_'): solid}."""
    return read_step_solids(built[1] / "assembly.step")


@pytest.mark.slow
def test_the_build_checks_every_pair_with_the_capstan_parts(built):
    """The build's one check over the motion (21 poses) finds no collision and no overlap; the
    assembly holds each waist's drum, axle, bearing block, capstan, two rope runs, tensioner
    and the moved motor's shaft."""
    _, out, rep = built
    itf = rep["interference"]
    assert itf["collisions"] == [] and rep["overlap_volume_mm3"] == 0.0 and itf["n_poses"] == 21
    names = set(rep["placement"]["instances"])
    for arm, i in (("A", 1), ("B", 4)):
        for n in (f"{arm}_waist.capstan_drum", f"capstan_{i}", f"capstan_rope_run_{i}_1",
                  f"capstan_rope_run_{i}_2", f"capstan_tensioner_{i}", f"bearing_block_{i}",
                  f"{arm}_waist_motor.shaft"):
            assert n in names, n
    assert "A_waist.waist_axle4" in names and "A_waist.motor_waist_shaft4" not in names  # on its own axle


@pytest.mark.slow
def test_assembly_step_read_back_shares_no_volume_between_a_capstan_part_and_any_other(step_solids):
    """assembly.step read back with OCCT: each drum, capstan, rope run, axle and bearing block
    has no common volume (OCCT Boolean common, above 1e-4 mm^3) with any other solid at the
    exported pose but a fastener (screws and nuts engage their holes' threads: the build's
    fastener check); a rope run on its own drum and capstan is the rope's contact, not checked."""
    cap = {k: v for k, v in step_solids.items()
           if k.endswith(("capstan_drum", "waist_axle4")) or k.startswith("capstan_rope_run_")
           or k in ("capstan_1", "capstan_4", "bearing_block_1", "bearing_block_4")}
    assert len(cap) == 2 * (1 + 1 + 1 + 2 + 1), sorted(cap)  # drums, axles, blocks, runs, capstans
    others = {k: v for k, v in step_solids.items() if not any(w in k for w in ("screw", "nut", "tensioner", "anchor"))}
    drum = {"1": "A_waist_capstan_drum", "4": "B_waist_capstan_drum"}
    checked = 0
    for a, A in cap.items():
        for b, B in others.items():
            if a == b or (b in cap and b < a):
                continue
            run = a.split("_")[3] if a.startswith("capstan_rope_run_") else (
                b.split("_")[3] if b.startswith("capstan_rope_run_") else None)
            if run is not None and {a, b} & {drum[run], f"capstan_{run}"}:
                continue  # the rope in its own drum's and capstan's grooves
            if A.bounding_box().overlaps(B.bounding_box(), tolerance=0.0) is False:
                continue
            checked += 1
            assert common_mm3(A, B) <= 1e-4, (a, b)
    assert checked >= len(cap)  # each part meets some solid's bounding box (18 pairs at home)


@pytest.mark.slow
def test_drum_and_rope_run_volumes_against_closed_forms(design, step_solids):
    """Each waist drum read back: the annular sector from the 6 mm axle bore to the crests
    (120 - 1) / 2 + 0.35 = 59.85 mm over its arc, 10 mm thick, less the two anchors' radial M3
    tap holes (9 mm below the groove's bottom out through the crests) and the groove (Pappus:
    the 0.5 mm circle's segment under the crests round the arc between the anchors less a land
    of one tap drill and one rope diameter each side). Each rope run: a 1 mm cylinder along the
    external tangent of the pitch circles, sqrt(82^2 - (60 - 20)^2) mm, less its trim at the
    capstan's crests (the shared run_trim_mm)."""
    from cad.assembly.capstan_hardware import run_trim_mm
    from cad.data.catalog import tap_drill_mm
    from cad.families.pen.capstan_solids import waist_sides

    h = 0.35 * ROPE_D
    r_b, r_i = R_D - ROPE_D / 2, 6.0 / 2
    r_o = r_b + h
    x, w = np.polynomial.legendre.leggauss(400)
    u = -ROPE_D / 2 + 0.5 * h * (x + 1.0)  # radial offset from the section circle's centre at 60 mm
    chord = 2.0 * np.sqrt(ROPE_D ** 2 / 4 - u * u)
    area = 0.5 * h * np.sum(w * chord)
    rbar = 0.5 * h * np.sum(w * chord * (R_D + u)) / area
    hole = radial_hole_mm3(tap_drill_mm("M3-0.5") / 2, r_o, 9.0 + h)
    land = math.degrees((tap_drill_mm("M3-0.5") + ROPE_D) / r_b)
    for sd in waist_sides(design):
        lo, hi = sorted(sd.anchors_deg)
        groove = area * rbar * math.radians(hi - lo - 2 * land)
        sector = 0.5 * math.radians(sd.arc_span_deg) * (r_o ** 2 - r_i ** 2) * 10.0
        assert step_solids[f"{sd.joint[0]}_waist_capstan_drum"].volume == pytest.approx(
            sector - 2 * hole - groove, rel=2e-5)
    drawn = math.sqrt(C_MM ** 2 - (R_D - R_C) ** 2) - run_trim_mm(R_C, h)
    for k in (f"{i}_{j}" for i in (1, 4) for j in (1, 2)):
        assert step_solids[f"capstan_rope_run_{k}"].volume == pytest.approx(
            math.pi * (ROPE_D / 2) ** 2 * drawn, rel=1e-6)


@pytest.mark.slow
def test_bom_rope_lines_and_winding_steps_name_parts_of_the_assembly(design, built, step_solids):
    """bom.csv's rope lines are the shared :func:`cad.datasheet.capstan_rows.cable_bom_line`'s
    (the cut length checked above); the anchors, tensioners and lock nuts assembly.md's winding
    steps name are instances of assembly.step; the tensioner hardware and the capstans are
    ordered, two of each."""
    import re

    from cad.families.pantograph.capstan import bom_lines

    _, out, _ = built
    with open(out / "bom.csv", newline="", encoding="utf-8") as f:
        rows = {r["part"]: r for r in csv.DictReader(f)}
    for r in bom_lines(design):
        assert rows[r["part"]]["description"] == r["description"]
    assert int(rows["capstan_tensioner_nut"]["quantity"]) == 2
    # the design's two waist transmissions are the same: one capstan, one tensioner screw, ordered twice
    assert int(rows["capstan_waist"]["quantity"]) == 2 and int(rows["capstan_tensioner_screw_waist"]["quantity"]) == 2
    text = (out / "assembly.md").read_text(encoding="utf-8")
    named = set(re.findall(r"capstan_(?:anchor_\d_1|tensioner_\d|tensioner_nut_\d)\b", text))
    assert named == {f"capstan_{k}" for i in (1, 4) for k in (f"anchor_{i}_1", f"tensioner_{i}",
                                                               f"tensioner_nut_{i}")}
    assert named <= set(step_solids)


@pytest.mark.slow
def test_mjcf_in_mujoco_meshes_are_the_instances_gear_and_armature(design, built):
    """The MJCF read back by MuJoCo at its written pose: the set of (body, geom, mesh) is the
    assembly's (body, instance, kind) of every made part, each geom at the assembly's world
    pose; each waist actuator's gear is 3 and its joint's armature 3^2 (J_m + J_c), J_c the
    capstan as a steel tube (bore 6 mm, crests 39 + 0.7 mm, 1.5 d per turn + 8 mm hub long) less
    its groove (:func:`tests.capstan_ref.grooved_capstan_izz_kg_m2`)."""
    import mujoco

    from cad.data.catalog import get_motor
    from cad.data.materials import get_material
    from cad.families.pen import assemble
    from tests.capstan_ref import grooved_capstan_izz_kg_m2

    _, out, _ = built
    m = mujoco.MjModel.from_xml_path(str(out / f"{design.name}.xml"))
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    geoms = {}
    for g in range(m.ngeom):
        T, M, R = np.eye(4), np.eye(4), np.zeros(9)
        T[:3, :3], T[:3, 3] = d.geom_xmat[g].reshape(3, 3), d.geom_xpos[g]
        mujoco.mju_quat2Mat(R, m.mesh_quat[m.geom_dataid[g]])  # the mesh's frame moved to its inertia's
        M[:3, :3], M[:3, 3] = R.reshape(3, 3), m.mesh_pos[m.geom_dataid[g]]
        body = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, int(m.geom_bodyid[g]))
        geoms[mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_GEOM, g)] = (
            "ground" if body == "world" else body,
            mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_MESH, int(m.geom_dataid[g])), T @ np.linalg.inv(M))
    model = assemble(design, "preview")
    want = {}
    for i in model.instances:
        if i.kind.made and i.kind.listed:
            T = (np.eye(4) if i.body == "ground" else model.tf_world_body[i.body]) @ i.tf_body_part
            T[:3, 3] *= 1e-3
            want[i.name] = (i.body, i.kind.name, T)
    assert {(b, n, k) for n, (b, k, _) in geoms.items()} == {(b, n, k) for n, (b, k, _) in want.items()}
    for name, (_b, _k, T) in want.items():
        np.testing.assert_allclose(geoms[name][2][:3, 3], T[:3, 3], atol=1e-9, err_msg=name)
        # a body of revolution's inertial frame (MuJoCo's mesh_quat) is an eigenvector of a
        # degenerate inertia: its rotation comes back to ~1e-8 (the pen rod)
        np.testing.assert_allclose(geoms[name][2][:3, :3], T[:3, :3], atol=1e-7, err_msg=name)
    assert {"A_capstan_drum_waist", "waist_axle"} <= {k for b, k, _ in geoms.values() if b == "A_waist"}
    jc = grooved_capstan_izz_kg_m2(40.0, ROPE_D, WRAPS, 6.0, get_material("steel-1018").density_kg_m3)
    jm = get_motor("maxon-re40").rotor_inertia_kg_m2
    for arm in "AB":
        a = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_ACTUATOR, f"{arm}_motor_waist")
        assert m.actuator_gear[a, 0] == pytest.approx(3.0, rel=1e-12)
        j = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, f"{arm}_q_waist")
        assert m.dof_armature[m.jnt_dofadr[j]] == pytest.approx(9.0 * (jm + jc), rel=1e-3)
        s = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_ACTUATOR, f"{arm}_motor_lower")
        assert m.actuator_gear[s, 0] == pytest.approx(1.0, rel=1e-12)  # the shoulders direct


@pytest.mark.slow
def test_firmware_gear_is_each_drum_over_its_capstan(built):
    """The generated firmware's HC_GEAR, in the motor order (arm A waist, lower, upper, arm B's):
    120 / 40 = 3 on the waists (the design's drum and capstan), 1 on the direct shoulders."""
    import re

    _, out, _ = built
    text = "\n".join(p.read_text() for p in sorted((out / "firmware").glob("*.h")))
    gear = re.search(r"#define HC_GEAR \{([^}]*)\}", text).group(1)
    assert [float(v) for v in re.findall(r"HC_R\(([-\d.e]+)\)", gear)] == [120 / 40, 1.0, 1.0, 120 / 40, 1.0, 1.0]


@pytest.mark.slow
def test_datasheet_figures_regression_pin(built):
    """Regression pin (values recorded from our own build, 2026-12, preview: the bearings'
    plain rings carry the catalog masses): continuous force in every direction 0.8378 N (MISS
    against 2 N: the shoulders are direct), first mode 20.7 Hz (MISS against 150 Hz, as the
    direct pen), the waists' drum arc 88.56 deg; docs/families/pen.md states them."""
    _, _, rep = built
    rows = {r["key"]: r for r in rep["datasheet"]["rows"]}
    assert round(rows["continuous_force_N"]["value"], 4) == 0.8378
    assert round(rows["first_mode_Hz"]["value"], 1) == 20.7
    assert rows["continuous_force_N"]["verdict"] == "miss" and rows["first_mode_Hz"]["verdict"] == "miss"
    assert round(rows["drum_sector_deg_1"]["value"], 2) == 88.56
    assert all(rows[f"{k}_{i}"]["verdict"] == "ok" for k in ("cable_safety_factor", "cable_slip_margin",
                                                                "drum_sector_deg") for i in (1, 4))
