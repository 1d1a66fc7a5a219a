"""MJCF/URDF of the plain 5-bar pantograph (closed loop) and the PowerMouse (free flotor, coil
forces as actuators), issue 32 item 3: read back with MuJoCo and ``xml.etree``.

References, each independent of the writer:

* 5-bar: MuJoCo's joint-space inertia (``mj_fullM``, armature included) reduced onto the
  loop-closure manifold with MuJoCo's own constraint rows (:func:`cad.sim.mj.null_basis`)
  against the closed-form 5-bar mass matrix of :func:`cad.kinematics.fivebar.mass_matrix_kg`
  (the dynamics module) at home (``report.json``) and at the workspace corners (joint angles
  from :func:`cad.kinematics.fivebar.ik`);
* PowerMouse: MuJoCo's 6 x 6 mass matrix of the free flotor against the rigid-body spatial
  inertia assembled by hand from ``report.json`` ``flotor`` (m, COM, tensor); MuJoCo's
  generalized actuator force per unit control against the wrench map of
  :mod:`cad.actuators.powermouse` written in ``report.json``;
* force ranges against the motor catalog's peak torque (data, not our computation) and the
  report's eq (8)-(9) coil force; masses against ``report.json``.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import assert_one_line_error, hapticad

from tests.conftest import SIM_FORMATS

ROOT = Path(__file__).resolve().parents[3]
#: Exact float round trip (repr) of a written number.
EXACT_REL = 1e-12
#: MuJoCo's mass matrix against the closed forms: both are the same mechanics in double
#: precision (measured 2e-15 relative at home); the loop-closing Newton stops at CLOSE_TOL_M.
DYN_REL = 1e-9


@pytest.fixture(scope="module")
def fivebar(shared_build):
    """designs/pantograph.toml's shared simulator build (tests/conftest.py ``SIM_FORMATS``:
    preview, MJCF, URDF, STL): ``(design, out, report)``. Read-only."""
    return shared_build("pantograph.toml", SIM_FORMATS["pantograph.toml"], "preview")


@pytest.fixture(scope="module")
def powermouse(shared_build):
    """designs/powermouse.toml's shared simulator build (preview, MJCF, STL). Read-only."""
    return shared_build("powermouse.toml", SIM_FORMATS["powermouse.toml"], "preview")


def _closed_form_mass_g(design, rep: dict, xy_mm) -> np.ndarray:
    """The dynamics module's 2 x 2 mass matrix at the handle (g): the 5-bar's links and rotors
    (:func:`cad.kinematics.fivebar.mass_matrix_kg`) + the handle translating with E."""
    from cad.data.catalog import get_motor
    from cad.kinematics import fivebar as fb5

    def lm(b):
        mp = rep["bodies"][b]
        return fb5.LinkMass(mp["mass_kg"], (mp["com_mm"][0] * 1e-3, mp["com_mm"][1] * 1e-3),
                            mp["inertia_com_kg_m2"][2][2])

    jm = get_motor(design.parts.motor).rotor_inertia_g_cm2 * 1e-7
    mass = fb5.FiveBarMass(lm("proximal_left"), lm("proximal_right"), lm("distal_left"), lm("distal_right"), jm)
    from cad.families.pantograph.layout import lower_five_bar

    M = fb5.mass_matrix_kg(lower_five_bar(design), np.atleast_2d(xy_mm), mass)[0]
    return (M + rep["bodies"]["handle"]["mass_kg"] * np.eye(2)) * 1e3


def test_fivebar_mjcf_loads_closed_with_the_report_masses(fivebar):
    from cad.sim import mj

    design, out, rep = fivebar
    assert f"{design.name}.xml" in rep["files"] and f"{design.name}.urdf" in rep["files"]
    m, d = mj.load(out / f"{design.name}.xml")  # mj_forward at the written pose
    assert (m.nv, m.neq, m.nu) == (5, 1, 2)
    assert mj.loop_residual_m(m, d) < 1e-12  # the loop closes at the written pose
    root = ET.parse(out / f"{design.name}.xml").getroot()
    for b in root.iter("body"):
        assert float(b.find("inertial").get("mass")) == rep["bodies"][b.get("name")]["mass_kg"]
        assert m.body_mass[m.body(b.get("name")).id] == pytest.approx(rep["bodies"][b.get("name")]["mass_kg"],
                                                                     rel=EXACT_REL)


def test_fivebar_forceranges_are_the_bom_motors_peak_torques(fivebar):
    """Force range = the catalog motor's peak torque (the BOM's motor), armature = its rotor
    inertia -- not the GII's ``[actuators] torque_max_Nm`` normalisation."""
    from cad.data.catalog import get_motor
    from cad.sim import mj

    design, out, rep = fivebar
    spec = get_motor(design.parts.motor)
    assert [r for r in rep["bom"] if r.get("part") == "motor"][0]["quantity"] == 2
    m, _ = mj.load(out / f"{design.name}.xml")
    for i, joint in enumerate(("q_left", "q_right")):
        assert m.actuator(i).name == f"motor_{joint[2:]}"
        assert m.jnt_dofadr[m.actuator_trnid[i, 0]] == mj.joint_dof(m, joint)
        np.testing.assert_allclose(m.actuator_forcerange[i], [-spec.torque_peak_mNm * 1e-3,
                                                             spec.torque_peak_mNm * 1e-3], rtol=EXACT_REL)
        assert m.dof_armature[mj.joint_dof(m, joint)] == pytest.approx(spec.rotor_inertia_g_cm2 * 1e-7,
                                                                       rel=EXACT_REL)
    assert spec.torque_peak_mNm * 1e-3 != design.actuators["torque_max_Nm"]


def test_fivebar_mass_matrix_from_mujoco_equals_the_dynamics_module(fivebar):
    """MuJoCo (mj_fullM + the loop's constraint rows) = the closed-form 5-bar mass matrix, at
    home (report.json effective_mass_home) and at the four workspace corners."""
    import mujoco

    from cad.families.pantograph.layout import lower_five_bar
    from cad.kinematics import fivebar as fb5
    from cad.sim import mj

    design, out, rep = fivebar
    m, d = mj.load(out / f"{design.name}.xml")
    r = mj.fivebar_task_mass_matrix(m, d)
    home = np.array(rep["effective_mass_home"]["mass_matrix_g"])
    np.testing.assert_allclose(r["M_xy"] * 1e3, home, rtol=DYN_REL, atol=DYN_REL * np.abs(home).max())
    # the handle's COM sits on its pin's axis: a free spin leaves the apparent mass unchanged
    np.testing.assert_allclose(r["M_apparent"], r["M_xy"], rtol=1e-9, atol=1e-12)
    c, h = np.array(design.workspace["center_mm"]), design.workspace["side_mm"] / 2
    fb = lower_five_bar(design)
    for sx, sy in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
        xy = c + h * np.array([sx, sy])
        ik = fb5.ik(fb, xy[None])
        d = mujoco.MjData(m)
        d.qpos[mj.joint_qpos(m, "q_left")] = ik.q_rad[0, 0]
        d.qpos[mj.joint_qpos(m, "q_right")] = ik.q_rad[0, 1]
        r = mj.fivebar_task_mass_matrix(m, d)
        assert r["residual_m"] < 1e-10
        np.testing.assert_allclose(d.site_xpos[m.site("handle").id][:2] * 1e3, xy, atol=1e-6)
        want = _closed_form_mass_g(design, rep, xy)
        np.testing.assert_allclose(r["M_xy"] * 1e3, want, rtol=DYN_REL, atol=DYN_REL * np.abs(want).max())


def test_fivebar_urdf_is_the_open_tree_with_its_loop_pair(fivebar):
    import mujoco

    design, out, rep = fivebar
    urdf = ET.parse(out / f"{design.name}.urdf").getroot()
    pairs = {j.get("name") for j in urdf.findall("joint") if j.get("name").startswith("loop_")}
    assert pairs == {"loop_E_a", "loop_E_b"}
    assert "loop closure loop_E" in (out / f"{design.name}.urdf").read_text()
    mu = mujoco.MjModel.from_xml_path(str(out / f"{design.name}.urdf"))  # a second parser
    for b in ("proximal_left", "distal_right", "handle"):
        assert mu.body_mass[mu.body(b).id] == pytest.approx(rep["bodies"][b]["mass_kg"], rel=EXACT_REL)


def test_powermouse_flotor_mass_matrix_is_its_spatial_inertia(powermouse):
    """MuJoCo's mass matrix of the free flotor (qvel: v world, w body) = m A^T A + diag(0, I_c)
    with v_com = v - [c]x w, from report.json's flotor (mass, COM, tensor about the COM)."""
    from cad.sim import mj

    design, out, rep = powermouse
    assert f"{design.name}.xml" in rep["files"]
    m, d = mj.load(out / f"{design.name}.xml")
    assert (m.nv, m.nu, m.neq) == (6, 6, 0)
    fl = rep["flotor"]
    assert m.body_mass[m.body("flotor").id] == pytest.approx(fl["mass_kg"], rel=EXACT_REL)
    assert fl["mass_kg"] * 1e3 == pytest.approx(rep["flotor_mass_g"], rel=EXACT_REL)
    c = np.array(fl["com_mm"]) * 1e-3
    cx = np.array([[0, -c[2], c[1]], [c[2], 0, -c[0]], [-c[1], c[0], 0]])
    A = np.hstack([np.eye(3), -cx])
    want = fl["mass_kg"] * A.T @ A
    want[3:, 3:] += np.array(fl["inertia_com_kg_m2"])
    M = mj.full_mass_matrix(m, d)
    np.testing.assert_allclose(M, want, rtol=0, atol=1e-12 * np.abs(want).max())
    # apparent mass at the flotor's COM, every direction: the flotor's mass (datasheet row)
    jp, jr = mj.site_jacobian(m, d, "com")
    lam = np.linalg.inv(jp @ np.linalg.solve(M, jp.T))
    np.testing.assert_allclose(lam, fl["mass_kg"] * np.eye(3), rtol=0, atol=1e-9 * fl["mass_kg"])


def test_powermouse_coil_actuators_are_the_wrench_map(powermouse):
    """One newton of coil i's control gives MuJoCo's generalized force = the wrench map's
    column i / the gain (N per ampere-turn); force range = the eq (8)-(9) coil force at
    peak_power_W (report.json actuator.peak_force_N)."""
    import mujoco

    from cad.sim import mj

    design, out, rep = powermouse
    m, d = mj.load(out / f"{design.name}.xml")
    W = np.array(rep["wrench_map"]) / rep["gain_N_per_ampere_turn"]
    for i in range(6):
        d.ctrl[:] = 0.0
        d.ctrl[i] = 1.0
        mujoco.mj_forward(m, d)
        # flotor frame = world at the centre pose: (F world, torque body) = (F, tau about the centre)
        np.testing.assert_allclose(d.qfrc_actuator, W[:, i], rtol=0, atol=1e-12)
    np.testing.assert_allclose(m.actuator_forcerange[:, 1], rep["actuator"]["peak_force_N"], rtol=EXACT_REL)


def test_powermouse_refuses_urdf_in_one_line(tmp_path):
    code, _, err = hapticad("build", ROOT / "designs" / "powermouse.toml", "--formats", "urdf",
                            "--out", tmp_path / "y")
    assert_one_line_error(code, err, "--formats", "urdf")
    assert not (tmp_path / "y").exists()
