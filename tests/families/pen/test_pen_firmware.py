"""The haptic pen's generated firmware (cad/families/pen/firmware.py through cad.firmware).

Independent references: the pen's inverse kinematics and its Jacobian q_dot = J_ik v of
:mod:`cad.kinematics.haptic_pen` (written for the GII, not for the firmware): the firmware's
forward kinematics must return the task pose the IK started from, and J_fk J_ik D = I (D
turns X_dot into the IK's task rates); tau = J^T F and the gravity torques must give the
task force F and the gradient of the potential energy through J_ik (virtual work), the
potential computed from the layout's 3-D body frames (cad/families/pen/layout.py) and the
solids' masses and COMs in report.json -- not from the firmware's planar formulas. The C is
compiled and run against the numpy model (the build's own test_device.c), and its motor
currents against each joint's own motor constants, by hand.
"""

from __future__ import annotations

import json
import math
import subprocess

import numpy as np
import pytest

from cad import tolerances as tol
from cad.device import resolve_device
from cad.device.readback import header_facts
from cad.families.pen import firmware as pfw
from cad.families.pen.layout import body_poses
from cad.firmware import linkage_model
from cad.firmware.device import device_spec
from cad.firmware.spec import G0_M_S2
from cad.kinematics import haptic_pen as hp
from tests.compilers import compiler
from tests.conftest import PEN_FORMATS


@pytest.fixture(scope="module")
def pen(shared_build):
    d, out, rep = shared_build("haptic_pen.toml", PEN_FORMATS, "inertia")
    spec = device_spec(d, rep, "test", "test", resolve_device(d), linkage_model(d))
    return d, out, rep, spec


def _task(d, n: int, seed: int = 1) -> np.ndarray:
    X = pfw.task_samples(d, np.random.default_rng(seed), n)
    _, st = hp.ik(d.mechanism, X)
    return X[st == 0]


def _D(X) -> np.ndarray:
    """X_dot -> v = (c_dot, w_yaw = cos(pitch) yaw_dot, w_pitch = pitch_dot) (haptic_pen)."""
    D = np.zeros((len(X), 5, 5))
    D[:, [0, 1, 2, 4], [0, 1, 2, 4]] = 1.0
    D[:, 3, 3] = np.cos(X[:, 4])
    return D


def test_forward_kinematics_returns_the_pose_the_ik_started_from(pen):
    d, _, _, spec = pen
    X = _task(d, 200)
    q, _ = hp.ik(d.mechanism, X)
    Xf, st = pfw.forward(spec, q)
    assert len(X) > 150 and np.all(st == 0)
    ref = np.column_stack([X[:, :3] * 1e-3, X[:, 3:]])
    assert np.abs(Xf - ref).max() < 1e-12


def test_jacobian_inverts_the_papers_jacobian_and_torques_give_the_force(pen):
    d, _, _, spec = pen
    X = _task(d, 100, seed=2)
    q, _ = hp.ik(d.mechanism, X)
    J_fk = pfw.jacobian(spec, q)
    J_ik = hp.jacobian_si(d.mechanism, X)[0] @ _D(X)  # q_dot per X_dot
    assert np.abs(J_fk @ J_ik - np.eye(5)).max() < 1e-9
    F = np.random.default_rng(3).uniform(-5, 5, (len(X), 5))
    tau = np.einsum("nij,ni->nj", J_fk, F)
    assert np.abs(np.einsum("nji,nj->ni", J_ik, tau) - F).max() < 1e-9  # virtual work


def _potential_J(d, rep, X_mm_rad) -> np.ndarray:
    """V (N,) J of every moving body at task poses (mm, rad): g z_COM from the layout's frames."""
    T = body_poses(d, X_mm_rad)
    V = np.zeros(len(X_mm_rad))
    for name, b in rep["bodies"].items():
        c = np.append(np.asarray(b["com_mm"], float), 1.0)
        V += b["mass_kg"] * G0_M_S2 * (T[name] @ c)[:, 2] * 1e-3
    return V


def test_gravity_torques_hold_the_potential_of_the_solids(pen):
    d, _, rep, spec = pen
    X = _task(d, 40, seed=4)
    q, _ = hp.ik(d.mechanism, X)
    tg, ok = pfw.gravity_extra(spec, q, pfw.GRAVITY_M_S2)
    J_ik = hp.jacobian_si(d.mechanism, X)[0] @ _D(X)
    h = np.array([1e-3, 1e-3, 1e-3, 1e-6, 1e-6])  # mm, rad
    grad = np.zeros((len(X), 5))
    for k in range(5):
        dX = np.zeros(5)
        dX[k] = h[k]
        dV = _potential_J(d, rep, X + dX) - _potential_J(d, rep, X - dX)
        grad[:, k] = dV / (2 * h[k] * (1e-3 if k < 3 else 1.0))  # N, N m
    assert ok.all()
    got = np.einsum("nji,nj->ni", J_ik, tg)
    assert np.abs(got - grad).max() < 1e-5 * np.abs(grad).max()
    assert np.abs(grad[:, 2]).min() > 1.0  # the weight of the moving bodies is felt along z


def test_the_build_compiles_and_matches_its_numpy_model(pen, tmp_path):
    _, out, _, _ = pen
    fw = out / "firmware"
    summary = json.loads((fw / "test_vectors.json").read_text())["summary"]
    assert summary["ok"] == 1200 and summary["refused"] == 60
    for use_float, tols in ((False, (tol.FIRMWARE_DOUBLE_POSITION_M, tol.FIRMWARE_DOUBLE_TORQUE_NM,
                                     tol.FIRMWARE_FD_JACOBIAN)),
                            (True, (tol.FIRMWARE_FLOAT_POSITION_M, tol.FIRMWARE_FLOAT_TORQUE_NM, 0.0))):
        exe = tmp_path / ("tf" if use_float else "td")
        subprocess.run([compiler("c"), "-std=c99", "-O2", "-Wall", "-Wextra", "-pedantic", "-Werror",
                        *(["-DHAPTICAD_USE_FLOAT"] if use_float else []), "-o", str(exe),
                        str(fw / "test_device.c"), str(fw / "hapticad_device.c"), "-lm"],
                       check=True, capture_output=True, timeout=120)
        r = subprocess.run([str(exe), str(fw / "test_vectors.json"), *map(repr, tols)],
                           capture_output=True, text=True, timeout=120)
        assert r.returncode == 0 and "failures 0" in r.stdout, r.stdout + r.stderr


CURRENTS = r"""
#include <stdio.h>
#include "hapticad_device.h"
int main(int argc, char **argv)
{
    hc_real tau[HC_N_JOINTS], a[HC_N_JOINTS];
    int i, r;
    for (i = 0; i < HC_N_JOINTS; ++i) tau[i] = (hc_real)atof(argv[2 + i]);
    (void)argc;
    r = hc_motor_currents(tau, atoi(argv[1]), a);
    printf("%d", r);
    for (i = 0; i < HC_N_JOINTS; ++i) printf(" %.17g", (double)a[i]);
    printf("\n");
    return 0;
}
"""


def test_each_joint_has_its_own_motor_in_the_header_and_the_currents(pen, tmp_path):
    """RE 40 waists and RE 35 shoulders: the header states each joint's Kt and limits (the
    resolved device's, which the BOM orders); hc_motor_currents divides by each joint's Kt
    and scales all currents by the one joint furthest over its own limit."""
    d, out, _, _ = pen
    fw = out / "firmware"
    h = header_facts((fw / "hapticad_device.h").read_text())
    motors = resolve_device(d).motors
    assert [m.catalog_key for m in motors] == ["maxon-re40", "maxon-re35", "maxon-re35"] * 2
    assert h["kt_Nm_per_A"] is None  # no one value for motors that differ
    assert h["kt_Nm_per_A_joints"] == [m.kt_Nm_per_A for m in motors]
    assert h["current_continuous_A_joints"] == [m.spec.current_continuous_A for m in motors]
    src = tmp_path / "cur.c"
    src.write_text("#include <stdlib.h>\n" + CURRENTS)
    exe = tmp_path / "cur"
    subprocess.run([compiler("c"), "-std=c99", "-O2", "-I", str(fw), "-o", str(exe), str(src),
                    str(fw / "hapticad_device.c"), "-lm"], check=True, capture_output=True, timeout=120)
    kt = np.array(h["kt_Nm_per_A_joints"])
    ic = np.array(h["current_continuous_A_joints"])

    def run(tau):
        r = subprocess.run([str(exe), "0", *map(repr, map(float, tau))], capture_output=True,
                           text=True, check=True, timeout=60).stdout.split()
        return int(r[0]), np.array([float(v) for v in r[1:]])

    scaled, amps = run(kt * 1.0)  # 1 A in every motor: under every limit
    assert scaled == 0 and np.allclose(amps, 1.0, rtol=1e-14)
    tau = kt * 1.0
    tau[0] = kt[0] * 2 * ic[0]  # the RE 40 at twice its continuous current
    scaled, amps = run(tau)
    assert scaled == 1 and amps[0] == pytest.approx(ic[0], rel=1e-14)
    assert np.allclose(amps[1:], (tau / kt)[1:] / 2, rtol=1e-14) and np.all(np.abs(amps) <= ic * (1 + 1e-14))


def test_chai3d_and_wall_state_the_datasheets_figures(pen):
    _, out, rep, _ = pen
    fw = out / "firmware"
    rows = {r["key"]: r for r in rep["datasheet"]["rows"]}
    chai = json.loads((fw / "chai3d_device.json").read_text())
    assert chai["encoder_counts_per_rev"] == 4000 and chai["m_sensedRotation"]
    assert chai["m_maxLinearForce"] == rows["continuous_force_N"]["value"]
    assert chai["m_maxLinearStiffness"] == rows["eq25_K_max_N_per_m"]["value"]
    sketch = (fw / "wall_example" / "wall_example.ino").read_text()
    K = float(sketch.split("#define WALL_K_N_PER_M ", 1)[1].split("\n", 1)[0])
    assert K == rows["eq25_K_max_N_per_m"]["value"]
    assert math.isclose(chai["m_workspaceRadius"], 0.05)  # half the 100 mm side of the box
