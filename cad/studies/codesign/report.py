"""The optimize report and its Pareto chart (M11 max against torque variation)."""

from __future__ import annotations

import time
from pathlib import Path

from cad.bench.common import save_chart
from cad.datasheet.run import device_datasheet
from cad.design import bounds, parse_design
from cad.errors import HapticadError
from cad.families.fourbar.limits import prototype_limits
from cad.studies.codesign import distributed, exact, prototype, search
from cad.studies.codesign.prototype import judged, motor_bound, prototype_design


def optimize_fourbar(design, objective: str, trials: int, seed: int, top: int, chart_dir: Path | None,
                     progress=None, out_stem: str | None = None,
                     proportions_tol: float = 0.0, starts: bool = True,
                     beat_prototype: bool = False, where: dict | None = None) -> tuple[dict, object]:
    """Search (cheap model), re-evaluate the best ``top`` candidates exactly, pick the lightest
    accepted one. ``starts=False``: without the hand-written :data:`search.STARTS`.
    ``beat_prototype``: the brief of :mod:`cad.studies.codesign.prototype` (every trial judged
    on every limit; without an accepted design, the report's ``prototype_front``).
    The report's ``misses``: the design's targets the accepted optimum misses
    (:func:`cad.studies.codesign.exact.misses`). Warnings of the exact re-evaluations are
    dropped but the accepted candidate's (the design ``--out`` writes), said once. Returns (JSON-able report, accepted Candidate
    or None). ``where``: run the search on Dask (:func:`cad.studies.codesign.distributed.run`:
    ``study`` folder, ``workers`` or ``scheduler``); the report then has a ``study`` entry.
    None: in this process, as always."""
    t0 = time.perf_counter()
    if beat_prototype:

        design = prototype_design(design)
    pb = search.problem_from(design)
    pb.fixed_parts = search.fixed_parts(design)
    pb.proportions_tol = proportions_tol
    pb.all_limits = beat_prototype
    cands, records, study = _search(pb, trials, seed, starts, where, progress,
                                    {"objective": objective, "proportions_tol": proportions_tol,
                                     "starts": starts, "beat_prototype": beat_prototype})
    t_search = time.perf_counter() - t0
    checked, best, best_said = [], None, []
    seen = set()
    for c in cands:
        key = (repr(sorted(c.parts.items())), round(c.mechanism["phi1_min_deg"], 1))
        if key in seen:
            continue
        seen.add(key)
        if len(checked) >= top:
            break
        if progress:
            progress(f"exact re-evaluation {len(checked) + 1}/{top} (cheap M11 {c.cheap['M11_max_g']:.2f} g)")
        with bounds.muted() as said:  # a candidate's warnings: re-said only for the one written
            try:
                ex = exact.evaluate(design, c, f"{design.name}_candidate")
            except HapticadError as exc:
                checked.append({"trial": c.number, "parts": c.parts, "mechanism": c.mechanism, "transmission": c.transmission,
                                "rejected": str(exc)})
                continue
            checked.append({"trial": c.number, "parts": c.parts, "mechanism": c.mechanism,
                            "transmission": c.transmission, "exact": ex})
            if beat_prototype:
                ex["datasheet"] = _datasheet_check(design, c)
        if exact.accepted(ex) and (not beat_prototype or ex["datasheet"]["ok"]) and (best is None or ex["M11_max_g"] < best[1]["M11_max_g"]):
            best, best_said = (c, ex), said
    for w in best_said:
        bounds.warn(w)
    front = search.pareto(records)
    rep = {
        "design": design.name, "family": design.family, "objective": objective,
        "library": "optuna TPE (multivariate, seeded)", "trials": trials, "seed": seed,
        "hand_written_starts": len(search.STARTS) if starts else 0,
        "feasible_trials": sum(r["value"] is not None for r in records),
        "requirements": {"stroke_mm": pb.stroke_mm, "dy_max_mm": pb.dy_max_mm,
                         "min_transmission_angle_deg": pb.mu_min_deg, "force_N": design.force_N,
                         "motor_continuous_torque_mNm": search.MOTOR_CONTINUOUS_TORQUE_MNM},
        "search_wall_s": t_search, "exact_checked": checked,
        "best": None if best is None else {"trial": best[0].number, "mechanism": best[0].mechanism,
                                           "parts": best[0].parts, "transmission": best[0].transmission,
                                           "layer_order": best[1]["layers"],
                                           "cheap": _clean(best[0].cheap), "exact": best[1]},
        "layer_orders_searched": None if "layer_order" in pb.fixed_parts else list(search.LAYER_ORDERS),
        "pareto_front": [{k: r[k] for k in ("trial", "M11_max_g", "torque_variation", "footprint_mm2")}
                         for r in front],
        "wall_s": time.perf_counter() - t0,
        "misses": [] if best is None else exact.misses(best[1], checked),
        "infeasible_reasons": infeasible_reasons(records),
        **({} if study is None else {"study": study}),  # on Dask: the journal, workers, timings
    }
    if beat_prototype:
        rep["prototype"] = _prototype_report(design, pb, records, best, chart_dir, out_stem)
        rep["wall_s"] = time.perf_counter() - t0
    if chart_dir is not None:
        rep["chart"] = plot_pareto(records, front, best, chart_dir / f"{out_stem or design.name}_pareto")
    return rep, (best[0] if best else None)


def _search(pb, trials: int, seed: int, starts: bool, where: dict | None, progress,
            options: dict) -> tuple[list, list[dict], dict | None]:
    """(candidates, records, the report's ``study`` entry or None): the search in this process
    (``where`` None) or on Dask (:func:`cad.studies.codesign.distributed.run`, ``options``
    the search options that name its study)."""
    if where is None:
        return (*search.run(pb, trials, seed, starts=starts), None)
    return distributed.run(pb, trials, seed, starts, {**where, "options": options}, progress)


def infeasible_reasons(records: list[dict], most: int = 5) -> list[dict]:
    """The commonest reasons trials were infeasible on the cheap model, most first: [{"reason"
    (the reason's first two clauses: the check and the field), "trials"}]."""
    count: dict[str, int] = {}
    for r in records:
        why = r.get("infeasible")
        if why:
            key = ": ".join(why.split(": ")[:2])[:100]
            count[key] = count.get(key, 0) + 1
    top = sorted(count.items(), key=lambda kv: -kv[1])[:most]
    return [{"reason": k, "trials": n} for k, n in top]


def _datasheet_check(design, cand) -> dict:
    """The full datasheet of a candidate (:func:`cad.datasheet.run.device_datasheet`: a build at
    inertia fidelity, the reduced-model wall threshold for K_max; a figure within its sampling
    error of the limit is "within sampling error", not a miss): {key: (value, verdict)} of
    its limited rows and ``ok``."""
    d = parse_design(exact.candidate_raw(design, cand, f"{design.name}_candidate"), str(design.source))
    ds = device_datasheet(d)
    rows = {r["key"]: {"value": r["value"], "verdict": r["verdict"],
                       "limit": None if r["limit"] is None else f"{r['limit']['op']} {r['limit']['value']:g}"}
            for r in ds["rows"] if r["limit"] is not None or r["key"] == "M11_g"}
    m11 = rows.get("M11_g")
    if m11 is not None and m11["value"] is not None:  # the M11 limit is a brief target, not a datasheet row's
        lim = next((t for t in design.targets if t.key == "M11_max_g" and t.max is not None), None)
        if lim is not None:
            m11["limit"] = f"<= {lim.max:g}"
            m11["verdict"] = "ok" if m11["value"] <= lim.max else "miss"
    return {"ok": ds["ok"] and all(v["verdict"] != "miss" for v in rows.values()), "rows": rows,
            "warnings": ds["warnings"]}


def _prototype_report(design, pb, records, best, chart_dir, out_stem) -> dict:
    """The --beat-prototype part of the report: the limits, the motors' bound, and without an
    accepted design the Pareto front of (continuous force, friction) with its two ends
    verified on the full datasheet."""
    lim = prototype_limits()
    out = {"limits": {k: {"op": v.op, "value": v.value, "reason": v.reason} for k, v in lim.items()},
           "motor_bounds": [prototype.motor_bound(k) for k in search.MOTOR_CONTINUOUS_TORQUE_MNM],
           "met_by": None if best is None else best[0].number}
    keep = ("trial", "M11_max_g", "first_mode_Hz", "max_stress_MPa", "stroke_mm", "dy_max_mm",
            "continuous_force_N", "friction_N")
    out["judged_trials"] = len(prototype.judged(records))
    out["fronts"] = {}
    for name, x, y, relaxed in prototype.FRONTS:
        fr = prototype.front(records, x, y, relaxed)
        pts = [{**{k: r.get(k) for k in keep}, "motor": pb.evaluated[r["trial"]].parts["motor"],
                "bar_material": pb.evaluated[r["trial"]].parts["bar_material"],
                "crank_span_deg": pb.evaluated[r["trial"]].mechanism["phi1_max_deg"]
                - pb.evaluated[r["trial"]].mechanism["phi1_min_deg"]} for r in fr]
        ends = [] if not fr else ([fr[0], fr[-1]] if len(fr) > 1 else [fr[0]])
        out["fronts"][name] = {
            "x": x, "y": y, "relaxed": list(relaxed), "points": pts,
            "ends_exact": [{"trial": r["trial"], **_datasheet_check(design, pb.evaluated[r["trial"]])}
                           for r in ends]}
    if chart_dir is not None:
        out["chart"] = plot_fronts(records, out["fronts"], lim, chart_dir / f"{out_stem or design.name}_front")
    return out


def plot_fronts(records, fronts: dict, lim, stem: Path) -> list[str]:
    """One panel per front: the judged trials meeting every other limit, the front, the two
    limits."""
    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.5 * len(fronts), 4.5))
    axes = np.atleast_1d(fig.subplots(1, len(fronts)))
    for ax, f in zip(axes, fronts.values(), strict=True):
        x, y = f["x"], f["y"]
        allowed = {x, y, *f["relaxed"]}
        pts = [r for r in judged(records) if set(r["misses"]) <= allowed]
        ax.scatter([r[y] for r in pts], [r[x] for r in pts], s=8, c="0.7",
                   label="trials meeting every other limit" + (f" ({', '.join(f['relaxed'])} relaxed)"
                                                               if f["relaxed"] else "") + ", cheap model")
        ax.plot([r[y] for r in f["points"]], [r[x] for r in f["points"]], "o-", color="C0", ms=4,
                label="Pareto front")
        if (x, y) == ("continuous_force_N", "friction_N"):  # F_cont / F_s <= T_cont / (Kt I0)

            fs = np.linspace(lim[y].value * 0.9, max([r[y] for r in pts] + [lim[y].value]) * 1.05, 2)
            for i, k in enumerate(search.MOTOR_CONTINUOUS_TORQUE_MNM):
                b = motor_bound(k)
                ax.plot(fs, b["ratio"] * fs, ls=":", color=f"C{4 + i}", lw=1,
                        label=f"{k}: bound T_cont / (Kt I0) = {b['ratio']:.1f}")
        ax.axhline(lim[x].value, color="C3", lw=1, ls="--", label=f"{x} {lim[x].op} {lim[x].value:g}")
        ax.axvline(lim[y].value, color="C2", lw=1, ls="--", label=f"{y} {lim[y].op} {lim[y].value:g}")
        ax.set_xlabel(y)
        ax.set_ylabel(x)
        ax.set_ylim(0.0, max([r[x] for r in pts] + [lim[x].value]) * 1.25)
        ax.grid(True, lw=0.3)
        ax.legend(fontsize=7)
    return save_chart(fig, stem.parent, stem.name)


def _clean(d: dict) -> dict:
    return {k: v for k, v in d.items() if k != "mechanism"}


def plot_pareto(records, front, best, stem: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure


    ok = [r for r in records if r.get("value") is not None]
    fig = Figure(figsize=(6.5, 4.5))
    ax = fig.subplots()
    ax.scatter([r["torque_variation"] for r in ok], [r["M11_max_g"] for r in ok], s=8, c="0.7",
               label="feasible trials (cheap model)")
    ax.plot([r["torque_variation"] for r in front], [r["M11_max_g"] for r in front], "o-", color="C0",
            ms=4, label="Pareto front (cheap model)")
    if best is not None:
        ax.plot([best[1]["torque_variation"]], [best[1]["M11_max_g"]], "*", color="C3", ms=14,
                label=f"optimum on exact solids: {best[1]['M11_max_g']:.1f} g")
    ax.set_xscale("log")
    ax.set_xlabel("torque variation (Table I, max |tau - <tau>| / <tau>)")
    ax.set_ylabel("M11 max over the stroke (g)")
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8)
    return save_chart(fig, stem.parent, stem.name)
