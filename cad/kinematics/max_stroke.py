"""The longest straight segment of a four-bar's coupler curve, found globally with a bound.

Problem (``hapticad synth --objective max-stroke``, free ``range``): over every crank window
[a, b] (b - a < 2 pi, the loop closing on all of it) maximise the stroke |P(b) - P(a)|
subject to dy(a, b) = max over phi in [a, b] of the distance of P(phi) from the chord line
<= dy_tol, the transmission angle >= mu_min over the window, and x(phi) monotone along the
chord.

Method: branch and bound over cells of windows [a0, a1] x [b0, b1] of crank angle. For a cell
with midpoints (am, bm), half widths (ha, hb) and the largest coupler-point speeds La, Lb over
its two end intervals (sampled at 0.01 deg, plus the largest acceleration times half that
step), every window in it has

    stroke <= |P(bm) - P(am)| + La ha + Lb hb                                   (upper)
    dy     >= max_k  |s_k| - (|1 - t_k| da + |t_k| db) - (da + db) |s_k| / c
                         - 2 (da + db)^2 / c                                    (lower)

with c the midpoint chord, s_k and t_k the signed distance and the chord parameter of each
sample P_k of the core [a1, b0] (in every window of the cell) and da = La ha, db = Lb hb the
ends' largest moves (the chord line moves by at most the interpolated or extrapolated end
moves, plus its turn for points off the line and a second-order term for the chord's change
of length). A cell whose lower dy bound exceeds dy_tol, whose core holds
a transmission angle below mu_min or a crank angle where the loop does not close, or whose
upper stroke is below the best feasible stroke found, holds no better window and is dropped;
the others are split in four, down to 0.005 deg or until the next level would take the
cells bounded past :data:`cad.tolerances.SYNTH_BOUND_MAX_CELLS` (the bound is then that of
the cells left: still valid, less tight, and reported as it is). The best feasible window found on the way
(its dy, transmission angle and monotonicity checked by :func:`cad.kinematics.metrics.
compute_metrics` with the extremum refined) is polished by Nelder-Mead; the largest upper
bound of the cells left is the proof: no window of the linkage is longer than
``upper_bound_mm``. Monotonicity is not used to drop cells (dropping fewer cells keeps the
bound valid). Pure numpy/scipy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cad.errors import KinematicsError
from cad.kinematics.fourbar import (
    FourBar,
    closure_margin,
    coupler_point_and_jacobian,
    solve,
    transmission_angle_rad,
)
from cad.kinematics.metrics import Metrics, compute_metrics
from cad.tolerances import SYNTH_BOUND_MAX_CELLS, TOGGLE_SIN

#: Sample step of the speed bounds (rad): 0.01 deg.
SPEED_STEP = math.radians(0.01)
#: Sample step of the core points of the dy lower bound (rad): 0.05 deg.
CORE_STEP = math.radians(0.05)
#: Step of the first pass of the dy lower bound (rad): 0.5 deg; the finer pass looks only
#: within one such step of the first pass's largest value (any subset gives a valid bound).
COARSE_STEP = math.radians(0.5)
#: First cell size (rad) and the size below which cells are not split further (rad).
FIRST_CELL = math.radians(1.0)
LAST_CELL = math.radians(0.005)


@dataclass(frozen=True)
class MaxStroke:
    """The longest feasible window found and the proven bound.

    phi1_min_rad / phi1_max_rad: the window; metrics: its refined metrics;
    upper_bound_mm: no window of the linkage meeting the constraints is longer;
    cells: windows cells evaluated (all levels); levels: bisection levels run.
    """

    phi1_min_rad: float
    phi1_max_rad: float
    metrics: Metrics
    upper_bound_mm: float
    cells: int
    levels: int


class _Curve:
    """The coupler curve sampled once over two turns: closure, transmission angle and a
    speed bound (mm/rad) on a SPEED_STEP grid, as prefix counts / arrays for interval queries."""

    def __init__(self, fb: FourBar, mu_min_deg: float):
        self.fb = fb
        phi = np.arange(0.0, 2 * math.pi, SPEED_STEP)
        closes = closure_margin(fb, phi) > 0
        if not closes.any():
            raise KinematicsError("the loop closes at no crank angle")
        safe = np.where(closes, phi, phi[np.flatnonzero(closes)[0]])
        toggle = np.abs(np.sin(transmission_angle_rad(solve(fb, safe)))) < TOGGLE_SIN
        closes &= ~toggle  # a toggle is no place for a window either (no finite Jacobian)
        if not closes.any():
            raise KinematicsError("the loop closes at no crank angle away from a toggle")
        safe = np.where(closes, phi, phi[np.flatnonzero(closes)[0]])
        pose = solve(fb, safe)
        _, J = coupler_point_and_jacobian(fb, safe)
        speed = np.where(closes, np.linalg.norm(J, axis=1), 0.0)
        acc = np.abs(np.diff(speed, append=speed[:1])) / SPEED_STEP
        speed = speed + acc.max() * SPEED_STEP / 2
        mu = np.degrees(transmission_angle_rad(pose))
        bad = ~closes | (mu < mu_min_deg)
        self.closes2 = np.concatenate([closes, closes, closes[:1]])
        self.n = phi.size
        self.closes2 = np.concatenate([closes, closes, closes[:1]])
        core = np.arange(0.0, 4 * math.pi + CORE_STEP, CORE_STEP)
        core_safe = np.where(self.closes2[np.minimum((core / SPEED_STEP).astype(int),
                                                    self.closes2.size - 1) % self.n], core, safe[0])
        self.core_P = coupler_point_and_jacobian(fb, core_safe)[0]
        self.core_P_phi0 = float(safe[0])
        self.speed2 = np.concatenate([speed, speed, speed[:1]])
        self.bad_count = np.concatenate([[0], np.cumsum(np.concatenate([bad, bad]))])

    def _k(self, phi: np.ndarray) -> np.ndarray:
        return np.floor(phi / SPEED_STEP).astype(int)

    def max_speed(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """Largest speed bound (mm/rad) over each [lo, hi] (arrays, rad, 0 <= lo < 2 pi)."""
        i0 = self._k(lo)
        i1 = np.minimum(self._k(hi) + 2, self.speed2.size)
        idx = np.stack([i0, i1], axis=1).ravel()
        return np.maximum.reduceat(self.speed2, idx)[::2]

    def end_point(self, lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """A reference crank angle in each end interval [lo, hi] where the loop closes (the
        midpoint when it does, else the closing grid angle nearest it; NaN when none does)
        and the largest distance (rad) from it to the interval's ends."""
        mid = (lo + hi) / 2
        ref = mid.copy()
        for i in np.flatnonzero(~self.closes2[self._k(mid)]):
            k = np.arange(self._k(lo[i]), self._k(hi[i]) + 1)
            good = k[self.closes2[np.minimum(k, self.closes2.size - 1)]]
            ref[i] = np.nan if good.size == 0 else (good[np.argmin(np.abs(good - self._k(mid[i])))] + 0.5) * SPEED_STEP
        return ref, np.maximum(ref - lo, hi - ref)

    def core_ok(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """Each core [lo, hi] closes and keeps the transmission angle (empty core: True)."""
        i0, i1 = self._k(lo), np.maximum(self._k(hi), self._k(lo))
        i1 = np.minimum(i1, self.bad_count.size - 1)
        return (self.bad_count[i1] - self.bad_count[i0]) == 0


def _ends(curve: _Curve, a0, a1, b0, b1):
    """Reference angles of both ends, their largest moves (mm) and the cells whose ends close."""
    ra, wa = curve.end_point(a0, a1)
    rb, wb = curve.end_point(b0, b1)
    ok = np.isfinite(ra) & np.isfinite(rb)
    ra, rb = np.where(ok, ra, a0), np.where(ok, rb, b0)
    return ra, rb, curve.max_speed(a0, a1) * wa, curve.max_speed(b0, b1) * wb, ok


def _upper(curve: _Curve, a0, a1, b0, b1):
    """Stroke upper bound (mm) of each cell: the reference chord plus the ends' largest
    moves; -inf for a cell with an end where the loop never closes."""
    ra, rb, da, db, ok = _ends(curve, a0, a1, b0, b1)
    Pa = coupler_point_and_jacobian(curve.fb, np.where(ok, ra, curve.core_P_phi0))[0]
    Pb = coupler_point_and_jacobian(curve.fb, np.where(ok, rb, curve.core_P_phi0))[0]
    return np.where(ok, np.linalg.norm(Pb - Pa, axis=1) + da + db, -np.inf)


def _coarse_best(curve: _Curve, dy_tol, mu_min, force_N, step_deg: float = 0.5):
    """A first feasible window: every window on a ``step_deg`` grid with its dy sampled on
    the grid, the longest few checked exactly (:func:`_feasible`). (lo, hi, Metrics) or None."""
    phi = np.radians(np.arange(0.0, 360.0, step_deg))
    ok = curve.core_ok(phi, phi + math.radians(step_deg))
    n = phi.size
    P = coupler_point_and_jacobian(curve.fb, np.where(ok, phi, curve.core_P_phi0))[0]
    P2, ok2 = np.concatenate([P, P]), np.concatenate([ok, ok])
    cand = []
    for i in np.flatnonzero(ok):
        run = np.flatnonzero(~ok2[i:i + n])
        m = run[0] if run.size else n - 1
        seg = P2[i:i + m]
        c = seg - seg[0]
        L = np.maximum(np.linalg.norm(c, axis=1), 1e-12)
        u = c / L[:, None]
        dist = np.abs(u[:, 0, None] * c[None, :, 1] - u[:, 1, None] * c[None, :, 0])
        dy = np.where(np.arange(m)[None, :] <= np.arange(m)[:, None], dist, 0).max(axis=1)
        good = np.flatnonzero(dy <= dy_tol)
        if good.size:
            j = good[np.argmax(L[good])]
            cand.append((L[j], phi[i], phi[i] + j * math.radians(step_deg)))
    for _, lo, hi in sorted(cand, reverse=True)[:20]:
        m = _feasible(curve.fb, lo, hi, dy_tol, mu_min, force_N)
        if m is not None:
            return lo, hi, m
    return None


def _cell_bounds(curve: _Curve, a0, a1, b0, b1, step: float):
    """(stroke upper bound, dy lower bound) of each cell (arrays, rad); core samples every
    ``step`` rad (any subset of the core gives a valid lower bound)."""
    fb = curve.fb
    ra, rb, da, db, ok = _ends(curve, a0, a1, b0, b1)
    Pa = coupler_point_and_jacobian(fb, np.where(ok, ra, curve.core_P_phi0))[0]
    Pb = coupler_point_and_jacobian(fb, np.where(ok, rb, curve.core_P_phi0))[0]
    chord = Pb - Pa
    c = np.maximum(np.linalg.norm(chord, axis=1), 1e-12)
    u = chord / c[:, None]
    lower, arg = _lower_pass(curve, Pa, u, c, da, db, a1, b0,
                             max(1, int(round(max(step, COARSE_STEP) / CORE_STEP))))
    fine = max(1, int(round(step / CORE_STEP)))
    if fine < int(round(COARSE_STEP / CORE_STEP)):  # refine about the coarse maximum
        half = COARSE_STEP
        lo = np.maximum(a1, arg - half)
        hi = np.minimum(b0, arg + half)
        lower2, _ = _lower_pass(curve, Pa, u, c, da, db, lo, hi, fine)
        lower = np.maximum(lower, lower2)
    return c + da + db, lower


def _lower_pass(curve: _Curve, Pa, u, c, da, db, lo, hi, stride: int):
    """max over the grid samples in [lo, hi] (every ``stride`` CORE_STEP) of the distance
    from the chord line less the slack (the dy lower bound, module docstring), and the crank
    angle where it is reached, per cell."""
    k0 = np.ceil(lo / CORE_STEP).astype(int)
    n = np.maximum((np.floor(hi / CORE_STEP).astype(int) - k0) // stride + 1, 0)
    n = np.where(hi > lo, n, 0)
    lower, arg = np.zeros(lo.size), (lo + hi) / 2
    for chunk in np.array_split(np.arange(lo.size), max(1, int(n.sum() // 1_000_000) + 1)):
        if chunk.size == 0 or n[chunk].max() == 0:
            continue
        k = np.arange(n[chunk].max())
        mask = k[None, :] < n[chunk, None]
        idx = np.where(mask, k0[chunk, None] + stride * k[None, :], k0[chunk, None])
        d = curve.core_P[np.minimum(idx, curve.core_P.shape[0] - 1)] - Pa[chunk, None, :]
        uc, cc = u[chunk], c[chunk, None]
        s = np.abs(uc[:, 0, None] * d[..., 1] - uc[:, 1, None] * d[..., 0])
        t = (d[..., 0] * uc[:, 0, None] + d[..., 1] * uc[:, 1, None]) / cc
        dd = (da + db)[chunk, None]
        slack = (np.abs(1 - t) * da[chunk, None] + np.abs(t) * db[chunk, None]
                 + dd * s / cc + 2 * dd * dd / cc)
        v = np.where(mask, s - slack, -np.inf)
        j = np.argmax(v, axis=1)
        lower[chunk] = np.maximum(v[np.arange(chunk.size), j], 0.0)
        arg[chunk] = idx[np.arange(chunk.size), j] * CORE_STEP
    return lower, arg


def _feasible(fb, lo, hi, dy_tol, mu_min, force_N) -> Metrics | None:
    """The refined metrics of [lo, hi] when the window meets every constraint, else None."""
    try:
        m = compute_metrics(fb, lo, hi, force_N=force_N, samples=2001, refine=True)
    except (KinematicsError, ValueError):
        return None
    ok = (m.dy_max_mm <= dy_tol and m.min_transmission_angle_deg >= mu_min
          and m.linearity_velocity > 1e-3)
    return m if ok else None


def _first_cells():
    """Every window cell of FIRST_CELL size with a0 in [0, 2 pi), b - a < 2 pi."""
    n = int(round(2 * math.pi / FIRST_CELL))
    i, j = np.meshgrid(np.arange(n), np.arange(1, n - 1), indexing="ij")
    a0 = (i * FIRST_CELL).ravel().astype(float)
    b0 = a0 + (j * FIRST_CELL).ravel()
    return a0, a0 + FIRST_CELL, b0, b0 + FIRST_CELL


def _split(a0, a1, b0, b1):
    am, bm = (a0 + a1) / 2, (b0 + b1) / 2
    A0 = np.concatenate([a0, a0, am, am])
    A1 = np.concatenate([am, am, a1, a1])
    B0 = np.concatenate([b0, bm, b0, bm])
    B1 = np.concatenate([bm, b1, bm, b1])
    return A0, A1, B0, B1


def _polish(fb, lo, hi, dy_tol, mu_min, force_N):
    """Nelder-Mead on -stroke over (lo, hi) from a feasible window, infeasible points
    penalised: the longest feasible window near it (at least the start)."""
    from scipy.optimize import minimize

    def cost(x):
        m = _feasible(fb, x[0], x[1], dy_tol, mu_min, force_N)
        return 1e6 if m is None else -m.stroke_mm

    res = minimize(cost, [lo, hi], method="Nelder-Mead",
                   options={"xatol": 1e-7, "fatol": 1e-7, "initial_simplex":
                            [[lo, hi], [lo + 1e-3, hi], [lo, hi - 1e-3]]})
    return (res.x[0], res.x[1]) if res.fun < cost([lo, hi]) else (lo, hi)


def global_max_stroke(fb: FourBar, dy_tol_mm: float, mu_min_deg: float,
                      force_N: float = 5.0) -> MaxStroke | None:
    """The longest window meeting the constraints (module docstring) and the bound that no
    window is longer than ``upper_bound_mm``; None when no window is feasible."""
    curve = _Curve(fb, mu_min_deg)
    first = _coarse_best(curve, dy_tol_mm, mu_min_deg, force_N)
    if first is None:
        return None
    best, best_m = (first[0], first[1]), first[2]
    cells, size, evaluated, level, upper_left = _first_cells(), FIRST_CELL, 0, 0, 0.0
    while cells[0].size:
        level += 1
        cells, up, n = _surviving(curve, cells, size, best_m.stroke_mm, dy_tol_mm)
        evaluated += n
        for i in np.argsort(-up)[:8]:  # the most promising cells' midpoints
            lo, hi = (cells[0][i] + cells[1][i]) / 2, (cells[2][i] + cells[3][i]) / 2
            m = _feasible(fb, lo, hi, dy_tol_mm, mu_min_deg, force_N)
            if m is not None and m.stroke_mm > best_m.stroke_mm:
                best, best_m = (lo, hi), m
        keep = up > best_m.stroke_mm
        cells, up = tuple(c[keep] for c in cells), up[keep]
        upper_left = float(up.max()) if up.size else 0.0
        if size <= LAST_CELL or evaluated + 4 * cells[0].size > SYNTH_BOUND_MAX_CELLS:
            break
        cells, size = _split(*cells), size / 2
    lo, hi = _polish(fb, *best, dy_tol_mm, mu_min_deg, force_N)
    m = _feasible(fb, lo, hi, dy_tol_mm, mu_min_deg, force_N)
    return MaxStroke(lo, hi, m, max(upper_left, m.stroke_mm), evaluated, level)


def _surviving(curve: _Curve, cells, size: float, floor_mm: float, dy_tol_mm: float):
    """The cells that may hold a feasible window longer than ``floor_mm``, their stroke
    upper bounds, and how many cells were bounded."""
    keep = curve.core_ok(cells[1], cells[2])
    cells = tuple(c[keep] for c in cells)
    up = _upper(curve, *cells)
    keep = up > floor_mm
    cells, up = tuple(c[keep] for c in cells), up[keep]
    _, low = _cell_bounds(curve, *cells, max(CORE_STEP, size / 2))
    keep = low <= dy_tol_mm
    return tuple(c[keep] for c in cells), up[keep], int(keep.size)
