"""Least-squares identification of a 2-motor 5-bar pantograph from a log (issue 37).

Dynamics (Lagrange; the closed chain cut at the end effector into two serial 2-link arms, the
loop closure imposed by virtual work: Khalil & Dombre, *Modeling, Identification and Control
of Robots*, 2002, §7.10 (closed loops) and ch. 12 (the model linear in the inertial
parameters); the 5-bar case: Campion, Wang & Hayward, *The Pantograph Mk-II*, IROS 2005).
Tree coordinates theta = (q1, q2, psi1, psi2): the motors' absolute proximal angles and the
absolute angles of the distal links (elbow C_i to the end effector E). One arm with proximal
length l, proximal angle a, distal angle b, delta = b - a has the kinetic energy::

    T = 1/2 Ip a'^2 + 1/2 Id b'^2 + l a' b' (mx cos(delta) - my sin(delta))

and the joint torques (absolute angles)::

    tau_a = Ip a'' + mx l (cos d b'' - sin d b'^2) + my l (-sin d b'' - cos d b'^2)
    tau_b = Id b'' + mx l (cos d a'' + sin d a'^2) + my l (-sin d a'' + cos d a'^2)

with Ip the proximal link's inertia about its motor axis plus the distal mass times l^2 (the
rotor separately), Id the distal link's inertia about the elbow, (mx, my) its first moment in
its frame (origin C, x towards E). The handle translates with E: a point mass on the left arm
at (l3, 0). The motor torques are tau_q = W^T tau_tree with W = d theta / dq = [I; Psi],
Psi = d psi / dq from the closure C1 + l3 u(psi1) = C2 + l4 u(psi2).

Identified (the mass matrix is linear in them): ``c_link`` (the scale of the solids' link and
handle parameters: predicted 1), ``J0_kg_m2``, ``J1_kg_m2`` (inertia turning with each motor:
the rotor, a pulley; predicted the rotor's) -- three unknowns, as many as a 2x2 mass matrix
has numbers at one pose, so a log near home determines them -- and per motor Coulomb
``Tc{j}_Nm`` and viscous ``b{j}_Nm_s_per_rad`` friction, the gravity scale ``cg`` (vertical
devices), the constant torques ``T0{j}_Nm``, one delay and the current-gain sign of each motor.

The signal path (filter, derivatives, slow rows left out, delay column, covariance) is the
1-motor fit's (:mod:`cad.identify.regression`), per joint; the two joints' equations are
stacked.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from cad.identify.regression import (
    EDGE_ROWS,
    FILTER_HZ,
    Estimates,
    NotExcited,
    derivatives,
    lowpass,
)
from cad.tolerances import IDENT_CONDITION_MAX, IDENT_SLOW_FRACTION


@dataclass(frozen=True)
class FiveBarGeom:
    """A 5-bar's geometry (m): motor axes B1, B2, proximal lengths l1 (left) and l2 (right),
    distal lengths l3 (left), l4 (right), assembly mode (+1: E left of C1 -> C2)."""

    b1: tuple[float, float]
    b2: tuple[float, float]
    l1: float
    l2: float
    l3: float
    l4: float
    assembly: int


#: Tree parameter names, left arm then right arm (kg m^2, kg m^2, kg m, kg m).
TREE = ("IpL", "IdL", "mxL", "myL", "IpR", "IdR", "mxR", "myR")


def closure(g: FiveBarGeom, q) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(E (N, 2) m, psi (N, 2) rad, Psi = dpsi/dq (N, 2, 2), ok (N,)) of joint angles q (N, 2)
    rad: E by circle intersection in the assembly mode ``g.assembly``."""
    q = np.atleast_2d(np.asarray(q, float))
    C1 = np.asarray(g.b1) + g.l1 * np.column_stack([np.cos(q[:, 0]), np.sin(q[:, 0])])
    C2 = np.asarray(g.b2) + g.l2 * np.column_stack([np.cos(q[:, 1]), np.sin(q[:, 1])])
    d = C2 - C1
    r = np.hypot(d[:, 0], d[:, 1])
    a = (g.l3**2 - g.l4**2 + r * r) / (2 * r)
    h2 = g.l3**2 - a * a
    ok = h2 > 0
    h = np.sqrt(np.where(ok, h2, 0.0))
    u = d / r[:, None]
    E = C1 + a[:, None] * u + g.assembly * h[:, None] * np.column_stack([-u[:, 1], u[:, 0]])
    psi = np.column_stack([np.arctan2(*(E - C1)[:, ::-1].T), np.arctan2(*(E - C2)[:, ::-1].T)])
    n1 = np.column_stack([-np.sin(psi[:, 0]), np.cos(psi[:, 0])])
    n2 = np.column_stack([-np.sin(psi[:, 1]), np.cos(psi[:, 1])])
    m1 = np.column_stack([-np.sin(q[:, 0]), np.cos(q[:, 0])])
    m2 = np.column_stack([-np.sin(q[:, 1]), np.cos(q[:, 1])])
    A = np.stack([g.l3 * n1, -g.l4 * n2], axis=-1)  # (N, 2, 2): columns psi1', psi2'
    R = np.stack([-g.l1 * m1, g.l2 * m2], axis=-1)  # C2' - C1' per q'
    Psi = np.linalg.solve(A, R)
    return E, psi, Psi, ok


def arm_regressor(l_m, a, b, va, vb, aa, ab) -> tuple[np.ndarray, np.ndarray]:
    """(tau_a (N, 4), tau_b (N, 4)) per unit of (Ip, Id, mx, my) of one arm (module docstring):
    proximal length ``l_m``, absolute angles, rates and accelerations of the proximal (a) and
    distal (b) links."""
    d = b - a
    c, s = np.cos(d), np.sin(d)
    z = np.zeros_like(a)
    ta = np.column_stack([aa, z, l_m * (c * ab - s * vb * vb), l_m * (-s * ab - c * vb * vb)])
    tb = np.column_stack([z, ab, l_m * (c * aa + s * va * va), l_m * (-s * aa + c * va * va)])
    return ta, tb


def joint_regressor(g: FiveBarGeom, q, v, a, psi, vpsi, apsi, Psi) -> np.ndarray:
    """Y (N, 2, 8): motor torques per unit of each tree parameter (:data:`TREE`), tau_q = W^T
    tau_tree, from the joint and distal angles, rates, accelerations and Psi (N, 2, 2)."""
    taL, tbL = arm_regressor(g.l1, q[:, 0], psi[:, 0], v[:, 0], vpsi[:, 0], a[:, 0], apsi[:, 0])
    taR, tbR = arm_regressor(g.l2, q[:, 1], psi[:, 1], v[:, 1], vpsi[:, 1], a[:, 1], apsi[:, 1])
    n = len(q)
    Yt = np.zeros((n, 4, 8))  # rows: q1, q2, psi1, psi2
    Yt[:, 0, :4], Yt[:, 2, :4] = taL, tbL
    Yt[:, 1, 4:], Yt[:, 3, 4:] = taR, tbR
    return Yt[:, :2, :] + np.einsum("nij,nik->njk", Psi, Yt[:, 2:, :])


def tree_params(l1: float, l3: float, prox, dist, handle_kg: float = 0.0) -> np.ndarray:
    """(Ip, Id, mx, my) of one arm from its links' ``(mass kg, (cx, cy) m, Izz about the COM
    kg m^2)`` in their frames; ``handle_kg`` a point mass at E (the left arm's)."""
    mp, cp, ip = prox
    md, cd, idd = dist
    Ip = ip + mp * (cp[0] ** 2 + cp[1] ** 2) + (md + handle_kg) * l1 * l1
    Id = idd + md * (cd[0] ** 2 + cd[1] ** 2) + handle_kg * l3 * l3
    return np.array([Ip, Id, md * cd[0] + handle_kg * l3, md * cd[1]])


def mass_matrix(g: FiveBarGeom, beta, J_kg_m2, q) -> np.ndarray:
    """Joint-space mass matrix (N, 2, 2) kg m^2 at q (N, 2): W^T M_tree W of the tree
    parameters ``beta`` (8,) plus ``J_kg_m2`` (2,) on the diagonal (the regressor at rest)."""
    q = np.atleast_2d(np.asarray(q, float))
    _, psi, Psi, _ = closure(g, q)
    z = np.zeros_like(q)
    cols = []
    for k in range(2):  # M e_k: the torques of a unit acceleration of joint k from rest
        a = np.zeros_like(q)
        a[:, k] = 1.0
        Y = joint_regressor(g, q, z, a, psi, z, Psi @ np.eye(2)[k], Psi)
        cols.append(Y @ np.asarray(beta, float) + a * np.asarray(J_kg_m2, float))
    return np.stack(cols, axis=-1)


def signals(g: FiveBarGeom, q, Te_s: float) -> dict:
    """Filtered joint angles and their rates and accelerations, the distal angles (unwrapped,
    from the filtered q) and theirs, Psi: the inputs of :func:`joint_regressor` (N rows)."""
    qf, v, a = np.empty_like(q), np.empty_like(q), np.empty_like(q)
    for j in range(q.shape[1]):
        qf[:, j], v[:, j], a[:, j] = derivatives(q[:, j], Te_s)
    _, psi, Psi, ok = closure(g, qf)
    psi = np.unwrap(psi, axis=0)
    vpsi = np.gradient(psi, Te_s, axis=0)
    return {"q": qf, "v": v, "a": a, "psi": psi, "vpsi": vpsi, "apsi": np.gradient(vpsi, Te_s, axis=0),
            "Psi": Psi, "ok": ok}


@dataclass(frozen=True)
class Fit2(Estimates):
    """Estimates ``theta`` {name: value}, covariance ``cov`` (order of ``names``), the delay
    (periods), the current-gain sign of each motor, the signals the fit saw (``t_s``, ``q``
    rad (N, 2), ``tau_meas``/``tau_fit`` N m (N, 2), ``mask`` (N, 2))."""

    theta: dict[str, float]
    cov: np.ndarray
    names: tuple[str, ...]
    delay_samples: float
    current_sign: tuple[int, ...]
    rms_residual_Nm: float
    mask: np.ndarray
    t_s: np.ndarray
    q: np.ndarray
    tau_meas: np.ndarray
    tau_fit: np.ndarray
    extra: dict = field(default_factory=dict)


def moving_rows(v: np.ndarray, Te: float) -> np.ndarray:
    """Rows (N,) where a joint moves: faster than IDENT_SLOW_FRACTION of its peak, away from
    reversals by the filter's impulse response, away from the log's edges."""
    slow = np.abs(v) <= IDENT_SLOW_FRACTION * np.max(np.abs(v))
    k = max(1, round(0.5 / (FILTER_HZ * Te)))
    m = ~(np.convolve(slow.astype(float), np.ones(2 * k + 1), "same") > 0)
    m[:EDGE_ROWS] = False
    m[-EDGE_ROWS:] = False
    return m


def design_matrix(g: FiveBarGeom, sig: dict, beta_links, grav, Te: float) -> tuple[np.ndarray, tuple[str, ...]]:
    """X (N, 2, p) and names of the model (module docstring) for the signals ``sig``:
    ``beta_links`` (8,) the solids' tree parameters, ``grav`` (N, 2) the predicted gravity
    torques at the filtered q (None: horizontal)."""
    q, v, a = sig["q"], sig["v"], sig["a"]
    Y = joint_regressor(g, q, v, a, sig["psi"], sig["vpsi"], sig["apsi"], sig["Psi"])
    n = len(q)
    cols, names = [Y @ np.asarray(beta_links, float)], ["c_link"]
    for j in range(2):
        c = np.zeros((n, 2))
        c[:, j] = a[:, j]
        cols.append(c)
        names.append(f"J{j}_kg_m2")
    for j in range(2):
        c, b = np.zeros((n, 2)), np.zeros((n, 2))
        c[:, j] = lowpass(np.sign(v[:, j]), Te)
        b[:, j] = v[:, j]
        cols += [c, b]
        names += [f"Tc{j}_Nm", f"b{j}_Nm_s_per_rad"]
    if grav is not None:
        cols.append(np.asarray(grav, float))
        names.append("cg")
    for j in range(2):
        c = np.zeros((n, 2))
        c[:, j] = 1.0
        cols.append(c)
        names.append(f"T0{j}_Nm")
    return np.stack(cols, axis=-1), tuple(names)


def scaled_lstsq(X, y):
    """(theta, X with unit columns, the column scales, its condition number) of the least
    squares ``X theta = y`` solved on unit columns."""
    scale = np.linalg.norm(X, axis=0)
    scale[scale == 0] = 1.0
    Xn = X / scale
    sv = np.linalg.svd(Xn, compute_uv=False)
    cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else math.inf
    th, *_ = np.linalg.lstsq(Xn, y, rcond=None)
    return th / scale, Xn, scale, cond


def fit(t_s, q_rad, current_A, kt_Nm_per_A: float, g: FiveBarGeom, beta_links, gravity=None) -> Fit2:
    """Fit the model to a log segment: times (s, uniform), joint angles (N, 2) rad, commanded
    currents (N, 2) A; ``gravity`` a callable q (N, 2) -> predicted gravity torques (N, 2) N m
    (None: horizontal). Each motor's current-gain sign is the one of the two sign patterns
    (+,+), (+,-) that fits better, negated when the link scale comes out negative.
    Raises :class:`NotExcited` when too few rows move or the regressors are ill-conditioned."""
    t_s = np.asarray(t_s, float)
    Te = float(np.median(np.diff(t_s)))
    sig = signals(g, np.asarray(q_rad, float), Te)
    mask = np.column_stack([moving_rows(sig["v"][:, j], Te) for j in range(2)]) & sig["ok"][:, None]
    if mask.sum(axis=0).min() < 50:
        raise NotExcited(f"only {int(mask.sum(axis=0).min())} samples of a joint move faster than "
                         f"{100 * IDENT_SLOW_FRACTION:g} % of its peak rate")
    X3, names = design_matrix(g, sig, beta_links, None if gravity is None else gravity(sig["q"]), Te)
    tau_raw = kt_Nm_per_A * np.column_stack([lowpass(np.asarray(current_A, float)[:, j], Te) for j in range(2)])
    best = None
    for s1 in (1, -1):
        tau = tau_raw * np.array([1.0, s1])
        dtau = np.gradient(tau, Te, axis=0)
        X = np.concatenate([X3[mask[:, j], j, :] for j in range(2)])
        X = np.column_stack([X, np.concatenate([dtau[mask[:, j], j] for j in range(2)])])
        y = np.concatenate([tau[mask[:, j], j] for j in range(2)])
        th, Xn, scale, cond = scaled_lstsq(X, y)
        rss = float(np.sum((y - X @ th) ** 2))
        if best is None or rss < best[0]:
            best = (rss, s1, th, Xn, scale, cond, X, y, tau, dtau)
    rss, s1, th, Xn, scale, cond, X, y, tau, dtau = best
    if cond > IDENT_CONDITION_MAX:
        raise NotExcited(f"the regressors are ill-conditioned (condition {cond:.3g} > {IDENT_CONDITION_MAX:.3g}): "
                         "the motion does not separate inertia, friction and offsets")
    p = len(names)
    dof = max(1, len(y) - len(th))
    inflate = max(1.0, 1.0 / (2.0 * FILTER_HZ * Te))
    cov = rss / dof * inflate * np.linalg.inv(Xn.T @ Xn) / np.outer(scale, scale)
    s0 = 1 if th[names.index("c_link")] >= 0 else -1
    sign = (s0, s0 * s1)
    tau_fit = np.full_like(tau, np.nan)
    for j in range(2):
        tau_fit[mask[:, j], j] = s0 * (X3[mask[:, j], j, :] @ th[:p])
    tau_meas = s0 * (tau - th[-1] * dtau)
    return Fit2(dict(zip(names, map(float, s0 * th[:p]), strict=True)), cov[:p, :p], names, float(th[-1] / Te),
                sign, math.sqrt(rss / len(y)), mask, t_s, sig["q"], tau_meas, tau_fit,
                {"condition": cond, "rows_used": int(mask.sum())})
