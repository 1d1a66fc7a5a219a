"""Issue 33 item 4: every value inside a key's bound loads or is refused in one line.

Seeded property test over :data:`cad.design.bounds.FIELDS`: for each bundled design and each
numeric key of a table the design has, values at both ends of the bound and seeded random
values inside it (log-uniform over positive ranges, signed where the bound is) are put in the
raw design and parsed (``parse_design``: bounds, schema, cross-checks; the cheap path of
``hapticad check`` before any CAD). Each parse returns a design or raises DesignError with a
one-line message naming a key; any other exception (a traceback) fails. The reference is the
contract itself: docs/bounds.md says a value outside is refused and inside is checked.
"""

from __future__ import annotations

import copy
import math
import random
import tomllib
from pathlib import Path

import pytest

from cad.design import bounds, parse_design
from cad.errors import DesignError

ROOT = Path(__file__).resolve().parents[3]
DESIGNS = sorted(p.name for p in (ROOT / "designs").glob("*.toml"))


def _samples(b: bounds.Bound, rng: random.Random, n: int) -> list[float]:
    lo = 0.0 if b.signed or b.lo is None else b.lo
    hi = b.hi if b.hi is not None else max(1.0, abs(lo)) * 1e6
    if b.lo_open and not b.signed:
        lo = math.nextafter(lo, math.inf) if lo != 0 else min(1e-12, hi)
    out = [lo, hi]
    for _ in range(n):
        if lo > 0 and hi / lo > 100:
            out.append(math.exp(rng.uniform(math.log(lo), math.log(hi))))
        else:
            out.append(rng.uniform(lo, hi))
    if b.signed:
        out += [-v for v in out]
    if b.integer:
        out = [float(round(v)) if b.lo is None or round(v) >= b.lo else float(math.ceil(v)) for v in out]
        out = [int(v) for v in out]
    return out


@pytest.mark.parametrize("design", DESIGNS)
def test_every_value_inside_a_bound_loads_or_is_one_line(design):
    rng = random.Random(f"issue33:{design}")
    raw0 = tomllib.loads((ROOT / "designs" / design).read_text())
    tried = 0
    for name, b in bounds.FIELDS.items():
        table, key = name.split(".", 1)
        if not isinstance(raw0.get(table), dict):
            continue
        for v in _samples(b, rng, 4):
            raw = copy.deepcopy(raw0)
            raw[table][key] = v
            tried += 1
            try:
                parse_design(raw, design)
            except DesignError as exc:
                msg = str(exc)
                assert "\n" not in msg and exc.field, (name, v, msg)
            finally:
                bounds.reset()  # warnings of implausible values are expected, not kept
    assert tried > 0
