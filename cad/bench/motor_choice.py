"""Benchmark: how the co-design search gets its motor (issue 35 §1): screened per trial on the
cheap model (:func:`cad.studies.codesign.search.screen_motor`, the default) against the motor as
one more TPE categorical over the same catalog motors, and against the categorical over the two
motors the search chose among before (RE 35, RE 40).

Per brief and seed: one in-process search (:func:`cad.studies.codesign.search.run`, the
hand-written starts in) of ``trials`` trials; the best feasible cheap M11 (g, None when no trial
was feasible), its motor, the feasible trials and the wall time. The reference is the other
method on the same seeds: a lower mean best M11 at the same budget is the better search. No
accuracy knob: ``error`` is None.
"""

from __future__ import annotations

import statistics
import time
from pathlib import Path

from cad.design import load_design
from cad.studies.codesign import search

ROOT = Path(__file__).resolve().parents[2]
REFERENCE = "issue 35 §1: the motor screened per trial against a TPE categorical (same seeds, same budget)"
#: (brief, trials): the direct-drive light brief and the capstan Hoeken (the search of the
#: 150-trial test tests/unit/studies/test_optimize_capstan.py)
BRIEFS = (("designs/hoeken_light_brief.toml", 200), ("designs/hoeken_capstan.toml", 150))
#: method -> (Problem.motor_choice, motors searched: None = search.searched_motors())
METHODS = {"screen": ("screen", None), "categorical": ("categorical", None),
           "categorical RE 35 / RE 40": ("categorical", ("maxon-re35", "maxon-re40"))}


def one(brief: str, trials: int, seed: int, method: str) -> dict:
    """One search; its best feasible cheap M11 (g), motor, feasible trials, wall (s)."""
    choice, motors = METHODS[method]
    keep = search.MOTOR_CONTINUOUS_TORQUE_MNM
    if motors is not None:
        search.MOTOR_CONTINUOUS_TORQUE_MNM = {k: search.MOTORS[k].torque_continuous_mNm for k in motors}
    try:
        d = load_design(ROOT / brief)
        pb = search.problem_from(d)
        pb.fixed_parts = search.fixed_parts(d)
        pb.motor_choice = choice
        t0 = time.perf_counter()
        cands, _ = search.run(pb, trials, seed=seed)
        wall = time.perf_counter() - t0
    finally:
        search.MOTOR_CONTINUOUS_TORQUE_MNM = keep
    best = cands[0] if cands else None
    return {"seed": seed, "best_M11_g": None if best is None else best.cheap["M11_max_g"],
            "motor": None if best is None else best.parts["motor"], "feasible": len(cands), "wall_s": wall}


def run(quick: bool, out_dir: Path) -> dict:  # noqa: ARG001 - no charts
    """Every brief x method x seed (``quick``: seeds 0-1; else 0-7)."""
    seeds = range(2) if quick else range(8)
    out = {"topic": "motor_choice", "reference": REFERENCE, "motors": list(search.searched_motors()),
           "seeds": list(seeds), "briefs": [], "points": [], "charts": []}
    for brief, trials in BRIEFS:
        row = {"brief": brief, "trials": trials, "methods": {}}
        for method in METHODS:
            runs = [one(brief, trials, s, method) for s in seeds]
            found = [r["best_M11_g"] for r in runs if r["best_M11_g"] is not None]
            row["methods"][method] = {"runs": runs, "no_feasible": len(runs) - len(found),
                                      "mean_best_M11_g": statistics.mean(found) if found else None,
                                      "median_best_M11_g": statistics.median(found) if found else None}
            out["points"].append({"method": f"{method} ({Path(brief).stem})", "knob": "seed",
                                  "time_s": statistics.mean(r["wall_s"] for r in runs), "error": None})
        out["briefs"].append(row)
    return out
