"""The delta's kinematics see the base and effector radii only through R - r.

Closed form (Clavel's delta, the effector translating, no Stamper offsets): arm i's shoulder
sits at R u_i and its effector joint at P + r u_i, so every constraint |E_i - (P + r u_i)| = L_b
is |(E_i - r u_i) - P| = L_b with E_i - r u_i the elbow of a delta with base radius R - r and
r = 0. Inverse kinematics, the Jacobian and so the GII (isotropy paper eq 5) are the same for
every (R, r) of one difference: ``[optimize]`` over both radii has one free parameter
(docs/families/delta.md, "Workspace and the GII")."""

import dataclasses

import numpy as np
import pytest

from cad.design import load_design
from cad.kinematics import delta as D

ROOT = __import__("pathlib").Path(__file__).resolve().parents[3]


@pytest.fixture(scope="module")
def design():
    return load_design(ROOT / "designs" / "delta.toml")


def _with(design, R, r):
    m = dataclasses.replace(design.mechanism, base_radius_mm=R, effector_radius_mm=r)
    return dataclasses.replace(design, mechanism=m)


def test_ik_and_jacobian_depend_on_the_radii_only_through_their_difference(design):
    P = design.workspace_points()
    a, b = _with(design, 80.0, 15.0), _with(design, 65.0, 0.0)
    ta, tb = D.ik(a.mechanism, P), D.ik(b.mechanism, P)
    np.testing.assert_allclose(ta.theta_rad, tb.theta_rad, rtol=0, atol=1e-12)
    Ja, _ = D.jacobian_rad_per_m(a.mechanism, P)
    Jb, _ = D.jacobian_rad_per_m(b.mechanism, P)
    np.testing.assert_allclose(Ja, Jb, rtol=1e-12, atol=1e-9)


def test_the_gii_ties_for_one_difference_and_not_for_another(design):
    """R 80 / r 15 and R 70 / r 5 (difference 65 mm) tie; R 60 / r 5 (55 mm) does not."""
    g = {Rr: _with(design, *Rr).gii().gii for Rr in ((80.0, 15.0), (70.0, 5.0), (60.0, 5.0))}
    assert g[(70.0, 5.0)] == pytest.approx(g[(80.0, 15.0)], rel=1e-12)
    assert abs(g[(60.0, 5.0)] - g[(80.0, 15.0)]) > 1e-3
