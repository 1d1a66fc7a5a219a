"""The study behind Fig. 2 of the isotropy paper: optimal 5-bar vs workspace placement.

A 100 mm square workspace has its centre placed on the symmetry axis from
300 mm below to 300 mm above the base line; for each placement the symmetric
5-bar (base a, proximal l2, distal l3) that maximizes the GII (eq 5, 11 x 11
grid with boundary, equal motors, isotropic force requirement) is found by
culling over a discrete grid, and brute force confirms it. With the elbow
conventions of :mod:`cad.kinematics.fivebar`, placements below the base use
the elbows-in branch (the mirror image of elbows-out), so the two halves of
the curve differ. The figure in the paper is lost; the numbers here are ours.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from cad.io.atomic import atomic_path
from cad.io.figures import save_figure
from cad.isotropy.culling import brute_force, culling
from cad.isotropy.gii import square_grid_mm
from cad.isotropy.problems import FiveBarProblem, candidate_grid

SIDE_MM = 100.0
GRID = 11


def ranges(quick: bool) -> dict[str, tuple[float, float, int]]:
    """Candidate grid: base 0-400 mm, links 25-500 mm (<= 5 workspace sides)."""
    if quick:
        return {
            "base_mm": (0.0, 400.0, 9),
            "proximal_mm": (25.0, 500.0, 11),
            "distal_mm": (25.0, 500.0, 11),
        }
    return {
        "base_mm": (0.0, 400.0, 17),
        "proximal_mm": (25.0, 500.0, 20),
        "distal_mm": (25.0, 500.0, 20),
    }


def placements_mm(quick: bool) -> np.ndarray:
    """Workspace-centre heights above the base line (mm), -300 ... +300."""
    return np.arange(-300.0, 301.0, 100.0 if quick else 50.0)


def run(out_dir: Path | None = None, quick: bool = True) -> dict:
    """Run the study; returns rows per placement and writes fig2_study.png/.svg to out_dir."""
    rng = ranges(quick)
    _, params = candidate_grid(rng, {})
    rows = []
    for yc in placements_mm(quick):
        pr = FiveBarProblem(params, square_grid_mm([0.0, yc], SIDE_MM, GRID), GRID)
        c = culling(pr)
        t0 = time.perf_counter()
        b = brute_force(pr)
        tb = time.perf_counter() - t0
        best = pr.candidate(c.best_index)
        rows.append(
            {
                "center_y_mm": float(yc),
                **best,
                "gii": c.gii,
                "at_bound": [k for k, (lo, hi, _) in rng.items() if best[k] in (lo, hi)],
                "culling_evaluations": c.jacobian_evaluations,
                "brute_evaluations": b.jacobian_evaluations,
                "evaluation_ratio": b.jacobian_evaluations / c.jacobian_evaluations,
                "culling_time_s": c.wall_time_s,
                "brute_time_s": tb,
                "same_optimum": bool(b.best_index == c.best_index and b.gii == c.gii),
            }
        )
    out = {
        "topic": "Fig. 2 study: optimum symmetric 5-bar vs placement of a 100 mm square workspace",
        "quick": quick,
        "grid": GRID,
        "side_mm": SIDE_MM,
        "ranges": {k: list(v) for k, v in rng.items()},
        "n_candidates": int(params["base_mm"].size),
        "rows": rows,
        "all_same_optimum": all(r["same_optimum"] for r in rows),
        "min_evaluation_ratio": min(r["evaluation_ratio"] for r in rows),
    }
    if out_dir is not None:
        out["charts"] = _plot(rows, Path(out_dir))
    return out


def _plot(rows, out_dir: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt


    y = [r["center_y_mm"] / 10 for r in rows]
    fig, ax = plt.subplots(2, 1, figsize=(6.5, 6.5), sharex=True)
    for key, label, m in (
        ("base_mm", "base a", "o"),
        ("proximal_mm", "proximal l2", "s"),
        ("distal_mm", "distal l3", "^"),
    ):
        line = ax[0].plot(y, [r[key] / 10 for r in rows], m + "-", label=label)[0]
        yb = [(yy, r[key] / 10) for yy, r in zip(y, rows, strict=True) if key in r["at_bound"]]
        if yb:
            ax[0].plot(*zip(*yb, strict=True), m, ms=12, mfc="none", color=line.get_color())
    ax[0].set_ylabel("optimum length (cm)\n(ringed: at its range bound)")
    ax[0].legend()
    ax[0].set_title("Optimum 5-bar for a 10 cm square workspace (culling = brute force)")
    ax[1].plot(y, [r["gii"] for r in rows], "ko-")
    ax[1].set_ylabel("GII")
    ax[1].set_xlabel("workspace centre above the base line (cm)")
    ax[1].set_ylim(0, 1)
    fig.tight_layout()
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = []
    for ext in ("png", "svg"):
        target = out_dir / f"fig2_study.{ext}"
        with atomic_path(target) as tmp:
            save_figure(fig, tmp, ext, dpi=120)
        paths.append(str(target))
    plt.close(fig)
    return paths
