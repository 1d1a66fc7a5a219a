"""Monte Carlo and first-order propagation of manufacturing tolerances on a four-bar.

Pure numpy, vectorized over samples *and* crank angles (no CAD). What varies:

- **joint holes** of the three bars, each a 2-D position error in the bar's own frame
  (link frames as in docs/conventions.md): crank holes ``A1`` (on the motor shaft) and
  ``A2``; coupler holes ``A2``, ``A3`` and ``P`` (the handle); rocker holes ``A4``, ``A3``.
  Each coordinate is drawn independently.
- **pivots** on the base: ``A1`` (motor axis) and ``A4`` (rocker post), 2-D errors in R0.
- **link lengths** ``l1``, ``l2``, ``l3``, ``le``: an error along the bar (e.g. a scale or
  kerf error of the cutting process), added to the hole-to-hole distance.

Each tolerance ``T`` (mm) has a distribution: ``normal`` (T = 3 sigma, the usual process
capability reading) or ``uniform`` (every value in [-T, T] equally likely).

How the errors enter the linkage (Hoeken paper Fig. 1 symbols):

- crank: v = h_A2 - h_A1 (holes in the crank frame); l1 = |v| + dl1, and the crank's
  direction is rotated by delta1 = atan2(v_y, v_x) from the commanded motor angle, so the
  effective phi1 = phi1_cmd + delta1 (the motor range is commanded, not manufactured);
- coupler: u = h_A3 - h_A2, w = h_P - h_A2; l2 = |u| + dl2, le = |w| + dle,
  phi_e = atan2(w) - atan2(u);
- rocker: l3 = |h_A3 - h_A4| + dl3;
- base: (l5, l4) = A4 - A1 with both pivots displaced (only their difference matters:
  a common shift moves the whole path, and the metrics live in the path frame).

Metrics per sample, with the definitions of :mod:`cad.kinematics.metrics` (path frame from
P(phi1_min) to P(phi1_max) of *that* sample): ``stroke_mm``, ``dy_max_mm`` and ``slope_max``
(grid maximum, then the two best local maxima zoomed to 1e-7 rad), ``torque_mean_mNm`` and
``torque_variation`` (uniform grid, same formula), ``min_transmission_angle_deg`` and, when
inertia coefficients H are given, ``M11_min_g`` / ``M11_max_g`` (eq 22 on the grid). H is
held at its nominal value: a hole error of 0.05 mm changes a 100 mm bar's mass moments by
~1e-3 relative, far below the kinematic effect on M11 through J.

A sample whose loop cannot close or toggles somewhere in its range is *failed* (counted
against the yield, excluded from the distributions).

First-order (Jacobian) propagation: central differences of every metric with respect to
every error variable give sigma_lin(m) = sqrt(sum_i (dm/de_i sigma_i)^2); the share of
each tolerance is its part of that variance (the sensitivity). At small tolerances the
Monte Carlo standard deviation must equal sigma_lin (tests/unit/studies/test_tolerance.py).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from cad import tolerances as tol
from cad.errors import DesignError
from cad.kinematics.fourbar import FourBar
from cad.tolerances import FD_STEP_MM, ZOOM_SECOND_PEAK_REL, ZOOM_XTOL_RAD

#: holes of each bar, in the bar's own frame
BAR_HOLES: dict[str, tuple[str, ...]] = {
    "crank": ("A1", "A2"), "coupler": ("A2", "A3", "P"), "rocker": ("A4", "A3"),
}
PIVOTS: tuple[str, ...] = ("A1", "A4")
LENGTHS: tuple[str, ...] = ("l1", "l2", "l3", "le")
DISTRIBUTIONS: tuple[str, ...] = ("normal", "uniform")

#: metric keys computed per sample (target keys of cad.design.targets where they exist)
METRIC_KEYS: tuple[str, ...] = (
    "stroke_mm", "dy_max_mm", "slope_max", "torque_mean_mNm", "torque_variation",
    "min_transmission_angle_deg", "M11_min_g", "M11_max_g",
)

#: zoom refinement of extrema: points per pass (the bracket at which it stops: ZOOM_XTOL_RAD;
#: the second peak zoomed too: ZOOM_SECOND_PEAK_REL; propagation step: FD_STEP_MM, cad.tolerances)
ZOOM_POINTS = 21

#: samples evaluated per vectorized batch at the default 401 crank angles (memory ~ CHUNK x
#: angles x 30 float64 arrays, ~200 MB); with more angles a batch holds fewer samples
#: (:func:`chunk_rows`), so memory stays there whatever ``--angles`` is (20001 angles at 2048
#: samples per batch was ~10 GB). Samples are independent rows: the batch size changes no value.
CHUNK = 2048
DEFAULT_ANGLES = 401


def chunk_rows(angles: int) -> int:
    """Samples per vectorized batch for ``angles`` crank angles (at least 1, at most CHUNK)."""
    return max(1, min(CHUNK, CHUNK * DEFAULT_ANGLES // max(int(angles), 1)))


@dataclass(frozen=True)
class Tolerance:
    """One manufacturing tolerance.

    name : ``crank.A2`` (a bar hole), ``base.A4`` (a pivot) or ``length.l2`` (a link length).
    tol_mm : the tolerance T (mm, > 0).
    distribution : ``normal`` (T = 3 sigma) or ``uniform`` (+-T).
    """

    name: str
    tol_mm: float
    distribution: str = "normal"

    @property
    def sigma_mm(self) -> float:
        """Standard deviation of each error coordinate, mm."""
        return self.tol_mm / 3.0 if self.distribution == "normal" else self.tol_mm / math.sqrt(3.0)

    @property
    def dims(self) -> int:
        """Error coordinates: 2 for a hole or pivot (x, y), 1 for a length."""
        return 1 if self.name.startswith("length.") else 2

    def as_dict(self) -> dict:
        return {"name": self.name, "tol_mm": self.tol_mm, "distribution": self.distribution,
                "sigma_mm": self.sigma_mm}


def all_tolerance_names() -> tuple[str, ...]:
    """Every name a :class:`Tolerance` may carry."""
    holes = tuple(f"{b}.{h}" for b, hs in BAR_HOLES.items() for h in hs)
    return holes + tuple(f"base.{p}" for p in PIVOTS) + tuple(f"length.{k}" for k in LENGTHS)


def validate_tolerances(tols: tuple[Tolerance, ...]) -> None:
    """Raise DesignError naming the tolerance on an unknown name, a bad value or distribution."""
    names = all_tolerance_names()
    seen = set()
    for t in tols:
        if t.name not in names:
            raise DesignError(f"tolerance {t.name}", f"unknown (known: {', '.join(names)})")
        if t.name in seen:
            raise DesignError(f"tolerance {t.name}", "given twice")
        seen.add(t.name)
        if not (math.isfinite(t.tol_mm) and 0 < t.tol_mm <= tol.TOLERANCE_MAX_MM):
            raise DesignError(f"tolerance {t.name}",
                              f"must be in (0, {tol.TOLERANCE_MAX_MM:g}] mm, got {t.tol_mm!r}"
                              + (" (a value in um? give mm)" if t.tol_mm > tol.TOLERANCE_MAX_MM else ""))
        if t.distribution not in DISTRIBUTIONS:
            raise DesignError(f"tolerance {t.name}",
                              f"distribution must be normal or uniform, got {t.distribution!r}")


def _columns(tols: tuple[Tolerance, ...]) -> list[tuple[Tolerance, int]]:
    return [(t, k) for t in tols for k in range(t.dims)]


def sample_errors(tols: tuple[Tolerance, ...], n: int, rng: np.random.Generator) -> np.ndarray:
    """Random error variables, shape (n, V) mm, one column per coordinate of each tolerance."""
    cols = _columns(tols)
    e = np.empty((n, len(cols)))
    for j, (t, _) in enumerate(cols):
        if t.distribution == "normal":
            e[:, j] = rng.normal(0.0, t.sigma_mm, n)
        else:
            e[:, j] = rng.uniform(-t.tol_mm, t.tol_mm, n)
    return e


def perturbed_params(fb: FourBar, tols: tuple[Tolerance, ...], e: np.ndarray) -> dict[str, np.ndarray]:
    """Effective linkage of every sample (module docstring), arrays of shape (S,).

    Returns l1..l5, le (mm), phi_e (rad), delta1 (rad, crank direction offset).
    """
    S = e.shape[0]
    err: dict[str, np.ndarray] = {}
    j = 0
    for t in tols:
        err[t.name] = e[:, j:j + t.dims]
        j += t.dims
    z2 = np.zeros((S, 2))

    def hole(name: str, nominal: tuple[float, float]) -> np.ndarray:
        return np.asarray(nominal, dtype=float)[None, :] + err.get(name, z2)

    def dlen(k: str) -> np.ndarray:
        return err[f"length.{k}"][:, 0] if f"length.{k}" in err else np.zeros(S)

    v = hole("crank.A2", (fb.l1_mm, 0.0)) - hole("crank.A1", (0.0, 0.0))
    u = hole("coupler.A3", (fb.l2_mm, 0.0)) - hole("coupler.A2", (0.0, 0.0))
    w = hole("coupler.P", (fb.le_mm * math.cos(fb.phi_e_rad), fb.le_mm * math.sin(fb.phi_e_rad))) \
        - hole("coupler.A2", (0.0, 0.0))
    r = hole("rocker.A3", (fb.l3_mm, 0.0)) - hole("rocker.A4", (0.0, 0.0))
    base = hole("base.A4", (fb.l5_mm, fb.l4_mm)) - hole("base.A1", (0.0, 0.0))
    return {
        "l1": np.hypot(v[:, 0], v[:, 1]) + dlen("l1"),
        "l2": np.hypot(u[:, 0], u[:, 1]) + dlen("l2"),
        "l3": np.hypot(r[:, 0], r[:, 1]) + dlen("l3"),
        "le": np.hypot(w[:, 0], w[:, 1]) + dlen("le"),
        "l4": base[:, 1], "l5": base[:, 0],
        "phi_e": np.arctan2(w[:, 1], w[:, 0]) - np.arctan2(u[:, 1], u[:, 0]),
        "delta1": np.arctan2(v[:, 1], v[:, 0]),
    }


def batch_kinematics(p: dict[str, np.ndarray], branch: int, phi1: np.ndarray) -> dict[str, np.ndarray]:
    """P, J = dP/dphi1, alpha2, alpha3 for per-sample linkages ``p`` (arrays (S, 1)) at ``phi1`` (S, K).

    Same equations as :func:`cad.kinematics.fourbar.coupler_point_and_jacobian` (eqs 3-12)
    broadcast over samples; instead of raising, ``ok`` (S, K) marks poses that close and are
    away from a toggle (|sin(phi2 - phi3)| >= TOGGLE_SIN). Lengths mm, angles rad.
    """
    l1, l2, l3, l4, l5, le, pe = (p[k] for k in ("l1", "l2", "l3", "l4", "l5", "le", "phi_e"))
    c1, s1 = np.cos(phi1), np.sin(phi1)
    dx, dy = l1 * c1 - l5, l1 * s1 - l4
    A, B = 2.0 * l2 * dx, 2.0 * l2 * dy
    C = l3 * l3 - l2 * l2 - (dx * dx + dy * dy)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = C / np.sqrt(A * A + B * B)
        closes = np.abs(ratio) <= 1.0 + 1e-12
        phi2 = np.arctan2(B, A) + branch * np.arccos(np.clip(ratio, -1.0, 1.0))
        c2, s2 = np.cos(phi2), np.sin(phi2)
        c3, s3 = (dx + l2 * c2) / l3, (dy + l2 * s2) / l3  # eqs 7-8
        s23 = s2 * c3 - c2 * s3
        ok = closes & (np.abs(s23) >= tol.TOGGLE_SIN)
        a2 = l1 * (s3 * c1 - c3 * s1) / (l2 * s23)  # eq 11
        a3 = l1 * (s2 * c1 - c2 * s1) / (l3 * s23)
    ce, se = np.cos(pe), np.sin(pe)
    cpe, spe = c2 * ce - s2 * se, s2 * ce + c2 * se
    P = np.stack([l1 * c1 + le * cpe, l1 * s1 + le * spe], axis=-1)
    J = np.stack([-l1 * s1 - le * a2 * spe, l1 * c1 + le * a2 * cpe], axis=-1)
    return {"P": P, "J": J, "a2": a2, "a3": a3, "phi2": phi2, "s23": s23, "ok": ok}


def _zoom_max(f: Callable[[np.ndarray, np.ndarray], np.ndarray], t: np.ndarray, vals: np.ndarray,
              rows: np.ndarray) -> np.ndarray:
    """Max over t of ``f`` for every row: the two best local grid maxima, zoomed to ZOOM_XTOL_RAD.

    ``f(rows, t_grid)`` returns values (len(rows), K) at commanded angles t_grid (len(rows), K);
    ``vals`` (S, N) are the values on the uniform grid ``t`` (N,). Returns (S,).
    """
    S, N = vals.shape
    v = np.where(np.isfinite(vals), vals, -np.inf)
    locmax = np.ones_like(v, dtype=bool)
    locmax[:, 1:] &= v[:, 1:] >= v[:, :-1]
    locmax[:, :-1] &= v[:, :-1] >= v[:, 1:]
    score = np.where(locmax, v, -np.inf)
    order = np.argsort(-score, axis=1)[:, :2]
    best = v.max(axis=1)
    lo, hi = t[0], t[-1]
    step = (t[-1] - t[0]) / (N - 1)
    top = score[np.arange(S), order[:, 0]]
    for n_cand, c_idx in enumerate(order.T):
        sel = np.arange(S)
        if n_cand:  # a second peak only where it may beat the first (grid error << 1 %)
            sel = np.nonzero(score[sel, c_idx] >= top - ZOOM_SECOND_PEAK_REL * np.abs(top))[0]
            if sel.size == 0:
                continue
        best[sel] = np.maximum(best[sel], _zoom_rows(f, rows[sel], t[c_idx[sel]], step, lo, hi))
    return best


def _zoom_rows(f, rows: np.ndarray, centre: np.ndarray, step: float, lo: float, hi: float) -> np.ndarray:
    """Zoom local grids around ``centre`` (one per row) down to ZOOM_XTOL_RAD; the max found."""
    n = len(rows)
    best = np.full(n, -np.inf)
    offs = np.linspace(-1.0, 1.0, ZOOM_POINTS)
    half = step
    while half > ZOOM_XTOL_RAD:
        grid = np.clip(centre[:, None] + half * offs[None, :], lo, hi)
        g = f(rows, grid)
        g = np.where(np.isfinite(g), g, -np.inf)
        j = np.argmax(g, axis=1)
        best = np.maximum(best, g[np.arange(n), j])
        centre = grid[np.arange(n), j]
        half = 2.0 * half / (ZOOM_POINTS - 1)
    return best


def batch_metrics(p: dict[str, np.ndarray], branch: int, phi1_min_rad: float, phi1_max_rad: float,
                  force_N: float, angles: int, H=None) -> dict[str, np.ndarray]:
    """Metrics of every sample (module docstring), arrays (S,); ``valid`` (S,) bool.

    ``p``: per-sample linkages from :func:`perturbed_params` (shape (S,)); the crank is
    commanded over [phi1_min, phi1_max] (rad) on ``angles`` uniform samples; ``H`` an
    :class:`cad.dynamics.inertia.InertiaCoefficients` or None (then no M11).
    """
    q = {k: np.asarray(v, dtype=float)[:, None] for k, v in p.items()}
    S = q["l1"].shape[0]
    t = np.linspace(phi1_min_rad, phi1_max_rad, angles)
    phi = t[None, :] + q["delta1"]
    k = batch_kinematics(q, branch, phi)
    valid = k["ok"].all(axis=1)
    P, J = k["P"], k["J"]
    origin = P[:, 0, :]
    chord = P[:, -1, :] - origin
    stroke = np.hypot(chord[:, 0], chord[:, 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        xh = chord / stroke[:, None]
    yh = np.stack([-xh[:, 1], xh[:, 0]], axis=-1)
    y = np.einsum("skj,sj->sk", P - origin[:, None, :], yh)
    jx = np.einsum("skj,sj->sk", J, xh)
    jy = np.einsum("skj,sj->sk", J, yh)

    def sub(rows: np.ndarray) -> dict[str, np.ndarray]:
        return {kk: vv[rows] for kk, vv in q.items()}

    def abs_y(rows: np.ndarray, tg: np.ndarray) -> np.ndarray:
        kk = batch_kinematics(sub(rows), branch, tg + q["delta1"][rows])
        return np.abs(np.einsum("skj,sj->sk", kk["P"] - origin[rows][:, None, :], yh[rows]))

    def abs_slope(rows: np.ndarray, tg: np.ndarray) -> np.ndarray:
        kk = batch_kinematics(sub(rows), branch, tg + q["delta1"][rows])
        a = np.einsum("skj,sj->sk", kk["J"], xh[rows])
        b = np.einsum("skj,sj->sk", kk["J"], yh[rows])
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.abs(b / a)

    rows = np.arange(S)
    with np.errstate(divide="ignore", invalid="ignore"):
        dy_max = _zoom_max(abs_y, t, np.abs(y), rows)
        slope_max = _zoom_max(abs_slope, t, np.abs(jy / jx), rows)
        tau = force_N * jx  # N * mm/rad = mN.m
        tau_mean = np.abs(tau).mean(axis=1)
        tau_var = np.abs(tau - tau.mean(axis=1, keepdims=True)).max(axis=1) / tau_mean
        mu = np.degrees(np.arcsin(np.clip(np.abs(k["s23"]), 0.0, 1.0))).min(axis=1)
    out = {"stroke_mm": stroke, "dy_max_mm": dy_max, "slope_max": slope_max,
           "torque_mean_mNm": tau_mean, "torque_variation": tau_var,
           "min_transmission_angle_deg": mu}
    if H is not None:
        c = np.cos(phi - k["phi2"] - H.beta2_rad)
        D = (H.H11_kg_m2 + 2.0 * H.H12_kg_m2 * c * k["a2"] + H.H22_kg_m2 * k["a2"] ** 2
             + H.H33_kg_m2 * k["a3"] ** 2)
        with np.errstate(divide="ignore", invalid="ignore"):
            n2 = (jx**2 + jy**2) * 1e-6  # (m/rad)^2
            m11 = D * jx**2 * 1e-6 / n2**2 * 1e3  # g, eq (22) in path axes
        out["M11_min_g"] = m11.min(axis=1)
        out["M11_max_g"] = m11.max(axis=1)
    valid &= np.all([np.isfinite(v) for v in out.values()], axis=0) & (stroke > 0)
    for key in out:
        out[key] = np.where(valid, out[key], np.nan)
    out["valid"] = valid
    return out


@dataclass(frozen=True)
class ToleranceStudy:
    """Inputs of a study: the nominal linkage and its commanded range (rad), the tolerances."""

    linkage: FourBar
    phi1_min_rad: float
    phi1_max_rad: float
    force_N: float
    tolerances: tuple[Tolerance, ...]
    angles: int = DEFAULT_ANGLES
    H: object = None

    def metrics(self, e: np.ndarray) -> dict[str, np.ndarray]:
        """Metrics for error rows ``e`` (S, V) mm, evaluated in batches of :func:`chunk_rows`."""
        parts = []
        rows = chunk_rows(self.angles)
        for i in range(0, max(e.shape[0], 1), rows):
            p = perturbed_params(self.linkage, self.tolerances, e[i:i + rows])
            parts.append(batch_metrics(p, self.linkage.branch, self.phi1_min_rad, self.phi1_max_rad,
                                       self.force_N, self.angles, self.H))
        return {k: np.concatenate([pp[k] for pp in parts]) for k in parts[0]}

    @property
    def n_vars(self) -> int:
        return sum(t.dims for t in self.tolerances)

    def nominal(self) -> dict[str, float]:
        """Metrics of the nominal linkage through the same kernel."""
        m = self.metrics(np.zeros((1, self.n_vars)))
        return {k: float(v[0]) for k, v in m.items() if k != "valid"}

    def gradient(self, step_mm: float = FD_STEP_MM) -> dict[str, np.ndarray]:
        """d metric / d error variable (per mm), central differences, shape (V,) per metric."""
        V = self.n_vars
        e = np.concatenate([np.eye(V) * step_mm, -np.eye(V) * step_mm])
        m = self.metrics(e)
        return {k: (v[:V] - v[V:]) / (2.0 * step_mm) for k, v in m.items() if k != "valid"}

    def first_order(self) -> dict[str, dict]:
        """Linear standard deviation of every metric and each tolerance's share of its variance."""
        grad = self.gradient()
        sig = np.array([t.sigma_mm for t, _ in _columns(self.tolerances)])
        owners = [t.name for t, _ in _columns(self.tolerances)]
        out = {}
        for key, g in grad.items():
            contrib = (g * sig) ** 2
            total = float(contrib.sum())
            per: dict[str, float] = {}
            for name, c in zip(owners, contrib, strict=True):
                per[name] = per.get(name, 0.0) + float(c)
            out[key] = {
                "linear_std": math.sqrt(total),
                "sensitivity": [{"tolerance": n, "std": math.sqrt(c),
                                 "share": (c / total) if total > 0 else 0.0}
                                for n, c in sorted(per.items(), key=lambda kv: -kv[1])],
            }
        return out

    def monte_carlo(self, samples: int, seed: int = 0) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """(errors (S, V), metrics) of ``samples`` seeded random draws."""
        rng = np.random.default_rng(seed)
        e = sample_errors(self.tolerances, samples, rng)
        return e, self.metrics(e)
