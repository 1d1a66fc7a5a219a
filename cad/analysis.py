"""Analysis of a four-bar design without CAD: metrics, range checks, apparent mass.

This is what ``hapticad analyze`` prints. It imports only numpy/scipy so the
command starts fast; it never imports OCP, build123d or cadquery.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from cad.design.fourbar import FourBarDesign
from cad.dynamics.inertia import (
    InertiaCoefficients,
    apparent_mass_matrix,
    apparent_mass_summary,
    equivalent_inertia,
)
from cad.dynamics.stiffness import stiffness_range_N_per_m
from cad.kinematics.families import PAPER_TABLES, family_linkage
from cad.kinematics.fourbar import check_range, jacobian_mm_per_rad, solve
from cad.kinematics.metrics import compute_metrics, path_frame

METRIC_KEYS = ("stroke_mm", "dy_max_mm", "slope_max", "linearity", "torque_mean_mNm",
               "torque_variation", "bbox_mm", "min_transmission_angle_deg")


def paper_comparison(family: str, force_N: float = 5.0) -> dict[str, Any] | None:
    """Our metrics at the paper's own Fig. 2 dimensions beside Tables I/II, or None for custom."""
    if family not in PAPER_TABLES:
        return None
    fb, lo, hi = family_linkage(family)
    m = compute_metrics(fb, lo, hi, force_N=force_N).as_dict()
    paper = PAPER_TABLES[family]
    rows = {}
    for k, v in paper.items():
        ours = m.get(k) if k != "dimensions" else f"{m['bbox_mm'][0]:.0f} x {m['bbox_mm'][1]:.0f} mm"
        rows[k] = {"paper": v, "ours": ours}
    return rows


def apparent_mass_curves(design: FourBarDesign, H: InertiaCoefficients, samples: int | None = None) -> dict[str, np.ndarray]:
    """x (mm, path frame), D (kg m^2) and M (kg, (N,2,2), path axes) over the stroke."""
    fb = design.linkage
    n = samples or design.samples
    phi = np.linspace(design.phi1_min_rad, design.phi1_max_rad, n)
    pose = solve(fb, phi)
    fr = path_frame(fb, design.phi1_min_rad, design.phi1_max_rad)
    M = apparent_mass_matrix(fb, pose, H, fr)
    return {"phi1_rad": phi, "x_mm": fr.to_path(pose.P_mm)[:, 0],
            "D_kg_m2": equivalent_inertia(fb, pose, H), "M_kg": M}


def analyze(design: FourBarDesign, samples: int | None = None,
            inertia: InertiaCoefficients | None = None) -> dict[str, Any]:
    """Everything ``hapticad analyze --json`` prints (schema in README)."""
    n = samples or design.samples
    fb = design.linkage
    lo, hi = design.phi1_min_rad, design.phi1_max_rad
    rc = check_range(fb, lo, hi, samples=max(n, 361))
    m = compute_metrics(fb, lo, hi, force_N=design.force_N, samples=n)
    out: dict[str, Any] = {"name": design.name, **design.resolved_linkage(), "force_N": design.force_N}
    md = m.as_dict()
    for k in METRIC_KEYS:
        out[k] = md[k]
    out["torque_range_ratio"] = md["torque_range_ratio"]
    out["linearity_definitions"] = {
        "linearity": "1 - max|x(phi1) - endpoint line| / stroke",
        "linearity_fit": md["linearity_fit"],
        "linearity_velocity": md["linearity_velocity"],
    }
    out["samples"] = n
    out["range_check"] = {"problems": list(rc.problems), "closes": rc.closes}
    paper = paper_comparison(design.family, design.force_N) if design.stroke_mm_requested is None else None
    if paper is None and design.family in PAPER_TABLES:
        paper = paper_comparison(design.family, design.force_N)
        out["paper_note"] = "paper values are for the paper's Fig. 2 dimensions (50 mm class)"
    if paper is not None:
        out["paper"] = paper
    H = inertia or design.inertia
    if H is not None:
        curves = apparent_mass_curves(design, H, n)
        out["inertia"] = H.as_dict()
        out["apparent_mass"] = apparent_mass_summary(curves["M_kg"])
    if design.stiffness is not None:
        kmin, kmax = stiffness_range_N_per_m(design.stiffness)
        out["stiffness"] = {"K_min_N_per_m": kmin, "K_max_N_per_m": kmax}
    return out


def jacobian_at(design: FourBarDesign, phi1_deg: float) -> tuple[float, float]:
    """dP/dphi1 at one crank angle, mm/rad, R0."""
    pose = solve(design.linkage, np.array([math.radians(phi1_deg)]))
    j = jacobian_mm_per_rad(design.linkage, pose)[0]
    return float(j[0]), float(j[1])
