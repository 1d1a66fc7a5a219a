"""Benchmark: ``hapticad sweep`` throughput with 1 and 2 Dask workers (issue 16 §1).

Each run is a fresh process ``hapticad sweep designs/hoeken.toml --vary
parts.bar_thickness_mm=LO:HI:N --workers W --out TMP --json`` with its own empty shape
cache, so every variant rebuilds its bars (as a new design would). Throughput is the
evaluation phase, variants per second: after the LocalCluster has started, every worker
has imported the CAD stack and the workers together have made the first variant's parts
into the shared cache (``startup_s``, reported apart, as is the whole command's
``wall_s``); the speed-up is 2-worker over 1-worker throughput (goal >= 1.7x on this
2-core machine), ``speedup_wall_total`` the same ratio of whole-command wall times. The machine is
shared with other jobs, so the 1-minute load average is recorded beside each run; the CPU time per variant
(``variant_cpu_s_median``, measured inside the worker) gives evaluations per hour per
dedicated core independently of that load.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from cad.bench.common import save_chart

ROOT = Path(__file__).resolve().parents[2]
GOAL_SPEEDUP = 1.7
REFERENCE = "goal: 2 workers >= 1.7x the throughput of 1 worker (issue 16 section 1)"


def _sweep(design: str, n: int, workers: int, tmp: Path, offset: float) -> dict:
    env = {**os.environ, "HAPTICAD_CACHE_DIR": str(tmp / f"shapes-{workers}-{offset}")}
    lo, hi = 5.0 + offset, 8.0 + offset
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    r = subprocess.run([sys.executable, "-m", "cad", "sweep", design, "--vary",
                        f"parts.bar_thickness_mm={lo}:{hi}:{n}", "--workers", str(workers),
                        "--out", str(tmp / f"out-{workers}-{offset}"), "--json"],
                       capture_output=True, text=True, env=env, cwd=ROOT)
    if r.returncode != 0:
        raise RuntimeError(f"sweep bench failed: {r.stderr.strip()[-500:]}")
    s = json.loads(r.stdout)
    s["load_avg_1min"] = load
    return s


def run(quick: bool, out_dir: Path, design: str = "designs/hoeken.toml") -> dict:
    """1- and 2-worker sweeps of ``n`` variants (``quick``: 8 variants, 1 repeat; else 32, 3:
    with 16 variants, 8 per worker, one variant of tail on one worker is 1/8 of its run)."""
    n, repeats = (8, 1) if quick else (32, 3)
    runs: dict[int, list[dict]] = {1: [], 2: []}
    with tempfile.TemporaryDirectory(prefix="hapticad-bench-sweep-") as tmp:
        for rep in range(repeats):
            for w in (1, 2):
                runs[w].append(_sweep(design, n, w, Path(tmp), 0.001 * rep))
    rate = {w: statistics.median(s["variants_per_s"] for s in runs[w]) for w in runs}
    per_variant = {w: statistics.median(s["variant_wall_s_median"] for s in runs[w]) for w in runs}
    cpu = statistics.median(s["variant_cpu_s_median"] for w in runs for s in runs[w])
    speedup = rate[2] / rate[1]
    points = [{"method": f"{w} worker{'s' if w > 1 else ''}", "knob": "workers", "time_s": 1.0 / rate[w],
               "error": None, "variants_per_s": rate[w], "variant_wall_s_median": per_variant[w],
               "startup_s": statistics.median(s["startup_s"] for s in runs[w]),
               "wall_s": statistics.median(s["wall_s"] for s in runs[w]),
               "client_cpu_s": statistics.median(s.get("client_cpu_s") or 0.0 for s in runs[w]),
               "load_avg_1min": [s["load_avg_1min"] for s in runs[w]]} for w in (1, 2)]
    return {
        "topic": "sweep", "reference": REFERENCE, "design": design, "variants": n, "repeats": repeats,
        "variants_per_s_1": rate[1], "variants_per_s_2": rate[2], "speedup_2_workers": speedup,
        "speedup_wall_total": points[0]["wall_s"] / points[1]["wall_s"],
        "evaluations_per_hour_1_worker": 3600.0 * rate[1],
        "variant_cpu_s_median": cpu,
        "evaluations_per_hour_per_core": 3600.0 / cpu,
        "task_bytes_in_median": runs[1][0]["task_bytes_in_median"],
        "task_bytes_out_median": runs[1][0]["task_bytes_out_median"],
        "points": points, "runs": runs,
        "charts": _chart(points, speedup, Path(out_dir)),
    }


def _chart(points, speedup: float, out_dir: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt


    fig, ax = plt.subplots(figsize=(5, 4))
    ax.bar([p["method"] for p in points], [p["variants_per_s"] for p in points], color=["#337ab7", "#5cb85c"])
    ax.set_ylabel("variants per second (evaluation phase, median)")
    ax.set_title(f"hapticad sweep: speed-up {speedup:.2f}x with 2 workers", fontsize=10)
    fig.suptitle(REFERENCE, fontsize=8)
    fig.tight_layout(rect=(0, 0, 1, 0.93))
    paths = save_chart(fig, out_dir, "sweep_throughput")
    plt.close(fig)
    return paths
