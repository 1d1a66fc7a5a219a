"""The 5-bar capstan's own checks come before the motors' placement, and each refusal names
what is wrong (a new user's findings, stop 45): a capstan too small for the set screw is
refused on its diameter with the bend-ratio note that names the fix; a centre distance that
puts each motor's mount plate on its own bearing block is refused on centre_distance_mm with the
distance it needs; when no direction places the drums, the refusal says what met. Every
family's capstan below its rope's bend ratio warns at load with the diameter that fixes it."""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_helpers import assert_one_line_error, hapticad

ROOT = Path(__file__).resolve().parents[3]
BUNDLED = (ROOT / "designs" / "pantograph_capstan.toml").read_text()
#: The 7x7 rope's minimum bend ratio (rope makers, cad/data/cables.py) and its diameter, mm.
MIN_BEND_7X7, ROPE_MM = 40.0, 0.8


def _variant(tmp_path, capstan: str, drum: str, extra: str = "") -> Path:
    p = tmp_path / "v.toml"
    text = BUNDLED.replace("capstan_diameter_mm = 32.0", f"capstan_diameter_mm = {capstan}")
    p.write_text(text.replace("drum_diameter_mm = 128.0", drum) + extra)
    return p


def test_a_capstan_too_small_for_its_set_screw_is_refused_on_its_diameter(tmp_path):
    """8 mm capstan, ratio 4: the set screw's wall and the bend ratio 8 / 0.8 = 10 < 40 are
    what is wrong (not the drums' placement); the note names the capstan that fixes the bend
    ratio, 40 x 0.8 = 32 mm; nothing written."""
    out = tmp_path / "out"
    code, _, err = hapticad("build", _variant(tmp_path, "8.0", "ratio = 4.0"), "--out", out)
    need = MIN_BEND_7X7 * ROPE_MM
    assert_one_line_error(code, err, "transmission.capstan_diameter_mm", "set screw", "D/d = 10.0",
                          f"a capstan of at least {need:.1f} mm")
    assert "drum" not in err.split("; note:")[0]
    assert not out.exists() or not any(out.iterdir())


def test_the_set_screw_refusal_names_the_smallest_capstan_that_holds_one(tmp_path):
    """The capstan named by the refusal is the inverse of the set-screw rule: the forward check
    (cad.assembly.capstan_hardware.capstan_set_screw) accepts it and refuses 0.2 mm less."""
    import re
    from types import SimpleNamespace

    from cad.assembly.capstan_hardware import capstan_set_screw
    from cad.errors import DesignError

    code, _, err = hapticad("check", _variant(tmp_path, "8.0", "ratio = 4.0"))
    need = float(re.search(r"a capstan of at least ([0-9.]+) mm \(its rim", err).group(1))
    d = SimpleNamespace(parts=SimpleNamespace(motor="maxon-re35"))

    def t(dc):
        return SimpleNamespace(capstan_diameter_mm=dc, cable_diameter_mm=ROPE_MM)

    capstan_set_screw(d, t(need))
    with pytest.raises(DesignError, match="a capstan of at least"):
        capstan_set_screw(d, t(need - 0.2))


def test_a_centre_distance_inside_the_mount_plates_is_refused_with_the_distance_needed(tmp_path):
    """24 mm capstan, ratio 2 (48 mm drum): C = r_c + r_d + gap is shorter than the motor's
    mount plate side plus the clearance, so each plate meets its own joint's bearing block in
    every direction; the refusal names centre_distance_mm and the distance needed."""
    from cad.actuators.capstan import CAPSTAN_GAP_MM
    from cad.data.catalog import get_motor
    from cad.families.pantograph.capstan import CLEARANCE_MM
    from cad.parts.motor import mount_side_mm

    code, _, err = hapticad("check", _variant(tmp_path, "24.0", "ratio = 2.0"))
    C = (24.0 + 48.0) / 2 + CAPSTAN_GAP_MM
    need = mount_side_mm(get_motor("maxon-re35")) + CLEARANCE_MM
    assert C < need
    assert_one_line_error(code, err, "transmission.centre_distance_mm", f"{C:g} mm",
                          f"centre_distance_mm >= {need:g}")


def test_no_direction_that_places_the_drums_says_what_met(tmp_path):
    """The bundled design on a 100 mm base with its motors 90 mm off the joints: every one of
    the 360 / 5 = 72 directions is refused, each for a reason the line counts."""
    p = _variant(tmp_path, "32.0", "drum_diameter_mm = 128.0\ncentre_distance_mm = 90.0")
    p.write_text(p.read_text().replace("base_mm = 110.0", "base_mm = 100.0"))
    code, _, err = hapticad("check", p)
    assert_one_line_error(code, err, "transmission", "of 72 directions", "the two swept drums meet in")


@pytest.mark.parametrize("design", ["pantograph_capstan.toml", "delta_capstan.toml", "hoeken_capstan.toml",
                                    "haptic_pen_capstan.toml"])
def test_every_family_warns_at_load_of_a_rope_below_its_bend_ratio(design):
    """A 20 mm capstan bends the 0.8 mm 7x7 rope at D/d = 25 < 40: loading the design (any family
    with capstans) records one warning naming the rope, the ratio and the 32 mm capstan
    (40 x 0.8) that fixes it, once however many motors share the capstan."""
    import re

    from cad.design import bounds, parse_design
    from cad.design.fields import load_toml

    raw = load_toml(ROOT / "designs" / design)
    tabs = raw["transmission"] if isinstance(raw["transmission"], list) else [raw["transmission"]]
    for t in tabs:
        t["capstan_diameter_mm"], t["cable"] = 20.0, "steel-7x7-0.8"
    bounds.reset()
    parse_design(raw, design)
    w = [x for x in bounds.collected() if x.startswith("transmission:")]
    assert len(w) == 1, w
    assert re.search(r"steel-7x7-0\.8 on a 20 mm capstan: bend ratio D/d = 25\.0 .* at least 32\.0 mm", w[0])


def test_the_powermouse_refuses_a_capstan_with_its_reason(tmp_path):
    """The PowerMouse has no motor shaft: [transmission] is refused naming the table and why,
    not as an unknown key."""
    p = tmp_path / "pm.toml"
    p.write_text((ROOT / "designs" / "powermouse.toml").read_text()
                 + '\n[transmission]\nkind = "capstan"\ncapstan_diameter_mm = 32.0\nratio = 4.0\n'
                 'cable = "steel-7x7-0.8"\n')
    code, _, err = hapticad("check", p)
    assert_one_line_error(code, err, "transmission", "voice coils", "remove [transmission]")
    assert "unknown key" not in err


def test_the_pen_takes_a_direct_drive_table_and_a_capstan_whose_solids_it_refuses():
    """A direct-drive [transmission] on the pen is what it already is (six direct motors); a
    capstan in one of its six tables loads (its analyses read it: tests/families/pen/
    test_pen_capstan.py) and the build's pre-CAD check refuses its solids naming the table (a
    capstan shoulder beside a direct one cannot be laid out)."""
    from cad.design import parse_design
    from cad.design.fields import load_toml
    from cad.errors import DesignError
    from cad.families.pen.build import check_options

    raw = load_toml(ROOT / "designs" / "haptic_pen.toml")
    raw["transmission"] = {"kind": "direct"}
    d = parse_design(raw, "pen")
    assert [t.ratio for t in d.transmissions] == [1.0] * 6
    check_options(d, "fabrication", None)
    raw["transmission"] = [{"kind": "direct"}] * 5 + [
        {"kind": "capstan", "capstan_diameter_mm": 32.0, "ratio": 4.0, "cable": "steel-7x7-0.8"}]
    d = parse_design(raw, "pen")
    assert [t.ratio for t in d.transmissions] == [1.0] * 5 + [4.0]
    with pytest.raises(DesignError, match="^transmission: the haptic pen's capstans cannot be laid out .*B_q_lower is direct"):
        check_options(d, "fabrication", None)


@pytest.mark.parametrize("design", ["pantograph_capstan.toml", "hoeken_capstan.toml"])
def test_the_rotor_row_states_the_inertia_the_models_take(design):
    """The datasheet's reflected-rotor row gives n^2 J_m and, in its note, the n^2 (J_m + J_c)
    the effective mass / H11, the MJCF armature and the firmware take: the resolved device's
    joint_rotor_inertia_kg_m2 (a new user read only half of it from the row)."""
    import re

    from cad.datasheet import capstan_rows as cr
    from cad.design import load_design
    from cad.device import resolve_device
    from cad.families.pantograph.capstan import capstan_joints

    d = load_design(ROOT / "designs" / design)
    dev = resolve_device(d)
    joints = ([cr.capstan_joint(dev, "crank", 90.0)] if "hoeken" in design else
              capstan_joints(d))
    for j in joints:
        rows, _ = cr.datasheet_rows(j)
        (r,) = [x for x in rows if x["key"].startswith("reflected_rotor_inertia_g_cm2")]
        total = float(re.search(r"n\^2 \(J_m \+ J_c\) = ([0-9.]+) g cm\^2", r["model"]).group(1))
        assert total == pytest.approx(dev.joint_rotor_inertia_kg_m2(j.name) * 1e7, rel=1e-3)  # 4 digits
        assert r["value"] == pytest.approx(j.transmission.ratio ** 2 * j.motor.spec.rotor_inertia_g_cm2)
