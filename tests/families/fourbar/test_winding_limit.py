"""The winding-temperature row has a verdict: <= 100 K (125 C winding at 25 C ambient, the
maxon data sheets' thermal data) where the motor gives its thermal resistances and the design
holds force_N continuously. Reference: dT = I^2 R (Rth_winding + Rth_housing), I = F |dx/dphi1|
/ Kt, computed here by hand from the catalog constants and the four-bar's own lever arm."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from cad.data.catalog import get_motor
from cad.datasheet import judge
from cad.design import load_design
from cad.families.fourbar.datasheet import lever, thermal_limit, thermal_rows

DESIGNS = Path(__file__).resolve().parents[3] / "designs"


def _rise_by_hand_K(design) -> float:
    m = get_motor(design.parts.motor)
    _, Jx, *_ = lever(design)
    I_A = design.force_N * np.abs(Jx).max() / (m.torque_constant_mNm_per_A * 1e-3)
    return I_A**2 * m.terminal_resistance_ohm * (m.thermal_resistance_housing_K_per_W
                                                 + m.thermal_resistance_winding_K_per_W)


def _judged(design):
    m = get_motor(design.parts.motor)
    _, Jx, *_ = lever(design)
    rows = thermal_rows(design, m, Jx)
    warnings = judge(rows, thermal_limit(design, rows))
    return rows[0], warnings


def test_the_re40_light_hoeken_meets_the_winding_limit():
    d = load_design(DESIGNS / "hoeken_light.toml")
    r, warnings = _judged(d)
    assert r["value"] == pytest.approx(_rise_by_hand_K(d), rel=1e-9)
    assert r["verdict"] == "ok" and r["limit"]["value"] == 100.0 and not warnings


def test_twice_the_force_overheats_the_winding_and_says_so():
    d = load_design(DESIGNS / "hoeken_light.toml")
    hot = dataclasses.replace(d, force_N=2 * d.force_N)
    r, warnings = _judged(hot)
    assert r["value"] == pytest.approx(4 * _rise_by_hand_K(d), rel=1e-9) and r["value"] > 100
    assert r["verdict"] == "miss" and len(warnings) == 1 and "winding" in warnings[0]


def test_no_limit_for_peak_basis_or_a_motor_without_thermal_data():
    d = load_design(DESIGNS / "hoeken_light.toml")
    r, _ = _judged(dataclasses.replace(d, force_N=2 * d.force_N, force_basis="peak"))
    assert r["verdict"] == "info" and r["limit"] is None
    r, _ = _judged(load_design(DESIGNS / "hoeken.toml"))  # RE 35: no thermal resistances read
    assert r["value"] is None and r["verdict"] == "info"
