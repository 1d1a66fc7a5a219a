"""User part scripts in either dialect (cadquery and build123d) feed the same pipeline."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from cad.errors import DesignError

ROOT = Path(__file__).resolve().parents[3]

B123D_SCRIPT = """
from build123d import Align, Cylinder, Pos

def make_handle(params):
    a = (Align.CENTER, Align.CENTER, Align.MIN)
    h, r = params["height_mm"], params["diameter_mm"] / 2
    knob = Cylinder(r, h, align=a) - Cylinder(params["screw_clearance_mm"] / 2, h, align=a)
    return knob - Pos(0, 0, params["floor_mm"]) * Cylinder(params["counterbore_mm"] / 2, h, align=a)
"""


def params():
    from cad.design.parts import PartsSpec
    from cad.parts.handle import handle_params

    return handle_params(PartsSpec(), floor_mm=10.0)


def test_cadquery_script_returns_a_valid_ocp_solid():
    from cad.export.shapes import is_valid
    from cad.massprops.occt import volume_mm3
    from cad.parts.handle import user_handle_shape

    shape = user_handle_shape(ROOT / "designs" / "handle_cq.py", params())
    assert is_valid(shape)
    # independent: cadquery's own volume of the same object
    import runpy

    cq_obj = runpy.run_path(str(ROOT / "designs" / "handle_cq.py"))["make_handle"](params())
    assert volume_mm3(shape) == pytest.approx(cq_obj.val().Volume(), rel=1e-12)


def test_build123d_script_volume_is_the_closed_form(tmp_path):
    from cad.massprops.occt import volume_mm3
    from cad.parts.handle import user_handle_shape

    script = tmp_path / "knob.py"
    script.write_text(B123D_SCRIPT)
    p = params()
    shape = user_handle_shape(script, p)
    R, h, f = p["diameter_mm"] / 2, p["height_mm"], p["floor_mm"]
    rc, rcb = p["screw_clearance_mm"] / 2, p["counterbore_mm"] / 2
    expected = math.pi * (R * R * h - rc * rc * f - rcb * rcb * (h - f))
    assert volume_mm3(shape) == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("dialect", ["cadquery", "build123d"])
def test_both_dialects_go_through_the_build(tmp_path, dialect, monkeypatch):
    """Build a Hoeken with the user handle: its mass is volume x density and sits in the coupler."""
    monkeypatch.setenv("HAPTICAD_ALLOW_SCRIPTS", "1")  # the user's opt-in (docs/reliability.md "Design scripts")
    from cad.data.materials import get_material
    from cad.design import load_design
    from cad.pipeline import build_design

    if dialect == "cadquery":
        design = ROOT / "designs" / "hoeken_cq_handle.toml"
    else:
        (tmp_path / "knob.py").write_text(B123D_SCRIPT)
        src = (
            (ROOT / "designs" / "hoeken.toml")
            .read_text()
            .replace("[parts]\n", '[parts]\nhandle_script = "knob.py"\nhandle_material = "pla"\n')
        )
        design = tmp_path / "h.toml"
        design.write_text(src)
    d = load_design(design)
    rep = build_design(d, tmp_path / "out", {"step"}, fidelity="inertia", use_cache=False)
    assert rep["handle"].startswith("user script")
    assert rep["interference"]["collisions"] == []
    from cad.massprops.occt import read_step, volume_mm3

    shape = read_step(tmp_path / "out" / "parts" / "handle.step")
    rho = get_material(d.parts.handle_material).density_kg_m3
    if d.parts.printed(d.parts.handle_material):  # PLA / PETG: FDM printed (walls + infill)
        from cad.parts.printed import printed_mass_kg

        expected_g = printed_mass_kg(shape, rho, d.parts.print_settings()) * 1e3
        assert expected_g < volume_mm3(shape) * 1e-9 * rho * 1e3  # lighter than a solid block
    else:
        expected_g = volume_mm3(shape) * 1e-9 * rho * 1e3
    assert rep["part_masses_g"]["handle"] == pytest.approx(expected_g, rel=1e-9)
    coupler_parts = {p["part"]: p["mass_g"] for p in rep["links"]["coupler"]["parts"]}
    assert coupler_parts["handle"] == pytest.approx(rep["part_masses_g"]["handle"], rel=1e-12)


@pytest.mark.parametrize(
    ("body", "words"),
    [
        ("raise RuntimeError('boom')", "failed: RuntimeError: boom"),
        ("def make_handle(params):\n    return 42\n", "expected a build123d or cadquery object"),
        ("x = 1\n", "defines no make_handle"),
        ("from build123d import Box\nhandle = Box(1, 1, 1).faces()[0]\n", "valid solid"),
    ],
)
def test_broken_scripts_are_design_errors(tmp_path, body, words):
    from cad.parts.handle import user_handle_shape

    script = tmp_path / "bad.py"
    script.write_text(body)
    with pytest.raises(DesignError) as ei:
        user_handle_shape(script, params())
    assert ei.value.field == "parts.handle_script" and words in str(ei.value)


def test_missing_script_is_a_design_error(tmp_path, monkeypatch):
    monkeypatch.setenv("HAPTICAD_ALLOW_SCRIPTS", "1")
    from cad.design.parts import parse_parts
    from cad.parts.handle import resolve_script

    p = parse_parts({"handle_script": "nowhere.py"})
    with pytest.raises(DesignError, match="file not found"):
        resolve_script(p, str(tmp_path / "design.toml"))
