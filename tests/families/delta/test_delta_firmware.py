"""The delta's generated C (cad/families/delta/firmware.py) compiled with the system C
compiler and run against the numpy model: IK angles and status, FK, the Jacobian
(J^-1 of :func:`cad.kinematics.delta.jacobian_rad_per_m`, and central finite differences of
the C's own FK), tau = J^T F and the gravity torques of :func:`cad.dynamics.delta
.gravity_torques_Nm`, at the workspace grid plus seeded random points of both bundled
designs, some of them unreachable or outside the joint limits (the C must refuse those
with the same status). Double build to 1e-9 (round-off ~1e-15), float build to the float
tolerances of :mod:`cad.tolerances`.
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

from cad import tolerances as tol
from cad.design import load_design
from cad.dynamics.delta import DeltaMass
from cad.families.delta.firmware import c_files, reference_vectors, vectors_c
from tests.compilers import compiler

ROOT = Path(__file__).resolve().parents[3]
MASS = DeltaMass(upper_arm_kg_m2=2e-4, upper_arm_kg=0.05, upper_arm_com_mm=40.0,
                 lower_arm_kg=0.03, effector_kg=0.08)

MAIN = r"""
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "hapticad_delta.h"
#include "vectors.h"

static double worst[7];
static void keep(int k, double e) { if (e > worst[k]) worst[k] = e; }

int main(void)
{
    int n, i, k, bad_status = 0, ok_rows = 0, fk_rows = 0;
    for (n = 0; n < V_N; ++n) {
        hc_real P[3], th[3], Pf[3], Jx[9], F[3], tau[3], tg[3], Pp[3], Pm[3], tp[3];
        int st;
        for (i = 0; i < 3; ++i) { P[i] = (hc_real)V_P_m[3 * n + i]; F[i] = (hc_real)V_F_N[3 * n + i]; }
        st = hcd_inverse(P, th);
        if (st != (int)V_ik_status[n]) { ++bad_status; printf("row %d status %d want %d\n", n, st, (int)V_ik_status[n]); }
        if (st) continue;
        ++ok_rows;
        for (i = 0; i < 3; ++i) keep(0, fabs(th[i] - V_theta_rad[3 * n + i]));
        for (i = 0; i < 3; ++i) th[i] = (hc_real)V_theta_rad[3 * n + i];
        st = hcd_forward(th, Pf);
        if (st != (int)V_fk_status[n]) { ++bad_status; printf("row %d fk status %d want %d\n", n, st, (int)V_fk_status[n]); }
        if (st) continue;
        ++fk_rows;
        for (i = 0; i < 3; ++i) keep(1, fabs(Pf[i] - V_P_fk_m[3 * n + i]));
        hcd_jacobian(th, Jx);
        for (i = 0; i < 9; ++i) keep(2, fabs(Jx[i] - V_Jx_m_per_rad[9 * n + i]));
        hcd_joint_torques(th, F, tau);
        hcd_gravity_torques(th, tg);
        for (i = 0; i < 3; ++i) keep(3, fabs(tau[i] - V_tau_Nm[3 * n + i]));
        for (i = 0; i < 3; ++i) keep(4, fabs(tg[i] - V_tau_gravity_Nm[3 * n + i]));
        for (k = 0; k < 3; ++k) {           /* column k against central differences of FK */
            for (i = 0; i < 3; ++i) tp[i] = th[i];
            tp[k] = th[k] + HC_R(1e-6); hcd_forward(tp, Pp);
            tp[k] = th[k] - HC_R(1e-6); hcd_forward(tp, Pm);
            for (i = 0; i < 3; ++i) keep(5, fabs((Pp[i] - Pm[i]) / 2e-6 - Jx[3 * i + k]));
        }
    }
    printf("theta %.3e P %.3e Jx %.3e tau %.3e grav %.3e fd %.3e bad %d ok %d fk %d\n", worst[0],
           worst[1], worst[2], worst[3], worst[4], worst[5], bad_status, ok_rows, fk_rows);
    return 0;
}
"""


def _points(des, rng):
    """Workspace grid, random points around it (some out of reach or the joint limits)."""
    grid = des.workspace_points()
    c = np.asarray(des.workspace["center_mm"])
    wide = c + rng.uniform(-1, 1, size=(60, 3)) * np.array([1.5, 1.5, 2.5]) * des.params["upper_arm_mm"]
    return np.vstack([grid, wide])


def _run(tmp: Path, files: dict, vec_text: str, use_float: bool) -> dict:
    for name, text in {**files, "vectors.h": vec_text, "main.c": MAIN}.items():
        (tmp / name).write_text(text)
    exe = tmp / ("t_f" if use_float else "t_d")
    flags = ["-DHAPTICAD_USE_FLOAT"] if use_float else []
    cmd = [compiler("c"), "-std=c99", "-O2", "-Wall", "-Wextra", "-pedantic", "-Werror", *flags,
           "-I", str(tmp), "-o", str(exe), str(tmp / "main.c"), str(tmp / "hapticad_delta.c"), "-lm"]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    r = subprocess.run([str(exe)], capture_output=True, text=True, timeout=60)
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
    vec = reference_vectors(des.mechanism, MASS, P, F)
    n_ok = int(np.sum(vec["ik_status"] == 0))
    assert 0 < n_ok < len(P)  # both kinds of row are exercised
    assert set(vec["ik_status"]) >= {0, 1}
    got = _run(tmp_path, c_files(des.mechanism, MASS, des.name), vectors_c(vec), use_float)
    assert got["ok"] == n_ok
    assert got["fk"] >= len(des.workspace_points())  # the whole grid, and some points more
    if use_float:
        # float: statuses near a reach edge may differ; values at rows both call ok
        assert got["P"] < tol.FIRMWARE_FLOAT_POSITION_M
        assert got["tau"] < tol.FIRMWARE_FLOAT_TORQUE_NM
        assert got["grav"] < tol.FIRMWARE_FLOAT_TORQUE_NM
        return
    assert got["bad"] == 0
    assert got["theta"] < 1e-12
    assert got["P"] < tol.FIRMWARE_DOUBLE_POSITION_M
    assert got["Jx"] < tol.FIRMWARE_DOUBLE_POSITION_M
    assert got["tau"] < tol.FIRMWARE_DOUBLE_TORQUE_NM
    assert got["grav"] < tol.FIRMWARE_DOUBLE_TORQUE_NM
    assert got["fd"] < tol.FIRMWARE_FD_JACOBIAN


def test_header_names_the_design_and_branch():
    des = load_design(ROOT / "designs" / "delta.toml")
    files = c_files(des.mechanism, MASS, des.name, "ab12")
    assert "design 'delta' (delta), design hash sha256:ab12" in files["hapticad_delta.c"]
    assert "IK branch: elbow out" in files["hapticad_delta.h"]
    assert f"HC_R({des.mechanism.lower_arm_mm * 1e-3!r})" in files["hapticad_delta.c"]
