"""``hapticad gii`` / ``hapticad optimize`` on the pantograph families: JSON keys, values, bad input."""

from __future__ import annotations

import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
import tomli_w
from cli_helpers import assert_one_line_error, hapticad, hapticad_json

from cad.design import load_design
from cad.kinematics.fivebar import FiveBar

DESIGNS = Path(__file__).resolve().parents[3] / "designs"


@pytest.mark.parametrize("name", ["pantograph", "haptic_mouse", "haptic_pen"])
def test_gii_json_keys_and_values(name):
    out = hapticad_json("gii", DESIGNS / f"{name}.toml")
    for key in (
        "gii",
        "sigma_min",
        "sigma_max",
        "sigma_min_at_mm",
        "sigma_max_at_mm",
        "sigma_min_at",
        "sigma_max_at",
        "n_points",
        "jacobian_evaluations",
        "failure",
        "failed_at",
    ):
        assert key in out
    design = load_design(DESIGNS / f"{name}.toml")
    r = design.gii()
    assert out["gii"] == r.gii and 0 < out["gii"] < 1
    assert out["gii"] == pytest.approx(out["sigma_min"] / out["sigma_max"], rel=1e-15)
    assert out["failure"] is None


def test_gii_of_pantograph_design_matches_a_hand_built_fivebar():
    from cad.isotropy.gii import fivebar_gii

    out = hapticad_json("gii", DESIGNS / "pantograph.toml")
    r = fivebar_gii(FiveBar.symmetric(75.0, 125.0, 175.0), (0.0, 200.0), 100.0, 11)
    assert out["gii"] == r.gii
    assert out["sigma_min_at_mm"] == r.sigma_min_at.tolist()


def test_optimize_culling_and_brute_agree_with_tenfold_fewer_evaluations():
    c = hapticad_json("optimize", DESIGNS / "pantograph.toml", "--method", "culling")
    b = hapticad_json("optimize", DESIGNS / "pantograph.toml", "--method", "brute")
    for key in (
        "best",
        "gii",
        "jacobian_evaluations",
        "wall_time_s",
        "brute_force_evaluations",
        "method",
    ):
        assert key in c and key in b
    assert c["best"] == b["best"] and c["gii"] == b["gii"]
    assert b["jacobian_evaluations"] == 17 * 20 * 20 * 121
    assert b["jacobian_evaluations"] >= 10 * c["jacobian_evaluations"]
    # the bundled mechanism is the optimum of its own [optimize] grid
    assert c["best"] == {"base_mm": 75.0, "proximal_mm": 125.0, "distal_mm": 175.0}


def test_optimize_mouse_and_pen_culling():
    m = hapticad_json("optimize", DESIGNS / "haptic_mouse.toml")
    assert m["method"] == "culling" and m["best"] == {
        "base_mm": 75.0,
        "proximal_mm": 125.0,
        "distal_mm": 175.0,
    }
    assert m["fixed"]["crank_mm"] == pytest.approx(20.0)
    p = hapticad_json("optimize", DESIGNS / "haptic_pen.toml")
    assert p["best"] == {
        "shoulder_base_mm": 60.0,
        "proximal_mm": 140.0,
        "distal_mm": 180.0,
        "waist_torque_ratio": 1.75,
    }
    assert p["evaluation_ratio"] >= 10


def _write(tmp_path: Path, raw: dict) -> Path:
    p = tmp_path / "bad.toml"
    p.write_bytes(tomli_w.dumps(raw).encode())
    return p


def _raw(name="pantograph"):
    with open(DESIGNS / f"{name}.toml", "rb") as fh:
        return tomllib.load(fh)


@pytest.mark.parametrize(
    "section, key, value, needle",
    [
        ("mechanism", "base_mm", -10.0, "mechanism.base_mm"),
        ("mechanism", "distal_mm", 0.0, "mechanism.distal_mm"),
        ("mechanism", "proximal", 100.0, "mechanism.proximal"),
        ("workspace", "grid", 1, "workspace.grid"),
        ("workspace", "center_mm", [0.0], "workspace.center_mm"),
        ("workspace", "side_mm", -1.0, "workspace.side_mm"),
        ("optimize", "base_mm", [0.0, 100.0, 0], "optimize.base_mm"),
        ("optimize", "distal_mm", [100.0, 50.0, 3], "optimize.distal_mm"),
        ("actuators", "torque_max_Nm", -1.0, "actuators.torque_max_Nm"),
    ],
)
def test_bad_design_exits_2_with_one_line(tmp_path, section, key, value, needle):
    raw = _raw()
    raw[section][key] = value
    path = _write(tmp_path, raw)
    for cmd in (("gii",), ("optimize", "--method", "brute")):
        code, out, err = hapticad(*cmd, path, "--json")
        assert_one_line_error(code, err, needle)
        assert out == ""


def test_bad_method_and_wrong_family(tmp_path):
    code, _, err = hapticad("optimize", DESIGNS / "pantograph.toml", "--method", "genetic")
    assert_one_line_error(code, err, "--method")
    raw = _raw("haptic_mouse")
    raw["parts"]["tube_id_mm"] = 9.0
    code, _, err = hapticad("gii", _write(tmp_path, raw))
    assert_one_line_error(code, err, "parts.tube_id_mm")
    del raw["optimize"]
    raw["parts"]["tube_id_mm"] = 6.0
    code, _, err = hapticad("optimize", _write(tmp_path, raw))
    assert_one_line_error(code, err, "optimize")


def test_unreachable_design_reports_gii_zero_and_the_point(tmp_path):
    raw = _raw()
    raw["workspace"]["center_mm"] = [0.0, 400.0]
    out = hapticad_json("gii", _write(tmp_path, raw))
    assert out["gii"] == 0.0
    assert "unreachable" in out["failure"]
    assert set(out["failed_at"]) == {"x_mm", "y_mm"}


def test_negative_base_through_the_console_entry_point(tmp_path):
    raw = _raw()
    raw["mechanism"]["base_mm"] = -5.0
    r = subprocess.run(
        [sys.executable, "-m", "cad", "gii", str(_write(tmp_path, raw)), "--json"],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 2 and r.stdout == ""
    assert len(r.stderr.strip().splitlines()) == 1 and "mechanism.base_mm" in r.stderr
    assert "Traceback" not in r.stderr


def test_gii_text_output_is_readable_lines():
    """``gii`` without --json prints readable lines (issue 34 item 6): the extreme points as
    ``x = .. mm, y = .. mm`` (no Python dict), the same point the JSON gives."""
    out = hapticad_json("gii", DESIGNS / "pantograph.toml")
    code, text, err = hapticad("gii", DESIGNS / "pantograph.toml")
    assert code == 0, err
    assert "{" not in text and "'" not in text
    p = out["sigma_min_at"]
    assert f"at x = {p['x_mm']:g} mm, y = {p['y_mm']:g} mm" in text.splitlines()[1]
