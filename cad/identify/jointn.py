"""Least-squares identification of a device of n motors from a log, its links' dynamics
given as a function (issue 37): the delta and any family whose rigid-body model is a
joint-space mass matrix of the solids (pure numpy, no CAD import).

Model per motor j (joint angles q, rates q', accelerations q'', all filtered; Lagrange)::

    s_j Kt i_j(t - n Te) = c_link tau_link_j(q, q', q'') + J_j q_j'' + Tc_j sign(q_j')
                          + b_j q_j' [+ cg g_j(q)] + T0_j

with ``tau_link`` the inverse dynamics of the solids' links (no rotor, no gravity; the
device's :class:`JointModel`), linear in the scale ``c_link`` of every link's mass and
inertia (predicted 1), ``J_j`` the inertia turning with motor j (predicted its rotor times
the ratio squared), Coulomb ``Tc_j`` and viscous ``b_j`` friction, the gravity scale ``cg``
of the solids' gravity torques ``g`` (a device with gravity), constant torques ``T0_j``,
one delay and the current-gain sign of each motor (Khalil & Dombre, *Modeling,
Identification and Control of Robots*, 2002, ch. 12: the model linear in the parameters).

:func:`lagrange_torques` gives ``tau_link`` of any mass matrix M(q):
tau = M q'' + sum_k (dM/dq_k q'_k) q' - 1/2 [q'^T dM/dq_k q']_k (the Euler-Lagrange equation
of T = 1/2 q'^T M q', dM/dq_k by central differences).

The signal path (filter, derivatives, slow rows left out, delay column, covariance) is the
5-bar fit's (:mod:`cad.identify.joint2`), per joint, with the filter at
:data:`FIT_FILTER_HZ`.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from cad.identify.excitation import F1_HZ
from cad.identify.joint2 import Fit2, moving_rows, scaled_lstsq
from cad.identify.regression import NotExcited, derivatives, lowpass
from cad.tolerances import IDENT_CONDITION_MAX, IDENT_SLOW_FRACTION

#: Central-difference step of dM/dq (rad).
DQ_RAD = 1e-5
#: The fit's low-pass cut-off (Hz): 5/3 of the chirp's top frequency (F1_HZ = 15 Hz). Measured
#: on the delta's bench logs (2000-count encoders, links +15 %): at the 1- and 2-motor fits'
#: 40 Hz the encoder's quantization noise in the accelerations (errors in the regressors)
#: biased the apparent mass low by 4-5 %, at 25 Hz by 0.3 % (a 400 000-count encoder: +0.2 %).
FIT_FILTER_HZ = 25.0


@dataclass(frozen=True)
class JointModel:
    """A device's links for the fit: ``n`` motors; ``link_torques(q, v, a)`` -> (N, n) N m,
    the solids' links' inverse dynamics (no rotor, no gravity) at joint angles, rates and
    accelerations (N, n) rad, rad/s, rad/s^2; ``gravity(q)`` -> (N, n) N m, the torques
    holding the solids against gravity (None: no gravity load).

    An over-actuated device (more motors than degrees of freedom: the twin pantograph, the
    pen) gives ``basis(q)`` -> W (N, n, k): joint rates per unit rate of k independent
    coordinates (q' = W X'). Its motors can push against each other without moving it (the
    loop's internal force), so only W^T tau is seen: the fit's equations are the k rows of
    W^T tau (Khalil & Dombre §7.10: the closed chain's dynamics in independent coordinates),
    ``link_torques`` and ``gravity`` may give any joint torques with the right W^T tau (the
    least-norm ones), and the constant offsets are identified as k generalized offsets spread
    over the motors by least norm at the log's middle pose (a torque pattern W^T cancels is
    not observable)."""

    n: int
    link_torques: Callable
    gravity: Callable | None = None
    basis: Callable | None = None


def lagrange_torques(mass_matrix: Callable, q, v, a, dq: float = DQ_RAD) -> np.ndarray:
    """Inverse dynamics (N, n) N m of T = 1/2 q'^T M(q) q' (module docstring) at (N, n)
    angles, rates and accelerations; ``mass_matrix(q)`` -> (N, n, n) kg m^2."""
    q, v, a = (np.atleast_2d(np.asarray(x, float)) for x in (q, v, a))
    n = q.shape[1]
    tau = np.einsum("nij,nj->ni", mass_matrix(q), a)
    for k in range(n):
        e = np.zeros(n)
        e[k] = dq
        dM = (mass_matrix(q + e) - mass_matrix(q - e)) / (2.0 * dq)
        tau += v[:, k:k + 1] * np.einsum("nij,nj->ni", dM, v)
        tau[:, k] -= 0.5 * np.einsum("ni,nij,nj->n", v, dM, v)
    return tau


def filtered(q_rad, Te_s: float, fc_Hz: float = FIT_FILTER_HZ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(q, q', q'') (N, n) of the log's angles, each joint through the fit's filter."""
    q = np.asarray(q_rad, float)
    out = [np.empty_like(q) for _ in range(3)]
    for j in range(q.shape[1]):
        out[0][:, j], out[1][:, j], out[2][:, j] = derivatives(q[:, j], Te_s, fc_Hz)
    return out[0], out[1], out[2]


def design_matrix(model: JointModel, q, v, a, Te: float, offsets=None,
                  fc_Hz: float = FIT_FILTER_HZ) -> tuple[np.ndarray, tuple[str, ...]]:
    """X (N, n, p) and the parameter names of the model (module docstring); ``offsets``
    (n, k): the joint torques of k generalized offsets ``F0{i}`` in place of the n per-motor
    ``T0{j}_Nm`` (an over-actuated device, :class:`JointModel`)."""
    n, rows = model.n, len(q)
    cols, names = [model.link_torques(q, v, a)], ["c_link"]

    def on(j, x):
        c = np.zeros((rows, n))
        c[:, j] = x
        return c

    for j in range(n):
        cols.append(on(j, a[:, j]))
        names.append(f"J{j}_kg_m2")
    for j in range(n):
        cols += [on(j, lowpass(np.sign(v[:, j]), Te, fc_Hz)), on(j, v[:, j])]
        names += [f"Tc{j}_Nm", f"b{j}_Nm_s_per_rad"]
    if model.gravity is not None:
        cols.append(np.asarray(model.gravity(q), float))
        names.append("cg")
    if offsets is None:
        for j in range(n):
            cols.append(on(j, np.ones(rows)))
            names.append(f"T0{j}_Nm")
    else:
        for i in range(offsets.shape[1]):
            cols.append(np.broadcast_to(offsets[:, i], (rows, n)).copy())
            names.append(f"F0{i}")
    return np.stack(cols, axis=-1), tuple(names)


def _best_signs(X3, mask, tau_raw, Te, P=None):
    """The least-squares solution of the sign pattern (motor 0 +, others +/-) that fits best;
    ``P`` (N, k, n): the equations' projection W^T (None: one equation per motor)."""
    n = tau_raw.shape[1]
    best = None
    for signs in itertools.product((1, -1), repeat=n - 1):
        tau = tau_raw * np.array((1, *signs))
        if P is not None:
            tau = np.einsum("nkj,nj->nk", P, tau)
        eqs = range(tau.shape[1])
        dtau = np.gradient(tau, Te, axis=0)
        X = np.concatenate([X3[mask[:, j], j, :] for j in eqs])
        X = np.column_stack([X, np.concatenate([dtau[mask[:, j], j] for j in eqs])])
        y = np.concatenate([tau[mask[:, j], j] for j in eqs])
        th, Xn, scale, cond = scaled_lstsq(X, y)
        rss = float(np.sum((y - X @ th) ** 2))
        if best is None or rss < best["rss"]:
            best = {"rss": rss, "signs": signs, "th": th, "Xn": Xn, "scale": scale, "cond": cond, "y": y,
                    "tau": tau, "dtau": dtau}
    return best


def _offsets(model: JointModel, q, mask) -> tuple[np.ndarray | None, np.ndarray | None, np.ndarray | None]:
    """(P (N, k, n) = W^T, C (n, k) the least-norm joint torques of unit generalized offsets
    at the logged pose nearest the moving rows' median, that pose (n,) rad) of an
    over-actuated model; (None, None, None) otherwise."""
    if model.basis is None:
        return None, None, None
    W = np.asarray(model.basis(q), float)
    moving = q[mask.any(axis=1)]
    mid = moving[np.argmin(np.sum((moving - np.median(moving, axis=0)) ** 2, axis=1))]  # a pose of the log
    Wm = np.asarray(model.basis(mid[None]), float)[0]
    return np.swapaxes(W, 1, 2), Wm @ np.linalg.inv(Wm.T @ Wm), mid


def _per_motor(names, th, cov, C):
    """(names, theta, cov) with the generalized offsets ``F0{i}`` turned into per-motor
    ``T0{j}_Nm`` = C F0 (covariance C cov C^T)."""
    if C is None:
        return names, th, cov
    k = [i for i, m in enumerate(names) if m.startswith("F0")]
    keep = [i for i in range(len(names)) if i not in k]
    L = np.zeros((len(keep) + C.shape[0], len(names)))
    L[np.arange(len(keep)), keep] = 1.0
    L[len(keep):, k] = C
    out = tuple(names[i] for i in keep) + tuple(f"T0{j}_Nm" for j in range(C.shape[0]))
    return out, L @ th, L @ cov @ L.T


def fit(t_s, q_rad, current_A, kt_Nm_per_A, model: JointModel, top_Hz: float | None = None) -> Fit2:
    """Fit the model to a log segment: times (s, uniform), joint angles (N, n) rad, commanded
    currents (N, n) A. The current-gain signs: the pattern of the 2^(n-1) with motor 0's as
    configured that fits best, all negated when the link scale comes out negative. Raises
    :class:`NotExcited` when a joint has fewer than 50 moving rows or the regressors are
    ill-conditioned (condition > IDENT_CONDITION_MAX). An over-actuated model's equations,
    torques and mask are the k rows of W^T tau (:class:`JointModel`). ``kt_Nm_per_A``: a
    number or one per motor; ``top_Hz``: the excitation's top frequency when lowered from
    F1_HZ (the filter then sits at 5/3 of it)."""
    t_s = np.asarray(t_s, float)
    Te = float(np.median(np.diff(t_s)))
    fc = FIT_FILTER_HZ if top_Hz is None else min(FIT_FILTER_HZ, FIT_FILTER_HZ / F1_HZ * top_Hz)
    q, v, a = filtered(q_rad, Te, fc)
    n = model.n
    mask = np.column_stack([moving_rows(v[:, j], Te) for j in range(n)])
    if mask.sum(axis=0).min() < 50:
        raise NotExcited(f"only {int(mask.sum(axis=0).min())} samples of a joint move faster than "
                         f"{100 * IDENT_SLOW_FRACTION:g} % of its peak rate")
    P, C, mid = _offsets(model, q, mask)
    X3, names = design_matrix(model, q, v, a, Te, C, fc)
    if P is not None:
        X3 = np.einsum("nkj,njp->nkp", P, X3)
        mask = np.repeat(mask.any(axis=1)[:, None], P.shape[1], axis=1)
    tau_raw = np.asarray(kt_Nm_per_A, float) * np.column_stack([lowpass(np.asarray(current_A, float)[:, j], Te, fc)
                                                                for j in range(n)])
    b = _best_signs(X3, mask, tau_raw, Te, P)
    if b["cond"] > IDENT_CONDITION_MAX:
        raise NotExcited(f"the regressors are ill-conditioned (condition {b['cond']:.3g} > {IDENT_CONDITION_MAX:.3g}): "
                         "the motion does not separate inertia, friction and offsets")
    th, p = b["th"], len(names)
    dof = max(1, len(b["y"]) - len(th))
    inflate = max(1.0, 1.0 / (2.0 * fc * Te))
    cov = b["rss"] / dof * inflate * np.linalg.inv(b["Xn"].T @ b["Xn"]) / np.outer(b["scale"], b["scale"])
    s0 = 1 if th[names.index("c_link")] >= 0 else -1
    tau_fit = np.full_like(b["tau"], np.nan)
    for j in range(tau_fit.shape[1]):
        tau_fit[mask[:, j], j] = s0 * (X3[mask[:, j], j, :] @ th[:p])
    names_out, th_out, cov_out = _per_motor(names, s0 * th[:p], cov[:p, :p], C)
    extra = {"condition": b["cond"], "rows_used": int(mask.sum())}
    if C is not None:  # W^T at the pose the offsets were spread at: F0 = W^T T0
        extra["offset_W"], extra["offset_pose_rad"] = np.linalg.pinv(C), mid
    return Fit2(dict(zip(names_out, map(float, th_out), strict=True)), cov_out, names_out, float(th[-1] / Te),
                tuple(s0 * s for s in (1, *b["signs"])), math.sqrt(b["rss"] / len(b["y"])), mask, t_s, q,
                s0 * (b["tau"] - th[-1] * b["dtau"]), tau_fit, extra)
