"""The 5-bar pantograph's predicted figures for identification (issue 37) and the
identification run (the four-bar's: :mod:`cad.sim.identify_device`).

:func:`predict` gathers, from the build's DeviceSpec (:func:`cad.firmware.device.device_spec`:
the linkage and working modes, the bodies' masses from the solids, the motor, the encoder):
the tree parameters of the solids (:func:`cad.identify.joint2.tree_params`, the handle a
point mass at E), the rotor inertia, the joint ranges over the workspace rectangle, the
motors' Coulomb friction (Kt I0 of the data sheet, when it gives I0), the gravity torques of
a vertical device (:func:`cad.firmware.reference.gravity_torques`) and the excitation plan
(:func:`cad.identify.excitation2.plan2`).

:func:`identify` fits a log (:mod:`cad.identify.joint2`) and sets every figure beside its
prediction with a verdict (:mod:`cad.tolerances` ``IDENT_*``): the apparent mass at the
handle at home along x and y (the datasheet's ``effective_mass_home``), each motor's
friction and offset, the gravity scale, each encoder's direction and each current gain's sign.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import cad
from cad.device import resolve_device
from cad.errors import DesignError, FileDamaged
from cad.firmware import linkage_model, reference
from cad.firmware.device import device_spec
from cad.firmware.spec import motor_data
from cad.identify import excitation2, joint2
from cad.identify.joint2 import Fit2, FiveBarGeom, NotExcited
from cad.identify.logfile import Log
from cad.io import guard
from cad.isotropy.gii import workspace_half_mm
from cad.kinematics import fivebar as fb5
from cad.pipeline import design_hash
from cad.sim.device import device_build
from cad.sim.identify_device import SEPARABLE_CORRELATION, excitation_start, figure_row
from cad.tolerances import (
    IDENT_FRICTION_TOL_REL,
    IDENT_GRAVITY_TOL_REL,
    IDENT_MASS_TOL_REL,
    IDENT_MIN_TRAVEL_COUNTS,
    IDENT_OFFSET_TOL_FRACTION,
)

#: Control period of the pantograph's routine (s): 1 kHz, the rate of the Pantograph Mk-II's
#: haptic loop (Campion, Wang & Hayward, IROS 2005), inside the 1-4 kHz of haptic servo loops.
TE_S = 1e-3
#: Samples per side of the workspace grid whose inverse kinematics gives the joint ranges.
RANGE_GRID = 21


@dataclass(frozen=True)
class Prediction5:
    """A 5-bar's predicted figures (module docstring); SI units, tuples per motor."""

    name: str
    design_hash: str
    geom: FiveBarGeom
    beta_links: np.ndarray
    rotor_kg_m2: float
    Te_s: float
    kt_Nm_per_A: float
    i_max_A: float
    counts_per_rev: int
    direction: tuple[int, int]
    zero_rad: tuple[float, float]
    q_min_rad: tuple[float, float]
    q_max_rad: tuple[float, float]
    q_home_rad: tuple[float, float]
    Tc_Nm: float | None
    friction_source: str
    spec: object  # cad.firmware.spec.DeviceSpec (gravity torques)
    plan: excitation2.Plan2

    @property
    def vertical(self) -> bool:
        return self.spec.gravity_m_s2 is not None

    def gravity(self, q):
        """Predicted gravity torques (N, 2) N m at q (N, 2); None for a horizontal device."""
        if not self.vertical:
            return None
        return reference.gravity_torques(self.spec, np.atleast_2d(q))

    def angles(self, counts) -> np.ndarray:
        """Joint angles (N, 2) rad the firmware reads from ``counts`` (configured directions)."""
        c = np.asarray(counts, float).reshape(-1, 2)
        return np.asarray(self.zero_rad) + np.asarray(self.direction) * 2 * math.pi / self.counts_per_rev * c

    def task_mass_terms(self, q) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(A, B0, B1) (3 of (2, 2) kg) with the task mass matrix at q (1, 2) equal to
        c_link A + J0 B0 + J1 B1 (linear in the identified parameters)."""
        Jx = jacobian(self.geom, q)[0]
        Jq = np.linalg.inv(Jx)
        Mq = joint2.mass_matrix(self.geom, self.beta_links, (0.0, 0.0), q)[0]
        out = [Jq.T @ Mq @ Jq]
        for k in range(2):
            e = np.zeros((2, 2))
            e[k, k] = 1.0
            out.append(Jq.T @ e @ Jq)
        return tuple(out)

    def task_mass_kg(self, q, c_link: float = 1.0, J=None) -> np.ndarray:
        """Task-space mass matrix (2, 2) kg at q (1, 2) of the given parameters (default the
        prediction: the solids and the rotors)."""
        J = (self.rotor_kg_m2,) * 2 if J is None else J
        A, B0, B1 = self.task_mass_terms(q)
        return c_link * A + J[0] * B0 + J[1] * B1


def jacobian(g: FiveBarGeom, q) -> np.ndarray:
    """dE/dq (N, 2, 2) m/rad of the closure (:func:`cad.identify.joint2.closure`)."""
    q = np.atleast_2d(np.asarray(q, float))
    _, psi, Psi, _ = joint2.closure(g, q)
    n1 = np.column_stack([-np.sin(psi[:, 0]), np.cos(psi[:, 0])])
    m1 = np.column_stack([-np.sin(q[:, 0]), np.cos(q[:, 0])])
    J = g.l3 * n1[:, :, None] * Psi[:, None, 0, :]
    J[:, :, 0] += g.l1 * m1
    return J


def geom_of(params: dict) -> FiveBarGeom:
    """The :class:`FiveBarGeom` of a pantograph DeviceSpec's ``params`` (m)."""
    p = params
    return FiveBarGeom((p["b1x"], p["b1y"]), (p["b2x"], p["b2y"]), p["l2l"], p["l2r"], p["l3l"], p["l3r"],
                       int(p["assembly"]))


def beta_of(geom: FiveBarGeom, bodies: dict) -> np.ndarray:
    """The solids' tree parameters (8,) (:data:`cad.identify.joint2.TREE`) of the bodies
    (``{name: Body}``), the handle (when built) a point mass at E on the left arm."""
    def lm(n):
        b = bodies[n]
        return b.mass_kg, b.com_m, b.izz_kg_m2

    h = bodies["handle"].mass_kg if "handle" in bodies else 0.0
    return np.concatenate([joint2.tree_params(geom.l1, geom.l3, lm("proximal_left"), lm("distal_left"), h),
                           joint2.tree_params(geom.l2, geom.l4, lm("proximal_right"), lm("distal_right"))])


def joint_ranges(design, geom_mm) -> tuple[tuple[float, float], tuple[float, float]]:
    """(q_min, q_max) (rad, per joint) over a :data:`RANGE_GRID` grid of the workspace rectangle."""
    (cx, cy), (hx, hy) = design.workspace["center_mm"], workspace_half_mm(design.workspace)
    X, Y = np.meshgrid(np.linspace(cx - hx, cx + hx, RANGE_GRID), np.linspace(cy - hy, cy + hy, RANGE_GRID))
    ik = fb5.ik(geom_mm, np.column_stack([X.ravel(), Y.ravel()]))
    q = ik.q_rad[ik.ok]
    return tuple(map(float, q.min(axis=0))), tuple(map(float, q.max(axis=0)))


def _friction(device) -> tuple[float | None, str]:
    m = device.motor.spec
    f = m.friction_torque_mNm() if hasattr(m, "friction_torque_mNm") else None
    if f is None:
        return None, f"{device.motor.name}: no no-load current in its data: no friction prediction"
    return 1e-3 * f, f"{device.motor.name}: brushes and bearings Kt I0 (the motor's no-load current)"


def _gravity_A(spec, motor) -> float:
    """The largest motor current holding the device against gravity at home (A; 0 when horizontal)."""
    if spec.gravity_m_s2 is None:
        return 0.0
    return float(np.max(np.abs(reference.gravity_torques(spec, np.array([spec.q_home_rad]))))) / motor.kt_Nm_per_A


def predict(design, report: dict) -> Prediction5:
    """The :class:`Prediction5` of a 5-bar ``design`` built into ``report`` (report.json:
    its ``bodies``). DesignError naming ``firmware.plane`` when a vertical device's weight at
    home takes the motors' whole continuous current (no current is left to excite it)."""

    device = resolve_device(design)
    h = design_hash(design)
    spec = device_spec(design, report, h, cad.__version__, device, linkage_model(design))
    g = geom_of(spec.params)
    beta = beta_of(g, spec.bodies)
    motor = motor_data(device.motor.spec)
    lo, hi = joint_ranges(design, design.mechanism)
    home = np.array([spec.q_home_rad])
    Mq = joint2.mass_matrix(g, beta, (device.motor.rotor_inertia_kg_m2,) * 2, home)[0]
    dq = np.linalg.solve(jacobian(g, home)[0], np.array([0.0, 1.0]))  # the hand move: +y
    try:
        plan = excitation2.plan2(TE_S, motor.kt_Nm_per_A, motor.current_continuous_A, lo, hi, spec.q_home_rad,
                                 np.diag(Mq), np.sign(dq), device.encoder.counts_per_rev,
                                 gravity_ff=spec.gravity_m_s2 is not None, gravity_A=_gravity_A(spec, motor))
    except ValueError as exc:
        raise DesignError("firmware.plane", f"the identification routine cannot run: {exc} "
                          "(counterbalance the links, lighter links or a stronger motor)") from None
    Tc, src = _friction(device)
    return Prediction5(design.name, h, g, beta, device.motor.rotor_inertia_kg_m2, TE_S, motor.kt_Nm_per_A,
                       motor.current_continuous_A, device.encoder.counts_per_rev,
                       tuple(int(d) for d in spec.encoder_direction), tuple(spec.encoder_zero_rad), lo, hi,
                       tuple(spec.q_home_rad), Tc, src, spec, plan)


def build_report(design, build_dir: Path | None) -> dict:
    """report.json of the design's build (:func:`build_folder`)."""
    return build_folder(design, build_dir)[1]


def build_folder(design, build_dir: Path | None) -> tuple[Path, dict]:
    """(folder, report.json) of the design's build: ``build_dir`` (a finished ``build
    --formats mjcf`` of this design; DesignError naming ``--build-dir`` otherwise) or the
    cached simulator build (:func:`cad.sim.device.device_build`); the folder holds
    ``<name>.xml``."""
    if build_dir is not None:
        build_dir = Path(build_dir)
        if not (os.path.lexists(build_dir / "report.json") and os.path.lexists(build_dir / f"{design.name}.xml")):
            raise DesignError("--build-dir", f"{build_dir} holds no report.json and {design.name}.xml "
                              "(run hapticad build DESIGN --formats mjcf --out DIR first)")
        folder = build_dir
    else:
        folder = device_build(design, None)
    rep = guard.load_json(folder / "report.json", "report", "--build-dir")
    if not isinstance(rep, dict) or rep.get("name") != design.name or not isinstance(rep.get("bodies"), dict):
        raise DesignError("--build-dir", f"{folder} is not a build of {design.name!r} (its report.json "
                          "names another design or has no bodies)")
    return folder, rep


def predict_from_build(design, build_dir=None) -> Prediction5:
    """:func:`predict` with the bodies of the design's build (:func:`build_report`)."""
    return predict(design, build_report(design, None if build_dir is None else Path(build_dir)))


# ------------------------------------------------------------------ identification
def _mass_rows(pred: Prediction5, f: Fit2) -> list[dict]:
    home = np.array([pred.q_home_rad])
    terms = pred.task_mass_terms(home)
    idx = [f.names.index(k) for k in ("c_link", "J0_kg_m2", "J1_kg_m2")]
    C = f.cov[np.ix_(idx, idx)]
    th = np.array([f.theta[f.names[i]] for i in idx])
    M_pred = pred.task_mass_kg(home)
    rows = []
    for k, ax in ((0, "x"), (1, "y")):
        w = np.array([t[k, k] for t in terms])
        rows.append(figure_row(f"M{ax}{ax}_g@home", f"apparent mass at the handle along {ax} at home (other axis held)",
                         1e3 * float(w @ th), 1e3 * math.sqrt(max(float(w @ C @ w), 0.0)), "g",
                         1e3 * float(M_pred[k, k]), tol_rel=IDENT_MASS_TOL_REL, explain="apparent_mass"))
    return rows


def _friction_rows(pred: Prediction5, f: Fit2) -> list[dict]:
    rows = []
    for j in range(2):
        rows.append(figure_row(f"Tc{j}_mNm", f"Coulomb friction at motor {j}", 1e3 * f.theta[f"Tc{j}_Nm"],
                         1e3 * f.sigma(f"Tc{j}_Nm"), "mN m", None if pred.Tc_Nm is None else 1e3 * pred.Tc_Nm,
                         tol_rel=IDENT_FRICTION_TOL_REL, explain="friction"))
        rows.append(figure_row(f"b{j}_mNm_s_per_rad", f"viscous friction at motor {j}", 1e3 * f.theta[f"b{j}_Nm_s_per_rad"],
                         1e3 * f.sigma(f"b{j}_Nm_s_per_rad"), "mN m s/rad", None))
    return rows


def _gravity_rows(pred: Prediction5, f: Fit2) -> list[dict]:
    tol0 = 1e3 * IDENT_OFFSET_TOL_FRACTION * pred.kt_Nm_per_A * pred.i_max_A
    offs = [figure_row(f"offset{j}_mNm", f"constant torque offset at motor {j}", 1e3 * f.theta[f"T0{j}_Nm"],
                 1e3 * f.sigma(f"T0{j}_Nm"), "mN m", 0.0, tol_abs=tol0, explain="offset") for j in range(2)]
    if "cg" not in f.theta:
        return offs
    i = f.names.index("cg")
    q_med = np.median(f.q[f.mask.any(axis=1)], axis=0)
    g_med = pred.gravity(q_med[None, :])[0]
    loads = []
    for j in range(2):
        k = f.names.index(f"T0{j}_Nm")
        w = np.zeros(len(f.names))
        w[i], w[k] = g_med[j], 1.0
        loads.append(figure_row(f"gravity_load{j}_mNm", f"gravity load and offset at motor {j} at q = "
                          f"({math.degrees(q_med[0]):.1f}, {math.degrees(q_med[1]):.1f}) deg",
                          1e3 * (f.theta["cg"] * g_med[j] + f.theta[f"T0{j}_Nm"]),
                          1e3 * math.sqrt(max(float(w @ f.cov @ w), 0.0)), "mN m", 1e3 * float(g_med[j]),
                          tol_rel=IDENT_GRAVITY_TOL_REL, explain="gravity"))
    cg = figure_row("gravity_scale", "gravity load / the solids' prediction", f.theta["cg"], f.sigma("cg"), "1", 1.0,
              tol_rel=IDENT_GRAVITY_TOL_REL, explain="gravity")

    def corr(j):
        k = f.names.index(f"T0{j}_Nm")
        return abs(f.cov[i, k]) / math.sqrt(max(f.cov[i, i] * f.cov[k, k], 1e-300))

    rho = max(corr(j) for j in range(2))
    if rho > SEPARABLE_CORRELATION:
        why = (f"not separable on this log (correlation {rho:.3f}): the gravity torques vary too little over "
               "the poses visited; gravity_load*_mNm hold both")
        for r in (cg, *offs):
            r.update(verdict="n/a", explain=why)
    return [*loads, cg, *offs]


def _signs(enc, gain) -> list[dict]:
    out = []
    for j in range(2):
        fix_e = (f"swap encoder {j}'s A and B channels or flip its entry of [firmware] encoder_direction")
        fix_g = f"swap motor {j}'s leads or negate its driver's current command"
        if enc[j] == 0:
            e = {"key": f"encoder_direction_{j}", "value": "not determined", "verdict": "n/a",
                 "explain": "the handle was not moved by hand in the first phase"}
        else:
            e = {"key": f"encoder_direction_{j}", "value": "as configured" if enc[j] > 0 else "reversed",
                 "verdict": "within" if enc[j] > 0 else "MISS", **({} if enc[j] > 0 else {"explain": fix_e})}
        out.append(e)
        if gain is not None:
            gr = {"key": f"current_gain_sign_{j}", "value": "+" if gain[j] > 0 else "reversed",
                  "verdict": "within" if gain[j] > 0 else "MISS"}
            if gain[j] < 0:
                gr["explain"] = fix_g
            out.append(gr)
    return out


def hand_directions(pred: Prediction5, q: np.ndarray) -> tuple[int, int]:
    """Per joint: +1 when its hand-phase excursion has the sign the +y move gives
    (``plan.hand_sign``), -1 against, 0 when it moved less than 5 counts."""
    min_rad = 5 * 2 * math.pi / pred.counts_per_rev
    out = []
    for j in range(2):
        d = q[:, j] - q[0, j] if len(q) else np.zeros(0)
        k = int(np.argmax(np.abs(d))) if d.size else 0
        out.append(0 if not d.size or abs(d[k]) < min_rad else int(np.sign(d[k]) * pred.plan.hand_sign[j]))
    return tuple(out)


def _base(pred: Prediction5, log: Log) -> dict:
    return {"design": pred.name, "design_hash": pred.design_hash, "log_design_hash": log.design_hash,
            "hash_matches": log.design_hash == pred.design_hash, "rows": len(log.t_s), "figures": []}


def _stopped(pred: Prediction5, log: Log, q, k0: int, enc) -> dict | None:
    """The result of a log whose routine stopped early (None when it ran through): after the
    hand phase (an encoder reversed), or with a joint out of its range or hold envelope: a
    motor's current gain is reversed when the motion seen from the hold's start is closer to
    what the reversed commanded current would cause (with the predicted gravity, from rest,
    the joint's own inertia) than to what the current as configured would."""
    base = _base(pred, log)
    if k0 >= len(q) and min(enc) < 0:
        sig = [r for r in _signs(enc, None)]
        return {**base, "stopped": "after the hand phase: a joint moved against the +y hand move", "figures": sig,
                "misses": [r["key"] for r in sig if r["verdict"] == "MISS"]}
    lo, hi = np.asarray(pred.q_min_rad), np.asarray(pred.q_max_rad)
    env = np.abs(q[k0:] - np.asarray(pred.q_home_rad)) > np.asarray(pred.plan.envelope_rad)
    out = np.flatnonzero(np.any((q[k0:] < lo) | (q[k0:] > hi) | env, axis=1))
    if out.size == 0 or len(q) - k0 < 10:
        return None
    end = k0 + int(out[0])
    seg = slice(k0, end + 1)
    Te = float(np.median(np.diff(log.t_s[seg]))) if end > k0 else pred.Te_s
    Mq = joint2.mass_matrix(pred.geom, pred.beta_links, (pred.rotor_kg_m2,) * 2, np.array([pred.q_home_rad]))[0]
    grav = pred.gravity(q[seg]) if pred.vertical else np.zeros((end + 1 - k0, 2))
    gain = []
    for j in range(2):  # from rest at the hold's start: the motion each sign of the current would cause
        seen = q[end, j] - q[k0, j]
        moved = [float(np.sum(np.cumsum((s * pred.kt_Nm_per_A * log.current_A[seg, j] - grav[:, j]) / Mq[j, j])))
                 * Te**2 for s in (1, -1)]
        gain.append(1 if abs(moved[0] - seen) <= abs(moved[1] - seen) else -1)
    sig = _signs(enc, gain)
    return {**base, "stopped": f"at t = {log.t_s[end]:.3f} s: a joint left its range (or the hold envelope)", "figures": sig,
            "misses": [r["key"] for r in sig if r["verdict"] == "MISS"]}


def identify(pred: Prediction5, log: Log, path) -> tuple[dict, Fit2 | None]:
    """(result, fit) of a parsed 2-motor log of the design of ``pred`` (fit None when the
    routine stopped early); FileDamaged (field LOG) when the log excites too little."""
    q = pred.angles(log.counts)
    k0 = excitation_start(log.current_A)
    enc = hand_directions(pred, q[:k0]) if k0 > 0 else (0, 0)
    home = np.asarray(pred.zero_rad)
    q = np.where(np.asarray(enc) < 0, 2 * home - q, q)  # a reversed encoder, read the right way round
    early = _stopped(pred, log, q, k0, enc)
    if early is not None:
        return early, None
    travel = int(np.ptp(log.counts[k0:], axis=0).min()) if k0 < len(q) else 0
    if travel < IDENT_MIN_TRAVEL_COUNTS:
        raise FileDamaged("LOG", path, f"has too little excitation: a joint travelled {travel} counts under "
                                       f"current (at least {IDENT_MIN_TRAVEL_COUNTS})")
    try:
        f = joint2.fit(log.t_s[k0:], q[k0:], log.current_A[k0:], pred.kt_Nm_per_A, pred.geom, pred.beta_links,
                       pred.gravity if pred.vertical else None)
    except NotExcited as exc:
        raise FileDamaged("LOG", path, f"has too little excitation: {exc}") from None
    figs = _mass_rows(pred, f) + _friction_rows(pred, f) + _gravity_rows(pred, f) + _signs(enc, f.current_sign)
    res = {**_base(pred, log),
           "excitation_from_s": float(log.t_s[min(k0, len(log.t_s) - 1)]),
           "delay_samples": f.delay_samples, "rms_residual_mNm": 1e3 * f.rms_residual_Nm,
           "condition": f.extra["condition"], "rows_fitted": f.extra["rows_used"],
           "estimates": {k: {"value": v, "sigma": f.sigma(k)} for k, v in f.theta.items()},
           "figures": figs, "misses": [r["key"] for r in figs if r["verdict"] == "MISS"],
           "friction_source": pred.friction_source,
           "model": "s_j Kt i_j(t - n Te) = c_link (W^T tau_tree(solids))_j + J_j q_j'' + Tc_j sign(q_j') + "
                    "b_j q_j' [+ cg g_j(q)] + T0_j (5-bar, cad.identify.joint2)"}
    return res, f


__all__ = ["Prediction5", "build_folder", "build_report", "identify", "predict", "predict_from_build"]
