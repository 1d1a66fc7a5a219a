"""Numbers typed in the prose of docs/ pages that come from a run or from the code, recomputed
now (or read from the committed JSON the page names) at the printed rounding, so the page
cannot drift from them (issue 34 §4). Each test parses the number from the page; no CAD build
(kinematics, catalogs and committed JSON only), well under a second each."""

from __future__ import annotations

import json
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def page(name: str) -> str:
    """The page's text with its line breaks folded to single spaces."""
    return " ".join((ROOT / name).read_text(encoding="utf-8").split())


def number(text: str, pattern: str) -> float:
    """The one float the regex ``pattern`` captures in ``text`` (its first group)."""
    found = re.findall(pattern, text)
    assert len(found) == 1, f"{pattern!r} found {len(found)} times"
    return float(found[0])


def test_simulation_default_substep_is_within_its_stated_error_of_mujoco():
    """docs/simulation.md: the reduced model's default sub-step (cad/sim/wall.py SUBSTEP_MAX_S)
    is the bench's sub-step whose K_max lies within the stated error of MuJoCo's at its finest
    step (docs/bench/bench_wall.json, the committed run the page names)."""
    from cad.sim.wall import SUBSTEP_MAX_S
    text = page("docs/simulation.md")
    sub_us = number(text, r"default (\d+) µs sub-step is the one the bench found within")
    err_pct = number(text, r"sub-step is the one the bench found within (\d+) % of MuJoCo at its finest step")
    assert sub_us == round(SUBSTEP_MAX_S * 1e6)
    sa = json.loads((ROOT / "docs/bench/bench_wall.json").read_text())["wall"]["speed_accuracy"]
    assert sa["reference"] == "mujoco model at its finest step"
    row, = (r for r in sa["reduced"] if abs(r["substep_s"] - SUBSTEP_MAX_S) < 1e-12)
    ref = min(sa["mujoco"], key=lambda r: r["step_s"])["K_max_N_per_m"]
    rel = abs(row["K_max_N_per_m"] / ref - 1)
    assert abs(rel - abs(row["rel_error"])) < 1e-12
    assert rel < err_pct / 100


def test_ordering_allowances_are_the_ones_the_stock_column_adds():
    """docs/ordering.md's allowance column against the constants cad.export.order adds
    (cad/tolerances.py STOCK_*, the radius mesh deflection) and its mass rounding rule."""
    from cad import tolerances as tol
    from cad.export import order
    text = page("docs/ordering.md")
    assert number(text, r"\| (\d+) mm per side on W, L;") == tol.STOCK_PLATE_MARGIN_MM
    mesh = re.findall(r"mesh at ([\d.]+) mm \+ ([\d.]+) mm, so never below the solid\), \+ (\d+) mm; L \+ (\d+) mm",
                      text)
    assert [tuple(map(float, m)) for m in mesh] == [(order.RADIUS_MESH_DEFLECTION_MM, order.RADIUS_MESH_DEFLECTION_MM,
                                                     tol.STOCK_ROD_DIAMETER_ALLOWANCE_MM, tol.STOCK_LENGTH_ALLOWANCE_MM)]
    assert number(text, r"the exact radii of the cylinders about the part's axis; L \+ (\d+) mm") == \
        tol.STOCK_LENGTH_ALLOWANCE_MM
    assert number(text, r"\| (\d+) mm per side \|") == tol.STOCK_BLOCK_MARGIN_MM
    step, below = re.findall(r"whole grams, ([\d.]+) g below (\d+) g", text)[0]
    limit = float(below)
    assert order._grams(limit - 0.06) == f"{limit - 0.06:.1f}" and float(step) == 0.1
    assert order._grams(limit + 0.4) == f"{limit:.0f}"


def table_row(name: str, first_cell: str) -> list[str]:
    """The cells of the one table row of page ``name`` whose first cell starts with ``first_cell``."""
    rows = [[c.strip() for c in line.strip().strip("|").split("|")]
            for line in (ROOT / name).read_text(encoding="utf-8").splitlines() if line.startswith("|")]
    found = [r for r in rows if r[0].startswith(first_cell)]
    assert len(found) == 1, f"{name}: {len(found)} rows start with {first_cell!r}"
    return found[0]


def _pct(a: float, b: float) -> str:
    """``b`` against ``a`` as the page prints it (``+0.3 %``, ``−0.2 %``; a real minus sign)."""
    return f"{100 * (b / a - 1):+.{1 if abs(b / a - 1) >= 1e-3 else 2}f} %".replace("-", "−")


def test_datasheet_structure_proofs_table_is_what_the_proofs_compute():
    """docs/datasheet.md's "Independent proofs" table: each device figure, its independent value
    and their difference at the printed rounding, recomputed by the proofs' own functions
    (tests/unit/structure/test_structure_proofs.py: the force method, unit loads and statics by
    hand, none calling cad.structure.frame) and the device model now."""
    import numpy as np

    from cad.kinematics.metrics import path_frame
    from tests.unit.structure import test_structure_proofs as proofs
    dev = proofs.hoeken_device_at_mid_stroke()
    d, el, rho, end_r, pose, st = dev
    cz_m_per_N, f1_Hz = proofs._hoeken_out_of_plane(d, el, rho, end_r, pose)
    ex = np.asarray(path_frame(d.linkage, d.phi1_min_rad, d.phi1_max_rad).x_hat, float)
    cx_um = proofs._hoeken_inplane_compliance_m_per_N(d, el, end_r, pose, ex) * 1e6
    stress_dev, stress_hand = proofs.hoeken_beam_stress_MPa(dev)
    name = "docs/datasheet.md"
    mode = table_row(name, "Hoeken first mode, crank held")
    assert f"{1e3 * proofs.KNOB_KG:g} g knob at P" in mode[0]
    assert mode[1] == f"{st['first_mode_Hz']:.2f} Hz" and mode[3] == f"{f1_Hz:.2f} Hz, {_pct(st['first_mode_Hz'], f1_Hz)}"
    z = table_row(name, "Hoeken handle compliance out of plane")
    cz = st["compliance_um_per_N"]["z"]
    assert z[1] == f"{cz:.2f} um/N" and z[3] == f"{cz_m_per_N * 1e6:.2f} um/N, {_pct(cz, cz_m_per_N * 1e6)}"
    x = table_row(name, "Hoeken handle compliance along the path")
    cx = st["compliance_um_per_N"]["x"]
    assert x[1] == f"{cx:.3f} um/N" and x[3] == f"{cx_um:.3f} um/N, {_pct(cx, cx_um)}"
    s = table_row(name, "Hoeken peak stress at")
    assert f"= {d.force_N:g} N" in s[0]
    assert s[1] == f"{stress_dev:.3f} MPa" and s[3] == f"{stress_hand:.3f} MPa, {_pct(stress_dev, stress_hand)}"
    fb, *_, pst = proofs._pantograph_home()
    home = pst["per_pose"]["home"]
    c = table_row(name, "5-bar at home: handle compliance x / y")
    assert c[1] == f"{home['compliance_um_per_N']['x']:.3f} / {home['compliance_um_per_N']['y']:.3f} um/N"
    p = table_row(name, "5-bar at home: peak in-plane stress at")
    assert p[0].endswith(f"at {float(fb.actuators['force_max_N']):g} N")
    assert p[1] == f"{home['max_stress_in_plane_MPa']:.3f} MPa"


def _continuous_force_N(design_path: Path) -> tuple[float, float]:
    """(continuous force at the handle, force_N) of a four-bar design: the motor's continuous
    torque over the largest lever max |dx/dphi1| of the handle along the path, the lever a
    central finite difference of the solved coupler point (independent of the datasheet's
    analytic Jacobian; tests/docs/test_readme_numbers.py does the same for README)."""
    import numpy as np

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
    return MOTORS[d.parts.motor].torque_continuous_mNm * 1e-3 / lever_m.max(), float(d.force_N)


def test_datasheet_continuous_force_warnings_match_the_designs():
    """docs/datasheet.md: the Hoeken's continuous-force warning and the hoeken_pla case's row
    (tests/cases/silent-limits) state the force each design's motor gives through its lever,
    and the design's force_N as the limit."""
    text = page("docs/datasheet.md")
    f, lim = _continuous_force_N(ROOT / "designs/hoeken.toml")
    assert f"It warns once: `continuous force at the handle = {f:.2f} N, limit >= {lim:g} N" in text
    f, lim = _continuous_force_N(ROOT / "tests/cases/silent-limits/hoeken_pla.toml")
    assert f"| `hoeken_pla.toml` (every made part PLA) | continuous force {f:.2f} N < {lim:g} N;" in text
    f, lim = _continuous_force_N(ROOT / "tests/cases/silent-limits/cheb80.toml")
    assert f < 1.0 and f"(Chebyshev, 80 mm, {lim:g} N) | continuous force < 1 N (limit {lim:g} N);" in text


def test_datasheet_motor_sentences_match_the_catalog():
    """docs/datasheet.md's motor paragraph: the RE 35 winding's Kt, R, continuous torque and its
    stall torque Kt U / R, and the RE 40's Kt, as cad/data/catalog.py states them (the sources
    are named there and walked by tests/unit/data/test_catalog_sources.py)."""
    from cad.data.catalog import MOTORS
    text = page("docs/datasheet.md")
    re35, re40 = MOTORS["maxon-re35"], MOTORS["maxon-re40"]
    volts = number(text, r"RE 35: a (\d+) V winding")
    assert f"{volts:g} V winding" in re35.winding
    assert (f"(Kt {re35.torque_constant_mNm_per_A:g} mN·m/A, R {re35.terminal_resistance_ohm:g} Ω, "
            f"{re35.torque_continuous_mNm:g} mN·m continuous") in text
    stall = re35.torque_constant_mNm_per_A * volts / re35.terminal_resistance_ohm
    assert abs(stall - re35.stall_torque_mNm) < 1e-9
    assert f"its stall torque (Kt·U/R = {stall:.0f} mN·m" in text
    assert f"RE 35's {re35.torque_continuous_mNm:g} / {re35.torque_peak_mNm:g} mN m" in text
    order, v40 = re.findall(r"RE 40: order number (\d+) \((\d+) V\)", text)[0]
    assert f"order number {order}, {v40} V" in re40.winding
    assert f"Kt {re40.torque_constant_mNm_per_A:g} mN·m/A" in text


def test_datasheet_five_bar_forces_match_the_committed_datasheet_run():
    """docs/datasheet.md: the bundled 5-bar's continuous and peak force in every direction and
    the GII normalisation's force, against the committed capture docs/datasheets/pantograph.json
    (the run the page's structure table renders; a regression pin of our own run)."""
    rows = {r["key"]: r for r in json.loads((ROOT / "docs/datasheets/pantograph.json").read_text())
            ["datasheet"]["rows"]}
    text = page("docs/datasheet.md")
    assert (f"(the bundled 5-bar: {rows['continuous_force_N']['value']:.3f} N continuous, "
            f"{rows['peak_force_N']['value']:.2f} N peak from the") in text
    assert f"`[actuators] torque_max_Nm = 1` gives {rows['force_any_dir_N']['value']:.2f} N" in text


PANTOGRAPH_PAGE = "docs/families/pantograph-powermouse.md"


def _capture_rows(name: str) -> dict[str, dict]:
    return {r["key"]: r for r in json.loads((ROOT / f"docs/datasheets/{name}.json").read_text())["datasheet"]["rows"]}


def test_pantograph_forces_match_the_committed_datasheet_runs():
    """The 5-bar's and the haptic mouse's continuous / peak force in every direction, and the 5-bar's
    force_max_N that the continuous force misses, against the committed captures
    docs/datasheets/pantograph.json and haptic_mouse.json (regression pins of our own runs)."""
    text = page(PANTOGRAPH_PAGE)
    five, mouse = _capture_rows("pantograph"), _capture_rows("haptic_mouse")
    assert (f"(the bundled 5-bar with the RE 35: {five['continuous_force_N']['value']:.3f} N continuous, "
            f"{five['peak_force_N']['value']:.2f} N peak; the haptic mouse "
            f"{mouse['continuous_force_N']['value']:.3f} N / {mouse['peak_force_N']['value']:.2f} N)") in text
    lim = five["continuous_force_N"]["limit"]["value"]
    assert five["continuous_force_N"]["verdict"] == "miss"
    assert (f"the bundled 5-bar asks for {lim:g} N and its two RE 35 motors give "
            f"{five['continuous_force_N']['value']:.3f} N in the worst direction") in text


def test_powermouse_flotor_figures_match_the_committed_datasheet_run():
    """The flotor's mass, peak acceleration and the motion check's touching clearance, against
    docs/datasheets/powermouse.json (the page names it; a regression pin of our own run)."""
    text = page(PANTOGRAPH_PAGE)
    pm = _capture_rows("powermouse")
    assert (f"the flotor weighs {pm['flotor_mass_g']['value']:.1f} g (peak acceleration "
            f"{pm['peak_acceleration_G']['value']:.2f} G;") in text
    assert f"The motion check finds {pm['min_clearance_mm']['value']:g} mm (touching)" in text


def test_powermouse_corner_holes_are_the_excursion_bound():
    """The PowerMouse's corner-hole sentences: the stem's and the post's largest distance off
    the diagonal (cad.actuators.powermouse.diagonal_excursion_mm), the hole sizes they give
    with the margin, the advised limits rounded inwards, the bundled corner hole and the coil
    gap = motion range, all from the bundled design now (pure numpy, no CAD)."""
    import math

    from cad.design import load_design
    from cad.families.powermouse import parts as pp
    from cad.families.powermouse.build import actuator_gap_mm
    d = load_design(ROOT / "designs/powermouse.toml")
    g = pp.geometry(d, actuator_gap_mm(d))
    text = page(PANTOGRAPH_PAGE)
    Ho = g.housing_inner_half_mm + g.housing_wall_mm
    stem, post = g.excursion_mm(Ho * math.sqrt(3.0)), g.excursion_mm(g.flotor_edge_mm / 2 * math.sqrt(3.0))
    m = pp.HOLE_MARGIN_MM
    assert f"move the handle stem **{stem:.2f} mm** off the axis" in text
    assert f"and the post **{post:.2f} mm** off the axis" in text
    assert f"the stem + 2 × ({stem:.2f} + {m:g}) mm = {g.housing_hole_mm:.1f} mm" in text
    assert g.handle_diameter_mm + 2 * (stem + m) == g.housing_hole_mm
    room = 2 * (g._coil_distance_mm() - pp.COIL_WALL_MM)
    assert (f"the post + 2 × ({post:.2f} + {m:g}) = {pp._up(g.corner_hole_min_mm):.2f} mm and "
            f"≤ {pp._down(room):.2f} mm") in text
    assert f"The bundled design has **{g.corner_hole_mm:g} mm**." in text
    assert f"`handle.diameter_mm` ≤ {pp._down(room - 2 * pp.HANDLE_BOSS_WALL_MM):.1f})" in text
    gap = (g.gap_mm - g.coil_width_mm) / 2
    assert f"nominal coil–magnet gap is {gap:.1f} mm = `motion.range_mm`" in text and gap == g.range_mm
    assert f"±{g.range_mm:g} mm / ±{g.range_deg:g}° range" in text


def test_pen_numbers_table_is_the_committed_datasheet_run():
    """docs/families/pen.md's "Numbers" table, our column: moving mass, effective masses and
    inertias at home, force in every direction (GII normalisation, continuous, peak), against
    docs/datasheets/haptic_pen.json (the run the page names; a regression pin of our own run).
    The paper's column is the isotropy paper's Table 3 (ledger `paper:`)."""
    from cad.data.catalog import MOTORS
    rows = _capture_rows("haptic_pen")
    v = {k: r["value"] for k, r in rows.items()}

    def ours(first_cell: str) -> str:
        return table_row("docs/families/pen.md", first_cell)[1]

    assert ours("moving mass").startswith(f"{v['moving_mass_g']:.0f} g")
    assert ours("effective mass at home, x") == f"{v['effective_mass_home.mass_x_g_apparent']:.0f} g (apparent)"
    assert ours("effective mass at home, y") == f"{v['effective_mass_home.mass_y_g_diag']:.0f} g"
    assert ours("effective mass at home, z") == f"{v['effective_mass_home.mass_z_g_diag']:.0f} g"
    assert ours("effective inertia at home") == (f"{v['effective_mass_home.inertia_yaw_g_cm2_apparent']:.0f} / "
                                                 f"{v['effective_mass_home.inertia_pitch_g_cm2_apparent']:.0f} g cm²")
    assert ours("force in every direction") == f"{v['force_any_dir_N']:.1f} N"
    assert ours("continuous force in every direction") == f"{v['continuous_force_N']:.2f} N"
    assert ours("peak force in every direction") == f"{v['peak_force_N']:.1f} N"
    re40, re35 = MOTORS["maxon-re40"], MOTORS["maxon-re35"]
    assert (f"RE 40 waists {re40.torque_continuous_mNm:g} mN m, RE 35 shoulders {re35.torque_continuous_mNm:g} mN m"
            in table_row("docs/families/pen.md", "continuous force in every direction")[0])
    assert (f"(stall torques {re40.stall_torque_mNm:g} / {re35.stall_torque_mNm:g} mN m)"
            in table_row("docs/families/pen.md", "peak force in every direction")[0])
