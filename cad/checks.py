"""Targets against computed values: the logic behind ``hapticad check`` (pure, no CAD).

``values_from_report`` flattens a build report (``report.json``) into the keys
that :data:`cad.design.targets.TARGET_KEYS` names; ``evaluate`` compares them
with the targets and returns one row per target.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import asdict, dataclass
from typing import Any

from cad.design.targets import Target


@dataclass(frozen=True)
class CheckRow:
    """One target against its computed value. ``gap_rel`` = (computed - reference) / |reference|."""

    key: str
    computed: float | None
    target: str
    ok: bool
    gap_rel: float | None
    target_data: dict[str, float] | None = None
    margin: float | None = None

    def as_dict(self) -> dict[str, Any]:
        """JSON row: ``target`` as data (``{"value", "tol_rel"}`` or ``{"min", "max"}``),
        ``target_text`` for display, ``margin`` in the key's unit (> 0: met by that much)."""
        d = asdict(self)
        d["target_text"] = d.pop("target")
        d["target"] = d.pop("target_data")
        return d


def values_from_report(report: dict[str, Any]) -> dict[str, float]:
    """Flatten the quantities a target can name from a build or analyze report."""
    vals: dict[str, float] = {}
    for k in ("H11_kg_m2", "H12_kg_m2", "H22_kg_m2", "H33_kg_m2", "stroke_mm", "dy_max_mm",
              "slope_max", "torque_mean_mNm", "torque_variation", "min_transmission_angle_deg",
              "min_clearance_mm"):
        v = report.get(k)
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            vals[k] = float(v)
    for k, v in (report.get("apparent_mass") or {}).items():
        if isinstance(v, (int, float)):
            vals[k] = float(v)
    st = report.get("structure") or {}
    if st:
        vals["first_mode_Hz"] = float(st["first_mode_Hz"])
        vals["max_stress_MPa"] = float(st["max_stress_MPa"])
        for ax in ("x", "z"):
            vals[f"compliance_{ax}_um_per_N"] = float(st["compliance_um_per_N"][ax])
    for k in ("D_min_kg_m2", "D_max_kg_m2"):
        if isinstance(report.get(k), (int, float)):
            vals[k] = float(report[k])
    links = report.get("links") or {}
    moving = 0.0
    for name in ("crank", "coupler", "rocker"):
        li = links.get(name) or {}
        m = li.get("mass_g", li.get("mass_kg", None))
        if m is None:
            continue
        g = float(m) if "mass_g" in li else float(m) * 1e3
        vals[f"{name}_mass_g"] = g
        moving += g
    if moving:
        vals["moving_mass_g"] = moving
    return vals


def evaluate(targets: tuple[Target, ...] | list[Target], values: dict[str, float]) -> list[CheckRow]:
    """Compare every target with its computed value (a missing value fails, with computed None)."""
    rows = []
    for t in targets:
        c = values.get(t.key)
        if c is None:
            rows.append(CheckRow(t.key, None, t.describe(), False, None, t.as_data()))
            continue
        rows.append(CheckRow(t.key, c, t.describe(), t.ok(c), t.gap(c), t.as_data(), t.margin(c)))
    return rows


def miss_line(key: str, target_text: str, best: float | None, written: float | None = None) -> str:
    """One line for one missed target (``optimize``, ``fit``): the key, the target and the best
    figure reached, 6 significant digits (a 35.004 miss of <= 35 stays visible); ``written``,
    the written design's figure, when it differs from ``best``."""
    def fmt(v):
        return "not computed" if v is None else f"{v:.6g}"

    line = f"target missed: {key} (target {target_text}): best reached {fmt(best)}"
    if written is not None and written != best:
        line += f", written design {fmt(written)}"
    return line


def best_reached(t: Target, seen: Iterable[Any]) -> float | None:
    """The figure among ``seen`` (the values of ``t.key`` over the candidates a search
    evaluated; None, NaN and non-numbers skipped) closest to meeting ``t``: the smallest
    :func:`violation` (for ``>= min`` the largest, for ``<= max`` the smallest); None when no
    candidate computed it. Ties keep the first seen."""
    vals = [float(v) for v in seen
            if isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)]
    return min(vals, key=lambda v: violation(t, v)) if vals else None


def violation(t: Target, computed: float) -> float:
    """How far outside its tolerance a value is, relative to the reference (0 when met)."""
    if t.value is not None:
        tol = t.tol_abs if t.tol_abs is not None else abs(t.value) * (t.tol_rel or 0.0)
        return max(0.0, abs(computed - t.value) - tol) / abs(t.value or 1.0)
    v = 0.0
    if t.max is not None and computed > t.max:
        v = (computed - t.max) / abs(t.max or 1.0)
    if t.min is not None and computed < t.min:
        v = max(v, (t.min - computed) / abs(t.min or 1.0))
    return v


def merge_targets(design_targets, cli_targets) -> tuple[Target, ...]:
    """CLI targets replace design targets with the same key; others are kept."""
    cli_keys = {t.key for t in cli_targets}
    return tuple(t for t in design_targets if t.key not in cli_keys) + tuple(cli_targets)
