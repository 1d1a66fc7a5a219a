"""The Novint Falcon's geometry (designs/delta_falcon.toml) against Stamper's model.

Reference: the inverse kinematics of R. E. Stamper's thesis (U. Maryland 1997) in the form
the open driver libnifalcon states it (its InverseKinematic: theta_3 = acos((p_v + f) / b),
then the half-angle root of l_0 + l_1 t + l_2 t^2 = 0 for theta_1), written out here from
those equations with the driver's constants (FalconGeometry.h), in the driver's frame
(w = -z). And the published workspace: Novint's 4 x 4 x 4 in cube.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cad.design import load_design
from cad.kinematics import delta as D

ROOT = Path(__file__).resolve().parents[3]
# FalconGeometry.h (libnifalcon), in mm
A, B, C, DD, E, F, R, S = 60.0, 102.5, 14.0, 11.25, 11.25, -25.0, 37.233758, -27.330909
PHY = (np.pi / 2 + np.pi / 12, -np.pi / 6 + np.pi / 12, -5 * np.pi / 6 + np.pi / 12)
INCH_MM = 25.4


def _stamper_theta1(P: np.ndarray) -> np.ndarray:
    x, y, w = P[0], P[1], -P[2]
    out = []
    for ph in PHY:
        pu = -R + np.cos(ph) * x + np.sin(ph) * y
        pv = -(S - np.cos(ph) * y + np.sin(ph) * x)
        s3 = np.sin(np.arccos((pv + F) / B))
        common = (w * w + pu * pu + 2 * C * pu + A * A + C * C - DD * DD - E * E - B * B * s3 * s3
                  - 2 * B * E * s3 - 2 * B * DD * s3 - 2 * DD * E)
        l0, l1, l2 = common - 2 * A * pu - 2 * A * C, -4 * A * w, common + 2 * A * pu + 2 * A * C
        t = -(np.sqrt(l1 * l1 - 4 * l2 * l0) + l1) / (2 * l2)
        out.append(2 * np.arctan(t))
    return np.array(out)


def test_bundled_falcon_is_stampers_geometry():
    d = load_design(ROOT / "designs" / "delta_falcon.toml").mechanism
    rng = np.random.default_rng(5)
    pts = np.column_stack([rng.uniform(-40, 40, 60), rng.uniform(-40, 40, 60),
                           rng.uniform(-150, -80, 60)])
    pose = D.ik(d, pts)
    assert np.all(pose.ok)
    for P, theta in zip(pts, pose.theta_rad, strict=True):
        np.testing.assert_allclose(theta, _stamper_theta1(P), atol=1e-12)


def test_fk_with_joint_offsets_inverts_ik_and_jacobian_matches_differences():
    d = load_design(ROOT / "designs" / "delta_falcon.toml").mechanism
    theta = np.random.default_rng(9).uniform(-0.3, 1.0, (100, 3))
    pose = D.fk(d, theta)
    assert np.all(pose.ok)
    np.testing.assert_allclose(D.ik(d, pose.P_mm).theta_rad, theta, atol=1e-10)
    P = pose.P_mm[:8]
    J, _ = D.jacobian_rad_per_m(d, P)
    h = 1e-5
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        fd = (D.ik(d, P + e).theta_rad - D.ik(d, P - e).theta_rad) / (2 * h) * 1e3
        np.testing.assert_allclose(J[:, :, k], fd, rtol=1e-6, atol=1e-6)


def test_published_four_inch_cube_is_not_fully_reachable():
    """Novint's 4 in cube is not reached by this geometry on the axis: the largest cube is
    91.8 mm (regression pin of our bisection, 0.1 mm steps), and the 4 in cube about that
    centre has unreachable samples, named."""
    d = load_design(ROOT / "designs" / "delta_falcon.toml").mechanism
    best = D.largest_cube_mm(d, (-200.0, -60.0))
    assert best["side_mm"] == pytest.approx(91.8, abs=0.2)
    assert best["center_z_mm"] == pytest.approx(-111.0, abs=1.0)
    assert best["side_mm"] < 4 * INCH_MM
    pts = D.box_grid_mm([0, 0, best["center_z_mm"]], [4 * INCH_MM] * 3, 5)
    pose = D.ik(d, pts)
    assert not np.all(pose.ok) and "unreachable" in pose.describe(int(np.flatnonzero(~pose.ok)[0]))
    inside = D.box_grid_mm([0, 0, best["center_z_mm"]], [best["side_mm"]] * 3, 9)
    assert np.all(D.ik(d, inside).ok)


def test_datasheet_force_and_notes_with_the_default_motor():
    """The Falcon states no motor: the datasheet's force is the resolved default's (the
    catalog's maxon RE 35), by the force row's own model checked against sampled force
    directions, and the notes say the motor is not the Falcon's and set the workspace and
    force beside Novint's figures (the force unknown: no source found)."""
    from cad.device import resolve_device
    from cad.families.delta.datasheet import force_in_every_direction_N, published_notes

    des = load_design(ROOT / "designs" / "delta_falcon.toml")
    dev = resolve_device(des)
    assert dev.motor.spec.key == "maxon-re35"
    tc = dev.motor.spec.torque_continuous_mNm * 1e-3
    fc, at = force_in_every_direction_N(des, tc)
    # sampled directions: the torque each needs at the worst point, |tau|_2 at the limit
    rng = np.random.default_rng(3)
    u = rng.normal(size=(4000, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    t = D.joint_torques_Nm(des.mechanism, np.repeat(np.asarray(at)[None], len(u), 0), u)
    sampled = float(np.min(tc / np.linalg.norm(t, axis=1)))
    assert sampled >= fc * (1 - 1e-12) and sampled == pytest.approx(fc, rel=2e-3)
    assert fc == pytest.approx(0.4726, abs=5e-4)  # N, regression pin (RE 35, 90 mm cube)
    notes = published_notes(des, dev, fc, 10 * fc)
    assert any(n.startswith("motors: the design states none") and dev.motor.name in n for n in notes)
    falcon = [n for n in notes if n.startswith("Novint Falcon geometry")]
    assert len(falcon) == 1 and "101.6 mm (4 in) cube" in falcon[0] and "91.8 mm" in falcon[0]
    assert "not the Falcon's motors" in falcon[0] and "Novint's force: unknown" in falcon[0]
    # a design with its own motor and another geometry gets neither note
    other = load_design(ROOT / "designs" / "delta.toml")
    assert published_notes(other, resolve_device(other), 1.0, 2.0) == []
