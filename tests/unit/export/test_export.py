"""Exports: STEP re-imports valid with the same volume, STL watertight and accepted by
manifold3d, byte-identical output, DXF area = volume / thickness, atomic failure."""

from __future__ import annotations

import csv
import hashlib
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from cad.errors import MeshError

ROOT = Path(__file__).resolve().parents[3]


@pytest.fixture(scope="module")
def plate():
    """A plate part with holes and a slot: 80 x 30 x 6 mm (closed form volume below)."""
    from build123d import Box, Cylinder, Pos, SlotCenterToCenter, extrude

    body = Box(80, 30, 6) - Pos(-30, 0, 0) * Cylinder(4, 10) - Pos(30, 0, 0) * Cylinder(3, 10)
    body = body - extrude(SlotCenterToCenter(20, 8), amount=10, both=True)
    return body.solids()[0].wrapped


PLATE_VOLUME = (80 * 30 - math.pi * 16 - math.pi * 9 - (20 * 8 + math.pi * 16)) * 6


def test_plate_fixture_volume(plate):
    from cad.massprops.occt import volume_mm3

    assert volume_mm3(plate) == pytest.approx(PLATE_VOLUME, rel=1e-9)


def test_step_reimports_valid_with_the_same_volume(plate, tmp_path):
    from cad.export import export_part
    from cad.export.shapes import is_valid
    from cad.massprops.occt import read_step, volume_mm3

    paths = export_part(plate, "plate", tmp_path, {"step"})
    assert [p.name for p in paths] == ["plate.step"]
    back = read_step(paths[0])
    topo = getattr(back, "wrapped", back)
    assert is_valid(topo)
    assert volume_mm3(topo) == pytest.approx(PLATE_VOLUME, rel=1e-9)
    head = paths[0].read_text(errors="replace")[:400]
    assert "2000-01-01T00:00:00" in head and "'plate'" in head


def test_stl_is_watertight_manifold_and_close_to_the_solid(plate, tmp_path):
    from cad.export import export_part
    from cad.export.stl import manifold_status, open_edge_count, read_stl_arrays

    (p,) = export_part(plate, "plate", tmp_path, {"stl"}, tolerance_mm=0.01)
    v, f = read_stl_arrays(p.read_bytes())
    assert open_edge_count(f) == 0
    assert manifold_status(v, f) == "NoError"
    import manifold3d

    m = manifold3d.Manifold(manifold3d.Mesh64(vert_properties=v, tri_verts=f.astype(np.uint64)))
    # chordal mesh of the holes lies outside the solid's material: volume within tol x hole area
    hole_wall = 6 * (2 * math.pi * 4 + 2 * math.pi * 3 + 2 * math.pi * 4 + 40)
    assert abs(m.volume() - PLATE_VOLUME) <= 0.01 * hole_wall
    assert m.genus() == 3  # three through holes (two round, one slot)


def test_open_shell_is_refused_and_nothing_is_written(tmp_path):
    from build123d import Box

    from cad.export import export_part

    open_shell = Box(10, 10, 10).faces()[0].wrapped  # a single face: not watertight
    with pytest.raises(MeshError):
        export_part(open_shell, "broken", tmp_path, {"step", "stl"})
    assert list(tmp_path.iterdir()) == []


def test_stl_step_dxf_bytes_are_identical_in_process(plate, tmp_path):
    from cad.export import export_part

    a = export_part(plate, "plate", tmp_path / "a", {"step", "stl", "dxf"}, plate=True)
    b = export_part(plate, "plate", tmp_path / "b", {"step", "stl", "dxf"}, plate=True)
    assert [p.read_bytes() for p in a] == [p.read_bytes() for p in b]


def test_assembly_step_named_solids_and_stable_bytes(plate, tmp_path):
    """Two exports of an assembly in one process: OCCT numbers assembly usages with a
    process-wide counter; cad.export.step renumbers them, so the bytes agree."""
    from build123d import import_step

    from cad.export import export_assembly_step
    from cad.export.shapes import placed
    from cad.parts import translation

    items = [
        ("left", plate, (1.0, 0.0, 0.0)),
        ("right", placed(plate, translation(100.0)), (0.0, 0.0, 1.0)),
    ]
    p1 = export_assembly_step(items, tmp_path / "a.step", name="asm")
    p2 = export_assembly_step(items, tmp_path / "b.step", name="asm")
    assert p1.read_bytes() == p2.read_bytes()
    back = import_step(p1)
    assert sorted(c.label for c in back.children) == ["left", "right"]
    assert back.children[0].color is not None
    assert sum(s.volume for s in back.solids()) == pytest.approx(2 * PLATE_VOLUME, rel=1e-9)


def test_dxf_profile_area_times_thickness_is_the_volume(plate, tmp_path):
    from cad.export import export_part
    from cad.export.dxf import dxf_profile_area_mm2

    (p,) = export_part(plate, "plate", tmp_path, {"dxf"}, plate=True)
    text = p.read_text()
    assert "$INSUNITS" in text
    assert dxf_profile_area_mm2(text) * 6 == pytest.approx(PLATE_VOLUME, rel=1e-9)


def test_manifest_lists_every_file_with_its_sha256(plate, tmp_path):
    from cad.export import export_part, verify_manifest, write_manifest

    export_part(plate, "plate", tmp_path, {"step", "stl"})
    write_manifest(tmp_path, {"build_key": "k"})
    doc = json.loads((tmp_path / "manifest.json").read_text())
    names = sorted(r["path"] for r in doc["files"])
    assert names == ["plate.step", "plate.stl"]
    for r in doc["files"]:
        data = (tmp_path / r["path"]).read_bytes()
        assert r["sha256"] == hashlib.sha256(data).hexdigest() and r["bytes"] == len(data)
    assert verify_manifest(tmp_path)["build_key"] == "k"
    (tmp_path / "plate.stl").write_bytes(b"tampered")
    assert verify_manifest(tmp_path) is None


def test_bom_rows_and_columns(tmp_path):
    from cad.export import BOM_COLUMNS, write_bom

    p = write_bom(
        [
            {
                "part": "crank",
                "material": "aluminium-6061",
                "quantity": 1,
                "made_or_bought": "made",
                "mass_g": 12.345,
            },
            {
                "part": "bearing",
                "material": "steel-1018",
                "quantity": 3,
                "made_or_bought": "bought",
                "mass_g": 3.0,
            },
        ],
        tmp_path,
    )
    lines = p.read_text().splitlines()
    assert lines[0].split(",") == list(BOM_COLUMNS)
    rows = list(csv.DictReader(lines))
    assert (rows[1]["mass_g"], rows[1]["total_mass_g"]) == ("3.00", "9.00")
    assert rows[1]["unit_price"] == rows[1]["line_price"] == ""  # no price given: empty
    with pytest.raises(ValueError):
        write_bom(
            [
                {
                    "part": "x",
                    "material": "pla",
                    "quantity": 1,
                    "made_or_bought": "maybe",
                    "mass_g": 1,
                }
            ],
            tmp_path,
        )


def test_a_failure_mid_build_leaves_the_output_untouched(tmp_path, monkeypatch):
    """The third STEP export fails: the output folder keeps its old content, no temp dirs."""
    import cad.export.step as step_mod
    from cad.design import load_design
    from cad.pipeline import build_design

    out = tmp_path / "exports" / "hoeken"
    out.mkdir(parents=True)
    (out / "old.txt").write_text("previous build")
    from cad.export.manifest import write_manifest

    write_manifest(out)  # a previous build's folder: everything in it listed
    calls = {"n": 0}
    real = step_mod.step_bytes

    def flaky(*a, **k):
        calls["n"] += 1
        if calls["n"] == 3:
            raise OSError("disk full (simulated)")
        return real(*a, **k)

    monkeypatch.setattr(step_mod, "step_bytes", flaky)
    # the part STEP bytes must be made here, not read from the derived cache
    monkeypatch.setattr("cad.io.derived_cache.cache_dir", lambda: None)
    d = load_design(ROOT / "designs" / "hoeken.toml")
    with pytest.raises(OSError):
        build_design(d, out, {"step"}, fidelity="inertia", use_cache=False)
    assert sorted(p.name for p in out.iterdir()) == ["manifest.json", "old.txt"]
    assert sorted(p.name for p in out.parent.iterdir()) == ["hoeken"]


@pytest.mark.slow
def test_stl_and_step_are_byte_identical_across_processes(tmp_path):
    """Two fresh processes export the same part: identical STL, STEP and DXF bytes."""
    code = (
        "import sys, hashlib; from pathlib import Path; from build123d import Box, Cylinder, Pos;"
        "from cad.export import export_part;"
        "b=(Box(80,30,6)-Pos(-30,0,0)*Cylinder(4,10)).solids()[0].wrapped;"
        "ps=export_part(b,'plate',Path(sys.argv[1]),{'step','stl','dxf'},plate=True);"
        "print(' '.join(hashlib.sha256(p.read_bytes()).hexdigest() for p in ps))"
    )
    outs = [
        subprocess.run(
            [sys.executable, "-c", code, str(tmp_path / d)],
            capture_output=True,
            text=True,
            check=True,
        ).stdout
        for d in ("a", "b")
    ]
    assert outs[0] == outs[1] and len(outs[0].split()) == 3


def test_bom_line_mass_is_quantity_times_printed_unit_mass(tmp_path):
    """A reader multiplies the printed columns: Hoeken's M3x10 cap screw (0.915 g, printed
    0.92) x 4 is 3.68 on the line, not the unrounded 3.66; M6x16 (5.744 g, printed 5.74) x 5
    is 28.70 (hand arithmetic on the printed cells, read back from the csv)."""
    from cad.export import write_bom

    p = write_bom(
        [{"part": "cap_screw_M3-0.5x10", "material": "steel", "quantity": 4,
          "made_or_bought": "bought", "mass_g": 0.9154},
         {"part": "cap_screw_M6-1x16", "material": "steel", "quantity": 5,
          "made_or_bought": "bought", "mass_g": 5.7441}],
        tmp_path,
    )
    rows = list(csv.DictReader(p.read_text().splitlines()))
    assert [(r["mass_g"], r["total_mass_g"]) for r in rows] == [("0.92", "3.68"), ("5.74", "28.70")]
    for r in rows:
        assert float(r["total_mass_g"]) == pytest.approx(float(r["mass_g"]) * int(r["quantity"]), abs=1e-12)
