"""Every datasheet figure is a ``check`` / ``fit`` target for the pantograph families, the
first mode included, and a missed first mode says what blocks it and by how much (issue 32).

References: the force recomputed by hand from the 5-bar Jacobian (SVD over the workspace
grid) and the RE 35's catalog continuous torque; the mode ceiling's estimate against a real
build of the design it proposes (the solids' masses, the datasheet's structure model); the
clevis-height rule against the build's own refusal one step above it.
"""

from __future__ import annotations

import copy
import json
import tomllib
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import hapticad

from cad.design import load_design, parse_design

DESIGNS = Path(__file__).resolve().parents[3] / "designs"


def _force_by_hand_N(design_path: Path) -> float:
    from cad.data.catalog import get_motor
    from cad.kinematics.fivebar import STATUS_OK, jacobian_rad_per_m

    d = load_design(design_path)
    J, st = jacobian_rad_per_m(d.mechanism, d.workspace_points())
    per_Nm = min(np.linalg.svd(J[i].T, compute_uv=False)[-1] for i in np.flatnonzero(st == STATUS_OK))
    return per_Nm * get_motor(d.parts.motor).torque_continuous_mNm * 1e-3


@pytest.mark.slow  # an end-to-end search or build run (20-40 s): CI's slow set keeps the default suite under 10 min
def test_fit_moves_the_links_to_a_motor_force_target(tmp_path):
    out = tmp_path / "fit.toml"
    code, _, err = hapticad("fit", DESIGNS / "pantograph.toml", "--target", "continuous_force_N>=0.69",
                            "--free", "mechanism.proximal_mm=100:140", "--trials", "5", "--out", out)
    assert code == 0, err
    assert _force_by_hand_N(out) >= 0.69  # the written design, evaluated independently
    assert _force_by_hand_N(DESIGNS / "pantograph.toml") < 0.69  # the start did not meet it
    # the written design still misses the default first-mode limit: said in the file, and
    # `hapticad check` of the written file (a second command reading it) agrees
    (line,) = [ln for ln in out.read_text().splitlines() if ln.startswith("# default limit missed:")]
    code, o, _ = hapticad("check", out, "--json")  # checks the file's [targets], warns on the limits
    res = json.loads(o)
    assert code == 0 and res["ok"] and not res["limits_met"]
    (warning,) = [w for w in res["limit_warnings"] if w.startswith("first structural mode")]
    check_Hz = float(warning.split(") = ", 1)[1].split(" Hz", 1)[0])
    fit_Hz = float(line.split("first_mode_Hz = ", 1)[1].split(",", 1)[0])
    assert fit_Hz == pytest.approx(check_Hz, rel=1e-3) and fit_Hz < 150


def test_fit_that_cannot_meet_a_datasheet_target_exits_1_with_the_best_figure(tmp_path):
    out = tmp_path / "fit.toml"
    code, _, err = hapticad("fit", DESIGNS / "pantograph.toml", "--target", "continuous_force_N>=5",
                            "--free", "mechanism.proximal_mm=100:140", "--trials", "3", "--out", out)
    assert code == 1
    (line,) = [ln for ln in err.splitlines() if "target missed:" in ln]
    best = float(line.rsplit("best reached ", 1)[1].split(",")[0])
    assert best == pytest.approx(_force_by_hand_N(out), rel=1e-5)  # the written (best) design's figure
    assert "target missed: continuous_force_N" in out.read_text()  # and in the file's comment


def test_check_first_mode_target_names_what_blocks_it():
    code, out, err = hapticad("check", DESIGNS / "pantograph.toml", "--target", "first_mode_Hz>=150", "--json")
    assert code == 1, err
    res = json.loads(out)
    (row,) = res["rows"]
    ds = json.loads(hapticad("datasheet", DESIGNS / "pantograph.toml", "--json")[1])["datasheet"]
    rows = {r["key"]: r for r in ds["rows"]}
    assert row["computed"] == rows["first_mode_Hz"]["value"] and row["computed"] < 150
    (why,) = [w for w in res["limit_warnings"] if "best the tubes reach" in w]
    assert "out of plane bending" in why and "150 Hz needs tube_od_mm" in why
    reach = rows["first_mode_reachable_Hz"]
    assert rows["first_mode_Hz"]["value"] < reach["value"] < 150  # the layout cannot reach 150 Hz
    assert "best the tubes reach" in reach["model"]


def test_mode_ceiling_against_a_real_build_of_its_best_tube():
    """The ceiling's estimate (the start's clevis masses kept) against the datasheet's model on a
    real build of the tube it proposes, at the largest clevis height the shaft allows; one step
    taller and the build refuses (the rule the ceiling names)."""
    from cad.errors import DesignError
    from cad.families.pantograph.datasheet import structure
    from cad.families.pantograph.mode_ceiling import clevis_height_max_mm, mode_ceiling
    from cad.families.pantograph.targets import pantograph_target_values

    raw = tomllib.loads((DESIGNS / "pantograph.toml").read_text())
    d0 = parse_design(raw, "p")
    _, rep0 = pantograph_target_values(d0, "inertia", {"moving_mass_g"})
    c = mode_ceiling(d0, rep0["bodies"], 10.0, 150.0)
    b = c["best"]
    h = clevis_height_max_mm(d0)
    assert b["tube_od_mm"] == h - 2.0
    r = copy.deepcopy(raw)
    r.setdefault("parts", {}).update(tube_od_mm=b["tube_od_mm"], tube_id_mm=b["tube_id_mm"],
                                     tube_material=b["tube_material"], clevis_height_mm=h)
    d = parse_design(r, "best")
    _, rep = pantograph_target_values(d, "inertia", {"moving_mass_g"})
    built = structure(d, rep)["first_mode_Hz"]
    assert built == pytest.approx(b["first_mode_Hz"], rel=0.01)
    # regression pins (this model, the bundled design; the figures docs/check-fit.md quotes)
    assert h == 14.0 and round(c["now"]["first_mode_Hz"], 1) == 32.8
    assert round(b["first_mode_Hz"]) == 95 and round(built, 1) == 94.9
    assert round(c["od_needed_mm"], 1) == 16.6 and "clevis_height_mm >= 18.6 mm" in c["text"]
    r["parts"]["clevis_height_mm"] = h + 0.5
    with pytest.raises(DesignError, match="clevis_height_mm"):
        from cad.families.pantograph.layout import set_screw_plan

        set_screw_plan(parse_design(r, "taller"))


@pytest.mark.slow
def test_fit_first_mode_with_the_tubes_misses_and_says_why(tmp_path):
    """~18 builds (minutes): the bundled 5-bar's first mode cannot reach 150 Hz with tubes that
    fit its clevises; fit exits 1 with the best figure and the ceiling line. Covered cheaply by
    the check and ceiling tests above."""
    out = tmp_path / "fit.toml"
    code, _, err = hapticad("fit", DESIGNS / "pantograph.toml", "--target", "first_mode_Hz>=150",
                            "--free", "parts.tube_od_mm=6:10", "--out", out)
    assert code == 1
    assert "target missed: first_mode_Hz" in err and "best the tubes reach" in err


def test_optimize_says_which_targets_its_gii_optimum_misses(tmp_path):
    """The GII optimum of a 5-bar whose [targets] ask 2 N continuous: exit 1, one line with the
    optimum's figure (= the written design's force by hand), and the same line in its comment."""
    src = tmp_path / "p.toml"
    text = (DESIGNS / "pantograph.toml").read_text()
    text = text.split("\n[optimize]")[0] + ("\n[optimize]\nbase_mm = [0.0, 400.0, 5]\nproximal_mm = [100.0, 200.0, 5]\n"
                                          "distal_mm = [150.0, 250.0, 5]\n\n[targets]\ncontinuous_force_N = { min = 2.0 }\n")
    src.write_text(text)
    out = tmp_path / "opt.toml"
    code, _, err = hapticad("optimize", src, "--out", out)
    assert code == 1
    (line,) = [ln for ln in err.splitlines() if "target missed: continuous_force_N" in ln]
    assert float(line.rsplit("best reached ", 1)[1]) == pytest.approx(_force_by_hand_N(out), rel=1e-5)
    assert "target missed: continuous_force_N" in out.read_text()
    src.write_text(text.replace("min = 2.0", "min = 0.5"))  # met: exit 0, nothing said
    code, _, err = hapticad("optimize", src, "--out", tmp_path / "opt2.toml")
    assert code == 0 and "target missed" not in err


def test_optimize_says_which_default_limits_its_gii_optimum_misses(tmp_path):
    """The bundled 5-bar has no [targets]: its GII optimum is written (exit 0) and every
    default limit it misses is said on stderr and in the file, with the figures `hapticad
    check` computes on the written file and the force computed by hand."""
    out = tmp_path / "opt.toml"
    code, _, err = hapticad("optimize", DESIGNS / "pantograph.toml", "--out", out)
    assert code == 0, err
    said = [ln for ln in err.splitlines() if "misses a default datasheet limit" in ln]
    in_file = [ln for ln in out.read_text().splitlines() if ln.startswith("# default limit missed:")]
    code, o, _ = hapticad("check", out, "--json")
    missed = [r for r in json.loads(o)["rows"] if not r["ok"]]
    assert code == 1 and {r["key"] for r in missed} == {"continuous_force_N", "first_mode_Hz"}
    assert len(said) == len(in_file) == len(missed)
    force = next(r["computed"] for r in missed if r["key"] == "continuous_force_N")
    assert force == pytest.approx(_force_by_hand_N(out), rel=1e-4)
    assert f"= {force:.4g} N" in said[0] and f"= {force:.4g} N" in in_file[0]


def test_fit_trials_flag_is_checked_before_any_search():
    code, _, err = hapticad("fit", DESIGNS / "pantograph.toml", "--target", "gii>=0.7",
                            "--free", "mechanism.proximal_mm=100:140", "--trials", "0")
    assert code == 2 and "--trials" in err and len(err.strip().splitlines()) == 1, err
