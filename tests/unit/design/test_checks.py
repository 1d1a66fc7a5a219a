"""Target parsing and evaluation (the logic of `hapticad check`)."""

import pytest

from cad.checks import evaluate, merge_targets, values_from_report, violation
from cad.design.targets import parse_cli_target, parse_target, parse_targets
from cad.errors import DesignError


def test_value_tolerance_and_bounds():
    t = parse_target("H11_kg_m2", {"value": 3e-5, "tol_rel": 0.1})
    assert t.ok(3.29e-5) and not t.ok(3.31e-5)
    assert violation(t, 3.6e-5) == pytest.approx((0.6e-5 - 0.3e-5) / 3e-5)
    b = parse_target("M11_max_g", {"max": 45.0})
    assert b.ok(44.9) and not b.ok(45.1)
    assert violation(b, 45.0) == 0.0
    a = parse_target("stroke_mm", {"value": 50.0, "tol_abs": 0.5})
    assert a.ok(50.49) and not a.ok(50.51)
    assert parse_target("coupler_mass_g", 40.0).tol_rel == 0.05


def test_cli_target_forms():
    assert parse_cli_target("M11_max_g=40").value == 40.0
    assert parse_cli_target("M11_max_g<=40").max == 40.0
    assert parse_cli_target("stroke_mm>=45").min == 45.0
    with pytest.raises(DesignError, match="--target"):
        parse_cli_target("M11_max_g")
    with pytest.raises(DesignError, match="not a number"):
        parse_cli_target("M11_max_g=abc")
    with pytest.raises(DesignError, match="unknown target"):
        parse_cli_target("M99=1")


def test_bad_target_tables():
    with pytest.raises(DesignError, match="targets.H11_kg_m2"):
        parse_targets({"H11_kg_m2": {"value": 1.0, "max": 2.0}})
    with pytest.raises(DesignError, match="min 3.0 > max 2.0"):
        parse_targets({"stroke_mm": {"min": 3.0, "max": 2.0}})
    with pytest.raises(DesignError, match="tol_rel"):
        parse_targets({"stroke_mm": {"value": 3.0, "tol_rel": -1}})


def test_evaluate_from_report():
    report = {"H11_kg_m2": 3.0e-5, "apparent_mass": {"M11_max_g": 50.0},
              "links": {"crank": {"mass_g": 10.0}, "coupler": {"mass_g": 30.0}, "rocker": {"mass_g": 20.0}}}
    vals = values_from_report(report)
    assert vals["moving_mass_g"] == 60.0
    targets = parse_targets({"H11_kg_m2": {"value": 2.97e-5, "tol_rel": 0.05}, "M11_max_g": {"max": 45.0},
                             "H33_kg_m2": 1e-5})
    rows = {r.key: r for r in evaluate(targets, vals)}
    assert rows["H11_kg_m2"].ok
    assert not rows["M11_max_g"].ok and rows["M11_max_g"].gap_rel == pytest.approx(5 / 45)
    assert rows["H33_kg_m2"].computed is None and not rows["H33_kg_m2"].ok


def test_merge_cli_overrides_design():
    d = parse_targets({"H11_kg_m2": 1e-5, "H22_kg_m2": 2e-5})
    c = (parse_cli_target("H11_kg_m2=5e-5"),)
    m = {t.key: t for t in merge_targets(d, c)}
    assert m["H11_kg_m2"].value == 5e-5 and m["H22_kg_m2"].value == 2e-5


def test_rows_carry_targets_as_data_and_margins():
    targets = parse_targets({"M11_max_g": {"max": 45.0}, "stroke_mm": {"min": 40.0, "max": 60.0},
                             "H11_kg_m2": {"value": 3e-5, "tol_rel": 0.1}})
    vals = {"M11_max_g": 41.5, "stroke_mm": 57.0, "H11_kg_m2": 3.2e-5}
    rows = {r.key: r.as_dict() for r in evaluate(targets, vals)}
    assert rows["M11_max_g"]["target"] == {"max": 45.0}
    assert rows["M11_max_g"]["margin"] == pytest.approx(3.5)  # 45 - 41.5 g
    assert rows["stroke_mm"]["target"] == {"min": 40.0, "max": 60.0}
    assert rows["stroke_mm"]["margin"] == pytest.approx(3.0)  # nearest limit is the max
    assert rows["H11_kg_m2"]["target"] == {"value": 3e-5, "tol_rel": 0.1}
    assert rows["H11_kg_m2"]["margin"] == pytest.approx(0.3e-5 - 0.2e-5)
    assert rows["H11_kg_m2"]["target_text"] == "3e-05 ± 10%"
    missed = {r.key: r.as_dict() for r in evaluate(targets, {"M11_max_g": 50.0})}
    assert missed["M11_max_g"]["margin"] == pytest.approx(-5.0) and not missed["M11_max_g"]["ok"]
