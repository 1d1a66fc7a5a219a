"""The 2-motor routine's reference (:mod:`cad.identify.excitation2`) against closed forms:
held exactly at home, the commanded currents are the two tapered chirps alone (motor 0
sweeping f0 -> f1, motor 1 f1 -> f0, written out here); the hand-move check, the hold
envelope and the range stop; the clamp."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cad.identify import excitation2 as ex


@pytest.fixture(scope="module")
def plan():
    return ex.plan2(1e-3, 0.04, 2.0, (0.0, -1.0), (1.2, 0.2), (0.6, -0.4), (1e-3, 8e-4), (1, -1), 4000)


def _phases(p, n):
    """(status of each period, currents) of angles held at home."""
    st = ex.State2()
    out = [ex.step(p, st, list(p.q_home_rad)) for _ in range(n)]
    return np.array([s for _, s in out]), np.array([i for i, _ in out])


def test_held_at_home_the_currents_are_the_two_chirps(plan):
    p = plan
    status, cur = _phases(p, p.n_samples)
    assert status[-1] == ex.DONE and np.all(status[:-1] == ex.RUNNING)
    t = np.arange(p.n_samples) * p.Te_s
    c = t - p.T_hand_s - p.T_settle_s
    on = (c >= 0) & (c < p.T_chirp_s)
    T, f0, f1 = p.T_chirp_s, p.f0_Hz, p.f1_Hz
    u = np.clip(np.minimum(np.minimum(1.0, c / p.T_taper_s), (T - c) / p.T_taper_s), 0, None)
    w = np.sin(0.5 * np.pi * u) ** 2
    up = p.amplitude_A * w * np.sin(2 * np.pi * (f0 * c + (f1 - f0) * c**2 / (2 * T)))
    down = p.amplitude_A * w * np.sin(2 * np.pi * (f1 * c + (f0 - f1) * c**2 / (2 * T)))
    np.testing.assert_allclose(cur[on, 0], up[on], atol=1e-12)
    np.testing.assert_allclose(cur[on, 1], down[on], atol=1e-12)
    assert np.all(cur[~on] == 0.0)  # hand phase, hold and rest at home: no current
    assert p.amplitude_A == pytest.approx(0.6 * 2.0)


def test_hold_gains_and_envelope(plan):
    p = plan
    for j, (lo, hi, h) in enumerate(zip(p.q_min_rad, p.q_max_rad, p.q_home_rad, strict=True)):
        half = min(h - lo, hi - h)
        assert p.kp_Nm_per_rad[j] == pytest.approx(p.amplitude_A * 0.04 / (0.35 * half))
        assert p.envelope_rad[j] == pytest.approx(ex.HOLD_ENVELOPE_FRACTION * half)
        # beyond the envelope the hold alone is at the clamp: (1 / 0.6) 0.35 = 0.58 < 0.6
        assert p.kp_Nm_per_rad[j] * p.envelope_rad[j] / 0.04 > p.i_max_A


def _run(p, path):
    st = ex.State2()
    return [ex.step(p, st, q) for q in path]


def test_a_joint_leaving_its_envelope_stops_the_routine(plan):
    p = plan
    n_hand = round(p.T_hand_s / p.Te_s)
    home = list(p.q_home_rad)
    out_of_env = [home[0] + 1.01 * p.envelope_rad[0], home[1]]  # still inside the range
    assert p.q_min_rad[0] <= out_of_env[0] <= p.q_max_rad[0]
    res = _run(p, [home] * (n_hand + 10) + [out_of_env] * 3)
    assert res[-3][1] == ex.RANGE and res[-1] == ([0.0, 0.0], ex.RANGE)


def test_a_hand_move_against_the_sign_stops_before_any_current(plan):
    p = plan
    n_hand = round(p.T_hand_s / p.Te_s)
    home = list(p.q_home_rad)
    d = 2 * p.hand_min_rad
    path = [[home[0], home[1] + d * math.sin(math.pi * k / n_hand)] for k in range(n_hand)]  # joint 1: wrong way
    res = _run(p, path + [home] * 5)
    assert all(i == [0.0, 0.0] for i, _ in res)
    assert res[n_hand][1] == ex.ENCODER


def test_currents_are_clamped(plan):
    p = plan
    n_hand = round(p.T_hand_s / p.Te_s)
    home = list(p.q_home_rad)
    # the hold fully ramped in, a joint far (but inside its envelope and range) from home
    far = [home[0] + 0.99 * p.envelope_rad[0], home[1]]
    res = _run(p, [home] * (n_hand + round(p.T_settle_s / p.Te_s) + 2) + [far] * 50)
    assert max(abs(i[0]) for i, _ in res) == p.i_max_A
