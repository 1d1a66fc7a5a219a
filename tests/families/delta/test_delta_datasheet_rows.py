"""The delta's datasheet rows the issue asks of every family (issue 36 item 4): the workspace
and its reachable / well-conditioned volumes, the gravity load and its share of the
continuous torque, the BOM cost from ``[prices]``; and the GII commands on a cylinder
workspace.

References: the workspace's volume in closed form (box W D H, cylinder pi D^2 H / 4); the
gravity load against the potential energy's gradient by central finite differences through
the forward kinematics and the body poses (V(theta) = sum m g z_com, the torque holding the
solids still is dV/dtheta: a second method, not J^-T grad_x V); the continuous torque the
share divides by from the catalog (maxon RE 40: 187 mN m, its data sheet); the BOM cost
against the sum of order.csv's priced lines read back.
"""

from __future__ import annotations

import copy
import csv
import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from cad.data.catalog import get_motor
from cad.design import parse_design
from cad.families.delta.datasheet import rows_and_limits
from cad.families.delta.design import JOINTS
from cad.families.delta.layout import poses_at
from cad.isotropy.report import optimize_report
from cad.kinematics.delta import fk, ik
from tests.cli_helpers import hapticad, hapticad_json
from tests.conftest import DELTA_FORMATS

ROOT = Path(__file__).resolve().parents[3]
RAW = tomllib.loads((ROOT / "designs" / "delta.toml").read_text())
CYLINDER = {"shape": "cylinder", "center_mm": [0.0, 0.0, -180.0], "diameter_mm": 100.0,
            "height_mm": 80.0, "grid": 4}


def _rows(ds_rows) -> dict:
    return {r["key"]: r for r in ds_rows}


def _cylinder_file(tmp_path) -> Path:
    text = (ROOT / "designs" / "delta.toml").read_text()
    a = text.index("[workspace]")
    b = text.index("[actuators]")
    cyl = ('[workspace]\nshape = "cylinder"\ncenter_mm = [0.0, 0.0, -180.0]\ndiameter_mm = 100.0\n'
           "height_mm = 80.0\ngrid = 4\n\n")
    p = tmp_path / "cyl.toml"
    p.write_text(text[:a] + cyl + text[b:])
    return p


def test_gii_and_optimize_take_a_cylinder_workspace(tmp_path):
    """`hapticad gii` on a cylinder crashed (KeyError 'size_mm'): its extents are [D, D, H]."""
    path = _cylinder_file(tmp_path)
    rep = hapticad_json("gii", path)
    assert rep["workspace_size_mm"] == [100.0, 100.0, 80.0] and rep["workspace_shape"] == "cylinder"
    assert rep["n_points"] == 4 * (1 + 6 + 12 + 18)  # the axis and 3 rings on 4 levels
    code, out, _ = hapticad("gii", path)  # the text names the shape (it read "100 x 100 x 80 mm")
    assert code == 0 and "of a d100 x 80 mm cylinder workspace" in out.splitlines()[0], out
    # the optimize report (cad.isotropy.report; the CLI also builds the optimum for its
    # limits, a minute): the same grid, three candidates
    raw = copy.deepcopy(RAW)
    raw["workspace"] = CYLINDER
    raw["optimize"] = {"upper_arm_mm": [100.0, 120.0, 3]}
    opt = optimize_report(parse_design(raw, "cyl_opt.toml"), "culling")
    assert opt["n_points"] == rep["n_points"] and opt["n_candidates"] == 3


def test_datasheet_rows_of_a_cylinder_workspace():
    """The datasheet's rows from the design alone (the build's rows absent: None): the
    workspace row is the cylinder's volume, the forces are taken over its grid."""
    raw = copy.deepcopy(RAW)
    raw["workspace"] = CYLINDER
    d = parse_design(raw, "cyl.toml")
    rows, _, _ = rows_and_limits(d, {})
    r = _rows(rows)
    assert r["workspace_cm3"]["value"] == pytest.approx(math.pi / 4 * 100.0**2 * 80.0 / 1000)
    assert r["workspace_cm3"]["figure"] == "workspace cylinder d100 x 80 mm"
    assert r["continuous_force_N"]["value"] > 0
    assert "gravity_torque_max_Nm" not in r  # no build, no solids' masses


def test_workspace_rows_of_the_bundled_delta(shared_build):
    d, _, rep = shared_build("delta.toml", DELTA_FORMATS, "preview")
    r = _rows(rep["datasheet"]["rows"])
    assert r["workspace_cm3"]["value"] == pytest.approx(100.0**3 / 1000)
    assert r["workspace_cm3"]["figure"] == "workspace box 100 x 100 x 100 mm"
    # the whole reachable volume holds the 1000 cm^3 cube, and the well-conditioned is within it
    assert r["reachable_volume_cm3"]["value"] > 1000.0
    assert r["well_conditioned_volume_cm3"]["value"] <= r["reachable_volume_cm3"]["value"]
    assert "10 mm" in r["reachable_volume_cm3"]["model"]


def _potential_J(d, theta, width, bodies) -> float:
    """V (J) of the moving solids at joint angles theta (3,): sum m g z of each body's centre."""
    pose = fk(d, theta[None, :])
    assert pose.ok[0]
    tfs = poses_at(d, pose.P_mm, pose.theta_rad, width)
    V = 0.0
    for name, b in bodies.items():
        T = tfs[name][0]
        z_mm = T[2, :3] @ np.asarray(b["com_mm"]) + T[2, 3]
        V += b["mass_kg"] * 9.80665 * z_mm * 1e-3
    return V


def test_the_gravity_load_is_the_potential_energys_gradient(shared_build):
    d, _, rep = shared_build("delta.toml", DELTA_FORMATS, "preview")
    g = rep["gravity"]
    bodies = {k: v for k, v in rep["bodies"].items() if k != "ground"}
    assert {f"upper_{i}" for i in range(3)} | {"effector"} <= set(bodies)
    h = 1e-6
    for j in range(3):
        theta = ik(d.mechanism, [g["at_mm"][j]]).theta_rad[0]
        e = np.eye(3)[j] * h
        dV = (_potential_J(d.mechanism, theta + e, d.parallelogram_width_mm, bodies)
              - _potential_J(d.mechanism, theta - e, d.parallelogram_width_mm, bodies)) / (2 * h)
        assert abs(dV) == pytest.approx(g["joint_torque_max_Nm"][j], rel=1e-5)
    # the row: the worst joint (direct drive: motor = joint) and its share of the RE 40's T_cont
    r = _rows(rep["datasheet"]["rows"])
    worst = max(g["joint_torque_max_Nm"])
    assert r["gravity_torque_max_Nm"]["value"] == pytest.approx(worst)
    t_cont = get_motor("maxon-re40", "test").torque_continuous_mNm * 1e-3
    assert t_cont == pytest.approx(0.187)
    assert r["gravity_torque_share"]["value"] == pytest.approx(worst / t_cont)
    assert g["motor_joint"] in JOINTS
    assert "before gravity compensation" in r["continuous_force_N"]["model"]


@pytest.mark.slow  # a delta build of its own (every pair of solids at 125 points), ~40 s
def test_a_priced_delta_build_has_the_bom_cost_of_its_order(tmp_path):
    design = tmp_path / "priced.toml"
    design.write_text((ROOT / "designs" / "delta.toml").read_text()
                      + '\n[prices]\ncurrency = "EUR"\n"maxon RE 40" = 250.0\n')
    out = tmp_path / "out"
    code, _, err = hapticad("build", design, "--out", out, "--fidelity", "preview")
    assert code == 0, err
    with (out / "order.csv").open() as f:
        lines = list(csv.DictReader(f))
    priced = [float(r["line_price"]) for r in lines if r["line_price"] and r["group"] != "total"]
    assert priced and sum(priced) == pytest.approx(3 * 250.0)  # three motors
    r = _rows(json.loads((out / "report.json").read_text())["datasheet"]["rows"])
    assert r["bom_cost"]["value"] == pytest.approx(sum(priced))
    assert r["bom_cost"]["unit"] == "EUR"


def test_encoders_are_numbered_as_their_motors(shared_build):
    """assembly.md names the delta's encoders encoder_0 .. encoder_2, one per motor_0 ..
    motor_2 (the delta numbers arms, motors and joints theta_i from 0); a row without
    instance names keeps the pipeline's encoder_1 .. encoder_n (the 5-bar's, whose motors are
    numbered from 1)."""
    from cad.pipeline.family import NO_SOLID_STEP, build_steps

    _, out, rep = shared_build("delta.toml", DELTA_FORMATS, "preview")
    text = (out / "assembly.md").read_text()
    inst = rep["placement"]["instances"]
    assert sorted(n for n, p in inst.items() if p["kind"] == "motor") == ["motor_0", "motor_1", "motor_2"]
    for i in range(3):
        assert f"`motor_{i}`" in text and f"`encoder_{i}` (encoder)" in text
    assert "`encoder_3`" not in text
    row = {"part": "encoder", "description": "e", "quantity": 2}
    steps = build_steps([], None, (), [row])
    step = next(s for s in steps if s.title == NO_SOLID_STEP)
    assert step.new == ["encoder_1", "encoder_2"] and steps[-1].title == "final checks"


def test_every_limited_row_is_a_target_key_and_every_target_key_a_row(delta_build):
    """``hapticad check`` lists each limited row under "target key": each must be a key
    ``[targets]`` / ``--target`` takes (a tester's ``--target 'ball_joint_tilt_max_deg<=20'``
    was refused as unknown), and each target key a row of the delta's datasheet."""
    from cad.design.targets import DELTA_TARGET_KEYS

    d, _, rep = delta_build
    rows, limits, _ = rows_and_limits(d, rep)
    keys = {r["key"] for r in rows}
    assert set(limits) <= set(DELTA_TARGET_KEYS), set(limits) - set(DELTA_TARGET_KEYS)
    assert set(DELTA_TARGET_KEYS) <= keys, set(DELTA_TARGET_KEYS) - keys
