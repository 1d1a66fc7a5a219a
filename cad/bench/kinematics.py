"""Kinematics benchmarks: pose throughput vs pylinkage, metric accuracy vs samples, analyze wall time.

- ``poses``: 100k crank angles of the Hoeken linkage, our vectorized solve +
  Jacobian (eqs 3-12) against pylinkage's numba ``step_fast`` on the same
  linkage and count (positions only, JIT warm-up excluded). Median of repeats.
  Goal: >= 100x. pylinkage's coupler point is checked against ours.
- ``metric_samples``: dy_max and slope_max from N uniform samples, error
  against the exact extremum (Brent/golden refinement to 1e-13 rad, the
  reference), time per evaluation. Chart: error vs time, log-log.
- ``analyze_wall``: process wall time of ``hapticad analyze designs/hoeken.toml
  --json`` (median of runs). Goal: <= 0.6 s.
"""

from __future__ import annotations

import json
import math
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from cad.bench.common import median_time
from cad.kinematics.families import family_linkage
from cad.kinematics.fourbar import coupler_point_and_jacobian, jacobian_mm_per_rad, solve
from cad.kinematics.metrics import compute_metrics
from cad.report.figures import save_figure

REPO = Path(__file__).resolve().parents[2]


def pylinkage_linkage(pl, fb, lo: float, dphi: float):
    """The same four-bar in pylinkage: crank, RRR dyad for A3, fixed dyad for P."""
    p0 = solve(fb, np.array([lo]))
    O1 = pl.Ground(0.0, 0.0)
    O2 = pl.Ground(fb.l5_mm, fb.l4_mm)
    crank = pl.Crank(anchor=O1, radius=fb.l1_mm, angular_velocity=dphi, initial_angle=lo)
    a3 = pl.RRRDyad(
        anchor1=crank.output,
        anchor2=O2,
        distance1=fb.l2_mm,
        distance2=fb.l3_mm,
        x=float(p0.A3_mm[0, 0]),
        y=float(p0.A3_mm[0, 1]),
    )
    P = pl.FixedDyad(anchor1=crank.output, anchor2=a3, distance=fb.le_mm, angle=fb.phi_e_rad)
    return pl.Linkage([O1, O2, crank, a3, P])


def _median_time(fn, repeats: int) -> float:
    return median_time(fn, repeats)[0]


def bench_poses(n: int = 100_000, repeats: int = 7) -> dict:
    fb, lo, hi = family_linkage("hoeken")
    phi = np.linspace(lo, hi, n)

    def ours():
        coupler_point_and_jacobian(fb, phi)

    def ours_full():
        p = solve(fb, phi)
        jacobian_mm_per_rad(fb, p)

    t_ours = _median_time(ours, repeats)
    t_full = _median_time(ours_full, repeats)
    out = {
        "n_poses": n,
        "ours_s": t_ours,
        "ours_poses_per_s": n / t_ours,
        "goal_ratio": 100.0,
        "ours_full_pose_s": t_full,
        "note": "ours = P and J (fused, coupler_point_and_jacobian); ours_full_pose = every joint "
        "+ unwrapped angles + J; pylinkage step_fast = every joint, no J (numba)",
    }
    try:
        import pylinkage as pl
    except ImportError:
        out["pylinkage"] = "not installed"
        return out
    dphi = (hi - lo) / (n - 1)
    link = pylinkage_linkage(pl, fb, lo, dphi)
    link.step_fast(iterations=10)  # numba JIT warm-up

    def theirs():
        return pylinkage_linkage(pl, fb, lo, dphi).step_fast(iterations=n)

    t_pl = _median_time(theirs, max(3, repeats // 2))
    # agreement: pylinkage steps before recording, so row i is phi1 = lo + (i + 1) * dphi
    tr = pylinkage_linkage(pl, fb, lo, dphi).step_fast(iterations=1000)
    ref = solve(fb, lo + dphi * (np.arange(1000) + 1)).P_mm
    import itertools

    t = time.perf_counter()
    list(itertools.islice(pylinkage_linkage(pl, fb, lo, dphi).step(), 2000))
    t_py = (time.perf_counter() - t) / 2000
    out.update(
        {
            "pylinkage_step_fast_s": t_pl,
            "ratio": t_pl / t_ours,
            "pylinkage_step_python_s_per_pose": t_py,
            "ratio_vs_python_step": t_py * n / t_ours,
            "pylinkage_version": getattr(pl, "__version__", "?"),
            "max_P_difference_mm": float(np.abs(tr[:, 4, :] - ref).max()),
        }
    )
    return out


def bench_metric_samples(quick: bool) -> dict:
    fb, lo, hi = family_linkage("hoeken")
    exact = compute_metrics(fb, lo, hi, samples=4001, refine=True)
    pts = []
    repeats = 3 if quick else 7
    runs = [("uniform samples", n, False) for n in (11, 21, 51, 101, 301, 1001, 3001, 10001, 30001)]
    runs += [("samples + zoom refinement", n, True) for n in (11, 51, 201)]
    for method, n, refine in runs:
        t, m = median_time(
            lambda n=n, r=refine: compute_metrics(fb, lo, hi, samples=n, refine=r), repeats
        )
        pts.append(
            {
                "method": method,
                "knob": n,
                "time_s": t,
                "error": abs(m.dy_max_mm - exact.dy_max_mm) / exact.dy_max_mm,
                "error_slope": abs(m.slope_max - exact.slope_max) / exact.slope_max,
            }
        )
    return {
        "topic": "kinematic metrics",
        "reference": "exact extremum of |y| (root of dy/dphi1, 1e-13 rad)",
        "exact_dy_max_mm": exact.dy_max_mm,
        "points": pts,
    }


def bench_analyze_wall(runs: int = 5) -> dict:
    cmd = [sys.executable, "-m", "cad", "analyze", str(REPO / "designs" / "hoeken.toml"), "--json"]
    ts = []
    for _ in range(runs):
        t = time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True)
        ts.append(time.perf_counter() - t)
    return {"median_s": statistics.median(ts), "min_s": min(ts), "runs": runs, "goal_s": 0.6}


def chart(res: dict, out_dir: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    pts = res["points"]
    for method, marker in (("uniform samples", "o-"), ("samples + zoom refinement", "s-")):
        p = [q for q in pts if q["method"] == method]
        ax.loglog(
            [q["time_s"] for q in p],
            [max(q["error"], 1e-17) for q in p],
            marker,
            label=f"{method} (dy_max)",
        )
        for q in p:
            ax.annotate(str(q["knob"]), (q["time_s"], max(q["error"], 1e-17)), fontsize=7)
    ax.set_xlabel("time per metric evaluation (s)")
    ax.set_ylabel("relative error of dy_max")
    ax.set_title("Kinematic metrics: error vs time\nreference: " + res["reference"], fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.tight_layout()
    files = []
    for ext in ("png", "svg"):
        f = out_dir / f"kinematics_error_vs_time.{ext}"
        save_figure(fig, f, dpi=110)
        files.append(f.name)
    plt.close(fig)
    return files


def run(quick: bool, out_dir: Path) -> dict:
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    res = bench_metric_samples(quick)
    res["charts"] = chart(res, out_dir)
    res["poses"] = bench_poses(n=100_000, repeats=3 if quick else 9)
    res["analyze_wall"] = bench_analyze_wall(3 if quick else 7)
    (out_dir / "kinematics.json").write_text(json.dumps(res, indent=1))
    return res


if __name__ == "__main__":  # pragma: no cover
    r = run(True, Path(".bench"))
    print(json.dumps({k: r[k] for k in ("poses", "analyze_wall")}, indent=1))
    print(math.nan if not r else "ok")
