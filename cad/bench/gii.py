"""Benchmark: GII error against time over workspace sampling, and culling vs brute force.

1. Sampling (isotropy paper eq 5 on a sampled workspace). Design: an
   unoptimized 5-bar (a = 60, l2 = 110, l3 = 150 mm) with a 100 mm square
   centred at (20, 180) mm, chosen because its sigma_min lies inside an edge,
   off the grid nodes (for the optimized, symmetric designs the extremes sit
   at nodes every odd grid contains, and every grid is exact). Methods:

   * ``grid`` -- n x n grid, boundary included (what ``hapticad gii`` does);
   * ``boundary`` -- n samples per edge of the square only (4 n - 4 points):
     cheaper, exact only when both extremes of sigma lie on the boundary.

   Reference: the 1025 x 1025 grid (1 050 625 samples). Error: relative error of
   the GII against it. A nested grid's GII can only be >= the reference (a
   subset of its samples), so the error is the optimism of coarse sampling.

2. Optimizers: culling against brute force on the Fig. 2 problem (5-bar,
   100 mm square, 11 x 11 grid) for growing candidate sets. Error: |GII_culling
   - GII_brute| (0: same optimum); the counts of Jacobian evaluations are the
   machine-independent measure.

Times are medians of repeats (``time.perf_counter``).
"""

from __future__ import annotations

import statistics
from pathlib import Path

import numpy as np

from cad.bench.common import median_time as _median_time
from cad.io.atomic import atomic_path
from cad.isotropy.culling import brute_force, culling
from cad.isotropy.gii import fivebar_gii, gii_from_jacobians, square_grid_mm
from cad.isotropy.problems import FiveBarProblem, candidate_grid
from cad.kinematics.fivebar import STATUS_NAMES, FiveBar, jacobian_rad_per_m
from cad.report.figures import save_figure

DESIGN = {"base_mm": 60.0, "proximal_mm": 110.0, "distal_mm": 150.0}
CENTER_MM = (20.0, 180.0)
SIDE_MM = 100.0
REFERENCE_GRID = 1025
REFERENCE = f"{REFERENCE_GRID} x {REFERENCE_GRID} grid over the square (boundary included)"
#: Errors below this are drawn at this value on the log axis (exact results give 0).
ERROR_FLOOR = 1e-17


def boundary_points_mm(center_mm, side_mm: float, n: int) -> np.ndarray:
    """n samples per edge of the square, corners once: (4 n - 4, 2) mm."""
    t = np.linspace(-0.5, 0.5, n) * side_mm
    cx, cy = center_mm
    lo, hi = -0.5 * side_mm, 0.5 * side_mm
    pts = [np.c_[cx + t, np.full(n, cy + lo)], np.c_[cx + t, np.full(n, cy + hi)]]
    pts += [
        np.c_[np.full(n - 2, cx + lo), cy + t[1:-1]],
        np.c_[np.full(n - 2, cx + hi), cy + t[1:-1]],
    ]
    return np.vstack(pts)


def _boundary_gii(fb: FiveBar, n: int) -> float:
    pts = boundary_points_mm(CENTER_MM, SIDE_MM, n)
    J, st = jacobian_rad_per_m(fb, pts)
    return gii_from_jacobians(J, st, pts, 1.0, 1.0, STATUS_NAMES).gii


def sampling_points(quick: bool) -> tuple[float, list[dict]]:
    """GII error against time for grid and boundary sampling; returns (reference GII, points)."""
    fb = FiveBar.symmetric(**DESIGN)
    ref = fivebar_gii(fb, CENTER_MM, SIDE_MM, REFERENCE_GRID).gii
    ns = (3, 5, 9, 17, 33, 65) if quick else (3, 5, 9, 17, 33, 65, 129, 257, 513)
    repeats = 3 if quick else 7
    points = []
    for n in ns:
        t, g = _median_time(lambda n=n: fivebar_gii(fb, CENTER_MM, SIDE_MM, n).gii, repeats)
        points.append(
            {
                "method": "grid",
                "knob": n,
                "samples": n * n,
                "time_s": t,
                "gii": g,
                "error": abs(g - ref) / ref,
            }
        )
        t, g = _median_time(lambda n=n: _boundary_gii(fb, n), repeats)
        points.append(
            {
                "method": "boundary",
                "knob": n,
                "samples": 4 * n - 4,
                "time_s": t,
                "gii": g,
                "error": abs(g - ref) / ref,
            }
        )
    return ref, points


def optimizer_points(quick: bool) -> list[dict]:
    """Culling vs brute force on the Fig. 2 problem for growing candidate sets."""
    sets = (
        [(5, 6, 6), (9, 11, 11)] if quick else [(5, 6, 6), (9, 11, 11), (17, 20, 20), (33, 39, 39)]
    )
    placements = (-200.0, 200.0) if quick else (-300.0, -100.0, 0.0, 100.0, 300.0)
    repeats = 1 if quick else 3
    out = []
    for na, n2, n3 in sets:
        _, params = candidate_grid(
            {
                "base_mm": (0.0, 400.0, na),
                "proximal_mm": (25.0, 500.0, n2),
                "distal_mm": (25.0, 500.0, n3),
            },
            {},
        )
        for yc in placements:
            pr = FiveBarProblem(params, square_grid_mm([0.0, yc], SIDE_MM, 11), 11)
            rb = 1 if pr.n_candidates > 10_000 else repeats
            tb, b = _median_time(lambda pr=pr: brute_force(pr), rb)
            tc, c = _median_time(lambda pr=pr: culling(pr), repeats)
            same = bool(b.best_index == c.best_index and b.gii == c.gii)
            for res, t in ((b, tb), (c, tc)):
                out.append(
                    {
                        "method": res.method,
                        "knob": pr.n_candidates,
                        "center_y_mm": yc,
                        "time_s": t,
                        "error": abs(res.gii - b.gii),
                        "gii": res.gii,
                        "jacobian_evaluations": res.jacobian_evaluations,
                        "same_optimum": same,
                    }
                )
    return out


def run(quick: bool, out_dir: Path) -> dict:
    """Run both benchmarks; write gii_sampling.{png,svg} and gii_culling.{png,svg} into out_dir."""
    ref, samp = sampling_points(quick)
    opt = optimizer_points(quick)
    cul = [p for p in opt if p["method"] == "culling"]
    bru = [p for p in opt if p["method"] == "brute"]
    ratios = [
        b["jacobian_evaluations"] / c["jacobian_evaluations"] for b, c in zip(bru, cul, strict=True)
    ]
    result = {
        "topic": "GII: sampling density and optimizer",
        "reference": REFERENCE,
        "reference_gii": ref,
        "design": {**DESIGN, "center_mm": list(CENTER_MM), "side_mm": SIDE_MM},
        "points": samp + opt,
        "culling_all_same_optimum": all(p["same_optimum"] for p in cul),
        "culling_ratio": min(ratios),
        "culling_evaluation_ratio_min": min(ratios),
        "culling_evaluation_ratio_median": statistics.median(ratios),
        "quick": quick,
    }
    result["charts"] = _plot(samp, opt, Path(out_dir))
    return result


def _plot(samp, opt, out_dir: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt


    out_dir.mkdir(parents=True, exist_ok=True)
    paths = []
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for method, m in (("grid", "o-"), ("boundary", "s--")):
        pts = [p for p in samp if p["method"] == method]
        ax.loglog(
            [p["time_s"] for p in pts], [max(p["error"], ERROR_FLOOR) for p in pts], m, label=method
        )
        for p in pts:
            ax.annotate(str(p["knob"]), (p["time_s"], max(p["error"], ERROR_FLOOR)), fontsize=7)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("relative GII error")
    ax.set_title(f"GII vs sampling (reference: {REFERENCE_GRID}^2 grid)")
    ax.legend()
    fig.tight_layout()
    for ext in ("png", "svg"):
        target = out_dir / f"gii_sampling.{ext}"
        with atomic_path(target) as tmp:
            save_figure(fig, tmp, ext, dpi=120)
        paths.append(str(target))
    plt.close(fig)

    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    for method, m in (("brute", "s"), ("culling", "o")):
        pts = [p for p in opt if p["method"] == method]
        ax[0].loglog(
            [p["knob"] for p in pts], [p["jacobian_evaluations"] for p in pts], m, label=method
        )
        ax[1].loglog([p["knob"] for p in pts], [p["time_s"] for p in pts], m, label=method)
    ax[0].set_xlabel("candidates")
    ax[0].set_ylabel("Jacobian evaluations")
    ax[1].set_xlabel("candidates")
    ax[1].set_ylabel("time (s)")
    ax[0].legend()
    ax[0].set_title("culling = brute-force optimum")
    fig.tight_layout()
    for ext in ("png", "svg"):
        target = out_dir / f"gii_culling.{ext}"
        with atomic_path(target) as tmp:
            save_figure(fig, tmp, ext, dpi=120)
        paths.append(str(target))
    plt.close(fig)
    return paths
