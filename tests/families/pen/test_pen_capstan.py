"""A capstan on the motors of the haptic pen (issue 35): the design takes ``[transmission]``
(one table for the six motors, or ``[[transmission]]`` one per motor: arm A waist, lower, upper,
then arm B's), and every analysis reads the resolved device's ratio n. The solids are not
built (:mod:`cad.families.pen.capstan_solids`, :mod:`cad.families.pen.shoulder_capstan`;
tests/families/pen/test_pen_full_capstan_build.py reads the build back); the figures here read the design, the resolved device and seeded plausible
bodies (not from a build), as tests/families/pantograph/test_twin_capstan.py does.

References, each independent of the code under test:

* force, resolution and the reflected inertia: the pen's Jacobian dq/dX (6 x 5) by central
  finite differences of its inverse kinematics (not the analytic Jacobian the datasheet uses);
* reflected inertia n^2 (J_m + J_c), J_c the grooved capstan by hand (tests/capstan_ref.py),
  J_m the catalog motors' (data);
* the ropes at the pen: the stiffness as the Hessian of the ropes' potential energy
  1/2 sum k_i (q_i(X + dX) - q_i(X))^2 by finite differences of the inverse kinematics (no
  Jacobian), inverted, the pen's moments free; each rope's k_q = EA (2 / L) r_d^2 by hand;
* MuJoCo: its joint-space inertia with the loops closed, mapped to the pen's task velocities,
  against the effective mass (the rotors as armature); gear, force range, armature against the
  catalog motors and the hand formula;
* firmware: the generated C compiled with gcc and run: counts -> angle and torque -> current
  through each motor's n and K_t by hand; the build's own test_device.c over its vectors
  (numpy model and finite differences);
* the frame: a waist rope in series with the held arm adds rho_E^2 / k_w to the normal
  compliance at the pen end (two springs in series: the rigid arm turning on the rope, the
  clamped frame), a shoulder rope only adds compliance, ropes 1e9 times stiffer give back the
  held frame.
"""

from __future__ import annotations

import copy
import json
import math
import re
import subprocess
import tomllib
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import assert_one_line_error, hapticad

from cad.design import parse_design
from cad.device import resolve_device
from cad.kinematics import haptic_pen as hp
from tests.compilers import compiler

ROOT = Path(__file__).resolve().parents[3]
BUNDLED = ROOT / "designs" / "haptic_pen_capstan.toml"
RAW = tomllib.loads(BUNDLED.read_text())
DIRECT = tomllib.loads((ROOT / "designs" / "haptic_pen.toml").read_text())
JOINTS = tuple(f"{a}_q_{j}" for a in ("A", "B") for j in ("waist", "lower", "upper"))
WAIST = {"capstan_diameter_mm": 40.0, "cable": "steel-7x7-1", "rope_d": 1.0}
SHOULDER = {"capstan_diameter_mm": 32.0, "cable": "steel-7x7-0.8", "rope_d": 0.8}
#: One ratio per motor for the per-motor tests.
NS = (3.0, 4.0, 5.0, 2.5, 4.5, 6.0)
#: The bundled design's ratios (its file: 120 / 40 on the waists, 128 / 32 on the shoulders).
NB = (3.0, 4.0, 4.0, 3.0, 4.0, 4.0)
WRAPS = 3.0
#: Same mechanics in double precision, two methods (measured ~1e-15 relative).
DYN_REL = 1e-9


def _design(raw=RAW):
    return parse_design(copy.deepcopy(raw), "variant.toml")


def _kind(j: str) -> dict:
    return WAIST if j.endswith("waist") else SHOULDER


def _tables(ns) -> list[dict]:
    out = []
    for j, n in zip(JOINTS, ns, strict=True):
        k = _kind(j)
        out.append({"kind": "capstan", "capstan_diameter_mm": k["capstan_diameter_mm"],
                    "drum_diameter_mm": k["capstan_diameter_mm"] * n, "cable": k["cable"], "wraps": WRAPS})
    return out


def _per_motor(ns=NS) -> dict:
    raw = copy.deepcopy(RAW)
    raw["transmission"] = _tables(ns)
    return raw


def _one_ratio(n: float) -> dict:
    raw = copy.deepcopy(RAW)
    raw["transmission"] = _tables((n,) * 6)
    return raw


def _motor(d, j: str):
    from cad.data.catalog import get_motor

    return get_motor(d.parts.waist_motor if j.endswith("waist") else d.parts.motor)


def _jq_by_hand(d, j: str, n: float) -> float:
    """n^2 (J_m + J_c), J_c of the grooved steel capstan by hand (tests/capstan_ref.py)."""
    from cad.data.materials import get_material
    from tests.capstan_ref import grooved_capstan_izz_kg_m2

    m, k = _motor(d, j), _kind(j)
    jc = grooved_capstan_izz_kg_m2(k["capstan_diameter_mm"], k["rope_d"], WRAPS, m.shaft_diameter_mm,
                                   get_material("steel-1018").density_kg_m3)
    return n * n * (m.rotor_inertia_g_cm2 * 1e-7 + jc)


def _fd_jacobian(pen, X: np.ndarray, h: float = 1e-4) -> np.ndarray:
    """dq/dX (N, 6, 5) by central differences of the inverse kinematics; X (N, 5) (mm, rad),
    columns per m and per rad."""
    X = np.atleast_2d(X)
    J = np.empty((len(X), 6, 5))
    for k in range(5):
        e = np.zeros(5)
        e[k] = h
        dq = hp.ik(pen, X + e)[0] - hp.ik(pen, X - e)[0]
        J[:, :, k] = dq / (2 * h * (1e-3 if k < 3 else 1.0))
    return J


def _bodies(d, rng) -> dict:
    """report.json ``bodies`` of a pen: seeded plausible values (not from a build)."""
    from cad.families.pen.layout import body_poses, home_task

    out = {}
    for b in body_poses(d, home_task(d)[None]):
        if b == "ground":
            continue
        L = 70.0 if b == "pen" else 150.0
        m = float(rng.uniform(0.02, 0.12))
        Iz = m * (L * 1e-3) ** 2 / 12 + 1e-6
        out[b] = {"mass_kg": m, "com_mm": [L / 2 if b == "pen" else float(rng.uniform(10, 70)),
                                           float(rng.uniform(-3, 3)), float(rng.uniform(-3, 3))],
                  "inertia_com_kg_m2": np.diag([float(rng.uniform(1, 5)) * 1e-6, Iz, Iz]).tolist()}
    return out


def _massprops(rep: dict) -> dict:
    from cad.massprops.props import MassProps

    return {k: MassProps(v["mass_kg"], np.asarray(v["com_mm"]) * 1e-3, np.asarray(v["inertia_com_kg_m2"]))
            for k, v in rep.items()}


def _home(d) -> np.ndarray:
    from cad.families.pen.layout import home_task

    return home_task(d)


# ----------------------------------------------------------------------------- the design
def test_bundled_file_states_its_capstans():
    ts = RAW["transmission"]
    assert [t["drum_diameter_mm"] / t["capstan_diameter_mm"] for t in ts] == list(NB)
    assert [(t["capstan_diameter_mm"], t["cable"]) for t in ts] == [
        (_kind(j)["capstan_diameter_mm"], _kind(j)["cable"]) for j in JOINTS]


def test_both_forms_reach_the_resolved_device():
    one = dict(RAW, transmission=_tables((4.0,) * 6)[1])  # one table: the same capstan on all six
    dev = resolve_device(_design(one))
    assert [t.motor_joint for t in dev.transmissions] == list(JOINTS)
    assert all(t.is_capstan and t.ratio == 4.0 and t.cable.key == "steel-7x7-0.8" for t in dev.transmissions)
    per = resolve_device(_design(_per_motor()))
    assert [t.ratio for t in per.transmissions] == list(NS)
    assert [per.joint_counts_per_rev(j) for j in JOINTS] == [4000 * n for n in NS]
    assert resolve_device(_design(DIRECT)).transmissions[0].ratio == 1.0


@pytest.mark.parametrize("table, field", [
    ('[transmission]\nkind = "capstan"\ncapstan_diameter_mm = 32.0\nratio = 0.25\ncable = "steel-7x7-0.8"\n',
     "transmission.ratio"),
    ('[transmission]\nkind = "capstan"\ncapstan_diameter_mm = 32.0\nratio = 4.0\ncable = "nylon-1"\n',
     "transmission.cable"),
    ('[[transmission]]\nkind = "direct"\n[[transmission]]\nkind = "direct"\n', "transmission"),
    ('[[transmission]]\nkind = "direct"\n' * 5 + '[[transmission]]\nkind = "belt"\n', "transmission.6.kind"),
])
def test_a_bad_transmission_exits_2_naming_the_field(tmp_path, table, field):
    p = tmp_path / "bad.toml"
    p.write_text((ROOT / "designs" / "haptic_pen.toml").read_text() + "\n" + table)
    code, _, err = hapticad("check", p)
    assert_one_line_error(code, err, field)


@pytest.mark.parametrize("args", [("build",), ("check",), ("datasheet",), ("render",),
                                  ("fit", "--target", "first_mode_Hz>=10", "--free", "mechanism.proximal_mm=130:150"),
                                  ("optimize",), ("bench-log",), ("identify", "log.csv")])
def test_every_command_that_needs_the_solids_passes_one_refusal(tmp_path, args):
    """Every command that needs the pen's capstan solids goes through the one pre-CAD refusal
    (:func:`cad.families.pen.capstan_layout.refuse_solids`): the bundled file with a 5 mm motor
    plate (its far shoulder band's capstan 2.2 mm past the RE 35 shaft,
    tests/families/pen/test_pen_capstan_layout.py) exits 2 from each in one line naming
    ``transmission``, nothing written; the bundled file's 2.8 mm plate passes it
    (:func:`test_the_bundled_file_is_not_refused`)."""
    raw = copy.deepcopy(RAW)
    p = tmp_path / "thick.toml"
    p.write_text(BUNDLED.read_text().replace("motor_mount_thickness_mm = 2.8", "motor_mount_thickness_mm = 5.0"))
    from cad.identify.logfile import columns

    cols = columns(6)  # a well-formed log: the command reads it before the design's build
    (tmp_path / "log.csv").write_text(f"# hapticad identification log sha256:{'0' * 64}\n{','.join(cols)}\n"
                                      + "\n".join(",".join([f"{k * 1e-3:g}"] + ["0"] * (len(cols) - 1))
                                                  for k in range(3)) + "\n")
    out = tmp_path / "out"
    extra = {"build": ("--out", str(out)), "render": ("--out", str(out)), "fit": ("--out", str(out)),
             "optimize": ("--out", str(out)), "bench-log": ("--out", str(tmp_path / "bench.csv"))}.get(args[0], ())
    rest = [str(tmp_path / a) if a.endswith(".csv") else a for a in args[1:]]
    code, _, err = hapticad(args[0], p, *rest, *extra)
    assert raw["parts"]["motor_mount_thickness_mm"] == 2.8
    assert_one_line_error(code, err, "transmission", "capstans cannot be laid out",
                          "the layout places the motors of waists at", "arm B shoulders: the directions found",
                          "mm past the maxon-re35 shaft's tip", "parts.motor_mount_thickness_mm <= 2.80")
    assert not out.exists() or not any(out.iterdir())
    assert not (tmp_path / "bench.csv").exists()


def test_the_bundled_file_is_not_refused():
    """The bundled file (2.8 mm motor plate): every pair of capstan motors laid out, the one
    refusal every solid command passes returns None, the build's pre-CAD check passes."""
    from cad.families.pen import capstan_layout as cl
    from cad.families.pen.build import check_options

    d = _design()
    assert all(p.clash is None for p in cl.layout(d)) and len(cl.layout(d)) == 3
    assert cl.refusal(d) is None
    check_options(d, "fabrication", None)


# ----------------------------------------------------------------------------- force, resolution
def test_motor_force_through_each_ratio_against_finite_differences():
    """continuous_force_N = min over the workspace of sigma_min of the translational rows of
    J^T diag(n_i tau_i) (the pen's moments free), J = dq/dX by finite differences, tau_i each
    catalog motor's continuous torque (RE 40 waists, RE 35 shoulders)."""
    from cad.families.pantograph.datasheet import motor_force_rows

    d = _design(_per_motor())
    tau = np.array([_motor(d, j).torque_continuous_mNm * 1e-3 for j in JOINTS])
    J = _fd_jacobian(d.mechanism, d.workspace_points())
    A = np.swapaxes(J, 1, 2)[:, :3, :] * (np.asarray(NS) * tau)[None, None, :]
    sig = np.linalg.svd(A, compute_uv=False)[:, -1]
    rows = {r["key"]: r for r in motor_force_rows(d)}
    assert rows["continuous_force_N"]["value"] == pytest.approx(sig.min(), rel=1e-6)  # FD step error
    assert rows["continuous_force_N"]["max"] == pytest.approx(sig.max(), rel=1e-6)
    assert "x capstan n = 6 at B_q_upper" in rows["continuous_force_N"]["model"]


def test_resolution_through_each_ratio_against_finite_differences():
    from cad.families.pantograph.datasheet import joint_counts, resolution_m

    d = _design(_per_motor())
    X = d.workspace_points()
    counts = joint_counts(d)
    assert counts.tolist() == [4000 * n for n in NS]
    J = _fd_jacobian(d.mechanism, X)
    got = resolution_m(d, counts)
    for k in (0, len(X) // 2, len(X) - 1):
        want = np.linalg.norm(np.linalg.pinv(J[k][:, :3]) * (2 * math.pi / (4000 * np.asarray(NS)))[None, :], 2)
        assert got[k] == pytest.approx(want, rel=1e-6)


def test_motor_friction_at_the_pen_is_n_times_the_direct_pens():
    """friction_N: each motor's K_t I_0 reaches its joint n times, so one ratio on every motor
    gives n times the direct pen's (F = J^T diag(n f) s, linear in n); a sweep of directions of
    motion (J by finite differences) never exceeds it."""
    from cad.families.pantograph.datasheet import friction_row

    n = 4.0
    d = _design(_one_ratio(n))
    r, r0 = friction_row(d), friction_row(_design(DIRECT))
    assert r["value"] == pytest.approx(n * r0["value"], rel=1e-12) and "x capstan n = 4 at" in r["model"]
    f = np.array([n * _motor(d, j).torque_constant_mNm_per_A * _motor(d, j).no_load_current_mA * 1e-6
                  for j in JOINTS])  # n K_t I_0, N m
    J = _fd_jacobian(d.mechanism, d.workspace_points()[::9])
    v = np.random.default_rng(40).normal(size=(2000, 5))
    s = np.sign(np.einsum("nia,ka->nki", J, v))  # each joint's direction of turn
    F = np.einsum("nia,nki->nka", J, f * s)[..., :3]
    assert np.linalg.norm(F, axis=-1).max() <= r["value"] * (1 + 1e-6)


# ----------------------------------------------------------------------------- inertia
def test_reflected_rotor_inertia_in_the_effective_mass_at_home():
    """The effective mass at home minus the one without rotors = J^T diag(n_i^2 (J_m + J_c)) J
    (J by finite differences at home: pitch 0, so dX = dv; J_c by hand)."""
    from cad.families.pen.dynamics import effective_mass, mass_matrix_si, rotor_inertias

    d = _design(_per_motor())
    bodies = _massprops(_bodies(d, np.random.default_rng(35)))
    X = _home(d)
    jq = np.array([_jq_by_hand(d, j, n) for j, n in zip(JOINTS, NS, strict=True)])
    assert rotor_inertias(d).tolist() == pytest.approx(jq.tolist(), rel=1e-9)
    eff = effective_mass(d, bodies, X)
    bare = mass_matrix_si(d, bodies, X, np.zeros(6))
    J = _fd_jacobian(d.mechanism, X)[0]
    np.testing.assert_allclose(np.asarray(eff["mass_matrix_si"]) - bare, J.T @ np.diag(jq) @ J, rtol=1e-6,
                               atol=1e-6 * np.abs(J.T @ np.diag(jq) @ J).max())  # FD Jacobian
    direct = effective_mass(_design(DIRECT), bodies, X)
    assert eff["mass_x_g_diag"] > direct["mass_x_g_diag"]  # n^2 (J_m + J_c) > J_m on every joint


def _sim_model(d, rep: dict):
    from types import SimpleNamespace

    from cad.families.pen.layout import body_poses
    from cad.families.pen.sim import sim_model

    T = {b: v[0] for b, v in body_poses(d, _home(d)[None]).items()}
    return sim_model(d, SimpleNamespace(tf_world_body=T, instances=()), _massprops(rep))


def _mujoco_task_mass(d, m, data) -> np.ndarray:
    """MuJoCo's joint-space inertia (armature included) mapped to the pen's task velocities at
    home by the joint velocities that keep every loop closed (tests/families/pen/test_pen_build.py)."""
    import mujoco

    Mq = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, data, Mq)
    eq = data.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY
    Jeq = data.efc_J.reshape(-1, m.nv)[eq]
    pen = m.body("pen").id
    centre = data.xpos[pen] + data.xmat[pen].reshape(3, 3)[:, 0] * d.mechanism.pen_mm * 1e-3 / 2
    jp, jr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
    mujoco.mj_jac(m, data, jp, jr, centre, pen)
    target = np.zeros((6, 5))
    target[:3, :3] = np.eye(3)
    target[5, 3] = 1.0  # w_yaw -> omega z
    target[4, 4] = -1.0  # w_pitch -> -omega y (pen along +x)
    A = np.vstack([Jeq, jp, jr])
    rhs = np.vstack([np.zeros((len(Jeq), 5)), target])
    G = np.linalg.lstsq(A, rhs, rcond=None)[0]
    np.testing.assert_allclose(A @ G, rhs, atol=1e-9)
    return G.T @ Mq @ G


def test_mjcf_in_mujoco_has_gear_n_the_reflected_armature_and_the_effective_mass():
    import mujoco

    from cad.export.sim import mjcf_text
    from cad.families.pen.dynamics import effective_mass
    from cad.sim import mj

    d = _design(_per_motor())
    rep = _bodies(d, np.random.default_rng(36))
    m = mujoco.MjModel.from_xml_string(mjcf_text(_sim_model(d, rep)))
    data = mujoco.MjData(m)
    mujoco.mj_forward(m, data)
    names = [m.actuator(i).name for i in range(m.nu)]
    for j, n in zip(JOINTS, NS, strict=True):
        i = names.index(j.replace("_q_", "_motor_"))
        peak = _motor(d, j).torque_peak_mNm * 1e-3  # the motor's own; the joint gets n times it
        assert m.actuator_gear[i, 0] == n
        np.testing.assert_allclose(m.actuator_forcerange[i], [-peak, peak], rtol=1e-12)
        assert m.dof_armature[mj.joint_dof(m, j)] == pytest.approx(_jq_by_hand(d, j, n), rel=1e-9)
    M_mj = _mujoco_task_mass(d, m, data)
    M = np.asarray(effective_mass(d, _massprops(rep), _home(d))["mass_matrix_si"])
    np.testing.assert_allclose(M, M_mj, rtol=1e-6, atol=1e-9 * np.abs(M).max())  # FD body Jacobians


# ----------------------------------------------------------------------------- firmware
def test_firmware_compiled_with_gcc_goes_through_each_ratio(tmp_path):
    """HC_GEAR; counts -> angle 2 pi c / (4000 n_i) and torque -> current tau / (n_i K_t,i)
    (RE 40 waists, RE 35 shoulders) by hand; the CHAI3D file's ratios and force (the force in
    every direction through each n, J by finite differences); the build's own test_device.c
    passes over its vectors (numpy model, finite-difference Jacobian)."""
    from cad import tolerances as tol
    from cad.families.pantograph.datasheet import motor_force_rows
    from cad.firmware import linkage_files

    d = _design(_per_motor())
    rep = _bodies(d, np.random.default_rng(37))
    report = {"bodies": rep, "datasheet": {"rows": motor_force_rows(d)}}  # what a build's report holds
    files = linkage_files(d, report, "pen35", resolve_device(d))
    h = files["firmware/hapticad_device.h"]
    assert re.search(r"#define HC_GEAR \{ (.+) \}", h).group(1) == ", ".join(f"HC_R({n!r})" for n in NS)
    chai = json.loads(files["firmware/chai3d_device.json"])
    assert chai["transmission_ratio"] == list(NS) and chai["encoder_counts_per_rev"] == 4000
    tau = np.array([_motor(d, j).torque_continuous_mNm * 1e-3 for j in JOINTS])
    J = _fd_jacobian(d.mechanism, d.workspace_points())  # the force through each n, by hand
    A = np.swapaxes(J, 1, 2)[:, :3, :] * (np.asarray(NS) * tau)[None, None, :]
    assert chai["m_maxLinearForce"] == pytest.approx(np.linalg.svd(A, compute_uv=False)[:, -1].min(), rel=1e-6)
    fw = tmp_path / "fw"
    fw.mkdir()
    for rel, text in files.items():
        if rel.count("/") == 1:
            (fw / Path(rel).name).write_text(text)
    c = (1000, -500, 250, -125, 60, -30)
    tau = (0.3, -0.1, 0.2, -0.4, 0.05, -0.25)
    (tmp_path / "m.c").write_text(
        '#include <stdio.h>\n#include "hapticad_device.h"\nint main(void){hc_encoder_t e = HC_ENCODER_DEFAULT;'
        f'long c[6]={{{", ".join(map(str, c))}}};long z[6]={{0,0,0,0,0,0}};hc_real q[6],z0[6],a[6];'
        f'hc_real t[6]={{{", ".join(map(repr, tau))}}};int i,s;'
        'hc_counts_to_angles(&e,c,q);hc_counts_to_angles(&e,z,z0);s=hc_motor_currents(t,HC_LIMIT_PEAK,a);'
        'printf("%d\\n",s);for(i=0;i<6;++i)printf("%.17g %.17g %d\\n",q[i]-z0[i],a[i],(int)e.direction[i]);'
        'return 0;}\n')
    exe = tmp_path / "m"
    subprocess.run([compiler(), "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", f"-I{fw}", "-o", str(exe),
                    str(tmp_path / "m.c"), str(fw / "hapticad_device.c"), "-lm"], check=True, timeout=120)
    lines = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout.split("\n")
    assert lines[0] == "0"
    for k, (j, n) in enumerate(zip(JOINTS, NS, strict=True)):
        dq, a, sign = map(float, lines[1 + k].split())
        assert dq == pytest.approx(sign * 2 * math.pi * c[k] / (4000 * n), rel=1e-12)
        assert a == pytest.approx(tau[k] / (n * _motor(d, j).torque_constant_mNm_per_A * 1e-3), rel=1e-12)
    exe2 = tmp_path / "td"
    subprocess.run([compiler(), "-std=c99", "-O2", "-o", str(exe2), str(fw / "test_device.c"),
                    str(fw / "hapticad_device.c"), "-lm"], check=True, capture_output=True, timeout=120)
    r = subprocess.run([str(exe2), str(fw / "test_vectors.json"), *map(repr, (
        tol.FIRMWARE_DOUBLE_POSITION_M, tol.FIRMWARE_DOUBLE_TORQUE_NM, tol.FIRMWARE_FD_JACOBIAN))],
        capture_output=True, text=True, timeout=120)
    assert r.returncode == 0 and "failures 0" in r.stdout, r.stdout + r.stderr


# ----------------------------------------------------------------------------- identification
def test_identification_prediction_sees_the_motors_through_the_ratio():
    """K_t, counts, rotor and Coulomb friction at the joints: n K_t, n 4000, n^2 (J_m + J_c),
    n K_t I_0 from the catalog motors (data) and the hand J_c; its links' mass matrix without
    the rotors (no rotor counted twice). Different ratios (different counts per joint turn):
    each joint's K_t through its own n, the routine's step the coarsest joint's, 4000 x 2.5
    (the smallest of :data:`NS`)."""
    from cad.families.pen.dynamics import mass_matrix_si
    from cad.families.pen.identify import predict

    n = 4.0
    d = _design(_one_ratio(n))
    rep = _bodies(d, np.random.default_rng(38))
    p = predict(d, {"bodies": rep})
    assert p.counts_per_rev == 4000 * n
    for k, j in enumerate(JOINTS):
        m = _motor(d, j)
        assert p.kt_Nm_per_A[k] == pytest.approx(n * m.torque_constant_mNm_per_A * 1e-3, rel=1e-12)
        assert p.rotor_kg_m2[k] == pytest.approx(_jq_by_hand(d, j, n), rel=1e-9)
        assert p.Tc_Nm[k] == pytest.approx(n * m.torque_constant_mNm_per_A * m.no_load_current_mA * 1e-6, rel=1e-9)
    X = _home(d)
    lam = p.link_mass_X(np.array([[*(X[:3] * 1e-3), *X[3:]]]))[0]
    bare = mass_matrix_si(d, _massprops(rep), X, np.zeros(6))
    rotors = mass_matrix_si(d, _massprops(rep), X) - bare
    # pitch 0 at home: X' = v; the two body Jacobians by central differences of different steps
    # (measured 1e-8 apart), far below the rotors' share a double count would add
    S = np.diag(1.0 / np.sqrt(np.diag(bare)))  # each coordinate in its own unit: kg, kg m^2
    assert (np.diag(S @ rotors @ S) > 1e-2).all()
    np.testing.assert_allclose(S @ lam @ S, S @ bare @ S, rtol=1e-6, atol=1e-6)
    dp = _design(_per_motor())
    per = predict(dp, {"bodies": rep})
    assert per.counts_per_rev == 4000 * min(NS)
    for k, j in enumerate(JOINTS):
        assert per.kt_Nm_per_A[k] == pytest.approx(NS[k] * _motor(dp, j).torque_constant_mNm_per_A * 1e-3, rel=1e-12)


# ----------------------------------------------------------------------------- the ropes
def _k_q_by_hand(j: str, n: float) -> float:
    from cad.actuators.capstan import CAPSTAN_GAP_MM
    from cad.data.cables import CABLES

    k = _kind(j)
    rc = k["capstan_diameter_mm"] / 2
    rd = n * rc
    L = math.sqrt((rd + rc + CAPSTAN_GAP_MM) ** 2 - (rd - rc) ** 2) * 1e-3
    return CABLES[k["cable"]].axial_stiffness_EA_N * 2 / L * (rd * 1e-3) ** 2


def _energy_hessian(pen, X: np.ndarray, k: np.ndarray, h: float = 2e-3) -> np.ndarray:
    """(N, 5, 5) Hessian (per m and per rad) of the ropes' energy U = 1/2 sum k_i (q_i(X + dX) -
    q_i(X))^2 by central differences of the inverse kinematics (mm / rad steps of ``h``)."""
    q0 = hp.ik(pen, X)[0]
    sc = np.array([1e-3, 1e-3, 1e-3, 1.0, 1.0])

    def U(dX):
        dq = hp.ik(pen, X + dX)[0] - q0
        return 0.5 * np.einsum("i,ni->n", k, dq * dq)

    H = np.empty((len(X), 5, 5))
    E = np.eye(5) * h
    for a in range(5):
        for b in range(5):
            H[:, a, b] = (U(E[a] + E[b]) - U(E[a] - E[b]) - U(E[b] - E[a]) + U(-E[a] - E[b])) / (
                4 * h * h * sc[a] * sc[b])
    return H


def _energy_compliance(pen, X: np.ndarray, k: np.ndarray) -> np.ndarray:
    """(x, y, z) compliance (N, 3, 3) m/N of the ropes at the pen, its moments free: the inverse
    of :func:`_energy_hessian`, its translational block."""
    return np.linalg.inv(_energy_hessian(pen, X, k))[:, :3, :3]


def test_rope_stiffness_at_the_pen_against_the_ropes_potential_energy():
    """cable_handle_stiffness_N_per_m = min over the grid of 1 / lambda_max of the ropes' (x, y,
    z) compliance, the reference from the Hessian of the ropes' energy; K_max in series."""
    from cad.families.pantograph.capstan import capstan_rows

    d = _design(_per_motor())
    k = np.array([_k_q_by_hand(j, n) for j, n in zip(JOINTS, NS, strict=True)])
    rows = {r["key"]: r for r in capstan_rows(d, 900.0)[0]}
    for i, n in enumerate(NS):
        assert rows[f"cable_stiffness_Nm_per_rad_{i + 1}"]["value"] == pytest.approx(k[i], rel=1e-9)
        assert rows[f"transmission_ratio_{i + 1}"]["value"] == n
    C = _energy_compliance(d.mechanism, d.workspace_points(), k)
    worst = 1.0 / np.linalg.eigvalsh(C)[:, -1].max()
    assert rows["cable_handle_stiffness_N_per_m"]["value"] == pytest.approx(worst, rel=1e-4)  # FD Hessian
    assert rows["K_max_with_cable_N_per_m"]["value"] == pytest.approx(
        1 / (1 / 900.0 + 1 / rows["cable_handle_stiffness_N_per_m"]["value"]), rel=1e-12)


def test_a_direct_motor_among_ropes_holds_its_joint_rigidly():
    """[[transmission]] with arm A's waist direct: the pen moves only where that joint stays
    put, so the ropes' compliance is the energy reference restricted to the null space N of the
    held joint's row of dq/dX (both by finite differences of the IK): N (N^T H N)^-1 N^T."""
    from cad.families.pen.capstan import rope_compliance_m_per_N

    raw = _per_motor()
    raw["transmission"][0] = {"kind": "direct"}
    d = _design(raw)
    k = {j: _k_q_by_hand(j, n) for j, n in zip(JOINTS[1:], NS[1:], strict=True)}
    got = rope_compliance_m_per_N(d, k)
    X = d.workspace_points()[::11]
    H = _energy_hessian(d.mechanism, X, np.array([0.0, *k.values()]))
    row = _fd_jacobian(d.mechanism, X)[:, 0, :]  # the held waist's dq/dX
    want = []
    for Hi, ri in zip(H, row, strict=True):
        N = np.linalg.svd(ri[None, :])[2][1:].T  # (5, 4) null space of the held row
        want.append(np.linalg.eigvalsh((N @ np.linalg.inv(N.T @ Hi @ N) @ N.T)[:3, :3])[-1])
    np.testing.assert_allclose(got[::11], want, rtol=1e-4)  # FD Hessian and row


def test_capstan_rows_bom_lines_and_winding_steps_of_each_motor():
    """Each motor's rows against hand figures of the bundled design: bend ratio D/d, the rope
    load and safety factor at each motor's peak torque (RE 40 waists, RE 35 shoulders), the drum
    sector and the rope's cut length from the joint's range over the workspace (IK of the grid);
    one rope line per motor; the winding steps name each motor's anchor; every default limit of
    the capstan rows is met."""
    from cad.data.cables import CABLES
    from cad.families.pantograph.capstan import bom_lines, capstan_rows, winding_steps
    from cad.tolerances import CAPSTAN_RANGE_MARGIN_DEG

    d = _design()
    rows, lim = capstan_rows(d, None)
    v = {r["key"]: r["value"] for r in rows}
    q = np.degrees(np.unwrap(hp.ik(d.mechanism, d.workspace_points())[0], axis=0))
    rng = q.max(axis=0) - q.min(axis=0) + 2 * CAPSTAN_RANGE_MARGIN_DEG
    lines = bom_lines(d)
    assert [b["part"] for b in lines] == [f"capstan_cable_{i}" for i in range(1, 7)]
    steps = "\n".join(winding_steps(d))
    e = math.exp(0.12 * 2 * math.pi * WRAPS)
    for i, (j, n) in enumerate(zip(JOINTS, NB, strict=True)):
        s, k = f"_{i + 1}", _kind(j)
        dc = k["capstan_diameter_mm"]
        dT = _motor(d, j).torque_peak_mNm * 1e-3 / (dc / 2e3)  # n tau / r_d = tau / r_c
        T0 = dT / 2 * (e + 1) / (e - 1)
        rd, rc = n * dc / 2, dc / 2
        L = math.sqrt((rd + rc + 2.0) ** 2 - (rd - rc) ** 2)
        assert v["bend_ratio" + s] == dc / k["rope_d"]
        assert v["cable_pretension_N" + s] == pytest.approx(T0, rel=1e-9)
        assert v["cable_safety_factor" + s] == pytest.approx(
            CABLES[k["cable"]].min_breaking_load_N / (T0 + dT / 2), rel=1e-9)
        arc = rng[i] + 2 * math.degrees(2 * 10.0 / (2 * rd))
        assert v["drum_sector_deg" + s] == pytest.approx(arc, rel=1e-9)
        cut = math.pi * dc * WRAPS + 2 * L + math.pi * 2 * rd * arc / 360 + 2 * 20.0
        assert v["cable_cut_length_mm" + s] == pytest.approx(cut, rel=1e-9)
        assert f"cut length {cut:.0f} mm" in lines[i]["description"]
        assert f"capstan_anchor{s}_1" in steps and f"capstan_tensioner{s}" in steps
    assert len(lim) == 24 and all(lim[k].met(v[k]) for k in lim)
    assert capstan_rows(_design(DIRECT), 900.0) == ([], {}) and bom_lines(_design(DIRECT)) == []


# ----------------------------------------------------------------------------- the frame
def _pen_end_rho_m(d, arm: str) -> np.ndarray:
    """rho (m) of the arm's end E (its distance from the waist axis) at each structure pose."""
    from cad.families.pen.layout import motion_task
    from cad.structure import pen as sp

    X, _ = motion_task(d)
    T = sp.arm_poses(d, X, arm)[f"{arm}_distal_lower"]
    return (T @ np.array([d.mechanism.distal_mm, 0.0, 1.0]))[:, 1] * 1e-3


def _per_pose(d, rep, arm: str) -> np.ndarray:
    """(poses, 3) compliance um/N (vertical, radial, normal) of one arm at each structure pose."""
    from cad.families.pen.layout import motion_task
    from cad.structure import pen as sp
    from cad.structure.graph import directions

    X, _ = motion_task(d)
    g, lengths = sp.arm_graph(d, arm)
    lumped, _ = sp.arm_lumped(d, g, rep, lengths, arm)
    poses = sp.arm_poses(d, X, arm)
    return np.array([[sp.arm_at(g, lumped, {n: v[k] for n, v in poses.items()}, 1.0, directions())[
        "compliance_um_per_N"][ax] for ax in sp.AXES] for k in range(len(X))])


def test_a_waist_rope_adds_rho_squared_over_k_to_the_normal_compliance():
    """Two springs in series: with only the waists behind capstans, the arm turns rigidly about
    its waist axis on the rope (k_w) in series with the clamped frame, so at every pose the
    normal compliance at the pen end is the held frame's plus rho_E^2 / k_w (rho_E the end's
    distance from the waist axis), the in-plane ones unchanged; the first out-of-plane mode drops."""
    from cad.structure import pen as sp

    raw = copy.deepcopy(RAW)
    raw["transmission"] = [t if j.endswith("waist") else {"kind": "direct"}
                           for t, j in zip(_tables(NB), JOINTS, strict=True)]
    d, d0 = _design(raw), _design(DIRECT)
    rep = _bodies(d, np.random.default_rng(41))
    kw = _k_q_by_hand("A_q_waist", NB[0])
    for arm in ("A", "B"):
        rope, held = _per_pose(d, rep, arm), _per_pose(d0, rep, arm)
        np.testing.assert_allclose(rope[:, :2], held[:, :2], rtol=1e-9)
        np.testing.assert_allclose(rope[:, 2], held[:, 2] + _pen_end_rho_m(d, arm) ** 2 / kw * 1e6, rtol=1e-6)
    a, a0 = sp.analyse(d, rep, 1.0), sp.analyse(d0, rep, 1.0)
    assert a["first_mode_out_of_plane_Hz"] < a0["first_mode_out_of_plane_Hz"]
    assert a["first_mode_in_plane_Hz"] == pytest.approx(a0["first_mode_in_plane_Hz"], rel=1e-9)
    assert a["rope_stiffness_Nm_per_rad"] == pytest.approx({"A_q_waist": kw, "B_q_waist": kw}, rel=1e-12)


def test_the_shoulder_ropes_only_add_compliance(monkeypatch):
    """Every rope of the bundled design in the arms' frames: at every pose and axis at least as
    compliant as the held frame (springs in series only add compliance), the in-plane mode
    drops (the shoulder ropes turn the links about the plane's normal); ropes 1e9 times
    stiffer give back the held frame."""
    from cad.structure import pen as sp

    d, d0 = _design(), _design(DIRECT)
    rep = _bodies(d, np.random.default_rng(42))
    for arm in ("A", "B"):
        assert (_per_pose(d, rep, arm) >= _per_pose(d0, rep, arm) * (1 - 1e-9)).all()
    a, a0 = sp.analyse(d, rep, 1.0), sp.analyse(d0, rep, 1.0)
    assert a["first_mode_in_plane_Hz"] < a0["first_mode_in_plane_Hz"]
    stiff = {j: 1e9 * _k_q_by_hand(j, n) for j, n in zip(JOINTS, NB, strict=True)}
    monkeypatch.setattr(sp, "motor_rope_stiffness_Nm_per_rad", lambda design: stiff)
    for arm in ("A", "B"):
        np.testing.assert_allclose(_per_pose(d, rep, arm), _per_pose(d0, rep, arm), rtol=1e-5)


def test_bundled_design_figures_regression_pin():
    """Regression pin (our own run, typed in docs/families/pen.md and the design's header): the
    direct pen 0.84 N continuous in every direction, the capstan one 3.02 N against its 2 N;
    drum sectors 89 deg (waists) and 119 deg (shoulders); the ropes' 1.68e5 N/m at the pen."""
    from cad.families.pantograph.capstan import capstan_rows
    from cad.families.pantograph.datasheet import motor_force_rows

    d = _design()
    force = {r["key"]: r["value"] for r in motor_force_rows(d)}["continuous_force_N"]
    direct = {r["key"]: r["value"] for r in motor_force_rows(_design(DIRECT))}["continuous_force_N"]
    assert (round(direct, 2), round(force, 2)) == (0.84, 3.02) and force >= d.actuators["force_max_N"] == 2.0
    v = {r["key"]: r["value"] for r in capstan_rows(d, None)[0]}
    assert [round(v[f"drum_sector_deg_{i}"]) for i in range(1, 7)] == [89, 119, 119, 89, 119, 119]
    assert f"{v['cable_handle_stiffness_N_per_m']:.3g}" == "1.68e+05"


def test_the_pens_datasheet_rows_carry_the_capstan_rows_limits_and_ropes():
    """The pen's datasheet (the rows a build would print, here from seeded bodies): each motor's
    capstan rows with their default limits, the ropes at the pen and K_max in series with the
    datasheet's own eq (25) row, and the structure rows' boundary naming each rope's k_q (by
    hand); the direct pen has none of them."""
    from cad.families.pen.datasheet import rows_and_limits

    d = _design()
    rep = {"bodies": _bodies(d, np.random.default_rng(43))}
    rows, limits, _ = rows_and_limits(d, rep, None, simulate_wall=False)
    v = {r["key"]: r for r in rows}
    for i in range(1, 7):
        assert {f"bend_ratio_{i}", f"cable_safety_factor_{i}", f"drum_sector_deg_{i}"} <= limits.keys()
        assert v[f"transmission_ratio_{i}"]["value"] == NB[i - 1]
    k25, kh = v["eq25_K_max_N_per_m"]["value"], v["cable_handle_stiffness_N_per_m"]["value"]
    assert v["K_max_with_cable_N_per_m"]["value"] == pytest.approx(1 / (1 / k25 + 1 / kh), rel=1e-12)
    assert {"first_mode_Hz", "max_stress_MPa", "continuous_force_N"} <= limits.keys()
    kw = _k_q_by_hand("A_q_waist", 3.0)
    assert f"A_q_waist {kw:.4g} N m/rad" in v["first_mode_Hz"]["boundary"]
    rows0, limits0, _ = rows_and_limits(_design(DIRECT), rep, None, simulate_wall=False)
    assert not any(r["key"].startswith(("transmission_ratio", "cable_")) for r in rows0)
    assert "bend_ratio_1" not in limits0 and "k_q" not in {r["key"]: r for r in rows0}["first_mode_Hz"]["boundary"]
