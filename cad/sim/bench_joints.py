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
from cad.sim import identify_joints, mj
from cad.sim.bench import STOP_FRACTION
from cad.sim.wall import MJ_STEP_MAX_S

#: Bench Coulomb friction per motor when the prediction has none (fraction of Kt i_cont).
NOMINAL_TC_FRACTION = 0.03


def truth(pred, p: dict) -> dict:
    """The true parameters of the simulated device (the sidecar JSON), SI, and its apparent
    mass along each task axis at home. Per-motor values are lists; ``kt_Nm_per_A`` is a number
    when every motor has the same (a list otherwise)."""
    n = pred.n_joints
    kt, im = identify_joints.per_joint(pred.kt_Nm_per_A, n), identify_joints.per_joint(pred.i_max_A, n)
    Tc0 = (identify_joints.per_joint(pred.Tc_Nm, n) if pred.Tc_Nm is not None else
           [NOMINAL_TC_FRACTION * kt[j] * im[j] for j in range(n)])
    J = [x * p["rotor"] for x in identify_joints.per_joint(pred.rotor_kg_m2, n)]
    M = pred.task_mass_kg(np.array([pred.q_home_rad]), p["mass"], J)
    kt_true = [k * p["kt"] for k in kt]
    return {"perturb": p, "c_link": p["mass"], "J_kg_m2": J, "Tc_Nm": [t * p["friction"] * p["coulomb"] for t in Tc0],
            "Tc_source": "prediction" if pred.Tc_Nm is not None else
            f"bench assumption: {NOMINAL_TC_FRACTION:g} of the continuous torque",
            "b_Nm_s_per_rad": [0.0] * n, "offset_Nm": [1e-3 * p["offset_mNm"]] * n, "gravity_scale": p["gravity"],
            "kt_Nm_per_A": kt_true[0] if len(set(kt_true)) == 1 else kt_true, "encoder_direction": int(p["encoder"]),
            "current_gain_sign": 1 if p["kt"] > 0 else -1, "delay_samples": int(p["delay"]),
            "current_noise_A": p["noise"] * min(im),
            **{key.replace("@home", "_home"): scale * float(M[k, k])
               for k, (key, _, _, scale) in enumerate(identify_joints.mass_keys(pred))}}


def stop_range(plan) -> tuple[list[float], list[float]]:
    """(lo, hi) rad per joint of the bench's mechanical stops: the plan's range widened by
    :data:`cad.sim.bench.STOP_FRACTION` of it at each end."""
    span = [STOP_FRACTION * (h - lo) for lo, h in zip(plan.q_min_rad, plan.q_max_rad, strict=True)]
    return ([a - d for a, d in zip(plan.q_min_rad, span, strict=True)],
            [b + d for b, d in zip(plan.q_max_rad, span, strict=True)])


STATUS_WORDS = {excitation2.DONE: "done", excitation2.RANGE: "stopped: a joint left its range (or the hold envelope)",
                excitation2.ENCODER: "stopped: a joint moved against the hand move"}


def count_steps_rad(pred) -> list[float]:
    """Each joint's angle per encoder count (rad), as the firmware reads it (``pred.angles``:
    2 pi / (counts_per_rev n_j), n_j the joint's transmission ratio; 2 pi / counts_per_rev
    where the encoder is on the joint)."""
    n, motor = pred.n_joints, 2 * math.pi / pred.counts_per_rev
    d = pred.angles(np.eye(n)) - pred.angles(np.zeros((1, n)))
    return [motor if math.isclose(abs(float(d[j, j])), motor, rel_tol=1e-12) else abs(float(d[j, j]))
            for j in range(n)]


def run(pred, plant, tr: dict, qh: np.ndarray, ff, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(t_s (N,), counts (N, n), commanded currents (N, n) A) of one run of the routine on
    ``plant`` (``place(q)``, ``advance(tau, Te)``, ``q``) with the true parameters ``tr``,
    the hand move's joint angles ``qh`` (n_hand, n) and the firmware's gravity feed-forward
    ``ff(q) -> (n,)`` N m (None: no gravity); sets ``tr["status"]``."""
    rng = np.random.default_rng(seed)
    plan, n_j = pred.plan, pred.n_joints
    n, Te = plan.n_samples, plan.Te_s
    step = count_steps_rad(pred)
    sgn = [d * tr["encoder_direction"] for d in pred.direction]
    noise = rng.normal(0.0, tr["current_noise_A"], (n, n_j)).tolist()
    delay, ktt = tr["delay_samples"], identify_joints.per_joint(tr["kt_Nm_per_A"], n_j)
    counts, cmd = np.zeros((n, n_j), np.int64), np.zeros((n, n_j))
    st = excitation2.State2()
    for k in range(n):
        if k < len(qh):
            plant.place(qh[k])
        c = [math.floor(sgn[j] * (plant.q[j] - pred.zero_rad[j]) / step[j]) for j in range(n_j)]
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
            plant.advance([ktt[j] * (late[j] + noise[k][j]) for j in range(n_j)], Te)
    tr["status"] = STATUS_WORDS.get(st.status, "running")
    return np.arange(n) * Te, counts[:n], cmd[:n]


class MujocoPlant:
    """A build's MJCF in MuJoCo, driven by its motor joints :attr:`JOINTS` through the
    actuators :attr:`MOTORS` (a subclass names them): link masses and inertias scaled by
    ``c_link``, each motor joint's armature the true rotor inertia, Coulomb friction its
    ``frictionloss`` (hard: solref at 2 time steps; MuJoCo's default softness is 20 ms),
    viscous its ``damping``, the offsets constant applied torques, each motor driven with its
    joint torque over its MJCF ``gear`` (a capstan's n: MuJoCo applies gear x ctrl at the
    joint; ``tau_max_Nm`` is the joint's bound); gravity ``gravity_m_s2``
    (None: the model's own) times ``gravity_scale``; the loops re-closed after a placement
    (:func:`cad.sim.mj.close_loops`: hinge and ball joints); a motor joint beyond [lo, hi]
    is put back at the stop at rest (an inelastic stop), checked every MuJoCo step. Where the
    MJCF's hinge values are not the firmware's joint angles (the pen's), ``joint_map`` (s, c)
    gives q = s q_mjcf + c per motor joint."""

    JOINTS: tuple[str, ...] = ()
    MOTORS: tuple[str, ...] = ()

    def __init__(self, mjcf, tr: dict, lo, hi, tau_max_Nm: float, gravity_m_s2=None, joint_map=None):
        import mujoco

        self.mujoco = mujoco
        self.m, self.d = mj.load(mjcf)
        m = self.m
        self.iq = [mj.joint_qpos(m, j) for j in self.JOINTS]
        self.iv = [mj.joint_dof(m, j) for j in self.JOINTS]
        self.ia = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_ACTUATOR, a) for a in self.MOTORS]
        m.body_mass[1:] *= tr["c_link"]
        m.body_inertia[1:] *= tr["c_link"]
        for k, v in enumerate(self.iv):
            m.dof_armature[v] = tr["J_kg_m2"][k]
            m.dof_damping[v] = tr["b_Nm_s_per_rad"][k]
            m.dof_frictionloss[v] = tr["Tc_Nm"][k]
        g = np.asarray(m.opt.gravity if gravity_m_s2 is None else gravity_m_s2, float)
        m.opt.gravity[:] = g * tr["gravity_scale"]
        # a joint motor with a transmission (MJCF gear n: joint torque = n ctrl) is driven by the
        # joint torque / n; its range is the joint's over n
        self.gear = [mj.joint_torque_drive(m, a, tau_max_Nm) for a in self.ia]
        self.T0, self.lo, self.hi = tr["offset_Nm"], list(lo), list(hi)
        self.s, self.c = ([1.0] * len(self.iq), [0.0] * len(self.iq)) if joint_map is None else joint_map
        self._Te = None

    def _timestep(self, Te: float) -> int:
        nsub = max(1, math.ceil(Te / MJ_STEP_MAX_S))
        if self._Te != Te:
            self._Te = Te
            self.m.opt.timestep = Te / nsub
            for v in self.iv:
                self.m.dof_solref[v] = (2.0 * self.m.opt.timestep, 1.0)
                self.m.dof_solimp[v] = (0.9999, 0.9999, 0.001, 0.5, 2.0)
        return nsub

    @property
    def q(self) -> list[float]:
        """The motor joints' angles (rad)."""
        return [s * float(self.d.qpos[i]) + c for i, s, c in zip(self.iq, self.s, self.c, strict=True)]

    def place(self, q) -> None:
        """Put the motor joints at ``q`` at rest, the loops closed."""
        for i, v, s, c in zip(self.iq, q, self.s, self.c, strict=True):
            self.d.qpos[i] = (v - c) / s
        mj.close_loops(self.m, self.d, list(self.JOINTS))
        self.d.qvel[:] = 0.0
        self.mujoco.mj_forward(self.m, self.d)

    def advance(self, tau, Te: float) -> None:
        """One control period ``Te`` (s) with the joint torques ``tau`` (N m) applied."""
        nsub = self._timestep(Te)
        for a, t, sj, n in zip(self.ia, tau, self.s, self.gear, strict=True):  # tau q' = tau_mjcf q_mjcf'
            self.d.ctrl[a] = sj * t / n
        self.d.qfrc_applied[:] = 0.0
        for v, t0, sj in zip(self.iv, self.T0, self.s, strict=True):
            self.d.qfrc_applied[v] = -sj * t0
        n = len(self.iq)
        for _ in range(nsub):
            self.mujoco.mj_step(self.m, self.d)
            q = self.q
            if any(not self.lo[j] <= q[j] <= self.hi[j] for j in range(n)):  # an inelastic stop
                self.place([min(max(q[j], self.lo[j]), self.hi[j]) for j in range(n)])
