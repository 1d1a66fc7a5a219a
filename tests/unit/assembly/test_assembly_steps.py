"""Assembly steps for every family (issue 25 §4), read back from the build folder.

``assembly.md`` is parsed here (its ``- `name` (kind): ...`` bullets under ``## Step k``)
and compared with ``bom.csv`` (csv module: the quantity of every part kind) and
``report.json`` (every fastener record: what it clamps and the hole it engages): every part
instance is placed in exactly one step, and no fastener before the parts it joins.
"""

from __future__ import annotations

import csv
import json
import re
from collections import Counter
from pathlib import Path

import pytest

from tests.conftest import DELTA_FORMATS, FAMILY_DESIGNS, FAMILY_FORMATS, HOEKEN_SIM_FORMATS

_BULLET = re.compile(r"^- `([^`]+)` \(([^)]+)\): ")


@pytest.fixture(scope="module")
def builds(shared_builds):
    """``{family: out_dir}``: the shared family builds (``family_builds``), the bundled delta
    (preview, shared with tests/families/delta/test_delta_build.py) and the bundled Hoeken
    (preview, ``hoeken_sim_build``: its assembly.md, bom.csv and fastener records are the
    inertia build's), asked for together (tests/conftest.py ``shared_builds``: the other
    worker builds some of them at the same time)."""
    specs = {"hoeken": ("hoeken.toml", HOEKEN_SIM_FORMATS, "preview"),
             "delta": ("delta.toml", DELTA_FORMATS, "preview"),
             **{fam: (fn, FAMILY_FORMATS, "inertia") for fam, fn in FAMILY_DESIGNS.items()}}
    return {fam: b[1] for fam, b in zip(specs, shared_builds(specs.values()), strict=True)}


def _steps(out: Path) -> list[tuple[str, list[tuple[str, str]], list[str]]]:
    """``[(title, [(instance, kind)], [check])]`` of assembly.md."""
    steps = []
    for line in (out / "assembly.md").read_text(encoding="utf-8").splitlines():
        if line.startswith("## Step "):
            steps.append((line.split(": ", 1)[1], [], []))
        elif (m := _BULLET.match(line)) and steps:
            steps[-1][1].append((m.group(1), m.group(2)))
        elif line.startswith("- check: ") and steps:
            steps[-1][2].append(line[len("- check: "):])
    return steps


@pytest.mark.parametrize("fam", ["hoeken", "pantograph", "twin-pantograph", "powermouse", "delta"])
def test_steps_place_every_bom_instance_exactly_once(builds, fam):
    out = builds[fam]
    placed = [p for _, new, _ in _steps(out) for p in new]
    names = [n for n, _ in placed]
    assert len(names) == len(set(names)), Counter(names).most_common(3)
    with (out / "bom.csv").open(newline="") as fh:
        qty = {r["part"]: int(r["quantity"]) for r in csv.DictReader(fh)}
    assert Counter(k for _, k in placed) == Counter(qty)
    rep = json.loads((out / "report.json").read_text())
    assert "assembly.md" in rep["files"]
    assert "[assembly.md](assembly.md)" in (out / "report.md").read_text()
    # every instance of report.json's part list that has a BOM line is placed; the BOM lines
    # with no solid (the joint encoders: one per motor) in a step of their own, right before
    # the final checks (which turn the joints the encoders read)
    from cad.pipeline.family import NO_SOLID_STEP

    steps = _steps(out)
    no_solid = {n for t, new, _ in steps if t.endswith(NO_SOLID_STEP) for n, _ in new}
    assert steps[-1][0] == "final checks"
    assert (steps[-2][0] == NO_SOLID_STEP) == bool(no_solid), [t for t, _, _ in steps[-2:]]
    assert set(names) - no_solid <= set(rep["part_materials"])
    n_motors = {"hoeken": 1, "pantograph": 2, "twin-pantograph": 4, "powermouse": 0, "delta": 3}[fam]
    # numbered as the family numbers its motors: the delta's motor_0 .. motor_2, the others from 1
    first = 0 if fam == "delta" else 1
    assert no_solid == ({"encoder"} if n_motors == 1 else {f"encoder_{i}" for i in range(first, first + n_motors)})


@pytest.mark.parametrize("fam", ["hoeken", "powermouse"])
def test_no_fastener_before_the_parts_it_joins(builds, fam):
    out = builds[fam]
    step_of = {n: k for k, (_, new, _) in enumerate(_steps(out)) for n, _ in new}
    rep = json.loads((out / "report.json").read_text())
    assert rep["fasteners"]
    for name, f in rep["fasteners"].items():
        for part in (*f["clamps"], f["hole"].split(":")[0]):
            if part in step_of:  # an instance (kind names and the motor shaft: not placed)
                assert step_of[part] <= step_of[name], (name, part)


def test_hoeken_joints_are_one_step_each_with_their_stack_and_a_check(builds):
    steps = {t.split(":")[0]: (new, checks) for t, new, checks in _steps(builds["hoeken"])}
    new, checks = steps["joint pin_A2"]
    assert [n for n, _ in new] == ["head_spacer_A2", "bearing_A2", "gap_spacer_A2", "washer_A2",
                                   "nut_A2", "pin_A2"]
    assert checks == ["coupler and crank turn freely about pin_A2, no axial play"]
    assert {"joint pin_A3", "joint pin_A4"} <= set(steps)


def test_powermouse_steps_follow_its_plan(builds):
    titles = [t for t, _, _ in _steps(builds["powermouse"])]
    post = next(i for i, t in enumerate(titles) if t.startswith("post through"))
    lid = next(i for i, t in enumerate(titles) if t.startswith("housing lid"))
    flotor_in = next(i for i, t in enumerate(titles) if t.startswith("flotor (with the core)"))
    assert flotor_in < post < lid
    assert titles[-1] == "final checks"
