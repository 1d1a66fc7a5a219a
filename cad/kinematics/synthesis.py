"""Link-length and crank-range synthesis from the kinematic core.

Two documented objectives, both starting from a family's Fig. 2 proportions
(or a custom linkage) and keeping l4 and the assembly mode:

``max-stroke``
    With the coupler length l2 fixed, choose the crank range [phi1_min, phi1_max]
    (and, with ``free="all"``, the ratios l1/l2, l3/l2, l5/l2, le/l2 and phi_e)
    to **maximize the stroke** subject to ``dy_max_mm <= dy_tol_mm`` and
    ``min_transmission_angle_deg >= mu_min_deg``: the longest straight segment
    whose deviation stays under a tolerance.

``min-torque-variation``
    For a fixed stroke (lengths rescaled so the stroke equals ``stroke_mm``),
    choose the same free parameters to **minimize the torque variation**
    Delta tau / <tau> subject to dy_max/stroke not exceeding the start's value
    (straightness must not get worse), the crank span phi1_max - phi1_min not
    shrinking (it sets the encoder resolution per mm), the footprint
    max(bbox)/stroke not growing, and the transmission-angle bound.

Both objectives also require x(phi1) to be monotone over the range (dx/dphi1
keeps its sign: a haptic display must not reverse along its path).

``max-stroke`` over the crank range (``free="range"``, no stroke held) is solved globally by
branch and bound over every crank window (:mod:`cad.kinematics.max_stroke`), with a proven
upper bound on the stroke of any window (``upper_bound_mm``); with ``free="all"`` that
window is the first start of the search below. The other searches are a bounded Nelder-Mead
on a penalized objective (penalties are exact zero inside the feasible set), from the start
and from a few seeded perturbations; the best feasible point is polished and re-evaluated
with the refined metrics of :mod:`cad.kinematics.metrics`. Pure numpy/scipy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cad import tolerances as tol
from cad.errors import DesignError, KinematicsError
from cad.kinematics.fourbar import FourBar, check_range, closure_margin, solve
from cad.kinematics.max_stroke import global_max_stroke
from cad.kinematics.metrics import Metrics, compute_metrics
from cad.tolerances import (
    ROOT_XTOL_RAD,
    SYNTH_HELD_FATOL,
    SYNTH_HELD_XATOL,
    SYNTH_SEARCH_FATOL,
    SYNTH_SEARCH_XATOL,
)

OBJECTIVES = ("max-stroke", "min-torque-variation")
FREE_SETS = ("range", "all")


@dataclass(frozen=True)
class SynthesisResult:
    """Optimized linkage and range, its metrics, the start's metrics, and the search log."""

    objective: str
    linkage: FourBar
    phi1_min_rad: float
    phi1_max_rad: float
    metrics: Metrics
    start_metrics: Metrics
    evaluations: int
    feasible: bool
    #: max-stroke over the crank range: no window of the linkage meeting the constraints is
    #: longer (the global search's proof, :mod:`cad.kinematics.max_stroke`); None otherwise.
    upper_bound_mm: float | None = None


def _unpack(x, fb0: FourBar, free: str) -> tuple[FourBar, float, float]:
    if free == "range":
        return fb0, float(x[0]), float(x[1])
    l2 = fb0.l2_mm
    fb = FourBar(x[2] * l2, l2, x[3] * l2, fb0.l4_mm, x[4] * l2, x[5] * l2, float(x[6]), fb0.branch)
    return fb, float(x[0]), float(x[1])


def _pack(fb: FourBar, lo: float, hi: float, free: str) -> np.ndarray:
    if free == "range":
        return np.array([lo, hi])
    l2 = fb.l2_mm
    return np.array([lo, hi, fb.l1_mm / l2, fb.l3_mm / l2, fb.l5_mm / l2, fb.le_mm / l2, fb.phi_e_rad])


def _safe_metrics(fb, lo, hi, force_N, samples, refine=False) -> Metrics | None:
    if not hi > lo + 1e-3 or hi - lo > 2 * math.pi - 1e-3:
        return None
    try:
        if check_range(fb, lo, hi, samples=samples).problems:
            return None
        return compute_metrics(fb, lo, hi, force_N=force_N, samples=samples, refine=refine)
    except (KinematicsError, DesignError, FloatingPointError, ValueError):
        return None


def _hi_for_stroke(fb: FourBar, lo: float, stroke_mm: float, grid: int = 721) -> float | None:
    """First crank angle after ``lo`` (rad) where the chord |P(phi1) - P(lo)| reaches
    ``stroke_mm``, within one turn and before the loop stops closing; None when none does."""
    from scipy.optimize import brentq

    phi = lo + np.linspace(1e-3, 2 * math.pi - 1e-3, grid)
    closes = np.concatenate([[lo], phi])
    bad = np.flatnonzero(closure_margin(fb, closes) < 0)
    if bad.size and bad[0] == 0:
        return None
    phi = phi[: bad[0] - 1] if bad.size else phi
    if phi.size < 2:
        return None
    p_lo = solve(fb, np.array([lo])).P_mm[0]
    reach = np.flatnonzero(np.linalg.norm(solve(fb, phi).P_mm - p_lo, axis=1) >= stroke_mm)
    if reach.size == 0 or reach[0] == 0:
        return None

    def gap(b: float) -> float:
        return float(np.linalg.norm(solve(fb, np.array([b])).P_mm[0] - p_lo) - stroke_mm)

    return float(brentq(gap, phi[reach[0] - 1], phi[reach[0]], xtol=ROOT_XTOL_RAD))


def _straightest_at_stroke(fb0: FourBar, free: str, stroke_mm: float,
                           mu_min_deg: float, force_N: float, samples: int, starts: list,
                           counter: dict) -> tuple[FourBar, float, float] | None:
    """``max-stroke`` with the stroke held: least dy_max over (phi1_min [, ratios, phi_e])
    with phi1_max root-found for ``stroke_mm``. ``starts`` are packed vectors (``_pack``);
    returns the best linkage and range, None when no start holds the stroke."""
    from scipy.optimize import minimize

    def point(xr):
        fb, lo, _ = _unpack(np.insert(xr, 1, xr[0] + 1.0), fb0, free)
        if free == "all" and (min(xr[1], xr[2], xr[3]) <= 0.02 or xr[4] < 0):
            return None
        try:
            hi = _hi_for_stroke(fb, lo, stroke_mm)
        except (KinematicsError, DesignError, ValueError):
            return None
        return None if hi is None else (fb, lo, hi)

    def cost(xr):
        counter["n"] += 1
        p = point(xr)
        m = None if p is None else _safe_metrics(*p, force_N, samples)
        if m is None:
            return 1e6
        pen = 1e3 * max(0.0, mu_min_deg - m.min_transmission_angle_deg)
        pen += 1e3 * max(0.0, 1e-3 - m.linearity_velocity)
        return m.dy_max_mm / stroke_mm + pen

    best = None
    for xs in starts + _screened_starts(cost, starts[0]):
        res = minimize(cost, np.delete(xs, 1), method="Nelder-Mead",
                       options={"xatol": SYNTH_HELD_XATOL, "fatol": SYNTH_HELD_FATOL,
                                "maxiter": 400 * xs.size})
        if best is None or res.fun < best.fun:
            best = res
    return point(best.x) if best.fun < 1e5 else None


def _screened_starts(cost, x0: np.ndarray, step_deg: float = 5.0, keep: int = 2) -> list:
    """Extra starts for the held stroke: ``x0`` with phi1_min on a ``step_deg`` grid over
    [0, 360) deg; the ``keep`` best that hold the stroke (cost < 1e5). The starts near
    the design's phi1_min can all lie in the flat infeasible region (cost 1e6), where
    Nelder-Mead cannot move, although another part of the coupler curve holds the stroke."""
    trial = []
    for lo in np.radians(np.arange(0.0, 360.0, step_deg)):
        x = x0.copy()
        x[0] = lo
        c = cost(np.delete(x, 1))
        if c < 1e5:
            trial.append((c, x))
    trial.sort(key=lambda t: t[0])
    return [x for _, x in trial[:keep]]


def _penalized_search(fb0: FourBar, free: str, objective: str, start: Metrics, span0: float,
                      dy_tol_mm: float, mu_min_deg: float, force_N: float, samples: int,
                      starts: list, counter: dict) -> tuple[FourBar, float, float] | None:
    """Nelder-Mead on the penalized objective (module docstring) from each packed start;
    the best linkage and range, None when no start reaches the feasible set."""
    from scipy.optimize import minimize

    ratio0 = start.dy_max_mm / start.stroke_mm
    size0 = max(start.bbox_mm) / start.stroke_mm

    def cost(x):
        counter["n"] += 1
        fb, lo, hi = _unpack(x, fb0, free)
        if free == "all" and min(x[2], x[3], x[4]) <= 0.02 or (free == "all" and x[5] < 0):
            return 1e6
        try:
            m = _safe_metrics(fb, lo, hi, force_N, samples)
        except DesignError:
            return 1e6
        if m is None:
            return 1e6
        pen = 1e3 * max(0.0, mu_min_deg - m.min_transmission_angle_deg)
        pen += 1e3 * max(0.0, 1e-3 - m.linearity_velocity)
        if objective == "max-stroke":
            pen += 1e3 * max(0.0, m.dy_max_mm / dy_tol_mm - 1.0)
            return -m.stroke_mm / fb0.l2_mm + pen
        pen += 1e3 * max(0.0, (m.dy_max_mm / m.stroke_mm) / ratio0 - 1.0)
        pen += 1e3 * max(0.0, span0 - (hi - lo))
        pen += 1e3 * max(0.0, (max(m.bbox_mm) / m.stroke_mm) / size0 - 1.0)
        return m.torque_variation + pen

    best = None
    for xs in starts:
        res = minimize(cost, xs, method="Nelder-Mead",
                       options={"xatol": SYNTH_SEARCH_XATOL, "fatol": SYNTH_SEARCH_FATOL,
                                "maxiter": 400 * xs.size})
        if best is None or res.fun < best.fun:
            best = res
    return _unpack(best.x, fb0, free) if best.fun < 1e5 else None


def synthesize(
    fb0: FourBar, phi1_min_rad: float, phi1_max_rad: float, objective: str = "max-stroke", *,
    free: str = "range", dy_tol_mm: float = 0.2, mu_min_deg: float = 30.0,
    stroke_mm: float | None = None, force_N: float = 5.0, samples: int = 241, restarts: int = 4,
    seed: int = 0,
) -> SynthesisResult:
    """Optimize ``fb0`` over its crank range for ``objective`` (see module docstring).

    ``stroke_mm`` (mm, or None) is a constraint under both objectives: the result's
    stroke equals it (max-stroke: the crank end is root-found, l2 kept; min-torque-variation:
    every length rescaled). Raises DesignError on a bad objective, free set or tolerance,
    KinematicsError when the start does not run over its range.
    """
    if objective not in OBJECTIVES:
        raise DesignError("--objective", f"unknown objective {objective!r} (known: {', '.join(OBJECTIVES)})")
    if free not in FREE_SETS:
        raise DesignError("--free", f"unknown free set {free!r} (known: {', '.join(FREE_SETS)})")
    if not dy_tol_mm > 0:
        raise DesignError("--dy-tol-mm", f"must be > 0, got {dy_tol_mm!r}")
    start = _safe_metrics(fb0, phi1_min_rad, phi1_max_rad, force_N, samples)
    if start is None:
        raise KinematicsError("the starting linkage does not run over its range; fix it before optimizing")
    counter = {"n": 0}
    x0 = _pack(fb0, phi1_min_rad, phi1_max_rad, free)
    rng = np.random.default_rng(seed)
    starts = [x0] + [x0 * (1 + 0.05 * rng.standard_normal(x0.size)) for _ in range(restarts)]
    bound = None
    if objective == "max-stroke" and stroke_mm is None:

        g = global_max_stroke(fb0, dy_tol_mm, mu_min_deg, force_N)
        counter["n"] += 0 if g is None else g.cells
        if g is not None:
            starts = [_pack(fb0, g.phi1_min_rad, g.phi1_max_rad, free)] + starts
            bound = g.upper_bound_mm if free == "range" else None
    if objective == "max-stroke" and stroke_mm is not None:
        found = _straightest_at_stroke(fb0, free, stroke_mm, mu_min_deg, force_N, samples, starts,
                                       counter)
    elif bound is not None:
        found = (fb0, g.phi1_min_rad, g.phi1_max_rad)
    else:
        found = _penalized_search(fb0, free, objective, start, phi1_max_rad - phi1_min_rad, dy_tol_mm,
                                  mu_min_deg, force_N, samples, starts, counter)
    m = None if found is None else _safe_metrics(*found, force_N, 2001, refine=True)
    feasible = m is not None
    fb, lo, hi = found if m is not None else (fb0, phi1_min_rad, phi1_max_rad)
    m = m if m is not None else start
    if objective == "min-torque-variation" and stroke_mm is not None:
        fb = fb.scaled(stroke_mm / m.stroke_mm)
        m = compute_metrics(fb, lo, hi, force_N=force_N, samples=2001)
    feasible = feasible and m.min_transmission_angle_deg >= mu_min_deg - 1e-6 and m.linearity_velocity > 0
    if objective == "max-stroke":
        feasible = feasible and m.dy_max_mm <= dy_tol_mm * 1.001
    if stroke_mm is not None:
        feasible = feasible and abs(m.stroke_mm - stroke_mm) <= tol.SYNTH_STROKE_REL * stroke_mm
    return SynthesisResult(objective, fb, lo, hi, m, start, counter["n"], bool(feasible), bound)
