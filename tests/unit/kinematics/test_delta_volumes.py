"""The delta's reachable and well-conditioned workspace (issue 36 §2): the grid count of
cad.kinematics.delta.workspace_volumes against a second method, Monte Carlo sampling of the
same box with independent uniform points (its standard error stated), and through
``hapticad gii --json``."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from cad.design import load_design
from cad.kinematics import delta as D
from tests.cli_helpers import hapticad

ROOT = Path(__file__).resolve().parents[3]


@pytest.mark.parametrize("name", ["delta_falcon", "delta"])
def test_grid_volumes_agree_with_monte_carlo(name):
    d = load_design(ROOT / "designs" / f"{name}.toml").mechanism
    got = D.workspace_volumes(d, step_mm=5.0)
    lo, hi = D.reach_box_mm(d)
    box_cm3 = float(np.prod(hi - lo)) * 1e-3
    n = 400_000
    P = np.random.default_rng(7).uniform(lo, hi, (n, 3))
    ratio, status = D.inverse_condition(d, P)
    for key, hit in (("reachable_cm3", status == D.STATUS_OK),
                     ("well_conditioned_cm3", (status == D.STATUS_OK) & (ratio >= D.WELL_CONDITIONED_MIN))):
        p = hit.mean()
        mc, se = box_cm3 * p, box_cm3 * np.sqrt(p * (1 - p) / n)
        # 4 standard errors of the sampling, plus 0.5 % for the grid's boundary cells (the
        # 5 mm and 2.5 mm grids differ by 0.1 to 0.3 %: docs/families/delta.md)
        assert abs(got[key] - mc) <= 4 * se + 0.005 * mc, (key, got[key], mc, se)


def test_every_reachable_cell_is_below_the_base_and_inside_the_box():
    d = load_design(ROOT / "designs" / "delta.toml").mechanism
    lo, hi = D.reach_box_mm(d)
    # just outside the box: nothing reached (the box holds the reach)
    ring = np.array([[hi[0] + 1, 0, -150], [0, lo[1] - 1, -150], [0, 0, lo[2] - 1]])
    assert not np.any(D.ik(d, ring).status == D.STATUS_OK)
    v = D.workspace_volumes(d, step_mm=10.0)
    assert 0 < v["well_conditioned_cm3"] <= v["reachable_cm3"] < float(np.prod(hi - lo)) * 1e-3


def test_gii_json_states_the_volumes_of_a_delta(tmp_path):
    code, out, err = hapticad("gii", ROOT / "designs" / "delta_falcon.toml", "--json")
    assert code == 0, err
    rep = json.loads(out)
    d = load_design(ROOT / "designs" / "delta_falcon.toml")
    assert rep["workspace_volumes"] == D.workspace_volumes(d.mechanism)
    ratio, _ = D.inverse_condition(d.mechanism, d.workspace_points())
    assert rep["workspace_inverse_condition_min"] == pytest.approx(float(ratio.min()), rel=1e-12)


#: Regression pins (our own run, 2026-12-05, 10 mm cells): the docs' figures.
PINS = {"delta": (5894.0, 5875.0, 0.462), "delta_falcon": (3591.0, 1437.0, 0.064)}


@pytest.mark.parametrize("name", sorted(PINS))
def test_bundled_volumes_regression_pin(name):
    d = load_design(ROOT / "designs" / f"{name}.toml")
    v = D.workspace_volumes(d.mechanism)
    ratio, _ = D.inverse_condition(d.mechanism, d.workspace_points())
    reach, good, worst = PINS[name]
    assert v["reachable_cm3"] == pytest.approx(reach, abs=0.5)
    assert v["well_conditioned_cm3"] == pytest.approx(good, abs=0.5)
    assert float(ratio.min()) == pytest.approx(worst, abs=5e-4)
