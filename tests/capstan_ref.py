"""By-hand reference of a grooved capstan's inertia for the tests (independent of
:mod:`cad.actuators.capstan_geometry`): a steel tube from the bore to the crests (pitch less one
rope diameter, plus the groove depth 0.35 d), 1.5 d per wrap + an 8 mm hub long, less the helical
groove: the circle of radius d / 2 on the pitch circle, the part of it inside the crests, its
int r^3 dA by Gauss-Legendre over the radial offset u (chord 2 sqrt(rho^2 - u^2)), swept round
2 pi per wrap and stretched along the helix by sqrt(1 + (p / 2 pi r_bar)^2)."""

from __future__ import annotations

import math

import numpy as np


def grooved_capstan_izz_kg_m2(dc_mm: float, rope_d_mm: float, wraps: float, bore_mm: float,
                              density_kg_m3: float) -> float:
    rho, h = rope_d_mm / 2, 0.35 * rope_d_mm
    r_p = dc_mm / 2
    ro, ri = (dc_mm - rope_d_mm) / 2 + h, bore_mm / 2
    L = 1.5 * rope_d_mm * wraps + 8.0
    m = math.pi * (ro * ro - ri * ri) * L * 1e-9 * density_kg_m3
    tube = 0.5 * m * (ro * ro + ri * ri) * 1e-6
    x, w = np.polynomial.legendre.leggauss(2000)
    u = -rho + 0.5 * h * (x + 1.0)
    chord = 2.0 * np.sqrt(np.maximum(rho * rho - u * u, 0.0))
    area = 0.5 * h * np.sum(w * chord)
    rbar = 0.5 * h * np.sum(w * chord * (r_p + u)) / area
    r3 = 0.5 * h * np.sum(w * chord * (r_p + u) ** 3)
    stretch = math.sqrt(1.0 + (1.5 * rope_d_mm / (2 * math.pi * rbar)) ** 2)
    return tube - density_kg_m3 * 1e-15 * 2 * math.pi * wraps * stretch * r3
