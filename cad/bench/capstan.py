"""Benchmark: the capstan Hoeken's cold build against the direct Hoeken's (issue 35: within
1.2 x, one run, ratio).

Each point is a fresh process, ``python -m cad build DESIGN --out TMP --no-cache --json``
with the bd_warehouse shape cache filled (the ``cold`` case of :mod:`cad.bench.build`), the
two designs interleaved so that the machine's load drifts alike for both; medians of the
repeats and their ratio. No accuracy knob: ``error`` is None.
"""

from __future__ import annotations

import os
import statistics
import tempfile
from pathlib import Path

from cad.bench.build import run_process

DESIGNS = {"direct": "designs/hoeken.toml", "capstan": "designs/hoeken_capstan.toml"}
RATIO_GOAL = 1.2
REFERENCE = "issue 35: the capstan Hoeken's cold build within 1.2 x the direct Hoeken's"


def run(quick: bool, out_dir: Path) -> dict:
    """Cold builds of both designs, interleaved (``quick``: 2 repeats each, else 5), after one
    warm-up build of each that fills the shape cache."""
    repeats = 2 if quick else 5
    times: dict[str, list[float]] = {k: [] for k in DESIGNS}
    with tempfile.TemporaryDirectory(prefix="hapticad-bench-capstan-") as tmp:
        env = {**os.environ, "HAPTICAD_CACHE_DIR": str(Path(tmp) / "shapes")}
        for name, design in DESIGNS.items():  # fill the shape cache (bearings, screws)
            run_process(["build", design, "--out", str(Path(tmp) / name), "--no-cache", "--json"], env)
        for _ in range(repeats):
            for name, design in DESIGNS.items():
                times[name].append(run_process(["build", design, "--out", str(Path(tmp) / name),
                                         "--no-cache", "--json"], env))
    med = {k: statistics.median(v) for k, v in times.items()}
    ratio = med["capstan"] / med["direct"]
    points = [{"method": f"cold build, {k}", "knob": "process wall", "time_s": med[k],
               "error": None, "times_s": times[k]} for k in DESIGNS]
    return {"topic": "capstan", "reference": REFERENCE, "designs": DESIGNS, "repeats": repeats,
            "direct_cold_s": med["direct"], "capstan_cold_s": med["capstan"], "ratio": ratio,
            "ratio_goal": RATIO_GOAL, "meets_goal": ratio <= RATIO_GOAL,
            "cpu_count": os.cpu_count(),
            "load_avg_1min": os.getloadavg()[0] if hasattr(os, "getloadavg") else None,
            "points": points, "charts": []}
