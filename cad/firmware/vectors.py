"""Test vectors (``test_vectors.json``) from hapticad's numpy model and the C program that
checks the generated code against them (``test_device.c``).

Rows (``"rows"``, the file's last key, so that the C reader can scan for it) are flat lists::

    status, counts[nj], q_from_counts[nj], q[nj], F[nt], X[nt], J[nt*nj], tau[nj],
    tau_gravity[nj], apparent_mass_kg, M[nt*nt]

``status`` is the C status code the model expects at ``q`` (0 = ok; then the other fields
hold the model's values, zeros otherwise). Poses: in-range samples of the workspace
(four-bar: the crank range; pantographs: the workspace square through the IK on the design's
elbow modes, the twin over the full turn) and refused ones (outside the crank range, loops
that cannot close, the other working mode, an inconsistent crank pin).
"""

from __future__ import annotations

import numpy as np

from cad.firmware import reference as ref
from cad.firmware.spec import DeviceSpec, angles_from_counts

N_OK = 1200
N_BAD = 60
SEED = 26


def rows(spec: DeviceSpec, design) -> tuple[list[list[float]], dict]:
    """The test-vector rows (module docstring) and a summary (counts of ok / refused rows)."""
    rng = np.random.default_rng(SEED)
    q_ok = spec.model.poses_ok(spec, design, rng, N_OK)
    bad = spec.model.poses_bad(spec, q_ok, rng, N_BAD)
    q = np.concatenate([q_ok, bad])
    n, nj, nt = len(q), spec.n_joints, spec.n_task
    half = spec.encoder_counts_per_rev // 4
    counts = rng.integers(-half, half + 1, (n, nj))
    qc = angles_from_counts(spec, counts)
    F = rng.uniform(-5.0, 5.0, (n, nt))
    if spec.model.force_scale is not None:  # e.g. the twin's moments: N m / 100 (a 20 mm crank)
        F *= np.asarray(spec.model.force_scale)
    X, status = ref.forward(spec, q)
    ok = status == 0
    J = ref.jacobian(spec, q)
    tau = np.where(ok[:, None], ref.joint_torques(spec, q, F), 0.0)
    tg = ref.gravity_torques(spec, q)
    m_app = np.zeros(n)
    if spec.model.apparent_mass_kg is not None:
        m_app[ok] = spec.model.apparent_mass_kg(spec, q[ok, 0])
    M = ref.mass_matrix(spec, q).reshape(n, nt * nt)
    out = np.column_stack([status, counts, qc, q, F, X, J.reshape(n, nt * nj), tau, tg, m_app, M])
    summary = {"n_rows": n, "ok": int(ok.sum()), "refused": int((~ok).sum()),
               "refused_by_status": {k: int((status == v).sum()) for k, v in ref.STATUS.items() if v}}
    return [[float(v) for v in r] for r in out], summary


TEST_PROGRAM = r"""/* test_device.c: checks hapticad_device.c against test_vectors.json (hapticad's numpy model).
 * Build and run (double, then float):
 *   cc -std=c99 -O2 -o test_device test_device.c hapticad_device.c -lm
 *   ./test_device test_vectors.json 1e-9 1e-9 1e-7
 *   cc -std=c99 -O2 -DHAPTICAD_USE_FLOAT -o test_device_f test_device.c hapticad_device.c -lm
 *   ./test_device_f test_vectors.json 2e-5 2e-5 0
 * Arguments: vectors, position tolerance (m), torque tolerance (N m), finite-difference
 * tolerance of the Jacobian (m/rad; 0 skips it); the position tolerance is also the
 * relative tolerance of the apparent mass and of the mass matrix (to its largest entry), the
 * angle tolerance of counts -> q and the
 * tolerance of |J - J_ref| / (1 + |J_ref|) (the twin's theta row is ~10 rad/rad). Prints one summary line; exit 0 when every
 * row passes, 1 otherwise. No dynamic allocation: rows are read one at a time.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "hapticad_device.h"

#define NJ HC_N_JOINTS
#define NT HC_N_TASK
#define ROW (1 + 3 * NJ + 2 * NT + NT * NJ + 2 * NJ + 1 + NT * NT)

static int next_number(FILE *f, double *v)
{
    int c;
    char buf[64];
    size_t n = 0;
    while ((c = fgetc(f)) != EOF && !(c == '-' || c == '+' || c == '.' || (c >= '0' && c <= '9')))
        if (c == '}') return 0;
    if (c == EOF) return 0;
    do {
        if (n + 1 < sizeof buf) buf[n++] = (char)c;
        c = fgetc(f);
    } while (c != EOF && (c == '-' || c == '+' || c == '.' || c == 'e' || c == 'E'
                          || (c >= '0' && c <= '9')));
    buf[n] = 0;
    *v = strtod(buf, NULL);
    return 1;
}

static int find_rows(FILE *f)
{
    const char *key = "\"rows\"";
    size_t k = 0;
    int c;
    while ((c = fgetc(f)) != EOF) {
        k = (c == key[k]) ? k + 1 : (c == key[0] ? 1 : 0);
        if (key[k] == 0) return 1;
    }
    return 0;
}

static double wrap(double a) { return a - 6.283185307179586 * floor(a / 6.283185307179586 + 0.5); }

static double err_x(const hc_real *x, const double *want, int i)
{
    double d = (double)x[i] - want[i];
    return (NT == 3 && i == 2) ? fabs(wrap(d)) : fabs(d);
}

int main(int argc, char **argv)
{
    double r[ROW], tol_x, tol_t, tol_fd, worst_x = 0, worst_j = 0, worst_t = 0, worst_g = 0;
    double worst_q = 0, worst_fd = 0, worst_m = 0, worst_M = 0;
    long rows = 0, ok_rows = 0, refused = 0, failures = 0;
    hc_encoder_t enc = HC_ENCODER_DEFAULT;
    FILE *f;
    if (argc < 5) { fprintf(stderr, "usage: %s vectors.json tol_m tol_Nm tol_fd\n", argv[0]); return 2; }
    tol_x = atof(argv[2]); tol_t = atof(argv[3]); tol_fd = atof(argv[4]);
    f = fopen(argv[1], "r");
    if (!f || !find_rows(f)) { fprintf(stderr, "cannot read rows of %s\n", argv[1]); return 2; }
    for (;;) {
        int i, j, st, k = 0;
        long counts[NJ];
        hc_real q[NJ], qc[NJ], F[NT], X[NT], J[NT * NJ], tau[NJ], tg[NJ], m, M[NT * NT];
        for (i = 0; i < ROW; ++i) if (!next_number(f, &r[i])) break;
        if (i < ROW) break;
        ++rows;
        for (i = 0; i < NJ; ++i) {
            counts[i] = (long)r[1 + i];
            q[i] = (hc_real)r[1 + 2 * NJ + i];
        }
        hc_counts_to_angles(&enc, counts, qc);
        for (i = 0; i < NJ; ++i)
            if (fabs((double)qc[i] - r[1 + NJ + i]) > worst_q) worst_q = fabs((double)qc[i] - r[1 + NJ + i]);
        for (i = 0; i < NT; ++i) F[i] = (hc_real)r[1 + 3 * NJ + i];
        st = hc_forward(q, X);
        if (st != (int)r[0]) {
            ++failures;
            if (failures < 10) fprintf(stderr, "row %ld: status %d, expected %d\n", rows, st, (int)r[0]);
            continue;
        }
        if (st) { ++refused; continue; }
        ++ok_rows;
        k = 1 + 3 * NJ + NT;
        for (i = 0; i < NT; ++i) if (err_x(X, r + k, i) > worst_x) worst_x = err_x(X, r + k, i);
        k += NT;
        hc_jacobian(q, J);
        for (i = 0; i < NT * NJ; ++i) {   /* relative to 1 + |J|: the twin's theta row is ~10 */
            double d = fabs((double)J[i] - r[k + i]) / (1.0 + fabs(r[k + i]));
            if (d > worst_j) worst_j = d;
        }
        if (tol_fd > 0) {
            for (j = 0; j < NJ; ++j) {
                hc_real qp[NJ], qm[NJ], Xp[NT], Xm[NT];
                const double h = 1e-6;
                memcpy(qp, q, sizeof q); memcpy(qm, q, sizeof q);
                qp[j] += (hc_real)h; qm[j] -= (hc_real)h;
                if (hc_forward(qp, Xp) || hc_forward(qm, Xm)) continue;
                for (i = 0; i < NT; ++i) {
                    double d = (double)Xp[i] - (double)Xm[i];
                    if (NT == 3 && i == 2) d = wrap(d);
                    d = fabs(d / (2 * h) - (double)J[i * NJ + j]);
                    if (d > worst_fd) worst_fd = d;
                }
            }
        }
        k += NT * NJ;
        hc_joint_torques(q, F, tau);
        for (i = 0; i < NJ; ++i) if (fabs((double)tau[i] - r[k + i]) > worst_t) worst_t = fabs((double)tau[i] - r[k + i]);
        k += NJ;
        hc_gravity_torques(q, tg);
        for (i = 0; i < NJ; ++i) if (fabs((double)tg[i] - r[k + i]) > worst_g) worst_g = fabs((double)tg[i] - r[k + i]);
        k += NJ;
        if (hc_apparent_mass(q, &m) == HC_OK && fabs((double)m - r[k]) / r[k] > worst_m)
            worst_m = fabs((double)m - r[k]) / r[k];
        k += 1;
        hc_mass_matrix(q, M);   /* relative to the largest entry of the row's M */
        {
            double big = 0;
            for (i = 0; i < NT * NT; ++i) if (fabs(r[k + i]) > big) big = fabs(r[k + i]);
            for (i = 0; i < NT * NT; ++i)
                if (fabs((double)M[i] - r[k + i]) / big > worst_M) worst_M = fabs((double)M[i] - r[k + i]) / big;
        }
    }
    fclose(f);
    if (worst_x > tol_x || worst_j > tol_x || worst_t > tol_t || worst_g > tol_t
        || worst_q > tol_x || (tol_fd > 0 && worst_fd > tol_fd) || worst_m > tol_x || worst_M > tol_x)
        ++failures;
    printf("rows %ld ok %ld refused %ld failures %ld max_err_X %.3e max_err_J %.3e "
           "max_err_tau %.3e max_err_gravity %.3e max_err_counts %.3e max_err_fd %.3e "
           "max_rel_err_mass %.3e max_rel_err_M %.3e\n", rows, ok_rows, refused, failures, worst_x,
           worst_j, worst_t, worst_g, worst_q, worst_fd, worst_m, worst_M);
    return (failures || rows == 0) ? 1 : 0;
}
"""
