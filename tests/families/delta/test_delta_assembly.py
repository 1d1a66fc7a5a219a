"""The delta's assembly model (cad/families/delta/assembly.py): instance and body counts,
the effector and the rods' ball sockets where the kinematics put them (the effector at
:func:`cad.kinematics.delta.fk` of the IK angles to 1e-6 mm; each socket's ball centre on
its stud's ball centre), and the one interference check of every family
(:func:`cad.assembly.interference.check_model`) over the workspace corners and centre of
the bundled delta (the whole 5 x 5 x 5 grid in the slow test).
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from cad.assembly.interference import check_model
from cad.design import load_design
from cad.families.delta.assembly import assemble
from cad.kinematics import delta as D

ROOT = Path(__file__).resolve().parents[3]


@pytest.fixture(scope="module")
def models():
    return {n: assemble(load_design(ROOT / "designs" / f"{n}.toml")) for n in ("delta", "delta_falcon")}


@pytest.mark.parametrize("name, n_inst, n_bodies, n_balls, n_hinges", [("delta", 54, 11, 12, 0),
                                                                       ("delta_falcon", 78, 14, 6, 6)])
def test_counts(models, name, n_inst, n_bodies, n_balls, n_hinges):
    """``n_inst``: the parts before the fasteners; the screws add, in closed form, per arm the
    motor's 3 face screws (the RE 40's and RE 35's bolt count), 2 bracket screws and a hub set
    screw, the handle's screw and one per effector cross bar: 3 (3 + 2 + 1) + 1 + 3 = 22."""
    m = models[name]
    assert len(m.instances) == n_inst + 3 * (3 + 2 + 1) + 1 + 3
    assert sum(i.fastener is not None for i in m.instances) == 22
    # ground, 3 upper arms, (3 knees with a joint offset), 6 rods, the effector
    assert len(m.bodies) == n_bodies
    n = len(m.design.workspace_points())
    assert all(T.shape == (n, 4, 4) for T in m.motion.values()) and len(m.pose_labels) == n
    # ball joints at the effector (and the elbows without a knee); the knee's hinges otherwise
    assert sum(i.kind.name == "ball_socket" for i in m.instances) == n_balls
    assert sum(i.kind.name == "ball_stud" for i in m.instances) == n_balls
    for kind in ("knee_clevis", "knee_hinge_pin", "knee_bearing", "rod_eye"):
        assert sum(i.kind.name == kind for i in m.instances) == n_hinges
    assert sum(i.kind.name == "motor" for i in m.instances) == 3


@pytest.mark.parametrize("name", ["delta", "delta_falcon"])
def test_effector_and_joints_sit_where_the_kinematics_put_them(models, name):
    m = models[name]
    d = m.design.mechanism
    X = m.extra.workspace_mm
    P_fk = D.fk(d, D.ik(d, X).theta_rad).P_mm
    np.testing.assert_allclose(m.motion["effector"][:, :3, 3], P_fk, atol=1e-6)
    studs = [i for i in m.instances if i.kind.name == "ball_stud"]
    sockets = [i for i in m.instances if i.kind.name == "ball_socket"]
    for pose in (0, len(X) // 2, len(X) - 1):
        ball = np.array([m.tf_world_part(i, pose)[:3, 3] for i in studs])
        for s in sockets:
            c = m.tf_world_part(s, pose)[:3, 3]
            assert np.min(np.linalg.norm(ball - c, axis=1)) < 1e-9, s.name


def test_the_drawn_knee_pins_are_the_models_hinge_axes(models):
    """The Falcon's knee: at every workspace pose each rod's top end turns on a pin whose
    axis is the analyses' hinge axis, the normal n_i = k_i x t_i of the parallelogram's plane
    (k_i the unit in-plane direction elbow -> effector joint, written out here from the IK's
    angles: :func:`cad.families.delta.structure.knee_arm`, the MJCF's hinge), through the
    rod's joint point (the top bar's centre -+ w/2 t_i); the pin (knee body), the bearing's
    two rings (knee and rod) and the rod's eye (rod body) share that axis and centre."""
    m = models["delta_falcon"]
    d, w = m.design.mechanism, m.design.parallelogram_width_mm
    X = m.extra.workspace_mm
    th = D.ik(d, X).theta_rad
    by = {i.name: i for i in m.instances}
    for pose in range(len(X)):
        for i in range(3):
            u, t = d.radial[i], d.tangential[i]
            elbow = d.base_radius_mm * u + d.axis_offset_mm * t + d.upper_arm_mm * (
                math.cos(th[pose, i]) * u - math.sin(th[pose, i]) * np.array([0.0, 0.0, 1.0]))
            wv = X[pose] + d.effector_radius_mm * u - elbow
            k = wv - (wv @ t) * t
            k /= np.linalg.norm(k)
            n = np.cross(k, t)
            for side, s in (("a", -0.5), ("b", 0.5)):
                c = elbow + d.joint_offset_mm * k + s * w * t
                pin = m.tf_world_part(by[f"knee_{i}.hinge_pin_{side}"], pose)
                eye = m.tf_world_part(by[f"lower_{i}_{side}.eye"], pose)
                assert np.allclose(pin[:3, 2], n, atol=1e-12) and np.allclose(pin[:3, 3], c, atol=1e-9)
                assert np.allclose(eye[:3, 2], n, atol=1e-12) and np.allclose(eye[:3, 3], c, atol=1e-9)
                brg = by[f"lower_{i}_{side}.knee_bearing"]
                outer = m.tf_world_part(brg, pose)
                inner = m.motion[f"knee_{i}"][pose] @ brg.tf_other_part
                for T in (outer, inner):
                    assert np.allclose(T[:3, 2], n, atol=1e-12)
                    assert np.allclose(T[:3, 3] + 2.0 * n, c, atol=1e-9)  # 623: B = 4 mm, z 0..B


def _corners_and_centre(m):
    X = m.extra.workspace_mm
    lo, hi = X.min(axis=0), X.max(axis=0)
    keep = [k for k, x in enumerate(X)
            if np.all(np.isclose(x, lo) | np.isclose(x, hi)) or np.allclose(x, (lo + hi) / 2)]
    motion = {b: T[keep] for b, T in m.motion.items()}
    return replace(m, motion=motion, pose_labels=tuple(m.pose_labels[k] for k in keep))


def test_delta_is_clear_at_the_workspace_corners(models):
    m = _corners_and_centre(models["delta"])
    assert len(m.pose_labels) == 9
    rep = check_model(m)
    assert rep.collisions == []
    # the ball joints' running clearance is the closest approach
    assert rep.min_clearance_mm == pytest.approx(0.05, abs=1e-6)


@pytest.mark.slow
def test_delta_is_clear_over_the_whole_workspace_grid(models):
    rep = check_model(models["delta"])
    assert rep.collisions == []
    assert rep.min_clearance_mm == pytest.approx(0.05, abs=1e-6)


def test_lambda_from_the_solids_regression_pin(models):
    """Regression pin (our own run): Lambda(x) of the bundled delta from its solids' body mass
    properties (OCCT integration) and the RE 35 rotors, at the workspace centre and its
    extremes over the grid; the formula itself is checked in test_delta_bodies.py. Re-pinned
    2026-12-06 with the fasteners drawn (the hubs' set-screw bosses and set screws on the arms, the
    handle's and the cross bars' screws on the effector; was 0.0959427 / 0.0985726 at the centre, 0.1207128 and
    0.0871720 over the grid)."""
    from cad.data.catalog import get_motor
    from cad.families.delta.dynamics import mass_matrix_from_bodies_kg
    from cad.pipeline.family import body_props, kind_props

    m = models["delta"]
    bp = body_props(m.instances, kind_props(m.instances))
    rotor = get_motor("maxon-re35").rotor_inertia_g_cm2 * 1e-7
    X = m.extra.workspace_mm
    ev = np.linalg.eigvalsh(mass_matrix_from_bodies_kg(m.design.mechanism, X, 30.0, bp, rotor))
    np.testing.assert_allclose(ev[len(X) // 2], [0.0986589, 0.0986589, 0.1012894], rtol=1e-5)
    assert ev[:, -1].max() == pytest.approx(0.1234381, rel=1e-5)
    assert ev[:, 0].min() == pytest.approx(0.0898850, rel=1e-5)
