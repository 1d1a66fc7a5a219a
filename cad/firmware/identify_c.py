"""C99 text of the identification routine of a four-bar (issue 37): ``identify/hapticad_identify.h``,
``identify/hapticad_identify.c`` and ``identify/identify_example.ino``.

``hc_ident_step`` is :func:`cad.identify.excitation.step` in C (same arithmetic, same order;
tests/unit/identify compiles it and compares the currents), with the constants of the plan
:func:`cad.sim.identify_device.predict` makes from the resolved device; ``hc_ident_log_header``
and ``hc_ident_log_row`` write the public log format (:mod:`cad.identify.logfile`).
"""

from __future__ import annotations

from cad.firmware.csrc import banner, lit
from cad.identify.excitation import DONE, ENCODER, RANGE, RUNNING, Plan

FOLDER = "identify"


def header(spec, p: Plan) -> str:
    return banner(spec, "hapticad_identify.h: the identification routine and its CSV log") + f"""
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
#define HC_IDENT_RANGE {RANGE}     /* stopped: the crank left its range (a reversed current gain?) */
#define HC_IDENT_ENCODER {ENCODER}   /* stopped: the hand move went towards - (encoder reversed) */

#define HC_IDENT_TE_S {lit(p.Te_s)}            /* control period (s): call hc_ident_step at this rate */
#define HC_IDENT_T_HAND_S {lit(p.T_hand_s)}      /* phase 1: move the handle by hand to + and back */
#define HC_IDENT_T_SETTLE_S {lit(p.T_settle_s)}
#define HC_IDENT_T_CHIRP_S {lit(p.T_chirp_s)}
#define HC_IDENT_F0_HZ {lit(p.f0_Hz)}
#define HC_IDENT_F1_HZ {lit(p.f1_Hz)}
#define HC_IDENT_T_TAPER_S {lit(p.T_taper_s)}
#define HC_IDENT_AMPLITUDE_A {lit(p.amplitude_A)}  /* chirp amplitude (A) */
#define HC_IDENT_I_MAX_A {lit(p.i_max_A)}      /* clamp: the motor's continuous current (A) */
#define HC_IDENT_KP_NM_PER_RAD {lit(p.kp_Nm_per_rad)}
#define HC_IDENT_KD_NM_S_PER_RAD {lit(p.kd_Nm_s_per_rad)}
#define HC_IDENT_KT_NM_PER_A {lit(p.kt_Nm_per_A)}
#define HC_IDENT_Q_MIN_RAD {lit(p.q_min_rad)}     /* joint range: leaving it stops the routine */
#define HC_IDENT_Q_MAX_RAD {lit(p.q_max_rad)}
#define HC_IDENT_Q_SAFE_LO_RAD {lit(p.safe_rad[0])} /* the chirp runs only inside */
#define HC_IDENT_Q_SAFE_HI_RAD {lit(p.safe_rad[1])}
#define HC_IDENT_ALPHA {lit(p.alpha)}         /* velocity low-pass per sample ({p.fc_Hz:g} Hz) */
#define HC_IDENT_HAND_MIN_RAD {lit(p.hand_min_rad)}
#define HC_IDENT_N_SAMPLES {p.n_samples}L

typedef struct {{ long k; hc_real q_prev, v_f, q_first, hand; int status; }} hc_ident_t;

void hc_ident_init(hc_ident_t *s);
/* one control period: the crank's encoder counts in, the motor current to command out (A);
 * returns HC_IDENT_* (the current is 0 unless HC_IDENT_RUNNING) */
int hc_ident_step(hc_ident_t *s, const hc_encoder_t *enc, long counts, hc_real *amps);
/* the log's two header lines / one row (t_s, counts_i..., current_A_i...), '\\n'-terminated,
 * into buf (n bytes); return the snprintf length */
int hc_ident_log_header(char *buf, size_t n);
int hc_ident_log_row(char *buf, size_t n, hc_real t_s, const long counts[HC_N_JOINTS],
                     const hc_real amps[HC_N_JOINTS]);

#ifdef __cplusplus
}}
#endif
#endif
"""


SOURCE = r"""
#include <math.h>
#include <stdio.h>
#include "hapticad_identify.h"

void hc_ident_init(hc_ident_t *s)
{
    s->k = 0; s->q_prev = HC_R(0.0); s->v_f = HC_R(0.0); s->q_first = HC_R(0.0);
    s->hand = HC_R(0.0); s->status = HC_IDENT_RUNNING;
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

int hc_ident_step(hc_ident_t *s, const hc_encoder_t *enc, long counts, hc_real *amps)
{
    long c[HC_N_JOINTS];
    hc_real q[HC_N_JOINTS], t, v, sp, g, i, ch;
    c[0] = counts;
    hc_counts_to_angles(enc, c, q);
    t = (hc_real)s->k * HC_IDENT_TE_S;
    v = (s->k == 0) ? HC_R(0.0) : (q[0] - s->q_prev) / HC_IDENT_TE_S;
    if (s->k == 0) s->q_first = q[0];
    s->v_f += HC_IDENT_ALPHA * (v - s->v_f);
    s->q_prev = q[0];
    s->k += 1;
    *amps = HC_R(0.0);
    if (s->status != HC_IDENT_RUNNING) return s->status;
    sp = t - HC_IDENT_T_HAND_S;
    if (sp < HC_R(0.0)) {
        hc_real d = q[0] - s->q_first;
        if (fabs(d) > fabs(s->hand)) s->hand = d;
        return HC_IDENT_RUNNING;
    }
    if (s->hand <= -HC_IDENT_HAND_MIN_RAD) s->status = HC_IDENT_ENCODER;
    else if (q[0] < HC_IDENT_Q_MIN_RAD || q[0] > HC_IDENT_Q_MAX_RAD) s->status = HC_IDENT_RANGE;
    else if (sp >= 2 * HC_IDENT_T_SETTLE_S + HC_IDENT_T_CHIRP_S) s->status = HC_IDENT_DONE;
    if (s->status != HC_IDENT_RUNNING) return s->status;
    g = sp / HC_IDENT_T_SETTLE_S;
    if (g > HC_R(1.0)) g = HC_R(1.0);
    i = -g * (HC_IDENT_KP_NM_PER_RAD * (q[0] - HC_R(0.5) * (HC_IDENT_Q_MIN_RAD + HC_IDENT_Q_MAX_RAD))
              + HC_IDENT_KD_NM_S_PER_RAD * s->v_f) / HC_IDENT_KT_NM_PER_A;
    ch = sp - HC_IDENT_T_SETTLE_S;
    if (ch >= HC_R(0.0) && ch < HC_IDENT_T_CHIRP_S && q[0] >= HC_IDENT_Q_SAFE_LO_RAD
        && q[0] <= HC_IDENT_Q_SAFE_HI_RAD) {
        hc_real ph = HC_R(2.0) * HC_R(3.141592653589793) * (HC_IDENT_F0_HZ * ch
                     + (HC_IDENT_F1_HZ - HC_IDENT_F0_HZ) * ch * ch / (HC_R(2.0) * HC_IDENT_T_CHIRP_S));
        i += HC_IDENT_AMPLITUDE_A * hc_ident_taper(ch) * sin(ph);
    }
    if (i > HC_IDENT_I_MAX_A) i = HC_IDENT_I_MAX_A;
    if (i < -HC_IDENT_I_MAX_A) i = -HC_IDENT_I_MAX_A;
    *amps = i;
    return HC_IDENT_RUNNING;
}

int hc_ident_log_header(char *buf, size_t n)
{
    return snprintf(buf, n, "# hapticad identification log; design %s; design hash sha256:%s; "
                    "firmware routine hc_ident_step; control period %.9g s\nt_s,counts_0,current_A_0\n",
                    HC_DEVICE_NAME, HC_DESIGN_HASH, (double)HC_IDENT_TE_S);
}

int hc_ident_log_row(char *buf, size_t n, hc_real t_s, const long counts[HC_N_JOINTS],
                     const hc_real amps[HC_N_JOINTS])
{
    return snprintf(buf, n, "%.9g,%ld,%.9g\n", (double)t_s, counts[0], (double)amps[0]);
}
"""


SKETCH = r"""
/* Flash this with hapticad_device.c and identify/hapticad_identify.c, open the serial monitor
 * at 921600 baud, save everything after the line 'log:' to LOG.csv, then run
 *   hapticad identify DESIGN LOG.csv --out DIR
 * Board I/O: replace read_counts() and write_current() with your encoder counter and driver. */
#include "hapticad_identify.h"

static long read_counts(void) { return 0; }              /* your encoder counter */
static void write_current(hc_real amps) { (void)amps; }  /* your current driver */

void setup(void)
{
    Serial.begin(921600);
    Serial.println("hapticad identification: in the next 2 s move the handle by hand towards the");
    Serial.println("end marked + and back to the middle, then let go. log:");
}

void loop(void)
{
    static hc_ident_t s;
    static int started = 0, status = HC_IDENT_RUNNING;
    static const hc_encoder_t enc = HC_ENCODER_DEFAULT;
    static unsigned long t0, next;
    char line[1024];  /* the header: ~170 characters + the design name */
    long counts[1];
    hc_real amps[1];
    if (!started) {
        hc_ident_init(&s);
        hc_ident_log_header(line, sizeof line);
        Serial.print(line);
        t0 = next = micros();
        started = 1;
    }
    if (status != HC_IDENT_RUNNING) { write_current(HC_R(0.0)); return; }
    while ((long)(micros() - next) < 0) {}
    next += (unsigned long)(HC_IDENT_TE_S * 1e6);
    counts[0] = read_counts();
    status = hc_ident_step(&s, &enc, counts[0], &amps[0]);
    write_current(amps[0]);
    hc_ident_log_row(line, sizeof line, (hc_real)(s.k - 1) * HC_IDENT_TE_S, counts, amps);
    Serial.print(line);
}
"""


def files(spec, p: Plan) -> dict[str, str]:
    """``{path under firmware/: text}`` of the routine for the four-bar ``spec`` and ``p``."""
    return {f"{FOLDER}/hapticad_identify.h": header(spec, p),
            f"{FOLDER}/hapticad_identify.c": banner(spec, "hapticad_identify.c") + SOURCE,
            f"{FOLDER}/identify_example.ino": banner(spec, "identify_example.ino") + SKETCH}
