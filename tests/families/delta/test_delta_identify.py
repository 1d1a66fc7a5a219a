"""Identification of a built delta (issue 37 for the 3-DOF family): the prediction, the
3-motor routine and the fit against independent references.

* the links' inverse dynamics (Euler-Lagrange of J_x^T Lambda J_x, :mod:`cad.identify.jointn`)
  against MuJoCo's forward dynamics of the build's MJCF (a second library, the loops closed by
  its own constraint solver) and against the power balance q'^T tau = dT/dt (closed form);
* the solids' gravity torques against the point-mass model the firmware compensates with
  (exact for rods split half and half: the potential is linear in the centres) and against
  central differences of the potential of the posed bodies;
* the generated C routine (3 motors) compiled and run on a bench run's counts: its currents
  equal the Python reference's;
* recovery on the virtual bench (MuJoCo): links +15 %, Coulomb friction x2, a 3 mN m offset.
  Stated tolerances (the fit's bias on these logs, measured, with margin): apparent mass 2 %
  (measured -0.3 to +0.1 %), Coulomb friction 10 % (measured +1 to +4 %), gravity load and
  offset 1 mN m; the reversed encoder and the reversed current gain are named.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
import pytest

from cad.design import load_design
from cad.identify import jointn, logfile
from cad.sim.bench import parse_perturb
from cad.sim.identify_fivebar import build_folder
from tests.cli_helpers import assert_one_line_error, hapticad, hapticad_json
from tests.conftest import DELTA_FORMATS

ROOT = Path(__file__).resolve().parents[3]
mujoco = pytest.importorskip("mujoco")


@pytest.fixture(scope="module")
def delta():
    return load_design(ROOT / "designs" / "delta.toml")


@pytest.fixture(scope="module")
def built(delta, shared_build):
    """The bundled delta's shared build (tests/conftest.py ``DELTA_FORMATS``: its MJCF and
    meshes), read as ``--build-dir`` (one delta build per run, not one more here)."""
    from cad.families.delta import identify as di

    folder, rep = build_folder(delta, shared_build("delta.toml", DELTA_FORMATS, "preview")[1])
    return folder, rep, di.predict(delta, rep)


def _q(pred, dq):
    return np.array(pred.q_home_rad) + np.asarray(dq, float)


def test_inverse_dynamics_equal_mujoco_forward_dynamics(built):
    from cad.families.delta.identify import MujocoPlantDelta
    from cad.sim import bench_joints, mj

    folder, _, pred = built
    tr = bench_joints.truth(pred, parse_perturb([]))
    pl = MujocoPlantDelta(folder / "delta.xml", tr, [-3.0] * 3, [3.0] * 3, 10.0)
    pl.m.opt.gravity[:] = 0.0
    for v in pl.iv:
        pl.m.dof_frictionloss[v] = 0.0
    for dq, v, tau in (([0.1, -0.05, 0.2], [2.0, -1.0, 1.5], [0.05, -0.02, 0.03]),
                       ([-0.1, 0.15, 0.0], [-1.0, 0.5, 3.0], [0.0, 0.04, -0.01])):
        q = _q(pred, dq)
        pl.place(q)
        pl.d.qvel[:] = mj.null_basis(pl.m, pl.d, list(pl.JOINTS)) @ np.asarray(v)
        for a, t in zip(pl.ia, tau, strict=True):
            pl.d.ctrl[a] = t
        mujoco.mj_forward(pl.m, pl.d)
        acc_mj = np.array([pl.d.qacc[k] for k in pl.iv])
        h = jointn.lagrange_torques(pred.link_mass_kg, q[None], np.asarray(v)[None], np.zeros((1, 3)))[0]
        acc = np.linalg.solve(pred.joint_mass_kg(q[None])[0], np.asarray(tau) - h)
        np.testing.assert_allclose(acc, acc_mj, rtol=5e-3, atol=1e-3 * np.max(np.abs(acc_mj)))


def test_power_balance_along_a_trajectory(built):
    """q'^T tau_links = dT/dt with T = 1/2 q'^T M q' (closed form, any trajectory)."""
    _, _, pred = built
    t = np.linspace(0.0, 0.5, 501)
    q = _q(pred, 0.0) + 0.2 * np.column_stack([np.sin(7 * t), np.sin(11 * t + 1), np.sin(5 * t + 2)])
    v = 0.2 * np.column_stack([7 * np.cos(7 * t), 11 * np.cos(11 * t + 1), 5 * np.cos(5 * t + 2)])
    a = -0.2 * np.column_stack([49 * np.sin(7 * t), 121 * np.sin(11 * t + 1), 25 * np.sin(5 * t + 2)])
    tau = jointn.lagrange_torques(pred.link_mass_kg, q, v, a)
    T = 0.5 * np.einsum("ni,nij,nj->n", v, pred.link_mass_kg(q), v)
    dT = np.gradient(T, t)
    np.testing.assert_allclose(np.sum(v * tau, axis=1)[5:-5], dT[5:-5], atol=2e-3 * np.max(np.abs(dT)))


def test_solids_gravity_equals_the_point_model_and_the_potential(built, delta):
    from cad.dynamics.delta import gravity_torques_Nm
    from cad.families.delta.layout import poses_at

    _, _, pred = built
    qs = np.array([_q(pred, dq) for dq in ([0, 0, 0], [0.2, -0.1, 0.05], [-0.15, 0.1, 0.3])])
    g = pred.gravity(qs)
    np.testing.assert_allclose(g, gravity_torques_Nm(pred.delta, pred.points_mm(qs), pred.mass), rtol=1e-9)

    def V(q):  # the posed bodies' potential, J (centres from their frames, mm)
        P = pred.points_mm(q[None])
        tf = poses_at(pred.delta, P, q[None], delta.parallelogram_width_mm)
        return sum(mp.mass_kg * 9.80665 * 1e-3 * (tf[b][0, :3, :3] @ (np.asarray(mp.com_m) * 1e3) + tf[b][0, :3, 3])[2]
                   for b, mp in pred.props.items() if b in tf)

    for q, gq in zip(qs, g, strict=True):
        fd = [(V(q + e) - V(q - e)) / 2e-6 for e in np.eye(3) * 1e-6]
        np.testing.assert_allclose(gq, fd, rtol=1e-5, atol=1e-7)


@pytest.fixture(scope="module")
def bench_run(built, delta):
    from cad.families.delta import identify as di

    folder, _, pred = built
    t, counts, cmd, tr = di.simulate(delta, pred, parse_perturb(["mass=1.15", "friction=2", "offset_mNm=3"]), 0,
                                     folder / "delta.xml")
    return t, counts, cmd, tr


def _fig(res, key):
    return next(r for r in res["figures"] if r["key"] == key)


def test_bench_recovers_perturbed_parameters(built, bench_run):
    from cad.sim import identify_joints

    _, _, pred = built
    t, counts, cmd, tr = bench_run
    assert tr["status"] == "done" and np.max(np.abs(cmd)) <= pred.i_max_A
    text = logfile.format_log(logfile.header_line("delta", pred.design_hash, "test", pred.Te_s), t, counts, cmd)
    res, f = identify_joints.identify(pred, logfile.parse_log(text, "t.csv", 3, pred.i_max_A), "t.csv")
    for ax in "xyz":
        r = _fig(res, f"M{ax}{ax}_g@home")
        assert r["value"] == pytest.approx(tr[f"M{ax}{ax}_g_home"], rel=0.02)
        assert r["verdict"] == "MISS"  # 15 % heavier than the solids say
    for j in range(3):
        assert _fig(res, f"Tc{j}_mNm")["value"] * 1e-3 == pytest.approx(tr["Tc_Nm"][j], rel=0.10)
        assert _fig(res, f"encoder_direction_{j}")["verdict"] == "within"
        assert _fig(res, f"current_gain_sign_{j}")["verdict"] == "within"
    q_med = np.median(f.q[f.mask.any(axis=1)], axis=0)
    true_load = tr["c_link"] * tr["gravity_scale"] * pred.gravity(q_med[None])[0] + np.array(tr["offset_Nm"])
    for j in range(3):
        assert _fig(res, f"gravity_load{j}_mNm")["value"] * 1e-3 == pytest.approx(true_load[j], abs=1e-3)


def test_c_routine_equals_reference(delta, built, bench_run, tmp_path):
    from cad.firmware import firmware_files
    from cad.pipeline import design_hash
    from tests.compilers import compiler

    _, rep, pred = built
    for rel, text in firmware_files(delta, rep, design_hash(delta)).items():
        p = tmp_path / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)
    fw = tmp_path / "firmware"
    (fw / "drv.c").write_text(DRIVER)
    cmd = [compiler("c"), "-std=c99", "-O2", "-Wall", "-Wextra", "-pedantic", "-Werror", "-o", str(tmp_path / "drv"),
           str(fw / "drv.c"), str(fw / "identify" / "hapticad_identify.c"), str(fw / "hapticad_device.c"), "-lm"]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    t, counts, amps_py, _ = bench_run
    r = subprocess.run([str(tmp_path / "drv"), str(tmp_path / "log.csv")], capture_output=True, text=True,
                       input="\n".join(" ".join(map(str, c)) for c in counts) + "\n", timeout=120)
    rows = np.array([ln.split() for ln in r.stdout.split("\n") if ln], dtype=float)
    np.testing.assert_allclose(rows[:, :3], amps_py, rtol=0, atol=1e-9)
    assert rows[-1, 3] == 1 and np.all(rows[:-1, 3] == 0)  # HC_IDENT_DONE once, at the end
    log = logfile.parse_log((tmp_path / "log.csv").read_text(), "log.csv", 3, pred.i_max_A)
    np.testing.assert_array_equal(log.counts, counts)
    h = (fw / "identify" / "hapticad_identify.h").read_text()
    assert "straight up (+z)" in h and "#define HC_IDENT_SWEEP_2 2" in h


DRIVER = r"""
#include <stdio.h>
#include "identify/hapticad_identify.h"
int main(int argc, char **argv) {
    hc_ident_t s; hc_encoder_t enc = HC_ENCODER_DEFAULT; long c[3]; hc_real a[3]; char buf[256];
    FILE *log = fopen(argc > 1 ? argv[1] : "log.csv", "w");
    long k = 0;
    hc_ident_init(&s);
    hc_ident_log_header(buf, sizeof buf); fputs(buf, log);
    while (scanf("%ld %ld %ld", &c[0], &c[1], &c[2]) == 3) {
        int st = hc_ident_step(&s, &enc, c, a);
        printf("%.17g %.17g %.17g %d\n", (double)a[0], (double)a[1], (double)a[2], st);
        hc_ident_log_row(buf, sizeof buf, (hc_real)k * HC_IDENT_TE_S, c, a); fputs(buf, log);
        ++k;
    }
    fclose(log);
    return 0;
}
"""


@pytest.mark.slow
def test_cli_names_a_reversed_encoder_and_a_reversed_gain(tmp_path):
    design = ROOT / "designs" / "delta.toml"
    for pert, key in (("encoder=-1", "encoder_direction_0"), ("kt=-1", "current_gain_sign_0")):
        log = tmp_path / f"{key}.csv"
        code, _, err = hapticad("bench-log", design, "--out", log, "--perturb", pert)
        assert code == 0, err
        res = hapticad_json("identify", design, log)
        assert key in res["misses"], res["misses"]


def test_a_two_motor_log_is_refused_in_one_line(tmp_path):
    log = tmp_path / "two.csv"
    log.write_text("# hapticad identification log; design delta; design hash sha256:" + "0" * 64 + "\n"
                   "t_s,counts_0,counts_1,current_A_0,current_A_1\n0,0,0,0,0\n0.001,0,0,0,0\n")
    code, _, err = hapticad("identify", ROOT / "designs" / "delta.toml", log)
    assert_one_line_error(code, err, "LOG")
