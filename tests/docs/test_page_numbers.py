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
