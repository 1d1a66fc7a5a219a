"""The device datasheet (issue 24): every figure a haptics reviewer asks for, from the model.

:func:`datasheet` turns a design and its build report (``report.json`` before the
``datasheet`` key is added) into ``{"family", "rows", "warnings", "ok", "notes"}``. Each row:

* ``key`` (stable, JSON), ``figure`` (words), ``value`` (the governing value: the minimum over
  the workspace for a force, the maximum for a resolution or a friction), ``min`` / ``max``
  over the workspace where the figure varies (else None), ``unit``;
* ``model``: the model or source the value comes from, ``boundary``: the boundary conditions
  of a structural figure (crank held or free, handle free or loaded), ``unverified``: True
  when it uses a value without a public source (:class:`cad.data.catalog.MotorSpec`);
* ``limit`` (:mod:`cad.datasheet.limits`, None for a figure without one) and ``verdict``:
  ``"ok"``, ``"miss"``, ``"info"`` or ``"within sampling error"`` (a miss smaller than the
  row's ``sampling_error_rel``, the simulated K_max's); ``paper``: the paper's measured value where it gives one.

``warnings`` holds one line per missed limit (figure, value, limit, key to change). Pure
numpy, no CAD import: computed by the build dispatcher and by ``hapticad datasheet``.
"""

from __future__ import annotations

import math
from typing import Any

from cad.datasheet.limits import Limit, loosened_notes
from cad.families import family_package
from cad.io.escape import md
from cad.tolerances import RANGE_SAME_REL


def row(key: str, figure: str, value, unit: str, model: str, *, lo=None, hi=None,
        boundary: str = "", unverified: bool = False, paper=None, inputs=None) -> dict[str, Any]:
    """One datasheet row (module docstring); ``value`` None: not computable (model says why).
    ``inputs``: the model's input values (SI, named), for a row another output reads them from
    (``eq25_K_max_N_per_m``: the firmware's wall)."""
    def f(v):
        return None if v is None else float(v)

    out = {"key": key, "figure": figure, "value": f(value), "min": f(lo), "max": f(hi),
           "unit": unit, "model": model, "boundary": boundary, "unverified": bool(unverified),
           "paper": paper, "limit": None, "verdict": "info"}
    if inputs is not None:
        out["inputs"] = {k: float(v) for k, v in inputs.items()}
    return out


def clearance_parts(report: dict) -> str:
    """``"; between <part a> and <part b>"`` of the build's smallest clearance (its
    interference report's closest pair: two different parts on two bodies; a bought part's own
    gap, a bearing's rings, is not one: :func:`cad.assembly.interference.own_part_gaps`), or
    ``""`` when the report names none."""
    parts = [p for p in ((report.get("interference") or {}).get("closest") or {}).get("parts", ()) if p]
    return f"; between {parts[0]} and {parts[1]}" if len(parts) == 2 else ""


def judge(rows: list[dict], limits: dict[str, Limit]) -> list[str]:
    """Verdicts on ``rows`` from ``limits`` (in place); returns the warning lines."""
    warnings = []
    for r in rows:
        lim = limits.get(r["key"])
        if lim is None:
            continue
        r["limit"] = lim.as_dict()
        ok = lim.met(r["value"])
        r["verdict"] = "ok" if ok else "miss"
        if not ok and within_sampling_error(r, lim):
            r["verdict"] = WITHIN_ERROR
        elif not ok:
            warnings.append(warning_line(r, lim))
    return warnings


#: Verdict of a figure that misses its limit by less than its own stated sampling error
#: (``sampling_error_rel`` of the row: the simulated K_max): neither met nor missed.
WITHIN_ERROR = "within sampling error"


def within_sampling_error(r: dict, lim: Limit) -> bool:
    """True when the row's value moved by its ``sampling_error_rel`` (either way) meets ``lim``."""
    e, v = r.get("sampling_error_rel"), r.get("value")
    return bool(e) and v is not None and (lim.met(v * (1.0 + e)) or lim.met(v * (1.0 - e)))


def with_unit(x: float, unit: str) -> str:
    """``x`` to 4 significant digits, then its unit (nothing after a unitless figure)."""
    return f"{x:.4g} {unit}" if unit else f"{x:.4g}"


def warning_line(r: dict, lim: Limit) -> str:
    """``<figure> = <value> <unit>, limit <op> <limit> <unit> (<reason>); change <keys>``."""
    v = "not computed" if r["value"] is None else with_unit(r["value"], r["unit"])
    return (f"{r['figure']} = {v}, limit {lim.op} {with_unit(lim.value, r['unit'])} ({lim.reason}); "
            f"change {lim.change}")


def default_limit_misses(ds: dict) -> list[str]:
    """The warning lines (:func:`warning_line`'s form) of the rows of ``ds`` (:func:`datasheet`)
    that miss a default limit (``limit["origin"] == "default"``; a limit the design's
    ``[targets]`` set is the caller's target, not listed here)."""
    out = []
    for r in ds["rows"]:
        lim = r.get("limit") or {}
        if lim.get("origin") == "default" and r.get("verdict") == "miss":
            v = "not computed" if r["value"] is None else with_unit(r["value"], r["unit"])
            out.append(f"{r['figure']} = {v}, limit {lim['op']} {with_unit(lim['value'], r['unit'])} "
                       f"({lim['reason']}); change {lim['change']}")
    return out


def datasheet(design, report: dict, out_dir=None, simulate_wall: bool = True) -> dict[str, Any]:
    """The datasheet of a built device (module docstring), dispatched on the family.
    ``out_dir``: where a family may write its chart (the pantographs' force ellipses);
    the chart's file name is then in ``notes`` and ``charts``. ``simulate_wall=False``: no
    wall simulation (the four-bar K_max row says so; evaluation builds)."""
    fam = getattr(design, "family", "")
    rows_and_limits = family_package(fam).datasheet_rows
    rows, limits, notes = rows_and_limits(design, report, out_dir=out_dir, simulate_wall=simulate_wall)
    rows += cost_rows(report)
    warnings = judge(rows, limits)
    charts = [n.rsplit(": ", 1)[1] for n in notes if n.startswith("force ellipses")]
    return {"family": fam, "rows": rows, "warnings": warnings, "ok": not warnings,
            "notes": loosened_notes(rows) + notes, "charts": charts}


def cost_rows(report: dict) -> list[dict]:
    """The BOM cost row of every family when the build was priced (``report["order"]``,
    :func:`cad.export.order.apply_prices`: ``--prices FILE.csv`` or the design's ``[prices]``):
    the total of the priced lines, in the price table's currency; the model names the price
    source and how many lines are unpriced (not in the total). No row without a price."""
    order = report.get("order") or {}
    if not order.get("priced_lines"):
        return []
    n, m = order["unpriced_lines"], order["priced_lines"] + order["unpriced_lines"]
    left = "every line priced" if n == 0 else f"{n} of {m} lines unpriced, not in the total"
    return [row("bom_cost", "BOM cost (priced lines)", order["total_price"], order.get("currency") or "",
                f"sum of quantity x unit price from {order.get('price_source') or 'the price table'}; "
                f"{left}")]


def fmt_value(r: dict) -> str:
    """Display text of a row's value and range (``2.92 (2.89 .. 2.95)``)."""
    v = r["value"]
    if v is None:
        return "—"
    s = _num(v)
    if r["min"] is not None and r["max"] is not None and not math.isclose(r["min"], r["max"], rel_tol=RANGE_SAME_REL):
        s += f" ({_num(r['min'])} .. {_num(r['max'])})"
    return s


def _num(v: float) -> str:
    return f"{v:.4g}"


def verdict_text(r: dict) -> str:
    lim = r.get("limit")
    if lim is None:
        return "—"
    word = {"ok": "ok", WITHIN_ERROR: WITHIN_ERROR}.get(r["verdict"], "MISS")
    looser = f"; [targets], looser than the default {lim['loosens'].split(' (')[0]}" if lim.get("loosens") else ""
    return f"{word} ({lim['op']} {lim['value']:.4g}{looser})"


def markdown(ds: dict) -> list[str]:
    """The datasheet as markdown lines (report.md, docs/datasheet.md)."""
    lines = ["## Datasheet", "", "| figure | value (min .. max) | unit | model / source | verdict |",
             "|---|---|---|---|---|"]
    for r in ds["rows"]:
        model = r["model"] + (f"; {r['boundary']}" if r["boundary"] else "")
        model += " (uses unverified data)" if r["unverified"] else ""
        if r.get("paper") is not None:
            model += f"; paper: {r['paper']}"
        lines.append(f"| {md(r['figure'])} | {fmt_value(r)} | {md(r['unit'])} | {md(model)} | "
                     f"{verdict_text(r)} |")
    if ds["warnings"]:
        lines += ["", *[f"- **warning:** {md(w)}" for w in ds["warnings"]]]
    for n in ds.get("notes", ()):
        lines.append(f"- {md(n)}")
    return lines + [""]
