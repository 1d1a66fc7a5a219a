"""Every non-four-bar family builds into the same, complete output (issue 10 §2).

Proof read back from disk with a second tool: the assembly STEP is re-imported with OCCT's
XCAF reader and every pair of its parts is intersected (``tests/step_pairs.py``, common
volume > 1e-3 mm^3 is a clash); the twin pantograph's solids are compared with the bench
plane (the bottom of its legs); the layout, BOM and manifest are read from the files.
One build per family at the cheap ``inertia`` fidelity (plain bearing rings: the check is
the same, the bearing is one part either way), shared through ``conftest.family_builds``.
"""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path

import pytest
from step_pairs import clashes, read_parts

ROOT = Path(__file__).resolve().parents[2]
FAMILIES = {
    "pantograph": "pantograph.toml",
    "twin-pantograph": "haptic_mouse.toml",
    "powermouse": "powermouse.toml",
}
LAYOUT = ("assembly.step", "bom.csv", "report.json", "report.md", "preview.png", "manifest.json")


@pytest.fixture(scope="module")
def builds(family_builds):
    return family_builds


@pytest.fixture(scope="module")
def step_parts(builds):
    """``{family: [(part name, [solids])]}`` read back from each assembly.step."""
    return {fam: read_parts(out / "assembly.step") for fam, (_, out, _) in builds.items()}


@pytest.mark.parametrize("fam", list(FAMILIES))
def test_every_family_writes_the_same_layout(builds, fam):
    _, out, rep = builds[fam]
    for name in LAYOUT:
        assert (out / name).is_file() and (out / name).stat().st_size > 0, name
    assert (out / "parts").is_dir() and any((out / "parts").glob("*.step"))
    manifest = {f["path"] for f in json.loads((out / "manifest.json").read_text())["files"]}
    on_disk = {p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file()} - {
        "manifest.json"
    }
    assert manifest == on_disk
    assert set(rep["files"]) | {"report.json"} <= manifest
    with (out / "bom.csv").open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert rows and all(r["description"].strip() for r in rows), rows
    # every BOM part has its STEP file but the joint encoders (bought, no modelled solid; one
    # per motor, cad.device.encoder_bom_rows)
    assert {r["part"] for r in rows if r["part"] != "encoder"} == {p.stem for p in (out / "parts").glob("*.step")}
    assert sum(int(r["quantity"]) for r in rows if r["part"] == "encoder") == len(rep["device"]["motors"])


@pytest.mark.parametrize("fam", list(FAMILIES))
def test_assembly_step_read_back_has_no_overlapping_pair(builds, step_parts, fam):
    _, out, rep = builds[fam]
    assert len(step_parts[fam]) == rep["interference"]["parts"]  # every instance is in the file
    assert clashes(out / "assembly.step") == []
    assert rep["overlap_volume_mm3"] == 0.0


def test_twin_pantograph_stands_on_the_bench(builds, step_parts):
    """No solid of the mouse (read back from assembly.step) lies below the legs' feet."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    _, out, rep = builds["twin-pantograph"]
    zmin = {}
    for name, solids in step_parts["twin-pantograph"]:
        b = Bnd_Box()
        for s in solids:
            BRepBndLib.AddOptimal_s(s, b, False)
        zmin[name] = b.CornerMin().Z()
    legs = [z for n, z in zmin.items() if n.startswith("leg_") and "screw" not in n]
    assert len(legs) == 4 and max(legs) - min(legs) < 1e-6
    bench = min(legs)
    assert bench == pytest.approx(rep["bench_z_mm"], abs=1e-6)
    low = {n: z for n, z in zmin.items() if z < bench - 1e-6}
    assert low == {}
    # the motors hang under the base plate and clear the bench
    motors = [
        z
        for n, z in zmin.items()
        if n.startswith("lower_motor_") and "mount" not in n and "screw" not in n
    ]
    assert len(motors) == 2 and min(motors) > bench + 5.0


def test_pantograph_5bar_builds_its_parts(builds):
    d, out, rep = builds["pantograph"]
    names = {p.stem for p in (out / "parts").glob("*.step")}
    assert {"clevis_hub", "tube_proximal", "tube_distal", "handle_pin", "knob", "leg"} <= names
    assert set(rep["bodies"]) == {
        "proximal_left",
        "proximal_right",
        "distal_left",
        "distal_right",
        "handle",
    }
    m = rep["effective_mass_home"]["mass_matrix_g"]
    assert m[0][1] == pytest.approx(m[1][0], rel=1e-12) and m[0][0] > 0 and m[1][1] > 0


def test_powermouse_can_be_put_together(builds, step_parts):
    """Open flotor and housing boxes with lids; the core (with its magnets) passes the flotor
    opening; the post is its own part in a bore; the test rig lives in rig/."""
    d, out, rep = builds["powermouse"]
    names = {n for n, _ in step_parts["powermouse"]}
    assert {"flotor_body", "flotor_lid", "housing_body", "housing_lid", "post", "core"} <= names
    assert not any(n.startswith(("act_", "rig_")) for n in names)
    g = rep["geometry_mm"]
    opening_half = g["flotor_edge_mm"] / 2 - rep["actuator_geometry_mm"]["coil_width_mm"]
    core_reach = g["core_half_mm"] + d.actuator.magnet_thickness_mm
    assert core_reach < opening_half
    rig = {n for n, _ in read_parts(out / "rig" / "assembly.step")}
    assert "coil" in rig and len(rig) == 11
    assert (out / "rig" / "bom.csv").is_file()


@pytest.mark.parametrize(
    "design, extra, field",
    [
        ("haptic_pen.toml", ["--phi1-deg", "10"], "--phi1-deg"),
        ("pantograph.toml", ["--phi1-deg", "10"], "--phi1-deg"),
        ("powermouse.toml", ["--phi1-deg", "10"], "--phi1-deg"),
    ],
)
def test_unsupported_combinations_fail_before_any_cad_import(tmp_path, design, extra, field):
    code = (
        "import sys\n"
        "from cad.cli.app import run\n"
        f"rc = run(['build', {str(ROOT / 'designs' / design)!r}, '--out', {str(tmp_path / 'o')!r}]"
        f" + {extra!r})\n"
        "assert 'build123d' not in sys.modules and 'OCP' not in sys.modules\n"
        "sys.exit(rc)\n"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert r.returncode == 2, r.stderr
    lines = [ln for ln in r.stderr.strip().splitlines() if ln.strip()]
    assert len(lines) == 1 and field in lines[0] and "Traceback" not in r.stderr
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("fam", list(FAMILIES))
def test_viewer_files_come_from_the_same_instances(builds, step_parts, fam):
    """report.html, the still and the animation exist; assembly.glb (read back with
    pygltflib) holds a node for every part instance of assembly.step (the motor shafts,
    not listed parts, are drawn with their motor's kind only in the STEP) and one per body."""
    import pygltflib

    _, out, rep = builds[fam]
    for name in ("report.html", "render.png", "animation.gif", "assembly.glb"):
        assert (out / name).is_file() and (out / name).stat().st_size > 0, name
    gl = pygltflib.GLTF2().load(str(out / "assembly.glb"))
    names = {n.name for n in gl.nodes}
    shafts = {n for n, _ in step_parts[fam] if n.endswith(".motor_shaft")}  # inside the motor
    assert {n for n, _ in step_parts[fam]} - shafts <= names
    bodies = {n[5:] for n in names if n.startswith("body:")}
    assert bodies == set(rep.get("bodies", {})) | {"ground"} or fam == "powermouse"
    assert gl.animations and gl.animations[0].channels
