"""Flat voice-coil (Lorentz) actuator: gap field, force per unit power, optimisers.

Pure numpy/scipy (magpylib is imported lazily, only by the ``"magpylib"`` field
model). Isotropy paper (Salcudean & Stocco), section 6, eqs (8)-(9), Fig. 7-8.

Actuator frame (used everywhere in this package)
------------------------------------------------
* z: gap normal (magnetisation direction); the gap centre plane is z = 0.
* x: actuation (force) direction. Two magnet pairs sit side by side:
  pair A centred at x = +w_m/2 polarised +z, pair B at x = -w_m/2 polarised -z
  (the paper's four magnets per actuator; 6 actuators x 4 = the PowerMouse's
  24 magnets).
* y: along the magnets' length l_m, the direction of the current in the
  coil's two straight legs (leg A over pair A carries +y, leg B -y), so both
  legs push along +x.

Magnet dimensions: l_m along y, w_m along x, t_m along z (all FULL lengths).
The gap d is the distance between the magnet faces; the coil is d_c = d - d_r
thick, d_r being the "rattle space" (paper: d_r = d - d_c).

Derivation of eq (9) (the extracted text garbles its bracket)
------------------------------------------------------------
A magnet uniformly polarised J = B_r z_hat is equivalent to a rectangular
current sheet ("solenoid") on its side faces. On its axis at a distance z
from a pole face, with half-dimensions a = w_m/2, b = l_m/2, Biot-Savart
gives the standard result (e.g. magpylib's cuboid kernel, Yang 1990)

    B_z = (B_r/pi) [atan(a b / (z1 sqrt(z1^2+a^2+b^2))) - atan(a b / (z2 sqrt(z2^2+a^2+b^2)))]

with z1, z2 the distances to the near and the far face. With full
dimensions and s = 2z this is atan(l w / (s sqrt(s^2 + l^2 + w^2))). Ideal
(mu -> infinity) back iron touching the magnet's back face: the tangential H
vanishes there, which is satisfied by an image magnet of the same polarisation
mirrored through the iron surface, so magnet + image is one magnet of
thickness 2 t_m. The two magnets' near faces are at d/2 from the gap centre
(s = d), the far faces of their images at d/2 + 2 t_m (s = d + 4 t_m); both
magnets contribute equally, hence

    B_g = (2 B_r / pi) [atan(w l / (d sqrt(d^2+l^2+w^2))) - atan(w l / ((4t+d) sqrt((4t+d)^2+l^2+w^2)))]   (9)

which equals magpylib's exact cuboid field with one image per plate to
~1e-15 relative (tests/unit/actuators/test_voicecoil.py).

Eq (9) keeps one image per plate. Two parallel ideal plates (at z = +-(d/2+t))
reflect each other's images without end: the full series is a periodic stack
of 2t-thick slabs with period d + 2t, all polarised alike; slab k >= 0 has its
near face at d/2 + k(d + 2t). Far slabs act as dipoles (field ~ 1/z^3), so the
truncation error after K slabs per side falls as 1/K^2
(:func:`image_series_tail_T`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from cad.actuators import field_magpylib as fm
from cad.errors import DesignError
from cad.tolerances import (
    GAP_XATOL_REL,
    NLP_ACTIVE_MM,
    NLP_COIL_WIDTH_MIN_MM,
    NLP_FEASIBLE_SLACK_MM,
    NLP_SLSQP_FTOL,
)

#: Field models understood by :func:`gap_field_T` and the optimisers.
MODELS = ("closed-form", "images", "magpylib")
Model = Literal["closed-form", "images", "magpylib"]

#: Copper resistivity at 20 C (ohm m), CRC Handbook.
RHO_COPPER_OHM_M = 1.72e-8
#: Remanence of sintered NdFeB N42 (T), typical datasheet 1.28-1.32; 1.2 is a
#: conservative value (N35-N38 class or N42 at ~60 C).
BR_DEFAULT_T = 1.2
#: Packing efficiency of round-wire coils (paper section 6: "about 75%").
ETA_PACK_DEFAULT = 0.75
#: Coil power of the paper's Fig. 8 (W).
POWER_DEFAULT_W = 8.0
#: Slabs per side used as the "converged" image-series reference before the
#: asymptotic tail is added (the tail at this K is < 1e-10 of B_g for any
#: geometry with t_m >= 0.01 d; the remainder after the tail ~ 1/K^4).
IMAGE_SERIES_CONVERGED_TERMS = 4096
#: Tenfold extensions of the default gap search before giving up: the optimum
#: lies below d_r + 10 (l_m + w_m + t_m + d_r) for every geometry tried
#: (tests/unit/actuators/test_stability_actuators.py), so this is a safety net.
GAP_BRACKET_EXTENSIONS = 30
#: Magnitude bounds of every VoiceCoilParams number (mm, W, T, ohm m). The kernels are
#: scale-free (eq 9 depends on length ratios; eq 8 is evaluated factor by factor), but
#: their sums, squares and the optimizer's tolerances need headroom: 1e+-100 leaves
#: > 200 orders of magnitude to float64's limits (the CLI fuzz hit overflows at 1e307
#: and denormal sizes of 1e-313). No actuator comes near either bound.
MAGNITUDE_MIN = 1e-100
MAGNITUDE_MAX = 1e100
_FLOAT_MAX = float(np.finfo(float).max)
_FLOAT_TINY = float(np.finfo(float).tiny)


@dataclass(frozen=True)
class VoiceCoilParams:
    """Parameters of one flat-coil actuator (isotropy paper Fig. 7).

    magnet_length_mm: l_m, magnet length along the coil legs (actuator y).
    magnet_width_mm: w_m, magnet width along the force (actuator x).
    magnet_thickness_mm: t_m, magnet thickness along the gap normal (z).
    rattle_mm: d_r = d - d_c, free space between coil and magnets (total, both sides).
    power_W: P_coil, power dissipated in the coil.
    br_T: B_r, magnet remanence.
    resistivity_ohm_m: rho of the coil conductor.
    eta_pack: conducting / total wire cross-section (0, 1].
    """

    magnet_length_mm: float
    magnet_width_mm: float
    magnet_thickness_mm: float
    rattle_mm: float
    power_W: float = POWER_DEFAULT_W
    br_T: float = BR_DEFAULT_T
    resistivity_ohm_m: float = RHO_COPPER_OHM_M
    eta_pack: float = ETA_PACK_DEFAULT

    def __post_init__(self) -> None:
        for name in self.__dataclass_fields__:
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise DesignError(name, f"must be a number, got {v!r}")
        for name in (
            "magnet_length_mm",
            "magnet_width_mm",
            "magnet_thickness_mm",
            "power_W",
            "br_T",
            "resistivity_ohm_m",
        ):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0):
                raise DesignError(name, f"must be a finite number > 0, got {v!r}")
        if not (math.isfinite(self.rattle_mm) and self.rattle_mm >= 0):
            raise DesignError("rattle_mm", f"must be a finite number >= 0, got {self.rattle_mm!r}")
        if not (0 < self.eta_pack <= 1):
            raise DesignError("eta_pack", f"must be in (0, 1], got {self.eta_pack!r}")
        for name in self.__dataclass_fields__:
            v = getattr(self, name)
            if v != 0 and not (MAGNITUDE_MIN <= v <= MAGNITUDE_MAX):
                raise DesignError(
                    name,
                    f"must lie in [{MAGNITUDE_MIN:g}, {MAGNITUDE_MAX:g}] (float64 headroom), got {v!r}",
                )

    @property
    def eta_geom(self) -> float:
        """Coil geometric efficiency (paper: ~0.6 for l_m = 20, w_m = 8 mm)."""
        return float(eta_geom(self.magnet_length_mm, self.magnet_width_mm))


# ---------------------------------------------------------------- kernels


def eta_geom(l_m, w_m):
    """Geometric efficiency of the racetrack coil, 2 l_m w_m / (2 l_m w_m + pi w_m^2).

    l_m, w_m: magnet length and width (any common unit), arrays broadcast.
    The coil's two legs are w_m wide and l_m long, joined by half-annuli of
    mean diameter w_m, so the mean turn is 2 l_m + pi w_m long and only the
    2 l_m under the magnets produces force. Isotropy paper section 6 (below eq 8).
    """
    l_m = np.asarray(l_m, dtype=float)
    w_m = np.asarray(w_m, dtype=float)
    return 2.0 * l_m / (2.0 * l_m + np.pi * w_m)  # w_m cancels: no under/overflow


def _face_term(s, l_m, w_m):
    """atan(l w / (s sqrt(s^2 + l^2 + w^2))): one pole face at distance s/2 on its axis.

    The term depends on length ratios only; all three lengths are divided by the
    power of two nearest their largest (exact in binary floating point, so the
    result is bit-identical in the normal range) so that no square over- or
    underflows for any positive finite sizes. s = 0 gives the limit pi/2.
    """
    s, l_m, w_m = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (s, l_m, w_m)))
    big = np.maximum(np.maximum(np.abs(s), np.abs(l_m)), np.abs(w_m))
    _, e = np.frexp(np.where(big > 0, big, 1.0))
    k = np.ldexp(1.0, -e)
    s, l_m, w_m = s * k, l_m * k, w_m * k
    with np.errstate(divide="ignore"):
        return np.arctan(l_m * w_m / (s * np.sqrt(s * s + l_m * l_m + w_m * w_m)))


def bg_eq9_T(gap_mm, l_m_mm, w_m_mm, t_m_mm, br_T):
    """Gap-centre field with one ideal back-iron image per plate (isotropy paper eq 9).

    gap_mm: d, magnet face to face (> 0); l_m_mm, w_m_mm, t_m_mm: full magnet
    dimensions; br_T: remanence. All broadcast; returns B_g in T.
    B_g = (2 B_r/pi) [atan(wl/(d sqrt(d^2+l^2+w^2))) - atan(wl/((4t+d) sqrt((4t+d)^2+l^2+w^2)))].
    """
    d = np.asarray(gap_mm, dtype=float)
    s_far = d + 4.0 * np.asarray(t_m_mm, dtype=float)
    return (2.0 * br_T / np.pi) * (
        _face_term(d, l_m_mm, w_m_mm) - _face_term(s_far, l_m_mm, w_m_mm)
    )


def bz_centerline_eq9_T(z_mm, gap_mm, l_m_mm, w_m_mm, t_m_mm, br_T):
    """Field along the magnet centre line (x = y = 0 of one pair), eq (9) extended.

    z_mm: positions across the gap, |z| < d/2 (array). Each magnet+image
    (a 2t slab) contributes (B_r/pi)[F(2 z1) - F(2 z1 + 4t)] with z1 its
    near-face distance; the paper's Fig. 8 "predicted gap field". Returns T.
    """
    z = np.asarray(z_mm, dtype=float)
    d = float(gap_mm)
    if not (math.isfinite(d) and d > 0):
        raise DesignError("gap_mm", f"must be a finite number > 0, got {gap_mm!r}")
    if not np.all(np.abs(z) < d / 2):
        raise DesignError(
            "z_mm", f"must lie strictly inside the gap |z| < {d / 2} mm, got {z_mm!r}"
        )
    out = np.zeros_like(z)
    for z1 in (d / 2 - z, d / 2 + z):
        s = 2.0 * z1
        out += (br_T / np.pi) * (
            _face_term(s, l_m_mm, w_m_mm) - _face_term(s + 4 * t_m_mm, l_m_mm, w_m_mm)
        )
    return out


def _check_slabs(n_slabs) -> None:
    if isinstance(n_slabs, bool) or not isinstance(n_slabs, (int, np.integer)) or n_slabs < 1:
        raise DesignError("n_slabs", f"must be an integer >= 1 (slabs per side), got {n_slabs!r}")


def _positive_gap(gap_mm) -> float:
    try:
        d = float(gap_mm)
    except (TypeError, ValueError):
        raise DesignError("gap_mm", f"must be a number, got {gap_mm!r}") from None
    if not (math.isfinite(d) and d > 0):
        raise DesignError("gap_mm", f"must be a finite number > 0, got {gap_mm!r}")
    return d


def _coil_gaps(gap_mm, params: VoiceCoilParams) -> np.ndarray:
    """Gaps (array) checked to leave room for a coil: finite, > 0 and >= d_r (d = d_r: d_c = 0)."""
    try:
        g = np.atleast_1d(np.asarray(gap_mm, dtype=float))
    except (TypeError, ValueError):
        raise DesignError("gap_mm", f"must be numbers, got {gap_mm!r}") from None
    bad = ~np.isfinite(g) | (g <= 0) | (g < params.rattle_mm)
    if bad.any():
        raise DesignError(
            "gap_mm",
            f"must be finite, > 0 and >= the rattle space d_r = {params.rattle_mm:g} mm "
            f"(no room for a coil below), got {g[bad][0]!r}",
        )
    return g


def bg_image_series_T(gap_mm, l_m_mm, w_m_mm, t_m_mm, br_T, n_slabs: int):
    """Gap-centre field between two ideal iron plates, image series truncated at K slabs per side.

    n_slabs: K >= 1 slabs (magnet+image, 2 t thick) per side; K = 1 is exactly
    eq (9). Slab k's near face is at d/2 + k (d + 2t). Scalars in, T out.
    """
    _check_slabs(n_slabs)
    d, t = _positive_gap(gap_mm), float(t_m_mm)
    k = np.arange(n_slabs, dtype=float)
    s = d + 2.0 * k * (d + 2.0 * t)
    terms = _face_term(s, l_m_mm, w_m_mm) - _face_term(s + 4.0 * t, l_m_mm, w_m_mm)
    # sum smallest first for round-off
    return float((2.0 * br_T / np.pi) * np.sum(terms[::-1]))


def image_series_tail_T(gap_mm, l_m_mm, w_m_mm, t_m_mm, br_T, n_slabs: int):
    """Asymptotic remainder of the image series after K slabs per side (T).

    Far slabs are dipoles: F(s) - F(s + 4t) ~ 8 t l w / s^3 with
    s_k = d + 2k(d + 2t); the sum over k >= K is approximated by the
    Euler-Maclaurin integral plus half the first term,
    2B_r/pi * t l w / (2 p^3) * (1/(K + c)^2) ..., i.e. proportional to 1/K^2.
    """
    _check_slabs(n_slabs)
    d, t = _positive_gap(gap_mm), float(t_m_mm)
    p = 2.0 * (d + 2.0 * t)  # spacing of s_k
    # s_k = d + 2t + p k shifted to the slab centre: sum_{k>=K} 8 t l w / (p (k + c))^3
    c = (d + 2.0 * t) / p
    a = 8.0 * (t / p) * (float(l_m_mm) / p) * (float(w_m_mm) / p)  # ratios: no over/underflow
    K = float(n_slabs)
    tail = a * (1.0 / (2.0 * (K + c - 0.5) ** 2))  # midpoint integral of 1/x^3 from K-1/2
    return (2.0 * br_T / np.pi) * tail


def bg_image_converged_T(
    gap_mm, l_m_mm, w_m_mm, t_m_mm, br_T, n_slabs: int = IMAGE_SERIES_CONVERGED_TERMS
):
    """Converged two-plate image-series field: K slabs summed plus the asymptotic tail (T)."""
    return bg_image_series_T(gap_mm, l_m_mm, w_m_mm, t_m_mm, br_T, n_slabs) + image_series_tail_T(
        gap_mm, l_m_mm, w_m_mm, t_m_mm, br_T, n_slabs
    )


def force_eq8_N(bg_T, gap_mm, params: VoiceCoilParams, eta_geom_value=None):
    """Actuator force for a uniform gap field, isotropy paper eq (8).

    F = B_g sqrt(eta_pack eta_geom) sqrt(P/rho) sqrt(2 w_m l_m (d - d_r)).
    bg_T: B_g (T), gap_mm: d (array, > d_r). Lengths converted to m inside.
    Returns N (0 where d <= d_r: no room for a coil).
    """
    eg = params.eta_geom if eta_geom_value is None else eta_geom_value
    dc_m = np.maximum(np.asarray(gap_mm, dtype=float) - params.rattle_mm, 0.0) * 1e-3
    # square roots taken factor by factor: no product over- or underflows
    sqrt_area = (
        math.sqrt(2.0 * params.magnet_width_mm * 1e-3)
        * math.sqrt(params.magnet_length_mm * 1e-3)
        * np.sqrt(dc_m)
    )
    return (
        np.asarray(bg_T, dtype=float)
        * math.sqrt(params.eta_pack * eg)
        * (math.sqrt(params.power_W) / math.sqrt(params.resistivity_ohm_m))
        * sqrt_area
    )


def ampere_turns(gap_mm, params: VoiceCoilParams) -> float:
    """N I of each coil leg at the design power (A): sqrt(P eta_pack eta_geom w_m d_c / (rho 2 l_m)).

    From P = I^2 R, R = rho l_wire / s_eff, N = w_m d_c / s_wire and eq (8):
    F = B_g (N I) 2 l_m, so N I = F / (2 l_m B_g). DesignError for d < d_r.
    """
    _coil_gaps(gap_mm, params)
    f1 = float(force_eq8_N(1.0, gap_mm, params))
    return f1 / (2.0 * params.magnet_length_mm * 1e-3)


# ---------------------------------------------------------------- models


def gap_field_T(gap_mm, params: VoiceCoilParams, model: Model = "closed-form", **kw) -> float:
    """B_g (T) entering eq (8) under a field model.

    closed-form: eq (9) (one ideal image per plate, field at the gap centre).
    images: the converged two-plate image series at the gap centre
        (kw: n_slabs to truncate instead).
    magpylib: magpylib cuboids of the whole actuator (both magnet pairs,
        opposite polarity) with fm.MAGPYLIB_IMAGE_SLABS image slabs per side,
        B_z averaged over the coil leg's volume (w_m x l_m x d_c) at mid-stroke;
        eq (8) is exact for that mean under the paper's assumption (ii).
        kw: n_slabs, neighbour (False: one pair only), average="centre" for the
        field at the gap centre over pair A instead of the coil mean.

    DesignError for a gap that is not a finite number > 0.
    """
    gap_mm = _positive_gap(gap_mm)
    lm, w, t, br = (
        params.magnet_length_mm,
        params.magnet_width_mm,
        params.magnet_thickness_mm,
        params.br_T,
    )
    if model == "closed-form":
        return float(bg_eq9_T(gap_mm, lm, w, t, br))
    if model == "images":
        n = kw.get("n_slabs")
        if n is None:
            return float(bg_image_converged_T(gap_mm, lm, w, t, br))
        return bg_image_series_T(gap_mm, lm, w, t, br, n)
    if model == "magpylib":
        n_slabs = kw.get("n_slabs", fm.MAGPYLIB_IMAGE_SLABS)
        neighbour = kw.get("neighbour", True)
        if kw.get("average", "coil") == "centre":
            return fm.bg_center_T(gap_mm, lm, w, t, br, n_slabs=n_slabs, neighbour=neighbour)
        return float(fm.coil_mean_bz_T(gap_mm, params, n_slabs=n_slabs, neighbour=neighbour))
    raise DesignError("model", f"unknown field model {model!r} (known: {', '.join(MODELS)})")


@dataclass(frozen=True)
class GapOptimum:
    """Result of the gap optimisation (isotropy paper Fig. 8).

    optimal_gap_mm: d maximising eq (8); coil_width_mm: d_c = d - d_r;
    Bg_T: the field used in eq (8) at the optimum; force_N: eq (8) force;
    eta_geom: coil geometric efficiency; model: field model name;
    n_evaluations: field evaluations spent; at_bound: True when the maximum
    lies on the caller's gap_max_mm (a constrained optimum, not the free one).
    """

    optimal_gap_mm: float
    coil_width_mm: float
    Bg_T: float
    force_N: float
    eta_geom: float
    model: str
    n_evaluations: int
    at_bound: bool = False

    def as_dict(self) -> dict:
        return {
            "optimal_gap_mm": self.optimal_gap_mm,
            "coil_width_mm": self.coil_width_mm,
            "Bg_T": self.Bg_T,
            "force_N": self.force_N,
            "eta_geom": self.eta_geom,
            "model": self.model,
            "at_bound": self.at_bound,
        }


def force_vs_gap_N(
    gap_mm, params: VoiceCoilParams, model: Model = "closed-form", **kw
) -> np.ndarray:
    """Eq (8) force for each gap in ``gap_mm`` (array, mm) under ``model``; Fig. 8 left.

    d = d_r gives 0 (no coil width); d < d_r, d <= 0 or a non-finite d is a DesignError.
    """
    g = _coil_gaps(gap_mm, params)
    if model == "closed-form":
        bg = bg_eq9_T(
            g,
            params.magnet_length_mm,
            params.magnet_width_mm,
            params.magnet_thickness_mm,
            params.br_T,
        )
    else:
        bg = np.array([gap_field_T(x, params, model, **kw) for x in g])
    return force_eq8_N(bg, g, params)


def optimal_gap(
    params: VoiceCoilParams,
    model: Model = "closed-form",
    *,
    gap_max_mm: float | None = None,
    xatol_mm: float | None = None,
    **kw,
) -> GapOptimum:
    """Gap d in (d_r, gap_max] maximising the eq (8) force (bounded scalar maximise).

    A log-spaced grid on d - d_r (from 1e-4 of the smaller of w_m and t_m, at
    least 4 points per decade) locates the bracket (the force rises from 0 at d = d_r
    and falls as ~d^-2.5 for large d), then Brent's bounded method refines it
    to ``xatol_mm`` (default 1e-8 (l_m + w_m + t_m + d_r): relative, so tiny and
    huge actuators are solved alike). gap_max_mm defaults to
    d_r + 10 (l_m + w_m + t_m + d_r) (the optimum lies near 1.2 d_r when d_r
    dwarfs the magnets); when the best grid point is that default bound, the
    search is extended tenfold until the maximum is interior. With an explicit
    gap_max_mm a maximum on it is returned with ``at_bound=True``.
    Independent of B_r, rho, P and eta_pack (they scale F by a constant).
    """
    from scipy.optimize import minimize_scalar

    if model not in MODELS:
        raise DesignError("model", f"unknown field model {model!r} (known: {', '.join(MODELS)})")
    dr = params.rattle_mm
    gmax, user_bound, xatol = _gap_search_limits(params, gap_max_mm, xatol_mm)
    shape = _GapShape(params, model, kw)
    xs, vals, i, lo, gmax = _bracket_gap(shape, params, model, gmax, user_bound)
    # Brent in log(d - d_r): scale-free; xatol in mm becomes a relative tolerance there
    ref = xs[-1]
    a = math.log(xs[i - 1] if i > 0 else 0.5 * lo)
    b = math.log(xs[min(i + 1, len(xs) - 1)])
    res = minimize_scalar(
        lambda u: shape(min(math.exp(u), xs[-1]), ref),
        bounds=(a, b),
        method="bounded",
        options={"xatol": xatol / xs[i]},
    )
    x_opt = min(math.exp(float(res.x)), xs[-1]) if res.fun <= vals[i] else float(xs[i])
    d_opt = dr + x_opt
    bg = gap_field_T(d_opt, params, model, **kw)
    with np.errstate(over="ignore", under="ignore"):
        force = float(force_eq8_N(bg, d_opt, params))
    if not (math.isfinite(d_opt) and math.isfinite(force) and d_opt > dr):
        raise DesignError(
            "force_N",
            f"the eq (8) force at the optimum d = {d_opt!r} mm is {force!r} N: the sizes, "
            "power, B_r or resistivity put it outside float64",
        )
    return GapOptimum(
        optimal_gap_mm=d_opt,
        coil_width_mm=d_opt - dr,
        Bg_T=float(bg),
        force_N=force,
        eta_geom=params.eta_geom,
        model=model,
        n_evaluations=shape.n,
        at_bound=bool(user_bound and gmax - d_opt <= 10.0 * xatol),
    )


def _gap_search_limits(
    params: VoiceCoilParams, gap_max_mm: float | None, xatol_mm: float | None
) -> tuple[float, bool, float]:
    """(gap_max_mm, given by the caller, xatol_mm) of :func:`optimal_gap`, validated.

    Raises :class:`DesignError` on a gap bound not above d_r, a rattle space too
    large for float64, or a non-positive xatol.
    """
    dr = params.rattle_mm
    size = params.magnet_length_mm + params.magnet_width_mm + params.magnet_thickness_mm
    user_bound = gap_max_mm is not None
    if user_bound:
        try:
            gmax = float(gap_max_mm)
        except (TypeError, ValueError):
            raise DesignError("gap_max_mm", f"must be a number, got {gap_max_mm!r}") from None
        if not (math.isfinite(gmax) and gmax > dr):
            raise DesignError(
                "gap_max_mm",
                f"must be finite and exceed the rattle space {dr} mm, got {gap_max_mm!r}",
            )
    else:
        gmax = min(dr + 10.0 * (size + dr), _FLOAT_MAX / 16)  # sizes near float max: capped
        if not gmax - dr > _FLOAT_TINY:
            raise DesignError("rattle_mm", f"too large to search beyond in float64, got {dr!r}")
    xatol = GAP_XATOL_REL * (size + dr) if xatol_mm is None else float(xatol_mm)
    if not (math.isfinite(xatol) and xatol > 0):
        raise DesignError("xatol_mm", f"must be finite and > 0, got {xatol_mm!r}")
    return gmax, user_bound, xatol


class _GapShape:
    """-(B_g / B_r) sqrt(x / ref) at d = d_r + x: eq (8) up to constant factors.

    Dimensionless and O(1) for any actuator size, so neither the grid nor
    Brent over- or underflows where the force in newtons would. ``n`` counts
    the field evaluations.
    """

    def __init__(self, params: VoiceCoilParams, model: Model, kw: dict) -> None:
        self.params, self.model, self.kw, self.n = params, model, kw, 0

    def __call__(self, x: float, ref: float) -> float:
        self.n += 1
        bg = gap_field_T(self.params.rattle_mm + x, self.params, self.model, **self.kw)
        return -(bg / self.params.br_T) * math.sqrt(x / ref)


def _bracket_gap(shape: _GapShape, params: VoiceCoilParams, model: Model, gmax: float,
                 user_bound: bool) -> tuple[np.ndarray, np.ndarray, int, float, float]:
    """Log-spaced grid on x = d - d_r locating the maximum of eq (8) (:func:`optimal_gap`).

    Returns (xs (n,) mm, shape values (n,), index of the best, grid start lo (mm),
    gap_max_mm after any tenfold extension). Raises :class:`DesignError` when the
    force still rises at the last default bound.
    """
    dr = params.rattle_mm
    per_decade, n_min = (2, 17) if model == "magpylib" else (4, 33)
    for _ in range(GAP_BRACKET_EXTENSIONS):
        span = gmax - dr
        # from 1e-4 of the smallest size (at most ~616 decades: 2.5k points for absurd inputs)
        lo = max(1e-4 * min(params.magnet_width_mm, params.magnet_thickness_mm, span), _FLOAT_TINY)
        n = max(n_min, math.ceil(per_decade * (math.log10(span) - math.log10(lo))) + 1)
        xs = np.geomspace(lo, gmax - dr, n)
        vals = np.array([shape(x, xs[-1]) for x in xs])
        i = int(np.argmin(vals))
        if i < n - 1 or user_bound:
            break
        gmax = dr + 10.0 * (gmax - dr)  # still rising at the default bound: look further
        if not gmax < _FLOAT_MAX / 16:
            break
    if i == n - 1 and not user_bound:
        raise DesignError(
            "gap_max_mm",
            f"the eq (8) force still rises at d = {gmax:g} mm: no interior optimum found",
        )
    return xs, vals, i, lo, gmax


# ---------------------------------------------------------------- NLP over (d, t_m, w_m, l_m)


@dataclass(frozen=True)
class ActuatorBounds:
    """Box bounds and constraints of the actuator NLP (isotropy paper section 6).

    gap_mm, magnet_thickness_mm, magnet_width_mm, magnet_length_mm: (min, max) in mm.
    d_max_mm: overall height bound, 2 t_s + 2 t_m + d <= d_max.
    alpha: back-iron saturation bound t_s >= alpha w_m (t_s is set to alpha w_m:
        force does not depend on t_s, so a thicker plate only costs height).
    footprint_max_mm: optional bound on the coil footprint l_m + 2 w_m (flotor size).
    """

    gap_mm: tuple[float, float]
    magnet_thickness_mm: tuple[float, float]
    magnet_width_mm: tuple[float, float]
    magnet_length_mm: tuple[float, float]
    d_max_mm: float
    alpha: float = 0.5
    footprint_max_mm: float | None = None

    def __post_init__(self) -> None:
        for name in ("gap_mm", "magnet_thickness_mm", "magnet_width_mm", "magnet_length_mm"):
            lo, hi = getattr(self, name)
            if not (0 < lo <= hi and math.isfinite(hi)):
                raise DesignError(name, f"bounds must satisfy 0 < min <= max, got {(lo, hi)!r}")
        if not self.d_max_mm > 0:
            raise DesignError("d_max_mm", f"must be > 0, got {self.d_max_mm!r}")
        if not self.alpha >= 0:
            raise DesignError("alpha", f"must be >= 0, got {self.alpha!r}")


@dataclass(frozen=True)
class ActuatorOptimum:
    """NLP optimum: gap and magnet dimensions (mm), plate thickness t_s, force (N).

    active: names of constraints active at the optimum (within 1e-6 mm).
    """

    gap_mm: float
    magnet_thickness_mm: float
    magnet_width_mm: float
    magnet_length_mm: float
    plate_thickness_mm: float
    force_N: float
    Bg_T: float
    active: tuple[str, ...] = field(default_factory=tuple)


def optimize_actuator(
    params: VoiceCoilParams,
    bounds: ActuatorBounds,
    *,
    model: Model = "closed-form",
    starts: int = 6,
    seed: int = 0,
) -> ActuatorOptimum:
    """Maximise eq (8) with eq (9) over x = (d, t_m, w_m, l_m) by SLSQP (multi-start).

    Constraints: 2 alpha w_m + 2 t_m + d <= d_max (t_s at its lower bound
    alpha w_m), d - d_r >= 1e-3 mm, optionally l_m + 2 w_m <= footprint_max.
    params supplies d_r, P, B_r, rho, eta_pack (its magnet sizes are ignored).
    Starts: the box centre plus seeded uniform draws, each projected into the
    feasible set by scaling towards the lower corner. Isotropy paper section 6.
    """
    if model != "closed-form" and model != "images":
        raise DesignError("model", f"the NLP supports closed-form or images, got {model!r}")
    nlp = _ActuatorNLP(params, bounds, model)
    best = None
    for x0 in _nlp_starts(nlp, starts, seed):
        x = nlp.solve(x0)
        if x is None:
            continue
        f = nlp.force(x)
        if best is None or f > best[0]:
            best = (f, x)
    if best is None:
        raise DesignError(
            "d_max_mm",
            f"actuator NLP: no feasible design within the bounds (2 alpha w_m + 2 t_m + d <= "
            f"{bounds.d_max_mm:g} mm with the lower bounds and d > d_r = {nlp.dr:g} mm)",
        )
    f, x = best
    return ActuatorOptimum(
        gap_mm=float(x[0]),
        magnet_thickness_mm=float(x[1]),
        magnet_width_mm=float(x[2]),
        magnet_length_mm=float(x[3]),
        plate_thickness_mm=float(bounds.alpha * x[2]),
        force_N=f,
        Bg_T=nlp.field(x),
        active=nlp.active(x),
    )


class _ActuatorNLP:
    """The NLP of :func:`optimize_actuator` on x = (d, t_m, w_m, l_m) (mm).

    lo, hi: (4,) box (d's lower bound raised to d_r + NLP_COIL_WIDTH_MIN_MM);
    the optimiser works on u = x / hi. Raises :class:`DesignError` ("gap_mm")
    when the gap's upper bound does not exceed the rattle space.
    """

    def __init__(self, params: VoiceCoilParams, bounds: ActuatorBounds, model: Model) -> None:
        self.params, self.bounds, self.model = params, bounds, model
        self.dr = params.rattle_mm
        self.lo = np.array([bounds.gap_mm[0], bounds.magnet_thickness_mm[0],
                            bounds.magnet_width_mm[0], bounds.magnet_length_mm[0]])
        self.hi = np.array([bounds.gap_mm[1], bounds.magnet_thickness_mm[1],
                            bounds.magnet_width_mm[1], bounds.magnet_length_mm[1]])
        self.lo[0] = max(self.lo[0], params.rattle_mm + NLP_COIL_WIDTH_MIN_MM)
        if self.lo[0] > self.hi[0]:
            raise DesignError(
                "gap_mm",
                f"upper bound {self.hi[0]} mm must exceed the rattle space {params.rattle_mm} mm",
            )
        self.scale = self.hi.copy()

    def field(self, x) -> float:
        """Gap field B_g (T) at x."""
        d, t, w, lm = x
        if self.model == "closed-form":
            return float(bg_eq9_T(d, lm, w, t, self.params.br_T))
        return float(bg_image_converged_T(d, lm, w, t, self.params.br_T, 512))

    def force(self, x) -> float:
        """Eq (8) force (N) at x."""
        d, t, w, lm = x
        p = self.params
        q = VoiceCoilParams(lm, w, t, self.dr, p.power_W, p.br_T, p.resistivity_ohm_m, p.eta_pack)
        return float(force_eq8_N(self.field(x), d, q))

    def height(self, x) -> float:
        """Slack (mm) of 2 alpha w_m + 2 t_m + d <= d_max."""
        return self.bounds.d_max_mm - (2 * self.bounds.alpha * x[2] + 2 * x[1] + x[0])

    def feasible(self, x) -> bool:
        """x meets the height, coil-width and footprint constraints (to NLP_FEASIBLE_SLACK_MM)."""
        ok = self.height(x) >= -NLP_FEASIBLE_SLACK_MM and x[0] > self.dr
        if self.bounds.footprint_max_mm is not None:
            ok = ok and x[3] + 2 * x[2] <= self.bounds.footprint_max_mm + NLP_FEASIBLE_SLACK_MM
        return bool(ok)

    def constraints(self) -> list[dict]:
        """SLSQP inequality constraints on u = x / scale, each normalized to O(1)."""
        b, scale, dr = self.bounds, self.scale, self.dr
        cons = [
            {"type": "ineq", "fun": lambda u: self.height(u * scale) / b.d_max_mm},
            {"type": "ineq", "fun": lambda u: (u[0] * scale[0] - dr - NLP_COIL_WIDTH_MIN_MM) / scale[0]},
        ]
        if b.footprint_max_mm is not None:
            fp = b.footprint_max_mm
            cons.append(
                {"type": "ineq", "fun": lambda u: (fp - (u[3] * scale[3] + 2 * u[2] * scale[2])) / fp}
            )
        return cons

    def solve(self, x0: np.ndarray) -> np.ndarray | None:
        """SLSQP from x0 (4,) mm; the optimum clipped to the box, or None when infeasible."""
        from scipy.optimize import minimize

        lo, hi, scale = self.lo, self.hi, self.scale
        res = minimize(
            lambda u: -self.force(u * scale) / 10.0,
            x0 / scale,
            method="SLSQP",
            bounds=list(zip(lo / scale, hi / scale, strict=True)),
            constraints=self.constraints(),
            options={"ftol": NLP_SLSQP_FTOL, "maxiter": 300},
        )
        x = np.clip(res.x * scale, lo, hi)
        return x if self.feasible(x) else None

    def active(self, x) -> tuple[str, ...]:
        """Names of the constraints active at x (within NLP_ACTIVE_MM)."""
        b, lo, hi = self.bounds, self.lo, self.hi
        active = []
        if abs(self.height(x)) < NLP_ACTIVE_MM:
            active.append("height")
        if b.footprint_max_mm is not None and abs(b.footprint_max_mm - x[3] - 2 * x[2]) < NLP_ACTIVE_MM:
            active.append("footprint")
        names = ("gap_mm", "magnet_thickness_mm", "magnet_width_mm", "magnet_length_mm")
        for i, n in enumerate(names):
            if abs(x[i] - lo[i]) < NLP_ACTIVE_MM:
                active.append(f"{n}>=min")
            if abs(x[i] - hi[i]) < NLP_ACTIVE_MM:
                active.append(f"{n}<=max")
        return tuple(active)


def _nlp_starts(nlp: _ActuatorNLP, starts: int, seed: int) -> list[np.ndarray]:
    """Feasible start points (mm): the box centre plus seeded uniform draws, each pulled
    towards the lower corner until feasible (dropped when it never is)."""
    lo, hi = nlp.lo, nlp.hi
    rng = np.random.default_rng(seed)
    starts_x = [0.5 * (lo + hi)] + [
        lo + rng.random(4) * (hi - lo) for _ in range(max(starts - 1, 0))
    ]
    out = []
    for x0 in starts_x:
        x0 = np.array(x0)
        for _ in range(60):  # pull towards the lower corner until feasible
            if nlp.feasible(x0):
                break
            x0 = lo + 0.8 * (x0 - lo)
        if nlp.feasible(x0):
            out.append(x0)
    return out


# ---------------------------------------------------------------- force along the stroke


@dataclass(frozen=True)
class StrokeForce:
    """Force along the stroke: real coil cross-section vs eq (8)'s uniform field.

    x_mm: coil displacement along the actuation axis (N,); force_N: Lorentz
    force with B_z integrated over both legs' volumes (N,); force_eq8_N: eq (8)
    with B_g at the gap centre (scalar, independent of x); Bg_T: that B_g;
    ampere_turns: N I per leg at the design power.
    """

    x_mm: np.ndarray
    force_N: np.ndarray
    force_eq8_N: float
    Bg_T: float
    ampere_turns: float


def gauss_box(lo_mm, hi_mm, n):
    """Gauss-Legendre nodes (M,3) and weights (M,) on the box [lo, hi] (n = points per axis, 3 ints)."""
    axes, wts = [], []
    for a, b, k in zip(lo_mm, hi_mm, n, strict=True):
        x, w = np.polynomial.legendre.leggauss(int(k))
        axes.append(0.5 * (b - a) * x + 0.5 * (a + b))
        wts.append(0.5 * (b - a) * w)
    X, Y, Z = np.meshgrid(*axes, indexing="ij")
    W = wts[0][:, None, None] * wts[1][None, :, None] * wts[2][None, None, :]
    return np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1), W.ravel()


def leg_boxes_mm(gap_mm, params: VoiceCoilParams, x_mm: float = 0.0, z_mm: float = 0.0):
    """The two straight coil legs as boxes ((lo, hi) for leg A, (lo, hi) for leg B), mm, actuator frame.

    Leg A spans x in [0, w_m], leg B [-w_m, 0] at mid-stroke, y in +-l_m/2,
    z in +-d_c/2; shifted by the coil displacement (x_mm, 0, z_mm).
    """
    w, lm = params.magnet_width_mm, params.magnet_length_mm
    dc = float(gap_mm) - params.rattle_mm
    if not dc > 0:  # also NaN
        raise DesignError(
            "gap_mm", f"must exceed the rattle space {params.rattle_mm} mm, got {gap_mm!r}"
        )
    a = (np.array([x_mm, -lm / 2, z_mm - dc / 2]), np.array([x_mm + w, lm / 2, z_mm + dc / 2]))
    b = (np.array([x_mm - w, -lm / 2, z_mm - dc / 2]), np.array([x_mm, lm / 2, z_mm + dc / 2]))
    return a, b


def stroke_force(
    gap_mm,
    params: VoiceCoilParams,
    x_mm,
    *,
    bz_fn: Callable[[np.ndarray], np.ndarray] | None = None,
    n_quad: tuple[int, int, int] = (8, 6, 6),
) -> StrokeForce:
    """Lorentz force on the coil legs along the stroke, field integrated over the coil volume.

    gap_mm: d; x_mm: displacements (N,) along the actuation axis.
    bz_fn: B_z (T) at points (M,3) in mm, actuator frame; default: magpylib
        model of the whole actuator (field_magpylib.actuator_bz_fn).
    n_quad: Gauss-Legendre points per axis (x, y, z) in each leg.
    F_x = (N I / (w_m d_c)) [ integral_A B_z dV - integral_B B_z dV ], the
    current density being uniform in each leg; end turns are ignored as in
    the paper's assumption (ii). With B_z = B_g everywhere this reduces to
    eq (8): F = B_g (N I) 2 l_m.
    """
    if bz_fn is None:
        bz_fn = fm.actuator_bz_fn(gap_mm, params)
    xs = np.atleast_1d(np.asarray(x_mm, dtype=float))
    dc = float(gap_mm) - params.rattle_mm
    ni = ampere_turns(gap_mm, params)
    jden = ni / (params.magnet_width_mm * dc)  # A per mm^2
    pts, wts, sign, owner = [], [], [], []
    for i, x in enumerate(xs):
        for sgn, (lo, hi) in zip((1.0, -1.0), leg_boxes_mm(gap_mm, params, x), strict=True):
            p, w = gauss_box(lo, hi, n_quad)
            pts.append(p)
            wts.append(w)
            sign.append(np.full(len(w), sgn))
            owner.append(np.full(len(w), i))
    P = np.concatenate(pts)
    bz = np.asarray(bz_fn(P), dtype=float)
    contrib = np.concatenate(wts) * np.concatenate(sign) * bz  # T mm^3
    integral = np.bincount(np.concatenate(owner), weights=contrib, minlength=len(xs))
    force = jden * integral * 1e-3  # A/mm^2 * T mm^3 = T A mm -> N * 1e-3
    bg = float(
        bg_eq9_T(
            gap_mm,
            params.magnet_length_mm,
            params.magnet_width_mm,
            params.magnet_thickness_mm,
            params.br_T,
        )
    )
    return StrokeForce(
        x_mm=xs,
        force_N=force,
        force_eq8_N=float(force_eq8_N(bg, gap_mm, params)),
        Bg_T=bg,
        ampere_turns=ni,
    )
