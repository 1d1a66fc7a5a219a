"""The excitation the generated firmware runs on a device of n >= 2 motors (the 5-bar
pantograph, the delta), and its Python reference (the C routine ``hc_ident_step`` of
:mod:`cad.firmware.identify2_c` computes the same numbers, tests/unit/identify).

The phases and the safety rules of the 1-motor routine (:mod:`cad.identify.excitation`),
per joint, at the control period ``Te_s`` (time t = k Te from the first sample):

1. ``hand`` (0 <= t < T_hand): current 0; the operator moves the handle by hand along the
   plan's ``hand_move`` (a planar device: away from the motors, +y; the delta: straight up,
   +z) and back: each joint's largest excursion from its first angle shows its encoder
   direction (``hand_sign``: the sign each joint must show, from the prediction's Jacobian at
   home);
2. ``hold`` (T_settle): a PD hold of each joint to its home angle, gains ramped from 0 to 1,
   plus, on a vertical device (``gravity_ff``), the gravity torques at the angles read
   (``hc_gravity_torques`` of the device code; not ramped: the device must not fall when the
   operator lets go);
3. ``chirp`` (T_chirp): the hold plus a tapered chirp per motor, amplitude ``A``; motor j
   sweeps by :data:`SWEEPS` ``[j % 4]``: up (f0 -> f1), down (f1 -> f0), up then down, down
   then up (linear in time, each leg half the chirp), so that the motors drive at different
   frequencies nearly all the time (the joint-space mass matrix is separable: a common
   excitation would move the device along one direction of joint space only); every chirp
   term is off while any joint is outside its safe range (the position-hold envelope);
4. ``rest`` (T_settle): the hold alone, then 0 A and done.

Stops (0 A on every motor from then on): ``ENCODER`` when at the end of the hand phase a
joint moved at least ``hand_min_rad`` against its ``hand_sign``; ``RANGE`` when during the
hold or the chirp a joint leaves its range or the hold envelope, ``envelope_rad`` from home
(:data:`HOLD_ENVELOPE_FRACTION` of its smaller half-range): the hold alone reaches the current
clamp at (1 / AMPLITUDE_FRACTION) TRAVEL_FRACTION = 0.58 of it, so a joint beyond is not held
(a reversed current gain pushes it there; the chirp moves a joint at most ~0.45 of it, its
static deflection 0.35 times the resonant gain 1 / (2 ZETA)). Every current is clamped at
+-``i_max_A`` (each joints own where the motors differ).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from cad.identify.excitation import (
    AMPLITUDE_FRACTION,
    DONE,
    ENCODER,
    F0_HZ,
    F1_HZ,
    FC_HZ,
    HAND_MIN_COUNTS,
    RANGE,
    RUNNING,
    SAFE_FRACTION,
    T_CHIRP_S,
    T_HAND_S,
    T_SETTLE_S,
    T_TAPER_S,
    TRAVEL_FRACTION,
    ZETA,
    RoutineTiming,
)

#: Sweep of motor j: ``SWEEPS[j % 4]`` = (starts at f1 instead of f0, turns back at half time).
SWEEPS = ((False, False), (True, False), (False, True), (True, True))
#: The hand move of a planar device (the delta's: "straight up (+z)").
HAND_MOVE_PLANAR = "straight away from the motors (+y)"

#: A joint's chirp reaches at least :data:`BAND_COUNTS` encoder counts of amplitude (an
#: inertia-dominated joint: A Kt / (J (2 pi f)^2)) up to 1/BAND_MARGIN of the top frequency;
#: the top frequency is lowered from F1_HZ only for a joint that would not (the pen's waists,
#: which swing both arms: 5 Hz instead of 15 Hz; every other bundled device keeps 15 Hz).
BAND_COUNTS, BAND_MARGIN = 10, 2.5

#: The hold envelope as a fraction of a joint's smaller half-range about home (module docstring).
HOLD_ENVELOPE_FRACTION = 0.6

__all__ = ["DONE", "ENCODER", "RANGE", "RUNNING", "Plan2", "State2", "plan2", "run_on_angles", "step"]


@dataclass(frozen=True)
class Plan2(RoutineTiming):
    """Every constant of the n-motor routine (SI; tuples per joint): the C code is written
    from these. ``q_home_rad``: the hold's target; ``hand_sign``: +1/-1, the sign of each
    joint's move when the handle goes +y."""

    Te_s: float
    kt_Nm_per_A: float
    i_max_A: float
    q_min_rad: tuple[float, ...]
    q_max_rad: tuple[float, ...]
    q_home_rad: tuple[float, ...]
    amplitude_A: float
    kp_Nm_per_rad: tuple[float, ...]
    kd_Nm_s_per_rad: tuple[float, ...]
    hand_sign: tuple[int, ...]
    envelope_rad: tuple[float, ...]
    gravity_ff: bool = False
    T_hand_s: float = T_HAND_S
    T_settle_s: float = T_SETTLE_S
    T_chirp_s: float = T_CHIRP_S
    f0_Hz: float = F0_HZ
    f1_Hz: float = F1_HZ
    fc_Hz: float = FC_HZ
    T_taper_s: float = T_TAPER_S
    safe_fraction: float = SAFE_FRACTION
    hand_min_rad: float = 0.0
    hand_move: str = HAND_MOVE_PLANAR
    #: per joint where the motors differ (the pen: RE 40 waists, RE 35 shoulders); empty: every
    #: joint's are ``kt_Nm_per_A`` and ``i_max_A``
    kt_joint_Nm_per_A: tuple[float, ...] = ()
    i_max_joint_A: tuple[float, ...] = ()
    amplitude_joint_A: tuple[float, ...] = ()

    @property
    def n_joints(self) -> int:
        return len(self.q_min_rad)

    def kt(self, j: int) -> float:
        """Joint j's torque per ampere (N m/A)."""
        return self.kt_joint_Nm_per_A[j] if self.kt_joint_Nm_per_A else self.kt_Nm_per_A

    def i_max(self, j: int) -> float:
        """Joint j's current clamp (A): its motor's continuous current."""
        return self.i_max_joint_A[j] if self.i_max_joint_A else self.i_max_A

    def amplitude(self, j: int) -> float:
        """Joint j's chirp amplitude (A)."""
        return self.amplitude_joint_A[j] if self.amplitude_joint_A else self.amplitude_A

    @property
    def safe_rad(self) -> tuple[tuple[float, float], ...]:
        """(lo, hi) of each joint: the range less ``safe_fraction`` of it at each end."""
        out = []
        for lo, hi in zip(self.q_min_rad, self.q_max_rad, strict=True):
            d = self.safe_fraction * (hi - lo)
            out.append((lo + d, hi - d))
        return tuple(out)


def plan2(Te_s: float, kt_Nm_per_A, i_max_A, q_min_rad, q_max_rad, q_home_rad,
          inertia_kg_m2, hand_sign, counts_per_rev: int, gravity_ff: bool = False,
          gravity_A=0.0, hand_move: str = HAND_MOVE_PLANAR) -> Plan2:
    """The :class:`Plan2` of an n-motor device: control period (s), torque constant (N m/A),
    continuous current (A) (each a number, or one per joint where the motors differ), joint
    ranges and home (rad, per joint), the predicted joint inertias at home (kg m^2), the
    hand-move signs, encoder counts per turn, whether the hold adds the gravity torques, the
    gravity current at home ``gravity_A`` (A; a number or per joint) and the hand move's words:
    each motor's chirp amplitude is AMPLITUDE_FRACTION of the current gravity leaves it
    (raises ValueError when gravity alone takes a motor's continuous current). Hold stiffness:
    the chirp amplitude deflects a joint by ``TRAVEL_FRACTION`` of its smaller half-range
    about home; damping ratio ``ZETA``; the top frequency F1_HZ, lower where a joint would move
    less than :data:`BAND_COUNTS` counts (:data:`BAND_MARGIN`)."""
    n = len(q_min_rad)
    kt, im, gA = (np.broadcast_to(np.asarray(x, float), (n,)) for x in (kt_Nm_per_A, i_max_A, gravity_A))
    if np.any(gA >= im):
        j = int(np.argmax(gA - im))
        raise ValueError(f"holding the device against gravity takes {gA[j]:.3g} A, the motors' continuous "
                         f"current is {im[j]:.3g} A")
    amp = AMPLITUDE_FRACTION * (im - gA)
    kp, kd, env = [], [], []
    for lo, hi, h, J, k, A in zip(q_min_rad, q_max_rad, q_home_rad, inertia_kg_m2, kt, amp, strict=True):
        half = min(h - lo, hi - h)
        env.append(HOLD_ENVELOPE_FRACTION * half)
        kp.append(float(A * k) / (TRAVEL_FRACTION * half))
        kd.append(2.0 * ZETA * math.sqrt(kp[-1] * J))
    same = bool(np.all(kt == kt[0]) and np.all(im == im[0]))
    step = 2.0 * math.pi / counts_per_rev
    f_counts = np.sqrt(amp * kt / (np.asarray(inertia_kg_m2, float) * BAND_COUNTS * step)) / (2.0 * math.pi)
    f1 = float(min(F1_HZ, BAND_MARGIN * float(np.min(f_counts))))
    if f1 < F1_HZ:  # the sweep lingers longer near the hold's resonance: less current
        amp = amp * math.sqrt(f1 / F1_HZ)
        kp = [k * math.sqrt(f1 / F1_HZ) for k in kp]
        kd = [2.0 * ZETA * math.sqrt(k * J) for k, J in zip(kp, inertia_kg_m2, strict=True)]
    one = bool(np.all(amp == amp[0]))
    return Plan2(Te_s, float(kt[0]), float(im[0]), tuple(map(float, q_min_rad)), tuple(map(float, q_max_rad)),
                 tuple(map(float, q_home_rad)), float(amp[0]), tuple(kp), tuple(kd), tuple(int(s) for s in hand_sign),
                 tuple(env), bool(gravity_ff), hand_min_rad=HAND_MIN_COUNTS * 2.0 * math.pi / counts_per_rev,
                 hand_move=hand_move, kt_joint_Nm_per_A=() if same else tuple(map(float, kt)),
                 i_max_joint_A=() if same else tuple(map(float, im)),
                 amplitude_joint_A=() if one else tuple(map(float, amp)), f1_Hz=f1)


@dataclass
class State2:
    """The routine's state: sample index, previous angles, filtered velocities, first angles,
    largest hand excursions (signed), status (lists of two; :func:`step` sizes them to the
    plan's joints on its first call)."""

    k: int = 0
    q_prev: list = field(default_factory=lambda: [0.0, 0.0])
    v_f: list = field(default_factory=lambda: [0.0, 0.0])
    q_first: list = field(default_factory=lambda: [0.0, 0.0])
    hand: list = field(default_factory=lambda: [0.0, 0.0])
    status: int = RUNNING


def _taper(p: Plan2, s: float) -> float:
    u = min(1.0, s / p.T_taper_s, (p.T_chirp_s - s) / p.T_taper_s)
    return math.sin(0.5 * math.pi * max(u, 0.0)) ** 2


def _phase(p: Plan2, j: int, c: float) -> float:
    """Chirp phase (rad) of motor j at time c in the chirp (:data:`SWEEPS`): the integral of
    its instantaneous frequency, linear from fa to fb over the chirp (or over each half, and
    back)."""
    down, turn = SWEEPS[j % 4]
    fa, fb = (p.f1_Hz, p.f0_Hz) if down else (p.f0_Hz, p.f1_Hz)
    if not turn:
        return 2.0 * math.pi * (fa * c + (fb - fa) * c * c / (2.0 * p.T_chirp_s))
    h = 0.5 * p.T_chirp_s
    if c <= h:
        return 2.0 * math.pi * (fa * c + (fb - fa) * c * c / (2.0 * h))
    u = c - h
    return 2.0 * math.pi * (fa * h + (fb - fa) * h / 2.0 + fb * u - (fb - fa) * u * u / (2.0 * h))


def _check(p: Plan2, st: State2, q, s: float) -> int:
    for j in range(p.n_joints):
        if st.hand[j] * p.hand_sign[j] <= -p.hand_min_rad:
            return ENCODER
    for j in range(p.n_joints):
        if q[j] < p.q_min_rad[j] or q[j] > p.q_max_rad[j] or abs(q[j] - p.q_home_rad[j]) > p.envelope_rad[j]:
            return RANGE
    return DONE if s >= 2 * p.T_settle_s + p.T_chirp_s else RUNNING


def step(p: Plan2, st: State2, q_rad, tau_g=None) -> tuple[list[float], int]:
    """([current A per motor], status) for the joint angles ``q_rad`` read this period and,
    when ``p.gravity_ff``, the gravity torques ``tau_g`` (N m per motor) at them; advances
    ``st``. The C function ``hc_ident_step`` does the same arithmetic in the same order."""
    n = p.n_joints
    if st.k == 0 and len(st.q_prev) != n:
        st.q_prev, st.v_f, st.q_first, st.hand = ([0.0] * n for _ in range(4))
    t = st.k * p.Te_s
    for j in range(n):
        v = 0.0 if st.k == 0 else (q_rad[j] - st.q_prev[j]) / p.Te_s
        if st.k == 0:
            st.q_first[j] = q_rad[j]
        st.v_f[j] += p.alpha * (v - st.v_f[j])
        st.q_prev[j] = q_rad[j]
    st.k += 1
    zero = [0.0] * n
    if st.status != RUNNING:
        return zero, st.status
    s = t - p.T_hand_s
    if s < 0.0:
        for j in range(n):
            d = q_rad[j] - st.q_first[j]
            if abs(d) > abs(st.hand[j]):
                st.hand[j] = d
        return zero, RUNNING
    st.status = _check(p, st, q_rad, s)
    if st.status != RUNNING:
        return zero, st.status
    g = min(1.0, s / p.T_settle_s)
    c = s - p.T_settle_s
    inside = all(lo <= q_rad[j] <= hi for j, (lo, hi) in enumerate(p.safe_rad))
    out = []
    for j in range(n):
        i = -g * (p.kp_Nm_per_rad[j] * (q_rad[j] - p.q_home_rad[j]) + p.kd_Nm_s_per_rad[j] * st.v_f[j]) / p.kt(j)
        if p.gravity_ff:
            i += tau_g[j] / p.kt(j)
        if 0.0 <= c < p.T_chirp_s and inside:
            i += p.amplitude(j) * _taper(p, c) * math.sin(_phase(p, j, c))
        out.append(max(-p.i_max(j), min(p.i_max(j), i)))
    return out, RUNNING


def run_on_angles(p: Plan2, q_rad, tau_g=None) -> np.ndarray:
    """Currents (N, n) A the routine commands for a given sequence of read angles (N, n) rad
    and gravity torques (N, n) N m (open loop: the reference the compiled C routine is
    compared with)."""
    st = State2()
    q = np.asarray(q_rad, dtype=float)
    tg = np.zeros_like(q) if tau_g is None else np.asarray(tau_g, float)
    return np.array([step(p, st, [float(x) for x in row], list(g))[0] for row, g in zip(q, tg, strict=True)])
