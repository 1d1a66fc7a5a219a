"""Markdown report with plots for a four-bar design.

Plots: coupler curve with its straight segment, y-deviation and motor torque
over the stroke, apparent mass M11/M12/M22 over x (Hoeken paper Fig. 6).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from cad.analysis import apparent_mass_curves
from cad.io.atomic import atomic_path, write_text_atomic
from cad.io.escape import mathtext
from cad.kinematics.fourbar import closure_margin, jacobian_mm_per_rad, solve
from cad.kinematics.metrics import path_frame
from cad.report.figures import TITLE_Y, save_figure


def _figure(width_in: float, height_in: float, ncols: int = 1, **adjust):
    """A matplotlib ``Figure`` with ``ncols`` axes side by side, fixed margins (fractions of
    the figure, ``adjust``: ``subplots_adjust`` keys) instead of ``tight_layout`` (which
    draws the figure once more to measure it). No pyplot: no global figure registry, and
    ``savefig`` renders with Agg for PNG."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width_in, height_in))
    ax = fig.subplots(1, ncols)
    fig.subplots_adjust(**adjust)
    return fig, ax


def plot_kinematics(design, path: Path) -> Path:
    """Coupler curve (full turn where it closes) and the straight segment, in R0."""
    fb = design.linkage
    lo, hi = design.phi1_min_rad, design.phi1_max_rad
    full = np.linspace(lo - np.pi, lo + np.pi, 1441)
    ok = closure_margin(fb, full) >= 0
    seg = np.linspace(lo, hi, 401)
    pose = solve(fb, seg)
    fr = path_frame(fb, lo, hi)
    xy = fr.to_path(pose.P_mm)
    tau = design.force_N * fr.rotate(jacobian_mm_per_rad(fb, pose))[:, 0]
    fig, ax = _figure(15, 4.6, 3, left=0.04, right=0.99, bottom=0.11, top=0.93, wspace=0.22)
    if ok.any():
        # split where closure fails so the curve is not drawn across gaps
        idx = np.nonzero(ok)[0]
        runs = np.split(idx, np.nonzero(np.diff(idx) > 1)[0] + 1)
        for r in runs:
            if len(r) > 1:
                P = solve(fb, full[r]).P_mm
                ax[0].plot(P[:, 0], P[:, 1], color="0.6", lw=1)
    ax[0].plot(pose.P_mm[:, 0], pose.P_mm[:, 1], color="C3", lw=2.5, label="straight segment")
    for k in (0, len(seg) // 2, -1):
        pts = np.array([[0, 0], pose.A2_mm[k], pose.A3_mm[k], fb.A4_mm])
        ax[0].plot(pts[:, 0], pts[:, 1], "o-", color="C0", lw=1, ms=3)
        ax[0].plot([pose.A2_mm[k, 0], pose.P_mm[k, 0]], [pose.A2_mm[k, 1], pose.P_mm[k, 1]],
                   "--", color="C0", lw=0.8)
    ax[0].set_aspect("equal")
    ax[0].set_title(f"{mathtext(design.name)}: coupler curve (R0, mm)", y=TITLE_Y)
    ax[0].legend(loc="best", fontsize=8)
    ax[1].plot(xy[:, 0], xy[:, 1] * 1e3, color="C3")
    ax[1].set_xlabel("x along path (mm)")
    ax[1].set_ylabel("y deviation (µm)")
    ax[1].set_title("deviation from the chord", y=TITLE_Y)
    ax[2].plot(xy[:, 0], tau, color="C2")
    ax[2].set_xlabel("x along path (mm)")
    ax[2].set_ylabel(f"motor torque for {design.force_N:g} N (mN·m)")
    ax[2].set_title("torque over the stroke", y=TITLE_Y)
    for a in ax:
        a.grid(alpha=0.3)
    with atomic_path(path) as tmp:
        save_figure(fig, tmp, "png", dpi=110)
    return path


def plot_apparent_mass(design, H, path: Path) -> Path:
    """M11, M12, M22 (g) over x (Hoeken paper Fig. 6)."""
    c = apparent_mass_curves(design, H, 401)
    M = c["M_kg"] * 1e3
    fig, ax = _figure(6.5, 4.2, left=0.12, right=0.97, bottom=0.12, top=0.92)
    ax.plot(c["x_mm"], M[:, 0, 0], label="M11")
    ax.plot(c["x_mm"], M[:, 0, 1], label="M12")
    ax.plot(c["x_mm"], M[:, 1, 1], label="M22")
    ax.set_xlabel("x along path (mm)")
    ax.set_ylabel("apparent mass (g)")
    ax.set_title(f"{mathtext(design.name)}: operational mass matrix (eq 22)", y=TITLE_Y)
    ax.grid(alpha=0.3)
    ax.legend()
    with atomic_path(path) as tmp:
        save_figure(fig, tmp, "png", dpi=110)
    return path


def _fmt(v: Any) -> str:
    if isinstance(v, float):
        return f"{v:.4g}"
    if isinstance(v, list):
        return " x ".join(_fmt(x) for x in v)
    return str(v)


def analysis_markdown(design, res: dict, images: dict[str, str]) -> str:
    lines = [f"# {design.name} — hapticad analysis", "",
             f"Family `{design.family}`, force {design.force_N:g} N, {res['samples']} crank samples.", ""]
    lines += ["## Linkage", "", "| key | value |", "|---|---|"]
    for k in ("l1_mm", "l2_mm", "l3_mm", "l4_mm", "l5_mm", "le_mm", "phi_e_deg", "phi1_min_deg",
              "phi1_max_deg", "branch"):
        lines.append(f"| `{k}` | {_fmt(res[k])} |")
    lines += ["", "## Metrics (path frame)", ""]
    paper = res.get("paper", {})
    lines += ["| metric | ours | paper (Tables I/II, paper dimensions) |", "|---|---|---|"]
    for k in ("stroke_mm", "dy_max_mm", "slope_max", "linearity", "torque_mean_mNm",
              "torque_variation", "bbox_mm", "min_transmission_angle_deg"):
        pk = "dimensions" if k == "bbox_mm" else k
        lines.append(f"| `{k}` | {_fmt(res[k])} | {_fmt(paper.get(pk, {}).get('paper', '—'))} |")
    lines += ["", f"![kinematics]({images['kinematics']})", ""]
    if "apparent_mass" in res:
        lines += ["## Apparent mass", "", "| key | value |", "|---|---|"]
        for k, v in res["apparent_mass"].items():
            lines.append(f"| `{k}` | {v:.4g} |")
        lines += ["", f"![apparent mass]({images['apparent_mass']})", ""]
    if res["range_check"]["problems"]:
        lines += ["## Warnings", ""] + [f"- {p}" for p in res["range_check"]["problems"]]
    return "\n".join(lines) + "\n"


def write_analysis_report(design, res: dict, out_dir: Path, inertia=None) -> Path:
    """Write ``analysis.md``, ``analysis.json`` and PNG plots into ``out_dir``; return the .md path."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    images = {"kinematics": "kinematics.png"}
    plot_kinematics(design, out_dir / "kinematics.png")
    if inertia is not None:
        images["apparent_mass"] = "apparent_mass.png"
        plot_apparent_mass(design, inertia, out_dir / "apparent_mass.png")
    write_text_atomic(out_dir / "analysis.json", json.dumps(res, indent=1))
    return write_text_atomic(out_dir / "analysis.md", analysis_markdown(design, res, images))
