"""The delta's report figure: the apparent mass over its workspace (issue 36 §4, "a map in
the report"): the largest and smallest eigenvalue of Lambda(x) (g) at every grid point, one
panel per height of the grid (z, base frame, mm), x-y scatter coloured on one scale per row."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from cad.io.atomic import atomic_path
from cad.io.escape import mathtext
from cad.report.figures import save_figure

#: The file the delta build writes (report.md and report.html show it).
APPARENT_MASS_MAP = "apparent_mass_map.png"


def map_layers(X_mm, eig_g) -> list[tuple[float, np.ndarray, np.ndarray]]:
    """``[(z_mm, xy_mm (k, 2), eig_g (k, 3))]`` of the grid points ``X_mm`` (n, 3) and their
    Lambda eigenvalues ``eig_g`` (n, 3, ascending), one entry per height (rounded to 1e-6 mm),
    lowest first: what each panel of :func:`plot_apparent_mass_map` draws."""
    X, E = np.asarray(X_mm, float), np.asarray(eig_g, float)
    zs = np.unique(np.round(X[:, 2], 6))
    return [(float(z), X[np.round(X[:, 2], 6) == z, :2], E[np.round(X[:, 2], 6) == z]) for z in zs]


def plot_apparent_mass_map(name: str, X_mm, eig_g, path: Path) -> Path:
    """Write the map of :func:`map_layers` to ``path`` (PNG): row 1 the largest eigenvalue of
    Lambda (the heaviest direction), row 2 the smallest, columns the grid's heights."""
    from matplotlib.figure import Figure

    layers = map_layers(X_mm, eig_g)
    E = np.asarray(eig_g, float)
    fig = Figure(figsize=(2.3 * len(layers) + 1.2, 4.8))
    axes = np.asarray(fig.subplots(2, len(layers), squeeze=False))
    fig.subplots_adjust(left=0.06, right=0.88, bottom=0.1, top=0.86, wspace=0.35, hspace=0.45)
    for row, (col, what) in enumerate(((-1, "largest"), (0, "smallest"))):
        lo, hi = float(E[:, col].min()), float(E[:, col].max())
        for ax, (z, xy, e) in zip(axes[row], layers, strict=True):
            sc = ax.scatter(xy[:, 0], xy[:, 1], c=e[:, col], vmin=lo, vmax=hi if hi > lo else lo + 1e-9,
                            cmap="viridis", s=60)
            ax.set_title(f"z = {z:.0f} mm", fontsize=8)
            ax.set_aspect("equal")
            ax.tick_params(labelsize=6)
        cb = fig.colorbar(sc, ax=list(axes[row]), fraction=0.03, pad=0.02)
        cb.set_label(f"{what} eigenvalue of Λ (g)", fontsize=7)
        cb.ax.tick_params(labelsize=6)
    fig.suptitle(f"{mathtext(name)}: apparent mass over the workspace (x, y in mm, base frame)", fontsize=9)
    with atomic_path(path) as tmp:
        save_figure(fig, tmp, "png", dpi=100)
    return path
