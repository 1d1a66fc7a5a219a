"""MJCF/URDF export (issue 14): read back with MuJoCo and an XML parser, checked against
report.json and against hapticad's own eq (22) / twin-pantograph mass matrix."""

from __future__ import annotations

import json
import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import assert_one_line_error, hapticad

from cad.data.catalog import get_motor
from tests.conftest import SIM_FORMATS

ROOT = Path(__file__).resolve().parents[3]


@pytest.fixture(scope="module")
def hoeken(hoeken_sim_build):
    return hoeken_sim_build


@pytest.fixture(scope="module")
def mouse(shared_build):
    """designs/haptic_mouse.toml's shared simulator build (tests/conftest.py ``SIM_FORMATS``:
    preview, MJCF, URDF, STL): ``(design, out, report)``. Read-only."""
    return shared_build("haptic_mouse.toml", SIM_FORMATS["haptic_mouse.toml"], "preview")


def _floats(s: str) -> list[float]:
    return [float(x) for x in s.split()]


def _tensor(fi: list[float]) -> np.ndarray:
    ixx, iyy, izz, ixy, ixz, iyz = fi
    return np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])


def test_files_listed_and_in_manifest(hoeken):
    _, out, rep, _ = hoeken
    man = json.loads((out / "manifest.json").read_text())
    listed = json.dumps(man)
    for f in ("hoeken.xml", "hoeken.urdf"):
        assert f in rep["files"] and f in listed and (out / f).is_file()


def test_mjcf_carries_report_inertias_exactly(hoeken):
    import mujoco

    _, out, rep, _ = hoeken
    root = ET.parse(out / "hoeken.xml").getroot()
    m = mujoco.MjModel.from_xml_path(str(out / "hoeken.xml"))
    for link in ("crank", "coupler", "rocker"):
        L = rep["links"][link]
        b = root.find(f".//body[@name='{link}']")
        inert = b.find("inertial")
        # XML: the exact floats of report.json (repr round trip)
        assert float(inert.get("mass")) == L["mass_kg"]
        assert _tensor(_floats(inert.get("fullinertia"))).tolist() == L["inertia_com_kg_m2"]
        np.testing.assert_allclose(_floats(inert.get("pos")), np.array(L["com_mm"]) * 1e-3, rtol=0, atol=1e-15)
        # MuJoCo's compiled model: principal moments + frame reassemble the same tensor
        bid = m.body(link).id
        assert m.body_mass[bid] == L["mass_kg"]
        R = np.zeros(9)
        mujoco.mju_quat2Mat(R, m.body_iquat[bid])
        R = R.reshape(3, 3)
        tensor = R @ np.diag(m.body_inertia[bid]) @ R.T
        Iref = np.array(L["inertia_com_kg_m2"])
        assert np.abs(tensor - Iref).max() <= 1e-9 * np.abs(Iref).max()
        np.testing.assert_allclose(m.body_ipos[bid], np.array(L["com_mm"]) * 1e-3, atol=1e-12)
    # motor: rotor inertia as armature, torque limit from the catalog
    assert m.dof_armature[m.joint("crank").dofadr[0]] == rep["Jm_kg_m2"]
    tau = get_motor("maxon-re35").torque_peak_mNm * 1e-3  # data-sheet stall torque, catalog
    assert m.actuator_ctrlrange[0].tolist() == pytest.approx([-tau, tau], rel=1e-12)


def test_urdf_inertias_and_loop_pair(hoeken):
    import mujoco

    d, out, rep, _ = hoeken
    root = ET.parse(out / "hoeken.urdf").getroot()
    for link in ("crank", "coupler", "rocker"):
        L = rep["links"][link]
        el = root.find(f"link[@name='{link}']/inertial")
        assert float(el.find("mass").get("value")) == L["mass_kg"]
        i = el.find("inertia")
        got = [[float(i.get("i" + a + b) if "i" + a + b in i.attrib else i.get("i" + b + a)) for b in "xyz"]
               for a in "xyz"]
        assert got == L["inertia_com_kg_m2"]
    # forward kinematics of the URDF tree with the joint values of the written pose
    # (crank = phi1, coupler = phi2 - phi1, rocker = phi3): the loop pair coincides
    joints = {j.get("name"): j for j in root.findall("joint")}
    parent = {j.find("child").get("link"): j for j in joints.values()}

    def origin(j):
        o = j.find("origin")
        x, (r, p, y) = np.array(_floats(o.get("xyz"))), _floats(o.get("rpy"))
        Rz = np.array([[math.cos(y), -math.sin(y), 0], [math.sin(y), math.cos(y), 0], [0, 0, 1]])
        Ry = np.array([[math.cos(p), 0, math.sin(p)], [0, 1, 0], [-math.sin(p), 0, math.cos(p)]])
        Rx = np.array([[1, 0, 0], [0, math.cos(r), -math.sin(r)], [0, math.sin(r), math.cos(r)]])
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = Rz @ Ry @ Rx, x
        return T

    from cad.kinematics.fourbar import solve

    phi1 = 0.5 * (d.phi1_min_rad + d.phi1_max_rad)
    pose = solve(d.linkage, np.array([phi1]))
    q = {"crank": phi1, "coupler": float(pose.phi2_rad[0]) - phi1, "rocker": float(pose.phi3_rad[0])}

    def world(link):
        if link == "base_link":
            return np.eye(4)
        j = parent[link]
        T = origin(j)
        if j.get("type") == "continuous":
            a = q[j.get("name")]
            Rq = np.eye(4)
            Rq[:2, :2] = [[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]]
            T = T @ Rq
        return world(j.find("parent").get("link")) @ T

    gap = np.linalg.norm(world("loop_A3_a")[:3, 3] - world("loop_A3_b")[:3, 3])
    assert gap < 1e-12
    np.testing.assert_allclose(world("coupler")[:2, 3], pose.A2_mm[0] * 1e-3, atol=1e-12)
    # MuJoCo reads the URDF too (second parser): same masses
    mu = mujoco.MjModel.from_xml_path(str(out / "hoeken.urdf"))
    for link in ("crank", "coupler", "rocker"):
        assert mu.body_mass[mu.body(link).id] == pytest.approx(rep["links"][link]["mass_kg"], rel=1e-12)


def test_mujoco_operational_inertia_equals_eq22(hoeken):
    """M(phi1) from MuJoCo's mass matrix + constraint Jacobian = eq (22), 21 crank angles."""
    from cad.dynamics.inertia import InertiaCoefficients, apparent_mass_matrix
    from cad.kinematics.fourbar import solve
    from cad.sim import mj

    d, out, rep, _ = hoeken
    H = InertiaCoefficients(rep["H11_kg_m2"], rep["H12_kg_m2"], rep["H22_kg_m2"], rep["H33_kg_m2"],
                            math.radians(rep["beta2_deg"]))
    m, data = mj.load(out / "hoeken.xml")
    phis = np.linspace(d.phi1_min_rad, d.phi1_max_rad, 21)
    for phi in phis:
        r = mj.fourbar_operational_inertia(m, data, phi)
        Mh = apparent_mass_matrix(d.linkage, solve(d.linkage, np.array([phi])), H)[0]
        assert np.abs(r["M_op_kg"] - Mh).max() <= 1e-6 * np.abs(Mh).max(), phi
        assert r["residual_m"] < 1e-12
        assert data.qpos[mj.joint_qpos(m, "crank")] == phi  # the crank joint's value is phi1


def test_loop_stays_closed_while_mujoco_drives_the_crank(hoeken):
    import mujoco

    from cad.sim import mj

    d, out, *_ = hoeken
    m, data = mj.load(out / "hoeken.xml")
    a, b = d.phi1_min_rad, d.phi1_max_rad
    q, v = mj.joint_qpos(m, "crank"), mj.joint_dof(m, "crank")
    data.qpos[q] = a
    mj.close_loops(m, data, ["crank"])
    T = 0.3
    worst = 0.0
    tau = m.actuator_ctrlrange[0, 1]
    while data.time < T:
        s = min(data.time / T, 1.0)
        ref = a + (b - a) * (3 * s * s - 2 * s**3)
        dref = (b - a) * (6 * s - 6 * s * s) / T
        data.ctrl[0] = np.clip(2.0 * (ref - data.qpos[q]) + 0.05 * (dref - data.qvel[v]), -tau, tau)
        mujoco.mj_step(m, data)
        worst = max(worst, mj.loop_residual_m(m, data))
    assert abs(data.qpos[q] - b) < 0.01  # it did cover the stroke
    assert worst < 1e-9


def test_twin_pantograph_effective_mass_from_mujoco(mouse):
    from cad.sim import mj

    _, out, rep = mouse
    m, data = mj.load(out / "haptic-mouse.xml")
    assert m.nv == 9 and m.neq == 3 and m.nu == 4
    # force ranges: the peak torque of the motor the BOM orders (catalog), not [actuators] torque_max_Nm
    peak = get_motor("maxon-re35").torque_peak_mNm * 1e-3
    assert [m.actuator(i).name for i in range(4)] == [f"{g}_motor_{s}" for g in ("crank", "knob")
                                                      for s in ("left", "right")]
    np.testing.assert_allclose(m.actuator_forcerange, [[-peak, peak]] * 4, rtol=1e-12)
    r = mj.twin_task_mass_matrix(m, data)
    M, Mi = r["M_task"], np.linalg.inv(r["M_task"])
    em = rep["effective_mass_home"]
    got = {"mass_x_g_diag": M[0, 0] * 1e3, "mass_y_g_diag": M[1, 1] * 1e3,
           "inertia_theta_g_cm2_diag": M[2, 2] * 1e7, "mass_x_g_apparent": 1e3 / Mi[0, 0],
           "mass_y_g_apparent": 1e3 / Mi[1, 1], "inertia_theta_g_cm2_apparent": 1e7 / Mi[2, 2]}
    for k, v in got.items():
        assert v == pytest.approx(em[k], rel=1e-6), k
    assert r["residual_m"] < 1e-12
    root = ET.parse(out / "haptic-mouse.xml").getroot()
    for name, body in (("crankshaft", "crankshaft"), ("knob_distal_left", "knob_distal_left")):
        el = root.find(f".//body[@name='{name}']/inertial")
        assert float(el.get("mass")) == rep["bodies"][body]["mass_kg"]
        assert _tensor(_floats(el.get("fullinertia"))).tolist() == rep["bodies"][body]["inertia_com_kg_m2"]
    # the URDF carries the same inertias; MuJoCo's compiled masses equal them
    urdf = ET.parse(out / "haptic-mouse.urdf").getroot()
    for name in ("crankshaft", "knob_distal_left", "crank_proximal_right"):
        el = root.find(f".//body[@name='{name}']/inertial")
        u = urdf.find(f"link[@name='{name}']/inertial")
        assert float(u.find("mass").get("value")) == float(el.get("mass"))
        i = u.find("inertia")
        assert [float(i.get(k)) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")] == _floats(
            el.get("fullinertia"))
        assert m.body_mass[m.body(name).id] == float(el.get("mass"))
    # three loop-closure joint pairs in the URDF
    pairs = {j.get("name") for j in urdf.findall("joint") if j.get("name").startswith("loop_")}
    assert pairs == {f"{lp}_{t}" for lp in ("loop_knob_E", "loop_crank_left", "loop_crank_right")
                     for t in "ab"}


def test_formats_errors(tmp_path):
    code, _, err = hapticad("build", ROOT / "designs" / "hoeken.toml", "--formats", "mjcf,sdf",
                            "--out", tmp_path / "x")
    assert_one_line_error(code, err, "--formats", "sdf")
    code, _, err = hapticad("build", ROOT / "designs" / "powermouse.toml", "--formats", "urdf",
                            "--out", tmp_path / "y")
    assert_one_line_error(code, err, "--formats", "urdf")
    assert not (tmp_path / "x").exists() and not (tmp_path / "y").exists()
