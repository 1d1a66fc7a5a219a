"""Benchmark: trials per second of the co-design search on Dask with 1 and 2 local workers
(issue 35 §4: one run, ratio).

Each point is a fresh process, ``hapticad optimize designs/hoeken_light_brief.toml --trials N
--exact-top 1 --workers W --study TMP --json`` into a new study folder; the throughput is the
report's ``study.trials_per_s``: the trials over the evaluation phase, after the LocalCluster
has started and its workers imported optuna and the cheap model (``startup_s``, reported
apart), before the exact re-evaluation. The 1- and 2-worker runs are interleaved so that the
machine's load drifts alike for both; medians of the repeats and their ratio. The in-process
search (no Dask, in-memory study) of the same trials is the reference point: its
``search_wall_s``. No accuracy knob: ``error`` is None.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DESIGN = "designs/hoeken_light_brief.toml"
REFERENCE = "issue 35: trials per second of optimize with 1 and 2 local Dask workers (one run, ratio)"


def _optimize(trials: int, workers: int | None, study: Path) -> dict:
    """One ``hapticad optimize`` process; its report (exit 1, a missed target, is a result)."""
    extra = [] if workers is None else ["--workers", str(workers), "--study", str(study)]
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    r = subprocess.run([sys.executable, "-m", "cad", "optimize", DESIGN, "--trials", str(trials),
                        "--exact-top", "1", *extra, "--json"], capture_output=True, text=True, cwd=ROOT)
    if r.returncode not in (0, 1) or not r.stdout.strip():
        raise RuntimeError(f"optimize bench failed: {r.stderr.strip()[-500:]}")
    rep = json.loads(r.stdout)
    rep["load_avg_1min"] = load
    return rep


def run(quick: bool, out_dir: Path) -> dict:  # noqa: ARG001 - no charts
    """In-process, 1- and 2-worker searches of ``trials`` trials (``quick``: 60 trials, 1
    repeat; else 200 trials, 3 repeats), interleaved."""
    trials, repeats = (60, 1) if quick else (200, 3)
    runs: dict[str, list[dict]] = {"in-process": [], "1": [], "2": []}
    with tempfile.TemporaryDirectory(prefix="hapticad-bench-optimize-") as tmp:
        for rep in range(repeats):
            for key in runs:
                w = None if key == "in-process" else int(key)
                runs[key].append(_optimize(trials, w, Path(tmp) / f"study-{key}-{rep}"))
    rate = {"in-process": statistics.median(trials / r["search_wall_s"] for r in runs["in-process"])}
    for w in ("1", "2"):
        rate[w] = statistics.median(r["study"]["trials_per_s"] for r in runs[w])
    points = [{"method": "in-process (no Dask)", "knob": "workers", "time_s": 1.0 / rate["in-process"],
               "error": None, "trials_per_s": rate["in-process"]}]
    for w in ("1", "2"):
        points.append({"method": f"{w} worker{'s' if w == '2' else ''}", "knob": "workers",
                       "time_s": 1.0 / rate[w], "error": None, "trials_per_s": rate[w],
                       "startup_s": statistics.median(r["study"]["startup_s"] for r in runs[w]),
                       "trials_per_s_runs": [r["study"]["trials_per_s"] for r in runs[w]],
                       "load_avg_1min": [r["load_avg_1min"] for r in runs[w]]})
    return {"topic": "optimize", "reference": REFERENCE, "design": DESIGN, "trials": trials,
            "repeats": repeats, "trials_per_s_in_process": rate["in-process"],
            "trials_per_s_1": rate["1"], "trials_per_s_2": rate["2"], "ratio_2_workers": rate["2"] / rate["1"],
            "cpu_count": os.cpu_count(), "points": points, "charts": []}
