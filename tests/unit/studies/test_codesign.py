"""Co-design: the committed light optimum re-checked on the exact solids, the cheap model's
error there, the search's constraints re-computed independently, the Pareto filter."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from cad.design import load_design
from tests.cli_helpers import assert_one_line_error, hapticad

ROOT = Path(__file__).resolve().parents[3]
LIGHT = ROOT / "designs" / "hoeken_light.toml"


@pytest.fixture(scope="module")
def light_check():
    code, out, err = hapticad("check", str(LIGHT), "--json")
    return code, json.loads(out), err


def test_hoeken_light_meets_its_brief_on_the_exact_solids(light_check):
    """Issue 13: Hoeken family, 50 mm, 5 N, dy <= 0.2 mm, M11 max <= 35 g (the paper: 42.8 g CAD,
    44 g measured, §III.B), zero interference, structural limits met."""
    code, res, err = light_check
    assert code == 0, err
    c = res["computed"]
    assert c["M11_max_g"] <= 35.0
    assert c["stroke_mm"] == pytest.approx(50.0, abs=0.01)
    assert c["dy_max_mm"] <= 0.2
    assert c["min_clearance_mm"] >= 0.5
    assert c["first_mode_Hz"] >= 150.0
    d = load_design(LIGHT)
    assert d.force_N == 5.0
    # peak crank torque within the chosen motor's continuous torque
    from cad.studies.codesign.search import MOTOR_CONTINUOUS_TORQUE_MNM

    assert c["torque_mean_mNm"] * (1 + c["torque_variation"]) <= MOTOR_CONTINUOUS_TORQUE_MNM[d.parts.motor]


def test_cheap_model_error_at_the_optimum(light_check):
    from cad.studies.codesign import cheap

    exact = light_check[1]["computed"]["M11_max_g"]
    est = cheap.apparent_mass(load_design(LIGHT))["M11_max_g"]
    assert abs(est - exact) / exact < 0.05  # docs/codesign.md: +1.5 % at this optimum


def test_search_candidates_meet_the_constraints_recomputed():
    from cad.kinematics.fourbar import FourBar
    from cad.kinematics.metrics import compute_metrics
    from cad.studies.codesign import search

    d = load_design(ROOT / "designs" / "hoeken_light_brief.toml")
    pb = search.problem_from(d)
    pb.fixed_parts = {"hub_shaft_engagement_min_mm": 5.0}
    cands, records = search.run(pb, 12, seed=1)
    assert len(records) == 12 and cands
    for c in cands[:3]:
        m = c.mechanism
        fb = FourBar(m["l1_mm"], m["l2_mm"], m["l3_mm"], m["l4_mm"], m["l5_mm"], m["le_mm"],
                     0.0, m["branch"])
        import math

        k = compute_metrics(fb, math.radians(m["phi1_min_deg"]), math.radians(m["phi1_max_deg"]), 5.0)
        assert k.stroke_mm == pytest.approx(50.0, rel=1e-4)
        assert k.dy_max_mm <= 0.2 + 1e-3
        assert k.min_transmission_angle_deg >= 40.0 - 1e-6
        assert c.parts["pin"].endswith(str(int(float(c.parts["bearing"].split("-")[0][1:]))))


def test_pareto_front_is_non_dominated():
    from cad.studies.codesign.search import pareto

    recs = [{"trial": i, "value": 1.0, "M11_max_g": a, "torque_variation": b}
            for i, (a, b) in enumerate([(30, 0.5), (31, 0.1), (32, 0.2), (29, 0.9), (35, 0.05)])]
    recs.append({"trial": 9, "value": None, "M11_max_g": 1, "torque_variation": 0.0})
    assert [r["trial"] for r in pareto(recs)] == [3, 0, 1, 4]


def test_objective_on_a_pantograph_is_refused():
    code, out, err = hapticad("optimize", str(ROOT / "designs" / "pantograph.toml"),
                              "--objective", "min-apparent-mass")
    assert_one_line_error(code, err, "--objective")


def test_search_perturbs_the_family_proportions_within_the_tolerance():
    """``--proportions-tol 0.05``: every candidate's link ratios (to l2) stay within 5 % of
    the family's (Hoeken paper Fig. 2), at least one differs, and stroke / dy_max /
    transmission angle, recomputed on the candidate's own linkage, meet the brief."""
    import math

    from cad.kinematics.fourbar import FourBar
    from cad.kinematics.metrics import compute_metrics
    from cad.studies.codesign import search

    d = load_design(ROOT / "designs" / "hoeken_light_brief.toml")
    pb = search.problem_from(d)
    pb.fixed_parts = {"hub_shaft_engagement_min_mm": 5.0}
    pb.proportions_tol = 0.05
    cands, records = search.run(pb, 16, seed=0)
    assert cands
    fam = d.linkage
    moved = 0.0
    for c in cands:
        m = c.mechanism
        for k in search.PROPORTIONS:
            if getattr(fam, k) == 0.0:  # a zero dimension stays zero (Hoeken's l4)
                assert m[k] == 0.0
                continue
            r = (m[k] / m["l2_mm"]) / (getattr(fam, k) / fam.l2_mm)
            assert 0.95 - 1e-6 <= r <= 1.05 + 1e-6, (k, r)
            moved = max(moved, abs(r - 1.0))
        fb = FourBar(m["l1_mm"], m["l2_mm"], m["l3_mm"], m["l4_mm"], m["l5_mm"], m["le_mm"],
                     math.radians(m["phi_e_deg"]), m["branch"])
        k = compute_metrics(fb, math.radians(m["phi1_min_deg"]), math.radians(m["phi1_max_deg"]), 5.0)
        assert k.stroke_mm == pytest.approx(50.0, rel=1e-4)
        assert k.dy_max_mm <= 0.2 + 1e-3
        assert k.min_transmission_angle_deg >= 40.0 - 1e-6
    assert moved > 1e-3


def test_optimize_never_replaces_a_users_file_named_like_its_chart(tmp_path):
    """`optimize --out x.toml` writes x_pareto.png/.svg beside x.toml: a file of that name
    the user made is refused before the search (exit 2, untouched, nothing written); a
    chart hapticad wrote (save_figure's creator mark) may be replaced."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    from cad.cli.cmd_optimize import chart_replaceable
    from cad.errors import DesignError
    from cad.report.figures import save_figure

    mine = tmp_path / "x_pareto.png"
    mine.write_bytes(b"\x89PNG\r\n\x1a\n my own chart")
    code, _, err = hapticad("optimize", str(ROOT / "designs" / "hoeken_light_brief.toml"),
                            "--objective", "min-apparent-mass", "--trials", "5",
                            "--out", str(tmp_path / "x.toml"))
    assert_one_line_error(code, err, "--out", "x_pareto.png")
    assert mine.read_bytes().endswith(b"my own chart")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x_pareto.png"]
    fig = Figure()
    fig.add_subplot().plot([0, 1])
    for ext in ("png", "svg"):
        ours = tmp_path / f"ours_pareto.{ext}"
        save_figure(fig, ours)
        assert chart_replaceable(ours, tmp_path / "d.toml")
        fig.savefig(tmp_path / f"theirs.{ext}")  # plain matplotlib: no hapticad mark
        with pytest.raises(DesignError):
            chart_replaceable(tmp_path / f"theirs.{ext}", tmp_path / "d.toml")
    assert not chart_replaceable(tmp_path / "absent.png", tmp_path / "d.toml")


@pytest.mark.slow
def test_optimize_reaches_the_light_result_without_the_hand_written_starts(tmp_path):
    """Issue 21: `optimize --no-starts` (TPE from its own random trials only, seed 0) reaches
    M11max <= 35 g on the exact solids within a budget of 800 trials, and the accepted optimum
    meets the brief. Slow: 800 cheap trials + 3 exact re-evaluations cost 41-46 s of CPU (2.1-3.3 min
    wall on the loaded 2-core machine); without the starts the first cheap trial <= 35 g came
    at trial 620 / 435 / 493 (seeds 0 / 1 / 2), so no smaller budget is honest."""
    out = tmp_path / "light.toml"
    code, o, err = hapticad("optimize", str(ROOT / "designs" / "hoeken_light_brief.toml"),
                            "--objective", "min-apparent-mass", "--trials", "800", "--seed", "0",
                            "--exact-top", "3", "--no-starts", "--out", str(out), "--json")
    assert code == 0, err
    rep = json.loads(o)
    assert rep["hand_written_starts"] == 0 and rep["trials"] == 800
    ex = rep["best"]["exact"]
    assert ex["M11_max_g"] <= 35.0
    code, o, err = hapticad("check", str(out), "--json")  # the written design, re-checked
    assert code == 0, err
    c = json.loads(o)["computed"]
    assert c["M11_max_g"] == pytest.approx(ex["M11_max_g"], rel=1e-6) and c["M11_max_g"] <= 35.0
    assert c["stroke_mm"] == pytest.approx(50.0, abs=0.01) and c["dy_max_mm"] <= 0.2


def test_optimize_exact_top_and_no_starts_flags():
    """`--exact-top K` re-evaluates exactly K distinct candidates on the solids (here 1, the
    cheapest); `--no-starts` drops the hand-written guesses: with them trial 0 is STARTS[0]
    (span 96 deg, carbon-fibre), without them it is TPE's own seeded random draw."""
    from cad.studies.codesign import search

    brief = str(ROOT / "designs" / "hoeken_light_brief.toml")
    code, o, err = hapticad("optimize", brief, "--objective", "min-apparent-mass", "--trials", "12",
                            "--seed", "1", "--exact-top", "1", "--json")
    rep = json.loads(o)
    # 12 trials do not reach the brief's M11 <= 35 g on the solids (35.00x g): exit 1 and the
    # one miss line (issue 32 item 4), the candidate is still the accepted best
    assert code == 1, err
    assert [m["key"] for m in rep["misses"]] == ["M11_max_g"] and rep["misses"][0]["written"] > 35.0
    assert sum("target missed" in ln for ln in err.splitlines()) == 1
    assert len(rep["exact_checked"]) == 1 and rep["hand_written_starts"] == len(search.STARTS)
    # in 12 trials the cheapest is STARTS[0] (trial 0); the one exact re-check accepts it
    assert rep["exact_checked"][0]["trial"] == rep["best"]["trial"] == 0
    assert rep["best"]["exact"]["M11_max_g"] == rep["exact_checked"][0]["exact"]["M11_max_g"]
    d = load_design(ROOT / "designs" / "hoeken_light_brief.toml")
    pb = search.problem_from(d)
    pb.fixed_parts = search.fixed_parts(d)
    _, with_starts = search.run(pb, 2, seed=1)
    _, without = search.run(pb, 2, seed=1, starts=False)
    # STARTS[0] gives 35.8 g (cheap model) on trial 0 (regression pin, our own run; issue 21)
    assert with_starts[0]["value"] == pytest.approx(35.823, abs=1e-3)
    assert [r["trial"] for r in without] == [0, 1]
    assert without[0].get("footprint_mm2") != with_starts[0]["footprint_mm2"]
    assert without[0]["value"] != with_starts[0]["value"]
