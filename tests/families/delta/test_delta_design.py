"""The delta design file (issue 36 §1) and the commands that take it (gii, optimize).

References: the GII of the loaded design against :func:`cad.isotropy.gii.delta_gii` on the
same grid built by hand (eq 5); the optimizer against brute force over the same candidates
(isotropy paper eq 6, culling is exact). ``designs/delta.toml`` states the optimum of its
own ``[optimize]`` ranges: a regression pin of our own run (the ranges and the cube are the
design's; no paper states this device).
"""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import numpy as np
import pytest

from cad.design import load_design, parse_design
from cad.errors import DesignError
from cad.isotropy.culling import optimize
from cad.isotropy.gii import delta_gii
from cad.kinematics.delta import Delta
from tests.cli_helpers import assert_one_line_error, hapticad, hapticad_json

ROOT = Path(__file__).resolve().parents[3]
DESIGN = ROOT / "designs" / "delta.toml"
RAW = tomllib.loads(DESIGN.read_text())


def test_gii_of_the_bundled_delta_against_a_hand_grid():
    d = load_design(DESIGN)
    m = RAW["mechanism"]
    delta = Delta(m["base_radius_mm"], m["effector_radius_mm"], m["upper_arm_mm"],
                  m["lower_arm_mm"], theta_min_rad=np.radians(m["motor_angle_min_deg"]),
                  theta_max_rad=np.radians(m["motor_angle_max_deg"]))
    t = np.linspace(-50, 50, 5)
    X, Y, Z = np.meshgrid(t, t, t - 180.0, indexing="ij")
    pts = np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=-1)
    rep = hapticad_json("gii", DESIGN)
    assert rep["family"] == "delta" and rep["n_points"] == 125
    assert rep["gii"] == pytest.approx(delta_gii(delta, pts).gii, rel=1e-12)
    assert rep["gii"] == pytest.approx(d.gii().gii, rel=1e-15) and rep["failure"] is None


@pytest.mark.slow  # an end-to-end search or build run (20-40 s): CI's slow set keeps the default suite under 10 min
def test_optimize_returns_the_bundled_geometry_and_culling_equals_brute_force():
    d = load_design(DESIGN)
    prob = d.problem()
    cull, brute = optimize(prob, "culling"), optimize(prob, "brute")
    assert cull.best_index == brute.best_index and cull.gii == brute.gii
    best = prob.candidate(cull.best_index)
    # regression pin: the bundled mechanism is the optimum of its own ranges
    assert best == {k: RAW["mechanism"][k] for k in best}
    rep = hapticad_json("optimize", DESIGN)
    assert rep["best"] == best and rep["gii"] == cull.gii


def test_cylinder_workspace_and_its_keys():
    raw = copy.deepcopy(RAW)
    raw["workspace"] = {"shape": "cylinder", "center_mm": [0, 0, -180], "diameter_mm": 100.0,
                        "height_mm": 80.0, "grid": 4}
    d = parse_design(raw, "cyl.toml")
    pts = d.workspace_points()
    assert pts.shape == (4 * (1 + 6 + 12 + 18), 3)
    assert np.hypot(pts[:, 0], pts[:, 1]).max() == pytest.approx(50.0)
    assert d.gii().gii > 0


@pytest.mark.parametrize("edit,field", [
    (lambda r: r["mechanism"].pop("upper_arm_mm"), "mechanism.upper_arm_mm"),
    (lambda r: r["mechanism"].update(lower_arm_mm=-5), "mechanism.lower_arm_mm"),
    (lambda r: r["mechanism"].update(motor_angle_max_deg=-60), "mechanism.motor_angle_max_deg"),
    (lambda r: r["workspace"].update(shape="sphere"), "workspace.shape"),
    (lambda r: r["workspace"].update(size_mm=[100, 100]), "workspace.size_mm"),
    (lambda r: r["workspace"].update(diameter_mm=80), "workspace.diameter_mm"),
    (lambda r: r.update(parts={"motor": "no-such-motor"}), "parts.motor"),
    (lambda r: r.update(parts={"bearing": "608"}), "parts.bearing"),
    (lambda r: r.update(parts={"encoder": "optical-2000", "encoder_counts_per_rev": 4096}),
     "parts.encoder_counts_per_rev"),
    (lambda r: r.update(motor={"torque_peak_mNm": -1.0}), "motor.torque_peak_mNm"),
    (lambda r: r.update(firmware={"plane": "vertical"}), "firmware.plane"),
    (lambda r: r.update(transmission={"kind": "capstan", "capstan_diameter_mm": 40.0, "ratio": 0.5,
                                      "cable": "steel-7x7-1"}), "transmission.ratio"),
    (lambda r: r.update(transmission=[{"kind": "direct"}] * 2), "transmission"),
    (lambda r: r.update(prices={"motor": -3.0}), "prices.motor"),  # [prices] as every family's
    (lambda r: r["optimize"].update(upper_arm_mm=[120, 60, 3]), "optimize.upper_arm_mm"),
    (lambda r: r["actuators"].update(torque_max_Nm=[1, 1]), "actuators.torque_max_Nm"),
])
def test_bad_input_names_the_field(edit, field):
    raw = copy.deepcopy(RAW)
    edit(raw)
    with pytest.raises(DesignError) as err:
        parse_design(raw, "bad.toml")
    assert err.value.field == field


@pytest.mark.parametrize("command", ["wall", "analyze"])
def test_commands_without_a_delta_model_refuse_in_one_line(command):
    """build, datasheet, check and fit take a delta (tests/families/delta/test_delta_build.py,
    test_delta_targets.py); the four-bar's commands refuse it, naming the commands that take it."""
    code, _, err = hapticad(command, DESIGN)
    assert_one_line_error(code, err, "mechanism.family",
                          "for a delta design use: hapticad check, hapticad fit, hapticad build, "
                          "hapticad gii")
