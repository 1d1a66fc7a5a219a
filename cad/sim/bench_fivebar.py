"""The virtual bench of the 5-bar pantograph (issue 37): the built device simulated with
perturbed parameters, running the firmware's 2-motor identification routine
(:mod:`cad.identify.excitation2`), logged in the public CSV format with a sidecar JSON of the
true parameters (the four-bar's bench: :mod:`cad.sim.bench`, whose perturbation keys this
one takes).

Device models: ``mujoco`` (the default), the build's exported MJCF (:class:`MujocoPlant5`);
``reduced``, the 5-bar's rigid-body dynamics in joint space (the tree of
:mod:`cad.identify.joint2` closed by virtual work), evaluated in closed form per step::

    (W^T M_tree W + diag(J)) q'' = s Kt i_applied - W^T (M_tree [0; psi''_0] + c_tree)
                                   - Tc tanh(q' / OMEGA_S) - b q' - cg g(q) - T0

with the solids' tree parameters scaled by ``mass`` and the rotors' inertia J by ``rotor``,
integrated by semi-implicit Euler in sub-steps of at most :data:`cad.sim.bench.SUBSTEP_MAX_S`.
Gravity (a vertical device) is the prediction's table (bilinear on a joint grid) times
``gravity``. The log is what the firmware sees: counts floored in each encoder's true
direction, the commanded currents; the applied current is the command ``delay`` periods late
plus Gaussian noise. A vertical device's routine adds the predicted gravity torques at the
angles read (the firmware's ``hc_gravity_torques``; here from a :class:`GravityTable`, within
~1e-5 N m of them). During the hand phase the handle follows a hand move along +y of
:data:`cad.sim.bench.HAND_FRACTION` of the workspace height and back. Where the motor has no
friction data the bench's Coulomb friction is :data:`cad.sim.bench_joints.NOMINAL_TC_FRACTION` of the continuous
torque (an assumption of the bench, said in the sidecar).
"""

from __future__ import annotations

import math

import numpy as np

from cad.sim import bench_joints
from cad.sim.bench import HAND_FRACTION, OMEGA_S, STOP_FRACTION, SUBSTEP_MAX_S
from cad.sim.identify_fivebar import jacobian

#: Joint grid of the gravity table (points per joint).
GRAVITY_GRID = 41


class GravityTable:
    """The prediction's gravity torques (N m) times ``scale`` on a :data:`GRAVITY_GRID` joint
    grid over [lo, hi] (rad), bilinear in between (plain floats: a fast scalar loop)."""

    def __init__(self, pred, lo, hi, scale: float = 1.0):
        self.q0 = [float(x) for x in lo]
        self.dq = [(h - low) / (GRAVITY_GRID - 1) for low, h in zip(lo, hi, strict=True)]
        a, b = np.meshgrid(*(np.linspace(low, h, GRAVITY_GRID) for low, h in zip(lo, hi, strict=True)), indexing="ij")
        tab = scale * pred.gravity(np.column_stack([a.ravel(), b.ravel()]))
        self.t = [tab[:, j].reshape(GRAVITY_GRID, GRAVITY_GRID).tolist() for j in range(2)]

    def __call__(self, q) -> tuple[float, float]:
        u = [(q[j] - self.q0[j]) / self.dq[j] for j in range(2)]
        i = [min(max(int(math.floor(u[j])), 0), GRAVITY_GRID - 2) for j in range(2)]
        f = [u[j] - i[j] for j in range(2)]
        out = []
        for t in self.t:
            a, b = t[i[0]][i[1]], t[i[0] + 1][i[1]]
            c, d = t[i[0]][i[1] + 1], t[i[0] + 1][i[1] + 1]
            out.append((1 - f[0]) * ((1 - f[1]) * a + f[1] * c) + f[0] * ((1 - f[1]) * b + f[1] * d))
        return out[0], out[1]


class Plant5:
    """The reduced 5-bar (plain floats: a fast scalar loop). ``place(q)`` (the hand holds
    the joints at q, at rest), ``advance(tau (2,), Te)``, ``q`` (2,) rad."""

    def __init__(self, pred, tr: dict, lo, hi):
        g = pred.geom
        self.g = g
        self.beta = (tr["c_link"] * np.asarray(pred.beta_links)).tolist()
        self.J = list(tr["J_kg_m2"])
        self.Tc, self.b, self.T0 = list(tr["Tc_Nm"]), list(tr["b_Nm_s_per_rad"]), list(tr["offset_Nm"])
        self.lo, self.hi = list(lo), list(hi)
        self.q, self.w = list(pred.q_home_rad), [0.0, 0.0]
        self.grav = GravityTable(pred, lo, hi, tr["gravity_scale"]) if pred.vertical else None

    def accel(self, q, w, tau) -> tuple[float, float]:
        g, (IpL, IdL, mxL, myL, IpR, IdR, mxR, myR) = self.g, self.beta
        c1, s1, c2, s2 = math.cos(q[0]), math.sin(q[0]), math.cos(q[1]), math.sin(q[1])
        C1x, C1y = g.b1[0] + g.l1 * c1, g.b1[1] + g.l1 * s1
        dx, dy = g.b2[0] + g.l2 * c2 - C1x, g.b2[1] + g.l2 * s2 - C1y
        r = math.hypot(dx, dy)
        a = (g.l3 * g.l3 - g.l4 * g.l4 + r * r) / (2 * r)
        h = math.sqrt(max(g.l3 * g.l3 - a * a, 0.0))
        ux, uy = dx / r, dy / r
        Ex, Ey = C1x + a * ux - g.assembly * h * uy, C1y + a * uy + g.assembly * h * ux
        p1 = math.atan2(Ey - C1y, Ex - C1x)
        p2 = math.atan2(Ey - (C1y + dy), Ex - (C1x + dx))
        cp1, sp1, cp2, sp2 = math.cos(p1), math.sin(p1), math.cos(p2), math.sin(p2)
        # A psi' = R q':  A = [l3 n1, -l4 n2], R = [-l1 m1, l2 m2]
        A11, A12, A21, A22 = -g.l3 * sp1, g.l4 * sp2, g.l3 * cp1, -g.l4 * cp2
        det = A11 * A22 - A12 * A21
        R11, R12, R21, R22 = g.l1 * s1, -g.l2 * s2, -g.l1 * c1, g.l2 * c2
        P11, P12 = (A22 * R11 - A12 * R21) / det, (A22 * R12 - A12 * R22) / det
        P21, P22 = (-A21 * R11 + A11 * R21) / det, (-A21 * R12 + A11 * R22) / det
        v1, v2 = P11 * w[0] + P12 * w[1], P21 * w[0] + P22 * w[1]
        bx = g.l3 * cp1 * v1 * v1 - g.l4 * cp2 * v2 * v2 - g.l2 * c2 * w[1] ** 2 + g.l1 * c1 * w[0] ** 2
        by = g.l3 * sp1 * v1 * v1 - g.l4 * sp2 * v2 * v2 - g.l2 * s2 * w[1] ** 2 + g.l1 * s1 * w[0] ** 2
        e1, e2 = (A22 * bx - A12 * by) / det, (-A21 * bx + A11 * by) / det  # psi''_0
        dL, dR = p1 - q[0], p2 - q[1]
        KL, KR = mxL * math.cos(dL) - myL * math.sin(dL), mxR * math.cos(dR) - myR * math.sin(dR)
        kL, kR = -mxL * math.sin(dL) - myL * math.cos(dL), -mxR * math.sin(dR) - myR * math.cos(dR)
        hL, hR = g.l1 * KL, g.l2 * KR
        # tree torques of psi''_0 and the velocity terms (rows q1, q2, psi1, psi2)
        t1, t2 = hL * e1 + g.l1 * kL * v1 * v1, hR * e2 + g.l2 * kR * v2 * v2
        t3, t4 = IdL * e1 - g.l1 * kL * w[0] ** 2, IdR * e2 - g.l2 * kR * w[1] ** 2
        h1, h2 = t1 + P11 * t3 + P21 * t4, t2 + P12 * t3 + P22 * t4
        # W^T M_tree W, W = [I; P]; M_tree left [[IpL, hL], [hL, IdL]] on (q1, psi1), right alike
        M11 = IpL + 2 * hL * P11 + IdL * P11 * P11 + IdR * P21 * P21 + self.J[0]
        M22 = IpR + 2 * hR * P22 + IdL * P12 * P12 + IdR * P22 * P22 + self.J[1]
        M12 = hL * P12 + hR * P21 + IdL * P11 * P12 + IdR * P21 * P22
        f = [tau[j] - self.Tc[j] * math.tanh(w[j] / OMEGA_S) - self.b[j] * w[j] - self.T0[j] for j in range(2)]
        if self.grav is not None:
            gv = self.grav(q)
            f = [f[0] - gv[0], f[1] - gv[1]]
        f1, f2 = f[0] - h1, f[1] - h2
        dm = M11 * M22 - M12 * M12
        return (M22 * f1 - M12 * f2) / dm, (M11 * f2 - M12 * f1) / dm

    def place(self, q) -> None:
        self.q, self.w = [float(q[0]), float(q[1])], [0.0, 0.0]

    def advance(self, tau, Te: float) -> None:
        nsub = max(1, math.ceil(Te / SUBSTEP_MAX_S))
        dt = Te / nsub
        q, w = self.q, self.w
        for _ in range(nsub):  # semi-implicit Euler
            a0, a1 = self.accel(q, w, tau)
            w = [w[0] + dt * a0, w[1] + dt * a1]
            q = [q[0] + dt * w[0], q[1] + dt * w[1]]
            for j in range(2):
                if not self.lo[j] <= q[j] <= self.hi[j]:  # an inelastic stop
                    q[j], w[j] = min(max(q[j], self.lo[j]), self.hi[j]), 0.0
        self.q, self.w = q, w


class MujocoPlant5(bench_joints.MujocoPlant):
    """The exported MJCF in MuJoCo (every link, the closed loop at E, the handle on its pin,
    the rotors as the motor joints' armature; :class:`cad.sim.bench_joints.MujocoPlant`),
    gravity in the device plane for a vertical device (``[firmware] gravity_direction``;
    the MJCF's own -z gravity is normal to the plane: no joint torque)."""

    JOINTS = ("q_left", "q_right")
    MOTORS = ("motor_left", "motor_right")

    def __init__(self, mjcf, pred, tr: dict, lo, hi, tau_max_Nm: float):
        g = pred.spec.gravity_m_s2
        super().__init__(mjcf, tr, lo, hi, tau_max_Nm, (0.0, 0.0, 0.0) if g is None else (g[0], g[1], 0.0))


def hand_path(pred, half_y_m: float, n: int) -> np.ndarray:
    """Joint angles (n, 2) of the operator's hand move: E from home along +y by HAND_FRACTION
    of the workspace height (``2 half_y_m``) and back, sin^2 in time; followed from home in
    the design's working modes by dq = (dE/dq)^-1 dE in small steps."""
    s = np.sin(np.pi * np.arange(n) / n) ** 2
    dy = np.diff(s * HAND_FRACTION * 2 * half_y_m, prepend=0.0)
    q = np.empty((n, 2))
    cur = np.array(pred.q_home_rad, float)
    for k in range(n):
        cur = cur + np.linalg.solve(jacobian(pred.geom, cur[None, :])[0], np.array([0.0, dy[k]]))
        q[k] = cur
    return q


def simulate(pred, p: dict, seed: int = 0, half_y_m: float = 0.05,
             mjcf=None) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict]:
    """(t_s (N,), counts (N, 2), commanded currents (N, 2) A, truth) of one run of the
    2-motor routine with perturbations ``p`` (:func:`cad.sim.bench.parse_perturb`) on the
    reduced 5-bar, or on MuJoCo with the MJCF file ``mjcf``; ``half_y_m`` half the workspace
    height (the hand move)."""
    tr = bench_joints.truth(pred, p)
    plan = pred.plan
    rng_j = [STOP_FRACTION * (h - lo) for lo, h in zip(plan.q_min_rad, plan.q_max_rad, strict=True)]
    lo = [a - d for a, d in zip(plan.q_min_rad, rng_j, strict=True)]
    hi = [b + d for b, d in zip(plan.q_max_rad, rng_j, strict=True)]
    plant = (Plant5(pred, tr, lo, hi) if mjcf is None else
             MujocoPlant5(mjcf, pred, tr, lo, hi, 2 * abs(tr["kt_Nm_per_A"]) * pred.i_max_A))
    qh = hand_path(pred, half_y_m, int(math.ceil(plan.T_hand_s / plan.Te_s)))
    ff = GravityTable(pred, lo, hi) if plan.gravity_ff else None  # the firmware's feed-forward
    t, counts, cmd = bench_joints.run(pred, plant, tr, qh, ff, seed)
    tr["model"] = "reduced" if mjcf is None else "mujoco"
    return t, counts, cmd, tr
