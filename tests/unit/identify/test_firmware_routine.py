"""The generated identification routine (issue 37 §1): ``firmware/identify/hapticad_identify.c``
compiled with the system C compiler (-std=c99 -Wall -Wextra -pedantic -Werror) and run on the
counts of virtual-bench runs: its currents equal the Python reference
(:func:`cad.identify.excitation.step`) that drove the bench, its log lines parse in the public
format, and in closed loop the excitation stays within the motor's continuous current (the
number hapticad_device.h states) and the crank within its joint range."""

from __future__ import annotations

import math
import re
import subprocess

import numpy as np
import pytest

from cad.identify import logfile
from cad.sim import bench
from tests.compilers import compiler

DRIVER = r"""
#include <stdio.h>
#include "identify/hapticad_identify.h"
int main(int argc, char **argv) {
    hc_ident_t s; hc_encoder_t enc = HC_ENCODER_DEFAULT; long c[1]; hc_real a[1]; char buf[256];
    FILE *log = fopen(argc > 1 ? argv[1] : "log.csv", "w");
    long k = 0;
    hc_ident_init(&s);
    hc_ident_log_header(buf, sizeof buf); fputs(buf, log);
    while (scanf("%ld", &c[0]) == 1) {
        int st = hc_ident_step(&s, &enc, c[0], &a[0]);
        printf("%.17g %d\n", (double)a[0], st);
        hc_ident_log_row(buf, sizeof buf, (hc_real)k * HC_IDENT_TE_S, c, a); fputs(buf, log);
        ++k;
    }
    fclose(log);
    return 0;
}
"""


def _report(H) -> dict:
    """A report.json's mass-property keys the firmware reads (paper H; link masses: the
    routine does not use them)."""
    link = {"mass_kg": 0.01, "com_mm": [10.0, 0.0, 0.0], "inertia_com_kg_m2": [[0, 0, 0], [0, 0, 0], [0, 0, 1e-6]]}
    return {"H11_kg_m2": H.H11_kg_m2, "H12_kg_m2": H.H12_kg_m2, "H22_kg_m2": H.H22_kg_m2,
            "H33_kg_m2": H.H33_kg_m2, "beta2_deg": 0.0, "links": {k: link for k in ("crank", "coupler", "rocker")}}


@pytest.fixture(scope="module")
def routine(tmp_path_factory, hoeken, paper_H):
    from cad.firmware import firmware_files
    from cad.pipeline import design_hash

    out = tmp_path_factory.mktemp("fw")
    for rel, text in firmware_files(hoeken, _report(paper_H), design_hash(hoeken)).items():
        p = out / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)
    fw = out / "firmware"
    (fw / "drv.c").write_text(DRIVER)
    exe = out / "drv"
    cmd = [compiler("c"), "-std=c99", "-O2", "-Wall", "-Wextra", "-pedantic", "-Werror", "-o", str(exe),
           str(fw / "drv.c"), str(fw / "identify" / "hapticad_identify.c"), str(fw / "hapticad_device.c"), "-lm"]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    return fw, exe


def _run(exe, counts, log_path):
    r = subprocess.run([str(exe), str(log_path)], input="\n".join(map(str, counts)) + "\n",
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    rows = np.array([ln.split() for ln in r.stdout.split("\n") if ln], dtype=float)
    return rows[:, 0], rows[:, 1].astype(int)


def _define(text: str, name: str) -> float:
    return float(re.search(rf"#define {name} HC_R\(([^)]+)\)", text).group(1))


def test_header_constants_are_the_plan_and_the_device(routine, pred):
    fw, _ = routine
    h = (fw / "identify" / "hapticad_identify.h").read_text()
    dev = (fw / "hapticad_device.h").read_text()
    p = pred.plan
    assert _define(h, "HC_IDENT_I_MAX_A") == _define(dev, "HC_CURRENT_CONTINUOUS_A") == p.i_max_A
    assert _define(h, "HC_IDENT_KT_NM_PER_A") == _define(dev, "HC_KT_NM_PER_A")
    assert _define(h, "HC_IDENT_KP_NM_PER_RAD") == p.kp_Nm_per_rad
    assert _define(h, "HC_IDENT_Q_MIN_RAD") == pred.q_min_rad and _define(h, "HC_IDENT_Q_MAX_RAD") == pred.q_max_rad
    assert pred.design_hash in h


@pytest.mark.parametrize("perturb", [["mass=1.15", "friction=2", "offset_mNm=3"],
                                     ["mass=0.8", "friction=0.5", "noise=0.02", "delay=3"]])
def test_c_routine_equals_reference_and_stays_within_limits(routine, pred, tmp_path, perturb):
    _, exe = routine
    t, counts, cmd, tr = bench.simulate(pred, bench.parse_perturb(perturb), seed=2)
    amps, status = _run(exe, counts, tmp_path / "log.csv")
    np.testing.assert_allclose(amps, cmd, rtol=0, atol=1e-12)
    assert status[-1] == 1 and np.all(status[:-1] == 0)  # HC_IDENT_DONE once, at the end
    assert np.max(np.abs(amps)) <= pred.i_max_A
    q = pred.angles(counts)
    assert pred.q_min_rad <= q.min() and q.max() <= pred.q_max_rad
    # the chirp does move the crank: more than a third of the range
    assert np.ptp(q) > (pred.q_max_rad - pred.q_min_rad) / 3
    log = logfile.parse_log((tmp_path / "log.csv").read_text(), "log.csv", 1, pred.i_max_A)
    assert log.design_hash == pred.design_hash and len(log.t_s) == len(counts)
    np.testing.assert_allclose(log.current_A[:, 0], cmd, rtol=1e-8, atol=1e-12)  # %.9g


def test_c_routine_refuses_a_reversed_encoder(routine, pred, tmp_path):
    _, exe = routine
    t, counts, cmd, tr = bench.simulate(pred, bench.parse_perturb(["encoder=-1"]), seed=0)
    amps, status = _run(exe, counts, tmp_path / "log.csv")
    assert np.all(amps == 0) and status[-1] == 3  # HC_IDENT_ENCODER
    assert tr["status"].startswith("stopped")
    assert math.isclose(float(np.max(np.abs(cmd))), 0.0)


def test_float_build_and_a_hostile_name(hoeken, paper_H, pred, tmp_path):
    """The routine compiles in the float build too, for a design whose name holds format
    (%s), quote, shell and markup specials, and its log header still parses with the hash."""
    from cad.firmware import firmware_files
    from cad.pipeline import design_hash

    d = hoeken.replace(name="ev$il #1 [x](y) =cmd ü 'q' %s &amp;")  # tests/regressions/test_hostile_strings.py
    for rel, text in firmware_files(d, _report(paper_H), design_hash(d)).items():
        p = tmp_path / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)
    fw = tmp_path / "firmware"
    (fw / "drv.c").write_text(DRIVER)
    exe = tmp_path / "drv_f"
    cmd = [compiler("c"), "-std=c99", "-O2", "-Wall", "-Wextra", "-pedantic", "-Werror", "-DHAPTICAD_USE_FLOAT",
           "-o", str(exe), str(fw / "drv.c"), str(fw / "identify" / "hapticad_identify.c"),
           str(fw / "hapticad_device.c"), "-lm"]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    t, counts, cmd_A, _ = bench.simulate(pred, bench.parse_perturb([]), seed=0)
    amps, status = _run(exe, counts[:8000], tmp_path / "log.csv")
    # float: angles to ~1e-7 rad relative, the hold's kp / Kt ~ 6 A/rad
    np.testing.assert_allclose(amps, cmd_A[:8000], rtol=0, atol=1e-4)
    log = logfile.parse_log((tmp_path / "log.csv").read_text(), "log.csv", 1, pred.i_max_A)
    assert log.design_hash == design_hash(d)
