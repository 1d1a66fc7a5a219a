"""The delta's body poses (layout) and Lambda(x) from body mass properties (dynamics).

References: (1) the joints the layout places satisfy the kinematics' own constraints (rod
length L_b, knee link g, effector at the FK position of the IK angles); (2) Lambda from
bodies equals :func:`cad.dynamics.delta.mass_matrix_kg` (the slender-rod closed form) when
the bodies are slender uniform rods, a point effector and an arm inertia; (3) twice the
kinetic energy of the posed bodies, velocities and angular velocities by central finite
differences of the layout's transforms (no Jacobian), equals x_dot^T Lambda x_dot, with
seeded random mass properties (off-axis centres, full tensors) on both bundled designs.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cad.design import load_design
from cad.dynamics.delta import DeltaMass, mass_matrix_kg
from cad.errors import DesignError
from cad.families.delta.dynamics import delta_mass_from_bodies, mass_matrix_from_bodies_kg
from cad.families.delta.layout import body_names, body_poses, rot_x, rot_z
from cad.kinematics import delta as D
from cad.massprops.props import MassProps

ROOT = Path(__file__).resolve().parents[3]
DESIGNS = ("delta.toml", "delta_falcon.toml")


def _design(name):
    return load_design(ROOT / "designs" / name)


@pytest.mark.parametrize("name", DESIGNS)
def test_layout_places_joints_on_the_kinematics(name):
    des = _design(name)
    d, w = des.mechanism, des.parallelogram_width_mm
    P = des.workspace_points()
    tfs = body_poses(d, P, w)
    assert set(tfs) == set(body_names(d))
    theta = D.ik(d, P).theta_rad
    np.testing.assert_allclose(D.fk(d, theta).P_mm, tfs["effector"][:, :3, 3], atol=1e-6)
    for i in range(3):
        for s, sign in (("a", -1), ("b", 1)):
            tf = tfs[f"lower_{i}_{s}"]
            bottom = P + d.effector_radius_mm * d.radial[i] + sign * w / 2 * d.tangential[i]
            end = tf[:, :3, 3] + d.lower_arm_mm * tf[:, :3, 0]
            np.testing.assert_allclose(end, bottom, atol=1e-9)
        elbow = tfs[f"upper_{i}"][:, :3, 3] + d.upper_arm_mm * tfs[f"upper_{i}"][:, :3, 0]
        if d.joint_offset_mm > 0:
            np.testing.assert_allclose(tfs[f"knee_{i}"][:, :3, 3], elbow, atol=1e-9)
    for tf in tfs.values():
        R = tf[:, :3, :3]
        np.testing.assert_allclose(R @ np.swapaxes(R, 1, 2), np.broadcast_to(np.eye(3), R.shape),
                                   atol=1e-12)
        np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-12)


def _rod(m_kg, L_m):
    return MassProps(m_kg, [L_m / 2, 0, 0], np.diag([0.0, m_kg * L_m**2 / 12, m_kg * L_m**2 / 12]))


def test_slender_rods_reduce_to_the_point_mass_model():
    des = _design("delta.toml")
    d = des.mechanism
    mass = DeltaMass(upper_arm_kg_m2=0.0, upper_arm_kg=0.05, upper_arm_com_mm=40.0,
                     lower_arm_kg=0.03, effector_kg=0.08, rotor_kg_m2=1e-6, ratio=8.0)
    arm = MassProps(0.05, [0.04, 0.0, 0.002], np.diag([1e-5, 3e-5, 2.5e-5]))
    # the arm about its motor axis (body y): parallel axes, written out by hand
    I_axis = 3e-5 + 0.05 * (0.04**2 + 0.002**2)
    mass = DeltaMass(**{**vars(mass), "upper_arm_kg_m2": I_axis})
    props = {"effector": MassProps(0.08, [0, 0, 0], np.zeros((3, 3)))}
    for i in range(3):
        props[f"upper_{i}"] = arm
        props[f"lower_{i}_a"] = props[f"lower_{i}_b"] = _rod(0.015, d.lower_arm_mm * 1e-3)
    P = des.workspace_points()
    ours = mass_matrix_from_bodies_kg(d, P, des.parallelogram_width_mm, props, 1e-6, 8.0)
    np.testing.assert_allclose(ours, mass_matrix_kg(d, P, mass), rtol=1e-12, atol=1e-15)
    back = delta_mass_from_bodies(d, props, 1e-6, 8.0)
    for k, v in vars(mass).items():
        assert getattr(back, k) == pytest.approx(v, rel=1e-12), k


def _random_props(rng, names):
    out = {}
    for b in names:
        if b == "ground":
            continue
        A = rng.normal(size=(3, 3))
        inertia = (A @ A.T + 0.1 * np.eye(3)) * 1e-5
        ev, V = np.linalg.eigh(inertia)
        ev = np.maximum(ev, 0.5 * ev.max())  # principal moments satisfy a + b >= c
        out[b] = MassProps(rng.uniform(0.01, 0.2), rng.normal(scale=0.02, size=3), V @ np.diag(ev) @ V.T)
    return out


def _log_so3(R):
    """Rotation vector of R (3, 3), angle < pi."""
    c = np.clip((np.trace(R) - 1) / 2, -1, 1)
    a = np.arccos(c)
    v = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / 2
    return v if a < 1e-12 else v * a / np.sin(a)


def _kinetic_energy_fd(d, w, props, P, v, rotor, ratio):
    h_mm = 1e-4
    plus = body_poses(d, P + h_mm * v, w)
    minus = body_poses(d, P - h_mm * v, w)
    dt = 2 * h_mm * 1e-3  # s, at 1 m/s along v
    T = 0.0
    for b, mp in props.items():
        Rp, Rm = plus[b][0, :3, :3], minus[b][0, :3, :3]
        c = np.asarray(mp.com_m) * 1e3
        cp, cm = plus[b][0, :3, 3] + Rp @ c, minus[b][0, :3, 3] + Rm @ c
        vel = (cp - cm) * 1e-3 / dt
        omega = _log_so3(Rp @ Rm.T) / dt
        R = body_poses(d, P, w)[b][0, :3, :3]
        T += 0.5 * mp.mass_kg * vel @ vel + 0.5 * omega @ R @ mp.inertia_com_kg_m2 @ R.T @ omega
    th_dot = (D.ik(d, P + h_mm * v).theta_rad - D.ik(d, P - h_mm * v).theta_rad)[0] / dt
    return T + 0.5 * ratio**2 * rotor * th_dot @ th_dot


@pytest.mark.parametrize("name", DESIGNS)
def test_lambda_is_twice_the_kinetic_energy_of_the_posed_bodies(name):
    des = _design(name)
    d, w = des.mechanism, des.parallelogram_width_mm
    rng = np.random.default_rng(36)
    props = _random_props(rng, body_names(d))
    P_all = des.workspace_points()
    for k in rng.choice(len(P_all), size=6, replace=False):
        P = P_all[k:k + 1]
        Lam = mass_matrix_from_bodies_kg(d, P, w, props, 2e-6, 5.0)[0]
        v = rng.normal(size=3)
        v /= np.linalg.norm(v)
        T = _kinetic_energy_fd(d, w, props, P, v, 2e-6, 5.0)
        assert 0.5 * v @ Lam @ v == pytest.approx(T, rel=1e-6)
        np.testing.assert_allclose(Lam, Lam.T, atol=1e-14)


def test_bad_rotor_and_ratio_are_named():
    des = _design("delta.toml")
    P = des.workspace_points()[:1]
    with pytest.raises(DesignError, match="rotor_kg_m2"):
        mass_matrix_from_bodies_kg(des.mechanism, P, 30.0, {}, -1.0)
    with pytest.raises(DesignError, match="ratio"):
        mass_matrix_from_bodies_kg(des.mechanism, P, 30.0, {}, 0.0, 0.0)


def test_rot_x_and_rot_z_against_scipy():
    """The layout's 4 x 4 rotations (degrees, right hand) against scipy's Rotation, and a
    quarter turn by hand (rot_x(90): y -> z; rot_z(90): x -> y)."""
    from scipy.spatial.transform import Rotation

    for deg in (-90.0, 30.0, 180.0, 247.5):
        for T, axis in ((rot_x(deg), "x"), (rot_z(deg), "z")):
            assert np.allclose(T[:3, :3], Rotation.from_euler(axis, deg, degrees=True).as_matrix(), atol=1e-15)
            assert np.array_equal(T[3], [0.0, 0.0, 0.0, 1.0]) and np.array_equal(T[:3, 3], np.zeros(3))
    assert np.allclose(rot_x(90.0)[:3, :3] @ [0, 1, 0], [0, 0, 1], atol=1e-15)
    assert np.allclose(rot_z(90.0)[:3, :3] @ [1, 0, 0], [0, 1, 0], atol=1e-15)
