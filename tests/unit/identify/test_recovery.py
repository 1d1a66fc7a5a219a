"""Identification recovers perturbed parameters (issue 37 §4): a heavier device (mass +15 %),
twice the friction and a constant torque offset ("gravity offset"), from

* logs of the virtual bench (:mod:`cad.sim.bench`, reduced model, the firmware's excitation),
  checked against the bench's sidecar truth;
* logs of an independent simulation written here: eq (14)'s D(phi1) computed by hand from the
  linkage's velocity ratios (not the bench's M11 Jx^2 tables), RK4 integration, its own
  excitation (a multisine with its own PD hold, no hand phase), rounding encoder, 1 kHz.

Stated tolerances (the regression's bias on these logs, measured, with margin): apparent mass
2 %, Coulomb friction 10 %, viscous friction 25 %, offset 0.2 mN m; a reversed encoder and a
reversed current gain are diagnosed; a log that does not move is refused in one line.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from cad.errors import DesignError, FileDamaged
from cad.identify import logfile
from cad.sim import bench
from cad.sim.identify_device import identify

#: The independent simulation's hold stiffness (N m/rad): resonance ~7 Hz with the paper's H,
#: inside its multisine's band so that the inertia is excited. A stiff hold leaves the
#: accelerations small against the encoder's quantization noise and least squares then
#: underestimates the mass (errors in the regressor): measured 1.2 % low at 0.1, 2 % at 0.3,
#: 4 % at 0.6 N m/rad.
KP = 0.1
MASS_REL, FS_REL, FV_REL, OFFSET_NM = 0.02, 0.10, 0.25, 2e-4


def _log(pred, t, counts, cur):
    text = logfile.format_log(logfile.header_line("hoeken", pred.design_hash, "test", pred.Te_s), t, counts, cur)
    return logfile.parse_log(text, "t.csv", 1, pred.i_max_A)


def _fig(res, key):
    return next(r for r in res["figures"] if r["key"] == key)


def _check(res, pred, mass_g_of, Fs_N, Fv, offset_Nm):
    masses = [r for r in res["figures"] if r["key"].startswith("M11_g@")]
    assert len(masses) == 5
    for r in masses:
        true = mass_g_of(math.radians(r["phi1_deg"]))
        assert r["value"] == pytest.approx(true, rel=MASS_REL)
        assert r["verdict"] == "MISS" and "heavier" in r["explain"]  # +15 % is outside 10 %
    assert _fig(res, "Fs_N")["value"] == pytest.approx(Fs_N, rel=FS_REL)
    assert _fig(res, "Fv_N_s_per_m")["value"] == pytest.approx(Fv, rel=FV_REL)
    assert _fig(res, "offset_mNm")["value"] * 1e-3 == pytest.approx(offset_Nm, abs=OFFSET_NM)
    assert _fig(res, "current_gain_sign")["value"] == "+"


def test_bench_recovers_mass_friction_offset(pred):
    p = bench.parse_perturb(["mass=1.15", "friction=2", "offset_mNm=3"])
    t, c, i, tr = bench.simulate(pred, p, seed=4)
    assert tr["status"] == "done"
    res, fit = identify(pred, _log(pred, t, c, i), "t.csv")
    _check(res, pred, lambda q: float(bench.true_apparent_mass_g(pred, tr, q)), tr["Fs_N"],
           tr["Fv_N_s_per_m"], tr["offset_Nm"])
    assert _fig(res, "encoder_direction")["value"] == "as configured"
    # one period of transport + half a period of the zero-order hold
    assert res["delay_samples"] == pytest.approx(1.5, abs=0.3)
    assert 0 < _fig(res, "Fs_N")["sigma"] < FS_REL * tr["Fs_N"]


def test_bench_unperturbed_is_within_every_tolerance(pred):
    t, c, i, tr = bench.simulate(pred, bench.parse_perturb([]), seed=1)
    res, _ = identify(pred, _log(pred, t, c, i), "t.csv")
    assert res["misses"] == []


def test_bench_reversed_encoder_is_diagnosed(pred):
    t, c, i, tr = bench.simulate(pred, bench.parse_perturb(["encoder=-1"]), seed=0)
    assert tr["status"].startswith("stopped") and np.all(i == 0)  # the routine never closed the loop
    res, fit = identify(pred, _log(pred, t, c, i), "t.csv")
    assert fit is None and res["misses"] == ["encoder_direction"]
    assert "encoder_direction" in _fig(res, "encoder_direction")["explain"]


def test_bench_reversed_current_gain_is_diagnosed(pred):
    t, c, i, tr = bench.simulate(pred, bench.parse_perturb(["kt=-1"]), seed=0)
    assert "left its range" in tr["status"]
    res, _ = identify(pred, _log(pred, t, c, i), "t.csv")
    assert _fig(res, "current_gain_sign")["value"] == "reversed"
    assert _fig(res, "encoder_direction")["value"] == "as configured"


def test_bench_perturb_errors_name_the_item():
    for bad, why in (("mass", "KEY=VALUE"), ("knob=2", "KEY=VALUE"), ("mass=x", "not a number"),
                     ("mass=-1", "must be in"), ("encoder=0.5", "1 or -1"), ("delay=1.5", "whole"),
                     ("kt=0", "kt")):
        with pytest.raises(DesignError) as e:
            bench.parse_perturb([bad])
        assert e.value.field == "--perturb" and why in str(e.value)


def test_a_log_that_does_not_move_is_refused(pred):
    t = np.arange(4000) * pred.Te_s
    with pytest.raises(FileDamaged, match="too little excitation: the crank travelled 3 counts"):
        identify(pred, _log(pred, t, np.arange(4000) % 4, np.full(4000, 0.1)), "t.csv")


# ------------------------------------------------------------ the independent simulation
def _eq14_D(design, H, q):
    """Hoeken paper eq (14): D = H11 + 2 H12 cos(phi1 - phi2 - beta2) a2 + H22 a2^2 + H33 a3^2."""
    from cad.kinematics.fourbar import solve, velocity_ratios

    pose = solve(design.linkage, q)
    a2, a3 = velocity_ratios(design.linkage, pose)
    c = np.cos(pose.phi1_rad - pose.phi2_rad - H.beta2_rad)
    return H.H11_kg_m2 + 2 * H.H12_kg_m2 * c * a2 + H.H22_kg_m2 * a2**2 + H.H33_kg_m2 * a3**2


def _independent_log(design, H, pred, factor, Tc, b, T0):
    grid = np.linspace(design.phi1_min_rad - 0.05, design.phi1_max_rad + 0.05, 3001)
    Dg = factor * _eq14_D(design, H, grid)
    dDg = np.gradient(Dg, grid)
    kt, imax, qc = pred.kt_Nm_per_A, pred.i_max_A, 0.5 * (design.phi1_min_rad + design.phi1_max_rad)
    step_q = 2 * math.pi / pred.counts_per_rev

    def f(q, w, tau):
        D, dD = np.interp(q, grid, Dg), np.interp(q, grid, dDg)
        return w, (tau - 0.5 * dD * w * w - Tc * math.tanh(w / 0.01) - b * w - T0) / D

    Te, n, h = 1e-3, 6000, 2.5e-4
    freqs = (1.3, 2.9, 5.1, 8.7, 13.0)
    q, w, prev = qc, 0.0, 0
    counts, cur = np.zeros(n, np.int64), np.zeros(n)
    for k in range(n):
        c = round((q - pred.zero_rad) / step_q)
        qm = pred.zero_rad + c * step_q
        vm = 0.0 if k == 0 else (c - prev) * step_q / Te
        prev = c
        i = sum(0.25 * math.sin(2 * math.pi * fr * k * Te + fr) for fr in freqs)
        i -= (KP * (qm - qc) + 0.003 * vm) / kt
        counts[k], cur[k] = c, min(imax, max(-imax, i))
        tau = kt * cur[k]
        for _ in range(round(Te / h)):  # RK4
            k1 = f(q, w, tau)
            k2 = f(q + h / 2 * k1[0], w + h / 2 * k1[1], tau)
            k3 = f(q + h / 2 * k2[0], w + h / 2 * k2[1], tau)
            k4 = f(q + h * k3[0], w + h * k3[1], tau)
            q += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            w += h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
    return np.arange(n) * Te, counts, cur


def test_eq14_by_hand_equals_the_prediction_tables(hoeken, paper_H, pred):
    # linear interpolation on the 4001-point grid: h^2 D''/8 ~ 1e-8 relative
    q = np.linspace(hoeken.phi1_min_rad, hoeken.phi1_max_rad, 50)
    np.testing.assert_allclose(pred.D(q), _eq14_D(hoeken, paper_H, q), rtol=1e-6)


def test_independent_simulation_recovers_mass_friction_offset(hoeken, paper_H, pred):
    J = pred.J_mid
    Fs, Fv, T0 = 2 * pred.Fs_N, 2 * pred.Fv_N_s_per_m, 3e-3
    t, c, i = _independent_log(hoeken, paper_H, pred, 1.15, Fs * J, Fv * J * J, T0)
    res, _ = identify(pred, _log(pred, t, c, i), "t.csv")
    _check(res, pred, lambda q: 1.15 * float(pred.M11_g(q)), Fs, Fv, T0)
    assert _fig(res, "encoder_direction")["value"] == "not determined"  # no hand phase


def test_vertical_device_gravity_scale_is_recovered(hoeken, paper_H):
    """A vertical Hoeken ([firmware] plane = "vertical"): the gravity torque of the links'
    masses and COMs (cad.firmware.reference.gravity_torques) scaled by 1.3 on the bench comes
    back as the gravity load at the log's middle pose within 5 %, a MISS of its 15 % tolerance.
    Over the poses the routine visits this gravity torque is nearly constant (-7.4 .. -5.3 mN m
    over the whole range), so its scale and a constant offset are not separable: both say n/a
    and why, rather than a confident wrong number."""
    from cad.sim.identify_device import predict
    from tests.unit.identify.test_firmware_routine import _report

    d = hoeken.replace({"firmware.plane": "vertical"})
    rep = _report(paper_H)
    rep["links"] = {k: {"mass_kg": m, "com_mm": [c, 2.0, 0.0], "inertia_com_kg_m2": [[0] * 3, [0] * 3, [0, 0, 1e-6]]}
                    for k, m, c in (("crank", 0.02, 8.0), ("coupler", 0.03, 40.0), ("rocker", 0.015, 20.0))}
    vp = predict(d, paper_H, rep)
    assert vp.g_table is not None and np.ptp(vp.g_table) > 0
    t, c, i, tr = bench.simulate(vp, bench.parse_perturb(["gravity=1.3"]), seed=3)
    assert tr["status"] == "done"
    res, _ = identify(vp, _log(vp, t, c, i), "t.csv")
    load = _fig(res, "gravity_load_mNm")
    assert load["value"] == pytest.approx(1.3 * load["predicted"], rel=0.05) and load["verdict"] == "MISS"
    for key in ("gravity_scale", "offset_mNm"):
        assert _fig(res, key)["verdict"] == "n/a" and "not separable" in _fig(res, key)["explain"]


def test_no_friction_data_gives_no_friction_verdict(paper_H, monkeypatch):
    """A design without [stiffness] whose motor has no friction data (wall_inputs refuses):
    the prediction, the firmware's plan and the bench still work; the friction verdicts are
    n/a (nothing to compare with)."""
    from cad.design import load_design
    from cad.sim.identify_device import predict
    from tests.unit.identify.conftest import ROOT

    hoeken = load_design(ROOT / "designs" / "hoeken_light.toml")
    assert hoeken.stiffness is None

    def refuse(design):
        raise DesignError("stiffness", "no friction data")

    monkeypatch.setattr("cad.sim.identify_device.wall_inputs", refuse)  # its caller
    p = predict(hoeken, paper_H)
    assert p.Fs_N == 0.0 and p.Fv_N_s_per_m == 0.0 and "no friction prediction" in p.friction_source
    t, c, i, tr = bench.simulate(p, bench.parse_perturb([]), seed=0)
    res, _ = identify(p, _log(p, t, c, i), "t.csv")
    assert _fig(res, "Fs_N")["verdict"] == "n/a" and _fig(res, "Fv_N_s_per_m")["verdict"] == "n/a"
