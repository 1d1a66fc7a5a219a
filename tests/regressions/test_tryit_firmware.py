"""Tester findings on the generated firmware (t2tester).

The four-bar's ``hc_forward`` compared the crank angle with [Q_MIN, Q_MAX] as a number, not
modulo 2 pi (fixed: it wraps into Q_MIN + [0, 2 pi) first). A design whose ``[firmware] encoder_zero_deg`` names the power-up angle with
another turn (-186 deg is the 174 deg of the Hoeken's 132..216 deg range) got firmware that
refused every encoder reading (HC_ERR_RANGE at count 0, the power-up pose itself), while the
build and the shipped test program reported success (the test vectors evaluate FK at q, never
at the angles from the counts).
Reference: the crank at 174 deg, P from cad.kinematics.fourbar (the design's numpy model).
"""
from __future__ import annotations

import dataclasses
import math
import subprocess

import numpy as np

from tests.compilers import compiler

MAIN = r"""
#include <stdio.h>
#include "hapticad_device.h"
int main(void) {
    hc_encoder_t enc = HC_ENCODER_DEFAULT;
    long counts[1] = { 0 };
    hc_real q[1], X[2];
    int st;
    hc_counts_to_angles(&enc, counts, q);
    st = hc_forward(q, X);
    printf("%d %.17g %.17g\n", st, (double)X[0], (double)X[1]);
    return 0;
}
"""


def test_encoder_zero_given_with_another_turn_reads_the_power_up_pose(request, tmp_path):
    cc = compiler("c")  # skips with the reason, fails under HAPTICAD_REQUIRE_CC=1
    from cad.firmware import firmware_files
    from cad.kinematics import fourbar as k4
    from cad.pipeline import design_hash

    d, _, rep, _ = request.getfixturevalue("hoeken_sim_build")
    d2 = dataclasses.replace(d, firmware=dataclasses.replace(d.firmware, encoder_zero_deg=(-186.0,)))
    for rel, text in firmware_files(d2, rep, design_hash(d2)).items():
        p = tmp_path / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)
    fw = tmp_path / "firmware"
    (fw / "main.c").write_text(MAIN)
    exe = tmp_path / "enc"
    r = subprocess.run([cc, "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", "-o", str(exe),
                        str(fw / "main.c"), str(fw / "hapticad_device.c"), "-lm"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    st, x, y = subprocess.run([str(exe)], capture_output=True, text=True, timeout=60).stdout.split()
    P = k4.coupler_point_and_jacobian(d.linkage, np.array([math.radians(174.0)]))[0][0] * 1e-3
    assert int(st) == 0
    assert abs(float(x) - P[0]) < 1e-9 and abs(float(y) - P[1]) < 1e-9


CURRENTS = r"""
#include <math.h>
#include <stdio.h>
#include "hapticad_device.h"
int main(void) {
    hc_real tau[HC_N_JOINTS], amps[HC_N_JOINTS];
    int i, k, r;
    hc_real bad[3];
    bad[0] = (hc_real)NAN; bad[1] = (hc_real)INFINITY; bad[2] = -(hc_real)INFINITY;
    for (k = 0; k < 3; ++k) {
        for (i = 0; i < HC_N_JOINTS; ++i) tau[i] = bad[k];
        r = hc_motor_currents(tau, HC_LIMIT_CONTINUOUS, amps);
        printf("%d", r);
        for (i = 0; i < HC_N_JOINTS; ++i) printf(" %g", (double)amps[i]);
        printf("\n");
    }
    return 0;
}
"""


def test_motor_currents_of_a_nan_or_infinite_torque_are_zero(request, tmp_path):
    """A NaN torque used to pass through as a NaN current (returning 0, "not scaled"), an
    infinite one became inf * 0 = NaN: an amplifier command no firmware should send."""
    cc = compiler("c")  # skips with the reason, fails under HAPTICAD_REQUIRE_CC=1
    _, out, _, _ = request.getfixturevalue("hoeken_sim_build")
    fw = out / "firmware"
    src = tmp_path / "cur.c"
    src.write_text(CURRENTS)
    exe = tmp_path / "cur"
    r = subprocess.run([cc, "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", f"-I{fw}",
                        "-o", str(exe), str(src), str(fw / "hapticad_device.c"), "-lm"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    for line in subprocess.run([str(exe)], capture_output=True, text=True, timeout=60).stdout.split("\n")[:3]:
        ret, *amps = line.split()
        assert ret == "1" and all(float(a) == 0.0 for a in amps), line
