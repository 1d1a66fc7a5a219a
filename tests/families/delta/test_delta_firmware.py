"""The delta's generated firmware (``--formats firmware``, cad/families/delta/firmware.py
through the generic writers of :mod:`cad.firmware`) compiled with the system C compiler and
run against the numpy model: IK angles and status, FK, the Jacobian (J^-1 of
:func:`cad.kinematics.delta.jacobian_rad_per_m`, and central finite differences of the C's
own FK), tau = J^T F, the gravity torques of :func:`cad.dynamics.delta.gravity_torques_Nm`
and the mass matrix of :func:`cad.dynamics.delta.mass_matrix_kg`, at the workspace grid plus
seeded random points of both bundled designs, some unreachable or outside the joint limits
(the C must refuse those with the same status). Double build to round-off (1e-12 rad,
:data:`cad.tolerances.FIRMWARE_DOUBLE_POSITION_M`), float build to the float tolerances.

Independent of the numpy model: the gravity torques against central differences of the
potential energy V(theta) written out here from the FK (a second path beside J^-T grad V);
the motor constants and the encoder count in the header against the design's ``[motor]``
table and ``[parts]`` encoder; the build's own ``test_device.c`` over ``test_vectors.json``.
"""

from __future__ import annotations

import copy
import json
import re
import subprocess
import tomllib
from pathlib import Path

import numpy as np
import pytest

import cad
from cad import tolerances as tol
from cad.data.catalog import get_motor
from cad.design import load_design, parse_design
from cad.device import resolve_device
from cad.device.readback import header_facts
from cad.dynamics.delta import G_M_S2, DeltaMass
from cad.families.delta.firmware import (
    DELTA,
    GRAVITY_M_S2,
    params_of,
    reference_vectors,
    vectors_c,
)
from cad.firmware import csrc, linkage_files
from cad.firmware.spec import DeviceSpec, motor_data
from cad.kinematics.delta import fk, ik
from tests.compilers import compiler

ROOT = Path(__file__).resolve().parents[3]
MASS = DeltaMass(upper_arm_kg_m2=2e-4, upper_arm_kg=0.05, upper_arm_com_mm=40.0,
                 lower_arm_kg=0.03, effector_kg=0.08, rotor_kg_m2=7.92e-6)
#: The Falcon's (g > 0) with a knee link: its mass, centre along it and inertia about its pin.
MASS_KNEE = DeltaMass(**{**vars(MASS), "knee_kg": 0.012, "knee_com_mm": 16.0, "knee_kg_m2": 5e-6})

MAIN = r"""
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "hapticad_device.h"
#include "vectors.h"

static double worst[8];
static void keep(int k, double e) { if (e > worst[k]) worst[k] = e; }

int main(void)
{
    int n, i, k, bad_status = 0, ok_rows = 0, fk_rows = 0;
    for (n = 0; n < V_N; ++n) {
        hc_real P[3], th[3], Pf[3], Jx[9], F[3], tau[3], tg[3], Pp[3], Pm[3], tp[3], M[9];
        int st;
        for (i = 0; i < 3; ++i) { P[i] = (hc_real)V_P_m[3 * n + i]; F[i] = (hc_real)V_F_N[3 * n + i]; }
        st = hc_inverse(P, th);
        if (st != (int)V_ik_status[n]) { ++bad_status; printf("row %d status %d want %d\n", n, st, (int)V_ik_status[n]); }
        if (st) continue;
        ++ok_rows;
        for (i = 0; i < 3; ++i) keep(0, fabs(th[i] - V_theta_rad[3 * n + i]));
        for (i = 0; i < 3; ++i) th[i] = (hc_real)V_theta_rad[3 * n + i];
        st = hc_forward(th, Pf);
        if (st != (int)V_fk_status[n]) { ++bad_status; printf("row %d fk status %d want %d\n", n, st, (int)V_fk_status[n]); }
        if (st) continue;
        ++fk_rows;
        for (i = 0; i < 3; ++i) keep(1, fabs(Pf[i] - V_P_fk_m[3 * n + i]));
        hc_jacobian(th, Jx);
        for (i = 0; i < 9; ++i) keep(2, fabs(Jx[i] - V_Jx_m_per_rad[9 * n + i]));
        hc_joint_torques(th, F, tau);
        hc_gravity_torques(th, tg);
        hc_mass_matrix(th, M);
        for (i = 0; i < 3; ++i) keep(3, fabs(tau[i] - V_tau_Nm[3 * n + i]));
        for (i = 0; i < 3; ++i) keep(4, fabs(tg[i] - V_tau_gravity_Nm[3 * n + i]));
        for (i = 0; i < 9; ++i) keep(6, fabs(M[i] - V_M_kg[9 * n + i]) / fabs(V_M_kg[0] + V_M_kg[4] + V_M_kg[8]));
        for (k = 0; k < 3; ++k) {           /* column k against central differences of FK */
            for (i = 0; i < 3; ++i) tp[i] = th[i];
            tp[k] = th[k] + HC_R(1e-6); hc_forward(tp, Pp);
            tp[k] = th[k] - HC_R(1e-6); hc_forward(tp, Pm);
            for (i = 0; i < 3; ++i) keep(5, fabs((Pp[i] - Pm[i]) / 2e-6 - Jx[3 * i + k]));
        }
    }
    printf("theta %.3e P %.3e Jx %.3e tau %.3e grav %.3e fd %.3e M %.3e bad %d ok %d fk %d\n", worst[0],
           worst[1], worst[2], worst[3], worst[4], worst[5], worst[6], bad_status, ok_rows, fk_rows);
    return 0;
}
"""


def device_spec(des, mass: DeltaMass = MASS) -> DeviceSpec:
    """A DeviceSpec of ``des`` with ``mass`` (any delta, the Falcon's knee included: no build)."""
    home = ik(des.mechanism, np.asarray(des.workspace["center_mm"])[None]).theta_rad[0]
    return DeviceSpec(kind="delta", name=des.name, family="delta", design_hash="ab12",
                      version=cad.__version__, n_joints=3, n_task=3,
                      params=params_of(des.mechanism, mass), q_home_rad=tuple(home),
                      encoder_counts_per_rev=2000, encoder_direction=(1, 1, 1),
                      encoder_zero_rad=tuple(home), motor=motor_data(get_motor("maxon-re35")),
                      gravity_m_s2=GRAVITY_M_S2, model=DELTA)


def _points(des, rng):
    """Workspace grid, random points around it (some out of reach or the joint limits)."""
    grid = des.workspace_points()
    c = np.asarray(des.workspace["center_mm"])
    wide = c + rng.uniform(-1, 1, size=(60, 3)) * np.array([1.5, 1.5, 2.5]) * des.params["upper_arm_mm"]
    return np.vstack([grid, wide])


def _compile(tmp: Path, files: dict, main: str, use_float: bool = False) -> Path:
    for name, text in {**files, "main.c": main}.items():
        (tmp / name).write_text(text)
    exe = tmp / ("t_f" if use_float else "t_d")
    flags = ["-DHAPTICAD_USE_FLOAT"] if use_float else []
    cmd = [compiler("c"), "-std=c99", "-O2", "-Wall", "-Wextra", "-pedantic", "-Werror", *flags,
           "-I", str(tmp), "-o", str(exe), str(tmp / "main.c"), str(tmp / "hapticad_device.c"), "-lm"]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    return exe


def _run(tmp: Path, spec, vec_text: str, use_float: bool) -> dict:
    files = {"hapticad_device.h": csrc.header(spec), "hapticad_device.c": csrc.source(spec),
             "vectors.h": vec_text}
    r = subprocess.run([str(_compile(tmp, files, MAIN, use_float))], capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 0, r.stdout + r.stderr
    last = r.stdout.strip().splitlines()[-1]
    return {k: float(v) for k, v in re.findall(r"(\w+) ([-+0-9.e]+)", last)}


@pytest.mark.parametrize("name", ["delta.toml", "delta_falcon.toml"])
@pytest.mark.parametrize("use_float", [False, True])
def test_c_matches_numpy(tmp_path, name, use_float):
    des = load_design(ROOT / "designs" / name)
    rng = np.random.default_rng(7)
    P = _points(des, rng)
    F = rng.normal(scale=5.0, size=P.shape)
    mass = MASS_KNEE if des.mechanism.joint_offset_mm > 0 else MASS
    vec = reference_vectors(des.mechanism, mass, P, F)
    n_ok = int(np.sum(vec["ik_status"] == 0))
    assert 0 < n_ok < len(P)  # both kinds of row are exercised
    assert set(vec["ik_status"]) >= {0, 2}  # ok and out of reach
    got = _run(tmp_path, device_spec(des, mass), vectors_c(vec), use_float)
    assert got["ok"] == n_ok
    assert got["fk"] >= len(des.workspace_points())  # the whole grid, and some points more
    if use_float:
        # float: statuses near a reach edge may differ; values at rows both call ok
        assert got["P"] < tol.FIRMWARE_FLOAT_POSITION_M
        assert got["tau"] < tol.FIRMWARE_FLOAT_TORQUE_NM
        assert got["grav"] < tol.FIRMWARE_FLOAT_TORQUE_NM
        assert got["M"] < tol.FIRMWARE_FLOAT_POSITION_M
        return
    assert got["bad"] == 0
    assert got["theta"] < 1e-12
    assert got["P"] < tol.FIRMWARE_DOUBLE_POSITION_M
    assert got["Jx"] < tol.FIRMWARE_DOUBLE_POSITION_M
    assert got["tau"] < tol.FIRMWARE_DOUBLE_TORQUE_NM
    assert got["grav"] < tol.FIRMWARE_DOUBLE_TORQUE_NM
    assert got["fd"] < tol.FIRMWARE_FD_JACOBIAN
    assert got["M"] < tol.FIRMWARE_DOUBLE_POSITION_M


def potential_J(d, theta: np.ndarray, m: DeltaMass) -> np.ndarray:
    """V(theta) (N,) J written out from the FK: effector at z_P, each arm's centre at
    z = -c sin(theta) (c its distance from the motor axis), each parallelogram's centre
    halfway between its elbow (z = -L_a sin theta) and the effector joint (z_P)."""
    zP = fk(d, theta).P_mm[:, 2] * 1e-3
    zE = -d.upper_arm_mm * 1e-3 * np.sin(theta)
    zG = -m.upper_arm_com_mm * 1e-3 * np.sin(theta)
    return G_M_S2 * (m.effector_kg * zP + np.sum(m.upper_arm_kg * zG + m.lower_arm_kg * (zE + zP[:, None]) / 2,
                                                    axis=1))


GRAVITY_MAIN = r"""
#include <stdio.h>
#include "hapticad_device.h"
#include "vectors.h"
int main(void)
{
    int n, i;
    for (n = 0; n < V_N; ++n) {
        hc_real th[3], tg[3];
        for (i = 0; i < 3; ++i) th[i] = (hc_real)V_theta_rad[3 * n + i];
        if (hc_gravity_torques(th, tg)) return 1;
        printf("%.17g %.17g %.17g\n", tg[0], tg[1], tg[2]);
    }
    return 0;
}
"""


def potential_knee_J(d, theta: np.ndarray, m: DeltaMass) -> np.ndarray:
    """V(theta) (N,) J of a delta with Stamper's knee, written out from the FK: as
    :func:`potential_J` with each parallelogram's centre halfway between its top bar (the knee's
    end, z_E + g k_z) and the effector joint, and each knee's centre at z_E + c_k k_z, k the unit
    in-plane direction elbow -> effector joint (the knee in line with the rods' projection)."""
    P = fk(d, theta).P_mm * 1e-3
    V = m.effector_kg * P[:, 2]
    for i in range(3):
        u, t = d.radial[i], d.tangential[i]
        E = (d.base_radius_mm * u + d.axis_offset_mm * t) * 1e-3 + d.upper_arm_mm * 1e-3 * (
            np.cos(theta[:, i])[:, None] * u - np.sin(theta[:, i])[:, None] * np.array([0, 0, 1.0]))
        w = P + d.effector_radius_mm * 1e-3 * u - E
        wp = w - (w @ t)[:, None] * t
        kz = wp[:, 2] / np.linalg.norm(wp, axis=1)
        zS = E[:, 2] + d.joint_offset_mm * 1e-3 * kz
        V += m.upper_arm_kg * (-m.upper_arm_com_mm * 1e-3 * np.sin(theta[:, i]))
        V += m.knee_kg * (E[:, 2] + m.knee_com_mm * 1e-3 * kz) + m.lower_arm_kg * (zS + P[:, 2]) / 2
    return G_M_S2 * V


@pytest.mark.parametrize("name", ["delta.toml", "delta_falcon.toml"])
def test_gravity_torques_are_the_derivative_of_the_potential(tmp_path, name):
    des = load_design(ROOT / "designs" / name)
    d, X = des.mechanism, des.workspace_points()
    th = ik(d, X).theta_rad
    h = 1e-6
    mass, pot = (MASS_KNEE, potential_knee_J) if d.joint_offset_mm > 0 else (MASS, potential_J)
    fd = np.stack([(pot(d, th + h * e, mass) - pot(d, th - h * e, mass)) / (2 * h)
                   for e in np.eye(3)], axis=1)
    spec = device_spec(des, mass)
    files = {"hapticad_device.h": csrc.header(spec), "hapticad_device.c": csrc.source(spec),
             "vectors.h": f"#define V_N {len(th)}\nstatic const double V_theta_rad[] = "
                          f"{{{', '.join(repr(float(v)) for v in th.ravel())}}};\n"}
    out = subprocess.run([str(_compile(tmp_path, files, GRAVITY_MAIN))], capture_output=True,
                         text=True, timeout=60, check=True).stdout
    got = np.array([list(map(float, line.split())) for line in out.splitlines()])
    # central differences of V: truncation ~h^2 V''' ~ 1e-12 N m, round-off ~1e-16 J / 1e-6 rad
    assert np.abs(got - fd).max() < 1e-8
    assert np.abs(fd).max() > 0.05  # the arms' weight is felt (not a vacuous comparison)


def _report_bodies() -> dict:
    """Moving bodies of a delta as report.json states them (body frames of
    cad.families.delta.layout; values plausible, not from a build: the C is checked against
    the numpy model of the same numbers)."""
    inertia = np.diag([1e-6, 2e-5, 2e-5]).tolist()
    b = {f"upper_{i}": {"mass_kg": 0.05, "com_mm": [40.0, 0.0, 0.0], "inertia_com_kg_m2": inertia}
         for i in range(3)}
    b |= {f"lower_{i}_{s}": {"mass_kg": 0.015, "com_mm": [95.0, 0.0, 0.0], "inertia_com_kg_m2": inertia}
          for i in range(3) for s in "ab"}
    b["effector"] = {"mass_kg": 0.08, "com_mm": [0.0, 0.0, -10.0], "inertia_com_kg_m2": inertia}
    return {"bodies": b}


MOTOR = {"name": "acme-60", "torque_constant_mNm_per_A": 60.0, "current_continuous_A": 1.5,
         "torque_continuous_mNm": 90.0, "torque_peak_mNm": 500.0, "rotor_inertia_g_cm2": 20.0}


def test_build_files_state_the_resolved_device_and_pass_their_own_test(tmp_path):
    """``--formats firmware``'s files (the family's hook, no CAD): the header's Kt, currents
    and encoder count are the design's [motor] table and [parts] count; the generated
    test_device.c passes over test_vectors.json in double and float."""
    raw = tomllib.loads((ROOT / "designs" / "delta.toml").read_text())
    raw = copy.deepcopy(raw) | {"parts": {"encoder_counts_per_rev": 4096}, "motor": MOTOR}
    des = parse_design(raw, "variant.toml")
    files = linkage_files(des, _report_bodies(), "ab12", resolve_device(des))
    h = header_facts(files["firmware/hapticad_device.h"])
    assert h["encoder_counts_per_rev"] == 4096
    assert h["kt_Nm_per_A"] == pytest.approx(0.060, rel=1e-15)
    assert h["current_continuous_A"] == pytest.approx(1.5, rel=1e-15)
    assert h["current_peak_A"] == pytest.approx(0.500 / 0.060, rel=1e-15)
    assert "int hc_inverse(" in files["firmware/hapticad_device.h"]
    # each arm about its motor axis: I_yy + m c^2 (parallel axes) + the [motor] rotor (direct)
    arms = re.search(r"ARM_AXIS\[3\] = \{(.+)\};", files["firmware/hapticad_device.c"]).group(1)
    arms = [float(v) for v in re.findall(r"HC_R\(([^)]+)\)", arms)]
    assert arms == pytest.approx([2e-5 + 0.05 * 0.040**2 + 20.0e-7] * 3, rel=1e-12)
    chai = json.loads(files["firmware/chai3d_device.json"])
    assert chai["encoder_counts_per_rev"] == 4096
    assert chai["m_workspaceRadius"] == pytest.approx(0.05, rel=1e-12)  # half the 100 mm cube
    vec = json.loads(files["firmware/test_vectors.json"])
    assert vec["summary"]["ok"] == 1200 and vec["summary"]["refused"] == 60
    fw = tmp_path / "fw"
    fw.mkdir()
    for rel, text in files.items():
        (fw / Path(rel).name).write_text(text)
    for use_float, tols in ((False, (tol.FIRMWARE_DOUBLE_POSITION_M, tol.FIRMWARE_DOUBLE_TORQUE_NM,
                                     tol.FIRMWARE_FD_JACOBIAN)),
                            (True, (tol.FIRMWARE_FLOAT_POSITION_M, tol.FIRMWARE_FLOAT_TORQUE_NM, 0.0))):
        exe = tmp_path / ("tf" if use_float else "td")
        cmd = [compiler("c"), "-std=c99", "-O2", "-Wall", "-Wextra", "-pedantic", "-Werror",
               *(["-DHAPTICAD_USE_FLOAT"] if use_float else []), "-o", str(exe),
               str(fw / "test_device.c"), str(fw / "hapticad_device.c"), "-lm"]
        subprocess.run(cmd, check=True, capture_output=True, timeout=120)
        r = subprocess.run([str(exe), str(fw / "test_vectors.json"), *map(repr, tols)],
                           capture_output=True, text=True, timeout=120)
        assert r.returncode == 0, r.stdout + r.stderr
        assert "failures 0" in r.stdout
