"""The haptic pen built through the family protocol (cad/families/pen): files from the CLI,
body masses against the STL files read back, the effective mass at home against MuJoCo's
kinetic energy, the MJCF's loop closures, the interference check over the motion (and a bad
variant caught with its pair and pose), the datasheet rows.

One build per module (the CLI, ``--fidelity inertia``: plain-ring bearings, the same
catalog masses).
"""

from __future__ import annotations

import json
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]
DESIGN = ROOT / "designs" / "haptic_pen.toml"


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    from cli_helpers import hapticad

    out = tmp_path_factory.mktemp("pen") / "out"
    code, stdout, err = hapticad("build", DESIGN, "--out", out, "--formats", "step,stl,dxf,mjcf",
                                 "--fidelity", "inertia", "--no-cache")
    assert code == 0, err
    rep = json.loads((out / "report.json").read_text())
    return out, rep


@pytest.fixture(scope="module")
def model():
    from cad.design import load_design
    from cad.families.pen import assemble

    return assemble(load_design(DESIGN), "inertia")


def test_cli_build_writes_the_pen(built):
    out, rep = built
    assert rep["family"] == "haptic-pen"
    for f in ("assembly.step", "bom.csv", "report.json", "report.md", "haptic-pen-200.xml",
              "parts/yoke.stl", "parts/ring.stl", "parts/pen_rod.stl", "parts/waist_bracket.step",
              "parts/base_plate.dxf", "render.png", "animation.gif", "report.html"):
        assert (out / f).is_file(), f
    bodies = set(rep["bodies"])
    assert {"pen", "A_yoke", "B_ring", "A_waist", "B_proximal_upper"} <= bodies and len(bodies) == 15


def test_layout_closes_every_loop_over_the_motion(model):
    """Identity: at every pose of the motion both distal tips meet the yoke's centre (E) and
    the pen's far end meets arm B's gimbal centre; the pen length between them is l6."""
    d = model.design
    l3, l6 = d.params["distal_mm"], d.mechanism.pen_mm
    T = model.motion
    for arm in ("A", "B"):
        E = T[f"{arm}_yoke"][:, :3, 3]
        for side in ("lower", "upper"):
            tip = (T[f"{arm}_distal_{side}"] @ np.array([l3, 0, 0, 1.0]))[:, :3]
            np.testing.assert_allclose(tip, E, atol=1e-9)
    far = (T["pen"] @ np.array([l6, 0, 0, 1.0]))[:, :3]
    np.testing.assert_allclose(far, T["B_yoke"][:, :3, 3], atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(far - T["A_yoke"][:, :3, 3], axis=1), l6, atol=1e-9)


def test_body_masses_equal_the_stl_volumes_read_back(built, model):
    """Each body's mass (exact B-rep, report.json) equals the sum over its parts of the STL
    file's volume (trimesh, read from disk) x the material density, plus the catalog mass of
    its bought parts (motors, bearings): a second route through the exported files."""
    import trimesh

    from cad.data.materials import get_material

    out, rep = built
    expect: dict[str, float] = {}
    vol_cache: dict[str, float] = {}
    for inst in model.instances:
        k = inst.kind
        if inst.body == "ground" or k.inertia_model == "none":
            continue
        if k.mass_kg is not None:
            m = k.mass_kg
        else:
            if k.name not in vol_cache:
                stl = out / "parts" / f"{k.name}.stl"  # made parts; a bought screw: its STEP
                mesh = (trimesh.load(stl, force="mesh") if stl.is_file()
                        else _step_mesh(out / "parts" / f"{k.name}.step"))
                assert mesh.is_watertight, k.name
                vol_cache[k.name] = float(mesh.volume)
            m = vol_cache[k.name] * 1e-9 * get_material(k.material).density_kg_m3
        expect[inst.body] = expect.get(inst.body, 0.0) + m
    assert set(expect) == set(rep["bodies"])
    for b, m in expect.items():
        # STL at 0.01 mm chordal tolerance: volumes within 1e-3 of the B-rep
        assert rep["bodies"][b]["mass_kg"] == pytest.approx(m, rel=1e-3), b


def test_screws_sit_in_their_holes_in_the_step_file(built):
    """Every screw has its record (catalog length, one screw per hole, engagement within the
    hole's window) and, read back from assembly.step (OCCT's XCAF reader), each vertical one
    engages the part its hole names by the recorded length, its tip free (tests/step_pairs)."""
    from step_pairs import read_parts, thread_in_part_mm

    from cad.data import catalog

    out, rep = built
    f, holes = rep["fasteners"], rep["tapped_holes"]
    assert len(f) == 30 and len({x["hole"] for x in f.values()}) == 30
    parts = dict(read_parts(out / "assembly.step"))
    measured = 0
    for name, x in f.items():
        cs = catalog.get_cap_screw(x["size"], "test")
        h = holes[x["hole"]]
        assert x["length_mm"] in cs.lengths_mm and x["engagement_mm"] <= h["depth_mm"] + 1e-9
        assert x["engagement_mm"] >= h["min_engagement_mm"] - 1e-9, name
        if ".shoulder_screw_" in name:
            continue  # horizontal: the check measures vertical screws
        e, tip_free = thread_in_part_mm(parts[name], parts[h["part"]], cs.d_mm, cs.dk_mm)
        assert e == pytest.approx(x["engagement_mm"], abs=0.01), (name, h["part"], e)
        assert tip_free, name
        measured += 1
    assert measured == 18  # legs 4, waist mount plates 8, waist motor faces 6


def _step_mesh(path: Path):
    """The STEP file read back (OCCT's reader), meshed at 0.01 mm, as a merged trimesh."""
    import trimesh
    from OCP.BRep import BRep_Tool
    from OCP.BRepMesh import BRepMesh_IncrementalMesh
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPControl import STEPControl_Reader
    from OCP.TopAbs import TopAbs_FACE, TopAbs_REVERSED
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopLoc import TopLoc_Location
    from OCP.TopoDS import TopoDS

    r = STEPControl_Reader()
    assert r.ReadFile(str(path)) == IFSelect_RetDone, path
    r.TransferRoots()
    shape = r.OneShape()
    BRepMesh_IncrementalMesh(shape, 0.01, False, 0.1, True)
    verts, faces = [], []
    exp = TopExp_Explorer(shape, TopAbs_FACE)
    while exp.More():
        face = TopoDS.Face_s(exp.Current())
        loc = TopLoc_Location()
        tri = BRep_Tool.Triangulation_s(face, loc)
        T = loc.Transformation()
        base = len(verts)
        for i in range(1, tri.NbNodes() + 1):
            p = tri.Node(i).Transformed(T)
            verts.append((p.X(), p.Y(), p.Z()))
        rev = face.Orientation() == TopAbs_REVERSED
        for i in range(1, tri.NbTriangles() + 1):
            a, b, c = tri.Triangle(i).Get()
            faces.append((base + a - 1, base + (c if rev else b) - 1, base + (b if rev else c) - 1))
        exp.Next()
    mesh = trimesh.Trimesh(np.array(verts), np.array(faces), process=True)
    mesh.merge_vertices()
    return mesh


def _mujoco_home(out: Path):
    import mujoco

    m = mujoco.MjModel.from_xml_path(str(out / "haptic-pen-200.xml"))
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    return mujoco, m, d


def test_mjcf_loads_and_its_loops_close_at_home(built):
    out, _ = built
    mujoco, m, d = _mujoco_home(out)
    assert m.neq == 4 and m.nu == 6 and m.nv == 15
    eq = d.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY
    assert eq.sum() == 12
    assert np.abs(d.efc_pos[eq]).max() < 1e-9  # m: every loop closed at the written pose


def test_mjcf_actuators_are_the_bom_motors_peak_torques(built):
    """Each actuator's force range (read back by MuJoCo) is the peak torque of the motor the
    BOM orders for its joint (catalog: RE 40 2560 mN m on the waists, RE 35 972.5 mN m on the
    shoulders, the data sheets cited in cad/data/catalog.py), not the GII's normalisation."""
    from cad.data.catalog import get_motor

    out, _ = built
    mujoco, m, _d = _mujoco_home(out)
    d = tomllib.loads(Path(DESIGN).read_text())
    peak = {"waist": get_motor(d["parts"]["waist_motor"]).torque_peak_mNm * 1e-3,
            "lower": get_motor(d["parts"]["motor"]).torque_peak_mNm * 1e-3}
    peak["upper"] = peak["lower"]
    for i in range(m.nu):
        name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_ACTUATOR, i)
        assert m.actuator_forcerange[i] == pytest.approx([-peak[name.split("_")[-1]], peak[name.split("_")[-1]]],
                                                         rel=1e-12), name


def test_effective_mass_at_home_equals_mujoco_kinetic_energy(built):
    """Second method: MuJoCo's joint-space mass matrix (its own composite-rigid-body pass over
    the MJCF's bodies, rotor inertia as armature), mapped to the task by the joint velocities
    that satisfy every loop constraint and give the pen a unit task velocity -- against the
    report's matrix (central differences of the body poses + the pen Jacobian)."""
    out, rep = built
    mujoco, m, d = _mujoco_home(out)
    Mq = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, Mq)  # armature (rotor inertia) included
    eq = d.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY
    Jeq = d.efc_J.reshape(-1, m.nv)[eq]
    pen = m.body("pen").id
    from cad.design import load_design

    l6 = load_design(DESIGN).mechanism.pen_mm * 1e-3
    centre = d.xpos[pen] + d.xmat[pen].reshape(3, 3)[:, 0] * l6 / 2
    jp, jr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
    mujoco.mj_jac(m, d, jp, jr, centre, pen)
    # task unit velocities at home (pen along +x): x, y, z; w_yaw -> omega z; w_pitch -> -y
    target = np.zeros((6, 5))
    target[:3, :3] = np.eye(3)
    target[5, 3] = 1.0
    target[4, 4] = -1.0
    A = np.vstack([Jeq, jp, jr])
    rhs = np.vstack([np.zeros((len(Jeq), 5)), target])
    G = np.linalg.lstsq(A, rhs, rcond=None)[0]
    np.testing.assert_allclose(A @ G, rhs, atol=1e-9)  # consistent: one motion per task velocity
    M_mj = G.T @ Mq @ G
    M = np.array(rep["effective_mass_home"]["mass_matrix_si"])
    np.testing.assert_allclose(M, M_mj, rtol=1e-6, atol=1e-9 * np.abs(M).max())


def test_no_solid_pair_overlaps_over_the_motion(built):
    _, rep = built
    itf = rep["interference"]
    assert itf["n_poses"] == 21 and itf["method"].endswith("occt")  # exact pass on the solids
    assert itf["collisions"] == [] and rep["overlap_volume_mm3"] == 0.0
    assert rep["min_clearance_mm"] >= 0.0


def test_a_bad_variant_is_caught_away_from_home_with_pair_and_pose(tmp_path):
    """A pen twice as thick (20 mm): its hub's rod boss reaches the gimbal ring once the pen
    pitches, so home is clear and the tilted poses are not; the build names the pair and
    the pose; nothing is published."""
    from cad.design import parse_design
    from cad.errors import InterferenceError
    from cad.families.pen import assemble
    from cad.pipeline import build_design, family

    raw = tomllib.loads(DESIGN.read_text())
    raw["parts"]["pen_diameter_mm"] = 20.0
    d = parse_design(raw, "thick_pen.toml")
    mdl = assemble(d, "inertia")
    assert family.check_assembly(mdl.instances, mdl.tf_world_body)["collisions"] == []
    with pytest.raises(InterferenceError) as exc:
        build_design(d, tmp_path / "o", {"step"}, fidelity="inertia", use_cache=False)
    msg = str(exc.value)
    pair = r"[AB]_ring\.ring\d / pen\.[AB]_pen_hub\d|pen\.[AB]_pen_hub\d / [AB]_ring\.ring\d"
    assert re.search(pair, msg), msg
    assert "pitch -45 deg" in msg or "pitch 45 deg" in msg, msg
    assert not (tmp_path / "o").exists()  # nothing published (the exports child wrote to a temporary folder)


def test_datasheet_prints_the_pen_rows():
    from cli_helpers import hapticad

    code, out, err = hapticad("datasheet", DESIGN, "--json")
    assert code == 0, err
    rows = {r["key"]: r for r in json.loads(out)["datasheet"]["rows"]}
    assert rows["force_any_dir_N"]["value"] > 0
    assert rows["effective_mass_home.mass_x_g_apparent"]["paper"] == 190.0  # Table 3
    assert rows["overlap_volume_mm3"]["value"] == 0.0
    # from the catalog motors' data-sheet torques, Table 3's smallest axis figure beside it
    assert rows["continuous_force_N"]["paper"] == 2.0 and rows["peak_force_N"]["paper"] == 20.0
    assert 0 < rows["continuous_force_N"]["value"] < rows["peak_force_N"]["value"]
    # the structure rows (cad/structure/pen.py), never silent: a value, its boundary
    # conditions and a verdict against the default limits; the pen's first mode misses
    # 150 Hz, one warning line on stderr, the JSON's warnings list holds it
    fm, st = rows["first_mode_Hz"], rows["max_stress_MPa"]
    assert fm["value"] is not None and fm["verdict"] == "miss" and fm["limit"]["value"] == 150.0
    assert "motors held" in fm["boundary"] and "planar, per pantograph" in fm["model"]
    assert st["verdict"] == "ok" and 0 < st["value"] < st["limit"]["value"]
    assert any(w.startswith("datasheet: first structural mode") for w in json.loads(out)["warnings"])
    assert "warning: datasheet: first structural mode" in err
    code, out, err = hapticad("datasheet", DESIGN)
    assert code == 0, err
    assert "effective mass at home" in out and "first structural mode" in out
    assert "warning: datasheet: first structural mode" in err


@pytest.mark.parametrize(
    "key, value, field",
    [
        ("knob_height_mm", 20.0, "parts.knob_height_mm"),  # the mouse's, refused
        ("pen_diamter_mm", 10.0, "parts.pen_diamter_mm"),  # a typo
        ("gimbal_ring_mm", 20.0, "parts.gimbal_ring_mm"),  # cannot hold the hub's bearings
        ("pen_diameter_mm", 29.0, "parts.pen_diameter_mm"),  # does not pass the ring
        ("pen_diameter_mm", 1e300, "parts.pen_diameter_mm"),  # past the part-size bound
        ("waist_motor", "maxon-re99", "parts.waist_motor"),  # not in the catalog
        ("tube_id_mm", 9.0, "parts.tube_id_mm"),  # the twin pantograph's own check
    ],
)
def test_bad_parts_keys_are_named_before_any_cad(tmp_path, key, value, field):
    from cli_helpers import assert_one_line_error, hapticad

    text = f'"{value}"' if isinstance(value, str) else repr(value)
    raw = re.sub(rf"^{key} = .*\n", "", DESIGN.read_text(), flags=re.M)  # the design's own value
    raw = raw.replace("[parts]\n", f"[parts]\n{key} = {text}\n")
    bad = tmp_path / "bad.toml"
    bad.write_text(raw)
    code, _, err = hapticad("build", bad, "--out", tmp_path / "o")
    assert_one_line_error(code, err, field)
    assert not (tmp_path / "o").exists()


def test_assembly_md_places_every_bom_line_once(built):
    """The pen writes assembly.md through the writer of every family: every BOM line (read
    back from bom.csv, a second writer) appears as many times as its quantity among the
    steps' part lines, and the pen's final checks close it."""
    import collections
    import csv

    from cad.families.pen.build import ASSEMBLY_CHECKS

    out, rep = built
    assert "assembly.md" in rep["files"]
    text = (out / "assembly.md").read_text()
    placed = collections.Counter(re.findall(r"^- `[^`]+` \(([^)]+)\)", text, re.M))
    with (out / "bom.csv").open(newline="") as f:
        rows = list(csv.DictReader(f))
    assert rows and {r["part"]: int(r["quantity"]) for r in rows} == dict(placed)
    for check in ASSEMBLY_CHECKS:
        assert f"- check: {check}" in text


def test_mass_x_breakdown_sums_to_the_effective_mass_part_by_part(built, model):
    """The breakdown of the x effective mass (report.json ``effective_mass_breakdown``, every
    part's kinetic energy) sums to ``effective_mass_home.mass_x_g_diag`` (computed from the
    combined body mass properties); each body's parts sum to that body's term; the shoulder
    motors' share equals the closed form of a rigid waist turning at v / R about its vertical
    axis (R = the home distance of E from the waist axis), sum of m d^2 + I_zz over the motors
    placed in the world."""
    from cad.families.pen.dynamics import body_jacobians, mass_breakdown
    from cad.massprops.props import MassProps
    from cad.pipeline import family

    out, rep = built
    bd = rep["effective_mass_breakdown"]
    em = rep["effective_mass_home"]
    assert bd["total_g"] == pytest.approx(em["mass_x_g_diag"], rel=1e-12)
    assert sum(bd["groups_g"].values()) == pytest.approx(bd["total_g"], rel=1e-12)
    assert sum(bd["by_kind_g"].values()) + sum(bd["rotors_g"].values()) == pytest.approx(bd["total_g"], rel=1e-12)
    assert bd["paper_g"] == 190.0 and "other" not in bd["groups_g"]
    d = model.design
    props = family.kind_props(model.instances)
    X = np.array(em["at_task"])
    parts: dict = {}
    for i in model.instances:
        if props[i.kind.name] is not None:
            T = i.tf_body_part
            parts.setdefault(i.body, []).append((i.kind.name, props[i.kind.name].transformed(T[:3, :3], T[:3, 3] * 1e-3)))
    r = mass_breakdown(d, parts, X, "x")
    jac = body_jacobians(d, X)
    for body, b in rep["bodies"].items():  # each body: its parts' terms = the combined body's term
        mp = MassProps(b["mass_kg"], np.array(b["com_mm"]) * 1e-3, np.array(b["inertia_com_kg_m2"]))
        whole = mass_breakdown(d, {body: [("all", mp)]}, X, "x", rotor_kg_m2=np.zeros(6))["total"]
        assert sum(v for bb, _, v in r["parts"] if bb == body) == pytest.approx(whole, rel=1e-9, abs=1e-15), body
    # closed form for the shoulder motors: the waist is a rigid body turning about z at v / R
    R_m = np.hypot(*(model.tf_world_body["A_yoke"][:2, 3] - model.tf_world_body["A_waist"][:2, 3])) * 1e-3
    want = 0.0
    for i in model.instances:
        if i.body.endswith("_waist") and i.kind.name.startswith("motor") and props[i.kind.name] is not None:
            Tw = model.tf_world_body[i.body] @ i.tf_body_part
            mp = props[i.kind.name].transformed(Tw[:3, :3], Tw[:3, 3] * 1e-3)  # world frame
            axis = model.tf_world_body[i.body][:2, 3] * 1e-3
            want += mp.mass_kg * np.sum((mp.com_m[:2] - axis) ** 2) + mp.inertia_com_kg_m2[2, 2]
    want /= R_m**2
    assert jac["A_waist"][1][2, 0] == pytest.approx(-1 / R_m, rel=1e-6)  # the waist turns at v / R
    got = bd["groups_g"]["shoulder motors (on the waist brackets)"] * 1e-3
    assert got == pytest.approx(want, rel=1e-6)
    assert bd["without_shoulder_motors_g"] == pytest.approx(bd["total_g"] - got * 1e3, rel=1e-12)
    from cad.families.pen.datasheet import rows_and_limits

    rows, _, _ = rows_and_limits(d, rep, simulate_wall=False)
    (row,) = [x for x in rows if x["key"] == "mass_x_breakdown_g"]
    assert row["value"] == bd["total_g"] and row["paper"] == 190.0
    assert f"{got * 1e3:.0f} g" in row["model"] and "shoulder motors" in row["model"]


def test_docs_pen_page_states_this_builds_breakdown(built):
    """docs/families/pen.md's "Why x is 860 g" table and text are this build's numbers (the
    typed-number ledger points here): the total, the motors' share and the rest, rounded as
    printed."""
    from pathlib import Path

    bd = built[1]["effective_mass_breakdown"]
    text = (Path(__file__).resolve().parents[3] / "docs" / "families" / "pen.md").read_text()
    assert f"**Why x is {bd['total_g']:.0f} g, not 190 g.**" in text
    assert f"| **{bd['total_g']:.0f}** |" in text
    assert f"it would be {bd['without_shoulder_motors_g']:.0f} g" in text
    for group, g in bd["groups_g"].items():
        assert f"| {g:.0f} |" in text, group
