"""The optimize report and its Pareto chart (M11 max against torque variation)."""

from __future__ import annotations

import time
from pathlib import Path


def optimize_fourbar(design, objective: str, trials: int, seed: int, top: int, chart_dir: Path | None,
                     progress=None, out_stem: str | None = None,
                     proportions_tol: float = 0.0, starts: bool = True) -> tuple[dict, object]:
    """Search (cheap model), re-evaluate the best ``top`` candidates exactly, pick the lightest
    accepted one. ``starts=False``: without the hand-written :data:`search.STARTS`.
    Returns (JSON-able report, accepted Candidate or None)."""
    from cad.errors import HapticadError
    from cad.studies.codesign import exact, search

    t0 = time.perf_counter()
    pb = search.problem_from(design)
    pb.fixed_parts = search.fixed_parts(design)
    pb.proportions_tol = proportions_tol
    cands, records = search.run(pb, trials, seed, starts=starts)
    t_search = time.perf_counter() - t0
    checked, best = [], None
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
        try:
            ex = exact.evaluate(design, c, f"{design.name}_candidate")
        except HapticadError as exc:
            checked.append({"trial": c.number, "parts": c.parts, "mechanism": c.mechanism,
                            "rejected": str(exc)})
            continue
        checked.append({"trial": c.number, "parts": c.parts, "mechanism": c.mechanism, "exact": ex})
        if exact.accepted(ex) and (best is None or ex["M11_max_g"] < best[1]["M11_max_g"]):
            best = (c, ex)
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
                                           "parts": best[0].parts, "layer_order": best[1]["layers"],
                                           "cheap": _clean(best[0].cheap), "exact": best[1]},
        "layer_orders_searched": None if "layer_order" in pb.fixed_parts else list(search.LAYER_ORDERS),
        "pareto_front": [{k: r[k] for k in ("trial", "M11_max_g", "torque_variation", "footprint_mm2")}
                         for r in front],
        "wall_s": time.perf_counter() - t0,
    }
    if chart_dir is not None:
        rep["chart"] = plot_pareto(records, front, best, chart_dir / f"{out_stem or design.name}_pareto")
    return rep, (best[0] if best else None)


def _clean(d: dict) -> dict:
    return {k: v for k, v in d.items() if k != "mechanism"}


def plot_pareto(records, front, best, stem: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    from cad.bench.common import save_chart

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
