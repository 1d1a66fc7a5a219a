"""A capstan on the motors of the twin-pantograph haptic mouse (issue 35 §1): the design takes
``[transmission]`` (one table for the four motors, or ``[[transmission]]`` one per motor: knob
left, knob right, crank left, crank right), and every analysis reads the resolved device's ratio
n. The figures here read the design, the resolved device and seeded plausible bodies (not
from a build), as tests/families/delta/test_delta_capstan.py does; the build of
designs/twin_pantograph_capstan.toml (its capstan solids): tests/families/pantograph/test_twin_capstan_build.py.

References, each independent of the code under test:

* force, resolution and the reflected inertia: the twin's Jacobian dq/dX (4 x 3) by central
  finite differences of its inverse kinematics (not the analytic Jacobian the datasheet uses);
* the ropes at the handle: the stiffness as the Hessian of the ropes' potential energy
  1/2 sum k_i (q_i(X + dX) - q_i(X))^2 by finite differences of the inverse kinematics (no
  Jacobian), inverted, the knob's moment free;
* reflected inertia n^2 (J_m + J_c), J_c the capstan tube's m (r_o^2 + r_i^2) / 2 written out
  here, from the catalog motor's rotor inertia (data);
* MuJoCo: its joint-space inertia reduced onto the twin's three coordinates
  (``cad.sim.mj.twin_task_mass_matrix``) against the effective mass at home; its gear, force
  range and armature against the catalog motor (data) and the hand formula;
* firmware: the generated C compiled with gcc and run: counts -> angle and torque -> current
  through each motor's n against the hand formulas, its mass matrix at home against MuJoCo's;
* the frame: each rope's k_q = EA (2 / L) r_d^2 by hand; springs in series can only add
  compliance (the frame with the ropes at least as compliant as the frame held rigidly and as
  the ropes on rigid links), a rope of infinite stiffness gives back the held frame.
"""

from __future__ import annotations

import copy
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
from cad.kinematics import twin_pantograph as tw
from tests.compilers import compiler

ROOT = Path(__file__).resolve().parents[3]
BUNDLED = ROOT / "designs" / "twin_pantograph_capstan.toml"
RAW = tomllib.loads(BUNDLED.read_text())
DIRECT = tomllib.loads((ROOT / "designs" / "haptic_mouse.toml").read_text())
JOINTS = ("knob_q_left", "knob_q_right", "crank_q_left", "crank_q_right")
#: One ratio per motor for the per-motor tests (capstan 32 mm; drums 96 .. 192 mm).
NS = (3.0, 4.0, 5.0, 6.0)
DC_MM, ROPE, ROPE_D, WRAPS = 32.0, "steel-7x7-0.8", 0.8, 3.0
#: The bundled design's ratio (its file: 136 mm drum / 32 mm capstan).
NB = 136.0 / 32.0
#: Same mechanics in double precision, two methods (measured ~1e-15 relative).
DYN_REL = 1e-9


def _design(raw=RAW):
    return parse_design(copy.deepcopy(raw), "variant.toml")


def _per_motor(ns=NS) -> dict:
    raw = copy.deepcopy(RAW)
    t = raw.pop("transmission")
    raw["transmission"] = [dict(t, drum_diameter_mm=DC_MM * n) for n in ns]
    return raw


def _capstan_izz_by_hand(bore_mm: float, dc_mm: float = DC_MM) -> float:
    """J_c of the grooved capstan by hand (tests/capstan_ref.py: a steel tube from the bore to
    the crests, the turns at 1.5 rope diameters plus an 8 mm hub, less the helical groove)."""
    from cad.data.materials import get_material
    from tests.capstan_ref import grooved_capstan_izz_kg_m2

    return grooved_capstan_izz_kg_m2(dc_mm, ROPE_D, WRAPS, bore_mm, get_material("steel-1018").density_kg_m3)


def _jq_by_hand(d, n: float) -> float:
    from cad.data.catalog import get_motor

    m = get_motor(d.parts.motor)
    return n * n * (m.rotor_inertia_g_cm2 * 1e-7 + _capstan_izz_by_hand(m.shaft_diameter_mm))


def _fd_jacobian(tp, X: np.ndarray, h: float = 1e-4) -> np.ndarray:
    """dq/dX (N, 4, 3) by central differences of the inverse kinematics; X (N, 3) (mm, mm,
    rad), columns in m and rad (h mm / h rad)."""
    X = np.atleast_2d(X)
    J = np.empty((len(X), 4, 3))
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        dq = tw.ik(tp, X + e).q_rad - tw.ik(tp, X - e).q_rad
        J[:, :, k] = dq / (2 * h * (1e-3 if k < 2 else 1.0))
    return J


def _bodies(rng) -> dict:
    """report.json ``bodies`` of a twin pantograph: seeded plausible values (not from a build)."""
    def body(m, L):
        Iz = m * (L * 1e-3) ** 2 / 12 + 1e-6
        return {"mass_kg": m, "com_mm": [L / 2, float(rng.uniform(-2, 2)), float(rng.uniform(-3, 3))],
                "inertia_com_kg_m2": np.diag([1e-6, Iz, Iz]).tolist()}
    out = {}
    for g in ("knob", "crank"):
        for s in ("left", "right"):
            out[f"{g}_proximal_{s}"] = body(float(rng.uniform(0.05, 0.09)), 125.0)
        out[f"{g}_distal"] = body(float(rng.uniform(0.03, 0.05)), 175.0)
        out |= {f"{g}_distal_{s}": out[f"{g}_distal"] for s in ("left", "right")}  # one kind, both sides
    out["crankshaft"] = {"mass_kg": 0.03, "com_mm": [5.0, 0.5, 10.0],
                         "inertia_com_kg_m2": np.diag([4e-6, 4e-6, 2e-6]).tolist()}
    return out


def _massprops(rep: dict) -> dict:
    from cad.massprops.props import MassProps

    return {k: MassProps(v["mass_kg"], np.asarray(v["com_mm"]) * 1e-3, np.asarray(v["inertia_com_kg_m2"]))
            for k, v in rep.items()}


def _home(d) -> np.ndarray:
    h = d.workspace["home_mm"]
    return np.array([h[0], h[1], math.radians(d.workspace["home_theta_deg"])])


# ----------------------------------------------------------------------------- the design
def test_bundled_file_states_its_capstan():
    t = RAW["transmission"]
    assert (t["drum_diameter_mm"] / t["capstan_diameter_mm"], t["capstan_diameter_mm"], t["wraps"], t["cable"]) == (
        NB, DC_MM, WRAPS, ROPE)


def test_both_forms_reach_the_resolved_device():
    one = resolve_device(_design())
    assert [t.motor_joint for t in one.transmissions] == list(JOINTS)
    assert all(t.is_capstan and t.ratio == NB and t.cable.key == ROPE for t in one.transmissions)
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
    ('[[transmission]]\nkind = "direct"\n[[transmission]]\nkind = "direct"\n[[transmission]]\nkind = "direct"\n'
     '[[transmission]]\nkind = "belt"\n', "transmission.4.kind"),
])
def test_a_bad_transmission_exits_2_naming_the_field(tmp_path, table, field):
    p = tmp_path / "bad.toml"
    p.write_text((ROOT / "designs" / "haptic_mouse.toml").read_text() + "\n" + table)
    code, _, err = hapticad("check", p)
    assert_one_line_error(code, err, field)


def test_the_build_is_refused_in_one_line_and_writes_nothing(tmp_path):
    """The bundled design with 5 mm layer gaps: the crank pantograph's drums meet in one band,
    and band 2's rope plane 2 x 5 + 10 + 5 = 25 mm up puts the capstan's hub top at
    25 - 1.5 x 0.8 x 3 / 2 = 23.2 mm, 23.2 - 11 = 12.2 mm past the RE 35 shaft's tip (22 mm
    from its face, less the 6 mm plate and the 5 mm mount plate), more than the 6 + 5 = 11 mm
    the motor gains with its mount plate on the base plate's top (by hand): ``build`` exits 2
    naming ``transmission``, the clash, the shortfall and the fixes, before any CAD, nothing
    written."""
    p = tmp_path / "gap5.toml"
    p.write_text(BUNDLED.read_text().replace('clevis_material = "aluminium-6061"',
                                             'clevis_material = "aluminium-6061"\nlayer_gap_mm = 5.0'))
    out = tmp_path / "out"
    code, _, err = hapticad("build", p, "--out", out)
    assert_one_line_error(code, err, "transmission", "crank pantograph", "136 mm drums", "meet in one band",
                          "12.2 mm past the maxon-re35 shaft", "more than the 11 mm", "smaller drum",
                          "direct drive on crank_q_left", "set parts.layer_gap_mm <= 4.40")
    assert not out.exists() or not any(out.iterdir())


@pytest.mark.parametrize("swap, fix", [
    (('cable = "steel-7x7-0.8"', 'cable = "steel-7x7-1.6"'), "0.1 .. 2.5 turns of the 1.5875 mm rope fit"),
    (("wraps = 3.0", "wraps = 12.0"), "0.1 .. 5 turns of the 0.8 mm rope fit"),
])
def test_a_capstan_off_its_shaft_is_refused_with_the_turns_that_fit(tmp_path, swap, fix):
    """A tester's finding: a thicker rope (or more turns) that puts the capstan off the motor
    shaft was refused naming transmission.wraps with no fix. The line now gives the turns that
    fit, by hand: the capstan's middle stays in the rope's plane, half the turns (1.5 d per
    turn) below it is the hub's top, the hub (15.14 - 1.5 x 1.5875 x 3 mm) under that. The
    1.6 mm rope's 3 turns start at z -3.57 mm, 0.57 mm under the face screws' heads (-3 mm):
    3 - 0.57 / (0.75 x 1.5875) = 2.52, floored to 2.5 turns; 12 turns of the 0.8 mm rope start
    at -7.20 mm: 12 - 4.20 / (0.75 x 0.8) = 5 turns, the capstan then on the heads exactly (the
    check's limit); the hub's top stays under the shaft's tip (11 mm) down to 0 turns."""
    p = tmp_path / "w.toml"
    p.write_text(BUNDLED.read_text().replace(*swap))
    code, _, err = hapticad("check", p)
    assert_one_line_error(code, err, "transmission.wraps", "its hub must sit on the maxon-re35 shaft", fix)


def test_the_layer_gap_the_refusal_names_lays_the_twin_out(tmp_path):
    """A tester's finding: the refusal above sent the user round in a circle (a smaller drum
    still clashes in one band) and never named the layer gap, the key that fixes it. Band 2's
    hub drops 2 mm per mm of gap (its rope plane 2 g + 1.5 drums up), so 12.2 - 11 = 1.2 mm
    over asks g <= 5 - 1.2 / 2 = 4.4 mm (by hand): at 4.40 mm the layout is found (the raised
    motor's shaft reaches band 2's hub), at 4.45 mm it is still refused."""
    from cad.design import load_design
    from cad.errors import DesignError
    from cad.families.pantograph.twin_placement import group_layout

    def gap(g):
        p = tmp_path / f"gap{g}.toml"
        p.write_text(BUNDLED.read_text().replace('clevis_material = "aluminium-6061"',
                                                 f'clevis_material = "aluminium-6061"\nlayer_gap_mm = {g}'))
        return load_design(p)

    assert group_layout(gap(4.4))
    with pytest.raises(DesignError, match="parts.layer_gap_mm <= 4.40"):
        group_layout(gap(4.45))


# ----------------------------------------------------------------------------- force, resolution
def test_motor_force_through_each_ratio_against_finite_differences():
    """continuous_force_N = min over the workspace of sigma_min of the translational rows of
    J^T diag(n_i tau) (the knob's moment free), J = dq/dX by finite differences."""
    from cad.data.catalog import get_motor
    from cad.families.pantograph.datasheet import motor_force_rows

    d = _design(_per_motor())
    tau = get_motor(d.parts.motor).torque_continuous_mNm * 1e-3
    J = _fd_jacobian(d.mechanism, d.workspace_points())
    A = np.swapaxes(J, 1, 2)[:, :2, :] * (np.asarray(NS) * tau)[None, None, :]
    sig = np.linalg.svd(A, compute_uv=False)[:, -1]
    rows = {r["key"]: r for r in motor_force_rows(d)}
    assert rows["continuous_force_N"]["value"] == pytest.approx(sig.min(), rel=1e-6)  # FD step error
    assert rows["continuous_force_N"]["max"] == pytest.approx(sig.max(), rel=1e-6)
    assert "x capstan n = 6 at crank_q_right" in rows["continuous_force_N"]["model"]


def test_resolution_through_each_ratio_against_finite_differences():
    from cad.families.pantograph.datasheet import joint_counts, resolution_m

    d = _design(_per_motor())
    X = d.workspace_points()
    counts = joint_counts(d)
    assert counts.tolist() == [4000 * n for n in NS]
    J = _fd_jacobian(d.mechanism, X)
    got = resolution_m(d, counts)
    for k in (0, len(X) // 2, len(X) - 1):
        want = np.linalg.norm(np.linalg.pinv(J[k][:, :2]) * (2 * math.pi / (4000 * np.asarray(NS)))[None, :], 2)
        assert got[k] == pytest.approx(want, rel=1e-6)


# ----------------------------------------------------------------------------- inertia
def test_reflected_rotor_inertia_in_the_effective_mass_at_home():
    """The effective mass at home minus the one without rotors = J^T diag(n_i^2 (J_m + J_c)) J
    on the diagonal (J by finite differences, J_c by hand): x, y in g, theta in g cm^2."""
    from cad.families.pantograph.dynamics import effective_mass

    d = _design(_per_motor())
    bodies = _massprops(_bodies(np.random.default_rng(35)))
    X = _home(d)
    eff, bare = effective_mass(d, bodies, X[:2])
    jq = np.array([_jq_by_hand(d, n) for n in NS])
    dev = resolve_device(d)
    assert [dev.joint_rotor_inertia_kg_m2(j) for j in JOINTS] == pytest.approx(jq.tolist(), rel=1e-9)
    J = _fd_jacobian(d.mechanism, X)[0]
    added = np.einsum("i,ia,ia->a", jq, J, J)
    for k, a, unit in (("mass_x_g_diag", 0, 1e3), ("mass_y_g_diag", 1, 1e3), ("inertia_theta_g_cm2_diag", 2, 1e7)):
        assert eff[k] - bare[k] == pytest.approx(added[a] * unit, rel=1e-6), k  # FD Jacobian


def _sim_xml(d, rep: dict) -> str:
    """The MJCF of ``d`` on the seeded bodies; the layers' heights from the same linkage's
    direct-drive layout (the bodies carry no part here; the per-motor drums, up to 192 mm, are
    not laid out)."""
    from cad.export.sim import mjcf_text
    from cad.families.pantograph.layout import layout
    from cad.families.pantograph.sim import sim_model

    X = _home(d)
    model = sim_model(d, _massprops(rep), [], layout(_design(DIRECT)), X.tolist(), tw.ik(d.mechanism, X[None]))
    return mjcf_text(model)


def test_mjcf_in_mujoco_has_gear_n_the_reflected_armature_and_the_effective_mass():
    import mujoco

    from cad.data.catalog import get_motor
    from cad.families.pantograph.dynamics import effective_mass
    from cad.sim import mj

    d = _design(_per_motor())
    rep = _bodies(np.random.default_rng(36))
    m = mujoco.MjModel.from_xml_string(_sim_xml(d, rep))
    data = mujoco.MjData(m)
    mujoco.mj_forward(m, data)
    peak = get_motor(d.parts.motor).torque_peak_mNm * 1e-3  # the motor's own; the joint gets n times it
    names = [m.actuator(i).name for i in range(m.nu)]
    for j, n in zip(JOINTS, NS, strict=True):
        i = names.index(j.replace("_q_", "_motor_"))
        assert m.actuator_gear[i, 0] == n
        np.testing.assert_allclose(m.actuator_forcerange[i], [-peak, peak], rtol=1e-12)
        assert m.dof_armature[mj.joint_dof(m, j)] == pytest.approx(_jq_by_hand(d, n), rel=1e-9)
    r = mj.twin_task_mass_matrix(m, data)
    M, Mi = r["M_task"], np.linalg.inv(r["M_task"])
    eff, _ = effective_mass(d, _massprops(rep), _home(d)[:2])
    got = {"mass_x_g_diag": M[0, 0] * 1e3, "mass_y_g_diag": M[1, 1] * 1e3, "inertia_theta_g_cm2_diag": M[2, 2] * 1e7,
           "mass_x_g_apparent": 1e3 / Mi[0, 0], "mass_y_g_apparent": 1e3 / Mi[1, 1],
           "inertia_theta_g_cm2_apparent": 1e7 / Mi[2, 2]}
    for k, v in got.items():
        assert v == pytest.approx(eff[k], rel=DYN_REL), k
    assert r["residual_m"] < 1e-12


# ----------------------------------------------------------------------------- firmware
def test_firmware_compiled_with_gcc_goes_through_each_ratio(tmp_path):
    """HC_GEAR, counts -> angle 2 pi c / (4000 n_i), torque -> current tau / (n_i K_t), the C mass
    matrix at home against MuJoCo's (the same bodies, armature n_i^2 (J_m + J_c)); the build's
    own test_device.c passes over its vectors."""
    import mujoco

    from cad.firmware import linkage_files
    from cad.sim import mj

    d = _design(_per_motor())
    rep = _bodies(np.random.default_rng(37))
    files = linkage_files(d, {"bodies": rep}, "tw35", resolve_device(d))
    h = files["firmware/hapticad_device.h"]
    assert re.search(r"#define HC_GEAR \{ (.+) \}", h).group(1) == ", ".join(f"HC_R({n!r})" for n in NS)
    fw = tmp_path / "fw"
    fw.mkdir()
    for rel, text in files.items():
        if rel.count("/") == 1:
            (fw / Path(rel).name).write_text(text)
    q0 = tw.ik(d.mechanism, _home(d)[None]).q_rad[0]
    (tmp_path / "m.c").write_text(
        '#include <stdio.h>\n#include "hapticad_device.h"\nint main(void){hc_encoder_t e = HC_ENCODER_DEFAULT;'
        'long c[4]={1000,-500,250,-125};long z[4]={0,0,0,0};hc_real q[4],z0[4],t[4]={0.3,-0.1,0.2,-0.4},a[4],M[9];'
        f'hc_real qh[4]={{{", ".join(repr(float(v)) for v in q0)}}};int i,s;'
        'hc_counts_to_angles(&e,c,q);hc_counts_to_angles(&e,z,z0);s=hc_motor_currents(t,HC_LIMIT_PEAK,a);'
        'i=hc_mass_matrix(qh,M);printf("%d %d\\n",s,i);'
        'for(i=0;i<4;++i)printf("%.17g %.17g %d\\n",q[i]-z0[i],a[i],(int)e.direction[i]);'
        'for(i=0;i<9;++i)printf("%.17g\\n",M[i]);return 0;}\n')
    exe = tmp_path / "m"
    subprocess.run([compiler(), "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", f"-I{fw}", "-o", str(exe),
                    str(tmp_path / "m.c"), str(fw / "hapticad_device.c"), "-lm"], check=True, timeout=120)
    lines = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout.split("\n")
    assert lines[0] == "0 0"
    kt = 38.9e-3  # maxon RE 35 catalog (cad.data.catalog maxon-re35)
    for k, (c, tau, n) in enumerate(zip((1000, -500, 250, -125), (0.3, -0.1, 0.2, -0.4), NS, strict=True)):
        dq, a, sign = map(float, lines[1 + k].split())
        assert dq == pytest.approx(sign * 2 * math.pi * c / (4000 * n), rel=1e-12)
        assert a == pytest.approx(tau / (n * kt), rel=1e-12)
    M = np.array([float(v) for v in lines[5:14]]).reshape(3, 3)
    m = mujoco.MjModel.from_xml_string(_sim_xml(d, rep))
    data = mujoco.MjData(m)
    mujoco.mj_forward(m, data)
    ref = mj.twin_task_mass_matrix(m, data)["M_task"]
    np.testing.assert_allclose(M, ref, rtol=DYN_REL, atol=DYN_REL * np.abs(ref).max())
    exe2 = tmp_path / "td"
    subprocess.run([compiler(), "-std=c99", "-O2", "-o", str(exe2), str(fw / "test_device.c"),
                    str(fw / "hapticad_device.c"), "-lm"], check=True, capture_output=True, timeout=120)
    from cad import tolerances as tol
    r = subprocess.run([str(exe2), str(fw / "test_vectors.json"), *map(repr, (
        tol.FIRMWARE_DOUBLE_POSITION_M, tol.FIRMWARE_DOUBLE_TORQUE_NM, tol.FIRMWARE_FD_JACOBIAN))],
        capture_output=True, text=True, timeout=120)
    assert r.returncode == 0 and "failures 0" in r.stdout, r.stdout + r.stderr


def test_identification_prediction_sees_the_motors_through_the_ratio():
    """The twin's identification prediction: K_t, counts, rotor and Coulomb friction at the
    joints, n K_t, n 4000, n^2 (J_m + J_c), n K_t I_0 from the catalog motor (data) and the hand
    J_c; its links' mass matrix without the rotors (no rotor counted twice)."""
    from cad.data.catalog import get_motor
    from cad.families.pantograph.dynamics import effective_mass
    from cad.families.pantograph.identify_twin import predict

    d = _design()
    rep = _bodies(np.random.default_rng(38))
    m = get_motor(d.parts.motor)
    p = predict(d, {"bodies": rep})
    assert p.kt_Nm_per_A == pytest.approx(NB * m.torque_constant_mNm_per_A * 1e-3, rel=1e-12)
    assert p.counts_per_rev == 4000 * NB
    assert p.rotor_kg_m2 == pytest.approx(_jq_by_hand(d, NB), rel=1e-9)
    assert p.Tc_Nm == pytest.approx(NB * m.torque_constant_mNm_per_A * m.no_load_current_mA * 1e-6, rel=1e-9)
    X = _home(d)
    lam = p.link_mass_X(np.array([[X[0] * 1e-3, X[1] * 1e-3, X[2]]]))[0]
    _, bare = effective_mass(d, _massprops(rep), X[:2])
    assert lam[0, 0] * 1e3 == pytest.approx(bare["mass_x_g_diag"], rel=1e-9)
    assert lam[2, 2] * 1e7 == pytest.approx(bare["inertia_theta_g_cm2_diag"], rel=1e-9)


# ----------------------------------------------------------------------------- the ropes
def _k_q_by_hand(n: float) -> float:
    from cad.actuators.capstan import CAPSTAN_GAP_MM
    from cad.data.cables import CABLES

    rd, rc = n * DC_MM / 2, DC_MM / 2
    L = math.sqrt((rd + rc + CAPSTAN_GAP_MM) ** 2 - (rd - rc) ** 2) * 1e-3
    return CABLES[ROPE].axial_stiffness_EA_N * 2 / L * (rd * 1e-3) ** 2


def _energy_compliance(tp, X: np.ndarray, k: np.ndarray, h: float = 2e-3) -> np.ndarray:
    """(x, y) compliance (N, 2, 2) m/N of the ropes at the handle, the knob's moment free: the
    inverse of the Hessian (m, rad) of U = 1/2 sum k_i (q_i(X + dX) - q_i(X))^2 by central
    differences of the inverse kinematics (mm / rad steps of ``h``)."""
    q0 = tw.ik(tp, X).q_rad
    sc = np.array([1e-3, 1e-3, 1.0])

    def U(dX):
        dq = tw.ik(tp, X + dX).q_rad - q0
        return 0.5 * np.einsum("i,ni->n", k, dq * dq)

    H = np.empty((len(X), 3, 3))
    E = np.eye(3) * h
    for a in range(3):
        for b in range(3):
            H[:, a, b] = (U(E[a] + E[b]) - U(E[a] - E[b]) - U(E[b] - E[a]) + U(-E[a] - E[b])) / (
                4 * h * h * sc[a] * sc[b])
    return np.linalg.inv(H)[:, :2, :2]


def test_rope_stiffness_at_the_handle_against_the_ropes_potential_energy():
    """cable_handle_stiffness_N_per_m = min over the grid of 1 / lambda_max of the ropes' (x, y)
    compliance, the reference from the Hessian of the ropes' energy; K_max in series."""
    from cad.families.pantograph.capstan import capstan_rows

    d = _design(_per_motor())
    k = np.array([_k_q_by_hand(n) for n in NS])
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
    """[[transmission]] with the knob's left motor direct: the ropes' compliance at the handle
    equals the energy reference with that joint's spring s times stiffer, s -> infinity by
    Richardson's extrapolation from s = 1e4 and 1e5 (the compliance goes as C + a / s)."""
    from cad.families.pantograph.twin_capstan import rope_compliance_m_per_N

    raw = _per_motor()
    raw["transmission"][0] = {"kind": "direct"}
    d = _design(raw)
    k = {j: _k_q_by_hand(n) for j, n in zip(JOINTS[1:], NS[1:], strict=True)}
    got = rope_compliance_m_per_N(d, k)
    X = d.workspace_points()[::7]
    C = [_energy_compliance(d.mechanism, X, np.array([s * k["knob_q_right"], *k.values()])) for s in (1e4, 1e5)]
    want = np.linalg.eigvalsh((10 * C[1] - C[0]) / 9)[:, -1]
    np.testing.assert_allclose(got[::7], want, rtol=1e-4)  # FD Hessian


def test_capstan_rows_bom_lines_and_winding_steps_of_each_motor():
    """Each motor's rows against hand figures of the bundled design: bend ratio D/d, the rope
    load and safety factor at the RE 35's peak torque, the drum sector and the rope's cut
    length from the link's range over the workspace (IK of the grid); one rope line per motor;
    the winding steps name each motor's anchor, tensioner and pretension; the default limits
    of the capstan rows are met."""
    from cad.data.cables import CABLES
    from cad.data.catalog import get_motor
    from cad.families.pantograph.capstan import bom_lines, capstan_rows, winding_steps
    from cad.tolerances import CAPSTAN_RANGE_MARGIN_DEG

    d = _design()
    rows, lim = capstan_rows(d, None)
    v = {r["key"]: r["value"] for r in rows}
    rope = CABLES[ROPE]
    dT = get_motor(d.parts.motor).torque_peak_mNm * 1e-3 / (DC_MM / 2e3)  # n tau / r_d = tau / r_c
    e = math.exp(0.12 * 2 * math.pi * WRAPS)
    T0 = dT / 2 * (e + 1) / (e - 1)
    rd, rc = NB * DC_MM / 2, DC_MM / 2
    L = math.sqrt((rd + rc + 2.0) ** 2 - (rd - rc) ** 2)
    q = np.degrees(np.unwrap(tw.ik(d.mechanism, d.workspace_points()).q_rad, axis=0))
    rng = q.max(axis=0) - q.min(axis=0) + 2 * CAPSTAN_RANGE_MARGIN_DEG
    lines = bom_lines(d)
    assert [b["part"] for b in lines] == [f"capstan_cable_{i}" for i in range(1, 5)]
    steps = "\n".join(winding_steps(d))
    for i in range(4):
        s = f"_{i + 1}"
        assert v["bend_ratio" + s] == DC_MM / ROPE_D
        assert v["cable_pretension_N" + s] == pytest.approx(T0, rel=1e-9)
        assert v["cable_safety_factor" + s] == pytest.approx(rope.min_breaking_load_N / (T0 + dT / 2), rel=1e-9)
        arc = rng[i] + 2 * math.degrees(2 * 10.0 / (2 * rd))
        assert v["drum_sector_deg" + s] == pytest.approx(arc, rel=1e-9)
        cut = math.pi * DC_MM * WRAPS + 2 * L + math.pi * 2 * rd * arc / 360 + 2 * 20.0
        assert v["cable_cut_length_mm" + s] == pytest.approx(cut, rel=1e-9)
        assert f"cut length {cut:.0f} mm" in lines[i]["description"]
        assert f"capstan_anchor{s}_1" in steps and f"capstan_tensioner{s}" in steps
        assert f"until the rope holds at least {T0:.1f} N (datasheet cable_pretension_N{s}" in steps
    assert len(lim) == 16 and all(lim[k].met(v[k]) for k in lim)
    assert capstan_rows(_design(DIRECT), 900.0) == ([], {}) and bom_lines(_design(DIRECT)) == []


@pytest.mark.slow
def test_the_ropes_in_the_frame_only_add_compliance(monkeypatch):
    """The frame with each link turned through its rope (k_q = EA (2 / L) r_d^2 by hand) at B:
    at every pose along x and y at least as compliant as the frame held rigidly at B and as the
    ropes on rigid links (springs in series only add compliance); ropes 1e9 times stiffer give
    back the held frame; the first in-plane mode drops (the ropes turn the links about z only)."""
    from cad.families.pantograph import twin_capstan
    from cad.structure import pantograph as sp

    d = _design()
    rep = _bodies(np.random.default_rng(39))
    k = _k_q_by_hand(NB)
    rope = sp.analyse(d, rep, 1.0, 10.0)
    assert rope["rope_stiffness_Nm_per_rad"] == pytest.approx(dict.fromkeys(JOINTS, k), rel=1e-12)
    held = sp.analyse(_design(DIRECT), rep, 1.0, 10.0)
    assert held["rope_stiffness_Nm_per_rad"] == {}
    X, labels = sp.poses(d)
    kinv = np.full(4, 1 / k)
    for x, lab in zip(X, labels, strict=True):
        c_rope = twin_capstan.handle_compliance_m_per_N(_fd_jacobian(d.mechanism, x)[0], kinv) * 1e6  # um/N
        for i, ax in enumerate("xy"):
            got = rope["per_pose"][lab]["compliance_um_per_N"][ax]
            assert got >= held["per_pose"][lab]["compliance_um_per_N"][ax] * (1 - 1e-9), (lab, ax)
            assert got >= c_rope[i, i] * (1 - 1e-6), (lab, ax)
    assert rope["first_mode_in_plane_Hz"] < held["first_mode_in_plane_Hz"]
    stiff = {j: 1e9 * k for j in JOINTS}
    monkeypatch.setattr(sp, "motor_rope_stiffness_Nm_per_rad", lambda design: stiff)
    very = sp.analyse(d, rep, 1.0, 10.0)
    for lab in labels:
        for ax in "xy":
            assert very["per_pose"][lab]["compliance_um_per_N"][ax] == pytest.approx(
                held["per_pose"][lab]["compliance_um_per_N"][ax], rel=1e-5)


def test_bundled_design_figures_regression_pin():
    """Regression pin (our own run, typed in docs/families/pantograph-powermouse.md and the
    design's header): the direct mouse 0.96 N continuous in every direction, the capstan one
    4.09 N against its 4 N (every default limit of its capstan rows met: the rows test above);
    drum sectors 90 deg (knob links) and 113 deg (crank links)."""
    from cad.families.pantograph.capstan import capstan_rows
    from cad.families.pantograph.datasheet import motor_force_rows

    d = _design()
    force = {r["key"]: r["value"] for r in motor_force_rows(d)}["continuous_force_N"]
    direct = {r["key"]: r["value"] for r in motor_force_rows(_design(DIRECT))}["continuous_force_N"]
    assert (round(direct, 2), round(force, 2)) == (0.96, 4.09) and force >= d.actuators["force_max_N"] == 4.0
    assert force == pytest.approx(NB * direct, rel=1e-12)  # one ratio on every motor: f = J^-T n tau
    v = {r["key"]: r["value"] for r in capstan_rows(d, None)[0]}
    assert [round(v[f"drum_sector_deg_{i}"]) for i in range(1, 5)] == [90, 90, 113, 113]


def test_three_direct_motors_hold_the_handle_so_one_rope_adds_no_handle_compliance():
    """[[transmission]] with only the crank's right motor through a capstan: the three direct
    joints' rows of dq/dX (finite differences) have rank 3 at every sample, so they hold the
    handle alone; the fourth motor's rows are there, no rope stiffness at the handle and no
    K_max in series (not an infinite figure)."""
    from cad.families.pantograph.capstan import capstan_rows

    raw = _per_motor()
    raw["transmission"][:3] = [{"kind": "direct"}] * 3
    d = _design(raw)
    s = np.linalg.svd(_fd_jacobian(d.mechanism, d.workspace_points())[:, :3, :], compute_uv=False)
    assert (s[:, -1] > 1e-6 * s[:, 0]).all()  # well above the FD error (~1e-8 relative)
    keys = {r["key"] for r in capstan_rows(d, 900.0)[0]}
    assert "transmission_ratio_4" in keys and "transmission_ratio_1" not in keys
    assert not keys & {"cable_handle_stiffness_N_per_m", "K_max_with_cable_N_per_m"}


def test_motor_friction_at_the_handle_is_n_times_the_direct_mouses():
    """friction_N: each motor's K_t I_0 reaches its joint n times (the rope's lever), so with one
    ratio on every motor the handle's Coulomb friction is n times the direct mouse's (F = J^T
    diag(n f) s, linear in n); a sweep of directions of motion (J = dq/dX by finite
    differences) never exceeds it (an upper bound for the redundant twin)."""
    from cad.data.catalog import get_motor
    from cad.families.pantograph.datasheet import friction_row

    d = _design()
    r, r0 = friction_row(d), friction_row(_design(DIRECT))
    assert r["value"] == pytest.approx(NB * r0["value"], rel=1e-12) and "x capstan n = 4.25" in r["model"]
    m = get_motor(d.parts.motor)
    f = NB * m.torque_constant_mNm_per_A * m.no_load_current_mA * 1e-6  # n K_t I_0, N m
    J = _fd_jacobian(d.mechanism, d.workspace_points()[::9])
    v = np.random.default_rng(40).normal(size=(2000, 3))
    s = np.sign(np.einsum("nia,ka->nki", J, v))  # each joint's direction of turn (n, k, 4)
    F = np.einsum("nia,nki->nka", J, f * s)[..., :2]  # J^T diag(f) s, the translational rows
    assert np.linalg.norm(F, axis=-1).max() <= r["value"] * (1 + 1e-6)
