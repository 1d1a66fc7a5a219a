"""Capstans on the delta's upper arms (designs/delta_capstan.toml, issue 36 item 1): each
figure against an independent reference, no CAD build (the datasheet's capstan rows read the
design and the resolved device only; MuJoCo reads seeded random bodies as in
tests/families/delta/test_delta_sim.py; the firmware reads a hand-made report's bodies as in
tests/families/delta/test_delta_firmware.py).

References: the force in every direction against a brute-force sweep of directions
(F(u) = T / |N^-1 J^-T u|); the reflected rotor inertia against the kinetic energy of the
rotors from finite differences of the inverse kinematics (v^T Lambda v = sum n_i^2 J_i
theta_dot_i^2); the rope's spring in series against the cantilever's two-spring closed form
F L^3 / (3 E I) + F L^2 / k; MuJoCo's task-space mass matrix against eq (1) with n^2 (J_m +
J_capstan) written out here; the compiled C firmware's counts -> angle and torque -> current
against q = 2 pi c / (counts n), i = tau / (n K_t); the command line's exit 2 on bad values.
"""

from __future__ import annotations

import copy
import math
import re
import subprocess
import sys
import tomllib
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from cad.actuators.capstan_geometry import capstan_izz_kg_m2
from cad.data.cables import get_cable
from cad.data.materials import get_material
from cad.design import parse_design
from cad.device import CAPSTAN_MATERIAL, resolve_device
from cad.families.delta import capstan as dcap
from cad.families.delta.datasheet import force_in_every_direction_N, resolution_um
from cad.families.delta.dynamics import mass_matrix_from_bodies_kg
from cad.families.delta.structure import Frame3D, first_mode, pivot_spring
from cad.kinematics.delta import ik, jacobian_rad_per_m
from cad.structure.frame import Section

ROOT = Path(__file__).resolve().parents[3]
RAW = tomllib.loads((ROOT / "designs" / "delta_capstan.toml").read_text())
DIRECT = tomllib.loads((ROOT / "designs" / "delta.toml").read_text())


def _design(raw=RAW):
    return parse_design(copy.deepcopy(raw), "variant.toml")


def _per_motor(ns=(2.0, 2.5, 3.0)) -> dict:
    raw = copy.deepcopy(RAW)
    t = raw.pop("transmission")
    raw["transmission"] = [dict(t, drum_diameter_mm=t["capstan_diameter_mm"] * n) for n in ns]
    return raw


def test_force_in_every_direction_through_the_ratios_against_a_sweep_of_directions():
    d = _design(_per_motor())
    ns = np.array([2.0, 2.5, 3.0])
    f, at = force_in_every_direction_N(d, 0.1, ns)
    # brute force: at every grid point the largest force along u is T / |N^-1 J^-T u|
    X = d.workspace_points()
    J, _ = jacobian_rad_per_m(d.mechanism, X)
    u = np.random.default_rng(3).normal(size=(4000, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    A = np.linalg.inv(np.swapaxes(J, 1, 2)) / ns[None, :, None]       # N^-1 J^-T
    reach = 0.1 / np.linalg.norm(np.einsum("nij,kj->nki", A, u), axis=2)  # (points, dirs)
    sweep = reach.min()
    assert f <= sweep * (1 + 1e-12) and f > sweep * (1 - 2e-3)  # sampled directions overshoot
    # one ratio on every arm: n times the direct drive's (f = J^T n tau)
    d1 = _design()
    assert force_in_every_direction_N(d1, 0.1, [2.5] * 3)[0] == pytest.approx(
        2.5 * force_in_every_direction_N(d1, 0.1)[0], rel=1e-12)
    # resolution: a joint turn is n motor turns
    assert resolution_um(d1, 2000, [2.5] * 3)[0] == pytest.approx(resolution_um(d1, 2000)[0] / 2.5, rel=1e-12)


def test_reflected_rotor_inertia_against_the_rotors_kinetic_energy():
    d = _design(_per_motor())
    dev = resolve_device(d)
    jm = dev.motor.rotor_inertia_kg_m2
    t = dev.transmission("theta_0")
    rho = get_material(CAPSTAN_MATERIAL).density_kg_m3
    jc = capstan_izz_kg_m2(t.capstan_diameter_mm, t.cable_diameter_mm, t.wraps,
                           dev.motor.spec.shaft_diameter_mm, rho)
    ns = np.array([2.0, 2.5, 3.0])
    rot = [dev.joint_rotor_inertia_kg_m2(f"theta_{i}") for i in range(3)]
    assert rot == pytest.approx((ns**2 * (jm + jc)).tolist(), rel=1e-12)
    P = np.asarray(d.workspace["center_mm"], float) + np.array([10.0, -20.0, 15.0])
    lam = mass_matrix_from_bodies_kg(d.mechanism, P[None], d.parallelogram_width_mm, {}, rot)[0]
    h = 1e-4  # mm
    for v in np.eye(3):
        dth = (ik(d.mechanism, (P + h * v)[None]).theta_rad[0]
               - ik(d.mechanism, (P - h * v)[None]).theta_rad[0]) / (2 * h * 1e-3)  # rad/m
        assert v @ lam @ v == pytest.approx(float(np.sum(ns**2 * (jm + jc) * dth**2)), rel=1e-6)


def test_rope_spring_in_series_with_a_beam_against_the_two_spring_closed_form():
    E, Iz, L, k, F = 70e9, 2e-10, 0.11, 800.0, 3.0
    s = Section(A=1e-4, Iz=Iz, Iy=5e-10, J=3e-10, cy=0.005, cz=0.005, t_torsion=0.002, E=E,
                G=26e9, rho=2700.0)
    f = Frame3D()
    a, b = f.node([0.0, 0.0, 0.0]), f.node([L, 0.0, 0.0])
    f.ground_springs.append((a, pivot_spring([0.0, 0.0, 1.0], k)))
    f.beam(a, b, s, [0.0, 0.0, 1.0])
    u = f.solve({b: np.array([0.0, F, 0.0])})
    assert u[6 * b + 1] == pytest.approx(F * L**3 / (3 * E * Iz) + F * L**2 / k, rel=1e-6)


def test_first_mode_with_the_ropes_lies_below_the_clamped_arms_and_meets_the_limit():
    d = _design()
    dev = resolve_device(d)
    k = dcap.rope_stiffness_Nm_per_rad(d, dev)
    c = np.asarray(d.workspace["center_mm"], float)
    rope = first_mode(d.mechanism, c, d.parallelogram_width_mm, rope_k_Nm_per_rad=k)
    clamped = first_mode(d.mechanism, c, d.parallelogram_width_mm)
    stiff = first_mode(d.mechanism, c, d.parallelogram_width_mm, rope_k_Nm_per_rad=(1e9,) * 3)
    assert rope["first_mode_Hz"] < clamped["first_mode_Hz"]
    assert stiff["first_mode_Hz"] == pytest.approx(clamped["first_mode_Hz"], rel=1e-5)
    assert rope["first_mode_Hz"] >= 150.0  # the default limit (cad.datasheet.limits.FIRST_MODE_MIN_HZ)
    # compliance: the ropes add J^-1 diag(1/k) J^-T to the frame's (two springs in series)
    J, _ = jacobian_rad_per_m(d.mechanism, c[None])
    Ji = np.linalg.inv(J[0])
    added = Ji @ np.diag(1 / np.asarray(k)) @ Ji.T
    assert rope["compliance_m_per_N"] == pytest.approx(clamped["compliance_m_per_N"] + added, rel=1e-5, abs=1e-12)


def test_capstan_rows_against_hand_formulas():
    d = _design()
    dev = resolve_device(d)
    rows, lim = dcap.datasheet_rows(d, dev, 850.0)
    v = {r["key"]: r["value"] for r in rows}
    t = RAW["transmission"]
    n = t["drum_diameter_mm"] / t["capstan_diameter_mm"]
    rope = get_cable(t["cable"])
    assert v["transmission_ratio"] == n
    assert v["reflected_rotor_inertia_g_cm2"] == pytest.approx(n * n * dev.motor.spec.rotor_inertia_g_cm2, rel=1e-12)
    assert v["bend_ratio"] == t["capstan_diameter_mm"] / rope.diameter_mm and lim["bend_ratio"].value == 40.0
    # open-belt free run at C = r_d + r_c + gap; k_q = EA (2 / L) r_d^2
    from cad.actuators.capstan import CAPSTAN_GAP_MM
    rd, rc = t["drum_diameter_mm"] / 2, t["capstan_diameter_mm"] / 2
    C = rd + rc + CAPSTAN_GAP_MM
    L = math.sqrt(C * C - (rd - rc) ** 2) * 1e-3
    kq = rope.axial_stiffness_EA_N * 2 / L * (rd * 1e-3) ** 2
    assert v["cable_stiffness_Nm_per_rad"] == pytest.approx(kq, rel=1e-12)
    # at the effector: k_q sigma_min(J)^2 (one k on every arm), weakest over the grid
    J, _ = jacobian_rad_per_m(d.mechanism, d.workspace_points())
    ke = kq * (np.linalg.svd(J, compute_uv=False)[:, -1] ** 2).min()
    assert v["cable_effector_stiffness_N_per_m"] == pytest.approx(ke, rel=1e-9)
    assert v["K_max_with_cable_N_per_m"] == pytest.approx(1 / (1 / 850.0 + 1 / ke), rel=1e-9)
    # the drum sector covers the motor-angle range plus two anchors of 10 mm (2 L_a / r_d rad each)
    rng = RAW["mechanism"]["motor_angle_max_deg"] - RAW["mechanism"]["motor_angle_min_deg"]
    assert v["drum_sector_deg"] == pytest.approx(rng + math.degrees(2 * 10.0 / rd), rel=1e-12)
    # every default limit of the capstan rows is met by the bundled design
    assert all(lim[k].met(v[k]) for k in lim)


def test_bundled_capstan_delta_figures_docs_state():
    """docs/families/delta.md "Capstan": the figures of designs/delta_capstan.toml it types (a
    regression pin at the docs' precision; each figure's model is checked above)."""
    d = _design()
    dev = resolve_device(d)
    v = {r["key"]: r["value"] for r in dcap.datasheet_rows(d, dev, None)[0]}
    fc = force_in_every_direction_N(d, dev.motor.spec.torque_continuous_mNm * 1e-3, [2.5] * 3)[0]
    assert (round(fc, 2), round(fc / 2.5, 3)) == (1.58, 0.634)
    assert round(v["cable_slip_margin"], 1) == 3.2 and round(v["cable_safety_factor"], 1) == 18.8
    assert round(v["drum_sector_deg"], 1) == 147.9 and round(v["cable_cut_length_mm"]) == 677
    assert round(v["cable_stiffness_Nm_per_rad"]) == 4389
    from cad.families.delta.datasheet import friction_row
    assert round(friction_row(d, dev.motor.spec, [2.5] * 3)["value"], 3) == 0.296
    c = np.asarray(d.workspace["center_mm"], float)
    k = dcap.rope_stiffness_Nm_per_rad(d, dev)
    assert round(first_mode(d.mechanism, c, d.parallelogram_width_mm, rope_k_Nm_per_rad=k)["first_mode_Hz"], 1) == 159.6
    assert round(first_mode(d.mechanism, c, d.parallelogram_width_mm)["first_mode_Hz"]) == 195


def test_per_motor_transmissions_give_one_row_set_per_arm():
    d = _design(_per_motor())
    rows, lim = dcap.datasheet_rows(d, resolve_device(d), None)
    v = {r["key"]: r["value"] for r in rows}
    assert [v[f"transmission_ratio_{i}"] for i in range(3)] == [2.0, 2.5, 3.0]
    assert "K_max_with_cable_N_per_m" not in v and "bend_ratio_2" in lim
    assert dcap.datasheet_rows(_design(DIRECT), resolve_device(_design(DIRECT)), 850.0) == ([], {})


def test_rope_bom_line_and_winding_steps():
    d = _design()
    dev = resolve_device(d)
    (line,) = dcap.bom_lines(d, dev)
    t = RAW["transmission"]
    from cad.actuators.capstan import CAPSTAN_GAP_MM
    rd, rc = t["drum_diameter_mm"] / 2, t["capstan_diameter_mm"] / 2
    L = math.sqrt((rd + rc + CAPSTAN_GAP_MM) ** 2 - (rd - rc) ** 2)
    rng = RAW["mechanism"]["motor_angle_max_deg"] - RAW["mechanism"]["motor_angle_min_deg"]
    sector = math.radians(rng) + 2 * 10.0 / rd
    # turns on the capstan + two free runs + the drum's arc + 2 x 20 mm tails (pitch diameters)
    cut = t["wraps"] * 2 * math.pi * rc + 2 * L + sector * rd + 40.0
    assert line["quantity"] == 3 and line["part"] == "capstan_cable"
    assert f"x {cut:.0f} mm" in line["designation"]
    steps = dcap.assembly_steps(d, dev)
    # one rope per arm (three of one cut), each naming its own arm's anchor, tensioner and nut
    assert len(steps) == 6
    for i in range(3):
        wind, tension = steps[2 * i], steps[2 * i + 1]
        assert f"cut {cut:.0f} mm of steel-7x7-1" in wind and f"under upper_{i}.capstan_anchor_1 " in wind
        assert "30.0 N" in tension and f"turn upper_{i}.capstan_tensioner " in tension
        assert f"lock it with upper_{i}.capstan_tensioner_nut " in tension


@pytest.mark.slow  # a delta build: every pair of solids at 125 workspace points (~1 min)
def test_the_built_capstan_delta_is_clean_and_its_solids_carry_the_capstans(shared_build):
    """designs/delta_capstan.toml built (preview): no solid overlap over the workspace grid with
    the drums, capstans, moved motors and rope runs drawn; Lambda from the solids' bodies with
    n^2 (J_m + J_capstan) (eq 1 recomputed here); the drum sector's arc covers both tangent
    points over the motor-angle range plus the anchors (2 gamma + range + 2 anchor arcs); the
    BOM's rope line, bearings and anchors; assembly.md's winding steps."""
    import csv

    from cad.massprops.props import MassProps

    d, out, rep = shared_build("delta_capstan.toml", ("step",), "preview")
    assert rep["overlap_volume_mm3"] == 0.0
    bodies = {k: MassProps(v["mass_kg"], np.asarray(v["com_mm"]) * 1e-3, np.asarray(v["inertia_com_kg_m2"]))
              for k, v in rep["placement"]["bodies"].items()}
    dev = resolve_device(d)
    t = dev.transmission("theta_0")
    jc = capstan_izz_kg_m2(t.capstan_diameter_mm, t.cable_diameter_mm, t.wraps, dev.motor.spec.shaft_diameter_mm,
                           get_material(CAPSTAN_MATERIAL).density_kg_m3)
    rot = 2.5**2 * (dev.motor.spec.rotor_inertia_g_cm2 * 1e-7 + jc)
    lam = mass_matrix_from_bodies_kg(d.mechanism, d.workspace_points(), d.parallelogram_width_mm, bodies, rot)
    eig = np.linalg.eigvalsh(lam)
    assert rep["apparent_mass"]["Lambda_max_eig_g"] == pytest.approx(eig[:, -1].max() * 1e3, rel=1e-9)
    rows = {r["key"]: r for r in rep["datasheet"]["rows"]}
    assert all(r["verdict"] != "miss" for r in rows.values())
    with (out / "bom.csv").open(encoding="utf-8", newline="") as f:
        bom = {r["part"]: r for r in csv.DictReader(f)}
    for part in ("capstan_drum", "capstan", "capstan_set_screw", "capstan_anchor_screw", "capstan_tensioner_screw",
                 "capstan_tensioner_nut", "arm_bearing", "arm_axle", "arm_bracket", "capstan_motor_bracket"):
        assert int(bom[part]["quantity"]) == 3, part
    assert int(bom["capstan_cable"]["quantity"]) == 3 and "cut length 677 mm" in bom["capstan_cable"]["description"]
    C = 72.0  # r_d + r_c + the 2 mm rim gap
    gamma = math.degrees(math.acos((50.0 - 20.0) / C))
    span = 2 * gamma + 125.0 + 2 * math.degrees(2 * 10.0 / 100.0)
    assert f"{span:.0f} deg arc" in bom["capstan_drum"]["description"]
    md = (out / "assembly.md").read_text()
    assert "wind the rope: cut 677 mm of steel-7x7-1" in md and "at least 30.0 N" in md


@pytest.mark.slow  # a delta build (~1 min)
def test_per_motor_capstans_build_with_their_own_parts(tmp_path):
    """[[transmission]] with a 110 mm drum on arm 2: each arm's capstan parts are its own BOM
    kinds (arm 2's drum 110 mm pitch), the ropes one line per arm, no overlap."""
    import csv

    from cad.design import load_design
    from cad.pipeline import build_design

    raw = _per_motor((2.5, 2.5, 2.75))
    lines = []
    for t in raw.pop("transmission"):
        lines += ["[[transmission]]", *(f"{k} = {v!r}".replace("'", '"') for k, v in t.items())]
    text = (ROOT / "designs" / "delta_capstan.toml").read_text()
    text = text[:text.index("[transmission]")] + "\n".join(lines) + "\n\n" + text[text.index("[parts]"):]
    (tmp_path / "pm.toml").write_text(text)
    build_design(load_design(tmp_path / "pm.toml"), tmp_path / "o", {"step"}, fidelity="preview", use_cache=False)
    import json
    rep = json.loads((tmp_path / "o" / "report.json").read_text())
    assert rep["overlap_volume_mm3"] == 0.0
    with (tmp_path / "o" / "bom.csv").open(encoding="utf-8", newline="") as f:
        bom = {r["part"]: r for r in csv.DictReader(f)}
    assert [bom[f"capstan_drum_{i}"]["description"].startswith(f"drum sector {p} mm pitch")
            for i, p in enumerate((100, 100, 110))] == [True] * 3
    assert all(int(bom[f"capstan_cable_{i}"]["quantity"]) == 1 for i in range(3))


mujoco = pytest.importorskip("mujoco")


def test_mjcf_gear_and_armature_give_lambda_with_n2_jm_in_mujoco():
    from cad.export.sim import mjcf_text
    from cad.families.delta.sim import sim_model
    from tests.families.delta.test_delta_sim import AGREE_REL, _bodies, mujoco_lambda

    d = _design()
    dev = resolve_device(d)
    n = RAW["transmission"]["drum_diameter_mm"] / RAW["transmission"]["capstan_diameter_mm"]
    t = dev.transmission("theta_0")
    jc = capstan_izz_kg_m2(t.capstan_diameter_mm, t.cable_diameter_mm, t.wraps, dev.motor.spec.shaft_diameter_mm,
                           get_material(CAPSTAN_MATERIAL).density_kg_m3)
    reflected = n * n * (dev.motor.spec.rotor_inertia_g_cm2 * 1e-7 + jc)
    bodies = _bodies(np.random.default_rng(35))
    P = np.asarray(d.workspace["center_mm"], float) + np.array([20.0, 0.0, -30.0])
    xml = mjcf_text(sim_model(d, bodies, dev, P))
    root = ET.fromstring(xml)
    motors = list(root.iter("motor"))
    assert [float(m.get("gear")) for m in motors] == [n] * 3
    peak = RAW["motor"]["torque_peak_mNm"] * 1e-3  # the motor's own limit; the joint gets n times it
    assert [m.get("forcerange") for m in motors] == [f"{-peak:g} {peak:g}"] * 3
    lam, residual, _ = mujoco_lambda(xml)
    ref = mass_matrix_from_bodies_kg(d.mechanism, P[None], d.parallelogram_width_mm, bodies, reflected)[0]
    assert residual < 1e-12
    assert np.abs(lam - ref).max() < AGREE_REL * np.abs(ref).max()


def test_firmware_counts_and_currents_through_the_ratio_in_c(tmp_path):
    from cad.firmware import linkage_files
    from tests.compilers import compiler
    from tests.families.delta.test_delta_firmware import _report_bodies

    d = _design()
    dev = resolve_device(d)
    files = linkage_files(d, _report_bodies(), "cap1", dev)
    n = 2.5
    h = files["firmware/hapticad_device.h"]
    assert re.search(r"#define HC_GEAR \{ (.+) \}", h).group(1) == ", ".join([f"HC_R({n!r})"] * 3)
    import json
    assert json.loads(files["firmware/chai3d_device.json"])["transmission_ratio"] == [n] * 3
    fw = tmp_path / "fw"
    fw.mkdir()
    for rel, text in files.items():
        (fw / Path(rel).name).write_text(text)
    (tmp_path / "m.c").write_text(
        '#include <stdio.h>\n#include "hapticad_device.h"\nint main(void){hc_encoder_t e = HC_ENCODER_DEFAULT;'
        'long c[3]={1000,-500,250};hc_real q[3],t[3]={0.05,-0.02,0.01},a[3];int i;hc_counts_to_angles(&e,c,q);'
        'hc_motor_currents(t,HC_LIMIT_CONTINUOUS,a);for(i=0;i<3;++i)printf("%.17g %.17g %.17g %d\\n",'
        'q[i]-e.zero_rad[i],a[i],(double)e.counts_per_rev,(int)e.direction[i]);return 0;}\n')
    exe = tmp_path / "m"
    subprocess.run([compiler("c"), "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", f"-I{fw}", "-o", str(exe),
                    str(tmp_path / "m.c"), str(fw / "hapticad_device.c"), "-lm"], check=True, timeout=120)
    out = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout.split("\n")
    kt = dev.motor.spec.torque_constant_mNm_per_A * 1e-3
    for line, c, tau in zip(out[:3], (1000, -500, 250), (0.05, -0.02, 0.01), strict=True):
        q, a, cpr, sign = map(float, line.split())
        assert q == pytest.approx(sign * 2 * math.pi * c / (cpr * n), rel=1e-15)
        assert a == pytest.approx(tau / (n * kt), rel=1e-15)
    # the build's own vectors pass in the compiled C (the mass model with n^2 (J_m + J_c))
    _assert_test_device_passes(fw, tmp_path / "td")


@pytest.mark.parametrize("table,field", [
    ('[transmission]\nkind = "capstan"\ncapstan_diameter_mm = -3.0\nratio = 2.0\ncable = "steel-7x7-1"\n',
     "transmission.capstan_diameter_mm"),
    ('[[transmission]]\nkind = "capstan"\ncapstan_diameter_mm = 40.0\nratio = 2.0\ncable = "steel-7x7-1"\n'
     '[[transmission]]\nkind = "direct"\n', "transmission"),
    ('[transmission]\nkind = "capstan"\ncapstan_diameter_mm = 40.0\nratio = 2.0\ncable = "nylon"\n',
     "transmission.cable"),
])
def test_bad_transmission_exits_2_naming_the_field(tmp_path, table, field):
    text = (ROOT / "designs" / "delta.toml").read_text() + "\n" + table
    p = tmp_path / "bad.toml"
    p.write_text(text)
    r = subprocess.run([sys.executable, "-m", "cad", "build", str(p), "--out", str(tmp_path / "o")],
                       capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert r.returncode == 2, r.stderr
    assert field in r.stderr and "Traceback" not in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


def test_a_knee_arm_on_its_rope_adds_the_same_series_compliance():
    """The Falcon's knee arms (Stamper's joint offset) on capstans: each arm's pivot is held by
    its rope, not clamped (found at the merge of the knee and capstan work: the knee arm
    clamped its axis whatever the rope); the same two-springs-in-series closed form as above."""
    falcon = parse_design(tomllib.loads((ROOT / "designs" / "delta_falcon.toml").read_text()))
    m = falcon.mechanism
    c = np.asarray(falcon.workspace["center_mm"], float)
    k = (900.0, 1200.0, 1500.0)
    rope = first_mode(m, c, falcon.parallelogram_width_mm, rope_k_Nm_per_rad=k)
    clamped = first_mode(m, c, falcon.parallelogram_width_mm)
    assert rope["first_mode_Hz"] < clamped["first_mode_Hz"]
    J, _ = jacobian_rad_per_m(m, c[None])
    Ji = np.linalg.inv(J[0])
    added = Ji @ np.diag(1 / np.asarray(k)) @ Ji.T
    assert rope["compliance_m_per_N"] == pytest.approx(clamped["compliance_m_per_N"] + added, rel=1e-5, abs=1e-12)


def test_firmware_with_a_ratio_per_arm_in_c_against_the_rotors_kinetic_energy(tmp_path):
    """[[transmission]] with n = 2, 2.5, 3: the firmware carries each arm's ratio (HC_GEAR) and
    its own reflected rotor in the mass model (ARM_AXIS[i] = I_arm + n_i^2 (J_m + J_capstan,i),
    J_capstan from the capstan's own closed form); the compiled C passes the build's vectors
    and finite differences (test_device.c), and its hc_mass_matrix minus the links' Lambda
    (no rotor) is the rotors' kinetic energy from finite differences of the IK:
    v^T dLambda v = sum_i n_i^2 (J_m + J_c,i) theta_dot_i^2."""
    from cad.dynamics.delta import mass_matrix_kg
    from cad.families.delta.dynamics import delta_mass_from_bodies
    from cad.families.delta.firmware import props_of
    from cad.firmware import linkage_files
    from tests.compilers import compiler
    from tests.families.delta.test_delta_firmware import _report_bodies

    ns = np.array([2.0, 2.5, 3.0])
    d = _design(_per_motor(tuple(ns)))
    dev = resolve_device(d)
    files = linkage_files(d, _report_bodies(), "cap3", dev)
    h, c = files["firmware/hapticad_device.h"], files["firmware/hapticad_device.c"]
    assert re.search(r"#define HC_GEAR \{ (.+) \}", h).group(1) == ", ".join(f"HC_R({float(n)!r})" for n in ns)
    jm = dev.motor.spec.rotor_inertia_g_cm2 * 1e-7
    rho = get_material(CAPSTAN_MATERIAL).density_kg_m3
    jc = [capstan_izz_kg_m2(t["capstan_diameter_mm"], get_cable(t["cable"]).diameter_mm, t["wraps"],
                            dev.motor.spec.shaft_diameter_mm, rho) for t in _per_motor(tuple(ns))["transmission"]]
    refl = ns**2 * (jm + np.asarray(jc))
    links = delta_mass_from_bodies(d.mechanism, props_of(_report_bodies()))
    axis = [float(v) for v in re.findall(r"HC_R\(([^)]+)\)", re.search(r"ARM_AXIS\[3\] = \{(.+)\};", c).group(1))]
    assert axis == pytest.approx((links.upper_arm_kg_m2 + refl).tolist(), rel=1e-12)
    fw = tmp_path / "fw"
    fw.mkdir()
    for rel, text in files.items():
        (fw / Path(rel).name).write_text(text)
    _assert_test_device_passes(fw, tmp_path / "td")
    # hc_mass_matrix at three points against the links' Lambda plus the rotors from the IK's rates
    P = np.asarray(d.workspace["center_mm"], float) + np.array([[0.0, 0.0, 0.0], [30.0, -20.0, 25.0],
                                                                  [-40.0, 35.0, -30.0]])
    th = ik(d.mechanism, P).theta_rad
    (tmp_path / "m.c").write_text(
        '#include <stdio.h>\n#include "hapticad_device.h"\nint main(void){static const double th[] = {'
        + ", ".join(repr(float(v)) for v in th.ravel()) + '};hc_real q[3], M[9];int n, i;for (n = 0; n < 3; ++n)'
        '{for (i = 0; i < 3; ++i) q[i] = th[3 * n + i];if (hc_mass_matrix(q, M)) return 1;for (i = 0; i < 9; ++i)'
        ' printf("%.17g ", (double)M[i]);printf("\\n");}return 0;}\n')
    exe2 = tmp_path / "m"
    subprocess.run([compiler("c"), "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", f"-I{fw}", "-o",
                    str(exe2), str(tmp_path / "m.c"), str(fw / "hapticad_device.c"), "-lm"], check=True, timeout=120)
    out = subprocess.run([str(exe2)], capture_output=True, text=True, check=True).stdout.split("\n")
    h_mm = 1e-4
    for k, (line, p) in enumerate(zip(out[:3], P, strict=True)):
        M = np.array(line.split(), float).reshape(3, 3)
        rot = M - mass_matrix_kg(d.mechanism, p[None], links)[0]
        for v in np.eye(3):
            dth = (ik(d.mechanism, (p + h_mm * v)[None]).theta_rad[0]
                   - ik(d.mechanism, (p - h_mm * v)[None]).theta_rad[0]) / (2 * h_mm * 1e-3)  # rad/m
            assert v @ rot @ v == pytest.approx(float(np.sum(refl * dth**2)), rel=1e-6), k


def test_per_motor_rows_of_the_shared_helper_against_hand_formulas():
    """cad.datasheet.capstan_rows.joints_rows (the per-motor rows the delta reads): with n = 2,
    2.5, 3 each arm's ratio row, its rope's k_q = EA (2 / L) r_d^2 at C = r_d + r_c + gap, in
    the arms' order, keys suffixed _0, _1, _2, and a slip limit per arm."""
    from cad.actuators.capstan import CAPSTAN_GAP_MM
    from cad.datasheet import capstan_rows as cr

    ns = (2.0, 2.5, 3.0)
    d = _design(_per_motor(ns))
    rows, lim, k_q = cr.joints_rows(dcap.joints(d, resolve_device(d)))
    v = {r["key"]: r["value"] for r in rows}
    rope = get_cable(RAW["transmission"]["cable"])
    rc = RAW["transmission"]["capstan_diameter_mm"] / 2
    for i, n in enumerate(ns):
        rd = rc * n
        L = math.sqrt((rd + rc + CAPSTAN_GAP_MM) ** 2 - (rd - rc) ** 2) * 1e-3
        kq = rope.axial_stiffness_EA_N * 2 / L * (rd * 1e-3) ** 2
        assert v[f"transmission_ratio_{i}"] == n
        assert k_q[f"theta_{i}"] == pytest.approx(kq, rel=1e-12) == v[f"cable_stiffness_Nm_per_rad_{i}"]
        assert f"cable_slip_margin_{i}" in lim
    order = [r["key"] for r in rows]
    assert order.index("cable_stiffness_Nm_per_rad_0") < order.index("transmission_ratio_1")
    assert cr.joints_rows(()) == ([], {}, {})


def test_friction_at_the_effector_through_the_ratios_against_the_dissipation_over_directions():
    """friction_N: each motor's Coulomb torque tau_f through its ratio at its joint; moving the
    effector along a unit v the friction dissipates sum_i n_i tau_f |J_i . v| per unit speed, so
    the resisting force along v is that sum (virtual work); its largest over a sweep of 4000
    directions and the workspace grid against the sign-corner form, the same point; one ratio n
    on every arm: n times the direct drive's; the datasheet row with K_t I_0 of the RE 35."""
    from cad.data.catalog import get_motor
    from cad.families.delta.datasheet import friction_N, friction_row

    ns = np.array([2.0, 2.5, 3.0])
    d = _design(_per_motor(tuple(ns)))
    hi, lo, at = friction_N(d, 0.01, ns)
    X = d.workspace_points()
    J, _ = jacobian_rad_per_m(d.mechanism, X)
    u = np.random.default_rng(11).normal(size=(4000, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    F = np.abs(np.einsum("i,nik,vk->nvi", ns * 0.01, J, u)).sum(axis=2)
    sweep = F.max()
    assert hi >= sweep * (1 - 1e-12) and hi < sweep * (1 + 2e-3)   # sampled directions undershoot
    assert np.allclose(X[int(np.argmax(F.max(axis=1)))], at)
    assert lo <= hi
    d1 = _design()
    assert friction_N(d1, 0.01, [2.5] * 3)[0] == pytest.approx(2.5 * friction_N(d1, 0.01)[0], rel=1e-12)
    m = get_motor("maxon-re35")
    r = friction_row(d1, m, [2.5] * 3)
    tf = m.torque_constant_mNm_per_A * m.no_load_current_mA * 1e-6   # Kt I0, N m
    assert r["key"] == "friction_N" and r["value"] == pytest.approx(friction_N(d1, tf, [2.5] * 3)[0], rel=1e-12)


def _assert_test_device_passes(fw: Path, exe: Path) -> None:
    """Compile the generated test_device.c with hapticad_device.c (gcc) and run it on its own
    test_vectors.json at the firmware tolerances: no failure."""
    from cad import tolerances as tol
    from tests.compilers import compiler

    subprocess.run([compiler("c"), "-std=c99", "-O2", "-o", str(exe), str(fw / "test_device.c"),
                    str(fw / "hapticad_device.c"), "-lm"], check=True, capture_output=True, timeout=120)
    r = subprocess.run([str(exe), str(fw / "test_vectors.json"), *map(repr, (
        tol.FIRMWARE_DOUBLE_POSITION_M, tol.FIRMWARE_DOUBLE_TORQUE_NM, tol.FIRMWARE_FD_JACOBIAN))],
        capture_output=True, text=True, timeout=120)
    assert r.returncode == 0 and "failures 0" in r.stdout, r.stdout + r.stderr
