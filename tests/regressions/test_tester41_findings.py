"""Faults an independent trial of issue 32 found (tester41): ``parts.process = "printed"`` with
metal parts said nothing, the pantographs' eq (25) row printed its two sides as a range over
the workspace (inverted when the encoder is coarse), and a pantograph's ``[motor]`` table was
named by the catalog key it replaces in the datasheet and in report.json."""

from __future__ import annotations

import csv
import json
import re
from pathlib import Path

import pytest

from tests.cli_helpers import hapticad

ROOT = Path(__file__).resolve().parents[2]


def _printed_warning(err: str) -> str:
    lines = [ln for ln in err.splitlines() if "are not in a printing filament" in ln]
    assert len(lines) == 1, err
    return lines[0]


def test_printed_process_names_the_metal_parts_the_bom_machines(tmp_path):
    """The reference is the written BOM: every part group the warning names is made and not
    FDM printed there, and every FDM-printed line is of a filament."""
    text = (ROOT / "designs" / "hoeken_printed.toml").read_text()
    d = tmp_path / "d.toml"
    d.write_text(text.replace('bar_material = "pla"', 'bar_material = "aluminium-6061"', 1)
                 .replace('hub_material = "pla"', 'hub_material = "aluminium-6061"', 1))
    code, _, err = hapticad("build", str(d), "--fidelity", "preview", "--formats", "step",
                            "--out", str(tmp_path / "o"))
    assert code == 0, err
    line = _printed_warning(err)
    named = dict(re.findall(r"([a-z ,]+?) \(([a-z0-9-]+)\)", line.split(": ", 2)[2].split(" are not")[0]))
    assert {k.strip(", ") for k in named} == {"crank, coupler, rocker", "hub"}
    assert set(named.values()) == {"aluminium-6061"}
    with open(tmp_path / "o" / "bom.csv", encoding="utf-8") as fh:
        rows = {r["part"]: r for r in csv.DictReader(fh)}
    for part in ("crank", "coupler", "rocker", "crank_hub"):
        assert rows[part]["material"] == "aluminium-6061"
        assert not rows[part]["process"].startswith("FDM"), rows[part]
    printed = [r for r in rows.values() if r["process"].startswith("FDM")]
    assert printed and all(r["material"] == "pla" for r in printed)


def test_printed_process_all_filament_adds_no_such_warning():
    code, _, err = hapticad("check", str(ROOT / "designs" / "hoeken_printed.toml"))
    assert code in (0, 1), err
    assert "are not in a printing filament" not in err


def test_machined_process_with_metal_parts_adds_no_such_warning():
    code, _, err = hapticad("check", str(ROOT / "designs" / "hoeken.toml"))
    assert code in (0, 1), err
    assert "are not in a printing filament" not in err


FIVEBAR = """name = "fivebar-rect"
[mechanism]
family = "pantograph"
base_mm = 75.0
proximal_mm = 125.0
distal_mm = 175.0
[workspace]
size_mm = [120.0, 60.0]
center_mm = [0.0, 200.0]
grid = 11
[actuators]
torque_max_Nm = 1.0
force_max_N = 1.0
[firmware]
encoder_counts_per_rev = {counts}
"""


def _fivebar_worst_step_m(counts: int, size_mm=(120.0, 60.0)) -> float:
    """Worst encoder step at the handle over the 11 x 11 grid: sigma_max(dE/dq) 2 pi / counts,
    dE/dq from a circle-intersection inverse kinematics by central differences (elbows out),
    written here independently of cad/."""
    import numpy as np

    a, l2, l3 = 75.0, 125.0, 175.0

    def ik(E):
        q = []
        for s, bx in ((1, -a / 2), (-1, a / 2)):
            d = E - np.array([bx, 0.0])
            r = np.hypot(*d)
            q.append(np.arctan2(d[1], d[0]) + s * np.arccos((l2**2 + r**2 - l3**2) / (2 * l2 * r)))
        return np.array(q)

    worst, h = 0.0, 1e-6
    for x in np.linspace(-size_mm[0] / 2, size_mm[0] / 2, 11):
        for y in np.linspace(200.0 - size_mm[1] / 2, 200.0 + size_mm[1] / 2, 11):
            E = np.array([x, y])
            dq = np.column_stack([(ik(E + e) - ik(E - e)) / (2 * h) for e in (np.array([h, 0]), np.array([0, h]))])
            worst = max(worst, np.linalg.svd(np.linalg.inv(dq), compute_uv=False)[0])
    return worst * 1e-3 * 2 * np.pi / counts


def _eq25_hand(step_m: float) -> tuple[float, float]:
    """Hoeken paper eq (25) with its §III.B.4 numbers: Fv 0.12, Fs 0.083, Te 0.33 ms, xdot 0.04."""
    return 2 * 0.12 / 0.00033, 2 * (0.083 + 0.12 * 0.04) / (step_m + 0.04 * 0.00033)


def _build_fivebar(tmp_path, counts: int):
    d = tmp_path / f"p{counts}.toml"
    d.write_text(FIVEBAR.format(counts=counts))
    out = tmp_path / f"o{counts}"
    code, _, err = hapticad("build", str(d), "--fidelity", "preview", "--formats", "firmware", "--out", str(out))
    assert code == 0, err
    rep = json.loads((out / "report.json").read_text())
    row = next(r for r in rep["datasheet"]["rows"] if r["key"] == "eq25_K_max_N_per_m")
    ino = (out / "firmware" / "wall_example" / "wall_example.ino").read_text()
    return row, ino, (out / "report.md").read_text()


def test_fivebar_eq25_row_with_a_coarse_encoder_says_its_range_is_empty(tmp_path):
    k_min, k_max = _eq25_hand(_fivebar_worst_step_m(1024))
    assert k_max < k_min  # 199 N/m against 727 N/m: no stiffness meets both sides
    row, ino, md = _build_fivebar(tmp_path, 1024)
    assert row["value"] == pytest.approx(k_max, rel=1e-6)
    assert row["min"] is None and row["max"] is None  # not a range over the workspace
    assert f"eq (25) range empty: its upper side {k_max:.4g} N/m is below its lower side 2 Fv / Te = {k_min:.4g} N/m" in row["model"]
    assert f" * eq (25) range empty: its upper side {k_max:.4g} N/m" in ino
    assert f"({k_min:.4g} .. {k_max:.4g})" not in md and f"{k_min:.4g} .. {k_max:.4g}" not in ino


def test_fivebar_eq25_row_with_a_fine_encoder_states_both_sides(tmp_path):
    k_min, k_max = _eq25_hand(_fivebar_worst_step_m(4000))
    assert k_max > k_min
    row, ino, _ = _build_fivebar(tmp_path, 4000)
    assert row["value"] == pytest.approx(k_max, rel=1e-6)
    assert f"eq (25) range {k_min:.4g} .. {k_max:.4g} N/m" in row["model"]
    assert f" * eq (25) range {k_min:.4g} .. {k_max:.4g} N/m at Te = 0.00033 s." in ino


MOTOR_TABLE = """[motor]
name = "bench motor X"
source = "a made-up data sheet (test)"
torque_constant_mNm_per_A = 50.0
terminal_resistance_ohm = 2.0
torque_continuous_mNm = 150.0
torque_peak_mNm = 600.0
stall_torque_mNm = 1200.0
current_continuous_A = 3.1
no_load_current_mA = 100.0
rotor_inertia_g_cm2 = 40.0
mass_g = 250.0
"""


def test_fivebar_motor_table_is_named_as_the_bom_orders_it(tmp_path):
    """The datasheet's force rows and report.json's ``motor`` name the motor of the BOM's motor
    line (the ``[motor]`` table), not the catalog key whose mount it keeps; the force itself is
    the table's 150 mN m over sigma_max(dE/dq) worst on the grid (independent kinematics)."""
    d = tmp_path / "m.toml"
    d.write_text(FIVEBAR.format(counts=4000) + MOTOR_TABLE)
    out = tmp_path / "o"
    code, _, err = hapticad("build", str(d), "--fidelity", "preview", "--formats", "step", "--out", str(out))
    assert code == 0, err
    with open(out / "bom.csv", encoding="utf-8") as fh:
        motor_line = next(r for r in csv.DictReader(fh) if r["group"] == "motors")
    assert motor_line["designation"] == "bench motor X"
    rep = json.loads((out / "report.json").read_text())
    assert rep["motor"]["name"] == motor_line["designation"]
    assert "[motor] table" in rep["motor"]["source"]
    rows = {r["key"]: r for r in rep["datasheet"]["rows"]}
    sigma_max_m = _fivebar_worst_step_m(4000) * 4000 / (2 * 3.141592653589793)
    assert rows["continuous_force_N"]["value"] == pytest.approx(0.150 / sigma_max_m, rel=1e-6)
    for key in ("continuous_force_N", "peak_force_N"):
        model = rows[key]["model"]
        assert "bench motor X" in model, model
        assert not re.search(r"orders: maxon-re35 \(", model), model


def test_firmware_page_numbers_of_an_empty_eq25_range():
    """docs/firmware.md: the bundled 5-bar (100 mm square) with a 1024-count encoder has eq (25)'s
    upper side at 196 N/m, below its lower side 727 N/m (closed form with independent kinematics);
    the datasheet's row function gives the same figure and says the range is empty."""
    from cad.families.pantograph.datasheet import k_max_row

    text = (ROOT / "docs" / "firmware.md").read_text()
    step = _fivebar_worst_step_m(1024, (100.0, 100.0))
    k_min, k_max = _eq25_hand(step)
    assert f"{k_max:.0f} N/m" == "196 N/m" and "196 N/m" in text
    assert f"{k_min:.0f} N/m" == "727 N/m" and "727 N/m" in text
    row = k_max_row(step)
    assert row["value"] == pytest.approx(k_max, rel=1e-12)
    assert "eq (25) range empty" in row["model"]
