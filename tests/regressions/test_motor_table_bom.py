"""Issue 32 item 2 (tester case motor-table-bom-still-catalog): with a ``[motor]`` table, the
BOM's motor line, ``order.csv``, ``report.json`` ``motor`` and the datasheet's winding
temperature row all name the table's motor and its mass, not the catalog motor whose mount it
uses; a build whose BOM names another motor is not published.

Files read back with ``csv`` / ``json``; references: the design's own ``[motor]`` table (TOML
read here) and, for the winding row, I^2 R (Rth_winding + Rth_housing) with I = force_N x
max |dx/dphi1| / Kt, the lever by central finite differences of the coupler point
(:func:`tests.regressions.test_outputs_agree.lever_fd`, a second method beside the build's
analytic Jacobian).
"""

from __future__ import annotations

import csv
import json
import tomllib
from pathlib import Path

import pytest

from tests.regressions.test_outputs_agree import FD_REL, lever_fd

ROOT = Path(__file__).resolve().parents[2]
DESIGNS = ROOT / "designs"
MOTOR = ('\n[motor]\nname = "acme-60"\ntorque_constant_mNm_per_A = 60.0\ncurrent_continuous_A = 1.5\n'
         'torque_continuous_mNm = 90.0\ntorque_peak_mNm = 500.0\nrotor_inertia_g_cm2 = 20.0\n'
         'mass_g = 200.0\nterminal_resistance_ohm = 3.0\nthermal_resistance_housing_K_per_W = 5.0\n'
         'thermal_resistance_winding_K_per_W = 2.0\n')
#: bom.csv prints masses with 2 decimals (g).
BOM_MASS_ABS_G = 0.005


def _rows(path: Path) -> list[dict]:
    with path.open(newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


@pytest.fixture(scope="module")
def build(tmp_path_factory):
    from cad.design import load_design
    from cad.pipeline import build_design

    tmp = tmp_path_factory.mktemp("motor_table")
    text = (DESIGNS / "hoeken.toml").read_text() + MOTOR
    (tmp / "d.toml").write_text(text)
    out = tmp / "out"
    build_design(load_design(tmp / "d.toml"), out, {"step"}, fidelity="preview", use_cache=False)
    return tomllib.loads(text), out


def test_the_bom_and_order_name_the_table_motor_and_its_mass(build):
    toml, out = build
    table = toml["motor"]
    motors = [r for r in _rows(out / "bom.csv") if r["group"] == "motors"]
    assert len(motors) == 1
    (m,) = motors
    assert m["description"].startswith(table["name"] + " ")
    assert "maxon RE 35" not in m["description"] and m["designation"] == table["name"]
    assert abs(float(m["mass_g"]) - table["mass_g"]) <= BOM_MASS_ABS_G
    order = [r for r in _rows(out / "order.csv") if r["group"] == "motors"]
    assert [(r["designation"], r["order_code"], r["quantity"]) for r in order] == [(table["name"], "", "1")]
    rep = json.loads((out / "report.json").read_text())
    assert rep["motor"]["name"] == table["name"]
    assert rep["motor"]["mass_kg"] * 1e3 == pytest.approx(table["mass_g"], rel=1e-12)
    assert rep["part_masses_g"][m["part"]] == pytest.approx(table["mass_g"], rel=1e-12)


def test_the_winding_row_is_the_table_motor(build):
    toml, out = build
    t = toml["motor"]
    rep = json.loads((out / "report.json").read_text())
    row = next(r for r in rep["datasheet"]["rows"] if r["key"] == "winding_rise_at_force_K")
    assert t["name"] in row["model"] and "RE 35" not in row["model"].split(";")[-1]
    i = toml["mechanism"]["force_N"] * lever_fd(toml).max() / (t["torque_constant_mNm_per_A"] * 1e-3)
    want = i ** 2 * t["terminal_resistance_ohm"] * (t["thermal_resistance_winding_K_per_W"]
                                                    + t["thermal_resistance_housing_K_per_W"])
    assert row["value"] == pytest.approx(want, rel=2 * FD_REL)  # I^2: twice the lever's error


def test_a_bom_naming_the_catalog_motor_is_not_published(tmp_path, monkeypatch):
    """The motor line's writer corrupted back to the catalog motor: refused in one line."""
    from cad.data.catalog import get_motor
    from cad.design import load_design
    from cad.device.readback import OutputsDisagree
    from cad.families.fourbar import mechanism
    from cad.pipeline import build_design

    real = mechanism.build_assembly
    corrupt = lambda *a, **kw: real(*a, **{**kw, "motor_spec": get_motor("maxon-re35")})  # noqa: E731
    monkeypatch.setattr(mechanism, "build_assembly", corrupt)
    monkeypatch.setattr("cad.families.fourbar.layout.build_assembly", corrupt)  # its caller
    (tmp_path / "d.toml").write_text((DESIGNS / "hoeken.toml").read_text() + MOTOR)
    out = tmp_path / "out"
    with pytest.raises(OutputsDisagree) as e:
        build_design(load_design(tmp_path / "d.toml"), out, {"step"}, fidelity="preview", use_cache=False)
    msg = str(e.value)
    assert "\n" not in msg
    assert msg.startswith("outputs disagree, nothing published: bom.csv: motor line 'maxon RE 35")
    assert "acme-60 (data of [motor]; mount of maxon-re35)" in msg
    assert not out.exists()
