"""What a sweep evaluates: ``--vary`` specs, the variants they make, and their keys.

``--vary KEY=V1,V2,...`` lists values (numbers, ``true``/``false`` or words such as
material names); ``--vary KEY=LO:HI:N`` is N evenly spaced numbers from LO to HI.
``KEY`` is a dotted design key (``parts.bar_thickness_mm``, ``mechanism.stroke_mm``).
Without ``--samples`` the sweep takes every combination; with ``--samples N`` it takes
N Latin-hypercube samples (scipy.stats.qmc) of the ranges [LO, HI] (N in LO:HI:N is
then ignored) and of the lists (each list split into equal strata).

A variant's key is the SHA-256 of the resolved design (its raw TOML mapping with the
varied values applied, canonical JSON) and the fidelity: the same combination reached
from another command line is recognized when a sweep resumes.
"""

from __future__ import annotations

import copy
import hashlib
import itertools
import json
import math
from dataclasses import dataclass
from typing import Any

from cad.errors import DesignError

#: combinations above this are refused (use --samples): a table that size is a mistake
MAX_VARIANTS = 100_000


@dataclass(frozen=True)
class Vary:
    """One varied key: a list of values, or a range (lo, hi, n)."""

    key: str
    values: tuple[Any, ...] = ()
    lo: float = math.nan
    hi: float = math.nan
    n: int = 0

    @property
    def is_range(self) -> bool:
        return not self.values

    def grid(self) -> tuple[Any, ...]:
        """The values of a full-factorial sweep."""
        if self.values:
            return self.values
        if self.n == 1:
            return (self.lo,)
        return tuple(self.lo + (self.hi - self.lo) * i / (self.n - 1) for i in range(self.n))


def _scalar(text: str) -> Any:
    t = text.strip()
    if t.lower() in ("true", "false"):
        return t.lower() == "true"
    try:
        v = float(t)
    except ValueError:
        return t
    if not math.isfinite(v):
        raise ValueError(t)
    return int(v) if t.lstrip("+-").isdigit() else v


def parse_vary(text: str) -> Vary:
    """``KEY=V1,V2,...`` or ``KEY=LO:HI:N`` -> :class:`Vary` (DesignError naming --vary)."""
    key, sep, rest = text.partition("=")
    key = key.strip()
    flag = f"--vary {text}"
    if not sep or not key or not rest.strip():
        raise DesignError(flag, "expected KEY=V1,V2,... or KEY=LO:HI:N")
    if "." not in key or key.startswith("name"):
        raise DesignError(flag, f"KEY must be a dotted design key such as parts.bar_thickness_mm, got {key!r}")
    if ":" in rest and "," not in rest:
        parts = rest.split(":")
        if len(parts) != 3:
            raise DesignError(flag, "a range is LO:HI:N")
        try:
            lo, hi = float(parts[0]), float(parts[1])
            n = int(parts[2])
        except ValueError:
            raise DesignError(flag, f"LO:HI:N must be two numbers and an integer, got {rest!r}") from None
        if not (math.isfinite(lo) and math.isfinite(hi)) or hi < lo:
            raise DesignError(flag, f"needs finite LO <= HI, got {lo} and {hi}")
        if not 1 <= n <= MAX_VARIANTS:
            raise DesignError(flag, f"N must be in [1, {MAX_VARIANTS}], got {n}")
        return Vary(key, lo=lo, hi=hi, n=n)
    try:
        vals = tuple(_scalar(v) for v in rest.split(",") if v.strip())
    except ValueError as exc:
        raise DesignError(flag, f"value {exc} is not finite") from None
    if not vals:
        raise DesignError(flag, "no values")
    return Vary(key, values=vals)


def apply(raw: dict[str, Any], assignment: dict[str, Any]) -> dict[str, Any]:
    """A deep copy of ``raw`` with every dotted key of ``assignment`` set."""
    out = copy.deepcopy(raw)
    for key, value in assignment.items():
        node = out
        *head, last = key.split(".")
        for k in head:
            nxt = node.setdefault(k, {})
            if not isinstance(nxt, dict):
                raise DesignError(key, f"{k} is not a table in the design")
            node = nxt
        node[last] = value
    return out


def assignments(varies: tuple[Vary, ...], samples: int | None, seed: int = 0) -> list[dict[str, Any]]:
    """Every combination (``samples`` None) or ``samples`` Latin-hypercube points."""
    if samples is None:
        total = math.prod(len(v.grid()) for v in varies)
        if total > MAX_VARIANTS:
            raise DesignError("--vary", f"{total} combinations (> {MAX_VARIANTS}); use --samples N")
        return [dict(zip([v.key for v in varies], combo, strict=True))
                for combo in itertools.product(*(v.grid() for v in varies))]
    from scipy.stats import qmc

    u = qmc.LatinHypercube(d=len(varies), seed=seed).random(samples)
    out = []
    for row in u:
        a = {}
        for v, x in zip(varies, row, strict=True):
            if v.is_range:
                a[v.key] = v.lo + (v.hi - v.lo) * float(x)
            else:
                a[v.key] = v.values[min(int(x * len(v.values)), len(v.values) - 1)]
        out.append(a)
    return out


def design_hash(raw: dict[str, Any], fidelity: str, extra: str = "") -> str:
    """SHA-256 (hex, 16 chars) of the resolved design mapping, the fidelity and ``extra``."""
    text = json.dumps(raw, sort_keys=True, default=str) + "|" + fidelity + "|" + extra
    return hashlib.sha256(text.encode()).hexdigest()[:16]
