"""The virtual bench (issue 37): a built four-bar simulated with perturbed parameters, running
the firmware's identification routine (:mod:`cad.identify.excitation`), logged in the public
CSV format (:mod:`cad.identify.logfile`) with a sidecar JSON of the true parameters.

Device models: ``mujoco`` (the default where the build has an MJCF: the four-bars), the
exported model with every link and its closed loop (:class:`_MujocoPlant`); ``reduced``, the 1-DOF crank dynamics of the build (Hoeken paper eq 14, D(q) of
:func:`cad.sim.identify_device.predict`) with the true parameters
``a(q) = mass (D(q) - Jm) + rotor Jm``::

    a q'' + 1/2 a'(q) q'^2 = kt Kt i_applied - Tc tanh(q' / OMEGA_S) - b q' - gravity g(q) - T0

integrated by semi-implicit Euler in sub-steps of at most :data:`SUBSTEP_MAX_S`. The log is
what the firmware sees and writes: encoder counts quantized (floor) in the true encoder
direction, the commanded current; the applied current is the command ``delay`` periods late
plus Gaussian noise. During the hand phase the handle follows a prescribed hand move towards
the + end and back (the operator).

Perturbations (``--perturb KEY=VALUE``; factors on the prediction unless said): ``mass`` (every
link, not the rotor), ``rotor``, ``friction`` (Coulomb and viscous), ``coulomb``, ``viscous``,
``gravity``, ``kt`` (negative: current gain reversed), ``encoder`` (+1 or -1: reversed),
``offset_mNm`` (a constant torque added, mN m), ``delay`` (periods, 0..4), ``noise`` (current
noise, standard deviation as a fraction of the continuous current).
"""

from __future__ import annotations

import math

import numpy as np

from cad.errors import DesignError
from cad.identify import excitation
from cad.sim import mj
from cad.sim.wall import MJ_STEP_MAX_S

#: Default true perturbation of each key (no perturbation; one period of delay and 0.5 % noise:
#: what a real driver adds).
DEFAULTS = {"mass": 1.0, "rotor": 1.0, "friction": 1.0, "coulomb": 1.0, "viscous": 1.0,
            "gravity": 1.0, "kt": 1.0, "encoder": 1.0, "offset_mNm": 0.0, "delay": 1.0,
            "noise": 0.005}
#: Bounds of each key (inclusive) and why.
BOUNDS = {"mass": (0.1, 10.0), "rotor": (0.0, 10.0), "friction": (0.0, 20.0), "coulomb": (0.0, 20.0),
          "viscous": (0.0, 20.0), "gravity": (0.0, 10.0), "kt": (-2.0, 2.0), "encoder": (-1.0, 1.0),
          "offset_mNm": (-1e3, 1e3), "delay": (0.0, 4.0), "noise": (0.0, 0.2)}
#: Regularization of the Coulomb sign in the simulated device (rad/s).
OMEGA_S = 0.02
SUBSTEP_MAX_S = 1e-4
#: Mechanical stops of the simulated crank, as a fraction of its range beyond each end.
STOP_FRACTION = 0.05
#: The hand phase moves the crank by this fraction of its range towards the + end and back.
HAND_FRACTION = 0.25


def parse_perturb(items) -> dict[str, float]:
    """``{key: value}`` of ``KEY=VALUE`` strings over :data:`DEFAULTS`; DesignError naming
    ``--perturb``, the item and the reason."""
    out = dict(DEFAULTS)
    for item in items or ():
        key, sep, val = str(item).partition("=")
        key = key.strip()
        if not sep or key not in DEFAULTS:
            raise DesignError("--perturb", f"{item!r}: expected KEY=VALUE with KEY one of {', '.join(DEFAULTS)}")
        try:
            v = float(val)
        except ValueError:
            raise DesignError("--perturb", f"{item!r}: {val!r} is not a number") from None
        lo, hi = BOUNDS[key]
        if not (math.isfinite(v) and lo <= v <= hi):
            raise DesignError("--perturb", f"{item!r}: {key} must be in [{lo:g}, {hi:g}]")
        if key == "encoder" and v not in (1.0, -1.0):
            raise DesignError("--perturb", f"{item!r}: encoder must be 1 or -1 (reversed)")
        if key == "delay" and v != round(v):
            raise DesignError("--perturb", f"{item!r}: delay is a whole number of periods")
        if key == "kt" and abs(v) < 0.1:
            raise DesignError("--perturb", f"{item!r}: |kt| must be >= 0.1 (a motor that pushes)")
        out[key] = v
    return out


def truth(pred, p: dict) -> dict:
    """The true parameters of the simulated device (the sidecar JSON), SI and the handle's
    figures the identification should find."""
    Jm = pred.rotor_kg_m2
    J = pred.J_mid
    Tc = pred.Fs_N * J * p["friction"] * p["coulomb"]
    b = pred.Fv_N_s_per_m * J * J * p["friction"] * p["viscous"]
    return {"perturb": p, "Tc_Nm": Tc, "b_Nm_s_per_rad": b, "Fs_N": Tc / J, "Fv_N_s_per_m": b / J**2,
            "offset_Nm": 1e-3 * p["offset_mNm"], "gravity_scale": p["gravity"],
            "rotor_kg_m2": Jm * p["rotor"], "mass_factor": p["mass"], "kt_Nm_per_A": pred.kt_Nm_per_A * p["kt"],
            "encoder_direction": int(p["encoder"]), "current_gain_sign": 1 if p["kt"] > 0 else -1,
            "delay_samples": int(p["delay"]), "current_noise_A": p["noise"] * pred.i_max_A}


def true_apparent_mass_g(pred, tr: dict, q) -> np.ndarray:
    """The simulated device's apparent mass along the path at crank angles ``q`` (g): the
    prediction's M11 scaled as its crank inertia D is."""
    Jm = pred.rotor_kg_m2
    D = pred.D(q)
    return pred.M11_g(q) * (tr["mass_factor"] * (D - Jm) + tr["rotor_kg_m2"]) / D


class _Plant:
    """The reduced model (plain-float table look-ups: a fast scalar loop). Interface of both
    plants: ``place(q)`` (the hand holds the crank at q, at rest), ``advance(tau, Te)`` (one
    control period under the motor torque tau), ``q`` (the crank angle, rad)."""

    def __init__(self, pred, tr: dict, lo: float, hi: float):
        tab = pred.tab
        Jm = pred.rotor_kg_m2
        self.phi0, self.h, self.n = tab.phi0, tab.h, tab.x.size
        self.a = (tr["mass_factor"] * (pred.D_table - Jm) + tr["rotor_kg_m2"]).tolist()
        self.da = (tr["mass_factor"] * pred.dD_table).tolist()
        g = pred.g_table
        self.g = None if g is None else (tr["gravity_scale"] * g).tolist()
        self.Tc, self.b, self.T0 = tr["Tc_Nm"], tr["b_Nm_s_per_rad"], tr["offset_Nm"]
        self.lo, self.hi = lo, hi
        self.q, self.w = 0.5 * (lo + hi), 0.0

    def _at(self, table, q):
        u = (q - self.phi0) / self.h
        i = min(max(int(math.floor(u)), 0), self.n - 2)
        f = u - i
        return table[i] + f * (table[i + 1] - table[i])

    def accel(self, q: float, w: float, tau: float) -> float:
        load = 0.5 * self._at(self.da, q) * w * w + self.Tc * math.tanh(w / OMEGA_S) + self.b * w + self.T0
        if self.g is not None:
            load += self._at(self.g, q)
        return (tau - load) / self._at(self.a, q)

    def place(self, q: float) -> None:
        self.q, self.w = q, 0.0

    def advance(self, tau: float, Te: float) -> None:
        nsub = max(1, math.ceil(Te / SUBSTEP_MAX_S))
        dt = Te / nsub
        q, w = self.q, self.w
        for _ in range(nsub):  # semi-implicit Euler
            w += dt * self.accel(q, w, tau)
            q += dt * w
            if not self.lo <= q <= self.hi:  # an inelastic stop
                q, w = min(max(q, self.lo), self.hi), 0.0
        self.q, self.w = q, w


class _MujocoPlant:
    """The exported MJCF in MuJoCo (closed loop, every link, the rotor as the crank's armature):
    link masses and inertias scaled by ``mass``, the rotor's armature by ``rotor``, Coulomb
    friction as the crank's ``frictionloss`` (hard, as :class:`cad.sim.wall.MujocoWall`),
    viscous as its ``damping``, the offset as a constant applied torque, gravity scaled; the
    stops as in the reduced model. ``tau_max_Nm`` and the torques :meth:`advance` takes are the
    crank's (through a capstan's n: :func:`cad.sim.mj.joint_torque_drive`)."""

    def __init__(self, mjcf, tr: dict, lo: float, hi: float, tau_max_Nm: float):
        import mujoco


        self.mujoco, self.mj = mujoco, mj
        self.m, self.d = mj.load(mjcf)
        m = self.m
        self.iq, self.iv = mj.joint_qpos(m, "crank"), mj.joint_dof(m, "crank")
        m.body_mass[1:] *= tr["mass_factor"]
        m.body_inertia[1:] *= tr["mass_factor"]
        m.dof_armature[self.iv] = tr["rotor_kg_m2"]
        m.dof_damping[self.iv] = tr["b_Nm_s_per_rad"]
        m.dof_frictionloss[self.iv] = tr["Tc_Nm"]
        m.opt.gravity[:] = m.opt.gravity * tr["gravity_scale"]
        self.gear = mj.joint_torque_drive(m, 0, tau_max_Nm)  # a capstan's n: ctrl = tau / n
        self.T0, self.lo, self.hi = tr["offset_Nm"], lo, hi

    def _timestep(self, Te: float) -> int:
        nsub = max(1, math.ceil(Te / MJ_STEP_MAX_S))
        if self.m.opt.timestep != Te / nsub:
            self.m.opt.timestep = Te / nsub
            self.m.dof_solref[self.iv] = (2.0 * self.m.opt.timestep, 1.0)
            self.m.dof_solimp[self.iv] = (0.9999, 0.9999, 0.001, 0.5, 2.0)
        return nsub

    @property
    def q(self) -> float:
        return float(self.d.qpos[self.iq])

    def place(self, q: float) -> None:
        self.d.qpos[self.iq] = q
        self.mj.close_loops(self.m, self.d, ["crank"])
        self.d.qvel[:] = 0.0
        self.mujoco.mj_forward(self.m, self.d)

    def advance(self, tau: float, Te: float) -> None:
        nsub = self._timestep(Te)
        self.d.ctrl[0] = tau / self.gear
        self.d.qfrc_applied[:] = 0.0
        self.d.qfrc_applied[self.iv] = -self.T0
        for _ in range(nsub):
            self.mujoco.mj_step(self.m, self.d)
            if not self.lo <= self.q <= self.hi:  # an inelastic stop
                self.place(min(max(self.q, self.lo), self.hi))


def simulate(pred, p: dict, seed: int = 0, mjcf=None) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict]:
    """(t_s (N,), counts (N,), commanded current (N,) A, truth) of one run of the routine with
    perturbations ``p`` (:func:`parse_perturb`) on the reduced model, or on MuJoCo with the
    MJCF file ``mjcf``."""
    rng = np.random.default_rng(seed)
    tr = truth(pred, p)
    plan = pred.plan
    stop = STOP_FRACTION * (plan.q_max_rad - plan.q_min_rad)
    lo, hi = plan.q_min_rad - stop, plan.q_max_rad + stop
    plant = (_Plant(pred, tr, lo, hi) if mjcf is None else
             _MujocoPlant(mjcf, tr, lo, hi, 2 * abs(tr["kt_Nm_per_A"]) * pred.i_max_A))
    n, Te = plan.n_samples, plan.Te_s
    step = 2 * math.pi / pred.counts_per_rev
    sgn = pred.direction * tr["encoder_direction"]
    qc, amp = plan.q_center_rad, HAND_FRACTION * (plan.q_max_rad - plan.q_min_rad)
    noise = rng.normal(0.0, tr["current_noise_A"], n).tolist()
    delay, ktt = tr["delay_samples"], tr["kt_Nm_per_A"]
    counts, cmd = np.zeros(n, np.int64), np.zeros(n)
    st = excitation.State()
    for k in range(n):
        t = k * Te
        if t < plan.T_hand_s:  # the operator's hand move (prescribed)
            plant.place(qc + amp * math.sin(math.pi * t / plan.T_hand_s) ** 2)
        c = math.floor(sgn * (plant.q - pred.zero_rad) / step)
        counts[k] = c
        cmd[k], status = excitation.step(plan, st, float(pred.angles(c)))
        if status != excitation.RUNNING:  # the routine stopped: so does its log
            n = k + 1
            break
        if t >= plan.T_hand_s:
            plant.advance(ktt * ((cmd[k - delay] if k >= delay else 0.0) + noise[k]), Te)
    tr["status"] = {excitation.DONE: "done", excitation.RANGE: "stopped: the crank left its range",
                    excitation.ENCODER: "stopped: the hand move went towards -"}.get(st.status, "running")
    tr["model"] = "reduced" if mjcf is None else "mujoco"
    return np.arange(n) * Te, counts[:n], cmd[:n], tr
