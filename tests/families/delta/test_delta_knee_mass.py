"""The firmware's lumped mass model with Stamper's knee (the Falcon, g = 22.5 mm;
:class:`cad.dynamics.delta.DeltaMass` knee_kg / knee_com_mm / knee_kg_m2,
:func:`cad.dynamics.delta.mass_matrix_kg` and ``gravity_force_N``) against independent
references:

(1) Lambda(x) from body mass properties (:func:`cad.families.delta.dynamics.
    mass_matrix_from_bodies_kg`: each body's velocity and angular-velocity Jacobians from the
    layout, another derivation of the knee's rate) with bodies the lumped model describes
    exactly (uniform slender rods, the knee's and the arm's centres on their link lines, a
    point effector), over the Falcon's workspace grid; and ``delta_mass_from_bodies`` reads
    the lumped parameters back from those bodies;
(2) the gravity force against central differences of the potential energy of those bodies,
    placed by the layout's transforms (:func:`cad.families.delta.layout.body_poses`: no
    Jacobian), and the joint torques against :func:`gravity_hold_torques_Nm`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cad.design import load_design
from cad.dynamics.delta import (
    G_M_S2,
    DeltaMass,
    gravity_force_N,
    gravity_torques_Nm,
    mass_matrix_kg,
)
from cad.families.delta.dynamics import (
    delta_mass_from_bodies,
    gravity_hold_torques_Nm,
    mass_matrix_from_bodies_kg,
)
from cad.families.delta.layout import body_poses
from cad.massprops.props import MassProps

ROOT = Path(__file__).resolve().parents[3]
FALCON = load_design(ROOT / "designs" / "delta_falcon.toml")


def _bodies(d) -> tuple[dict, DeltaMass]:
    """Bodies the lumped model describes exactly, and that model's parameters by hand."""
    Lb, g = d.lower_arm_mm * 1e-3, d.joint_offset_mm * 1e-3
    arm = MassProps(0.04, [0.03, 0.0, 0.0], np.diag([1e-6, 2e-5, 1.9e-5]))
    knee = MassProps(0.012, [0.016, 0.0, 0.0], np.diag([2e-7, 1.5e-6, 1.4e-6]))
    rod = MassProps(0.006, [Lb / 2, 0, 0], np.diag([0.0, 0.006 * Lb**2 / 12, 0.006 * Lb**2 / 12]))
    props = {"effector": MassProps(0.09, [0, 0, 0], np.zeros((3, 3)))}
    for i in range(3):
        props[f"upper_{i}"], props[f"knee_{i}"] = arm, knee
        props[f"lower_{i}_a"] = props[f"lower_{i}_b"] = rod
    assert g > 0
    mass = DeltaMass(upper_arm_kg_m2=2e-5 + 0.04 * 0.03**2, upper_arm_kg=0.04, upper_arm_com_mm=30.0,
                     lower_arm_kg=0.012, effector_kg=0.09, rotor_kg_m2=1e-6, ratio=1.0,
                     knee_kg=0.012, knee_com_mm=16.0, knee_kg_m2=1.5e-6 + 0.012 * 0.016**2)
    return props, mass


def test_lumped_knee_model_equals_lambda_from_bodies_over_the_grid():
    d, w = FALCON.mechanism, FALCON.parallelogram_width_mm
    props, mass = _bodies(d)
    X = FALCON.workspace_points()
    ref = mass_matrix_from_bodies_kg(d, X, w, props, 1e-6, 1.0)
    ours = mass_matrix_kg(d, X, mass)
    assert np.abs(ours - ref).max() < 1e-12 * np.abs(ref).max()
    # the knee matters: without it the lumped model is far off
    bare = mass_matrix_kg(d, X, DeltaMass(**{**vars(mass), "knee_kg": 0.0, "knee_kg_m2": 0.0}))
    assert np.abs(bare - ref).max() > 1e-3 * np.abs(ref).max()
    back = delta_mass_from_bodies(d, props, 1e-6, 1.0)
    for k, v in vars(mass).items():
        assert getattr(back, k) == pytest.approx(v, rel=1e-12, abs=1e-15), k


def _potential_J(d, w, props, P_mm) -> float:
    T = body_poses(d, np.asarray(P_mm, float)[None], w)
    V = 0.0
    for b, mp in props.items():
        c = T[b][0, :3, :3] @ (np.asarray(mp.com_m) * 1e3) + T[b][0, :3, 3]
        V += mp.mass_kg * G_M_S2 * c[2] * 1e-3
    return V


@pytest.mark.parametrize("k", [0, 31, 62, 93, 124])
def test_knee_gravity_is_the_gradient_of_the_potential(k):
    d, w = FALCON.mechanism, FALCON.parallelogram_width_mm
    props, mass = _bodies(d)
    P = FALCON.workspace_points()[k]
    h = 1e-3  # mm
    grad = [(_potential_J(d, w, props, P + h * e) - _potential_J(d, w, props, P - h * e)) / (2 * h * 1e-3)
            for e in np.eye(3)]
    F = gravity_force_N(d, P[None], mass)[0]
    np.testing.assert_allclose(F, grad, rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(gravity_torques_Nm(d, P[None], mass)[0],
                               gravity_hold_torques_Nm(d, P[None], w, props)[0], rtol=1e-10, atol=1e-14)
