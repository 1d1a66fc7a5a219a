"""Generated firmware (issue 26): the C code compiled with the system compiler and checked
against hapticad's numpy model (test vectors), finite differences of its own FK, the
potential energy of the solids' masses and COMs, and the motor catalog.

Needs ``cc``: on a machine without one the compiling tests are skipped with that reason;
``.ci/run`` installs gcc and sets ``HAPTICAD_REQUIRE_CC=1``, under which they fail instead.
"""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from cad import tolerances as tol

ROOT = Path(__file__).resolve().parents[3]
FAMILIES = ("hoeken", "pantograph", "twin-pantograph")


def _cc() -> str:
    cc = shutil.which("cc") or shutil.which("gcc")
    if not cc:
        why = "no C compiler (cc/gcc) on PATH (apt-get install gcc; .ci/run installs it)"
        if os.environ.get("HAPTICAD_REQUIRE_CC") == "1":
            pytest.fail(f"HAPTICAD_REQUIRE_CC=1 but {why}")
        pytest.skip(why)
    return cc


def _build(request, fam: str):
    """(design, out_dir, report.json) of the shared builds (tests/conftest.py)."""
    if fam == "hoeken":
        d, out, rep, _ = request.getfixturevalue("hoeken_sim_build")
        return d, out, rep
    d, out, _ = request.getfixturevalue("family_builds")[fam]
    return d, out, json.loads((out / "report.json").read_text())


def _run(fw: Path, tmp: Path, use_float: bool, extra: str = "") -> dict:
    """Compile test_device.c + hapticad_device.c (double or float) and run it on the vectors."""
    exe = tmp / ("test_f" if use_float else "test_d")
    flags = ["-DHAPTICAD_USE_FLOAT"] if use_float else []
    cmd = [_cc(), "-std=c99", "-O2", "-Wall", "-Wextra", "-pedantic", "-Werror", *flags, "-o",
           str(exe), str(fw / "test_device.c"), str(fw / "hapticad_device.c"), "-lm"]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    tols = ((tol.FIRMWARE_FLOAT_POSITION_M, tol.FIRMWARE_FLOAT_TORQUE_NM, 0.0) if use_float else
            (tol.FIRMWARE_DOUBLE_POSITION_M, tol.FIRMWARE_DOUBLE_TORQUE_NM, tol.FIRMWARE_FD_JACOBIAN))
    r = subprocess.run([str(exe), str(fw / "test_vectors.json"), *map(repr, tols)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    return {k: float(v) for k, v in re.findall(r"(\w+) ([-+0-9.e]+)", r.stdout)}


@pytest.mark.parametrize("fam", (*FAMILIES, "powermouse"))
def test_build_writes_firmware_that_names_design_hash_version_units(request, fam):
    import cad
    from cad.pipeline import design_hash

    d, out, rep = _build(request, fam)
    fw = out / "firmware"
    man = {f["path"] for f in json.loads((out / "manifest.json").read_text())["files"]}
    h = design_hash(d)
    sketch = () if fam == "powermouse" else ("wall_example/wall_example.ino",)
    for name in ("hapticad_device.h", "hapticad_device.c", "test_vectors.json", "test_device.c",
                 *sketch, "chai3d_device.json"):
        assert f"firmware/{name}" in rep["files"] and f"firmware/{name}" in man
        text = (fw / name).read_text()
        assert d.name in text and h in text and f"hapticad {cad.__version__}" in text
        if not name.endswith("json"):
            assert "Units: SI" in text and "Frame:" in text


@pytest.mark.parametrize("fam", FAMILIES)
@pytest.mark.parametrize("use_float", [False, True], ids=["double", "float"])
def test_c_matches_numpy_at_every_pose(request, tmp_path, fam, use_float):
    """Double: 1e-9 m / 1e-9 N m at every pose and J = central differences of the generated FK
    (1e-7 m/rad); float: the stated bounds (cad.tolerances). Refused poses return the model's
    status code (the program fails on any mismatch)."""
    _, out, _ = _build(request, fam)
    res = _run(out / "firmware", tmp_path, use_float)
    doc = json.loads((out / "firmware" / "test_vectors.json").read_text())
    assert res["rows"] == len(doc["rows"]) and res["ok"] >= 1000 and res["failures"] == 0
    assert res["refused"] >= 20 and res["refused"] == doc["summary"]["refused"]
    if not use_float:
        assert res["max_err_X"] <= 1e-9 and res["max_err_tau"] <= 1e-9 and res["max_err_fd"] <= 1e-7


def _run_c(fw: Path, tmp_path: Path, source: str) -> list[float]:
    """Compile ``source`` (C99) against the generated ``hapticad_device.c`` in ``fw``, run it,
    and return the numbers it prints."""
    (tmp_path / "m.c").write_text(source)
    subprocess.run([_cc(), "-std=c99", f"-I{fw}", "-o", str(tmp_path / "m"), str(tmp_path / "m.c"),
                    str(fw / "hapticad_device.c"), "-lm"], check=True, timeout=60)
    return list(map(float, subprocess.run([str(tmp_path / "m")], capture_output=True, text=True,
                                          check=True).stdout.split()))


def test_fourbar_refuses_angles_outside_the_crank_range(request):
    d, out, _ = _build(request, "hoeken")
    doc = json.loads((out / "firmware" / "test_vectors.json").read_text())
    R = np.array(doc["rows"])
    q = R[:, 3]
    outside = (q < d.phi1_min_rad) | (q > d.phi1_max_rad)
    assert outside.sum() >= 50 and (q[outside] < d.phi1_min_rad).any() and (q[outside] > d.phi1_max_rad).any()
    assert np.all(R[outside, 0] == doc["status_codes"]["HC_ERR_RANGE"]) and np.all(R[~outside, 0] == 0)


def _vertical(d):
    import dataclasses

    from cad.design.firmware import parse_firmware

    n = {"hoeken": 1, "pantograph": 2}.get(d.family, 4)
    return dataclasses.replace(d, firmware=parse_firmware(
        {"plane": "vertical", "gravity_direction": [0.3, -1.0]}, n))


def _potential_fourbar(d, rep, phi):
    from cad.families.fourbar.pose import body_transforms

    g = np.array([0.3, -1.0]) / math.hypot(0.3, 1.0) * 9.80665
    T = body_transforms(d.linkage, phi)
    V = np.zeros(len(phi))
    for b in ("crank", "coupler", "rocker"):
        L = rep["links"][b]
        c = np.array([*L["com_mm"], 1.0])
        V -= L["mass_kg"] * (np.einsum("nij,j->ni", T[b], c)[:, :2] * 1e-3) @ g
    return V


def _potential_pantograph(d, rep, X):
    from cad.families.pantograph.build import body_poses

    g = np.array([0.3, -1.0]) / math.hypot(0.3, 1.0) * 9.80665
    Xmm = np.array(X, dtype=float)
    Xmm[:, :2] *= 1e3
    T = body_poses(d, Xmm)
    V = np.zeros(len(X))
    for b, mp in rep["bodies"].items():
        c = np.array([*mp["com_mm"], 1.0])
        V -= mp["mass_kg"] * (np.einsum("nij,j->ni", T[b], c)[:, :2] * 1e-3) @ g
    return V


@pytest.mark.parametrize("fam", FAMILIES)
def test_gravity_torques_are_the_derivative_of_the_solids_potential(request, tmp_path, fam):
    """Vertical plane (g tilted, [0.3, -1]): the C gravity torques equal the numpy model's
    (compiled run, 1e-9 N m), which equal dV/dq of the potential of the solids' masses and
    COMs placed by the build's own body transforms (central differences). Twin pantograph
    (redundant): Jq^T tau = dV/dX, the wrench the torques render."""
    from cad.families.pantograph import firmware as pf
    from cad.firmware import reference as ref
    from cad.firmware import write_firmware
    from cad.kinematics import twin_pantograph as tw
    from cad.firmware.device import device_spec
    from cad.pipeline import design_hash

    d, _, rep = _build(request, fam)
    dv = _vertical(d)
    write_firmware(dv, rep, tmp_path, design_hash(dv))
    res = _run(tmp_path / "firmware", tmp_path, False)
    assert res["failures"] == 0 and res["ok"] >= 1000
    spec = device_spec(dv, rep, "", "")
    doc = json.loads((tmp_path / "firmware" / "test_vectors.json").read_text())
    R = np.array(doc["rows"])
    nj, nt = spec.n_joints, spec.n_task
    R = R[R[:, 0] == 0][::40]
    q = R[:, 1 + 2 * nj: 1 + 3 * nj]
    tg = ref.gravity_torques(spec, q)
    assert np.abs(tg).max() > 1e-3  # the links do weigh
    if fam == "hoeken":
        h = 1e-6
        fd = (_potential_fourbar(d, rep, q[:, 0] + h) - _potential_fourbar(d, rep, q[:, 0] - h)) / (2 * h)
        np.testing.assert_allclose(tg[:, 0], fd, rtol=0, atol=1e-8)
        return
    X, _ = ref.forward(spec, q)
    grad = np.zeros((len(X), nt))
    for k in range(nt):
        h = 1e-7 if k < 2 else 1e-6
        Xp, Xm = X.copy(), X.copy()
        Xp[:, k] += h
        Xm[:, k] -= h
        grad[:, k] = (_potential_pantograph(d, rep, Xp) - _potential_pantograph(d, rep, Xm)) / (2 * h)
    if fam == "pantograph":
        J = ref.jacobian(spec, q)  # dE/dq: dV/dq = J^T dV/dE
        np.testing.assert_allclose(tg, np.einsum("nij,ni->nj", J, grad), rtol=0, atol=1e-8)
    else:  # poses where the crank pin lies on its circle (IK(FK(q)) = q; the vectors also
        # hold readings up to FIRMWARE_CRANK_TOL_M off it, which no task pose X describes)
        Xmm = np.column_stack([X[:, :2] * 1e3, X[:, 2]])
        on = np.all(np.abs(tw.ik(pf.twin_of(spec.params), Xmm).q_rad - q) < 1e-9, axis=1)
        assert on.sum() >= 25
        Jq, tg, grad = pf.twin_task_jacobian(spec, q[on]), tg[on], grad[on]
        np.testing.assert_allclose(np.einsum("nij,ni->nj", Jq, tg), grad, rtol=0, atol=1e-8)


def test_motor_currents_saturate_at_the_catalog_limits(request, tmp_path):
    """i = tau / Kt, scaled down together to the continuous / peak current of the catalog."""
    from cad.data.catalog import get_motor

    _, out, rep = _build(request, "pantograph")
    m = get_motor(rep["motor"]["key"])
    kt = m.torque_constant_mNm_per_A * 1e-3
    fw = out / "firmware"
    (tmp_path / "m.c").write_text(
        '#include <stdio.h>\n#include "hapticad_device.h"\nint main(void){hc_real t[2]={0.01,-0.02},'
        'b[2]={3.0,-1.5},a[2];int s;s=hc_motor_currents(t,HC_LIMIT_CONTINUOUS,a);'
        'printf("%d %.17g %.17g\\n",s,a[0],a[1]);s=hc_motor_currents(b,HC_LIMIT_CONTINUOUS,a);'
        'printf("%d %.17g %.17g\\n",s,a[0],a[1]);s=hc_motor_currents(b,HC_LIMIT_PEAK,a);'
        'printf("%d %.17g %.17g\\n",s,a[0],a[1]);return 0;}\n')
    exe = tmp_path / "m"
    subprocess.run([_cc(), "-std=c99", f"-I{fw}", "-o", str(exe), str(tmp_path / "m.c"),
                    str(fw / "hapticad_device.c"), "-lm"], check=True, timeout=60)
    lines = [list(map(float, s.split())) for s in subprocess.run(
        [str(exe)], capture_output=True, text=True, check=True).stdout.splitlines()]
    assert lines[0] == pytest.approx([0, 0.01 / kt, -0.02 / kt], rel=1e-12)
    ic, ip = m.current_continuous_A, m.torque_peak_mNm / m.torque_constant_mNm_per_A
    assert lines[1] == pytest.approx([1, ic, -ic / 2], rel=1e-12)  # direction kept
    big = 3.0 / kt
    assert lines[2] == pytest.approx([1, ip, -ip / 2] if big > ip else [0, big, -big / 2], rel=1e-12)


def test_wall_sketch_compiles_and_chai3d_numbers_follow_eq25(request, tmp_path):
    """The sketch compiles as C99 with a stub micros(); its K is eq (25)'s K_max of the design's
    [stiffness] table (Hoeken paper §III.B.4: ~2500 N/m), the CHAI3D description carries it."""
    from cad.dynamics.stiffness import stiffness_range_N_per_m

    d, out, _ = _build(request, "hoeken")
    fw = out / "firmware"
    (tmp_path / "sk.c").write_text('static unsigned long micros(void) { return 0; }\n'
                                   f'#include "{fw / "wall_example" / "wall_example.ino"}"\n'
                                   'int main(void) { setup(); loop(); return 0; }\n')
    subprocess.run([_cc(), "-std=c99", "-Wall", "-Werror", f"-I{fw}", "-o", str(tmp_path / "sk"),
                    str(tmp_path / "sk.c"), str(fw / "hapticad_device.c"), "-lm"], check=True,
                   timeout=60)
    subprocess.run([str(tmp_path / "sk")], check=True, timeout=10)
    kmax = stiffness_range_N_per_m(d.stiffness)[1]
    ino = (fw / "wall_example" / "wall_example.ino").read_text()
    assert f"#define WALL_K_N_PER_M {kmax!r}" in ino
    c3 = json.loads((fw / "chai3d_device.json").read_text())
    assert c3["m_maxLinearStiffness"] == kmax and c3["m_maxLinearDamping"] == d.stiffness.Fv_N_s_per_m
    assert 0 < c3["m_maxLinearForce"] < c3["m_maxLinearForce_peak"]
    assert c3["m_workspaceRadius"] == pytest.approx(0.025, rel=0.05)  # half the 50 mm stroke


@pytest.mark.parametrize("table, field", [
    ('plane = "tilted"', "firmware.plane"),
    ("encoder_zero_deg = [1, 2]", "firmware.encoder_zero_deg"),
    ("encoder_direction = [1, -1]", "firmware.encoder_direction"),
    ("encoder_counts_per_rev = 0", "firmware.encoder_counts_per_rev"),
    ("gravity_direction = [0, 0]", "firmware.gravity_direction"),
    ("wall_stiffness = 3", "firmware.wall_stiffness"),
])
def test_bad_firmware_table_is_one_line_error(tmp_path, table, field):
    from cli_helpers import assert_one_line_error, hapticad

    src = (ROOT / "designs" / "hoeken.toml").read_text()
    p = tmp_path / "bad.toml"
    p.write_text(src + f"\n[firmware]\n{table}\n")
    code, _, err = hapticad("analyze", str(p))
    assert_one_line_error(code, err, field)


def _powermouse(request):
    d, out, _ = request.getfixturevalue("family_builds")["powermouse"]
    return d, out, json.loads((out / "report.json").read_text())


@pytest.mark.parametrize("design, table, field", [
    ("pantograph.toml", "encoder_direction = [1, 1, 1]", "firmware.encoder_direction"),
    ("haptic_mouse.toml", "plane = 3", "firmware.plane"),
    ("haptic_pen.toml", 'plane = "vertical"', "firmware.plane"),
])
def test_bad_firmware_table_of_the_pantographs(tmp_path, design, table, field):
    from cli_helpers import assert_one_line_error, hapticad

    p = tmp_path / "bad.toml"
    p.write_text((ROOT / "designs" / design).read_text() + f"\n[firmware]\n{table}\n")
    code, _, err = hapticad("gii", str(p))
    assert_one_line_error(code, err, field)


@pytest.mark.parametrize("use_float", [False, True], ids=["double", "float"])
def test_powermouse_map_matches_numpy(request, tmp_path, use_float):
    """NI = W^-1 w and w = W NI against numpy over 1200 wrenches (the build's wrench_map):
    double 1e-9 At / 1e-9 N, N m; float 1e-3 At / 2e-5 N, N m (cad.tolerances)."""
    _, out, rep = _powermouse(request)
    fw = out / "firmware"
    exe = tmp_path / "t"
    flags = ["-DHAPTICAD_USE_FLOAT"] if use_float else []
    subprocess.run([_cc(), "-std=c99", "-O2", "-Wall", "-Wextra", "-pedantic", "-Werror", *flags,
                    "-o", str(exe), str(fw / "test_device.c"), str(fw / "hapticad_device.c"), "-lm"],
                   check=True, timeout=120)
    tols = ((tol.FIRMWARE_FLOAT_AMPERE_TURNS, tol.FIRMWARE_FLOAT_TORQUE_NM) if use_float
            else (1e-9, 1e-9))
    r = subprocess.run([str(exe), str(fw / "test_vectors.json"), *map(repr, tols)],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "rows 1200" in r.stdout
    doc = json.loads((fw / "test_vectors.json").read_text())
    R = np.array(doc["rows"])
    W = np.array(rep["wrench_map"])
    np.testing.assert_allclose(np.linalg.solve(W, R[:, :6].T).T, R[:, 6:], rtol=0, atol=1e-9)


def test_powermouse_gravity_saturation_and_max_force(request, tmp_path):
    """Gravity wrench = (0, 0, m g, r_COM x m g) of the flotor's solids; saturation scales all
    six coils together to the continuous limit; the CHAI3D force is the largest force every
    direction gets within the continuous ampere-turns (checked on 20000 directions)."""
    _, out, rep = _powermouse(request)
    fw = out / "firmware"
    v = _run_c(fw, tmp_path,
        '#include <stdio.h>\n#include "hapticad_device.h"\nint main(void){hc_real g[6],w[6]='
        '{0,0,1e4,0,0,0},n[6];int i,s;hc_gravity_wrench(g);for(i=0;i<6;++i)printf("%.17g ",g[i]);'
        's=hc_ampere_turns_from_wrench(w,HC_LIMIT_CONTINUOUS,n);printf("%d ",s);'
        'for(i=0;i<6;++i)printf("%.17g ",n[i]);printf("\\n");return 0;}\n')
    m = rep["flotor"]["mass_kg"]
    r = np.array(rep["flotor"]["com_mm"]) * 1e-3
    F = np.array([0.0, 0.0, m * 9.80665])
    np.testing.assert_allclose(v[:6], [*F, *np.cross(r, F)], rtol=1e-12, atol=1e-15)
    W = np.array(rep["wrench_map"])
    ni = np.linalg.solve(W, [0, 0, 1e4, 0, 0, 0])
    cont = rep["actuator"]["ampere_turns_at_power"]
    assert v[6] == 1 and np.max(np.abs(v[7:])) == pytest.approx(cont, rel=1e-12)
    np.testing.assert_allclose(v[7:], ni * cont / np.max(np.abs(ni)), rtol=1e-12)
    fmax = json.loads((fw / "chai3d_device.json").read_text())["m_maxLinearForce"]
    u = np.random.default_rng(1).normal(size=(20000, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    need = np.abs(np.linalg.solve(W, np.column_stack([u * fmax, np.zeros_like(u)]).T)).max(axis=0)
    assert need.max() <= cont * (1 + 1e-12) and need.max() >= 0.99 * cont


def test_generation_imports_no_cad_library(request):
    """cad.firmware is pure generation code: from a report.json it needs no CAD library."""
    import sys

    _, out, _ = _build(request, "hoeken")
    code = (
        "import json, sys\n"
        "from cad.design import load_design\n"
        "from cad.firmware import firmware_files\n"
        f"rep = json.loads(open(r'{out / 'report.json'}').read())\n"
        f"files = firmware_files(load_design(r'{ROOT / 'designs' / 'hoeken.toml'}'), rep, 'h')\n"
        "bad = [m for m in ('OCP', 'build123d', 'cadquery', 'trimesh', 'manifold3d') if m in sys.modules]\n"
        "print('BAD', bad, len(files), sorted(files))\n"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    # the six device files (cad.firmware.FILES) and the identification routine's three
    assert "BAD [] 9" in r.stdout, r.stdout + r.stderr
    from cad.firmware import FILES

    assert all(f"firmware/{f}" in r.stdout for f in FILES)
    assert r.stdout.count("firmware/identify/") == 3


@pytest.mark.parametrize("fam", ("pantograph", "twin-pantograph"))
def test_mass_matrix_at_home_equals_the_builds_effective_mass(request, tmp_path, fam):
    """hc_mass_matrix at the encoders' zero (the home pose) equals report.json's
    effective_mass_home (cad.families.pantograph.build, the build's own mass model of the solids)."""
    _, out, rep = _build(request, fam)
    fw = out / "firmware"
    M = np.array(_run_c(fw, tmp_path,
        '#include <stdio.h>\n#include "hapticad_device.h"\nint main(void){hc_encoder_t e='
        'HC_ENCODER_DEFAULT;long c[HC_N_JOINTS]={0};hc_real q[HC_N_JOINTS],M[HC_N_TASK*HC_N_TASK];'
        'int i;hc_counts_to_angles(&e,c,q);if(hc_mass_matrix(q,M))return 1;'
        'for(i=0;i<HC_N_TASK*HC_N_TASK;++i)printf("%.17g ",M[i]);return 0;}\n'))
    eff = rep["effective_mass_home"]
    if fam == "pantograph":
        np.testing.assert_allclose(M.reshape(2, 2) * 1e3, eff["mass_matrix_g"], rtol=1e-9)
    else:
        M = M.reshape(3, 3)
        Mi = np.linalg.inv(M)
        np.testing.assert_allclose([M[0, 0] * 1e3, M[1, 1] * 1e3, M[2, 2] * 1e7, 1e3 / Mi[0, 0]],
                                   [eff["mass_x_g_diag"], eff["mass_y_g_diag"],
                                    eff["inertia_theta_g_cm2_diag"], eff["mass_x_g_apparent"]],
                                   rtol=1e-9)


SKETCH_HARNESS = r"""
#include "hapticad_device.h"
#define HC_SKETCH_IO 1
static unsigned long t_us = 0;
static unsigned long micros(void) { return t_us += 1000000; }  /* never waits */
static long test_counts = 0;
static double last_amps[HC_N_JOINTS];
static void read_encoders(long counts[HC_N_JOINTS]) { for (int i = 0; i < HC_N_JOINTS; ++i) counts[i] = test_counts; }
static void write_currents(const hc_real amps[HC_N_JOINTS]) { for (int i = 0; i < HC_N_JOINTS; ++i) last_amps[i] = amps[i]; }
static void motors_off(void) { for (int i = 0; i < HC_N_JOINTS; ++i) last_amps[i] = 0; }
#include "wall_example/wall_example.ino"
#include <stdio.h>
int main(void) {
    hc_real q[HC_N_JOINTS], X[HC_N_TASK];
    for (long c = 1; c < 100000; ++c) {          /* the first reading 1 mm inside the wall */
        long cs[HC_N_JOINTS];
        for (int i = 0; i < HC_N_JOINTS; ++i) cs[i] = c;
        hc_counts_to_angles(&enc, cs, q);
        if (hc_forward(q, X) != HC_OK) continue;
        if (WALL_NX * (X[0] - WALL_X0_M) + WALL_NY * (X[1] - WALL_Y0_M) > 1e-3) { test_counts = c; break; }
    }
    setup();
    loop(); double first = last_amps[0];         /* power-up sample: no previous position */
    loop(); double second = last_amps[0];        /* the handle held still */
    printf("%ld %.17g %.17g\n", test_counts, first, second);
    return 0;
}
"""


def test_wall_sketch_first_sample_has_no_damping_spike(request, tmp_path):
    """The sketch's first sample inside the wall (power-up, or after a refused pose) has no
    previous position: its damping term must be 0, so with the handle held still the first
    and second currents are equal and non-zero (t2 tester: s_prev = 0 gave a B s/Te spike)."""
    _, out, _ = _build(request, "hoeken")
    fw = out / "firmware"
    (tmp_path / "h.c").write_text(SKETCH_HARNESS)
    subprocess.run([_cc(), "-std=c99", "-Wall", "-Werror", f"-I{fw}", "-o", str(tmp_path / "h"),
                    str(tmp_path / "h.c"), str(fw / "hapticad_device.c"), "-lm"], check=True, timeout=60)
    counts, first, second = subprocess.run([str(tmp_path / "h")], check=True, timeout=10,
                                           capture_output=True, text=True).stdout.split()
    assert int(counts) > 0 and float(first) != 0.0
    assert float(first) == float(second)


def test_workspace_radius_is_the_largest_circle_inside_a_rectangle(tmp_path):
    """CHAI3D's ``m_workspaceRadius`` is the radius of the largest circle enclosed in the
    workspace (chai3d src/devices/CGenericHapticDevice.h): a 120 x 60 mm workspace gives
    half the shorter side, 0.03 m (it gave 0.06 m, half the longer side)."""
    from cad.design import load_design
    from cad.families.pantograph.firmware import workspace_radius_m

    text = (ROOT / "designs" / "haptic_mouse.toml").read_text().replace(
        "side_mm = 100.0", "size_mm = [120.0, 60.0]")
    p = tmp_path / "rect.toml"
    p.write_text(text)
    assert workspace_radius_m(None, load_design(p)) == pytest.approx(0.030, rel=1e-12)
    assert workspace_radius_m(None, load_design(ROOT / "designs" / "haptic_mouse.toml")) == pytest.approx(0.050, rel=1e-12)
