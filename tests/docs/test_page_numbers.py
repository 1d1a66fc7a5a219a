"""Numbers typed on docs/papers.md, docs/check-fit.md and docs/codesign.md that come from the
code, recomputed now and compared with the page at its printed rounding (issue 34 §4: a typed
run number is generated or checked, never left to drift). Each test reads its numbers from the
page, so the page and the code cannot part. Pure kinematics, closed forms and catalog data: no
CAD build, about a second in all."""

from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path

import numpy as np
import pytest

from cad.kinematics.families import FAMILIES, PAPER_TABLES, family_linkage
from cad.kinematics.metrics import compute_metrics

ROOT = Path(__file__).resolve().parents[2]


def _page(name: str) -> str:
    """The page's text with line breaks folded to single spaces (sentences wrap anywhere)."""
    return " ".join((ROOT / "docs" / name).read_text(encoding="utf-8").split())


def _printed(text: str, value: float) -> None:
    """``value`` rounds to ``text`` at the decimals ``text`` prints (half a unit of its last digit)."""
    decimals = len(text.split(".")[1]) if "." in text else 0
    assert abs(value - float(text)) <= 0.5 * 10 ** -decimals + 1e-12, (text, value)


def _metrics(family: str, branch_flip: bool = False):
    fb, lo, hi = family_linkage(family)
    if branch_flip:
        fb = dataclasses.replace(fb, branch=-fb.branch)
    return compute_metrics(fb, lo, hi, force_N=5.0)


PAPERS = _page("papers.md")
#: One row of the table in docs/papers.md "Reproducing the Hoeken paper": ours (paper) per column.
ROW = re.compile(r"\| (?P<f>[a-z-]+) \| [−+]1 \| (?P<stroke>[\d.]+) \| (?P<dy>[\d.]+) \([\d.]+\) \| "
                 r"(?P<slope>[\d.]+) \([\d.]+\) \| (?P<tau>[\d.]+) \([\d.]+\) \| (?P<tv>[\d.]+) \([\d.]+\) \| "
                 r"(?P<bx>\d+) × (?P<by>\d+) \(\d+ × \d+\) \| (?P<mu>[\d.]+)° \|")


def test_papers_table_is_the_code_at_the_papers_dimensions():
    """Every "ours" cell of the Fig. 2 / Tables I-II table (stroke, dy, slope, torque mean and
    variation, joint-centre box, min transmission angle) is ``compute_metrics`` at the paper's
    Fig. 2 dimensions and 5 N (what ``hapticad analyze designs/<family>.toml`` prints), and the
    paper's column is PAPER_TABLES (the paper's Tables I and II)."""
    rows = {m["f"]: m for m in ROW.finditer(PAPERS)}
    assert set(rows) == set(FAMILIES)
    for f, r in rows.items():
        m = _metrics(f)
        for key, value in (("stroke", m.stroke_mm), ("dy", m.dy_max_mm), ("slope", m.slope_max),
                           ("tau", m.torque_mean_mNm), ("tv", m.torque_variation),
                           ("bx", m.bbox_mm[0]), ("by", m.bbox_mm[1]),
                           ("mu", m.min_transmission_angle_deg)):
            _printed(r[key], value)
        assert f"{r['tv']} ({PAPER_TABLES[f]['torque_variation']:.3f})" in r[0]


def test_papers_other_assembly_modes():
    """The branches paragraph: the other mode of Roberts (stroke, dy), of Chebyshev-V (dy) and of
    Chebyshev (stroke, dy), the flipped ``branch`` at the same dimensions and crank range."""
    m = re.search(r"other mode of Roberts has a (\d+) mm stroke and dy = ([\d.]+) mm; of "
                  r"Chebyshev-V dy = ([\d.]+) mm", PAPERS)
    rob, chv = _metrics("roberts", True), _metrics("chebyshev-v", True)
    _printed(m[1], rob.stroke_mm)
    _printed(m[2], rob.dy_max_mm)
    _printed(m[3], chv.dy_max_mm)
    m = re.search(r"the other mode gives ([\d.]+) mm but dy = ([\d.]+) mm", PAPERS)
    ch = _metrics("chebyshev", True)
    _printed(m[1], ch.stroke_mm)
    _printed(m[2], ch.dy_max_mm)


def test_papers_slope_excess_and_roberts_height():
    """The slope item's +35 / +29 / +8 % (ours / Table II - 1) and the Roberts joint centres'
    46.5 mm height the Dimensions item quotes."""
    m = re.search(r"Slope \(\+(\d+) % Roberts, \+(\d+) % Chebyshev, \+(\d+) % Chebyshev-V\)", PAPERS)
    for pct, f in zip(m.groups(), ("roberts", "chebyshev", "chebyshev-v"), strict=True):
        _printed(pct, 100 * (_metrics(f).slope_max / PAPER_TABLES[f]["slope_max"] - 1))
    m = re.search(r"joint centres alone span ([\d.]+) mm", PAPERS)
    _printed(m[1], _metrics("roberts").bbox_mm[1])


def test_papers_apparent_mass_and_eq25_with_the_papers_values():
    """`hapticad analyze designs/hoeken.toml --inertia` with the paper's H (§III.B.2): M11, M12
    and M22 as the page prints them; eq (25)'s K_max and lower bound 2 Fv / Te from the
    design's [stiffness] table (the paper's identified values)."""
    from cad.analysis import analyze
    from cad.design import load_design
    from cad.dynamics.inertia import InertiaCoefficients

    H = InertiaCoefficients(2.97e-5, 3.22e-5, 1.17e-4, 7.09e-5)
    out = analyze(load_design(ROOT / "designs" / "hoeken.toml"), inertia=H)
    am, k = out["apparent_mass"], out["stiffness"]
    m = re.search(r"\*\*M11 ([\d.]+) – ([\d.]+) g\*\* \(paper 27.5 – 42.8\), \*\*M12 −([\d.]+) – "
                  r"([\d.]+) g\*\* \(−0.4 – 0.5\), M22 < ([\d.]+) g", PAPERS)
    _printed(m[1], am["M11_min_g"])
    _printed(m[2], am["M11_max_g"])
    _printed(m[3], -am["M12_min_g"])
    _printed(m[4], am["M12_max_g"])
    assert 0 <= am["M22_max_g"] < float(m[5])
    m = re.search(r"K ≤ \*\*(\d+) N/m\*\* \(paper: \"about 2500 N/m\"\); lower bound 2Fv/Te = (\d+) N/m", PAPERS)
    _printed(m[1], round(k["K_max_N_per_m"], -1))
    _printed(m[2], k["K_min_N_per_m"])
    assert k["K_min_N_per_m"] == pytest.approx(2 * 0.12 / 0.33e-3, rel=1e-12)


def test_papers_image_series_excess_over_eq9():
    """"The full two-plate image series is 13.1 / 9.6 / 6.3 % stronger than eq (9) at d = 6 /
    11 / 30 mm" for the Fig. 8 magnet (l 20, w 8, t 4 mm, B_r 1.2 T)."""
    from cad.actuators import voicecoil as vc

    m = re.search(r"series is ([\d.]+) / ([\d.]+) / ([\d.]+) % stronger than eq \(9\) at d = (\d+) / "
                  r"(\d+) / (\d+) mm", PAPERS)
    for pct, gap in zip(m.groups()[:3], m.groups()[3:], strict=True):
        d = float(gap)
        _printed(pct, 100 * (vc.bg_image_converged_T(d, 20, 8, 4, 1.2) / float(vc.bg_eq9_T(d, 20, 8, 4, 1.2)) - 1))


def _continuous_force_N(design_path: Path) -> float:
    """T_cont / max |dx/dphi1| over the design's stroke, the lever a central finite difference of
    the solved handle point in the path frame (independent of the datasheet's analytic
    Jacobian); T_cont of the design's motor from the catalog."""
    from cad.data.catalog import MOTORS
    from cad.design import load_design
    from cad.kinematics.fourbar import solve
    from cad.kinematics.metrics import path_frame

    d = load_design(design_path)
    fr = path_frame(d.linkage, d.phi1_min_rad, d.phi1_max_rad)
    phi = np.linspace(d.phi1_min_rad, d.phi1_max_rad, 2001)
    h = 1e-6
    x = lambda p: fr.to_path(solve(d.linkage, p).P_mm)[:, 0]  # noqa: E731
    lever_m = np.abs(x(phi + h) - x(phi - h)) / (2 * h) * 1e-3
    return MOTORS[d.parts.motor].torque_continuous_mNm * 1e-3 / lever_m.max()


def test_check_fit_cheb80_continuous_force():
    """docs/check-fit.md: the silent-limits case cheb80 (no motor named: the RE 35 default)
    misses its 10 N (``mechanism.force_N``) with the continuous force the page prints."""
    from cad.design import load_design

    path = ROOT / "tests" / "cases" / "silent-limits" / "cheb80.toml"
    assert load_design(path).force_N == 10.0
    m = re.search(r"its continuous force \(([\d.]+) N\) misses 10 N", _page("check-fit.md"))
    _printed(m[1], _continuous_force_N(path))


def test_codesign_friction_bound_is_the_catalog_motors():
    """docs/codesign.md's friction bound F_cont / F_s <= T_cont / (Kt I0) for the RE 40 and the
    RE 35 from the catalog, the ratio 5 N / 0.083 N needs, the RE 40's least friction at 5 N
    (5 N Kt I0 / T_cont) and its excess over the paper's 0.083 N; and the continuous force of
    designs/hoeken.toml in the fit example."""
    from cad.data.catalog import MOTORS

    text = _page("codesign.md")
    re40, re35 = MOTORS["maxon-re40"], MOTORS["maxon-re35"]
    ratio = {k: m.torque_continuous_mNm / (m.torque_constant_mNm_per_A * m.no_load_current_mA * 1e-3)
             for k, m in (("re40", re40), ("re35", re35))}
    m = re.search(r"linkage: ([\d.]+) for the RE 40 \(([\d.]+) mN·m, ([\d.]+) mN·m/A × ([\d.]+) mA\) and "
                  r"([\d.]+) for the RE 35, where 5 N with 0.083 N needs ([\d.]+)\. At 5 N the RE 40 "
                  r"cannot go below ([\d.]+) N of friction \(\+(\d+) % over", text)
    _printed(m[1], ratio["re40"])
    _printed(m[2], re40.torque_continuous_mNm)
    _printed(m[3], re40.torque_constant_mNm_per_A)
    _printed(m[4], re40.no_load_current_mA)
    _printed(m[5], ratio["re35"])
    _printed(m[6], 5 / 0.083)
    _printed(m[7], 5 / ratio["re40"])
    _printed(m[8], 100 * (5 / ratio["re40"] / 0.083 - 1))
    m = re.search(r"missed by every candidate there \(([\d.]+) N with the RE 35 against 5 N", text)
    _printed(m[1], _continuous_force_N(ROOT / "designs" / "hoeken.toml"))
    assert math.isfinite(ratio["re35"])


def test_papers_pen_moment_arm_read_back_from_table2():
    """The haptic pen's moment-to-force ratio read back from Table 2
    (``cad.isotropy.pen_study.fit_moment_arm``): the ratio, the worst error of the fitted rows,
    each row's ours / paper and the 15 cm row's, as the page prints them."""
    from cad.isotropy.pen_study import fit_moment_arm

    fit = fit_moment_arm()
    m = re.search(r"a single ratio of \*\*≈ (\d+) mm\*\* reproduces the 20–40 cm rows' GII within "
                  r"\*\*([\d.]+) %\*\* \(ours / paper ([\d., ]+)\), while the 15 cm row stays "
                  r"\*\*~[\d.]+×\*\* off \(([\d.]+)\)", PAPERS)
    _printed(m[1], fit["moment_arm_mm"])
    _printed(m[2], 100 * fit["max_rel_error_fitted_rows"])
    ratios = fit["ratio_ours_to_paper"]
    for text, cm in zip(m[3].split(", "), (20, 25, 30, 35, 40), strict=True):
        _printed(text, ratios[cm])
    _printed(m[4], ratios[15])


STRUCTURE = _page("structure.md")


def test_structure_bearing_table_is_the_code():
    """docs/structure.md's table: the links' FE compliance along x (``cad.structure.device.analyse``
    with ``fem``, the function a build calls; a static compliance, so the masses do not enter:
    checked by two mass sets), the bearings' Palmgren estimate, the share, and the bundled
    Hoeken's joint loads and ball deflections; and the ball sets quoted (bd_warehouse's model)."""
    from cad.design import load_design
    from cad.structure import bearings
    from cad.structure.device import analyse

    for name, bearing in (("hoeken", "618/8"), ("hoeken_paper", "618/6"), ("hoeken_light", "618/4")):
        d = load_design(ROOT / "designs" / f"{name}.toml")
        r = analyse(d, [], {"crank": 0.01, "coupler": 0.01, "rocker": 0.01}, "fem", M11_max_kg=0.05)
        r2 = analyse(d, [], {"crank": 0.05, "coupler": 0.02, "rocker": 0.03}, "fem", M11_max_kg=0.08)
        assert r2["compliance_um_per_N"]["x"] == pytest.approx(r["compliance_um_per_N"]["x"], rel=1e-9)
        fe, est = r["compliance_um_per_N"]["x"], r["bearing_compliance_estimate"]
        m = re.search(rf"\| `{name}.toml` \({re.escape(bearing)}\) \| ([\d.]+) µm/N \| ([\d.]+) µm/N "
                      rf"(?:\(joint loads ([\d.]+) / ([\d.]+) / ([\d.]+) N, deflections ([\d.]+) / ([\d.]+) / "
                      rf"([\d.]+) µm\) )?\| (\d+) % \|", STRUCTURE)
        _printed(m[1], fe)
        _printed(m[2], est["x_um_per_N"])
        _printed(m[9], 100 * est["x_um_per_N"] / fe)
        if name == "hoeken":
            for i, j in enumerate(("A2", "A3", "A4")):
                _printed(m[3 + i], est["joint_load_N"][j])
                _printed(m[6 + i], est["joint_deflection_um"][j])
    m = re.search(r"(\d+) × ([\d.]+) mm for 618/8, (\d+) × ([\d.]+) mm for 618/4", STRUCTURE)
    for (z, dw), size in zip(((m[1], m[2]), (m[3], m[4])), ("M8-16-4", "M4-9-2.5"), strict=True):
        Z, Dw = bearings.ball_set(size)
        assert int(z) == Z
        _printed(dw, Dw)


def test_structure_beam_against_fe_is_the_committed_bench():
    """The FE paragraph's figures are the committed bench (docs/bench/bench_structure.json,
    ``hapticad bench --only structure``, the data of the chart the page shows): the pocketed
    bar's beam and finest-FE compliance in plane and the beam's error, the solid bar's beam and
    Timoshenko errors, and the 16×2 meshes' errors."""
    import json

    pts = json.loads((ROOT / "docs/bench/bench_structure.json").read_text())["structure"]["points"]
    pt = {(p["bar"].split()[0], p["method"], tuple(p["knob"] or ())): p for p in pts}
    m = re.search(r"beam ([\d.]+) µm/N, FE ([\d.]+) µm/N\); the beam model is unconservative in x and "
                  r"off by (\d+) %", STRUCTURE)
    _printed(m[1], pt["pocketed", "beam", ()]["compliance_um_per_N"][0])
    _printed(m[2], pt["pocketed", "fem", (64, 8)]["compliance_um_per_N"][0])
    _printed(m[3], 100 * pt["pocketed", "beam", ()]["error"])
    m = re.search(r"the solid bar's beam error is ([\d.]+) % \(shear; Timoshenko ([\d.]+) %\), FE meshes "
                  r"16×2 reach ([\d.]+) % \(solid\) / (\d+) % \(pocketed\)", STRUCTURE)
    _printed(m[1], 100 * pt["solid", "beam", ()]["error"])
    _printed(m[2], 100 * pt["solid", "timoshenko closed form", ()]["error"])
    _printed(m[3], 100 * pt["solid", "fem", (16, 2)]["error"])
    _printed(m[4], 100 * pt["pocketed", "fem", (16, 2)]["error"])


def test_design_files_light_optimum_is_the_committed_run():
    """docs/design-files.md's M11 max of designs/hoeken_light.toml is the accepted optimum of the
    committed run (docs/codesign/hoeken_light_optimize.json, the source of docs/codesign.md's
    generated table), at its printed rounding."""
    import json

    data = json.loads((ROOT / "docs/codesign/hoeken_light_optimize.json").read_text())
    m = re.search(r"`hoeken_light.toml` \(its optimum, M11 max ([\d.]+) g\)", _page("design-files.md"))
    _printed(m[1], data["best"]["exact"]["M11_max_g"])


def test_limits_page_figures():
    """docs/limits.md: Roberts' torque variation against Table I and its joint-centre height
    against the paper's Dimensions, the Chebyshev stroke at Fig. 2's dimensions (the code now),
    and the RE 35 catalog values it quotes (cad/data/catalog.py, as the catalog holds them)."""
    from cad.data.catalog import MOTORS

    text = _page("limits.md")
    rob = _metrics("roberts")
    m = re.search(r"Roberts' torque variation \(([\d.]+) vs ([\d.]+)\) and its Dimensions \((\d+) mm high vs "
                  r"([\d.]+) mm between joint centres\)", text)
    _printed(m[1], rob.torque_variation)
    assert float(m[2]) == PAPER_TABLES["roberts"]["torque_variation"]
    _printed(m[4], rob.bbox_mm[1])
    m = re.search(r"the table's dimensions give a ([\d.]+) mm stroke", text)
    _printed(m[1], _metrics("chebyshev").stroke_mm)
    re35 = MOTORS["maxon-re35"]
    m = re.search(r"\(pilot Ø(\d+), 3×M3 on Ø(\d+), (\d+) mm shaft, (\d+) g, Jm ([\d.]+) g·cm²\)", text)
    for text_value, value in zip(m.groups(), (re35.pilot_diameter_mm, re35.bolt_circle_mm, re35.shaft_length_mm,
                                              1e3 * re35.mass_kg, re35.rotor_inertia_g_cm2), strict=True):
        _printed(text_value, value)
    assert (re35.bolt_count, re35.bolt_size) == (3, "M3-0.5")


def test_firmware_page_wall_and_force_of_the_hoeken():
    """docs/firmware.md: eq (25)'s K_max of designs/hoeken.toml's [stiffness] (the wall example
    and the CHAI3D stiffness), and the CHAI3D force of the Hoeken, min over poses of T_cont /
    sigma_max(J^T): recomputed here over the whole stroke (a superset of the firmware's test
    poses) with a finite-difference J of the handle point and the catalog's RE 35."""
    from cad.data.catalog import MOTORS
    from cad.design import load_design
    from cad.dynamics.stiffness import stiffness_range_N_per_m
    from cad.kinematics.fourbar import solve

    text = _page("firmware.md")
    d = load_design(ROOT / "designs" / "hoeken.toml")
    k_max = stiffness_range_N_per_m(d.stiffness)[1]
    m = re.search(r"\((\d+) N/m at Te = 0.33 ms, the paper's \"2500 N/m\"", text)
    _printed(m[1], round(k_max, -1))
    m = re.search(r"\(the Hoeken: (\d+) N/m; its simulated K_max is several times more\)", text)
    _printed(m[1], round(k_max, -1))
    assert d.stiffness.Te_s == 0.33e-3
    phi = np.linspace(d.phi1_min_rad, d.phi1_max_rad, 2001)
    h = 1e-6
    J_m = (solve(d.linkage, phi + h).P_mm - solve(d.linkage, phi - h).P_mm) / (2 * h) * 1e-3
    force_N = MOTORS[d.parts.motor].torque_continuous_mNm * 1e-3 / np.linalg.norm(J_m, axis=1).max()
    m = re.search(r"\(Hoeken: ([\d.]+) N, the paper states 3.3 N continuous\)", text)
    _printed(m[1], force_N)


def test_tolerances_page_nominal_dy_of_the_hoeken():
    """docs/tolerances.md: the bundled Hoeken's nominal dy_max (compute_metrics with the
    design's range and samples, as ``analyze`` and ``tolerance`` take them)."""
    from cad.design import load_design

    d = load_design(ROOT / "designs" / "hoeken.toml")
    m = compute_metrics(d.linkage, d.phi1_min_rad, d.phi1_max_rad, force_N=d.force_N, samples=d.samples)
    dy = re.search(r"The nominal bar set already gives \*\*dy_max = ([\d.]+) mm\*\*", _page("tolerances.md"))
    _printed(dy[1], m.dy_max_mm)


def test_codesign_re35_span_and_rotor_mass():
    """docs/codesign.md, why the light optimum takes the RE 40: the least crank span at which the
    RE 35's continuous torque gives 5 N over 50 mm (mean torque F s / span, virtual work) and
    its rotor's apparent mass Jm / lever^2 over the mean lever s / span, from the catalog; and
    trial 442's crank span in the committed beat-prototype run."""
    import json

    from cad.data.catalog import MOTORS

    re35 = MOTORS["maxon-re35"]
    text = _page("codesign.md")
    m = re.search(r"at 5 N over 50 mm an RE 35 \(([\d.]+) mN·m continuous\) needs a crank span of at least "
                  r"5 N × 50 mm / [\d.]+ mN·m = (\d+)°, and over the lever 50 mm / \d+° its rotor \(Jm "
                  r"([\d.]+) g·cm²\) alone adds Jm / lever² = (\d+) g of M11", text)
    span_rad = 5.0 * 0.050 / (re35.torque_continuous_mNm * 1e-3)
    lever_m = 0.050 / span_rad
    _printed(m[1], re35.torque_continuous_mNm)
    _printed(m[2], math.degrees(span_rad))
    _printed(m[3], re35.rotor_inertia_g_cm2)
    _printed(m[4], re35.rotor_inertia_g_cm2 * 1e-7 / lever_m**2 * 1e3)
    front = json.loads((ROOT / "docs/codesign/hoeken_prototype.json").read_text())["prototype"]["fronts"]
    pts = {p["trial"]: p for f in front.values() for p in f["points"]}
    m = re.search(r"The nearest design, trial (\d+) \(carbon-fibre bars, RE 40, (\d+)° of crank\)", text)
    _printed(m[2], pts[int(m[1])]["crank_span_deg"])


def test_codesign_capstan_run_is_the_json_of_that_run():
    """docs/codesign.md's capstan optimum: the figures typed there are those of the run's JSON
    (docs/codesign/hoeken_capstan_optimize.json, written by the command the page shows)."""
    import json

    rec = json.loads((ROOT / "docs" / "codesign" / "hoeken_capstan_optimize.json").read_text())
    text = (ROOT / "docs" / "codesign.md").read_text(encoding="utf-8")
    b = rec["best"]
    assert rec["command"].startswith("hapticad optimize designs/hoeken_capstan.toml --objective "
                                     "min-apparent-mass --trials 300") and rec["misses"] == []
    t = b["transmission"]
    for typed in (f"{b['exact']['M11_min_g']:.1f}–{b['exact']['M11_max_g']:.1f} g",
                  f"{t['capstan_diameter_mm']:.0f} mm capstan, {t['drum_diameter_mm']:.0f} mm drum",
                  f"at {t['centre_distance_mm']:.0f} mm", f"{b['parts']['bar_thickness_mm']:.0f} mm",
                  f"continuous force {b['cheap']['continuous_force_N']:.2f} N"):
        assert typed in text, typed


def test_performance_capstan_build_is_the_bench_json():
    """docs/performance.md's capstan build figures are those of docs/bench/capstan.json."""
    import json

    rec = json.loads((ROOT / "docs" / "bench" / "capstan.json").read_text())
    c = rec["capstan"]
    text = (ROOT / "docs" / "performance.md").read_text(encoding="utf-8")
    assert rec["command"] == "hapticad bench --only capstan"
    assert f"{c['capstan_cold_s']:.2f} s against {c['direct_cold_s']:.2f} s" in text
    assert f"a ratio of\n{c['ratio']:.2f} (goal" in text or f"a ratio of {c['ratio']:.2f} (goal" in text
    assert c["ratio"] == c["capstan_cold_s"] / c["direct_cold_s"]


def test_performance_optimize_dask_is_the_bench_json():
    """docs/bench/optimize.json (the table of docs/performance.md is generated from it): the
    command the page names, one run of 1 and 2 workers, and its ratio of their medians."""
    import json
    import statistics

    rec = json.loads((ROOT / "docs" / "bench" / "optimize.json").read_text())
    o = rec["optimize"]
    assert rec["command"] == "hapticad bench --only optimize"
    pts = {p["method"]: p for p in o["points"]}
    for w, key in (("1 worker", "trials_per_s_1"), ("2 workers", "trials_per_s_2")):
        assert len(pts[w]["trials_per_s_runs"]) == o["repeats"]
        assert o[key] == statistics.median(pts[w]["trials_per_s_runs"])
    assert o["ratio_2_workers"] == o["trials_per_s_2"] / o["trials_per_s_1"]
    assert "<!-- generated: goals docs/bench/optimize.json -->" in (ROOT / "docs" / "performance.md").read_text()
