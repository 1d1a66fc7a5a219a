"""``hapticad massprops``: STEP and STL round trips against closed forms, and bad input.

Reference: a box a x b x c centred at (10, -5, 3) mm and a cylinder R, h, whose mass
properties have closed forms (see tests/unit/massprops/test_massprops_occt.py).
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from build123d import Box, Cylinder, Pos, export_step, export_stl
from typer.testing import CliRunner

from cad.cli.app import register_commands, app
from cad.data.materials import MATERIALS

register_commands()
runner = CliRunner()

A, B, C = 10.0, 20.0, 30.0
CENTRE_MM = (10.0, -5.0, 3.0)


def box_ref(rho):
    m = rho * A * B * C * 1e-9
    return m, m / 12 * np.diag([B * B + C * C, A * A + C * C, A * A + B * B]) * 1e-6


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("mp")
    box = Pos(*CENTRE_MM) * Box(A, B, C)
    export_step(box, d / "box.step")
    export_stl(box, d / "box.stl")
    export_step(Cylinder(8.0, 25.0), d / "cyl.step")
    # an open STL: the box mesh with one triangle removed
    import trimesh

    tm = trimesh.load_mesh(d / "box.stl")
    trimesh.Trimesh(tm.vertices, tm.faces[1:], process=False).export(d / "open.stl")
    (d / "junk.step").write_text("not a step file\n")
    (d / "notes.txt").write_text("hello\n")
    return d


def invoke(*args):
    return runner.invoke(app, ["massprops", *map(str, args)])


def test_step_json_matches_closed_form_via_subprocess(files):
    # the real entry point (python -m cad), JSON on stdout, one object
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "cad",
            "massprops",
            str(files / "box.step"),
            "--material",
            "brass-360",
            "--json",
        ],
        capture_output=True,
        text=True,
    )
    assert out.returncode == 0, out.stderr
    res = json.loads(out.stdout)
    rho = MATERIALS["brass-360"].density_kg_m3
    m, inert = box_ref(rho)
    assert res["volume_mm3"] == pytest.approx(A * B * C, rel=1e-12)
    assert res["mass_kg"] == pytest.approx(m, rel=1e-12)
    np.testing.assert_allclose(res["com_mm"], CENTRE_MM, rtol=0, atol=1e-9)
    np.testing.assert_allclose(res["inertia_com_kg_m2"], inert, rtol=0, atol=1e-12 * inert.max())
    np.testing.assert_allclose(res["principal_moments_kg_m2"], np.sort(np.diag(inert)), rtol=1e-12)
    assert res["method"] == "occt-exact" and res["density_kg_m3"] == rho
    assert out.stderr == ""  # material given: no note


def test_step_cylinder_density_flag(files):
    r = invoke(files / "cyl.step", "--density", "1000", "--json")
    assert r.exit_code == 0, r.output
    res = json.loads(r.stdout)
    m = 1000 * math.pi * 64 * 25 * 1e-9
    assert res["mass_kg"] == pytest.approx(m, rel=1e-12)
    assert res["inertia_com_kg_m2"][2][2] == pytest.approx(m * 64e-6 / 2, rel=1e-12)
    assert res["material"] is None


def test_stl_round_trip_and_default_material(files):
    r = invoke(files / "box.stl", "--json")
    assert r.exit_code == 0, r.output
    res = json.loads(r.stdout)
    rho = MATERIALS["aluminium-6061"].density_kg_m3
    m, inert = box_ref(rho)
    assert res["watertight"] is True and res["method"] == "trimesh"
    assert res["material"] == "aluminium-6061"
    # binary STL stores float32 coordinates: ~1e-7 relative
    assert res["mass_kg"] == pytest.approx(m, rel=1e-6)
    np.testing.assert_allclose(res["com_mm"], CENTRE_MM, atol=1e-5)
    np.testing.assert_allclose(res["inertia_com_kg_m2"], inert, atol=1e-6 * inert.max())
    assert "using aluminium-6061" in r.stderr


def test_open_stl_warns_but_runs(files):
    r = invoke(files / "open.stl", "--density", "2000", "--json")
    assert r.exit_code == 0, r.output
    res = json.loads(r.stdout)
    assert res["watertight"] is False
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "not watertight" in lines[0]


def test_text_output(files):
    r = invoke(files / "box.step", "--material", "pla")
    assert r.exit_code == 0
    assert "mass_kg" in r.stdout and "principal_moments_kg_m2" in r.stdout


@pytest.mark.parametrize(
    "args, needle",
    [
        (["{d}/box.step", "--density", "2700", "--material", "pla"], "not both"),
        (["{d}/missing.step"], "file not found"),
        (["{d}/notes.txt"], "unsupported file type"),
        (["{d}/junk.step"], "not a readable STEP"),
        (["{d}/box.step", "--material", "cheese"], "unknown material 'cheese'"),
        (["{d}/box.step", "--density", "abc"], "--density"),
        (["{d}/box.step", "--density", "-5"], "> 0"),
    ],
)
def test_bad_input_exit_2_one_line(files, args, needle):
    r = invoke(*[a.format(d=files) for a in args])
    assert r.exit_code == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert lines[0].startswith("hapticad: error:") and needle in lines[0]
    assert r.stdout == ""
