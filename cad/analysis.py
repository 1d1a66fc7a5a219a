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


#: How each Table I/II quantity scales when every length is multiplied by s and the force
#: by f (torque = F dx/dphi1 is a length times a force; slopes and ratios are invariant).
PAPER_SCALING = {"torque_mean_mNm": (1, 1), "dy_max_mm": (1, 0), "stroke_mm": (1, 0),
                 "torque_variation": (0, 0), "slope_max": (0, 0), "linearity": (0, 0)}


def scaled_paper_row(key: str, value, scale: float, force_ratio: float):
    """A Table I/II value for a design scaled by ``scale`` (lengths) and ``force_ratio``."""
    if key == "dimensions":
        w, h = (float(x) for x in str(value).replace("mm", "").split("x"))
        return f"{w * scale:.0f} x {h * scale:.0f} mm"
    p_len, p_force = PAPER_SCALING[key]
    return float(value) * scale**p_len * force_ratio**p_force


def paper_expectations(design: FourBarDesign) -> dict[str, Any] | None:
    """The paper's Tables I/II scaled to a rescaled named-family design (None otherwise).

    A design with ``stroke_mm`` is the Fig. 2 linkage times ``s``; its expected metrics
    are the paper's times ``s`` (lengths, and torque also times F / 5 N), unchanged for
    slopes and ratios.
    """
    if design.family not in PAPER_TABLES or design.stroke_mm_requested is None:
        return None
    paper_fb, _, _ = family_linkage(design.family)
    s = design.linkage.l2_mm / paper_fb.l2_mm
    f = design.force_N / 5.0
    return {"scale": s, "force_ratio": f,
            "rows": {k: scaled_paper_row(k, v, s, f) for k, v in PAPER_TABLES[design.family].items()}}


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
    """Everything ``hapticad analyze --json`` prints (schema: docs/commands.md)."""
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
        "linearity_velocity_mean": md["linearity_velocity_mean"],
    }
    out["samples"] = n
    out["range_check"] = {"problems": list(rc.problems), "closes": rc.closes}
    paper = paper_comparison(design.family, design.force_N) if design.stroke_mm_requested is None else None
    expected = paper_expectations(design)
    if expected is not None:
        paper = paper_comparison(design.family, design.force_N)
        for k, row in paper.items():
            row["paper_scaled"] = expected["rows"][k]
        out["paper_scale"] = expected["scale"]
        out["paper_note"] = (f"'paper' and 'ours' are at the paper's Fig. 2 dimensions; "
                             f"'paper_scaled' is the paper's value for this design's scale "
                             f"s = {expected['scale']:.4g} (lengths x s, torque x s F / 5 N)")
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
