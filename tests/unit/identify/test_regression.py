"""The pure least-squares fit (cad.identify.regression) against closed forms: a torque computed
exactly from the model for an analytic crank motion gives back the parameters; a motion that
does not excite the inertia is refused (NotExcited); the excitation reference is bounded."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cad.identify import excitation
from cad.identify.regression import NotExcited, fit, hand_direction


def D(q):
    return 5e-5 + 1e-5 * np.cos(q)


def dD(q):
    return -1e-5 * np.sin(q)


def _motion(Te=5e-4, T=6.0):
    t = np.arange(0.0, T, Te)
    q = 3.0 + 0.3 * np.sin(2 * np.pi * 1.7 * t) + 0.1 * np.sin(2 * np.pi * 6.1 * t + 1.0)
    v = 0.3 * 2 * np.pi * 1.7 * np.cos(2 * np.pi * 1.7 * t) + 0.1 * 2 * np.pi * 6.1 * np.cos(2 * np.pi * 6.1 * t + 1.0)
    a = (-0.3 * (2 * np.pi * 1.7) ** 2 * np.sin(2 * np.pi * 1.7 * t)
         - 0.1 * (2 * np.pi * 6.1) ** 2 * np.sin(2 * np.pi * 6.1 * t + 1.0))
    return t, q, v, a


def test_exact_model_torque_gives_back_its_parameters():
    t, q, v, a = _motion()
    kt, c1, Tc, b, T0 = 0.04, 1.2, 3e-3, 2e-4, -1e-3
    # Coulomb as a steep tanh (continuous, what the filter sees), everything else exact
    tau = c1 * (D(q) * a + 0.5 * dD(q) * v * v) + Tc * np.tanh(v / 1e-3) + b * v + T0
    f = fit(t, q, tau / kt, kt, D, dD)
    for qq in (2.8, 3.0, 3.3):
        assert f.theta["c0_kg_m2"] + f.theta["c1"] * D(qq) == pytest.approx(c1 * D(qq), rel=0.01)
    assert f.theta["Tc_Nm"] == pytest.approx(Tc, rel=0.01)
    assert f.theta["b_Nm_s_per_rad"] == pytest.approx(b, rel=0.02)
    assert f.theta["T0_Nm"] == pytest.approx(T0, abs=2e-5)
    # c0 and c1 alone are told apart only by D's +-20 % variation over the motion: each within
    # 3 of its own sigmas (the covariance is honest), their sum above within 1 %
    assert abs(f.theta["c1"] - c1) < 3 * f.sigma("c1") and abs(f.theta["c0_kg_m2"]) < 3 * f.sigma("c0_kg_m2")
    # no delay in the data; measured 0.14 periods: the filtered Coulomb term's rounding
    assert abs(f.delay_samples) < 0.25 and f.current_sign == 1


def test_reversed_gain_is_seen_and_the_estimates_come_back_positive():
    t, q, v, a = _motion()
    tau = D(q) * a + 0.5 * dD(q) * v * v + 2e-3 * np.tanh(v / 1e-3)
    f = fit(t, q, -tau / 0.04, 0.04, D, dD)
    assert f.current_sign == -1 and f.theta["Tc_Nm"] == pytest.approx(2e-3, rel=0.01)


def test_a_motion_at_constant_speed_is_not_excited():
    t = np.arange(0.0, 2.0, 1e-3)
    q = 2.5 + 0.2 * t  # no acceleration: the inertia columns are zero
    with pytest.raises(NotExcited, match="ill-conditioned"):
        fit(t, q, np.full_like(t, 0.05), 0.04, D, dD)


def test_hand_direction():
    step = 2 * math.pi / 4000
    assert hand_direction(np.array([0, 3, 9, 4, 0]) * step, 5 * step) == 1
    assert hand_direction(np.array([0, -3, -9, -4, 0]) * step, 5 * step) == -1
    assert hand_direction(np.array([0, 2, -3, 1]) * step, 5 * step) == 0


def test_reference_routine_is_bounded_and_stops_out_of_range():
    p = excitation.plan(3.3e-4, 0.0389, 2.63, 2.3, 3.77, 6e-5, 3837)
    rng = np.random.default_rng(0)
    q = np.concatenate([np.full(int(p.T_hand_s / p.Te_s), 3.0), 3.0 + 0.4 * rng.uniform(-1, 1, 40000)])
    amps = excitation.run_on_angles(p, q)
    assert np.max(np.abs(amps)) <= p.i_max_A and np.max(np.abs(amps)) == p.i_max_A  # clamped, reached
    st = excitation.State()
    out = [excitation.step(p, st, 3.0)[1] for _ in range(int(p.T_hand_s / p.Te_s) + 5)]
    assert out[-1] == excitation.RUNNING
    assert excitation.step(p, st, 4.0) == (0.0, excitation.RANGE)  # beyond q_max: stopped, 0 A
    assert excitation.step(p, st, 3.0) == (0.0, excitation.RANGE)  # and stays stopped
