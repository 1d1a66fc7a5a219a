"""The four-bar's encoder implied by its ``[stiffness]`` inputs
(:meth:`cad.design.fourbar.FourBarDesign.stiffness_encoder`): the counts per crank turn
whose handle step at mid-stroke is ``encoder_resolution_m``. Pure numpy."""

from __future__ import annotations

import math

import numpy as np

from cad.kinematics.fourbar import jacobian_mm_per_rad, solve
from cad.kinematics.metrics import path_frame


def mid_stroke_lever_m_per_rad(design) -> float:
    """|dx/dphi1| of a four-bar design's handle along its path at mid-stroke (m/rad): the
    lever that turns one encoder step (rad) into eq (25)'s Delta (m)."""
    fb = design.linkage
    mid = 0.5 * (design.phi1_min_rad + design.phi1_max_rad)
    pose = solve(fb, np.array([mid]))
    fr = path_frame(fb, design.phi1_min_rad, design.phi1_max_rad)
    return abs(float(fr.rotate(jacobian_mm_per_rad(fb, pose))[0, 0])) * 1e-3


def stiffness_counts(design) -> tuple[int, str] | None:
    """Counts per crank turn whose handle step at mid-stroke is ``[stiffness]
    encoder_resolution_m``: 2 pi |dx/dphi1| / Delta, rounded to whole counts, with its
    source; None when the design has no ``[stiffness]`` table."""
    if design.stiffness is None:
        return None
    delta = design.stiffness.encoder_resolution_m
    exact = 2 * math.pi * mid_stroke_lever_m_per_rad(design) / delta
    n = max(1, round(exact))
    return n, (f"stiffness.encoder_resolution_m at mid-stroke; Delta = {delta:g} m: 2 pi |dx/dphi1| / "
               f"Delta = {exact:.6g}, rounded to {n} counts/rev")
