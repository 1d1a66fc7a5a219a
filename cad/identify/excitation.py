"""The excitation the generated firmware runs on a 1-motor device (four-bar), and its Python
reference (the C routine ``hc_ident_step`` computes the same numbers, tests/unit/identify).

Phases, at the control period ``Te_s`` (time t = k Te from the first sample):

1. ``hand`` (0 <= t < T_hand): current 0; the operator moves the handle by hand towards the
   end marked + (the path's +x, P(phi1_max)) and back: the log shows the encoder direction;
2. ``hold`` (T_hand + [0, T_settle)): a PD hold to the crank's mid-range angle, gains ramped
   from 0 to 1 (no jump when the handle was left elsewhere);
3. ``chirp`` (T_chirp): the hold plus ``A w(t) sin(2 pi (f0 s + (f1 - f0) s^2 / (2 T_chirp)))``
   amperes, s = time in the phase, w a sin^2 taper over ``T_taper`` at both ends; the chirp
   term is switched off while the crank is outside the safe range (the joint range less
   ``safe_fraction`` of it at each end): the position-hold safety envelope;
4. ``rest`` (T_settle): the hold alone, then current 0 and the routine reports done.

Safety: at the end of the hand phase, a hand move of at least :data:`HAND_MIN_COUNTS` counts
towards - (not +) means the encoder counts the other way than the firmware assumes: closing
the hold would push the crank away, so the routine stops there (status ``ENCODER``). Whenever
the crank leaves its joint range during the hold or the chirp the routine stops (``RANGE``:
a reversed current gain makes the hold push away too). Stopped, it commands 0 A.

Every command is clamped at +-``i_max_A`` (the motor's continuous current). The hold:
``i = -(kp (q - q_c) + kd v) / Kt`` with v the backward difference of q low-passed at
``fc_Hz`` (first order). Gains from the predicted inertia: the chirp amplitude held at
``travel_fraction`` of the half range, damping ratio ``zeta``.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

#: Phase durations (s), chirp band (Hz), amplitude as a fraction of the continuous current,
#: static deflection of the chirp amplitude against the hold as a fraction of the half range,
#: hold damping ratio, velocity filter cut-off (Hz), taper (s), safe-range fraction.
T_HAND_S = 2.0
T_SETTLE_S = 0.5
T_CHIRP_S = 8.0
F0_HZ, F1_HZ = 0.5, 15.0
AMPLITUDE_FRACTION = 0.6
TRAVEL_FRACTION = 0.35
ZETA = 0.4
FC_HZ = 50.0
T_TAPER_S = 0.5
SAFE_FRACTION = 0.1
#: The hand move that tells the encoder direction (counts).
HAND_MIN_COUNTS = 5
#: Status of :func:`step` (the C routine's return values).
RUNNING, DONE, RANGE, ENCODER = 0, 1, 2, 3


class RoutineTiming:
    """What every identification routine's plan derives from its period ``Te_s``, its velocity
    filter corner ``fc_Hz`` and its phase lengths (``T_hand_s``, ``T_settle_s``,
    ``T_chirp_s``): the 1-motor :class:`Plan` and the 2-motor
    :class:`cad.identify.excitation2.Plan2` share it."""

    @property
    def alpha(self) -> float:
        """Velocity filter gain per sample, Te / (Te + 1 / (2 pi fc))."""
        return self.Te_s / (self.Te_s + 1.0 / (2.0 * math.pi * self.fc_Hz))

    @property
    def n_samples(self) -> int:
        """Periods until the routine reports done (that period included)."""
        return int(math.ceil((self.T_hand_s + 2 * self.T_settle_s + self.T_chirp_s) / self.Te_s)) + 1

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class Plan(RoutineTiming):
    """Every constant of the routine (SI): the generated C code is written from these."""

    Te_s: float
    kt_Nm_per_A: float
    i_max_A: float
    q_min_rad: float
    q_max_rad: float
    amplitude_A: float
    kp_Nm_per_rad: float
    kd_Nm_s_per_rad: float
    T_hand_s: float = T_HAND_S
    T_settle_s: float = T_SETTLE_S
    T_chirp_s: float = T_CHIRP_S
    f0_Hz: float = F0_HZ
    f1_Hz: float = F1_HZ
    fc_Hz: float = FC_HZ
    T_taper_s: float = T_TAPER_S
    safe_fraction: float = SAFE_FRACTION
    hand_min_rad: float = 0.0

    @property
    def q_center_rad(self) -> float:
        return 0.5 * (self.q_min_rad + self.q_max_rad)

    @property
    def safe_rad(self) -> tuple[float, float]:
        d = self.safe_fraction * (self.q_max_rad - self.q_min_rad)
        return self.q_min_rad + d, self.q_max_rad - d


def plan(Te_s: float, kt_Nm_per_A: float, i_max_A: float, q_min_rad: float, q_max_rad: float,
         inertia_kg_m2: float, counts_per_rev: int) -> Plan:
    """The :class:`Plan` of a 1-motor device: control period (s), torque constant (N m/A),
    continuous current (A), crank range (rad), predicted crank inertia at mid-range (kg m^2),
    encoder counts per turn."""
    A = AMPLITUDE_FRACTION * i_max_A
    half = 0.5 * (q_max_rad - q_min_rad)
    kp = A * kt_Nm_per_A / (TRAVEL_FRACTION * half)
    kd = 2.0 * ZETA * math.sqrt(kp * inertia_kg_m2)
    return Plan(Te_s, kt_Nm_per_A, i_max_A, q_min_rad, q_max_rad, A, kp, kd,
                hand_min_rad=HAND_MIN_COUNTS * 2.0 * math.pi / counts_per_rev)


@dataclass
class State:
    """The routine's state: sample index, previous angle, filtered velocity, first angle and
    largest hand excursion (signed), status."""

    k: int = 0
    q_prev: float = math.nan
    v_f: float = 0.0
    q_first: float = 0.0
    hand: float = 0.0
    status: int = RUNNING


def _taper(p: Plan, s: float) -> float:
    u = min(1.0, s / p.T_taper_s, (p.T_chirp_s - s) / p.T_taper_s)
    return math.sin(0.5 * math.pi * max(u, 0.0)) ** 2


def step(p: Plan, st: State, q_rad: float) -> tuple[float, int]:
    """(commanded current A, status) for the crank angle ``q_rad`` read this period; advances
    ``st``. The C function ``hc_ident_step`` does the same arithmetic in the same order."""
    t = st.k * p.Te_s
    v = 0.0 if st.k == 0 else (q_rad - st.q_prev) / p.Te_s
    if st.k == 0:
        st.q_first = q_rad
    st.v_f += p.alpha * (v - st.v_f)
    st.q_prev = q_rad
    st.k += 1
    if st.status != RUNNING:
        return 0.0, st.status
    s = t - p.T_hand_s
    if s < 0.0:
        d = q_rad - st.q_first
        if abs(d) > abs(st.hand):
            st.hand = d
        return 0.0, RUNNING
    if st.hand <= -p.hand_min_rad:
        st.status = ENCODER
    elif q_rad < p.q_min_rad or q_rad > p.q_max_rad:
        st.status = RANGE
    elif s >= 2 * p.T_settle_s + p.T_chirp_s:
        st.status = DONE
    if st.status != RUNNING:
        return 0.0, st.status
    g = min(1.0, s / p.T_settle_s)
    i = -g * (p.kp_Nm_per_rad * (q_rad - p.q_center_rad) + p.kd_Nm_s_per_rad * st.v_f) / p.kt_Nm_per_A
    c = s - p.T_settle_s
    lo, hi = p.safe_rad
    if 0.0 <= c < p.T_chirp_s and lo <= q_rad <= hi:
        ph = 2.0 * math.pi * (p.f0_Hz * c + (p.f1_Hz - p.f0_Hz) * c * c / (2.0 * p.T_chirp_s))
        i += p.amplitude_A * _taper(p, c) * math.sin(ph)
    return max(-p.i_max_A, min(p.i_max_A, i)), RUNNING


def run_on_angles(p: Plan, q_rad) -> np.ndarray:
    """Currents (A) the routine commands for a given sequence of read angles (open loop: the
    reference the compiled C routine is compared with)."""
    st = State()
    return np.array([step(p, st, float(q))[0] for q in np.asarray(q_rad, dtype=float)])
