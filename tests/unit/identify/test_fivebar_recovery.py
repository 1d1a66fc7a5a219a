"""Identification of the 5-bar pantograph recovers perturbed parameters (issue 37 §4): a
heavier device (every link and the handle +15 %), twice the motors' Coulomb friction and
constant torque offsets ("gravity offset"; and gravity itself on a vertical device), from

* logs of the virtual bench (:mod:`cad.sim.bench_fivebar`: the firmware's 2-motor excitation,
  the joint-space dynamics in closed form), checked against its sidecar truth;
* logs of an independent simulation written here: the joint-space mass matrix of the
  library's twist maps (:func:`cad.kinematics.fivebar.mass_matrix_kg`, J^T M J) tabulated on a
  joint grid, the Coriolis terms from its Christoffel symbols (grid differences), gravity
  from the COM heights written out here (central differences of the potential), RK4
  integration, its own excitation (a multisine per motor with its own PD hold and gravity
  feed-forward, no hand phase), a rounding encoder.

Stated tolerances (the regression's bias on these logs, measured, with margin): apparent
mass at home 2 % on bench logs; on the independent logs 1 % with a 40 000-count encoder
(measured +0.1 %) and 4 % with the design's 4 000 counts (measured -2.2 % along x, -3.3 %
along y: the encoder's quantization noise in the accelerations biases least squares low,
errors in the regressors; the bench's chirp, with larger accelerations, -0.8 %); Coulomb
friction 10 %, offsets and gravity loads 0.3 mN m. Reversed encoders and reversed current
gains are diagnosed.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from cad.identify import logfile
from cad.kinematics import fivebar as fb5
from cad.sim import bench, bench_fivebar
from cad.sim.identify_fivebar import identify, predict

ROOT = Path(__file__).resolve().parents[3]
MASS_REL, TC_REL, OFFSET_NM = 0.02, 0.10, 3e-4
MASS_REL_FINE, MASS_REL_COARSE = 0.01, 0.04
#: The independent simulation's hold (N m/rad, N m s/rad) and multisine amplitude per sine (A).
KP, KD, AMP_A = 0.15, 0.004, 0.3


def _log(pred, t, counts, cur):
    text = logfile.format_log(logfile.header_line("p", pred.design_hash, "test", pred.Te_s), t, counts, cur)
    return logfile.parse_log(text, "t.csv", 2, pred.i_max_A)


def _fig(res, key):
    return next(r for r in res["figures"] if r["key"] == key)


def _check(res, M_true_g, Tc_true, T0_true, mass_rel=MASS_REL):
    for k, ax in enumerate("xy"):
        r = _fig(res, f"M{ax}{ax}_g@home")
        assert r["value"] == pytest.approx(M_true_g[k], rel=mass_rel)
        assert r["verdict"] == "MISS" and "heavier" in r["explain"]  # +15 % is outside 10 %
        assert 0 < r["sigma"] < mass_rel * r["value"]
    for j in range(2):
        assert _fig(res, f"Tc{j}_mNm")["value"] * 1e-3 == pytest.approx(Tc_true[j], rel=TC_REL)
        assert _fig(res, f"offset{j}_mNm")["value"] * 1e-3 == pytest.approx(T0_true[j], abs=OFFSET_NM)
        assert _fig(res, f"current_gain_sign_{j}")["value"] == "+"


# ------------------------------------------------------------------ the virtual bench
def test_bench_recovers_mass_friction_offset(panto_pred):
    pred = panto_pred
    t, c, i, tr = bench_fivebar.simulate(pred, bench.parse_perturb(["mass=1.15", "friction=2", "offset_mNm=3"]), 4)
    assert tr["status"] == "done"
    res, fit = identify(pred, _log(pred, t, c, i), "t.csv")
    _check(res, (tr["Mxx_g_home"], tr["Myy_g_home"]), tr["Tc_Nm"], tr["offset_Nm"])
    assert [_fig(res, f"Tc{j}_mNm")["verdict"] for j in range(2)] == ["MISS", "MISS"]  # x2 is outside 50 %
    for j in range(2):
        assert _fig(res, f"encoder_direction_{j}")["value"] == "as configured"
    # one period of transport + half a period of the zero-order hold
    assert res["delay_samples"] == pytest.approx(1.5, abs=0.3)


def test_bench_unperturbed_is_within_every_tolerance(panto_pred):
    t, c, i, tr = bench_fivebar.simulate(panto_pred, bench.parse_perturb([]), 1)
    res, _ = identify(panto_pred, _log(panto_pred, t, c, i), "t.csv")
    assert res["misses"] == []


def test_a_log_with_one_motors_current_negated_names_that_motor(panto_pred):
    """A logger that writes motor 1's current with the opposite sign (the routine itself ran
    fine): the fit's sign search names current_gain_sign_1 reversed, motor 0 as configured,
    and still finds the mass."""
    pred = panto_pred
    t, c, i, tr = bench_fivebar.simulate(pred, bench.parse_perturb(["mass=1.15"]), 5)
    res, _ = identify(pred, _log(pred, t, c, i * np.array([1.0, -1.0])), "t.csv")
    assert _fig(res, "current_gain_sign_0")["value"] == "+"
    assert _fig(res, "current_gain_sign_1")["value"] == "reversed"
    assert res["misses"] == ["Mxx_g@home", "Myy_g@home", "current_gain_sign_1"]
    assert _fig(res, "Mxx_g@home")["value"] == pytest.approx(tr["Mxx_g_home"], rel=MASS_REL)


def test_bench_excitation_stays_within_limits(panto_pred):
    p = panto_pred.plan
    t, c, i, tr = bench_fivebar.simulate(panto_pred, bench.parse_perturb(["mass=1.15"]), 0)
    q = panto_pred.angles(c)
    assert np.max(np.abs(i)) <= p.i_max_A
    assert np.all(q >= np.array(p.q_min_rad)) and np.all(q <= np.array(p.q_max_rad))
    # both joints move, each over more than a fifth of its range
    assert np.all(np.ptp(q, axis=0) > (np.array(p.q_max_rad) - p.q_min_rad) / 5)


def test_bench_reversed_encoder_is_diagnosed(panto_pred):
    t, c, i, tr = bench_fivebar.simulate(panto_pred, bench.parse_perturb(["encoder=-1"]), 0)
    assert tr["status"].startswith("stopped") and np.all(i == 0)
    res, fit = identify(panto_pred, _log(panto_pred, t, c, i), "t.csv")
    assert fit is None and "hand" in res["stopped"]
    assert res["misses"] == ["encoder_direction_0", "encoder_direction_1"]


def test_bench_reversed_current_gain_is_diagnosed(panto_pred):
    t, c, i, tr = bench_fivebar.simulate(panto_pred, bench.parse_perturb(["kt=-1"]), 0)
    assert tr["status"].startswith("stopped: a joint left its range")
    res, fit = identify(panto_pred, _log(panto_pred, t, c, i), "t.csv")
    assert fit is None and "left its range" in res["stopped"]
    gains = [_fig(res, f"current_gain_sign_{j}") for j in range(2)]
    assert any(g["value"] == "reversed" for g in gains)
    assert all(g["value"] == "reversed" for g in gains if g["verdict"] != "n/a")


def test_bench_vertical_recovers_gravity_load(vertical):
    """A vertical 5-bar on the bench (the routine adds the gravity torques to its hold):
    heavier links, more gravity and an offset; the gravity loads within 0.3 mN m of the
    sidecar truth, the mass within 2 %."""
    d, rep, pred = vertical
    assert pred.plan.gravity_ff
    t, c, i, tr = bench_fivebar.simulate(pred, bench.parse_perturb(["mass=1.15", "gravity=1.15", "offset_mNm=3"]), 1)
    assert tr["status"] == "done"
    res, fit = identify(pred, _log(pred, t, c, i), "t.csv")
    for k, ax in enumerate("xy"):
        assert _fig(res, f"M{ax}{ax}_g@home")["value"] == pytest.approx((tr["Mxx_g_home"], tr["Myy_g_home"])[k],
                                                                         rel=MASS_REL)
    q_med = np.median(fit.q[fit.mask.any(axis=1)], axis=0)
    true_load = tr["gravity_scale"] * pred.gravity(q_med[None, :])[0] + np.array(tr["offset_Nm"])
    for j in range(2):
        assert _fig(res, f"gravity_load{j}_mNm")["value"] * 1e-3 == pytest.approx(true_load[j], abs=OFFSET_NM)


def test_bench_vertical_reversed_gain_is_not_blamed_on_gravity(vertical):
    """A vertical device whose currents are reversed falls and is pushed out of its envelope:
    the stopped log names a reversed gain and no gain as configured (its weight alone, which
    the right current would have held, is not mistaken for the cause)."""
    d, rep, pred = vertical
    t, c, i, tr = bench_fivebar.simulate(pred, bench.parse_perturb(["kt=-1"]), 0)
    assert tr["status"].startswith("stopped: a joint left")
    res, fit = identify(pred, _log(pred, t, c, i), "t.csv")
    assert fit is None
    gains = [_fig(res, f"current_gain_sign_{j}")["value"] for j in range(2)]
    assert "reversed" in gains


# ------------------------------------------------------------------ an independent simulation
class _Independent:
    """The 5-bar of ``pred`` with its links and handle ``mass`` times the prediction, written
    here from the library's mass matrix (module docstring)."""

    N = 41

    def __init__(self, design, report, pred, mass: float, gravity_m_s2):
        self.pred, self.g = pred, gravity_m_s2
        fb = design.mechanism
        b = report["bodies"]
        self.b = {k: (mass * v["mass_kg"], np.array(v["com_mm"][:2]) * 1e-3, mass * v["inertia_com_kg_m2"][2][2])
                  for k, v in b.items()}
        lm = {k: fb5.LinkMass(m, tuple(c), i) for k, (m, c, i) in self.b.items()}
        fm = fb5.FiveBarMass(lm["proximal_left"], lm["proximal_right"], lm["distal_left"], lm["distal_right"],
                             pred.rotor_kg_m2)
        home = np.array(pred.q_home_rad)
        half = 0.5 * (np.array(pred.q_max_rad) - pred.q_min_rad)
        self.lo, self.h = home - 0.5 * half, half / (self.N - 1)
        axes = [self.lo[j] + self.h[j] * np.arange(self.N) for j in range(2)]
        Q = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 2)
        pose = fb5.fk(fb, Q, int(pred.spec.params["assembly"]))
        assert np.all(pose.status == fb5.STATUS_OK)
        Mt = fb5.mass_matrix_kg(fb, pose.E_mm, fm) + self.b["handle"][0] * np.eye(2)
        Jx = np.linalg.inv(fb5.jacobian_rad_per_m(fb, pose.E_mm)[0])
        M = np.einsum("nki,nkl,nlj->nij", Jx, Mt, Jx).reshape(self.N, self.N, 2, 2)
        dM = np.stack(np.gradient(M, self.h[0], self.h[1], axis=(0, 1)), axis=-1)  # dM_ij/dq_k
        self.M = M
        self.G = 0.5 * (dM + np.einsum("abikj->abijk", dM) - np.einsum("abjki->abijk", dM))
        self.V = None if gravity_m_s2 is None else self._potential(fb, pose).reshape(self.N, self.N)
        if self.V is not None:
            self.dV = np.stack(np.gradient(self.V, self.h[0], self.h[1]), axis=-1)

    def _potential(self, fb, pose):
        """-sum m g . r_G over the links and the handle, COMs placed by hand in each link frame."""
        g = np.asarray(self.g)

        def place(origin, angle, com):
            c, s = np.cos(angle), np.sin(angle)
            return origin + np.column_stack([c * com[0] - s * com[1], s * com[0] + c * com[1]])

        V = np.zeros(len(pose.E_mm))
        for side, B, C in ((0, fb.base_left_mm, pose.C_left_mm), (1, fb.base_right_mm, pose.C_right_mm)):
            s = ("left", "right")[side]
            mp, cp, _ = self.b[f"proximal_{s}"]
            md, cd, _ = self.b[f"distal_{s}"]
            d = pose.E_mm - C
            V -= mp * place(np.asarray(B) * 1e-3, pose.q_rad[:, side], cp) @ g
            V -= md * place(C * 1e-3, np.arctan2(d[:, 1], d[:, 0]), cd) @ g
        V -= self.b["handle"][0] * (pose.E_mm * 1e-3) @ g
        return V

    def _at(self, T, q):
        u = (np.asarray(q) - self.lo) / self.h
        i = np.clip(np.floor(u).astype(int), 0, self.N - 2)
        f = u - i
        return ((1 - f[0]) * ((1 - f[1]) * T[i[0], i[1]] + f[1] * T[i[0], i[1] + 1])
                + f[0] * ((1 - f[1]) * T[i[0] + 1, i[1]] + f[1] * T[i[0] + 1, i[1] + 1]))

    def gravity(self, q):
        return np.zeros(2) if self.V is None else self._at(self.dV, q)

    def accel(self, q, w, tau):
        c = self._at(self.G, q) @ w @ w
        (a, b), (_, d) = self._at(self.M, q)
        r = tau - c - self.gravity(q)
        det = a * d - b * b
        return np.array([d * r[0] - b * r[1], a * r[1] - b * r[0]]) / det


def _independent_log(design, report, pred, *, mass, Tc, T0, gravity=None, seed=0, T_s=10.0, amp_A=None):
    """(t, counts (N, 2), currents (N, 2), true task mass at home (g)) at 1 kHz."""
    rng = np.random.default_rng(seed)
    dev = _Independent(design, report, pred, mass, gravity)
    Te, n = 1e-3, int(T_s / 1e-3)
    kt, step = pred.kt_Nm_per_A, 2 * math.pi / pred.counts_per_rev
    home = np.array(pred.q_home_rad)
    freqs = (np.array([0.7, 1.9, 3.7, 6.1, 9.7]), np.array([1.1, 2.9, 4.9, 7.9, 12.1]))
    phase = rng.uniform(0, 2 * np.pi, (2, 5))
    kp, kd = KP, KD
    q, w = home.copy(), np.zeros(2)
    counts, cur = np.zeros((n, 2), np.int64), np.zeros((n, 2))
    prev = np.zeros(2)
    Tc, T0 = np.asarray(Tc), np.asarray(T0)

    def f(q, w, tau):
        return dev.accel(q, w, tau - Tc * np.tanh(w / 0.05) - T0)

    q_prev = home.copy()
    for k in range(n):
        t = k * Te
        counts[k] = np.round((q - np.asarray(pred.zero_rad)) / step)
        qr = np.asarray(pred.zero_rad) + counts[k] * step
        v = (qr - q_prev) / Te
        q_prev = qr
        ff = dev.gravity(qr) / kt
        ms = np.array([(AMP_A if amp_A is None else amp_A) * np.sum(np.sin(2 * np.pi * freqs[j] * t + phase[j])) for j in range(2)])
        cur[k] = np.clip((-kp * (qr - home) - kd * v) / kt + ff + ms, -pred.i_max_A, pred.i_max_A)
        tau = kt * (prev + rng.normal(0, 0.005 * pred.i_max_A, 2))  # one period of delay, noise
        prev = cur[k]
        for _ in range(1):  # RK4, one step a period
            dt = Te
            k1 = (w, f(q, w, tau))
            k2 = (w + dt / 2 * k1[1], f(q + dt / 2 * k1[0], w + dt / 2 * k1[1], tau))
            k3 = (w + dt / 2 * k2[1], f(q + dt / 2 * k2[0], w + dt / 2 * k2[1], tau))
            k4 = (w + dt * k3[1], f(q + dt * k3[0], w + dt * k3[1], tau))
            q = q + dt / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            w = w + dt / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
    Mq = dev._at(dev.M, home)
    Jx = np.linalg.inv(fb5.jacobian_rad_per_m(design.mechanism, fb5.fk(
        design.mechanism, home[None, :], int(pred.spec.params["assembly"])).E_mm)[0][0])
    Jq = np.linalg.inv(Jx)
    return np.arange(n) * Te, counts, cur, 1e3 * np.diag(Jq.T @ Mq @ Jq)


def test_independent_simulation_horizontal(panto, panto_pred, bars):
    """A 40 000-count encoder (a 10 000-line encoder read x4): the model's own accuracy."""
    pred = dataclasses.replace(panto_pred, counts_per_rev=40000)
    Tc, T0 = (2 * pred.Tc_Nm, 2 * pred.Tc_Nm), (3e-3, -2e-3)
    t, c, i, M_true = _independent_log(panto, bars(panto), pred, mass=1.15, Tc=Tc, T0=T0)
    res, _ = identify(pred, _log(pred, t, c, i), "t.csv")
    _check(res, M_true, Tc, T0, MASS_REL_FINE)
    assert [_fig(res, f"encoder_direction_{j}")["value"] for j in range(2)] == ["not determined"] * 2


@pytest.fixture(scope="module")
def vertical(tmp_path_factory, bars):
    from cad.design import load_design

    text = (ROOT / "designs" / "pantograph.toml").read_text() + '\n[firmware]\nplane = "vertical"\n'
    p = tmp_path_factory.mktemp("v") / "vertical.toml"
    p.write_text(text)
    d = load_design(p)
    # printed bars and a 5 g knob: the hold carries a third of the continuous torque against
    # gravity (the aluminium bars of the horizontal tests weigh 73 % of it)
    rep = bars(d, handle_kg=0.005, rho_kg_per_m=0.08)
    return d, rep, predict(d, rep)


def test_independent_simulation_vertical_recovers_gravity(vertical):
    """A vertical device 15 % heavier with constant offsets: the gravity load and offset at
    each motor (their sum: what the log determines near one pose) within 0.3 mN m of the
    truth, which the identification's own gravity model does not know (COM heights written
    here); the scale and the offsets alone are flagged not separable, never a false verdict."""
    d, rep, pred = vertical
    assert pred.vertical
    Tc, T0 = (2 * pred.Tc_Nm, 2 * pred.Tc_Nm), (3e-3, -2e-3)
    t, c, i, M_true = _independent_log(d, rep, pred, mass=1.15, Tc=Tc, T0=T0, gravity=pred.spec.gravity_m_s2, seed=2,
                                       amp_A=0.2)
    res, fit = identify(pred, _log(pred, t, c, i), "t.csv")
    for k, ax in enumerate("xy"):
        assert _fig(res, f"M{ax}{ax}_g@home")["value"] == pytest.approx(M_true[k], rel=MASS_REL_COARSE)
    dev = _Independent(d, rep, pred, 1.15, pred.spec.gravity_m_s2)
    q_med = np.median(fit.q[fit.mask.any(axis=1)], axis=0)
    true_load = dev.gravity(q_med) + np.array(T0)
    for j in range(2):
        r = _fig(res, f"gravity_load{j}_mNm")
        assert r["value"] * 1e-3 == pytest.approx(true_load[j], abs=OFFSET_NM)
        assert abs(r["value"]) > 20  # a real load: ~30 mN m
        assert _fig(res, f"Tc{j}_mNm")["value"] * 1e-3 == pytest.approx(Tc[j], rel=TC_REL)
        off = _fig(res, f"offset{j}_mNm")
        assert off["verdict"] == "n/a" and "not separable" in off["explain"]
    assert _fig(res, "gravity_scale")["verdict"] == "n/a"
