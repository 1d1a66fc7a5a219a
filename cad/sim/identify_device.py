"""The four-bar's predicted figures for identification (issue 37) and the identification run.

:func:`predict` gathers, from the resolved device and the datasheet's functions (one fact,
one place): the crank's equivalent inertia D(q) of the build's H11..H33 (Hoeken paper eq 14,
rotor included, :func:`cad.dynamics.inertia.equivalent_inertia`) and the apparent mass along
the path M11(q) (eq 22, path frame, :func:`cad.sim.wall.device_tables`), the motor's torque constant and continuous current
(:func:`cad.device.resolve_device`), the encoder (counts, ``[firmware]`` direction and zero),
the control period and the friction at the handle (:func:`cad.sim.device.wall_inputs`:
``[stiffness]`` or the datasheet's estimate), the gravity torque of a vertical device
(:func:`cad.firmware.reference.gravity_torques` of the solids' masses) and the excitation
plan (:func:`cad.identify.excitation.plan`).

:func:`identify` fits a log (:mod:`cad.identify.regression`) and sets every figure beside
its prediction with a verdict (:mod:`cad.tolerances` ``IDENT_*``) and, for a miss, what in the
design would explain it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

import cad
from cad.device import resolve_device
from cad.dynamics.inertia import InertiaCoefficients, equivalent_inertia
from cad.errors import DesignError, FileDamaged
from cad.families.fourbar.datasheet import lever, stiffness_inputs
from cad.firmware import reference
from cad.firmware.device import device_spec
from cad.firmware.spec import encoder_zero, motor_data
from cad.identify import excitation
from cad.identify.logfile import Log
from cad.identify.regression import Fit, NotExcited, fit, hand_direction
from cad.io import guard
from cad.kinematics.fourbar import solve
from cad.pipeline import design_hash
from cad.sim.device import device_build, read_device_report, wall_inputs
from cad.sim.wall import device_tables
from cad.tolerances import (
    IDENT_FRICTION_TOL_REL,
    IDENT_GRAVITY_TOL_REL,
    IDENT_MASS_TOL_REL,
    IDENT_MIN_TRAVEL_COUNTS,
    IDENT_OFFSET_TOL_FRACTION,
)

#: Families identify and bench-log cover (1-DOF four-bars); the others are refused in one line.
POSES = (0.05, 0.25, 0.5, 0.75, 0.95)


@dataclass(frozen=True)
class Prediction:
    """A four-bar's predicted figures (module docstring); SI units."""

    name: str
    design_hash: str
    tab: object  # cad.sim.wall.DeviceTables
    Te_s: float
    kt_Nm_per_A: float
    i_max_A: float
    counts_per_rev: int
    direction: int
    zero_rad: float
    q_min_rad: float
    q_max_rad: float
    rotor_kg_m2: float
    Fs_N: float
    Fv_N_s_per_m: float
    friction_source: str
    g_table: np.ndarray | None
    plan: excitation.Plan
    D_table: np.ndarray
    dD_table: np.ndarray

    def D(self, q):
        """Equivalent crank inertia (kg m^2), eq (14)."""
        return self.tab.at(self.D_table, q)

    def dD(self, q):
        return self.tab.at(self.dD_table, q)

    def M11_g(self, q):
        """Predicted apparent mass along the path (g), eq (22)."""
        return 1e3 * self.tab.at(self.tab.a, q) / self.tab.at(self.tab.Jx, q) ** 2

    def Jx(self, q):
        return self.tab.at(self.tab.Jx, q)

    def g(self, q):
        return None if self.g_table is None else self.tab.at(self.g_table, q)

    @property
    def J_mid(self) -> float:
        return float(abs(self.Jx(0.5 * (self.q_min_rad + self.q_max_rad))))

    @property
    def tau_cont_Nm(self) -> float:
        return self.kt_Nm_per_A * self.i_max_A

    def angles(self, counts) -> np.ndarray:
        """Crank angle (rad) the firmware reads from ``counts`` (configured direction)."""
        return self.zero_rad + self.direction * 2 * math.pi / self.counts_per_rev * np.asarray(counts, float)


def _gravity_table(design, report: dict | None, device, h: str, tab) -> np.ndarray | None:
    if not design.firmware.vertical:
        return None

    spec = device_spec(design, report, h, cad.__version__, device)
    phi = tab.phi0 + tab.h * np.arange(tab.x.size)
    return reference.gravity_torques(spec, phi[:, None])[:, 0]


def _friction_inputs(design) -> tuple[dict, str]:
    """Te and the friction prediction of :func:`cad.sim.device.wall_inputs`; a motor without
    friction data gives Fs = Fv = 0 (their verdicts n/a) instead of an error: the firmware
    and the bench do not need a friction prediction."""

    try:
        return wall_inputs(design)
    except DesignError:
        s, src = stiffness_inputs(design, lever(design)[1], None)
        return s, src + "; the motor has no friction data: no friction prediction"


def predict(design, H, report: dict | None = None) -> Prediction:
    """The :class:`Prediction` of a four-bar design with inertia coefficients ``H``
    (:class:`cad.dynamics.inertia.InertiaCoefficients`, from its build); ``report`` (the build's
    report.json) is needed for a vertical device's gravity torque only."""

    device = resolve_device(design)
    motor = motor_data(device.joint_motor("crank"))  # K_t, torques at the crank (x n through a capstan)
    counts = device.joint_counts_per_rev("crank")  # per crank turn
    s, src = _friction_inputs(design)

    tab = device_tables(design, H, 4001)
    lo, hi = design.phi1_min_rad, design.phi1_max_rad
    D = equivalent_inertia(design.linkage, solve(design.linkage, np.linspace(lo, hi, tab.x.size)), H)
    h = design_hash(design)
    zero = encoder_zero(design.firmware, (0.5 * (lo + hi),))[0]
    D_mid = float(tab.at(D, 0.5 * (lo + hi)))
    plan = excitation.plan(s["Te"], motor.kt_Nm_per_A, motor.current_continuous_A, lo, hi, D_mid, counts)
    return Prediction(design.name, h, tab, s["Te"], motor.kt_Nm_per_A, motor.current_continuous_A,
                      counts, int(design.firmware.encoder_direction[0]), zero,
                      lo, hi, device.joint_rotor_inertia_kg_m2("crank"), s["Fs"], s["Fv"], src,
                      _gravity_table(design, report, device, h, tab), plan, D, np.gradient(D, tab.h))


def predict_from_build(design, build_dir=None) -> Prediction:
    """:func:`predict` with H of the design's simulator build (:func:`cad.sim.device.device_build`)."""

    folder = device_build(design, build_dir)
    rep = read_device_report(folder, "--build-dir" if build_dir is not None else "identify")
    if design.firmware.vertical:
        rep = guard.load_json(folder / "report.json", "report", "--build-dir")
    H = InertiaCoefficients(rep["H11_kg_m2"], rep["H12_kg_m2"], rep["H22_kg_m2"], rep["H33_kg_m2"],
                            math.radians(rep["beta2_deg"]))
    return predict(design, H, rep)


#: What in the design would explain a miss, per figure and direction (measured above / below).
EXPLAIN = {
    "apparent_mass": ("a heavier part than the solids: the knob or handle, a denser material than "
                      "the design's, extra fasteners, a larger motor rotor (check the BOM masses); or "
                      "a weaker torque constant than the data sheet (the same current moves it less)",
                      "a lighter part than the solids: a hollow or printed part at low infill, a "
                      "missing knob or motor rotor; or a stronger torque constant than the data sheet"),
    "friction": ("a stiff bearing (preload, misalignment, a press fit too tight), a cable or shaft "
                 "rubbing, the motor's brushes", "less friction than predicted (the prediction is "
                 "an estimate: record the measured value in [stiffness])"),
    "viscous": ("a viscous drag: grease, a seal, a back-EMF path through the driver",
                "less damping than predicted (record the measured Fv in [stiffness])"),
    "gravity": ("a heavier or longer part than the solids, or the device tilted further than "
                "[firmware] gravity_direction says", "a lighter part, or the device less tilted"),
    "offset": ("a constant torque: a cable or spring pulling the crank, an unbalanced link in a "
               "device not quite horizontal, a current-sensor or driver offset",) * 2,
}


def figure_row(key, what, value, sigma, unit, pred, tol_rel=None, tol_abs=None, explain=None) -> dict:
    """One figure of the result: measured ``value`` +- ``sigma`` beside the prediction ``pred``
    (None: no prediction), the verdict within ``tol_abs`` or ``tol_rel`` of it (n/a without a
    prediction, or a relative tolerance of 0), and for a miss what would explain it
    (:data:`EXPLAIN` ``explain``, by whether the measured figure is larger in size)."""
    if pred is None or (tol_rel is not None and pred == 0):
        ok = None
    else:
        gap = value - pred
        lim = tol_abs if tol_abs is not None else tol_rel * abs(pred)
        ok = bool(abs(gap) <= lim)
    out = {"key": key, "what": what, "value": value, "sigma": sigma, "unit": unit,
           "predicted": pred, "tol_rel": tol_rel, "tol_abs": tol_abs,
           "verdict": "n/a" if ok is None else ("within" if ok else "MISS")}
    if ok is False and explain is not None:
        out["explain"] = EXPLAIN[explain][0 if abs(value) > abs(pred) else 1]  # larger in size (loads < 0)
    return out



def _mass_rows(pred: Prediction, f: Fit) -> list[dict]:
    c = f.names.index("c0_kg_m2"), f.names.index("c1")
    C = f.cov[np.ix_(c, c)]
    rows = []
    for p in POSES:
        q = float(np.quantile(f.q[f.mask], p))
        D, M = float(pred.D(q)), float(pred.M11_g(q))
        m = (f.theta["c0_kg_m2"] + f.theta["c1"] * D) / D * M  # M11 scales with D at a pose
        s = math.sqrt(max(float(np.array([1.0, D]) @ C @ np.array([1.0, D])), 0.0)) / D * M
        rows.append({**figure_row(f"M11_g@{math.degrees(q):.1f}deg", f"apparent mass along the path at "
                            f"phi1 = {math.degrees(q):.1f} deg", m, s, "g", M,
                            tol_rel=IDENT_MASS_TOL_REL, explain="apparent_mass"), "phi1_deg": math.degrees(q)})
    return rows


def _figures(pred: Prediction, f: Fit) -> list[dict]:
    J = pred.J_mid
    th = f.theta
    rows = _mass_rows(pred, f)
    rows.append(figure_row("Fs_N", "Coulomb friction at the handle (mid-stroke)", th["Tc_Nm"] / J,
                     f.sigma("Tc_Nm") / J, "N", pred.Fs_N, tol_rel=IDENT_FRICTION_TOL_REL, explain="friction"))
    rows.append(figure_row("Fv_N_s_per_m", "viscous friction at the handle (mid-stroke)", th["b_Nm_s_per_rad"] / J**2,
                     f.sigma("b_Nm_s_per_rad") / J**2, "N s/m", pred.Fv_N_s_per_m,
                     tol_rel=IDENT_FRICTION_TOL_REL, explain="viscous"))
    rows += _gravity_rows(pred, f)
    return rows


#: |correlation| of the gravity scale and the offset estimates above which the log cannot tell
#: them apart (the gravity torque barely varies over the poses it visited).
SEPARABLE_CORRELATION = 0.95


def _gravity_rows(pred: Prediction, f: Fit) -> list[dict]:
    """The offset; for a vertical device also the gravity load at the log's middle pose
    (gravity and offset together: always well determined) and the gravity scale, whose verdict
    (and the offset's) is n/a when the two are not separable on this log."""
    th = f.theta
    tol0 = 1e3 * IDENT_OFFSET_TOL_FRACTION * pred.tau_cont_Nm
    off = figure_row("offset_mNm", "constant torque offset on the crank", 1e3 * th["T0_Nm"], 1e3 * f.sigma("T0_Nm"),
               "mN m", 0.0, tol_abs=tol0, explain="offset")
    if "cg" not in th:
        return [off]
    i, j = f.names.index("cg"), f.names.index("T0_Nm")
    q = float(np.median(f.q[f.mask]))
    gm = float(pred.g(q))
    w = np.zeros(len(f.names))
    w[i], w[j] = gm, 1.0
    load = figure_row("gravity_load_mNm", f"gravity load and offset at phi1 = {math.degrees(q):.1f} deg",
                1e3 * (th["cg"] * gm + th["T0_Nm"]), 1e3 * math.sqrt(max(float(w @ f.cov @ w), 0.0)),
                "mN m", 1e3 * gm, tol_rel=IDENT_GRAVITY_TOL_REL, explain="gravity")
    cg = figure_row("gravity_scale", "gravity load / the solids' prediction", th["cg"], f.sigma("cg"), "1", 1.0,
              tol_rel=IDENT_GRAVITY_TOL_REL, explain="gravity")
    rho = f.cov[i, j] / math.sqrt(max(f.cov[i, i] * f.cov[j, j], 1e-300))
    if abs(rho) > SEPARABLE_CORRELATION:
        why = (f"not separable on this log (correlation {rho:.3f}): the gravity torque varies too little "
               "over the poses visited; gravity_load_mNm holds both")
        for r in (cg, off):
            r.update(verdict="n/a", explain=why)
    return [load, cg, off]


def _signs(enc: int, gain: int) -> list[dict]:
    fix_e = "swap the encoder's A and B channels or set [firmware] encoder_direction = [-1]"
    fix_g = "swap the motor leads or negate the driver's current command"
    if enc == 0:
        e = {"key": "encoder_direction", "value": "not determined", "verdict": "n/a",
             "explain": "the handle was not moved by hand in the first phase"}
    else:
        e = {"key": "encoder_direction", "value": "as configured" if enc > 0 else "reversed",
             "verdict": "within" if enc > 0 else "MISS", **({} if enc > 0 else {"explain": fix_e})}
    g = {"key": "current_gain_sign", "value": "+" if gain > 0 else "reversed",
         "verdict": "within" if gain > 0 else "MISS"}
    if gain < 0:
        g["explain"] = fix_g if enc != 0 else f"the encoder or the current is reversed: {fix_e}, or {fix_g}"
    return [e, g]


def excitation_start(current_A: np.ndarray) -> int:
    """Index of the first row with a nonzero current (the end of the hand phase)."""
    nz = np.flatnonzero(np.any(np.asarray(current_A) != 0.0, axis=1))
    return int(nz[0]) if nz.size else len(current_A)


def cut_short(plan, log: Log, k0: int) -> str:
    """"" when the log runs through the routine's hold, chirp and rest after the current
    starts at row ``k0`` (``plan``: :class:`cad.identify.excitation.Plan` or ``Plan2``, phase
    lengths in s), else the clause that says it ends early (a log cut mid-chirp excites too
    little because it is cut, not because the device is stiff)."""
    want = 2 * plan.T_settle_s + plan.T_chirp_s
    got = float(log.t_s[-1] - log.t_s[k0]) if k0 < len(log.t_s) else 0.0
    if got >= 0.95 * want:
        return ""
    return (f"; the log ends {got:.2f} s after the current starts, the routine runs {want:.2f} s "
            "from there: it was cut short (log until the routine reports done)")


def _stopped(pred: Prediction, log: Log, q: np.ndarray, k0: int, enc: int) -> dict | None:
    """The result of a log whose routine stopped early (None when it ran through): after the
    hand phase with no current (a reversed encoder), or with the crank out of its range (the
    hold pushed it away: the current gain reversed when the current drove the motion)."""
    base = {"design": pred.name, "design_hash": pred.design_hash, "log_design_hash": log.design_hash,
            "hash_matches": log.design_hash == pred.design_hash, "rows": len(log.t_s), "figures": []}
    if k0 >= len(q) and enc < 0:
        sig = _signs(enc, 1)[:1]
        return {**base, "stopped": "after the hand phase: the hand move went towards -", "figures": sig,
                "misses": ["encoder_direction"]}
    out = np.flatnonzero((q[k0:] < pred.q_min_rad) | (q[k0:] > pred.q_max_rad))
    if out.size == 0 or len(q) - k0 < 10:
        return None
    end = k0 + int(out[0])
    # from rest at the hold's start: the motion the commanded torque alone would cause
    # (integrated twice) against the motion seen; friction only slows, never reverses it
    seg = slice(k0, end + 1)
    acc = pred.kt_Nm_per_A * log.current_A[seg, 0] / pred.D(q[seg])
    Te = float(np.median(np.diff(log.t_s[seg]))) if end > k0 else pred.Te_s
    moved_cmd = float(np.sum(np.cumsum(acc))) * Te**2
    sig = _signs(enc, 1 if moved_cmd * (q[end] - q[k0]) >= 0 else -1)
    return {**base, "stopped": f"at t = {log.t_s[end]:.3f} s: the crank left its range",
            "figures": sig, "misses": [r["key"] for r in sig if r["verdict"] == "MISS"]}


def identify(pred: Prediction, log: Log, path) -> tuple[dict, Fit | None]:
    """(result, fit) of a parsed log of the design of ``pred`` (fit None when the routine
    stopped early: ``stopped`` says why, the figures are the signs); FileDamaged (field LOG)
    when the log excites too little (module docstring of :mod:`cad.identify.regression`)."""
    q = pred.angles(log.counts[:, 0])
    k0 = excitation_start(log.current_A)
    enc = hand_direction(q[:k0], 5 * 2 * math.pi / pred.counts_per_rev) if k0 > 0 else 0
    if enc < 0:
        q = 2 * pred.zero_rad - q
    early = _stopped(pred, log, q, k0, enc)
    if early is not None:
        return early, None
    travel = int(np.ptp(log.counts[k0:, 0])) if k0 < len(q) else 0
    if travel < IDENT_MIN_TRAVEL_COUNTS:
        raise FileDamaged("LOG", path, f"has too little excitation: the crank travelled {travel} counts "
                                       f"under current (at least {IDENT_MIN_TRAVEL_COUNTS})"
                                       + cut_short(pred.plan, log, k0))
    try:
        f = fit(log.t_s[k0:], q[k0:], log.current_A[k0:, 0], pred.kt_Nm_per_A, pred.D, pred.dD,
                pred.g if pred.g_table is not None else None)
    except NotExcited as exc:
        raise FileDamaged("LOG", path, f"has too little excitation: {exc}"
                          + cut_short(pred.plan, log, k0)) from None
    figs = _figures(pred, f) + _signs(enc, f.current_sign)
    res = {
        "design": pred.name, "design_hash": pred.design_hash, "log_design_hash": log.design_hash,
        "hash_matches": log.design_hash == pred.design_hash, "rows": len(log.t_s),
        "excitation_from_s": float(log.t_s[min(k0, len(log.t_s) - 1)]),
        "delay_samples": f.delay_samples, "rms_residual_mNm": 1e3 * f.rms_residual_Nm,
        "condition": f.extra["condition"], "rows_fitted": f.extra["rows_used"],
        "estimates": {k: {"value": v, "sigma": f.sigma(k)} for k, v in f.theta.items()},
        "figures": figs, "misses": [r["key"] for r in figs if r["verdict"] == "MISS"],
        "friction_source": pred.friction_source,
        "model": "s Kt i(t - n Te) = c0 q'' + c1 (D q'' + D' q'^2 / 2) + Tc sign(q') + b q' [+ cg g(q)] + T0",
    }
    return res, f
