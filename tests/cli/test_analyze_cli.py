"""``hapticad analyze``: JSON contract, paper comparison, apparent mass, report."""

import json
import subprocess
import sys
from pathlib import Path

import pytest
from cli_helpers import assert_one_line_error, hapticad, hapticad_json

DESIGNS = Path(__file__).resolve().parents[2] / "designs"
PAPER_H = "H11=2.97e-5,H12=3.22e-5,H22=1.17e-4,H33=7.09e-5"
METRICS = ("stroke_mm", "dy_max_mm", "slope_max", "linearity", "torque_mean_mNm", "torque_variation",
           "bbox_mm", "min_transmission_angle_deg")
LINKAGE = ("l1_mm", "l2_mm", "l3_mm", "l4_mm", "l5_mm", "le_mm", "phi_e_deg", "phi1_min_deg",
           "phi1_max_deg", "branch")


def test_json_contract_and_paper_apparent_mass():
    r = hapticad_json("analyze", DESIGNS / "hoeken.toml", "--inertia", PAPER_H)
    for k in METRICS + LINKAGE:
        assert k in r
    am = r["apparent_mass"]
    for k in ("M11_min_g", "M11_max_g", "M12_min_g", "M12_max_g", "M22_max_g"):
        assert k in am
    # Hoeken paper Fig. 6: M11 between 27.5 and 42.8 g with the paper's H
    assert am["M11_min_g"] == pytest.approx(27.5, rel=0.01)
    assert am["M11_max_g"] == pytest.approx(42.8, rel=0.01)
    assert r["paper"]["dy_max_mm"]["paper"] == 0.2
    assert r["stiffness"]["K_max_N_per_m"] == pytest.approx(2500, rel=0.05)  # eq (25)


def test_samples_option_and_bad_inertia():
    r = hapticad_json("analyze", DESIGNS / "roberts.toml", "--samples", "101")
    assert r["samples"] == 101
    code, _, err = hapticad("analyze", DESIGNS / "hoeken.toml", "--inertia", "H11=1e-5,H12=2e-5")
    assert_one_line_error(code, err, "--inertia", "missing")
    code, _, err = hapticad("analyze", DESIGNS / "hoeken.toml", "--samples", "2")
    assert_one_line_error(code, err, "--samples")


def test_report_written(tmp_path):
    r = hapticad_json("analyze", DESIGNS / "hoeken.toml", "--inertia", PAPER_H, "--report", tmp_path)
    md = (tmp_path / "analysis.md").read_text()
    assert "M11_max_g" in md and "kinematics.png" in md
    assert (tmp_path / "kinematics.png").stat().st_size > 10_000
    assert (tmp_path / "apparent_mass.png").stat().st_size > 10_000
    assert json.loads((tmp_path / "analysis.json").read_text())["stroke_mm"] == r["stroke_mm"]


def test_analyze_and_kinematics_import_no_cad():
    """`import cad.kinematics` / dynamics / actuators and the analyze command never load OCP,
    build123d or cadquery (they cost seconds and are not needed)."""
    code = (
        "import sys, runpy\n"
        "import cad.kinematics.fourbar, cad.kinematics.metrics, cad.kinematics.synthesis\n"
        "import cad.dynamics.inertia, cad.dynamics.stiffness, cad.analysis\n"
        "import cad.actuators, cad.isotropy\n"
        "from cad.cli.app import run\n"
        f"rc = run(['analyze', r'{DESIGNS / 'hoeken.toml'}', '--json'])\n"
        "bad = [m for m in ('OCP', 'build123d', 'cadquery', 'bd_warehouse', 'trimesh', 'manifold3d',"
        " 'matplotlib', 'magpylib') if m in sys.modules]\n"
        "print('BAD', bad, rc)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert "BAD [] 0" in out, out


def test_usage_errors_are_one_line_exit_2():
    for args in (("analyze",), ("analyze", DESIGNS / "hoeken.toml", "--samples", "x"), ("nope",)):
        code, out, err = hapticad(*args)
        assert_one_line_error(code, err)
        assert out == ""
