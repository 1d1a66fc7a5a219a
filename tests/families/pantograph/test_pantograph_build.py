"""Twin-pantograph mouse build: files, masses against closed forms, effective mass, interference."""

from __future__ import annotations

import csv
import json
import math

import pytest

from cad.design import parse_design
from cad.design.fields import load_toml
from cad.errors import InterferenceError

DESIGN = "designs/haptic_mouse.toml"


@pytest.fixture(scope="module")
def built(family_builds):
    """The shared mouse build (conftest.family_builds: inertia fidelity, every format)."""
    return family_builds["twin-pantograph"]


def test_files_manifest_and_bom(built):
    design, out, rep = built
    for name in (
        "clevis_hub",
        "clevis_pin",
        "clevis_bearing",
        "tube_proximal",
        "tube_distal",
        "crankshaft",
        "knob",
    ):
        assert (out / "parts" / f"{name}.step").stat().st_size > 0 and (
            out / "parts" / f"{name}.stl"
        ).stat().st_size > 0
    for plate in ("base_plate", "bridge_plate", "motor_mount"):
        assert (out / "parts" / f"{plate}.dxf").exists()
    assert (out / "assembly.step").exists()
    assert (
        not (out / "parts" / "bearing.stl").exists() and (out / "parts" / "bearing.step").exists()
    )  # bought: STEP only
    manifest = json.loads((out / "manifest.json").read_text())
    assert {f["path"] for f in manifest["files"]} >= {"bom.csv", "report.json", "parts/knob.step"}
    with (out / "bom.csv").open(newline="") as fh:
        rows = {r["part"]: r for r in csv.DictReader(fh)}
    assert rows["bearing"]["quantity"] == "16" and rows["motor"]["quantity"] == "4"
    assert rows["tube_distal"]["material"] == "carbon-fibre"


def test_part_masses_against_closed_forms(built):
    design, _, rep = built
    p = design.parts
    bom = {r["part"]: r for r in rep["bom"]}
    rho_cf = 1550.0
    for name, length in (
        ("tube_proximal", rep["layout_mm"]["tube_proximal_mm"]),
        ("tube_distal", rep["layout_mm"]["tube_distal_mm"]),
    ):
        v_mm3 = math.pi / 4 * (p.tube_od_mm**2 - p.tube_id_mm**2) * length
        assert bom[name]["mass_g"] == pytest.approx(v_mm3 * rho_cf * 1e-6, rel=1e-9)
    # tube lengths: link length minus the two clevis stand-offs
    assert rep["layout_mm"]["tube_distal_mm"] == pytest.approx(175.0 - 2 * (20.0 - 10.0))
    pin = math.pi / 4 * 4.0**2 * rep["layout_mm"]["pin_long_mm"] * 7870.0 * 1e-6
    assert bom["pin_long"]["mass_g"] == pytest.approx(pin, rel=1e-9)
    assert bom["bearing"]["mass_g"] == pytest.approx(0.7)  # SKF 618/4 catalogue mass
    # a moving body is the sum of its parts (2 clevises + tube + 4 bearings for a distal link)
    distal = rep["bodies"]["crank_distal_left"]["mass_kg"] * 1e3
    assert distal == pytest.approx(
        2 * bom["clevis_bearing"]["mass_g"] + bom["tube_distal"]["mass_g"] + 4 * 0.7, rel=1e-9
    )
    # symmetric distal link: COM at mid-length
    assert rep["bodies"]["crank_distal_left"]["com_mm"][0] == pytest.approx(87.5, abs=1e-6)


def test_effective_mass_and_gii_reported(built):
    _, _, rep = built
    e = rep["effective_mass_home"]
    for k in ("mass_x_g_diag", "mass_y_g_diag", "inertia_theta_g_cm2_diag", "mass_x_g_apparent"):
        assert e[k] > 0
    # apparent mass (others free) never exceeds the diagonal (others held): 1/(M^-1)_ii <= M_ii
    assert e["mass_x_g_apparent"] <= e["mass_x_g_diag"] * (1 + 1e-12)
    # the moving parts bound the translational mass from above on the diagonal:
    # no body moves faster than the end effector by more than the link ratios allow
    assert e["mass_x_g_diag"] < 2 * rep["moving_mass_g"]
    assert rep["effective_mass_home_without_rotors"]["mass_x_g_diag"] < e["mass_x_g_diag"]
    assert rep["paper_table1"]["mass_x_g"] == 395.0
    assert 0 < rep["gii"]["gii"] < 1
    assert rep["clearances_mm"]["min_gap_mm"] > 0.5


def test_interference_is_refused_before_anything_is_written(tmp_path):
    from pathlib import Path

    from cad.pipeline import build_design

    root = Path(__file__).resolve().parents[3]
    raw = load_toml(root / DESIGN)
    raw["mechanism"]["base_mm"] = 10.0  # proximal hubs 10 mm apart, 14 mm wide
    design = parse_design(raw, "tight.toml")
    out = tmp_path / "out"
    # the solid check names the first clash: the motors 10 mm apart share a volume
    with pytest.raises(InterferenceError, match=r"motor_\d / \w*motor_\d \(both on ground\) "
                       r"share [0-9.]+ mm\^3"):
        build_design(design, out, {"step"}, fidelity="preview", use_cache=False)
    assert not out.exists()


def _big_knob_mouse():
    """The mouse with a 250 mm knob (crank kept at 20 mm): the knob, at the bridge plate's
    height, reaches over the bridge plate (y <= 32.5 mm) when the crankshaft is on the near
    row of the workspace (y = 150 mm: knob edge at y = 25 mm) and clears it elsewhere (home
    y = 200 mm: edge at 75 mm; next row y = 175: edge at 50 mm)."""
    from pathlib import Path

    raw = load_toml(Path(__file__).resolve().parents[3] / DESIGN)
    raw["mechanism"]["knob_diameter_mm"] = 250.0
    raw["mechanism"]["crank_mm"] = 20.0
    return parse_design(raw, "big_knob.toml")


def test_solid_clash_away_from_home_is_found_with_pair_pose_and_volume():
    """The one interference check sweeps the solids over the workspace grid: a clash that
    exists only on the near row (not at home) is found, named by pair and pose, and its
    volume equals the closed form (circular segment of the knob below the plate's edge x
    plate thickness; the plate's holes lie outside the segment)."""
    from cad.assembly import interference as itf
    from cad.families.pantograph import assemble
    from cad.families.pantograph.build import motor_joints

    design = _big_knob_mouse()
    model = assemble(design, "preview")
    rep = itf.check_model(model, joints=motor_joints(design))
    assert rep.collisions, "the knob over the bridge plate was not found"
    assert {tuple(c["parts"]) for c in rep.collisions} == {("knob", "bridge_plate")}
    poses = {c["pose"] for c in rep.collisions}
    assert all(" y=150 mm" in p for p in poses), poses  # the near row only
    assert not any(p.startswith("home") for p in poses)
    assert len(poses) == 5 * 8  # 5 grid points of that row x 8 crank angles
    c = next(c for c in rep.collisions if c["pose"] == "x=0 y=150 mm theta=0 deg")
    r, h = 125.0, 32.5 - 25.0  # knob radius; the plate's edge y = 32.5 above its lowest y = 25
    assert model.extra.layout["bridge_y_mm"][1] == pytest.approx(32.5)
    segment_mm2 = r * r * math.acos((r - h) / r) - (r - h) * math.sqrt(2 * r * h - h * h)
    expected = segment_mm2 * design.parts.plate_thickness_mm
    assert c["parts_overlap_volume_mm3"] == pytest.approx(expected, rel=1e-9)
    with pytest.raises(InterferenceError, match=r"knob / bridge_plate collide at pose x=-?\d+ "
                       r"y=150 mm theta=\d+ deg \(overlap [0-9.]+ mm\^3"):
        itf.raise_on_collision(rep, 0.0)


def test_bundled_mouse_is_clear_over_its_motion(built):
    """The bundled mouse passes the check over its whole motion grid (home + 5 x 5 points x 8
    crank angles): no collision between bodies or within one, no two bodies touching."""
    _, _, rep = built
    itf = rep["interference"]
    assert itf["collisions"] == [] and rep["overlap_volume_mm3"] == 0.0
    assert itf["n_poses"] == 1 + 5 * 5 * 8
    assert itf["same_body"]["collisions"] == []
    assert rep["min_clearance_mm"] > 0.0
