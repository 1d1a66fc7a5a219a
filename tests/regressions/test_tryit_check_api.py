"""Tester findings on ``cad.check(design, targets=[...], merge=...)`` (t2tester).

H11, H22 and H33 are sums of m l^2 and J terms (Hoeken paper eqs 16-19), so > 0; only H12
(eq 19, m2 l1 lG2 with the COM angle) may be negative. A target that no device can meet is
bad input (exit 2 / DesignError naming the field), like any other impossible value.
"""
from __future__ import annotations

from pathlib import Path

import pytest
from cli_helpers import assert_one_line_error, hapticad

ROOT = Path(__file__).resolve().parents[2]
HOEKEN = ROOT / "designs" / "hoeken.toml"


@pytest.mark.parametrize("key", ("H11_kg_m2", "H22_kg_m2", "H33_kg_m2"))
def test_negative_diagonal_inertia_target_is_bad_input(key):
    code, _, err = hapticad("check", HOEKEN, "--target", f"{key}=-1e-5")
    assert_one_line_error(code, err, f"--target {key}", "-1e-05")


def test_negative_H12_target_stays_allowed():
    from cad.design.targets import parse_cli_target

    t = parse_cli_target("H12_kg_m2=-1e-5")
    assert t.key == "H12_kg_m2" and t.value == -1e-5


def test_api_check_takes_one_target_string_as_one_target():
    import cad
    from cad.errors import DesignError

    d = cad.load_design(HOEKEN)
    # a bare string used to be iterated character by character: "--target H: expected KEY=..."
    with pytest.raises(DesignError) as e:
        cad.check(d, targets="H11_kg_m2=-1e-5")
    assert "--target H11_kg_m2" in str(e.value)
