"""Least-squares identification of a 1-DOF device (a four-bar's crank) from a log.

Model (crank angle q rad, motor torque Nm; Hoeken paper eq (14) written for one coordinate)::

    s Kt i(t - n Te) = c0 q'' + c1 (D(q) q'' + 1/2 D'(q) q'^2) + Tc sign(q') + b q'
                       + cg g(q) + T0

with D(q) the predicted crank inertia (kg m^2, rotor included) and g(q) the predicted gravity
torque (N m; absent for a horizontal device). Unknowns: ``c0`` (kg m^2, inertia not in the
prediction's shape) and ``c1`` (scale of the predicted inertia), Coulomb ``Tc`` (N m) and
viscous ``b`` (N m s/rad) friction, gravity scale ``cg``, a constant torque offset ``T0``
(N m), the delay ``n`` (periods; one more linear unknown through
``tau(t - n Te) ~ tau(t) - n Te tau'(t)``) and
the sign ``s`` of the current gain (the fit's inertia comes out negative when the motor
pushes the other way than the encoder counts). Predicted: c0 = 0, c1 = 1, cg = 1, T0 = 0.

Derivatives: the angle and the current are low-passed by the same zero-phase 4th-order
Butterworth filter (:data:`FILTER_HZ`), then q', q'' by central differences. Rows slower
than :data:`cad.tolerances.IDENT_SLOW_FRACTION` of the peak rate are left out (Coulomb's
sign undefined). Covariance: sigma^2 (X^T X)^-1 with sigma^2 = RSS / (N - p), inflated by the
rows per independent sample of the filtered signal, 1 / (2 FILTER_HZ Te). The delay found
includes the zero-order hold (the command of period k acts until k + 1: half a period more
than the transport delay). Fitted, not assumed: a delay off by half a period leaves
``kp Te / 2`` of the position hold as a false viscous term.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from cad.tolerances import IDENT_CONDITION_MAX, IDENT_SLOW_FRACTION

#: Low-pass of the angle and current before differentiation (Hz): above the chirp's 15 Hz
#: end, below the encoder quantization noise that dominates the second derivative.
FILTER_HZ = 40.0
#: Rows left out at each end of the log (the filter's edge transients).
EDGE_ROWS = 8
NAMES = ("c0_kg_m2", "c1", "Tc_Nm", "b_Nm_s_per_rad", "cg", "T0_Nm")


class NotExcited(ValueError):
    """The log does not excite the model enough to fit it (the message says how)."""


class Estimates:
    """What every identification result gives from its estimates' names and covariance
    (``names``, ``cov``): the 1-motor :class:`Fit` and the 2-motor
    :class:`cad.identify.joint2.Fit2` share it."""

    def sigma(self, name: str) -> float:
        """One standard deviation of the estimate ``name``."""
        i = self.names.index(name)
        return float(math.sqrt(max(self.cov[i, i], 0.0)))


@dataclass(frozen=True)
class Fit(Estimates):
    """Estimates ``theta`` {name: value}, their covariance ``cov`` (names order of
    ``names``), the rows used (``mask``), the delay, the current-gain sign, the signals the fit
    saw (``q``, ``v``, ``a`` rad, rad/s, rad/s^2, ``tau_meas`` and ``tau_fit`` N m)."""

    theta: dict[str, float]
    cov: np.ndarray
    names: tuple[str, ...]
    delay_samples: float
    current_sign: int
    rms_residual_Nm: float
    mask: np.ndarray
    t_s: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    tau_meas: np.ndarray
    tau_fit: np.ndarray
    extra: dict = field(default_factory=dict)


def lowpass(x: np.ndarray, Te_s: float, fc_Hz: float = FILTER_HZ) -> np.ndarray:
    """Zero-phase 4th-order Butterworth low-pass of ``x`` sampled every ``Te_s``."""
    from scipy.signal import butter, sosfiltfilt

    wn = min(0.99, 2.0 * fc_Hz * Te_s)
    return sosfiltfilt(butter(4, wn, output="sos"), x)


def derivatives(q: np.ndarray, Te_s: float, fc_Hz: float = FILTER_HZ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(filtered q, q', q'') of a sampled angle (rad, rad/s, rad/s^2); ``fc_Hz`` the filter's
    cut-off."""
    qf = lowpass(q, Te_s, fc_Hz)
    v = np.gradient(qf, Te_s)
    return qf, v, np.gradient(v, Te_s)


def regressors(q, v, a, D, dD, g, Te_s: float) -> tuple[np.ndarray, tuple[str, ...]]:
    """(X (N, p), names) of the model (module docstring) over contiguous rows sampled every
    ``Te_s``; ``D``, ``dD``, ``g`` are callables of q (``g`` None: horizontal device, no
    gravity column). The Coulomb column is low-passed like the torque it explains (the
    filter's rounding of sign(q') at a reversal)."""
    cols = [a, D(q) * a + 0.5 * dD(q) * v * v, lowpass(np.sign(v), Te_s), v]
    names = list(NAMES[:4])
    if g is not None:
        cols.append(g(q))
        names.append("cg")
    cols.append(np.ones_like(q))
    names.append("T0_Nm")
    return np.column_stack(cols), tuple(names)


def _solve(X, y):
    scale = np.linalg.norm(X, axis=0)
    scale[scale == 0] = 1.0
    Xn = X / scale
    sv = np.linalg.svd(Xn, compute_uv=False)
    cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else math.inf
    th, *_ = np.linalg.lstsq(Xn, y, rcond=None)
    return th / scale, Xn, scale, cond


def fit(t_s, q_rad, current_A, kt_Nm_per_A: float, D, dD, g=None) -> Fit:
    """Fit the model to a log segment: times (s, uniform), crank angles (rad), commanded
    currents (A). Raises :class:`NotExcited` when the rows that move are too few or the
    regressors too ill-conditioned (:data:`cad.tolerances.IDENT_CONDITION_MAX`)."""
    t_s = np.asarray(t_s, float)
    Te = float(np.median(np.diff(t_s)))
    qf, v, a = derivatives(np.asarray(q_rad, float), Te)
    tau_all = kt_Nm_per_A * lowpass(np.asarray(current_A, float), Te)
    slow = np.abs(v) <= IDENT_SLOW_FRACTION * np.max(np.abs(v))
    # a reversal smears over the filter's impulse response: drop its neighbours too
    k = max(1, round(0.5 / (FILTER_HZ * Te)))
    mask = ~(np.convolve(slow.astype(float), np.ones(2 * k + 1), "same") > 0)
    mask[:EDGE_ROWS] = False
    mask[-EDGE_ROWS:] = False
    if mask.sum() < 50:
        raise NotExcited(f"only {int(mask.sum())} samples move faster than "
                         f"{100 * IDENT_SLOW_FRACTION:g} % of the peak rate")
    X, names = regressors(qf, v, a, D, dD, g, Te)
    X = X[mask]
    # the delay: tau(t - n Te) ~ tau(t) - n Te tau'(t), one more linear unknown (n Te)
    dtau = np.gradient(tau_all, Te)
    X = np.column_stack([X, dtau[mask]])
    y = tau_all[mask]
    th, Xn, scale, cond = _solve(X, y)
    n = float(th[-1] / Te)
    rss = float(np.sum((y - X @ th) ** 2))
    if cond > IDENT_CONDITION_MAX:
        raise NotExcited(f"the regressors are ill-conditioned (condition {cond:.3g} > "
                         f"{IDENT_CONDITION_MAX:.3g}): the motion does not separate inertia, friction and offset")
    dof = max(1, len(y) - len(th))
    inflate = max(1.0, 1.0 / (2.0 * FILTER_HZ * Te))
    cov = rss / dof * inflate * np.linalg.inv(Xn.T @ Xn) / np.outer(scale, scale)
    sign = 1 if th[names.index("c1")] >= 0 else -1
    p = len(names)
    tau_fit = np.full_like(tau_all, np.nan)
    tau_fit[mask] = sign * (X[:, :p] @ th[:p])
    tau_meas = sign * (tau_all - th[-1] * dtau)  # the torque acting, delay removed
    th = sign * th[:p]  # a reversed gain negates every estimate; the covariance stays
    return Fit(dict(zip(names, map(float, th), strict=True)), cov[:p, :p], names, n, sign,
               math.sqrt(rss / len(y)), mask, t_s, qf, v, a, tau_meas, tau_fit,
               {"condition": cond, "rows_used": int(mask.sum())})


def hand_direction(q_rad: np.ndarray, min_rad: float) -> int:
    """+1 when the hand phase's largest excursion from its first angle is positive (the
    operator moved towards the + end, as the routine asks), -1 when negative, 0 when it is
    smaller than ``min_rad`` (the handle was not moved: direction not determined)."""
    d = np.asarray(q_rad, float) - float(q_rad[0])
    if d.size == 0:
        return 0
    k = int(np.argmax(np.abs(d)))
    return 0 if abs(d[k]) < min_rad else (1 if d[k] > 0 else -1)
