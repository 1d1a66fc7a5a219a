"""Benchmark: cold ``hapticad build`` of the other families, and the PowerMouse motion check.

1. ``cold`` -- each point a fresh process, ``python -m cad build DESIGN --out TMP --no-cache
   --json`` with the shape cache filled by one untimed build (what a changed design costs
   on a machine that has built before), median of the repeats: the PowerMouse (goal
   <= 8 s, issue 16 section 3; measured 27-46 s before the fast-then-exact check), and in
   the full run the plain 5-bar and the twin pantograph;
2. ``motion check`` (in-process, PowerMouse, 52 extreme poses of the +-3 mm / +-5 deg
   range): :func:`cad.assembly.interference.pose_clearances` as built (fcl mesh distance at every
   pose, exact OCCT only within 2 tol + 0.05 mm of contact and at each group's closest
   pose) against the reference with every pose exact (``near_mm = inf``). Wall and CPU
   times are both recorded: on a shared machine the CPU time (process + children) is the
   better estimate of an idle machine's cost. Error = the
   largest |clearance - reference| over the poses (mm): 0 where both are exact, at most
   the mesh deviation (2 x 0.05 mm) elsewhere, by construction.
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from cad.assembly import interference as itf
from cad.bench.common import save_chart
from cad.design import load_design
from cad.families.powermouse import assemble
from cad.families.powermouse.motion import pose_group

ROOT = Path(__file__).resolve().parents[2]
DESIGNS = {
    "powermouse": "designs/powermouse.toml",
    "pantograph": "designs/pantograph.toml",
    "twin-pantograph": "designs/haptic_mouse.toml",
}
GOALS_S = {"powermouse": 8.0}
REFERENCE = (
    "goal: hapticad build designs/powermouse.toml cold <= 8 s (issue 16 section 3); "
    "motion check against every pose exact"
)


def _run(design: str, out: Path, env: dict) -> tuple[float, float]:
    """(wall s, CPU s of the process and its children) of one build."""
    import resource

    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    r = subprocess.run(
        [sys.executable, "-m", "cad", "build", design, "--out", str(out), "--no-cache", "--json"],
        capture_output=True,
        text=True,
        env=env,
        cwd=ROOT,
    )
    dt = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        raise RuntimeError(f"hapticad build {design} failed: {r.stderr.strip()}")
    return dt, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def motion_check(repeats: int) -> dict:
    """Time the PowerMouse's one interference check (:func:`cad.assembly.interference.check_model`
    over the flotor's excursions, as its build runs it: the closest pose of each pose group
    measured exactly) against the same check with every pose measured exactly; compare the
    clearance of every pose."""
    d = load_design(ROOT / DESIGNS["powermouse"])
    model = assemble(d)
    every = {label: label for label in model.pose_labels}
    itf.check_model(model, groups=pose_group)  # warm-up: meshes and OCCT caches, not timed
    out = {}
    for name, groups in (("fast-then-exact", pose_group), ("every pose exact", every.get)):
        ts, cpu = [], []
        for _ in range(repeats):
            t0, c0 = time.perf_counter(), time.process_time()
            res = itf.check_model(model, groups=groups).poses
            ts.append(time.perf_counter() - t0)
            cpu.append(time.process_time() - c0)
        out[name] = (statistics.median(ts), ts, res, statistics.median(cpu))
    ref = out["every pose exact"][2]
    return {"points": [_motion_point(name, *v, ref) for name, v in out.items()],
            "reference": "every pose measured with OCCT (the one interference check, groups of one)"}


def _motion_point(name: str, t: float, ts: list, res: dict, cpu: float, ref: dict) -> dict:
    """One chart point of :func:`motion_check`: time and the largest clearance error (mm)."""
    return {
        "method": name,
        "knob": "poses measured exactly",
        "time_s": t,
        "times_s": ts,
        "cpu_s": cpu,
        "error": max(abs(res[k][0] - ref[k][0]) for k in ref),
        "exact_poses": sum(1 for v in res.values() if v[2] == "exact"),
        "poses": len(res),
        "min_clearance_mm": min(v[0] for v in res.values()),
    }


def run(quick: bool, out_dir: Path) -> dict:
    """Cold builds (``quick``: the PowerMouse only, 2 repeats; else every family, 3) and the
    motion check (``quick``: 1 repeat, else 3)."""
    repeats = 2 if quick else 3
    fams = ["powermouse"] if quick else list(DESIGNS)
    cold = {}
    with tempfile.TemporaryDirectory(prefix="hapticad-bench-fam-") as tmp:
        tmp = Path(tmp)
        env = {**os.environ, "HAPTICAD_CACHE_DIR": str(tmp / "shapes")}
        for fam in fams:
            if fam != "powermouse":  # fill the shape cache (bd_warehouse bearings, screws)
                _run(DESIGNS[fam], tmp / "warm", env)
            runs = [_run(DESIGNS[fam], tmp / fam, env) for _ in range(repeats)]
            ts = [w for w, _ in runs]
            cold[fam] = {
                "median_s": statistics.median(ts),
                "times_s": ts,
                "cpu_median_s": statistics.median([c for _, c in runs]),
                "goal_s": GOALS_S.get(fam),
                "meets_goal": statistics.median(ts) <= GOALS_S[fam] if fam in GOALS_S else None,
            }
    mc = motion_check(1 if quick else 3)
    charts = _chart(cold, mc, Path(out_dir))
    return {
        "topic": "families",
        "reference": REFERENCE,
        "repeats": repeats,
        "cold": cold,
        "powermouse_cold_s": cold["powermouse"]["median_s"],
        "motion_check": mc,
        "cpu_count": os.cpu_count(),
        "load_avg_1min": os.getloadavg()[0] if hasattr(os, "getloadavg") else None,
        "points": mc["points"],
        "charts": charts,
    }


def _chart(cold: dict, mc: dict, out_dir: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    names = list(cold)
    ax1.bar(names, [cold[n]["median_s"] for n in names], color="#337ab7")
    for i, n in enumerate(names):
        if cold[n]["goal_s"]:
            ax1.hlines(cold[n]["goal_s"], i - 0.4, i + 0.4, colors="k", linestyles="--")
        ax1.annotate(
            f"{cold[n]['median_s']:.2f} s",
            (i, cold[n]["median_s"]),
            ha="center",
            textcoords="offset points",
            xytext=(0, 4),
            fontsize=8,
        )
    ax1.set_ylabel("cold build wall time [s] (median)")
    ax1.set_title("hapticad build --no-cache (dashed: goal)")
    for p in mc["points"]:
        ax2.scatter(p["time_s"], max(p["error"], 1e-12), s=40)
        ax2.annotate(
            f"{p['method']} ({p['exact_poses']}/{p['poses']} exact)",
            (p["time_s"], max(p["error"], 1e-12)),
            fontsize=8,
            textcoords="offset points",
            xytext=(4, 4),
        )
    ax2.set_yscale("log")
    ax2.set_xlabel("PowerMouse motion check time [s] (median)")
    ax2.set_ylabel("max |clearance - every pose exact| [mm]")
    ax2.set_title("error 1e-12 plotted for 0")
    fig.suptitle(REFERENCE, fontsize=8)
    fig.tight_layout(rect=(0, 0, 1, 0.93))

    paths = save_chart(fig, out_dir, "families_build")
    plt.close(fig)
    return paths
