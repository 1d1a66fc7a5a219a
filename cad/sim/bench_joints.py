"""The virtual bench's run of an n-motor device (issue 37): the firmware's routine
(:mod:`cad.identify.excitation2`) closed around a device model, logged as the firmware logs
it. Shared by the 5-bar (:mod:`cad.sim.bench_fivebar`) and the delta
(:mod:`cad.families.delta.identify`).

The log is what the firmware sees: counts floored in each encoder's true direction (the
configured one times ``encoder``), the commanded currents; the applied current is the
command ``delay`` periods late plus Gaussian noise. During the hand phase the device is
placed along the operator's hand move. A device with gravity runs the routine with the
firmware's gravity feed-forward at the angles read. Where the motor has no friction data
the bench's Coulomb friction is :data:`NOMINAL_TC_FRACTION` of the continuous torque (an
assumption of the bench, said in the sidecar).
"""

from __future__ import annotations

import math

import numpy as np

from cad.identify import excitation2

#: Bench Coulomb friction per motor when the prediction has none (fraction of Kt i_cont).
NOMINAL_TC_FRACTION = 0.03


def truth(pred, p: dict) -> dict:
    """The true parameters of the simulated device (the sidecar JSON), SI, and its apparent
    mass along each task axis at home."""
    n = pred.n_joints
    Tc0 = pred.Tc_Nm if pred.Tc_Nm is not None else NOMINAL_TC_FRACTION * pred.kt_Nm_per_A * pred.i_max_A
    Tc = Tc0 * p["friction"] * p["coulomb"]
    J = pred.rotor_kg_m2 * p["rotor"]
    M = pred.task_mass_kg(np.array([pred.q_home_rad]), p["mass"], (J,) * n)
    return {"perturb": p, "c_link": p["mass"], "J_kg_m2": [J] * n, "Tc_Nm": [Tc] * n,
            "Tc_source": "prediction" if pred.Tc_Nm is not None else
            f"bench assumption: {NOMINAL_TC_FRACTION:g} of the continuous torque",
            "b_Nm_s_per_rad": [0.0] * n, "offset_Nm": [1e-3 * p["offset_mNm"]] * n, "gravity_scale": p["gravity"],
            "kt_Nm_per_A": pred.kt_Nm_per_A * p["kt"], "encoder_direction": int(p["encoder"]),
            "current_gain_sign": 1 if p["kt"] > 0 else -1, "delay_samples": int(p["delay"]),
            "current_noise_A": p["noise"] * pred.i_max_A,
            **{f"M{a}{a}_g_home": 1e3 * float(M[k, k]) for k, a in enumerate(pred.axes)}}


STATUS_WORDS = {excitation2.DONE: "done", excitation2.RANGE: "stopped: a joint left its range (or the hold envelope)",
                excitation2.ENCODER: "stopped: a joint moved against the hand move"}


def run(pred, plant, tr: dict, qh: np.ndarray, ff, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(t_s (N,), counts (N, n), commanded currents (N, n) A) of one run of the routine on
    ``plant`` (``place(q)``, ``advance(tau, Te)``, ``q``) with the true parameters ``tr``,
    the hand move's joint angles ``qh`` (n_hand, n) and the firmware's gravity feed-forward
    ``ff(q) -> (n,)`` N m (None: no gravity); sets ``tr["status"]``."""
    rng = np.random.default_rng(seed)
    plan, n_j = pred.plan, pred.n_joints
    n, Te = plan.n_samples, plan.Te_s
    step = 2 * math.pi / pred.counts_per_rev
    sgn = [d * tr["encoder_direction"] for d in pred.direction]
    noise = rng.normal(0.0, tr["current_noise_A"], (n, n_j)).tolist()
    delay, ktt = tr["delay_samples"], tr["kt_Nm_per_A"]
    counts, cmd = np.zeros((n, n_j), np.int64), np.zeros((n, n_j))
    st = excitation2.State2()
    for k in range(n):
        if k < len(qh):
            plant.place(qh[k])
        c = [math.floor(sgn[j] * (plant.q[j] - pred.zero_rad[j]) / step) for j in range(n_j)]
        counts[k] = c
        q_read = pred.angles(np.array(c))[0]
        tg = ff(q_read) if ff is not None else None
        i, status = excitation2.step(plan, st, [float(x) for x in q_read], tg)
        cmd[k] = i
        if status != excitation2.RUNNING:
            n = k + 1
            break
        if k * Te >= plan.T_hand_s:
            late = cmd[k - delay] if k >= delay else (0.0,) * n_j
            plant.advance([ktt * (late[j] + noise[k][j]) for j in range(n_j)], Te)
    tr["status"] = STATUS_WORDS.get(st.status, "running")
    return np.arange(n) * Te, counts[:n], cmd[:n]
