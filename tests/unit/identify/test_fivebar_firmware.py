"""The generated 2-motor identification routine of the 5-bar pantograph (issue 37 §1):
``firmware/identify/hapticad_identify.c`` written by ``--formats firmware`` for a pantograph,
compiled with the system C compiler (-std=c99 -Wall -Wextra -pedantic -Werror, double and
float builds) and run on the counts of virtual-bench runs: its currents equal the Python
reference (:func:`cad.identify.excitation2.step`) that drove the bench, its log parses in
the public format with two counts and two current columns, and it refuses a reversed
encoder. The header's constants are the plan's and the device header's."""

from __future__ import annotations

import re
import subprocess

import numpy as np
import pytest

from cad.identify import logfile
from cad.sim import bench, bench_fivebar
from tests.compilers import compiler

DRIVER = r"""
#include <stdio.h>
#include "identify/hapticad_identify.h"
int main(int argc, char **argv) {
    hc_ident_t s; hc_encoder_t enc = HC_ENCODER_DEFAULT; long c[2]; hc_real a[2]; char buf[256];
    FILE *log = fopen(argc > 1 ? argv[1] : "log.csv", "w");
    long k = 0;
    hc_ident_init(&s);
    hc_ident_log_header(buf, sizeof buf); fputs(buf, log);
    while (scanf("%ld %ld", &c[0], &c[1]) == 2) {
        int st = hc_ident_step(&s, &enc, c, a);
        printf("%.17g %.17g %d\n", (double)a[0], (double)a[1], st);
        hc_ident_log_row(buf, sizeof buf, (hc_real)k * HC_IDENT_TE_S, c, a); fputs(buf, log);
        ++k;
    }
    fclose(log);
    return 0;
}
"""


def _build(tmp, design, report, flags=()):
    from cad.firmware import firmware_files
    from cad.pipeline import design_hash

    files = firmware_files(design, report, design_hash(design))
    for rel, text in files.items():
        p = tmp / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)
    fw = tmp / "firmware"
    (fw / "drv.c").write_text(DRIVER)
    exe = tmp / "drv"
    cmd = [compiler("c"), "-std=c99", "-O2", "-Wall", "-Wextra", "-pedantic", "-Werror", *flags, "-o", str(exe),
           str(fw / "drv.c"), str(fw / "identify" / "hapticad_identify.c"), str(fw / "hapticad_device.c"), "-lm"]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    return fw, exe, files


@pytest.fixture(scope="module")
def routine(tmp_path_factory, panto, bars):
    return _build(tmp_path_factory.mktemp("fw5"), panto, bars(panto))


def _run(exe, counts, log_path):
    r = subprocess.run([str(exe), str(log_path)], input="\n".join(f"{a} {b}" for a, b in counts) + "\n",
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    rows = np.array([ln.split() for ln in r.stdout.split("\n") if ln], dtype=float)
    return rows[:, :2], rows[:, 2].astype(int)


def _define(text: str, name: str) -> float:
    return float(re.search(rf"#define {name} HC_R\(([^)]+)\)", text).group(1))


def test_formats_firmware_writes_the_routine_for_a_pantograph(routine):
    _, _, files = routine
    assert {"firmware/identify/hapticad_identify.h", "firmware/identify/hapticad_identify.c",
            "firmware/identify/identify_example.ino"} <= set(files)
    assert "t_s,counts_0,counts_1,current_A_0,current_A_1" in files["firmware/identify/hapticad_identify.c"]


def test_header_constants_are_the_plan_and_the_device(routine, panto_pred):
    fw, _, _ = routine
    h = (fw / "identify" / "hapticad_identify.h").read_text()
    dev = (fw / "hapticad_device.h").read_text()
    p = panto_pred.plan
    assert _define(h, "HC_IDENT_I_MAX_A") == _define(dev, "HC_CURRENT_CONTINUOUS_A") == p.i_max_A
    assert _define(h, "HC_IDENT_KT_NM_PER_A") == _define(dev, "HC_KT_NM_PER_A")
    assert _define(h, "HC_IDENT_TE_S") == p.Te_s
    for j in range(2):
        assert _define(h, f"HC_IDENT_KP_NM_PER_RAD_{j}") == p.kp_Nm_per_rad[j]
        assert _define(h, f"HC_IDENT_Q_MIN_RAD_{j}") == p.q_min_rad[j]
        assert _define(h, f"HC_IDENT_Q_HOME_RAD_{j}") == p.q_home_rad[j]
        assert _define(h, f"HC_IDENT_ENVELOPE_RAD_{j}") == p.envelope_rad[j]
        assert f"#define HC_IDENT_HAND_SIGN_{j} {p.hand_sign[j]}" in h
    assert panto_pred.design_hash in h


@pytest.mark.parametrize("perturb", [["mass=1.15", "friction=2", "offset_mNm=3"],
                                     ["mass=0.8", "friction=0.5", "noise=0.02", "delay=3"]])
def test_c_routine_equals_reference(routine, panto_pred, tmp_path, perturb):
    _, exe, _ = routine
    pred = panto_pred
    t, counts, cmd, tr = bench_fivebar.simulate(pred, bench.parse_perturb(perturb), seed=2)
    assert tr["status"] == "done"
    amps, status = _run(exe, counts, tmp_path / "log.csv")
    np.testing.assert_allclose(amps, cmd, rtol=0, atol=1e-12)
    assert status[-1] == 1 and np.all(status[:-1] == 0)  # HC_IDENT_DONE once, at the end
    assert np.max(np.abs(amps)) <= pred.i_max_A
    log = logfile.parse_log((tmp_path / "log.csv").read_text(), "log.csv", 2, pred.i_max_A)
    assert log.design_hash == pred.design_hash and len(log.t_s) == len(counts)
    np.testing.assert_array_equal(log.counts, counts)
    np.testing.assert_allclose(log.current_A, cmd, rtol=1e-8, atol=1e-12)  # %.9g


def test_c_routine_refuses_a_reversed_encoder_and_a_reversed_gain(routine, panto_pred, tmp_path):
    _, exe, _ = routine
    t, counts, cmd, tr = bench_fivebar.simulate(panto_pred, bench.parse_perturb(["encoder=-1"]), seed=0)
    amps, status = _run(exe, counts, tmp_path / "log.csv")
    assert np.all(amps == 0) and status[-1] == 3  # HC_IDENT_ENCODER
    t, counts, cmd, tr = bench_fivebar.simulate(panto_pred, bench.parse_perturb(["kt=-1"]), seed=0)
    amps, status = _run(exe, counts, tmp_path / "log2.csv")
    np.testing.assert_allclose(amps, cmd, rtol=0, atol=1e-12)
    assert status[-1] == 2  # HC_IDENT_RANGE: the hold pushed a joint out of its envelope


def test_float_build(panto, bars, panto_pred, tmp_path):
    """The routine compiles in the float build too and follows the reference to float accuracy."""
    _, exe, _ = _build(tmp_path, panto, bars(panto), ("-DHAPTICAD_USE_FLOAT",))
    t, counts, cmd, _ = bench_fivebar.simulate(panto_pred, bench.parse_perturb([]), seed=0)
    amps, status = _run(exe, counts, tmp_path / "log.csv")
    assert status[-1] == 1
    np.testing.assert_allclose(amps, cmd, rtol=0, atol=1e-3 * panto_pred.i_max_A)


def test_vertical_routine_adds_the_gravity_torques(bars, tmp_path):
    """A vertical 5-bar: the C routine adds hc_gravity_torques to its hold; its currents equal
    the reference run with the numpy gravity torques (cad.firmware.reference) at the angles
    read, to the device code's stated torque accuracy (1e-9 N m) over Kt."""
    from cad import tolerances as tol
    from cad.design import load_design
    from cad.identify import excitation2
    from cad.sim.identify_fivebar import predict
    from tests.unit.identify.conftest import ROOT

    p = tmp_path / "vertical.toml"
    p.write_text((ROOT / "designs" / "pantograph.toml").read_text() + '\n[firmware]\nplane = "vertical"\n')
    d = load_design(p)
    rep = bars(d, handle_kg=0.005, rho_kg_per_m=0.08)
    pred = predict(d, rep)
    fw, exe, _ = _build(tmp_path, d, rep)
    assert "#define HC_IDENT_GRAVITY_FF 1" in (fw / "identify" / "hapticad_identify.h").read_text()
    t, counts, cmd, tr = bench_fivebar.simulate(pred, bench.parse_perturb(["mass=1.15"]), seed=1)
    assert tr["status"] == "done"
    q = pred.angles(counts)
    ref = excitation2.run_on_angles(pred.plan, q, pred.gravity(q))
    amps, status = _run(exe, counts, tmp_path / "log.csv")
    assert status[-1] == 1
    np.testing.assert_allclose(amps, ref, rtol=0, atol=2 * tol.FIRMWARE_DOUBLE_TORQUE_NM / pred.kt_Nm_per_A)
    # the bench's feed-forward (a bilinear table of the same torques): measured 1.0e-4 A off it
    np.testing.assert_allclose(cmd, ref, rtol=0, atol=3e-4)
    assert np.max(np.abs(ref[2000:])) > 0.5  # the hold carries the links: ~0.8 A


def test_a_vertical_device_too_heavy_to_excite(bars, tmp_path):
    """Heavy links on a vertical 5-bar whose weight at home takes more than the motors'
    continuous current: predict names firmware.plane in one line; the firmware is written
    without identify/, with a warning."""
    from cad.design import bounds, load_design
    from cad.errors import DesignError
    from cad.firmware import firmware_files
    from cad.pipeline import design_hash
    from cad.sim.identify_fivebar import predict
    from tests.unit.identify.conftest import ROOT

    p = tmp_path / "heavy.toml"
    p.write_text((ROOT / "designs" / "pantograph.toml").read_text() + '\n[firmware]\nplane = "vertical"\n')
    d = load_design(p)
    rep = bars(d, handle_kg=0.1, rho_kg_per_m=0.3)
    with pytest.raises(DesignError, match="firmware.plane: the identification routine cannot run"):
        predict(d, rep)
    bounds.reset()
    files = firmware_files(d, rep, design_hash(d))
    assert "firmware/hapticad_device.c" in files and not any("identify/" in f for f in files)
    assert any("no identify/ routine" in w and "firmware.plane" in w for w in bounds.collected())
    bounds.reset()
