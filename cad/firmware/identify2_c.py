"""C99 text of the identification routine of a device of n >= 2 motors (the 5-bar pantograph,
the delta; issue 37): ``identify/hapticad_identify.h``, ``identify/hapticad_identify.c`` and
``identify/identify_example.ino``.

``hc_ident_step`` is :func:`cad.identify.excitation2.step` in C (same arithmetic, same
order; tests/unit/identify compiles it and compares the currents), with the constants of the
plan :func:`cad.sim.identify_fivebar.predict` makes from the resolved device;
``hc_ident_log_header`` and ``hc_ident_log_row`` write the public log format
(:mod:`cad.identify.logfile`) with n ``counts_i`` and n ``current_A_i`` columns. The arrays
have ``HC_N_JOINTS`` entries (the device header's joint count, = the plan's).
"""

from __future__ import annotations

from cad.firmware.csrc import banner, lit
from cad.identify.excitation2 import DONE, ENCODER, RANGE, RUNNING, SWEEPS, Plan2

FOLDER = "identify"


def _per_joint(name: str, values, fmt=lit) -> str:
    return "\n".join(f"#define {name}_{j} {fmt(v)}" for j, v in enumerate(values))


def header(spec, p: Plan2) -> str:
    safe = p.safe_rad
    n = p.n_joints
    return banner(spec, f"hapticad_identify.h: the {n}-motor identification routine and its CSV log") + f"""
#ifndef HAPTICAD_IDENTIFY_H
#define HAPTICAD_IDENTIFY_H
#include <stddef.h>
#include "../hapticad_device.h"
#ifdef __cplusplus
extern "C" {{
#endif

/* hc_ident_step's return values */
#define HC_IDENT_RUNNING {RUNNING}   /* keep calling it every control period */
#define HC_IDENT_DONE {DONE}      /* finished: 0 A */
#define HC_IDENT_RANGE {RANGE}     /* stopped: a joint left its range (a reversed current gain?) */
#define HC_IDENT_ENCODER {ENCODER}   /* stopped: a joint moved against the hand move (encoder reversed) */

#define HC_IDENT_TE_S {lit(p.Te_s)}            /* control period (s): call hc_ident_step at this rate */
#define HC_IDENT_T_HAND_S {lit(p.T_hand_s)}      /* phase 1: move the handle by hand {p.hand_move} and back */
#define HC_IDENT_T_SETTLE_S {lit(p.T_settle_s)}
#define HC_IDENT_T_CHIRP_S {lit(p.T_chirp_s)}
#define HC_IDENT_F0_HZ {lit(p.f0_Hz)}   /* motor j sweeps by HC_IDENT_SWEEP_j: 0 F0 -> F1, 1 F1 -> F0, +2 back at half time */
#define HC_IDENT_F1_HZ {lit(p.f1_Hz)}
#define HC_IDENT_T_TAPER_S {lit(p.T_taper_s)}
#define HC_IDENT_AMPLITUDE_A {lit(p.amplitude_A)}  /* chirp amplitude (A) */
#define HC_IDENT_I_MAX_A {lit(p.i_max_A)}      /* clamp: the motor's continuous current (A) */
#define HC_IDENT_KT_NM_PER_A {lit(p.kt_Nm_per_A)}
/* per joint (the motors may differ): torque per ampere and current clamp */
{_per_joint("HC_IDENT_KT_NM_PER_A", [p.kt(j) for j in range(n)])}
{_per_joint("HC_IDENT_I_MAX_A", [p.i_max(j) for j in range(n)])}
{_per_joint("HC_IDENT_AMPLITUDE_A", [p.amplitude(j) for j in range(n)])}
#define HC_IDENT_ALPHA {lit(p.alpha)}         /* velocity low-pass per sample ({p.fc_Hz:g} Hz) */
#define HC_IDENT_HAND_MIN_RAD {lit(p.hand_min_rad)}
#define HC_IDENT_N_SAMPLES {p.n_samples}L
#define HC_IDENT_GRAVITY_FF {int(p.gravity_ff)}  /* 1: the hold adds hc_gravity_torques (a vertical device) */
/* per joint: hold gains, home (the hold's target), range and hold envelope about home (leaving
 * either stops the routine: beyond the envelope the hold is at the current clamp), the safe range (the chirps run only while every joint is inside), the sign of the hand move */
{_per_joint("HC_IDENT_KP_NM_PER_RAD", p.kp_Nm_per_rad)}
{_per_joint("HC_IDENT_KD_NM_S_PER_RAD", p.kd_Nm_s_per_rad)}
{_per_joint("HC_IDENT_Q_HOME_RAD", p.q_home_rad)}
{_per_joint("HC_IDENT_Q_MIN_RAD", p.q_min_rad)}
{_per_joint("HC_IDENT_Q_MAX_RAD", p.q_max_rad)}
{_per_joint("HC_IDENT_ENVELOPE_RAD", p.envelope_rad)}
{_per_joint("HC_IDENT_Q_SAFE_LO_RAD", [s[0] for s in safe])}
{_per_joint("HC_IDENT_Q_SAFE_HI_RAD", [s[1] for s in safe])}
{_per_joint("HC_IDENT_HAND_SIGN", p.hand_sign, str)}
{_per_joint("HC_IDENT_SWEEP", [_sweep(j) for j in range(n)], str)}

typedef struct {{ long k; hc_real q_prev[HC_N_JOINTS], v_f[HC_N_JOINTS], q_first[HC_N_JOINTS], hand[HC_N_JOINTS]; int status; }} hc_ident_t;

void hc_ident_init(hc_ident_t *s);
/* one control period: every encoder's counts in, every motor current to command out (A);
 * returns HC_IDENT_* (the currents are 0 unless HC_IDENT_RUNNING) */
int hc_ident_step(hc_ident_t *s, const hc_encoder_t *enc, const long counts[HC_N_JOINTS], hc_real amps[HC_N_JOINTS]);
/* the log's two header lines / one row ({_columns(n)}),
 * '\\n'-terminated, into buf (n bytes); return the snprintf length */
int hc_ident_log_header(char *buf, size_t n);
int hc_ident_log_row(char *buf, size_t n, hc_real t_s, const long counts[HC_N_JOINTS], const hc_real amps[HC_N_JOINTS]);

#ifdef __cplusplus
}}
#endif
#endif
"""


SOURCE = r"""
#include <math.h>
#include <stdio.h>
#include "hapticad_identify.h"

@ARRAYS@
void hc_ident_init(hc_ident_t *s)
{
    int j;
    s->k = 0;
    for (j = 0; j < HC_N_JOINTS; ++j) {
        s->q_prev[j] = HC_R(0.0); s->v_f[j] = HC_R(0.0); s->q_first[j] = HC_R(0.0); s->hand[j] = HC_R(0.0);
    }
    s->status = HC_IDENT_RUNNING;
}

static hc_real hc_ident_taper(hc_real c)
{
    hc_real u = c / HC_IDENT_T_TAPER_S, e = (HC_IDENT_T_CHIRP_S - c) / HC_IDENT_T_TAPER_S, w;
    if (e < u) u = e;
    if (u > HC_R(1.0)) u = HC_R(1.0);
    if (u < HC_R(0.0)) u = HC_R(0.0);
    w = sin(HC_R(0.5) * HC_R(3.141592653589793) * u);
    return w * w;
}

/* chirp phase (rad) at time c in the chirp: linear frequency fa -> fb over the chirp, or over
 * each half and back (sweep & 2); sweep & 1: fa = F1 (down) */
static hc_real hc_ident_phase(int sweep, hc_real c)
{
    hc_real fa = (sweep & 1) ? HC_IDENT_F1_HZ : HC_IDENT_F0_HZ;
    hc_real fb = (sweep & 1) ? HC_IDENT_F0_HZ : HC_IDENT_F1_HZ;
    hc_real h = HC_R(0.5) * HC_IDENT_T_CHIRP_S, u;
    if (!(sweep & 2))
        return HC_R(2.0) * HC_R(3.141592653589793) * (fa * c + (fb - fa) * c * c / (HC_R(2.0) * HC_IDENT_T_CHIRP_S));
    if (c <= h)
        return HC_R(2.0) * HC_R(3.141592653589793) * (fa * c + (fb - fa) * c * c / (HC_R(2.0) * h));
    u = c - h;
    return HC_R(2.0) * HC_R(3.141592653589793) * (fa * h + (fb - fa) * h / HC_R(2.0) + fb * u
                                                  - (fb - fa) * u * u / (HC_R(2.0) * h));
}

static int hc_ident_check(const hc_ident_t *s, const hc_real q[HC_N_JOINTS], hc_real sp)
{
    int j;
    for (j = 0; j < HC_N_JOINTS; ++j)
        if (s->hand[j] * HAND_SIGN[j] <= -HC_IDENT_HAND_MIN_RAD) return HC_IDENT_ENCODER;
    for (j = 0; j < HC_N_JOINTS; ++j)
        if (q[j] < QMIN[j] || q[j] > QMAX[j] || fabs(q[j] - HOME[j]) > ENV[j]) return HC_IDENT_RANGE;
    return (sp >= 2 * HC_IDENT_T_SETTLE_S + HC_IDENT_T_CHIRP_S) ? HC_IDENT_DONE : HC_IDENT_RUNNING;
}

int hc_ident_step(hc_ident_t *s, const hc_encoder_t *enc, const long counts[HC_N_JOINTS], hc_real amps[HC_N_JOINTS])
{
    hc_real q[HC_N_JOINTS], tg[HC_N_JOINTS], t, sp, g, ch;
    int j, inside;
    hc_counts_to_angles(enc, counts, q);
    t = (hc_real)s->k * HC_IDENT_TE_S;
    for (j = 0; j < HC_N_JOINTS; ++j) {
        hc_real v = (s->k == 0) ? HC_R(0.0) : (q[j] - s->q_prev[j]) / HC_IDENT_TE_S;
        if (s->k == 0) s->q_first[j] = q[j];
        s->v_f[j] += HC_IDENT_ALPHA * (v - s->v_f[j]);
        s->q_prev[j] = q[j];
    }
    s->k += 1;
    for (j = 0; j < HC_N_JOINTS; ++j) amps[j] = HC_R(0.0);
    if (s->status != HC_IDENT_RUNNING) return s->status;
    sp = t - HC_IDENT_T_HAND_S;
    if (sp < HC_R(0.0)) {
        for (j = 0; j < HC_N_JOINTS; ++j) {
            hc_real d = q[j] - s->q_first[j];
            if (fabs(d) > fabs(s->hand[j])) s->hand[j] = d;
        }
        return HC_IDENT_RUNNING;
    }
    s->status = hc_ident_check(s, q, sp);
    if (s->status != HC_IDENT_RUNNING) return s->status;
    g = sp / HC_IDENT_T_SETTLE_S;
    if (g > HC_R(1.0)) g = HC_R(1.0);
    ch = sp - HC_IDENT_T_SETTLE_S;
    for (j = 0; j < HC_N_JOINTS; ++j) tg[j] = HC_R(0.0);
    if (HC_IDENT_GRAVITY_FF) (void)hc_gravity_torques(q, tg);  /* a refused pose: 0, as the reference */
    inside = 1;
    for (j = 0; j < HC_N_JOINTS; ++j)
        if (q[j] < SLO[j] || q[j] > SHI[j]) inside = 0;
    for (j = 0; j < HC_N_JOINTS; ++j) {
        hc_real i = -g * (KP[j] * (q[j] - HOME[j]) + KD[j] * s->v_f[j]) / KT[j];
        if (HC_IDENT_GRAVITY_FF) i += tg[j] / KT[j];
        if (ch >= HC_R(0.0) && ch < HC_IDENT_T_CHIRP_S && inside) {
            i += AMP[j] * hc_ident_taper(ch) * sin(hc_ident_phase(SWEEP[j], ch));
        }
        if (i > IMAX[j]) i = IMAX[j];
        if (i < -IMAX[j]) i = -IMAX[j];
        amps[j] = i;
    }
    return HC_IDENT_RUNNING;
}

@LOG@
"""


SKETCH = r"""
/* Flash this with hapticad_device.c and identify/hapticad_identify.c, open the serial monitor
 * at 921600 baud, save everything after the line 'log:' to LOG.csv, then run
 *   hapticad identify DESIGN LOG.csv --out DIR
 * Board I/O: replace read_counts() and write_currents() with your encoder counters and drivers. */
#include "hapticad_identify.h"

static void read_counts(long c[HC_N_JOINTS]) { int j; for (j = 0; j < HC_N_JOINTS; ++j) c[j] = 0; }  /* your encoder counters */
static void write_currents(const hc_real a[HC_N_JOINTS]) { (void)a; }  /* your current drivers */

void setup(void)
{
    Serial.begin(921600);
    Serial.println("hapticad identification: in the next 2 s move the handle by hand");
    Serial.println("@HAND@ by a few cm and back to the middle, then let go. log:");
}

void loop(void)
{
    static hc_ident_t s;
    static int started = 0, status = HC_IDENT_RUNNING;
    static const hc_encoder_t enc = HC_ENCODER_DEFAULT;
    static unsigned long next;
    static const hc_real zero[HC_N_JOINTS] = { HC_R(0.0) };
    char line[1024];  /* the header: ~170 characters + the design name + the columns */
    long counts[HC_N_JOINTS];
    hc_real amps[HC_N_JOINTS];
    if (!started) {
        hc_ident_init(&s);
        hc_ident_log_header(line, sizeof line);
        Serial.print(line);
        next = micros();
        started = 1;
    }
    if (status != HC_IDENT_RUNNING) { write_currents(zero); return; }
    while ((long)(micros() - next) < 0) {}
    next += (unsigned long)(HC_IDENT_TE_S * 1e6);
    read_counts(counts);
    status = hc_ident_step(&s, &enc, counts, amps);
    write_currents(amps);
    hc_ident_log_row(line, sizeof line, (hc_real)(s.k - 1) * HC_IDENT_TE_S, counts, amps);
    Serial.print(line);
}
"""


def _sweep(j: int) -> int:
    """Motor j's sweep code (bit 0: down, bit 1: back at half time; :data:`SWEEPS`)."""
    down, turn = SWEEPS[j % 4]
    return int(down) + 2 * int(turn)


def _columns(n: int) -> str:
    return ", ".join(["t_s", *(f"counts_{j}" for j in range(n)), *(f"current_A_{j}" for j in range(n))])


_ARRAYS = (("hc_real", "KP", "HC_IDENT_KP_NM_PER_RAD"), ("hc_real", "KD", "HC_IDENT_KD_NM_S_PER_RAD"),
           ("hc_real", "HOME", "HC_IDENT_Q_HOME_RAD"), ("hc_real", "QMIN", "HC_IDENT_Q_MIN_RAD"),
           ("hc_real", "QMAX", "HC_IDENT_Q_MAX_RAD"), ("hc_real", "ENV", "HC_IDENT_ENVELOPE_RAD"),
           ("hc_real", "SLO", "HC_IDENT_Q_SAFE_LO_RAD"), ("hc_real", "SHI", "HC_IDENT_Q_SAFE_HI_RAD"),
           ("int", "HAND_SIGN", "HC_IDENT_HAND_SIGN"), ("int", "SWEEP", "HC_IDENT_SWEEP"),
           ("hc_real", "KT", "HC_IDENT_KT_NM_PER_A"), ("hc_real", "IMAX", "HC_IDENT_I_MAX_A"),
           ("hc_real", "AMP", "HC_IDENT_AMPLITUDE_A"))


def _arrays(n: int) -> str:
    return "\n".join(f"static const {t} {name}[HC_N_JOINTS] = {{ " + ", ".join(f"{m}_{j}" for j in range(n)) + " };"
                     for t, name, m in _ARRAYS)


def _log(n: int) -> str:
    """hc_ident_log_header and hc_ident_log_row for n joints."""
    head = ",".join(c.strip() for c in _columns(n).split(","))
    fmt = "%.9g" + ",%ld" * n + ",%.9g" * n
    args = ", ".join([*(f"counts[{j}]" for j in range(n)), *(f"(double)amps[{j}]" for j in range(n))])
    return f"""int hc_ident_log_header(char *buf, size_t n)
{{
    return snprintf(buf, n, "# hapticad identification log; design %s; design hash sha256:%s; "
                    "firmware routine hc_ident_step; control period %.9g s\\n"
                    "{head}\\n",
                    HC_DEVICE_NAME, HC_DESIGN_HASH, (double)HC_IDENT_TE_S);
}}

int hc_ident_log_row(char *buf, size_t n, hc_real t_s, const long counts[HC_N_JOINTS], const hc_real amps[HC_N_JOINTS])
{{
    return snprintf(buf, n, "{fmt}\\n", (double)t_s, {args});
}}
"""


def files(spec, p: Plan2) -> dict[str, str]:
    """``{path under firmware/: text}`` of the n-motor routine for ``spec`` and ``p``."""
    n = p.n_joints
    src = SOURCE.replace("@ARRAYS@", _arrays(n)).replace("@LOG@", _log(n))
    return {f"{FOLDER}/hapticad_identify.h": header(spec, p),
            f"{FOLDER}/hapticad_identify.c": banner(spec, "hapticad_identify.c") + src,
            f"{FOLDER}/identify_example.ino": banner(spec, "identify_example.ino") + SKETCH.replace("@HAND@", p.hand_move)}
