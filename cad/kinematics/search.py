"""Bounded 1-D minimization by golden-section search (pure Python/numpy).

Chosen over ``scipy.optimize.minimize_scalar`` only for import cost:
``import scipy.optimize`` takes ~0.6 s here, the whole budget of
``hapticad analyze``. Golden section converges linearly (factor 0.618 per
evaluation); 60 evaluations shrink a bracket by 3e-13, enough for the
extremum of a smooth function sampled at the bracket's resolution.
"""

from __future__ import annotations

import math
from collections.abc import Callable

INV_PHI = (math.sqrt(5.0) - 1.0) / 2.0


def golden_minimize(f: Callable[[float], float], a: float, b: float, xtol: float = 1e-12,
                    max_iter: int = 200) -> tuple[float, float]:
    """Minimize a unimodal ``f`` on [a, b]; returns (x_min, f(x_min))."""
    if b < a:
        a, b = b, a
    c = b - INV_PHI * (b - a)
    d = a + INV_PHI * (b - a)
    fc, fd = f(c), f(d)
    for _ in range(max_iter):
        if abs(b - a) <= xtol * (1.0 + abs(a) + abs(b)):
            break
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - INV_PHI * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + INV_PHI * (b - a)
            fd = f(d)
    return (c, fc) if fc < fd else (d, fd)
