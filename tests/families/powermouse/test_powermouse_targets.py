"""The PowerMouse takes ``check`` and ``fit`` targets (issue 32 §3: every datasheet figure a
target for every family): its values are its build's datasheet rows
(:mod:`cad.studies.build_targets`), its free parameters the keys of its tables."""

from __future__ import annotations

import json

import pytest

from cad.design import load_design
from cad.design.targets import POWERMOUSE_TARGET_KEYS
from cad.errors import DesignError
from cad.studies.build_targets import parse_free_tables
from tests.bundled import DESIGNS
from tests.cli_helpers import assert_one_line_error, hapticad


@pytest.fixture(scope="module")
def pm():
    return load_design(DESIGNS / "powermouse.toml")


def test_free_parameters_are_the_keys_of_its_tables(pm):
    p = parse_free_tables("flotor.edge_mm", pm)
    # the default range: 0.5x .. 1.5x the current value (cad.studies.fit.NUMERIC_DEFAULT_SPAN),
    # the current value being the design file's own 64 mm
    assert (p.kind, p.lo, p.hi) == ("numeric", 32.0, 96.0)
    assert parse_free_tables("flotor.edge_mm=50:60", pm).lo == 50.0
    assert parse_free_tables("handle.material", pm).kind == "choice"
    with pytest.raises(DesignError) as e:
        parse_free_tables("mechanism.base_mm", pm)
    assert e.value.field == "--free mechanism.base_mm" and "actuator" in str(e.value)
    with pytest.raises(DesignError):
        parse_free_tables("actuator.field_model", pm)  # a string: neither numeric nor a material


def test_targets_table_takes_its_datasheet_keys_only(tmp_path):
    text = (DESIGNS / "powermouse.toml").read_text()
    ok = tmp_path / "ok.toml"
    ok.write_text(text + "\n[targets]\ncontinuous_force_N = { min = 10.0 }\n")
    assert [t.key for t in load_design(ok).targets] == ["continuous_force_N"]
    bad = tmp_path / "bad.toml"
    bad.write_text(text + "\n[targets]\nM11_max_g = { max = 10.0 }\n")
    with pytest.raises(DesignError) as e:
        load_design(bad)
    assert "M11_max_g" in str(e.value)
    assert "M11_max_g" not in POWERMOUSE_TARGET_KEYS


def test_a_four_bar_key_is_refused_by_check_in_one_line():
    code, _o, err = hapticad("check", str(DESIGNS / "powermouse.toml"), "--target", "M11_max_g<=30")
    assert_one_line_error(code, err, "M11_max_g")


@pytest.mark.slow
def test_check_reads_the_datasheet_of_its_build():
    """One build (about 20 s): the checked values are the datasheet's (a second command reads
    them), and a target the design misses exits 1 naming it."""
    code, out, err = hapticad("check", str(DESIGNS / "powermouse.toml"), "--target",
                              "continuous_force_N>=10", "--target", "flotor_mass_g<=200", "--json")
    assert code == 1, err
    res = json.loads(out)
    code, ds_out, err = hapticad("datasheet", str(DESIGNS / "powermouse.toml"), "--fidelity",
                                 "inertia", "--json")
    assert code == 0, err
    rows = {r["key"]: r["value"] for r in json.loads(ds_out)["datasheet"]["rows"]}
    got = {r["key"]: r for r in res["rows"]}
    assert got["continuous_force_N"]["computed"] == pytest.approx(rows["continuous_force_N"], rel=1e-12)
    assert got["continuous_force_N"]["ok"] and not got["flotor_mass_g"]["ok"]
    assert got["flotor_mass_g"]["computed"] == pytest.approx(rows["flotor_mass_g"], rel=1e-12)
