"""The delta's bad input refused before any solid (issue 36 audit): a length typed in metres
(cad/families/delta/sizes.py: the least sizes the parts can be made at) and a workspace the
delta does not reach or a motor range too narrow for it (cad/families/delta/reach.py), each
one line naming the field, exit 2, nothing written. All at load or in the build's
check_options (no CAD import, no solid): cheap.

References: the least sizes against hand arithmetic on the hardware's dimensions (ball link
4.8 mm: socket 7.5, neck 7, shank 3; hub d12, cross bar d8; the 623 bearing's eye); the
axis reach against the closed form of a Clavel delta on its axis at the motor limits; the
suggested motor limit and workspace size by their consequence (the suggestion passes, a
little past it does not).
"""

from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path

import pytest

from cad.design import parse_design
from cad.errors import DesignError
from cad.families.delta.reach import check_workspace
from cad.families.delta.sizes import minimums_mm
from tests.cli_helpers import assert_one_line_error, hapticad

ROOT = Path(__file__).resolve().parents[3]
RAW = tomllib.loads((ROOT / "designs" / "delta.toml").read_text())
FALCON = tomllib.loads((ROOT / "designs" / "delta_falcon.toml").read_text())


def _toml(raw: dict) -> str:
    """The few TOML forms the delta designs use (tables of numbers, strings, lists)."""
    def val(v):
        if isinstance(v, str):
            return f'"{v}"'
        if isinstance(v, list):
            return "[" + ", ".join(val(x) for x in v) + "]"
        return repr(float(v)) if isinstance(v, float) else str(v)
    lines = [f"{k} = {val(v)}" for k, v in raw.items() if not isinstance(v, dict)]
    for name, table in raw.items():
        if isinstance(table, dict):
            lines += [f"\n[{name}]"] + [f'"{k}" = {val(v)}' if " " in k else f"{k} = {val(v)}"
                                        for k, v in table.items()]
    return "\n".join(lines) + "\n"


def _write(tmp_path, raw) -> Path:
    p = tmp_path / "bad.toml"
    p.write_text(_toml(raw))
    return p


# [mechanism] length fields with a metres value (the bundled delta; joint_offset_mm: the
# Falcon's). axis_offset_mm is signed and may be 0 (the bundled delta's): a value of 0.02
# mm is a buildable offset, not refused (no part needs it to be larger).
METRES = [("base_radius_mm", RAW), ("effector_radius_mm", RAW), ("upper_arm_mm", RAW),
          ("lower_arm_mm", RAW), ("parallelogram_width_mm", RAW), ("joint_offset_mm", FALCON)]


@pytest.mark.parametrize("key,base", METRES, ids=[k for k, _ in METRES])
@pytest.mark.parametrize("command", ["build", "datasheet"])
def test_a_length_in_metres_is_one_line_naming_the_field(tmp_path, key, base, command):
    raw = copy.deepcopy(base)
    mm = raw["mechanism"][key]
    raw["mechanism"][key] = mm / 1000
    out = tmp_path / "out"
    args = (command, _write(tmp_path, raw)) + (("--out", out) if command == "build" else ())
    code, stdout, err = hapticad(*args)
    assert_one_line_error(code, err, f"hapticad: error: mechanism.{key}: ",
                          f"got {mm / 1000:g}", "did you give metres?")
    assert not out.exists() and stdout == ""


def test_the_least_sizes_are_the_parts_dimensions():
    """Hand arithmetic on the hardware (module docstring of cad/families/delta/sizes.py)."""
    m = minimums_mm(30.0, 0.0)
    assert m["lower_arm_mm"][0] == pytest.approx(7.5 + 2 * 3.0)          # two sockets + shanks
    assert m["parallelogram_width_mm"][0] == pytest.approx(2 * 7.0)      # the studs' necks
    assert m["upper_arm_mm"][0] == pytest.approx((12.0 + 8.0) / 2)       # hub and cross bar
    assert m["effector_radius_mm"][0] == pytest.approx((15.0 + 7.5) / math.sqrt(3))
    assert m["base_radius_mm"][0] == pytest.approx((15.0 + 3.75 + 3.0) / math.sqrt(3))
    k = minimums_mm(30.0, 22.5)  # with the knee: the 623 bearing (d 3, D 10, B 4)'s eye
    r_eye = 10.0 / 2 + 1.5
    assert k["lower_arm_mm"][0] == pytest.approx(r_eye + 3.0 + 3.75 + 3.0)
    assert k["parallelogram_width_mm"][0] == pytest.approx(2 * (r_eye + 1.0 + 3.0))  # clevis bridge
    assert k["joint_offset_mm"][0] == pytest.approx(8.0)


@pytest.mark.parametrize("key", ["lower_arm_mm", "upper_arm_mm", "effector_radius_mm"])
def test_the_bound_is_where_it_says(key):
    """Just above the least value loads (the workspace is not looked at when loading), just
    below is refused naming the field."""
    least, strict, _ = minimums_mm(30.0, 0.0)[key]
    raw = copy.deepcopy(RAW)
    raw["mechanism"][key] = least * 1.001
    parse_design(raw, "ok.toml")
    raw["mechanism"][key] = least * 0.999
    with pytest.raises(DesignError) as e:
        parse_design(raw, "bad.toml")
    assert e.value.field == f"mechanism.{key}"


def _clavel_axis_z_mm(theta_deg: float) -> float:
    """z of the effector on the axis (x = y = 0) with every motor at theta: the elbow at
    (R + L_a cos t, -L_a sin t) in the arm's plane, the effector joint at (r, z) L_b from it."""
    m = RAW["mechanism"]
    t = math.radians(theta_deg)
    dx = m["base_radius_mm"] + m["upper_arm_mm"] * math.cos(t) - m["effector_radius_mm"]
    return -m["upper_arm_mm"] * math.sin(t) - math.sqrt(m["lower_arm_mm"] ** 2 - dx**2)


def test_a_workspace_out_of_reach_names_its_centre_and_the_reach(tmp_path):
    raw = copy.deepcopy(RAW)
    raw["workspace"]["center_mm"] = [0.0, 0.0, -1000.0]
    out = tmp_path / "out"
    code, _, err = hapticad("build", _write(tmp_path, raw), "--out", out)
    lo = math.ceil(_clavel_axis_z_mm(RAW["mechanism"]["motor_angle_max_deg"]))   # -284.3 -> -284
    hi = math.floor(_clavel_axis_z_mm(RAW["mechanism"]["motor_angle_min_deg"]))  # -46.9 -> -47
    assert (lo, hi) == (-284, -47)
    assert_one_line_error(code, err, "hapticad: error: workspace.center_mm: [0.0, 0.0, -1000.0] mm",
                          "unreachable", f"reaches z = {lo} .. {hi} mm")
    assert not out.exists()


def test_a_motor_range_too_narrow_names_the_limit_and_the_angle_that_does(tmp_path):
    raw = copy.deepcopy(RAW)
    raw["mechanism"]["motor_angle_max_deg"] = -30.0
    out = tmp_path / "out"
    code, _, err = hapticad("build", _write(tmp_path, raw), "--out", out)
    assert_one_line_error(code, err, "hapticad: error: mechanism.motor_angle_max_deg: -30 deg",
                          "set motor_angle_max_deg >= 84")
    assert not out.exists()
    raw["mechanism"]["motor_angle_max_deg"] = 84.0   # the suggestion: the grid is reached
    check_workspace(parse_design(raw, "ok.toml"))
    raw["mechanism"]["motor_angle_max_deg"] = 83.0
    with pytest.raises(DesignError) as e:
        check_workspace(parse_design(raw, "bad.toml"))
    assert e.value.field == "mechanism.motor_angle_max_deg"
    raw["mechanism"]["motor_angle_max_deg"] = 85.0
    raw["mechanism"]["motor_angle_min_deg"] = 30.0
    with pytest.raises(DesignError) as e:
        check_workspace(parse_design(raw, "bad.toml"))
    assert e.value.field == "mechanism.motor_angle_min_deg" and "set motor_angle_min_deg <= " in str(e.value)


@pytest.mark.parametrize("shape", ["box", "cylinder"])
def test_a_workspace_too_big_names_its_size_and_the_size_that_fits(tmp_path, shape):
    raw = copy.deepcopy(RAW)
    if shape == "box":
        raw["workspace"]["size_mm"] = [1000.0] * 3
        field = "workspace.size_mm"
    else:
        raw["workspace"] = {"shape": "cylinder", "center_mm": [0.0, 0.0, -180.0], "diameter_mm": 1000.0,
                            "height_mm": 800.0, "grid": 5}
        field = "workspace.diameter_mm"
    out = tmp_path / "out"
    code, _, err = hapticad("build", _write(tmp_path, raw), "--out", out)
    assert_one_line_error(code, err, f"hapticad: error: {field}: ", "shrink")
    assert not out.exists()
    text = err.split("at most ", 1)[1]
    fit = [float(v) for v in (text[1:].split("]")[0].split(",") if shape == "box"
                              else text.split(" mm")[0].split(" / "))]
    if shape == "box":
        raw["workspace"]["size_mm"] = fit
    else:
        raw["workspace"]["diameter_mm"], raw["workspace"]["height_mm"] = fit
    check_workspace(parse_design(raw, "fits.toml"))  # the size it names is reached
    grown = [v * 1.02 for v in fit]
    if shape == "box":
        raw["workspace"]["size_mm"] = grown
    else:
        raw["workspace"]["diameter_mm"], raw["workspace"]["height_mm"] = grown
    with pytest.raises(DesignError) as e:  # 2 % larger: some point out of reach or of the motor range
        check_workspace(parse_design(raw, "grown.toml"))
    assert e.value.field in (field, "mechanism.motor_angle_max_deg", "mechanism.motor_angle_min_deg")


def test_a_workspace_above_the_base_names_its_centre():
    raw = copy.deepcopy(RAW)
    raw["workspace"]["center_mm"] = [0.0, 0.0, 180.0]
    with pytest.raises(DesignError) as e:
        check_workspace(parse_design(raw, "up.toml"))
    assert e.value.field == "workspace.center_mm" and "below the base" in str(e.value)


def test_the_bundled_deltas_pass_the_checks():
    for name in ("delta.toml", "delta_capstan.toml", "delta_falcon.toml"):
        raw = tomllib.loads((ROOT / "designs" / name).read_text())
        check_workspace(parse_design(raw, name))  # raises on a refusal


def test_an_optimize_range_below_the_parts_is_one_line(tmp_path):
    """[optimize] lower_arm_mm = [0.14, 0.26, 13] (metres): no candidate could be built."""
    raw = copy.deepcopy(RAW)
    raw["optimize"]["lower_arm_mm"] = [0.14, 0.26, 13]
    code, stdout, err = hapticad("optimize", _write(tmp_path, raw))
    assert_one_line_error(code, err, "hapticad: error: optimize.lower_arm_mm: ", "must be >= 13.5 mm",
                          "got 0.14")
    assert stdout == ""
