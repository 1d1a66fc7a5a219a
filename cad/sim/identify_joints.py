"""The identification run of a device of n >= 2 motors (issue 37): a parsed log fitted by the
prediction's own fit (the 5-bar's :mod:`cad.identify.joint2`, the delta's
:mod:`cad.identify.jointn`) and every figure set beside its prediction with a verdict
(:mod:`cad.tolerances` ``IDENT_*``): the apparent mass at the handle along each task axis at
the prediction's home (the other axes held), each motor's friction and offset, the gravity
scale and loads, each encoder's direction and each current gain's sign.

The prediction (:class:`cad.sim.identify_fivebar.Prediction5`,
:class:`cad.families.delta.identify.PredictionDelta`) gives: ``name``, ``design_hash``,
``n_joints``, ``axes`` (the task axes' names), ``home_words``, ``kt_Nm_per_A``,
``i_max_A``, ``Tc_Nm`` (None: no friction data), ``friction_source``, ``counts_per_rev``,
``plan`` (:class:`cad.identify.excitation2.Plan2`), ``zero_rad``, ``q_min_rad``,
``q_max_rad``, ``q_home_rad``, ``Te_s``, ``vertical``, ``gravity(q)``, ``angles(counts)``,
``task_mass_terms(q)`` (the task mass matrix at q = c_link A + sum_j J_j B_j: (A, B_0, ...)),
``task_mass_kg(q)``, ``joint_mass_kg(q)`` (N, n, n) with the rotors, ``fit_log(t, q, i)``
(:class:`cad.identify.joint2.Fit2`) and ``model_words``.
"""

from __future__ import annotations

import math

import numpy as np

from cad.errors import FileDamaged
from cad.identify import jointn
from cad.identify.joint2 import Fit2, NotExcited
from cad.identify.logfile import Log
from cad.sim.identify_device import SEPARABLE_CORRELATION, cut_short, excitation_start, figure_row
from cad.tolerances import (
    IDENT_FRICTION_TOL_REL,
    IDENT_GRAVITY_TOL_REL,
    IDENT_MASS_TOL_REL,
    IDENT_MIN_TRAVEL_COUNTS,
    IDENT_OFFSET_TOL_FRACTION,
)

#: Central-difference step of J' q' (s): J(q +- eps q').
DT_JDOT_S = 1e-6


class OverActuated:
    """The model methods of an over-actuated device's prediction (the twin pantograph, the
    pen), from its ``n_joints``, ``task(q)`` -> X (N, k), ``task_jacobian(q)`` -> dX/dq
    (N, k, n), ``basis(q)`` -> W = dq/dX (N, n, k), ``link_mass_X(X)`` -> Lambda of the
    solids (N, k, k) and ``rotor_kg_m2`` (a number or per motor)."""

    def link_torques(self, q, v, a) -> np.ndarray:
        """Least-norm joint torques (N, n) whose W^T is the links' Euler-Lagrange force in X
        (X' = J q', X'' = J q'' + J' q', :func:`cad.identify.jointn.lagrange_torques`)."""
        J = self.task_jacobian(q)
        Jdv = (self.task_jacobian(q + DT_JDOT_S * v) - self.task_jacobian(q - DT_JDOT_S * v)) / (2 * DT_JDOT_S)
        Xd = np.einsum("nij,nj->ni", J, v)
        Xdd = np.einsum("nij,nj->ni", J, a) + np.einsum("nij,nj->ni", Jdv, v)
        F = jointn.lagrange_torques(self.link_mass_X, self.task(q), Xd, Xdd)
        return np.einsum("nij,nj->ni", np.linalg.pinv(np.swapaxes(self.basis(q), 1, 2)), F)

    def joint_mass_kg(self, q) -> np.ndarray:
        """(N, n, n) diagonal: the inertia each motor meets alone, the others free,
        1 / (W Lambda^-1 W^T)_jj with the rotors in Lambda (the hold's damping and the
        stopped-log heuristics read it)."""
        q = np.atleast_2d(np.asarray(q, float))
        W = self.basis(q)
        rot = np.asarray(per_joint(self.rotor_kg_m2, self.n_joints))
        lam = self.link_mass_X(self.task(q)) + np.einsum("nji,j,njk->nik", W, rot, W)
        mob = np.einsum("nij,njk,nlk->nil", W, np.linalg.inv(lam), W)
        return np.einsum("ni,ij->nij", 1.0 / np.diagonal(mob, axis1=1, axis2=2), np.eye(self.n_joints))

    def task_mass_terms(self, q) -> tuple[np.ndarray, ...]:
        """(A, B_0 .. B_{n-1}) (k, k): Lambda at q (1, n) = c_link A + sum_j J_j B_j."""
        W = self.basis(q)[0]
        return (self.link_mass_X(self.task(q))[0], *(np.outer(W[j], W[j]) for j in range(self.n_joints)))

    def task_mass_kg(self, q, c_link: float = 1.0, J=None) -> np.ndarray:
        """Lambda (k, k) at q (1, n) of the given parameters (default: the prediction)."""
        J = per_joint(self.rotor_kg_m2, self.n_joints) if J is None else J
        A, *B = self.task_mass_terms(q)
        return c_link * A + sum(j * b for j, b in zip(J, B, strict=True))


def per_joint(x, n: int) -> list[float]:
    """A prediction's value per motor: a number for every motor, or one per motor (the pen)."""
    return [float(v) for v in np.broadcast_to(np.asarray(x, float), (n,))]


def motor_friction(device) -> tuple[float | None, str]:
    """(Coulomb friction at each motor N m (Kt I0 of its data sheet; None without I0), its source)."""
    m = device.motor.spec
    f = m.friction_torque_mNm() if hasattr(m, "friction_torque_mNm") else None
    if f is None:
        return None, f"{device.motor.name}: no no-load current in its data: no friction prediction"
    return 1e-3 * f, f"{device.motor.name}: brushes and bearings Kt I0 (the motor's no-load current)"


def mass_keys(pred) -> tuple[tuple[str, str, str, float], ...]:
    """(key, words, unit, SI -> unit factor) of each diagonal entry of the task mass matrix
    the identification reports: the prediction's ``mass_keys`` or, by default, an apparent
    mass in g along each of its ``axes``."""
    return getattr(pred, "mass_keys", None) or tuple(
        (f"M{a}{a}_g@home", f"apparent mass at the handle along {a} at {pred.home_words} (other axes held)", "g", 1e3)
        for a in pred.axes)


def mass_rows(pred, f: Fit2) -> list[dict]:
    """The task mass matrix's diagonal at home (:func:`mass_keys`), the other axes held."""
    home = np.array([pred.q_home_rad])
    terms = pred.task_mass_terms(home)
    idx = [f.names.index(k) for k in ("c_link", *(f"J{j}_kg_m2" for j in range(pred.n_joints)))]
    C = f.cov[np.ix_(idx, idx)]
    th = np.array([f.theta[f.names[i]] for i in idx])
    M_pred = pred.task_mass_kg(home)
    rows = []
    for k, (key, words, unit, scale) in enumerate(mass_keys(pred)):
        w = np.array([t[k, k] for t in terms])
        rows.append(figure_row(key, words, scale * float(w @ th), scale * math.sqrt(max(float(w @ C @ w), 0.0)),
                               unit, scale * float(M_pred[k, k]), tol_rel=IDENT_MASS_TOL_REL, explain="apparent_mass"))
    return rows


def friction_rows(pred, f: Fit2) -> list[dict]:
    """Each motor's Coulomb (against the data sheet's Kt I0) and viscous friction."""
    rows = []
    Tc = [None] * pred.n_joints if pred.Tc_Nm is None else per_joint(pred.Tc_Nm, pred.n_joints)
    for j in range(pred.n_joints):
        rows.append(figure_row(f"Tc{j}_mNm", f"Coulomb friction at motor {j}", 1e3 * f.theta[f"Tc{j}_Nm"],
                               1e3 * f.sigma(f"Tc{j}_Nm"), "mN m", None if Tc[j] is None else 1e3 * Tc[j],
                               tol_rel=IDENT_FRICTION_TOL_REL, explain="friction"))
        rows.append(figure_row(f"b{j}_mNm_s_per_rad", f"viscous friction at motor {j}", 1e3 * f.theta[f"b{j}_Nm_s_per_rad"],
                               1e3 * f.sigma(f"b{j}_Nm_s_per_rad"), "mN m s/rad", None))
    return rows


def middle_pose(pred, f: Fit2) -> np.ndarray:
    """The joint angles (n,) the gravity loads are stated at: the moving rows' median; for an
    over-actuated device (whose joint angles must close its loop) the logged pose nearest it."""
    moving = f.q[f.mask.any(axis=1)]
    q_med = np.median(moving, axis=0)
    if getattr(pred, "basis", None) is None:
        return q_med
    return moving[np.argmin(np.sum((moving - q_med) ** 2, axis=1))]


def _loads(pred, f: Fit2, i: int) -> list[dict]:
    q_med = middle_pose(pred, f)
    g_med = pred.gravity(q_med[None, :])[0]
    at = ", ".join(f"{math.degrees(x):.1f}" for x in q_med)
    out = []
    for j in range(pred.n_joints):
        k = f.names.index(f"T0{j}_Nm")
        w = np.zeros(len(f.names))
        w[i], w[k] = g_med[j], 1.0
        out.append(figure_row(f"gravity_load{j}_mNm", f"gravity load and offset at motor {j} at q = ({at}) deg",
                              1e3 * (f.theta["cg"] * g_med[j] + f.theta[f"T0{j}_Nm"]),
                              1e3 * math.sqrt(max(float(w @ f.cov @ w), 0.0)), "mN m", 1e3 * float(g_med[j]),
                              tol_rel=IDENT_GRAVITY_TOL_REL, explain="gravity"))
    return out


#: What an over-actuated device's per-motor offsets are (their verdict is the generalized offsets').
LEAST_NORM = ("the motors can hold a torque pattern against each other that moves nothing (an over-actuated "
              "device): only the generalized offsets are observable; these are the least-norm motor offsets with "
              "the same effect")


def generalized_offset_rows(pred, f: Fit2, tol0_mNm: np.ndarray) -> list[dict]:
    """An over-actuated device's offsets along its independent coordinates, F0 = W^T T0 at
    the log's middle pose (``f.extra["offset_pose_rad"]``, stated in the row: constant motor
    offsets T0 give a generalized force that changes with the pose, W(q)^T T0), against 0
    within what motor offsets of ``tol0_mNm`` (n,) can give (sum_j |W_ji| tol0_j)."""
    W = f.extra["offset_W"]  # (k, n): F0 = W T0
    at = ", ".join(f"{math.degrees(x):.1f}" for x in f.extra["offset_pose_rad"])
    idx = [f.names.index(f"T0{j}_Nm") for j in range(pred.n_joints)]
    T0 = np.array([f.theta[f.names[i]] for i in idx])
    C = f.cov[np.ix_(idx, idx)]
    rows = []
    for i, (ax, unit, scale) in enumerate(pred.force_axes):
        w = W[i]
        rows.append(figure_row(f"offset_{ax}", f"constant generalized force along {ax} (the motors' offsets) at the log's "
                               f"middle pose q = ({at}) deg",
                               scale * float(w @ T0), scale * math.sqrt(max(float(w @ C @ w), 0.0)), unit, 0.0,
                               tol_abs=scale * 1e-3 * float(np.abs(w) @ tol0_mNm), explain="offset"))
    return rows


def gravity_rows(pred, f: Fit2) -> list[dict]:
    """Each motor's offset (an over-actuated device's: the least-norm ones, n/a, and its
    generalized offsets with the verdicts); with gravity, its load at the log's median pose
    and the scale (n/a with the reason when the log cannot separate them from the offsets)."""
    n = pred.n_joints
    kt, im = per_joint(pred.kt_Nm_per_A, n), per_joint(pred.i_max_A, n)
    tol0 = [1e3 * IDENT_OFFSET_TOL_FRACTION * kt[j] * im[j] for j in range(n)]
    offs = [figure_row(f"offset{j}_mNm", f"constant torque offset at motor {j}", 1e3 * f.theta[f"T0{j}_Nm"],
                       1e3 * f.sigma(f"T0{j}_Nm"), "mN m", 0.0, tol_abs=tol0[j], explain="offset") for j in range(n)]
    if "offset_W" in f.extra:
        for r in offs:
            r.update(verdict="n/a", explain=LEAST_NORM)
        offs += generalized_offset_rows(pred, f, np.asarray(tol0))
    if "cg" not in f.theta:
        return offs
    i = f.names.index("cg")
    loads = _loads(pred, f, i)
    cg = figure_row("gravity_scale", "gravity load / the solids' prediction", f.theta["cg"], f.sigma("cg"), "1", 1.0,
                    tol_rel=IDENT_GRAVITY_TOL_REL, explain="gravity")

    def corr(j):
        k = f.names.index(f"T0{j}_Nm")
        return abs(f.cov[i, k]) / math.sqrt(max(f.cov[i, i] * f.cov[k, k], 1e-300))

    rho = max(corr(j) for j in range(n))
    if rho > SEPARABLE_CORRELATION:
        why = (f"not separable on this log (correlation {rho:.3f}): the gravity torques vary too little over "
               "the poses visited; gravity_load*_mNm hold both")
        for r in (cg, *offs):
            r.update(verdict="n/a", explain=why)
    return [*loads, cg, *offs]


def sign_rows(enc, gain) -> list[dict]:
    """Each encoder's direction and (when known) each current gain's sign, with the fix."""
    out = []
    for j, e_j in enumerate(enc):
        fix_e = f"swap encoder {j}'s A and B channels or flip its entry of [firmware] encoder_direction"
        if e_j == 0:
            e = {"key": f"encoder_direction_{j}", "value": "not determined", "verdict": "n/a",
                 "explain": "the handle was not moved by hand in the first phase"}
        else:
            e = {"key": f"encoder_direction_{j}", "value": "as configured" if e_j > 0 else "reversed",
                 "verdict": "within" if e_j > 0 else "MISS", **({} if e_j > 0 else {"explain": fix_e})}
        out.append(e)
        if gain is not None:
            gr = {"key": f"current_gain_sign_{j}", "value": "+" if gain[j] > 0 else "reversed",
                  "verdict": "within" if gain[j] > 0 else "MISS"}
            if gain[j] < 0:
                gr["explain"] = f"swap motor {j}'s leads or negate its driver's current command"
            out.append(gr)
    return out


def hand_directions(pred, q: np.ndarray) -> tuple[int, ...]:
    """Per joint: +1 when its hand-phase excursion has the sign the hand move gives
    (``plan.hand_sign``), -1 against, 0 when it moved less than 5 counts."""
    min_rad = 5 * 2 * math.pi / pred.counts_per_rev
    out = []
    for j in range(pred.n_joints):
        d = q[:, j] - q[0, j] if len(q) else np.zeros(0)
        k = int(np.argmax(np.abs(d))) if d.size else 0
        out.append(0 if not d.size or abs(d[k]) < min_rad else int(np.sign(d[k]) * pred.plan.hand_sign[j]))
    return tuple(out)


def _base(pred, log: Log) -> dict:
    return {"design": pred.name, "design_hash": pred.design_hash, "log_design_hash": log.design_hash,
            "hash_matches": log.design_hash == pred.design_hash, "rows": len(log.t_s), "figures": []}


def _gain_signs(pred, log: Log, q, k0: int, end: int) -> list[int]:
    """Each motor's current-gain sign from the motion since the hold's start: the sign whose
    commanded current (with the predicted gravity, from rest, the joint's own inertia) comes
    closer to the motion seen."""
    seg = slice(k0, end + 1)
    Te = float(np.median(np.diff(log.t_s[seg]))) if end > k0 else pred.Te_s
    Mq = pred.joint_mass_kg(np.array([pred.q_home_rad]))[0]
    grav = pred.gravity(q[seg]) if pred.vertical else np.zeros((end + 1 - k0, pred.n_joints))
    gain, kt = [], per_joint(pred.kt_Nm_per_A, pred.n_joints)
    for j in range(pred.n_joints):
        seen = q[end, j] - q[k0, j]
        moved = [float(np.sum(np.cumsum((s * kt[j] * log.current_A[seg, j] - grav[:, j]) / Mq[j, j])))
                 * Te**2 for s in (1, -1)]
        gain.append(1 if abs(moved[0] - seen) <= abs(moved[1] - seen) else -1)
    return gain


def stopped(pred, log: Log, q, k0: int, enc) -> dict | None:
    """The result of a log whose routine stopped early (None when it ran through): after the
    hand phase (an encoder reversed), or with a joint out of its range or hold envelope (a
    current gain reversed: :func:`_gain_signs`)."""
    base = _base(pred, log)
    if k0 >= len(q) and min(enc) < 0:
        sig = sign_rows(enc, None)
        return {**base, "stopped": f"after the hand phase: a joint moved against the hand move ({pred.plan.hand_move})",
                "figures": sig, "misses": [r["key"] for r in sig if r["verdict"] == "MISS"]}
    lo, hi = np.asarray(pred.q_min_rad), np.asarray(pred.q_max_rad)
    env = np.abs(q[k0:] - np.asarray(pred.q_home_rad)) > np.asarray(pred.plan.envelope_rad)
    out = np.flatnonzero(np.any((q[k0:] < lo) | (q[k0:] > hi) | env, axis=1))
    if out.size == 0 or len(q) - k0 < 10:
        return None
    end = k0 + int(out[0])
    sig = sign_rows(enc, _gain_signs(pred, log, q, k0, end))
    return {**base, "stopped": f"at t = {log.t_s[end]:.3f} s: a joint left its range (or the hold envelope)",
            "figures": sig, "misses": [r["key"] for r in sig if r["verdict"] == "MISS"]}


def _fit(pred, log: Log, q, k0: int, path) -> Fit2:
    travel = int(np.ptp(log.counts[k0:], axis=0).min()) if k0 < len(q) else 0
    if travel < IDENT_MIN_TRAVEL_COUNTS:
        raise FileDamaged("LOG", path, f"has too little excitation: a joint travelled {travel} counts under "
                                       f"current (at least {IDENT_MIN_TRAVEL_COUNTS})"
                                       + cut_short(pred.plan, log, k0))
    try:
        return pred.fit_log(log.t_s[k0:], q[k0:], log.current_A[k0:])
    except NotExcited as exc:
        raise FileDamaged("LOG", path, f"has too little excitation: {exc}"
                          + cut_short(pred.plan, log, k0)) from None


def identify(pred, log: Log, path) -> tuple[dict, Fit2 | None]:
    """(result, fit) of a parsed n-motor log of the design of ``pred`` (fit None when the
    routine stopped early); FileDamaged (field LOG) when the log excites too little."""
    q = pred.angles(log.counts)
    k0 = excitation_start(log.current_A)
    enc = hand_directions(pred, q[:k0]) if k0 > 0 else (0,) * pred.n_joints
    home = np.asarray(pred.zero_rad)
    q = np.where(np.asarray(enc) < 0, 2 * home - q, q)  # a reversed encoder, read the right way round
    early = stopped(pred, log, q, k0, enc)
    if early is not None:
        return early, None
    f = _fit(pred, log, q, k0, path)
    figs = mass_rows(pred, f) + friction_rows(pred, f) + gravity_rows(pred, f) + sign_rows(enc, f.current_sign)
    res = {**_base(pred, log),
           "excitation_from_s": float(log.t_s[min(k0, len(log.t_s) - 1)]),
           "delay_samples": f.delay_samples, "rms_residual_mNm": 1e3 * f.rms_residual_Nm,
           "condition": f.extra["condition"], "rows_fitted": f.extra["rows_used"],
           "estimates": {k: {"value": v, "sigma": f.sigma(k)} for k, v in f.theta.items()},
           "figures": figs, "misses": [r["key"] for r in figs if r["verdict"] == "MISS"],
           "friction_source": pred.friction_source, "model": pred.model_words}
    return res, f
