"""A [motor] table whose torques contradict each other is refused in one line (exit 2): the
continuous and the peak torque are at most the stall torque (the winding's torque at nominal
voltage, maxon data sheet definitions); for a table without ``name`` (corrections to the
catalog winding) the catalog value fills the side not given, a named table is its own motor."""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_helpers import hapticad

from cad.data.catalog import get_motor

HOEKEN = Path(__file__).resolve().parents[3] / "designs" / "hoeken.toml"


@pytest.mark.parametrize(("table", "field"), [
    ('name = "m"\ntorque_peak_mNm = 1500.0\nstall_torque_mNm = 800.0', "motor.torque_peak_mNm"),
    ("stall_torque_mNm = 0.5", "motor.stall_torque_mNm"),  # a N m value: below the RE 35's 97.2 continuous
    ("torque_peak_mNm = 5000.0", "motor.torque_peak_mNm"),  # above the RE 35's stall torque
])
def test_contradicting_torques_are_refused_in_one_line(tmp_path, table, field):
    p = tmp_path / "d.toml"
    p.write_text(HOEKEN.read_text() + f"\n[motor]\n{table}\n")
    code, out, err = hapticad("datasheet", p)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1, err
    assert err.startswith(f"hapticad: error: {field}:") and "stall" in err and "Traceback" not in err


def test_a_named_motor_is_not_held_to_the_catalog_stall_torque(tmp_path):
    p = tmp_path / "d.toml"
    p.write_text(HOEKEN.read_text() + '\n[motor]\nname = "acme"\ntorque_peak_mNm = 1500.0\n')
    code, _, err = hapticad("datasheet", p)
    assert code == 0, err


def test_the_catalog_motors_hold_the_same_order():
    for key in ("maxon-re35", "maxon-re40"):
        m = get_motor(key)
        assert m.torque_continuous_mNm <= m.torque_peak_mNm <= m.stall_torque_mNm


@pytest.mark.parametrize("name", ["maxon-re25", "maxon-re40"])
def test_a_table_named_after_another_catalog_motor_is_refused(tmp_path, name):
    """A tester's finding: ``[motor] name = "maxon-re25"`` over the RE 35 labelled every row
    RE 25 with the RE 35's data. The name of another catalog motor is refused naming the fix;
    the ordered motor's own key is taken (a table of corrections named as the catalog does)."""
    p = tmp_path / "d.toml"
    p.write_text(HOEKEN.read_text() + f'\n[motor]\nname = "{name}"\n')
    code, out, err = hapticad("datasheet", p)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1, err
    assert err.startswith("hapticad: error: motor.name:") and f"set parts.motor = '{name}'" in err
    p.write_text(HOEKEN.read_text() + '\n[motor]\nname = "maxon-re35"\n')
    code, _, err = hapticad("datasheet", p)
    assert code == 0, err


@pytest.mark.parametrize("design", ["hoeken.toml", "delta_falcon.toml"])
def test_a_peak_below_the_continuous_torque_is_refused(tmp_path, design):
    """``torque_peak_mNm = 1.5`` (N m typed where mN m is asked) under the catalog motor's
    continuous torque (the RE 35's 97.2 mN m, both designs' motor): refused in one line naming
    the key and the slip, as a tester's build with it ran on with a 0.0098 N peak force."""
    p = tmp_path / "d.toml"
    p.write_text((HOEKEN.parent / design).read_text() + "\n[motor]\ntorque_peak_mNm = 1.5\n")
    code, out, err = hapticad("datasheet", p)
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1, err
    assert err.startswith("hapticad: error: motor.torque_peak_mNm:") and "1000x" in err, err
    assert "peak torque is at least its continuous torque" in err and "Traceback" not in err
