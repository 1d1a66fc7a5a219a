"""A ``[[transmission]]`` table is named in errors counted from 1, as the capstan rows, the rope
BOM lines and assembly.md count the motors (a tester's finding: messages numbered the motors
from 0 while the rows' suffixes run ``_1`` .. ``_n``)."""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]


def test_the_nth_table_is_named_n_as_its_motors_rows():
    from cad.design import parse_design
    from cad.design.transmission import parse_transmissions
    from cad.errors import DesignError
    from cad.families.pantograph.capstan import capstan_joints

    raw = tomllib.loads((ROOT / "designs" / "twin_pantograph_capstan.toml").read_text())
    t = raw.pop("transmission")
    drums = (96.0, 128.0, 160.0, 192.0)  # one ratio per motor: table n is told by its drum
    raw["transmission"] = [dict(t, drum_diameter_mm=dd) for dd in drums]
    joints = capstan_joints(parse_design(copy.deepcopy(raw), "per_motor.toml"))
    assert [(j.suffix, j.transmission.drum_diameter_mm) for j in joints] == [
        (f"_{n}", dd) for n, dd in enumerate(drums, 1)]
    for n in range(1, 5):
        bad = copy.deepcopy(raw["transmission"])
        bad[n - 1]["kind"] = "belt"
        with pytest.raises(DesignError) as e:
            parse_transmissions(bad, 4)
        assert e.value.field == f"transmission.{n}.kind"
