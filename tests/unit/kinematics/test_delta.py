"""Delta kinematics (cad/kinematics/delta.py) against independent references.

References: a closed form of the symmetric pose (all joint angles equal: the effector on the
z axis), a second method (FK by numerical least squares on the sphere equations, scipy),
finite differences of the IK for the Jacobian, virtual work for the statics, and closed-form
constructions of each singularity and of the reach edge (issue 36 §2: "tested at the
failure edges").
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import least_squares

from cad.errors import DesignError, KinematicsError
from cad.kinematics import delta as D

R, r, LA, LB = 60.0, 20.0, 100.0, 200.0
DELTA = D.Delta(R, r, LA, LB, theta_min_rad=-1.0, theta_max_rad=1.4)


def _symmetric_z(theta: float) -> float:
    """Closed form: equal angles put P on the z axis at the lower sphere point."""
    rho = R - r + LA * np.cos(theta)
    return -LA * np.sin(theta) - np.sqrt(LB**2 - rho**2)


@pytest.mark.parametrize("theta", [-0.5, 0.0, 0.3, 0.9, 1.3])
def test_fk_symmetric_pose_matches_closed_form(theta):
    pose = D.fk(DELTA, [theta] * 3)
    assert pose.status[0] == D.STATUS_OK
    np.testing.assert_allclose(pose.P_mm[0], [0, 0, _symmetric_z(theta)], atol=1e-10)


def test_fk_matches_least_squares_and_ik_inverts_it():
    rng = np.random.default_rng(7)
    theta = rng.uniform(-0.4, 1.1, (40, 3))
    pose = D.fk(DELTA, theta)
    assert np.all(pose.ok)
    for t, P in zip(theta, pose.P_mm, strict=True):
        C = DELTA.shifted_elbows_mm(t)
        sol = least_squares(lambda x, C=C: np.linalg.norm(x - C, axis=1) - LB, P + [3, -2, -4],
                            xtol=1e-14, ftol=1e-14, gtol=1e-14)
        np.testing.assert_allclose(sol.x, P, atol=1e-8)
    back = D.ik(DELTA, pose.P_mm)
    np.testing.assert_allclose(back.theta_rad, theta, atol=1e-12)


def test_ik_takes_the_elbow_out_branch():
    P = D.fk(DELTA, [0.2, 0.5, 0.8]).P_mm
    elbow_radius = R + LA * np.cos(D.ik(DELTA, P).theta_rad)
    # the other root of each arm's IK: reflect theta about atan2(B, A)
    for i in range(3):
        u = DELTA.radial[i]
        xp = P[0] @ u - (R - r)
        other = 2 * np.arctan2(-2 * LA * P[0, 2], 2 * LA * xp) - D.ik(DELTA, P).theta_rad[0, i]
        assert elbow_radius[0, i] > R + LA * np.cos(other)


def test_jacobian_matches_finite_differences_of_ik():
    P = D.fk(DELTA, np.random.default_rng(3).uniform(-0.2, 1.0, (10, 3))).P_mm
    J, status = D.jacobian_rad_per_m(DELTA, P)
    assert np.all(status == D.STATUS_OK)
    h = 1e-5
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        dtheta = (D.ik(DELTA, P + e).theta_rad - D.ik(DELTA, P - e).theta_rad) / (2 * h)
        np.testing.assert_allclose(J[:, :, k], dtheta * 1e3, rtol=1e-6, atol=1e-6)


def test_statics_by_virtual_work():
    """tau . dtheta = f . dx for a small displacement (J from the IK, not reused)."""
    P = D.fk(DELTA, [0.1, 0.6, 0.4]).P_mm
    f = np.array([[1.5, -2.0, 4.0]])
    tau = D.joint_torques_Nm(DELTA, P, f)
    dx_mm = np.array([1e-4, 2e-4, -1.5e-4])
    dtheta = D.ik(DELTA, P + dx_mm).theta_rad - D.ik(DELTA, P).theta_rad
    assert tau[0] @ dtheta[0] == pytest.approx(f[0] @ dx_mm * 1e-3, rel=1e-4)


def test_reach_edge_unreachable_just_outside_singular_on_ok_inside():
    """With r = R the shifted bases meet on the z axis, and P = (0, 0, -(L_a + L_b)) has
    every arm fully stretched straight down (serial singular, closed form); 1 ppm farther no
    arm reaches; 1 mm higher every arm is regular."""
    d = D.Delta(40.0, 40.0, LA, LB, theta_min_rad=-2.0, theta_max_rad=2.0)
    at = D.ik(d, [0, 0, -(LA + LB)])
    assert at.status[0] == D.STATUS_SINGULAR_SERIAL
    np.testing.assert_allclose(at.theta_rad[0], [np.pi / 2] * 3, atol=1e-7)
    assert D.ik(d, [0, 0, -(LA + LB) * (1 + 1e-6)]).status[0] == D.STATUS_UNREACHABLE
    assert D.ik(d, [0, 0, -(LA + LB) + 1.0]).status[0] == D.STATUS_OK


def test_parallel_singularity_lower_arms_horizontal():
    """Equal angles with R - r + L_a cos theta = L_b put the three lower arms in one
    horizontal plane: det A_x = 0 (the effector cannot resist a vertical force)."""
    d = D.Delta(150.0, 20.0, 100.0, 200.0, theta_min_rad=-2, theta_max_rad=2)
    theta = np.arccos((200.0 - 150.0 + 20.0) / 100.0)
    C = d.shifted_elbows_mm([theta] * 3)
    P = np.array([0.0, 0.0, C[0, 2]])
    assert D.ik(d, P).status[0] == D.STATUS_SINGULAR_PARALLEL
    J, status = D.jacobian_rad_per_m(d, P)
    assert status[0] == D.STATUS_SINGULAR_PARALLEL and not np.any(J)


def test_parallel_singularity_edge_just_inside_and_just_outside():
    """Both sides of DELTA_PARALLEL_SINGULAR (cad/tolerances.py). On the z axis with equal
    angles the lower arms are w_i = -rho u_i + h z (rho^2 + h^2 = L_b^2, h the effector's
    height above the shifted elbows), so in closed form |det A_x| / L_b^3 = (3 sqrt(3) / 2)
    rho^2 |h| / L_b^3 (the determinant of the rows (cos a_i, sin a_i, 1), a_i = 0, 120,
    240 deg, is 3 sqrt(3) / 2). h at the tolerance, h_edge, from that form; 10 % below it
    the pose is parallel-singular, 10 % above it regular."""
    from cad.tolerances import DELTA_PARALLEL_SINGULAR

    d = D.Delta(150.0, 20.0, 100.0, 200.0, theta_min_rad=-2, theta_max_rad=2)
    k = 3 * np.sqrt(3) / 2
    h_edge = DELTA_PARALLEL_SINGULAR * 200.0**3 / (k * 200.0**2)  # rho = L_b to 1e-15 relative
    for factor, want in ((0.9, D.STATUS_SINGULAR_PARALLEL), (1.1, D.STATUS_OK)):
        h = factor * h_edge
        rho = np.sqrt(200.0**2 - h**2)
        theta = np.arccos((rho - 150.0 + 20.0) / 100.0)
        C = d.shifted_elbows_mm([theta] * 3)
        P = np.array([0.0, 0.0, C[0, 2] + h])  # below the elbows' plane is -z: h > 0 is above
        pose = D.ik(d, P)
        np.testing.assert_allclose(pose.theta_rad[0], [theta] * 3, atol=1e-9)
        A = P - d.shifted_elbows_mm(pose.theta_rad[0])
        assert abs(np.linalg.det(A)) / 200.0**3 == pytest.approx(k * rho**2 * h / 200.0**3, rel=1e-3)
        assert pose.status[0] == want, factor


@pytest.mark.parametrize("side", ["max", "min"])
def test_joint_limit_edge_just_inside_and_just_outside(side):
    """The pose of equal angles theta0 (closed-form FK, :func:`_symmetric_z`) against a limit
    set 1e-9 rad past theta0 (inside: ok) and 1e-9 rad short of it (outside: joint limit); the
    IK returns theta0 to ~1e-13 rad, far below the 1e-9 step."""
    theta0 = 1.35 if side == "max" else -0.95
    P = np.array([0.0, 0.0, _symmetric_z(theta0)])
    np.testing.assert_allclose(D.ik(DELTA, P).theta_rad[0], [theta0] * 3, atol=1e-12)
    for shift, want in ((1e-9, D.STATUS_OK), (-1e-9, D.STATUS_JOINT_LIMIT)):
        if side == "max":
            d = D.Delta(R, r, LA, LB, theta_min_rad=-1.0, theta_max_rad=theta0 + shift)
        else:
            d = D.Delta(R, r, LA, LB, theta_min_rad=theta0 - shift, theta_max_rad=1.4)
        assert D.ik(d, P).status[0] == want, (side, shift)


def test_joint_limits_named_and_refused_in_statics():
    P = D.fk(DELTA, [1.35, 1.35, 1.35]).P_mm
    tight = D.Delta(R, r, LA, LB, theta_min_rad=-1.0, theta_max_rad=1.3)
    assert D.ik(tight, P).status[0] == D.STATUS_JOINT_LIMIT
    with pytest.raises(KinematicsError, match="outside the motor angle range"):
        D.joint_torques_Nm(tight, P, [0, 0, 1])


def test_no_assembly_when_spheres_do_not_meet():
    short = D.Delta(R, r, LA, 30.0)
    assert D.fk(short, [0.0, 0.0, 0.0]).status[0] == D.STATUS_NO_ASSEMBLY


@pytest.mark.parametrize("field,kwargs", [
    ("delta.upper_arm_mm", dict(upper_arm_mm=0.0)),
    ("delta.effector_radius_mm", dict(effector_radius_mm=-1.0)),
    ("delta.theta_max_rad", dict(theta_min_rad=1.0, theta_max_rad=0.5)),
])
def test_bad_parameters_name_the_field(field, kwargs):
    args = dict(base_radius_mm=R, effector_radius_mm=r, upper_arm_mm=LA, lower_arm_mm=LB)
    args.update(kwargs)
    with pytest.raises(DesignError) as err:
        D.Delta(**args)
    assert err.value.field == field


def test_box_grid_and_gii_of_symmetric_point_is_isotropic():
    """On the z axis the symmetric delta's J is, by its 3-fold symmetry, sigma-equal in x
    and y; the GII over a single axis point is sigma_min / sigma_max of that J (eq 5)."""
    from cad.isotropy.gii import delta_gii

    P = D.fk(DELTA, [0.6] * 3).P_mm
    J, _ = D.jacobian_rad_per_m(DELTA, P)
    s = np.linalg.svd(J[0], compute_uv=False)
    res = delta_gii(DELTA, P)
    assert res.gii == pytest.approx(s[-1] / s[0], rel=1e-12)
    # 3-fold symmetry: J^T J is diag(a, a, c) on the axis
    JTJ = J[0].T @ J[0]
    assert JTJ[0, 0] == pytest.approx(JTJ[1, 1], rel=1e-12)
    assert abs(JTJ[0, 1]) < 1e-9 * JTJ[0, 0]
    ratio, status = D.inverse_condition(DELTA, P)
    assert ratio[0] == pytest.approx(res.gii, rel=1e-12) and status[0] == D.STATUS_OK


def test_box_grid_faces_and_gii_names_an_unreachable_corner():
    from cad.isotropy.gii import delta_gii

    z0 = D.fk(DELTA, [0.6] * 3).P_mm[0, 2]
    pts = D.box_grid_mm([0, 0, z0], [40, 40, 30], 3)
    assert pts.shape == (27, 3)
    np.testing.assert_allclose(pts.min(axis=0), [-20, -20, z0 - 15])
    assert delta_gii(DELTA, pts).gii > 0
    far = D.box_grid_mm([0, 0, z0], [600, 600, 30], 3)
    res = delta_gii(DELTA, far)
    assert res.gii == 0 and "unreachable" in res.failure
    cyl = D.cylinder_grid_mm([0, 0, z0], 40.0, 20.0, 3)
    assert cyl.shape == (3 * (1 + 6 + 12), 3)
    assert np.max(np.hypot(cyl[:, 0], cyl[:, 1])) == pytest.approx(20.0)
    with pytest.raises(DesignError, match="workspace.size_mm"):
        D.box_grid_mm([0, 0, z0], [40, 0, 30], 3)


def test_delta_problem_culling_equals_brute_force_and_per_candidate_gii():
    """The culling optimizer (exact by construction) against brute force and against the
    GII of each candidate computed on its own (delta_gii, the scalar path)."""
    from cad.isotropy.culling import optimize
    from cad.isotropy.gii import delta_gii
    from cad.isotropy.problems import DeltaProblem, candidate_grid

    z0 = D.fk(DELTA, [0.6] * 3).P_mm[0, 2]
    pts = D.box_grid_mm([0, 0, z0], [60, 60, 40], 3)
    ranges = {"upper_arm_mm": (70.0, 130.0, 4), "lower_arm_mm": (170.0, 240.0, 4)}
    names, params = candidate_grid(ranges, {"base_radius_mm": R, "effector_radius_mm": r})
    prob = DeltaProblem(params, pts, (3, 3, 3), DELTA)
    cull, brute = optimize(prob, "culling"), optimize(prob, "brute")
    assert cull.best_index == brute.best_index and cull.gii == brute.gii
    scalar = [delta_gii(D.Delta(R, r, params["upper_arm_mm"][k], params["lower_arm_mm"][k],
                                theta_min_rad=-1.0, theta_max_rad=1.4), pts).gii
              for k in range(prob.n_candidates)]
    np.testing.assert_allclose(brute.gii_all, scalar, rtol=1e-12)
    assert cull.gii == pytest.approx(max(scalar), rel=1e-12) and max(scalar) > 0
