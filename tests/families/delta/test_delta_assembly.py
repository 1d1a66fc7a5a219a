"""The delta's assembly model (cad/families/delta/assembly.py): instance and body counts,
the effector and the rods' ball sockets where the kinematics put them (the effector at
:func:`cad.kinematics.delta.fk` of the IK angles to 1e-6 mm; each socket's ball centre on
its stud's ball centre), and the one interference check of every family
(:func:`cad.assembly.interference.check_model`) over the workspace corners and centre of
the bundled delta (the whole 5 x 5 x 5 grid in the slow test).
"""

from __future__ import annotations

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


@pytest.mark.parametrize("name, n_inst, n_bodies", [("delta", 54, 11), ("delta_falcon", 66, 14)])
def test_counts(models, name, n_inst, n_bodies):
    m = models[name]
    assert len(m.instances) == n_inst
    # ground, 3 upper arms, (3 knees with a joint offset), 6 rods, the effector
    assert len(m.bodies) == n_bodies
    n = len(m.design.workspace_points())
    assert all(T.shape == (n, 4, 4) for T in m.motion.values()) and len(m.pose_labels) == n
    assert sum(i.kind.name == "ball_socket" for i in m.instances) == 12
    assert sum(i.kind.name == "ball_stud" for i in m.instances) == 12
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
    extremes over the grid; the formula itself is checked in test_delta_bodies.py."""
    from cad.data.catalog import get_motor
    from cad.families.delta.dynamics import mass_matrix_from_bodies_kg
    from cad.pipeline.family import body_props, kind_props

    m = models["delta"]
    bp = body_props(m.instances, kind_props(m.instances))
    rotor = get_motor("maxon-re35").rotor_inertia_g_cm2 * 1e-7
    X = m.extra.workspace_mm
    ev = np.linalg.eigvalsh(mass_matrix_from_bodies_kg(m.design.mechanism, X, 30.0, bp, rotor))
    np.testing.assert_allclose(ev[len(X) // 2], [0.0959427, 0.0959427, 0.0985726], rtol=1e-5)
    assert ev[:, -1].max() == pytest.approx(0.1207128, rel=1e-5)
    assert ev[:, 0].min() == pytest.approx(0.0871720, rel=1e-5)
