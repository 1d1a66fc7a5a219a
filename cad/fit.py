"""Inverse design: adjust a four-bar design's free part parameters to meet its targets.

The objective is the largest target violation (0 when every target is met,
:func:`cad.checks.violation`); ties go to the smallest change from the start.
Each free parameter is searched in turn (coordinate descent, at most two sweeps):

- numeric (e.g. ``parts.bar_thickness_mm``): a 5-point grid over its bounds plus
  the start; if some values meet every target, bisection between the feasible
  value closest to the start and its infeasible neighbour finds the smallest
  change that still meets them; otherwise golden-section search around the best
  grid value minimizes the violation.
- choice (materials, ``bar_pockets``, and ``bar_thickness_mm``, picked from the stock
  thicknesses of the bar material, :data:`cad.codesign.search.STOCK_THICKNESS_MM`, nearest
  to the start first): every candidate is evaluated.

Every evaluation rebuilds the parts and integrates them exactly
(:func:`cad.build.inertia.inertia_model`); a parameter value for which the parts
cannot be built counts as infeasible. The log of every evaluation is returned.

Why not the plate-thickness shortcut alone: a bar's own mass properties scale
exactly linearly with its thickness, but the pins, spacers and layer heights
change with it too, so H is only nearly linear in ``bar_thickness_mm``. The log
reports how far the final value is from the straight line through its two
nearest grid values (measured linearity).
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from cad.checks import evaluate, violation
from cad.design.targets import Target
from cad.errors import DesignError, HapticadError

#: candidates tried for a free material parameter (light to heavy)
MATERIAL_CHOICES = ("carbon-fibre", "delrin", "pla", "petg", "aluminium-6061", "aluminium-7075",
                    "stainless-304", "steel-1018", "brass-360")
NUMERIC_DEFAULT_SPAN = (0.5, 1.5)


@dataclass
class FreeParam:
    """A free parameter: dotted path (``parts.bar_thickness_mm``), kind, bounds or choices."""

    path: str
    kind: str  # "numeric" | "choice"
    lo: float = math.nan
    hi: float = math.nan
    choices: tuple = ()


@dataclass
class FitResult:
    raw: dict
    start: dict[str, Any]
    values: dict[str, Any]
    objective: float
    met: bool
    log: list[dict] = field(default_factory=list)
    linearity_note: str = ""


def _get(raw: dict, path: str, default: Any) -> Any:
    node = raw
    for k in path.split(".")[:-1]:
        node = node.get(k, {})
    return node.get(path.split(".")[-1], default)


def _set(raw: dict, path: str, value: Any) -> dict:
    out = copy.deepcopy(raw)
    node = out
    *head, last = path.split(".")
    for k in head:
        node = node.setdefault(k, {})
    node[last] = value
    return out


def parse_free(spec: str, parts_spec) -> FreeParam:
    """``parts.KEY`` or ``parts.KEY=LO:HI`` (numeric) -> FreeParam with defaults from the spec."""
    from cad.design.parts import ALLOWED_KEYS

    key, _, rng = spec.partition("=")
    key = key.strip()
    if not key.startswith("parts."):
        key = "parts." + key
    name = key.split(".", 1)[1]
    if name not in ALLOWED_KEYS:
        raise DesignError(f"--free {spec}", f"unknown part parameter {name!r}")
    current = getattr(parts_spec, name)
    if name.endswith("_material"):
        if rng:
            raise DesignError(f"--free {spec}", "a material takes no range")
        return FreeParam(key, "choice", choices=MATERIAL_CHOICES)
    if isinstance(current, bool):
        return FreeParam(key, "choice", choices=(True, False))
    if name == "bar_thickness_mm":
        return _stock_thickness(spec, key, rng, parts_spec)
    if not isinstance(current, (int, float)) or current is None:
        raise DesignError(f"--free {spec}", f"{name} is not a numeric, material or boolean parameter")
    lo, hi = current * NUMERIC_DEFAULT_SPAN[0], current * NUMERIC_DEFAULT_SPAN[1]
    if rng:
        try:
            a, b = (float(x) for x in rng.split(":"))
        except ValueError:
            raise DesignError(f"--free {spec}", "range must be LO:HI (numbers)") from None
        if not (0 < a < b):
            raise DesignError(f"--free {spec}", f"need 0 < LO < HI, got {a}:{b}")
        from cad.design.bounds import FIELDS, check_number

        bound = FIELDS.get(key)
        if bound is not None:
            for x in (a, b):
                check_number(f"--free {key}", x, bound)
        lo, hi = a, b
    return FreeParam(key, "numeric", lo=lo, hi=hi)


def _stock_thickness(spec: str, key: str, rng: str, parts_spec) -> FreeParam:
    """Plate thickness: a choice among the stock thicknesses of the bar material
    (:data:`cad.codesign.search.STOCK_THICKNESS_MM`) inside LO:HI (default 0.5x..1.5x the
    current value), nearest to the current value first (ties go to the smallest change)."""
    from cad.codesign.search import STOCK_THICKNESS_MM

    cur = parts_spec.bar_thickness_mm
    stock = STOCK_THICKNESS_MM.get(parts_spec.bar_material, STOCK_THICKNESS_MM["aluminium-6061"])
    lo, hi = cur * NUMERIC_DEFAULT_SPAN[0], cur * NUMERIC_DEFAULT_SPAN[1]
    if rng:
        try:
            lo, hi = (float(x) for x in rng.split(":"))
        except ValueError:
            raise DesignError(f"--free {spec}", "range must be LO:HI (numbers)") from None
        if not (0 < lo < hi):
            raise DesignError(f"--free {spec}", f"need 0 < LO < HI, got {lo}:{hi}")
        from cad.design.bounds import FIELDS, check_number

        bound = FIELDS.get(key)
        if bound is not None:
            for x in (lo, hi):
                check_number(f"--free {key}", x, bound)
    inside = sorted((t for t in stock if lo - 1e-9 <= t <= hi + 1e-9), key=lambda t: (abs(t - cur), t))
    if not inside:
        raise DesignError(f"--free {spec}", f"no stock {parts_spec.bar_material} thickness in {lo:g}..{hi:g} mm "
                                            f"(stock: {', '.join(f'{t:g}' for t in stock)} mm)")
    return FreeParam(key, "choice", lo=lo, hi=hi, choices=tuple(inside))


def fit(raw: dict, source: str, targets: tuple[Target, ...], free: list[FreeParam],
        evaluate_values: Callable[[Any], dict[str, float]], echo: Callable[[str], None] | None = None,
        max_sweeps: int = 2) -> FitResult:
    """Coordinate search over ``free`` on the raw design (see module docstring)."""
    from cad.design import parse_design

    cache: dict[str, tuple[float, dict]] = {}
    log: list[dict] = []

    def objective(r: dict) -> tuple[float, dict]:
        key = repr([(p.path, _get(r, p.path, None)) for p in free])
        if key in cache:
            return cache[key]
        try:
            d = parse_design(r, source)
            vals = evaluate_values(d)
            obj = max((violation(t, vals[t.key]) if t.key in vals else math.inf) for t in targets)
        except HapticadError as exc:
            vals, obj = {"error": str(exc)}, math.inf
        entry = {"params": {p.path: _get(r, p.path, None) for p in free}, "objective": obj,
                 **{t.key: vals.get(t.key) for t in targets}}
        log.append(entry)
        if echo:
            ps = ", ".join(f"{k.split('.')[-1]}={v}" for k, v in entry["params"].items())
            why = f"  ({vals['error']})" if "error" in vals else ""
            echo(f"  eval {len(log):2d}: {ps}  ->  max violation {obj:.4g}{why}")
        cache[key] = (obj, vals)
        return obj, vals

    from cad.design import parse_design as _pd

    spec = _pd(raw, source).parts
    start_vals = {p.path: getattr(spec, p.path.split(".", 1)[1]) for p in free}
    cur = copy.deepcopy(raw)
    for p in free:
        cur = _set(cur, p.path, start_vals[p.path])
    best, _ = objective(cur)
    for _sweep in range(max_sweeps):
        if best == 0:
            break
        for p in free:
            if best == 0:
                break
            x0 = _get(cur, p.path, None)
            if p.kind == "choice":
                cands = [x0] + [c for c in p.choices if c != x0]
                scored = [(objective(_set(cur, p.path, c))[0], i, c) for i, c in enumerate(cands)]
                obj, _, c = min(scored)
                if obj < best:
                    best, cur = obj, _set(cur, p.path, c)
                continue
            grid = sorted({p.lo + (p.hi - p.lo) * k / 4 for k in range(5)} | {float(x0)})
            scored = [(objective(_set(cur, p.path, round(x, 6)))[0], x) for x in grid]
            feas = [x for o, x in scored if o == 0]
            if feas:
                xf = min(feas, key=lambda x: abs(x - x0))
                # smallest change: bisect between xf and the infeasible grid neighbour towards x0
                side = [x for o, x in scored if o > 0 and (x - xf) * (x0 - xf) > 0]
                if side:
                    xi = min(side, key=lambda x: abs(x - xf))
                    for _ in range(5):
                        xm = 0.5 * (xf + xi)
                        if objective(_set(cur, p.path, round(xm, 6)))[0] == 0:
                            xf = xm
                        else:
                            xi = xm
                best, cur = 0.0, _set(cur, p.path, round(xf, 6))
                continue
            ob, xb = min(scored)
            i = grid.index(xb)
            a, b = grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]
            from cad.kinematics.search import golden_minimize

            xg, og = golden_minimize(lambda x, c=cur, q=p: objective(_set(c, q.path, round(x, 6)))[0], a, b,
                                     xtol=1e-3, max_iter=8)
            xn, on = (xg, og) if og < ob else (xb, ob)
            if on < best:
                best, cur = on, _set(cur, p.path, round(xn, 6))
    values = {p.path: _get(cur, p.path, None) for p in free}
    final_vals = objective(cur)[1]
    rows = evaluate(targets, {k: v for k, v in final_vals.items() if isinstance(v, (int, float))})
    return FitResult(raw=cur, start=start_vals, values=values, objective=best,
                     met=all(r.ok for r in rows), log=log)
