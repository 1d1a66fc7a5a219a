"""The delta's MJCF (``--formats mjcf``, :mod:`cad.families.delta.sim`) loaded in MuJoCo:
the loops close, the handle site is the effector point, and MuJoCo's task-space mass
matrix -- its joint-space inertia (``mj_fullM``, armature included) reduced through the
loop constraints' rows (``efc_J``) onto the handle site's Jacobian (``mj_jacSite``):
Lambda^-1 = J_x (M^-1 - M^-1 J_c^T (J_c M^-1 J_c^T)^-1 J_c M^-1) J_x^T -- equals
:func:`cad.families.delta.dynamics.mass_matrix_from_bodies_kg` (eq 1) at several poses.

Tolerance: the MJCF's rods hang on ball joints, so each rod's spin about its own axis is
free (as in the hardware) and MuJoCo's Lambda takes the spin of least energy, while eq (1)
prescribes it (the rod's y axis in the parallelogram's plane). With seeded random bodies
whose rods are axisymmetric with an axial inertia of 1e-10 kg m^2 the two differ by
~1e-8 of the largest entry (measured; 1e-8 kg m^2 gives ~1e-6: the difference scales with
that inertia), so 1e-7 is asserted; the upper arms and the effector carry full random
inertia tensors and centres off their joints.
"""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import numpy as np
import pytest

from cad.design import parse_design
from cad.device import resolve_device
from cad.export.sim import mjcf_text
from cad.families.delta.dynamics import mass_matrix_from_bodies_kg
from cad.families.delta.sim import sim_model
from cad.massprops.props import MassProps

mujoco = pytest.importorskip("mujoco")
ROOT = Path(__file__).resolve().parents[3]
RAW = tomllib.loads((ROOT / "designs" / "delta.toml").read_text())
ROD_AXIAL_KG_M2 = 1e-10
AGREE_REL = 1e-7


def _box(rng, m: float) -> MassProps:
    """A solid box of mass m (random sides 1-10 cm, random orientation, centre off the origin)."""
    a, b, c = rng.uniform(0.01, 0.1, 3)
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    inertia = Q @ np.diag([b * b + c * c, a * a + c * c, a * a + b * b]) * m / 12 @ Q.T
    return MassProps(m, rng.normal(size=3) * 0.01, inertia)


def _bodies(rng) -> dict:
    out = {f"upper_{i}": _box(rng, 0.05) for i in range(3)}
    out |= {f"lower_{i}_{s}": MassProps(0.015, np.array([0.095, 0.0, 0.0]),
                                        np.diag([ROD_AXIAL_KG_M2, 4e-5, 4e-5]))
            for i in range(3) for s in "ab"}
    out["effector"] = _box(rng, 0.08)
    return out


def mujoco_lambda(xml: str) -> tuple[np.ndarray, float, np.ndarray]:
    """(Lambda (3, 3) kg at the handle site, largest loop residual m, handle position m)."""
    m = mujoco.MjModel.from_xml_string(xml)
    m.opt.jacobian = mujoco.mjtJacobian.mjJAC_DENSE
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    M = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, M)
    eq = d.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY
    Jc = np.array(d.efc_J).reshape(d.nefc, m.nv)[eq]
    site = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, "handle")
    jp, jr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
    mujoco.mj_jacSite(m, d, jp, jr, site)
    Mi = np.linalg.inv(M)
    Mc = Mi - Mi @ Jc.T @ np.linalg.solve(Jc @ Mi @ Jc.T, Jc @ Mi)
    return np.linalg.inv(jp @ Mc @ jp.T), float(np.abs(d.efc_pos[eq]).max()), d.site_xpos[site].copy()


def test_mujoco_task_mass_matrix_equals_eq1_at_several_poses():
    raw = copy.deepcopy(RAW) | {"motor": {"rotor_inertia_g_cm2": 20.0, "torque_peak_mNm": 500.0}}
    des = parse_design(raw, "variant.toml")
    dev = resolve_device(des)
    bodies = _bodies(np.random.default_rng(36))
    X = des.workspace_points()[::31]  # 5 poses: corners and the centre of the cube
    assert len(X) == 5
    for P in X:
        xml = mjcf_text(sim_model(des, bodies, dev, P))
        assert xml.count('type="ball"') == 7 and xml.count("<connect") == 5
        lam, residual, handle = mujoco_lambda(xml)
        assert residual < 1e-12 and np.allclose(handle, P * 1e-3, rtol=0, atol=1e-12)
        ref = mass_matrix_from_bodies_kg(des.mechanism, P[None], des.parallelogram_width_mm, bodies,
                                         20.0e-7)[0]
        assert np.abs(lam - ref).max() < AGREE_REL * np.abs(ref).max()
        # the rotors matter here: without them eq (1) is far off (not a vacuous comparison)
        bare = mass_matrix_from_bodies_kg(des.mechanism, P[None], des.parallelogram_width_mm, bodies)[0]
        assert np.abs(lam - bare).max() > 1e-3 * np.abs(ref).max()


def test_motors_take_the_resolved_armature_and_force_range():
    import xml.etree.ElementTree as ET

    raw = copy.deepcopy(RAW) | {"parts": {"motor": "maxon-re40"},
                                "motor": {"rotor_inertia_g_cm2": 20.0, "torque_peak_mNm": 500.0}}
    des = parse_design(raw, "variant.toml")
    root = ET.fromstring(mjcf_text(sim_model(des, _bodies(np.random.default_rng(1)),
                                             resolve_device(des))))
    joints = {j.get("name"): j for j in root.iter("joint")}
    for i in range(3):
        assert float(joints[f"theta_{i}"].get("armature")) == pytest.approx(20.0e-7, rel=1e-15)
    ranges = [m.get("forcerange") for m in root.iter("motor")]
    assert ranges == ["-0.5 0.5"] * 3


FALCON = tomllib.loads((ROOT / "designs" / "delta_falcon.toml").read_text())


def nullspace_lambda(xml: str) -> tuple[np.ndarray, float, np.ndarray, int]:
    """(Lambda (3, 3) kg at the handle site, largest loop residual m, handle position m, rank
    of the loop rows): the joint-space inertia restricted to the null space N of the loop
    constraints' rows (SVD; the Falcon's rows are redundant, so the projection of
    :func:`mujoco_lambda` would divide by a singular matrix): Lambda^-1 = J_x N (N^T M N)^-1
    N^T J_x^T."""
    m = mujoco.MjModel.from_xml_string(xml)
    m.opt.jacobian = mujoco.mjtJacobian.mjJAC_DENSE
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    M = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, M)
    eq = d.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY
    Jc = np.array(d.efc_J).reshape(d.nefc, m.nv)[eq]
    _, sv, Vt = np.linalg.svd(Jc)
    rank = int((sv > 1e-9 * sv[0]).sum())
    N = Vt[rank:].T
    site = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, "handle")
    jp, jr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
    mujoco.mj_jacSite(m, d, jp, jr, site)
    A = jp @ N
    lam = np.linalg.inv(A @ np.linalg.solve(N.T @ M @ N, A.T))
    return lam, float(np.abs(d.efc_pos[eq]).max()), d.site_xpos[site].copy(), rank


def _knee_bodies(rng) -> dict:
    """Random full inertia tensors and off-axis centres on every body (knees and rods too:
    the rods' spin is held by their hinges, as eq (1) prescribes it)."""
    out = {f"upper_{i}": _box(rng, 0.05) for i in range(3)}
    out |= {f"knee_{i}": _box(rng, 0.02) for i in range(3)}
    out |= {f"lower_{i}_{s}": _box(rng, 0.015) for i in range(3) for s in "ab"}
    out["effector"] = _box(rng, 0.08)
    return out


def test_falcon_knee_mjcf_equals_eq1_and_closes_its_loops():
    """The Falcon (g = 22.5 mm): knee hinges about t_i, rods hinged in the knee's plane; at 5
    poses MuJoCo's Lambda (null-space reduction) equals eq (1) (which takes the knee's and
    rods' angular velocities from the kinematics, no MuJoCo) to 1e-9 of its largest entry,
    the 15 loop rows have rank 12 (15 coordinates - 3 effector translations), and the loops
    stay closed over 0.2 s of free motion under gravity (MuJoCo's own constraint solver; measured
    9e-10 m)."""
    raw = copy.deepcopy(FALCON) | {"motor": {"rotor_inertia_g_cm2": 20.0, "torque_peak_mNm": 500.0}}
    des = parse_design(raw, "falcon_variant.toml")
    dev = resolve_device(des)
    bodies = _knee_bodies(np.random.default_rng(37))
    X = des.workspace_points()[::31]
    for P in X:
        xml = mjcf_text(sim_model(des, bodies, dev, P))
        assert xml.count('type="ball"') == 1 and xml.count("<connect") == 5
        lam, residual, handle, rank = nullspace_lambda(xml)
        assert rank == 12
        assert residual < 1e-12 and np.allclose(handle, P * 1e-3, rtol=0, atol=1e-12)
        ref = mass_matrix_from_bodies_kg(des.mechanism, P[None], des.parallelogram_width_mm, bodies,
                                         20.0e-7)[0]
        assert np.abs(lam - ref).max() < 1e-12 * np.abs(ref).max()
        # the knees matter here: without their bodies eq (1) is far off
        no_knee = {k: v for k, v in bodies.items() if not k.startswith("knee_")}
        bare = mass_matrix_from_bodies_kg(des.mechanism, P[None], des.parallelogram_width_mm,
                                          no_knee, 20.0e-7)[0]
        assert np.abs(lam - bare).max() > 1e-3 * np.abs(ref).max()
    m = mujoco.MjModel.from_xml_string(mjcf_text(sim_model(des, bodies, dev)))
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    for _ in range(int(0.2 / m.opt.timestep)):
        mujoco.mj_step(m, d)
    eq = d.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY
    assert np.abs(d.efc_pos[eq]).max() < 1e-6
    assert np.abs(d.qpos - m.qpos0).max() > 1e-3  # it moved
