"""Virtual-wall (Z-width) simulation of a four-bar haptic display (issue 14).

A sampled-data impedance controller renders a one-sided wall on the device's own dynamics:

* every period ``Te`` (zero-order hold): the crank encoder angle is quantized to
  ``2 pi / counts_per_rev``, mapped through the kinematics to the path coordinate
  ``x_hat`` and the lever ``J_hat = dx/dphi1`` (path frame, m and m/rad); velocity by
  backward difference ``v_hat = (x_hat[k] - x_hat[k-1]) / Te``; inside the wall
  (``x_hat > x_wall``) the force ``F = -K (x_hat - x_wall) - B v_hat`` becomes the motor
  torque ``tau = J_hat F``, saturated at the motor's peak torque;
* the device: friction of eq (23) at the handle, ``-Fv xdot - Fs sign(xdot)`` (Hoeken paper,
  ``[stiffness]`` Fv, Fs), and a hand pushing into the wall with a constant force
  :data:`HAND_FORCE_N` (no hand impedance: the worst case, only the device's own
  friction dissipates).

Two device models:

* ``reduced`` -- 1-DOF along the path with kinetic energy ``1/2 M11(x) xdot^2``
  (M11 of eq 22, path frame), written in the crank angle:
  ``a(phi) = M11 Jx^2``, ``a phi'' + 1/2 a'(phi) phi'^2 = Q``; integrated with
  semi-implicit Euler, viscous and Coulomb friction implicit (stick when the Coulomb
  impulse can stop the motion), :data:`SUBSTEP_MAX_S` sub-steps. Vectorized over a batch
  of walls (K, B).
* ``mujoco`` -- the exported MJCF (closed loop, all links, armature): the motor torque is
  the actuator control, the friction is MuJoCo's implicit joint damping ``Fv J^2`` and
  ``frictionloss`` ``Fs |J|`` on the crank (J at the wall), the hand force
  ``J_site^T F`` at the handle site.

Run: the handle starts on the wall surface moving into it at ``v0`` (``[stiffness]
xdot_max_m_per_s``, the paper's "maximum velocity before instability") and is pushed by the
hand. **Stability criterion**: over the last :data:`WINDOW_S` of :data:`T_SIM_S`, the
peak-to-peak excursion of the true path coordinate stays below
:data:`AMPLITUDE_COUNTS` encoder steps Delta (Delta = |J| 2 pi / counts at the wall) --
i.e. the contact oscillation has decayed to the quantization level within
``T_SIM_S - WINDOW_S``. That criterion is not monotone in K: near the limit stable and
unstable stiffnesses interleave over ~15 % of K (the Hoeken: unstable probes from 12.1 kN/m,
stable ones up to 16.9 kN/m), so a bisection lands on whichever island its probes hit (a
0.2 % change of apparent mass moved it by 14 %). ``K_max`` of the reduced model is therefore
:func:`k_max_estimate`: the threshold that best separates stable from unstable walls over a
fine grid (:data:`cad.tolerances.K_GRID_STEP`) around a first bisection, with its bootstrap
sampling error stated. The mujoco model (one run per K) keeps the plain bisection
:func:`k_max` between :data:`K_LO_N_PER_M` and :data:`K_HI_N_PER_M`, to :data:`K_RTOL`.

Bounds reported beside it: eq (25) (Diolaiti et al., Hoeken paper) and the passivity
bound of Colgate and Schenkel, ``b > K T / 2 + |B|`` with b = Fv, i.e.
``K < 2 (Fv - |B|) / Te``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cad.dynamics.inertia import apparent_mass_matrix
from cad.errors import DesignError, FileDamaged
from cad.io import guard
from cad.kinematics.fourbar import jacobian_mm_per_rad, solve
from cad.kinematics.metrics import path_frame
from cad.sim import mj
from cad.tolerances import K_BOOTSTRAP, K_GRID_STEP, K_RTOL

#: Hand force pushing into the wall (N): a light touch.
HAND_FORCE_N = 1.0
#: Simulated time and the final window the stability criterion looks at (s).
T_SIM_S = 0.5
WINDOW_S = 0.1
#: Stable: peak-to-peak of x in the window below this many encoder steps Delta.
AMPLITUDE_COUNTS = 2.0
#: Largest plant sub-step of the reduced model (s): at the paper's Te its K_max is within
#: 1 % of the mujoco model at 20 us steps (``hapticad bench --only wall``); 50 us is 25 % off.
SUBSTEP_MAX_S = 2e-5
#: Largest MuJoCo time step of the mujoco model (s): the exported loop solref (0.2 ms)
#: needs <= 0.1 ms.
MJ_STEP_MAX_S = 1e-4
#: Bisection bracket of K_max (N/m; its relative tolerance: K_RTOL). The hand pushes the handle
#: F/K into the wall: below ~300 N/m that is several mm and the first bounce takes
#: longer than the simulated time to die out.
K_LO_N_PER_M = 300.0
K_HI_N_PER_M = 1e6
N_PROBE = 15
#: The fine grid of :func:`k_max_estimate` spans the first bisection's K divided and
#: multiplied by this ratio (widened while the split lands in its outer tenth): the Hoeken's
#: intermittent band is 12.1 .. 16.9 kN/m, a ratio of 1.4.
K_WINDOW_RATIO = 1.5
#: Stroke fraction where the wall sits (0 = P(phi1_min), 1 = P(phi1_max)).
WALL_AT = 0.5
#: Samples of the reduced model's tables over the crank range.
TABLE_SAMPLES = 20001
MODELS = ("reduced", "mujoco")


@dataclass(frozen=True)
class WallSpec:
    """Controller and device parameters (SI). ``counts_per_rev``: encoder steps per crank
    turn; ``tau_max_Nm``: peak torque at the crank (n x the motor's through a capstan);
    ``Fv``/``Fs``: eq (23) friction at the handle; ``v0``: initial velocity into the wall."""

    Te_s: float
    counts_per_rev: float
    Fv_N_s_per_m: float
    Fs_N: float
    tau_max_Nm: float
    v0_m_per_s: float
    hand_N: float = HAND_FORCE_N
    T_sim_s: float = T_SIM_S

    def __post_init__(self) -> None:
        for k, lo in (("Te_s", 1e-6), ("counts_per_rev", 1.0), ("tau_max_Nm", 1e-9),
                      ("v0_m_per_s", 0.0), ("Fv_N_s_per_m", 0.0), ("Fs_N", 0.0)):
            v = getattr(self, k)
            if not (math.isfinite(v) and v >= lo):
                raise DesignError(k, f"must be finite and >= {lo:g}, got {v!r}")
        check_sampling_period(self.Te_s, "--Te-s")


def check_sampling_period(Te_s: float, field: str) -> None:
    """Raise DesignError naming ``field`` when a sampling period is over 0.05 s (a wall
    simulated at 20 Hz or slower is no haptic loop: most likely milliseconds were given)."""
    if Te_s > 0.05:
        raise DesignError(field, f"must be <= 0.05 s (a sampling period in seconds; "
                                 f"ms given?), got {Te_s!r}")


@dataclass(frozen=True)
class DeviceTables:
    """Reduced-model tables over a uniform crank grid (rad): path x (m), Jx = dx/dphi1
    (m/rad), a = M11 Jx^2 (kg m^2) and da/dphi1; the wall's crank angle and x."""

    phi0: float
    h: float
    x: np.ndarray
    Jx: np.ndarray
    a: np.ndarray
    da: np.ndarray
    phi_wall: float
    x_wall: float
    origin_m: np.ndarray  # path frame origin P(phi1_min) in R0 (m)
    x_axis: np.ndarray  # path x axis in R0 (unit, 2-D)

    def locate(self, phi):
        """(index, fraction) of crank angles on the grid (clamped to the table)."""
        u = (np.asarray(phi, dtype=float) - self.phi0) / self.h
        i = np.clip(np.floor(u).astype(np.int64), 0, self.x.size - 2)
        return i, u - i

    @staticmethod
    def lerp(table: np.ndarray, i, f):
        return table[i] + f * (table[i + 1] - table[i])

    def at(self, table: np.ndarray, phi):
        """Table value at crank angles ``phi`` (linear interpolation)."""
        i, f = self.locate(phi)
        return self.lerp(table, i, f)

    @property
    def J_wall(self) -> float:
        return float(self.at(self.Jx, self.phi_wall))

    def delta_m(self, counts_per_rev: float) -> float:
        """Encoder step along the path at the wall (m)."""
        return abs(self.J_wall) * 2 * math.pi / counts_per_rev


def device_tables(design, H, samples: int = TABLE_SAMPLES) -> DeviceTables:
    """Tables of the reduced model from the linkage and H (eq 22, path frame)."""
    fb = design.linkage
    lo, hi = design.phi1_min_rad, design.phi1_max_rad
    phi = np.linspace(lo, hi, samples)
    pose = solve(fb, phi)
    fr = path_frame(fb, lo, hi)
    x = fr.to_path(pose.P_mm)[:, 0] * 1e-3
    Jx = fr.rotate(jacobian_mm_per_rad(fb, pose))[:, 0] * 1e-3
    M11 = apparent_mass_matrix(fb, pose, H, fr)[:, 0, 0]
    a = M11 * Jx**2
    h = (hi - lo) / (samples - 1)
    phi_w = lo + WALL_AT * (hi - lo)
    return DeviceTables(lo, h, x, Jx, a, np.gradient(a, h), phi_w, float(np.interp(phi_w, phi, x)),
                        np.asarray(fr.origin_mm) * 1e-3, np.asarray(fr.x_hat))


def _controller(tab: DeviceTables, spec: WallSpec, phi, x_prev, K, B):
    """One sample: quantized angle -> x_hat, v_hat -> saturated torque (arrays)."""
    q = 2 * math.pi / spec.counts_per_rev
    phq = np.floor(phi / q) * q
    xh = tab.at(tab.x, phq)
    Jh = tab.at(tab.Jx, phq)
    vh = (xh - x_prev) / spec.Te_s
    pen = xh - tab.x_wall
    F = np.where(pen > 0, -K * pen - B * vh, 0.0)
    return np.clip(Jh * F, -spec.tau_max_Nm, spec.tau_max_Nm), xh


def simulate_reduced(tab: DeviceTables, spec: WallSpec, K, B, control: bool = True,
                     friction: bool = True, hand: bool = True, phi0=None, omega0=None,
                     substep_s: float = SUBSTEP_MAX_S):
    """Reduced model, vectorized over walls K, B (broadcast, N/m and N s/m).

    Returns (t (n,) s, x (n, batch) m at the control instants, phi, omega final arrays).
    """
    K, B = np.broadcast_arrays(np.atleast_1d(np.asarray(K, float)), np.atleast_1d(np.asarray(B, float)))
    n_b = K.size
    n = int(round(spec.T_sim_s / spec.Te_s))
    nsub = max(1, math.ceil(spec.Te_s / substep_s))
    dt = spec.Te_s / nsub
    phi = np.full(n_b, tab.phi_wall if phi0 is None else phi0, dtype=float)
    om = np.full(n_b, (spec.v0_m_per_s / tab.J_wall) if omega0 is None else omega0, dtype=float)
    Fv = spec.Fv_N_s_per_m if friction else 0.0
    Fs = spec.Fs_N if friction else 0.0
    Fh = spec.hand_N if hand else 0.0
    xs = np.empty((n, n_b))
    x_prev = tab.at(tab.x, np.floor(phi / (2 * math.pi / spec.counts_per_rev)) * (2 * math.pi / spec.counts_per_rev))
    tau = np.zeros(n_b)
    for k in range(n):
        xs[k] = tab.at(tab.x, phi)
        if control:
            tau, x_prev = _controller(tab, spec, phi, x_prev, K, B)
        for _ in range(nsub):
            i, f = tab.locate(phi)
            a = tab.lerp(tab.a, i, f)
            J = tab.lerp(tab.Jx, i, f)
            da = tab.lerp(tab.da, i, f)
            Q = tau + J * Fh - 0.5 * da * om * om
            w = (om + dt * Q / a) / (1.0 + dt * Fv * J * J / a)  # viscous: implicit
            imp = dt * Fs * np.abs(J) / a  # Coulomb impulse (rad/s) over the sub-step
            om = np.where(np.abs(w) <= imp, 0.0, w - np.sign(w) * imp)
            phi = phi + dt * om
    return np.arange(n) * spec.Te_s, xs, phi, om


def amplitude_m(t, xs, window_s: float = WINDOW_S) -> np.ndarray:
    """Peak-to-peak of x over the final window (m), per batch column."""
    w = t >= t[-1] - window_s
    return xs[w].max(axis=0) - xs[w].min(axis=0)


class MujocoWall:
    """The mujoco device model: the exported MJCF of the design (module docstring)."""

    def __init__(self, mjcf_path, tab: DeviceTables, spec: WallSpec):
        import mujoco


        self.mujoco, self.mj = mujoco, mj
        self.tab, self.spec = tab, spec
        self._load(mjcf_path)
        self.nsub = max(1, math.ceil(spec.Te_s / MJ_STEP_MAX_S))
        self.m.opt.timestep = spec.Te_s / self.nsub
        # the crank's torque bound and commands through the MJCF gear (a capstan's n)
        self.gear = self.mj.joint_torque_drive(self.m, 0, spec.tau_max_Nm)
        self.xhat = np.array([*tab.x_axis, 0.0])

    def _load(self, mjcf_path) -> None:
        """The model and what the wall uses of it (crank joint, handle site, one actuator);
        a file that is not a regular file within the ``mjcf`` limit, not loadable or lacking
        one of those is :class:`cad.errors.FileDamaged` naming it, never a traceback."""
        guard.check_mjcf(mjcf_path, "MJCF")
        try:
            self.m, self.d = self.mj.load(mjcf_path)
            self.q = self.mj.joint_qpos(self.m, "crank")
            self.v = self.mj.joint_dof(self.m, "crank")
            self.site = self.m.site("handle").id
            if self.m.nu < 1:
                raise ValueError("no actuator")
        except (ValueError, KeyError, IndexError) as exc:
            first = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
            raise FileDamaged("MJCF", mjcf_path, f"is not the MJCF of a hapticad build (mujoco: "
                              f"{first}); rebuild it: hapticad build DESIGN --formats mjcf") from None

    def reset(self, phi: float, omega: float, friction: bool = True) -> None:
        """Crank at ``phi`` (loop closed by MuJoCo's constraint rows), crank rate ``omega``."""
        self.mujoco.mj_resetData(self.m, self.d)
        self.d.qpos[self.q] = phi
        self.mj.close_loops(self.m, self.d, ["crank"])
        self.d.qvel[:] = self.mj.null_basis(self.m, self.d, ["crank"])[:, 0] * omega
        J = self.tab.J_wall
        self.m.dof_damping[self.v] = self.spec.Fv_N_s_per_m * J * J if friction else 0.0
        self.m.dof_frictionloss[self.v] = self.spec.Fs_N * abs(J) if friction else 0.0
        # hard Coulomb: MuJoCo's default friction-loss softness (solref 0.02 s) lets the
        # crank creep and dissipates far less than eq (23) near zero velocity
        self.m.dof_solref[self.v] = (2.0 * self.m.opt.timestep, 1.0)
        self.m.dof_solimp[self.v] = (0.9999, 0.9999, 0.001, 0.5, 2.0)
        self.mujoco.mj_forward(self.m, self.d)

    def apply(self, tau_Nm: float) -> None:
        """Command the crank torque ``tau_Nm`` (N m at the crank): the actuator's control is
        tau / n through the MJCF gear n (:func:`cad.sim.mj.joint_torque_drive`)."""
        self.d.ctrl[0] = tau_Nm / self.gear

    def handle_x(self) -> float:
        """Path coordinate of the handle site (m)."""
        return float((self.d.site_xpos[self.site, :2] - self.tab.origin_m) @ self.tab.x_axis)

    def run(self, K: float, B: float, control: bool = True, friction: bool = True,
            hand: bool = True, phi0=None, omega0=None):
        """One wall; returns (t (n,) s, x (n,) m, kinetic energy (n,) J) at the control instants."""
        spec, tab = self.spec, self.tab
        self.reset(tab.phi_wall if phi0 is None else phi0,
                   spec.v0_m_per_s / tab.J_wall if omega0 is None else omega0, friction)
        n = int(round(spec.T_sim_s / spec.Te_s))
        xs, en = np.empty(n), np.empty(n)
        qstep = 2 * math.pi / spec.counts_per_rev
        x_prev = np.array([tab.at(tab.x, math.floor(self.d.qpos[self.q] / qstep) * qstep)])
        M = np.zeros((self.m.nv, self.m.nv))
        jp = np.zeros((3, self.m.nv))
        Ka, Ba = np.array([K], float), np.array([B], float)
        for k in range(n):
            self.mujoco.mj_forward(self.m, self.d)  # mj_step leaves positions of the step's start
            xs[k] = self.handle_x()
            self.mujoco.mj_fullM(self.m, self.d, M)
            en[k] = 0.5 * self.d.qvel @ M @ self.d.qvel
            if control:
                tau, x_prev = _controller(tab, spec, np.array([self.d.qpos[self.q]]), x_prev, Ka, Ba)
                self.apply(float(tau[0]))
            if hand:
                self.mujoco.mj_jacSite(self.m, self.d, jp, None, self.site)
                self.d.qfrc_applied[:] = jp.T @ (spec.hand_N * self.xhat)
            for _ in range(self.nsub):
                self.mujoco.mj_step(self.m, self.d)
        return np.arange(n) * spec.Te_s, xs, en


def k_max(stable_of, k_lo: float = K_LO_N_PER_M, k_hi: float = K_HI_N_PER_M, n_probe: int = 1,
          rtol: float = K_RTOL) -> dict:
    """Largest stable K by bisection in log K (``n_probe`` > 1: that many probes per round,
    evaluated in one call; 1 is plain bisection). ``stable_of(K array) -> bool array``.

    Returns ``K_max_N_per_m`` (the largest K found stable; None when ``k_lo`` is already
    unstable, ``k_hi`` when nothing up to ``k_hi`` is), ``K_unstable_N_per_m`` (the smallest
    K found unstable above it) and ``simulations``.
    """
    ends = stable_of(np.array([k_lo, k_hi]))
    sims = 2
    if not ends[0]:
        return {"K_max_N_per_m": None, "K_unstable_N_per_m": k_lo, "simulations": sims}
    if ends[1]:
        return {"K_max_N_per_m": k_hi, "K_unstable_N_per_m": None, "simulations": sims}
    lo, hi = k_lo, k_hi
    while hi / lo > 1.0 + rtol:
        probes = np.geomspace(lo, hi, n_probe + 2)[1:-1]
        ok = np.asarray(stable_of(probes), dtype=bool)
        sims += probes.size
        first_bad = int(np.argmin(ok)) if not ok.all() else probes.size
        if first_bad < probes.size:
            hi = float(probes[first_bad])
        lo = float(probes[first_bad - 1]) if first_bad > 0 else lo
    return {"K_max_N_per_m": lo, "K_unstable_N_per_m": hi, "simulations": sims}


def threshold_split(stable) -> tuple[int, int]:
    """Index ``i`` of the split of probes sorted by K (``stable``: bool array) into a stable
    side ``[:i]`` and an unstable side ``[i:]`` with the fewest exceptions (unstable probes
    below plus stable probes above); ties go to the lowest ``i``. Returns (i, exceptions)."""
    ok = np.asarray(stable, dtype=bool)
    bad_below = np.concatenate([[0], np.cumsum(~ok)])
    good_above = np.concatenate([np.cumsum(ok[::-1])[::-1], [0]])
    exc = bad_below + good_above
    i = int(np.argmin(exc))
    return i, int(exc[i])


def _split_K(K: np.ndarray, i: int) -> float:
    """Stiffness of split ``i`` (geometric middle of the probes on either side, N/m)."""
    return float(math.sqrt(K[i - 1] * K[i])) if 0 < i < K.size else float(K[min(i, K.size - 1)])


def _bootstrap_rel(K: np.ndarray, ok: np.ndarray, K_max: float, n_boot: int, seed: int) -> float:
    """Half-width of the 95 % bootstrap interval of the split stiffness, relative to K_max."""
    rng = np.random.default_rng(seed)
    out = np.empty(n_boot)
    for b in range(n_boot):
        idx = np.sort(rng.integers(0, K.size, K.size))
        out[b] = _split_K(K[idx], threshold_split(ok[idx])[0])
    lo, hi = np.percentile(out, [2.5, 97.5])
    return float(max(hi / K_max - 1.0, 1.0 - lo / K_max, 0.0))


def k_max_estimate(stable_of, k_lo: float = K_LO_N_PER_M, k_hi: float = K_HI_N_PER_M,
                   step: float = K_GRID_STEP, n_boot: int = K_BOOTSTRAP, seed: int = 0) -> dict:
    """K_max as a stability threshold with its sampling error (N/m; module docstring).

    A first bisection (:func:`k_max`, :data:`N_PROBE` probes per round) finds a stable K next
    to an unstable one; ``stable_of`` (``K array -> bool array``) then probes a geometric grid
    of relative step ``step`` over that K / :data:`K_WINDOW_RATIO` .. x :data:`K_WINDOW_RATIO`
    (widened while the split lands in its outer tenth), and ``K_max_N_per_m`` is the split of
    those probes with the fewest exceptions (:func:`threshold_split`): stable walls below it,
    unstable above, but for ``exceptions`` probes. ``sampling_error_rel`` is the 95 % bootstrap
    half-width of that split (``n_boot`` resamples of the probes, seeded) plus ``step``.
    ``K_first_unstable_N_per_m`` / ``K_last_stable_N_per_m``: the intermittent band's ends
    among the probes. Without a bracket (``k_lo`` unstable, ``k_hi`` stable) returns the
    :func:`k_max` answer with ``sampling_error_rel`` None.
    """
    first = k_max(stable_of, k_lo, k_hi, n_probe=N_PROBE)
    sims = first["simulations"]
    if first["K_max_N_per_m"] is None or first["K_unstable_N_per_m"] is None:
        return {**first, "sampling_error_rel": None, "K_first_unstable_N_per_m": first["K_unstable_N_per_m"],
                "K_last_stable_N_per_m": first["K_max_N_per_m"], "exceptions": 0, "probes": 0}
    lo = max(k_lo, first["K_max_N_per_m"] / K_WINDOW_RATIO)
    hi = min(k_hi, first["K_unstable_N_per_m"] * K_WINDOW_RATIO)
    for _ in range(6):
        K = np.exp(np.arange(math.log(lo), math.log(hi) + 0.5 * step, step))
        ok = np.asarray(stable_of(K), dtype=bool)
        sims += K.size
        i, exc = threshold_split(ok)
        edge = max(1, K.size // 10)
        if i < edge and lo > k_lo:
            lo = max(k_lo, lo / K_WINDOW_RATIO)
        elif i > K.size - edge and hi < k_hi:
            hi = min(k_hi, hi * K_WINDOW_RATIO)
        else:
            break
    K_max = _split_K(K, i)
    return {"K_max_N_per_m": K_max, "K_unstable_N_per_m": float(K[min(i, K.size - 1)]),
            "sampling_error_rel": _bootstrap_rel(K, ok, K_max, n_boot, seed) + step,
            "K_first_unstable_N_per_m": float(K[~ok].min()) if (~ok).any() else None,
            "K_last_stable_N_per_m": float(K[ok].max()) if ok.any() else None,
            "exceptions": exc, "probes": int(K.size), "simulations": sims}


def reduced_stable_of(tab: DeviceTables, spec: WallSpec, B: float, substep_s: float = SUBSTEP_MAX_S):
    """``stable_of`` of the reduced model (vectorized over K) for :func:`k_max`."""
    tol = AMPLITUDE_COUNTS * tab.delta_m(spec.counts_per_rev)

    def f(K):
        # an unstable wall may diverge to inf / NaN (no viscous friction): that is "unstable"
        with np.errstate(over="ignore", invalid="ignore"):
            t, xs, *_ = simulate_reduced(tab, spec, K, B, substep_s=substep_s)
            return np.nan_to_num(amplitude_m(t, xs), nan=np.inf) < tol

    return f


def mujoco_stable_of(plant: MujocoWall, B: float):
    """``stable_of`` of the mujoco model (one run per K) for :func:`k_max`."""
    tol = AMPLITUDE_COUNTS * plant.tab.delta_m(plant.spec.counts_per_rev)

    def f(K):
        out = []
        for k in np.atleast_1d(K):
            t, x, _ = plant.run(float(k), B)
            out.append(amplitude_m(t, x[:, None])[0] < tol)
        return np.array(out)

    return f


def passivity_K_max(Fv_N_s_per_m: float, B_N_s_per_m: float, Te_s: float) -> float:
    """Colgate and Schenkel: passive iff b > K T / 2 + |B| -> K < 2 (b - |B|) / T (N/m; 0 when
    |B| >= b)."""
    return max(0.0, 2.0 * (Fv_N_s_per_m - abs(B_N_s_per_m)) / Te_s)
