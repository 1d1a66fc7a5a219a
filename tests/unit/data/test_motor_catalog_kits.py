"""The motors of the open haptic kits (issue 35 §2): each constant from a public source read at a
fixed commit, checked against maxon's own relations between a sheet's values (maxon 'Technology -
short and to the point': stall torque = Kt U_N / R, nominal current = T_N / Kt + I0; speed constant
= 30000 / (pi Kt); mechanical time constant = R J / Kt^2), and a motor whose sources state only
some constants refused until the design's [motor] gives the rest."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from cad.data.catalog import MOTOR_BUILD_FIELDS, MOTOR_DIMENSION_FIELDS, MOTORS, get_motor
from cad.design import parse_design
from cad.design.fields import load_toml
from cad.errors import DesignError

HOEKEN = Path(__file__).resolve().parents[3] / "designs" / "hoeken.toml"


def test_dcx22l_values_are_one_winding():
    """The DCX 22 L file's values (mattchg/ELEC441 MotorSpecs.m): 9 V nominal voltage, stall
    current 53.4 A, speed constant 1370 rpm/V are the file's own numbers not stored in the
    catalog; the relations tie the stored ones to them."""
    m = get_motor("maxon-dcx22l")
    U_N, I_stall, k_n = 9.0, 53.4, 1370.0
    assert m.torque_constant_mNm_per_A * U_N / m.terminal_resistance_ohm == pytest.approx(
        m.stall_torque_mNm, rel=0.005)
    assert U_N / m.terminal_resistance_ohm == pytest.approx(I_stall, rel=0.005)
    assert m.torque_continuous_mNm / m.torque_constant_mNm_per_A + m.no_load_current_mA * 1e-3 == (
        pytest.approx(m.current_continuous_A, rel=0.002))
    assert 30000.0 / (math.pi * m.torque_constant_mNm_per_A) == pytest.approx(k_n, rel=0.005)
    assert m.missing_build_fields() == ()


def test_ec45flat_values_are_one_winding():
    """vhsabino/MATLAB constants.m, 339285: speed constant 380 rpm/V and mechanical time
    constant 9.92 ms (the file's, not stored) against the stored Kt, R, J."""
    m = get_motor("maxon-ec45flat")
    kt = m.torque_constant_mNm_per_A * 1e-3
    assert 30000.0 / (math.pi * m.torque_constant_mNm_per_A) == pytest.approx(380.0, rel=0.005)
    assert m.terminal_resistance_ohm * m.rotor_inertia_kg_m2 / kt**2 == pytest.approx(9.92e-3, rel=0.005)


def test_re25_values_are_one_winding():
    """oliv5/apbteam motor.m, 118752: speed constant 407 rpm/V and nominal voltage 24 V (the
    file's, not stored) against the stored Kt (maxon: k_n k_M = 30000 / pi); the stall torque
    Kt U_N / R = 242 mN m is not stated there, so none is stored and the build asks [motor]."""
    m = get_motor("maxon-re25")
    assert 30000.0 / (math.pi * m.torque_constant_mNm_per_A) == pytest.approx(407.0, rel=0.005)
    assert m.rotor_inertia_kg_m2 == pytest.approx(10.3 / 1000 / 10000)
    assert set(m.missing_build_fields()) == {"torque_continuous_mNm", "torque_peak_mNm",
                                             "current_continuous_A", "mass_kg"}
    assert m.stall_torque_mNm is None and m.no_load_current_mA is None


@pytest.mark.parametrize("key", ["maxon-dcx22l", "maxon-re30", "maxon-ec45flat", "maxon-re25"])
def test_kit_motor_sources_and_dimensions(key):
    """Every stated constant names a repository file at a commit; every mounting dimension that
    no drawing read states says where its number comes from and reaches the BOM line."""
    m = get_motor(key)
    for f in MOTOR_BUILD_FIELDS:
        if getattr(m, f) is not None and not m.is_unverified(f):
            assert "commit" in m.source_of(f), (key, f)
    notes = dict(m.dimension_notes)
    assert set(notes) <= set(MOTOR_DIMENSION_FIELDS)
    assert notes and all(notes.values())
    assert "unverified mount dimensions" in m.bom_description()
    # the mount: the bolts clear the centring pilot, the pilot fits in the body
    hole = float(m.bolt_size[1:].split("-")[0])
    assert m.pilot_diameter_mm / 2 < m.bolt_circle_mm / 2 - hole / 2 < m.body_diameter_mm / 2


def _hoeken_with(motor: str, table: dict | None = None):
    raw = load_toml(HOEKEN)
    raw["parts"] = {**raw.get("parts", {}), "motor": motor}
    if table is not None:
        raw["motor"] = table
    return parse_design(raw, str(HOEKEN))


@pytest.mark.parametrize("key", ["maxon-re30", "maxon-ec45flat", "maxon-re25"])
def test_partial_motor_refused_then_completed_by_motor_table(key):
    with pytest.raises(DesignError) as e:
        _hoeken_with(key)
    assert e.value.field == "parts.motor" and "mass_g" in str(e.value) and "torque_continuous_mNm" in str(e.value)
    # the user's sheet completes it (values here: a test's, not a data sheet's)
    kt = get_motor(key).torque_constant_mNm_per_A
    table = {"source": "test", "torque_continuous_mNm": kt * 3.0, "current_continuous_A": 3.0,
             "torque_peak_mNm": 500.0, "mass_g": 200.0, "rotor_inertia_g_cm2": 30.0}
    d = _hoeken_with(key, table)
    assert d.parts.motor == key


def test_existing_motors_still_complete():
    for k in ("maxon-re35", "maxon-re40", "maxon-dcx22l"):
        assert MOTORS[k].missing_build_fields() == ()


@pytest.mark.slow
def test_hoeken_builds_on_the_dcx22l_and_its_force_is_kt_i_through_the_linkage(tmp_path):
    """hoeken.toml with ``parts.motor = "maxon-dcx22l"`` builds; its datasheet's continuous force
    is the sheet's Kt (I_N - I0) (maxon: T_N = Kt (I_N - I0)) over the largest |dx/dphi1| of the
    stroke, the latter by central differences of the coupler point (Hoeken paper eqs 3-12 through
    :func:`cad.kinematics.fourbar.solve`, not the datasheet's Jacobian); the force per ampere is
    Kt over the same lever; the BOM orders the DCX with its unverified dimensions named."""
    import numpy as np

    from cad.api import build_design
    from cad.kinematics.fourbar import solve

    d = _hoeken_with("maxon-dcx22l")
    rep = build_design(d, tmp_path, formats=("step",))
    m = get_motor("maxon-dcx22l")
    fb = d.linkage
    phi = np.linspace(d.phi1_min_rad, d.phi1_max_rad, 4001)
    ends = solve(fb, np.array([d.phi1_min_rad, d.phi1_max_rad])).P_mm
    u = (ends[1] - ends[0]) / np.linalg.norm(ends[1] - ends[0])  # the path frame's x
    h = 1e-6
    dP = (solve(fb, phi + h).P_mm - solve(fb, phi - h).P_mm) / (2 * h)
    lever_m = np.abs(dP @ u).max() * 1e-3
    rows = {r["key"]: r for r in rep["datasheet"]["rows"]}
    kt = m.torque_constant_mNm_per_A * 1e-3
    i_torque = m.current_continuous_A - m.no_load_current_mA * 1e-3
    assert rows["continuous_force_N"]["value"] == pytest.approx(kt * i_torque / lever_m, rel=2e-3)
    assert rows["force_per_ampere_N_per_A"]["value"] == pytest.approx(kt / lever_m, rel=1e-4)
    assert any("DCX 22 L" in str(line) and "unverified mount dimensions" in str(line)
               for line in rep["bom"]), rep["bom"]
