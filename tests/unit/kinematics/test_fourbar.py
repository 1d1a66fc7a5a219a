"""Four-bar kinematics: Hoeken paper eqs (1)-(12), and where they break."""

import math

import numpy as np
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from cad import tolerances as tol
from cad.errors import BranchJumpError, ClosureError, DesignError, ToggleError
from cad.kinematics.families import family_linkage
from cad.kinematics.fourbar import (
    FourBar,
    abc,
    check_range,
    closure_margin,
    jacobian_mm_per_rad,
    loop_residual_mm,
    phi2_tan_half,
    require_range,
    solve,
    tan_half_breakdown,
    velocity_ratios,
)

lengths = st.floats(10.0, 150.0)


@st.composite
def closing_linkages(draw):
    """Random linkages with a crank angle where the loop closes away from toggles."""
    fb = FourBar(draw(lengths), draw(lengths), draw(lengths), draw(st.floats(-50, 50)),
                 draw(st.floats(10, 150)), draw(st.floats(0, 200)), draw(st.floats(-3, 3)),
                 draw(st.sampled_from([1, -1])))
    phi = draw(st.floats(0, 2 * math.pi))
    m = closure_margin(fb, np.array([phi]))[0]
    assume(m > 1e-3)
    return fb, phi


@given(closing_linkages())
def test_loop_closure_residual(case):
    """Eqs (1)-(2) hold to < 1e-9 mm at any closing configuration."""
    fb, phi = case
    pose = solve(fb, np.array([phi]))
    assert loop_residual_mm(fb, pose)[0] < tol.CLOSURE_RESIDUAL_MM
    # the joint distances are the link lengths
    assert np.linalg.norm(pose.A3_mm[0] - pose.A2_mm[0]) == pytest.approx(fb.l2_mm, rel=1e-12)
    assert np.linalg.norm(pose.A3_mm[0] - fb.A4_mm) == pytest.approx(fb.l3_mm, rel=1e-12)


@given(closing_linkages())
def test_jacobian_matches_central_differences(case):
    """Eq (12) closed form against central differences of eqs (9)-(10)."""
    fb, phi = case
    pose = solve(fb, np.array([phi]))
    assume(abs(math.sin(pose.phi2_rad[0] - pose.phi3_rad[0])) > 0.05)
    h = tol.FD_STEP_RAD
    assume(closure_margin(fb, np.array([phi - h, phi + h])).min() > 1e-4)
    P = solve(fb, np.array([phi - h, phi + h])).P_mm
    fd = (P[1] - P[0]) / (2 * h)
    J = jacobian_mm_per_rad(fb, pose)[0]
    scale = max(np.linalg.norm(J), 1.0)
    assert np.allclose(J, fd, atol=1e-5 * scale, rtol=0)


@given(closing_linkages())
def test_velocity_ratios_match_differences(case):
    """Eq (11) against central differences of phi2 and phi3."""
    fb, phi = case
    pose = solve(fb, np.array([phi]))
    assume(abs(math.sin(pose.phi2_rad[0] - pose.phi3_rad[0])) > 0.05)
    h = 1e-6
    assume(closure_margin(fb, np.array([phi - h, phi + h])).min() > 1e-4)
    p = solve(fb, np.array([phi - h, phi, phi + h]))
    a2, a3 = velocity_ratios(fb, pose)
    assert a2[0] == pytest.approx((p.phi2_rad[2] - p.phi2_rad[0]) / (2 * h), abs=1e-5 * (1 + abs(a2[0])))
    assert a3[0] == pytest.approx((p.phi3_rad[2] - p.phi3_rad[0]) / (2 * h), abs=1e-5 * (1 + abs(a3[0])))


def test_branches_are_the_two_roots_of_eq3():
    """Both assembly modes satisfy A cos phi2 + B sin phi2 = C and equal eq (3)'s two roots."""
    fb, lo, hi = family_linkage("hoeken")
    phi = np.linspace(lo, hi, 50)
    A, B, C = abc(fb, phi)
    roots = []
    for b in (1, -1):
        p2 = solve(FourBar(*[getattr(fb, f) for f in ("l1_mm", "l2_mm", "l3_mm", "l4_mm", "l5_mm",
                                                       "le_mm", "phi_e_rad")], b), phi).phi2_rad
        assert np.allclose(A * np.cos(p2) + B * np.sin(p2), C, atol=1e-9 * np.hypot(A, B).max())
        roots.append(np.mod(p2, 2 * np.pi))
    th = [np.mod(phi2_tan_half(fb, phi, s), 2 * np.pi) for s in (1, -1)]
    # same unordered pair of roots
    ours = np.sort(np.stack(roots), axis=0)
    ref = np.sort(np.stack(th), axis=0)
    assert np.allclose(ours, ref, atol=1e-9)


def test_tan_half_form_breaks_at_A_plus_C_zero():
    """Eq (3) divides by A + C: at A + C = 0 one root is 0/0 (NaN); the atan2 form is exact there.

    For l4 = 0, A + C = 0 where cos(phi1) = ((l2+l5)^2 + l1^2 - l3^2) / (2 l1 (l2+l5)).
    """
    l1, l2, l3, l5 = 30.0, 40.0, 90.0, 60.0
    phi0 = math.acos(((l2 + l5) ** 2 + l1**2 - l3**2) / (2 * l1 * (l2 + l5)))
    fb = FourBar(l1, l2, l3, 0.0, l5, 40.0, 0.3, 1)
    A, B, C = abc(fb, np.array([phi0]))
    assert abs(A[0] + C[0]) < 1e-9 * math.hypot(A[0], B[0])
    assert closure_margin(fb, np.array([phi0]))[0] > 0.2  # the loop closes comfortably there
    assert tan_half_breakdown(fb, np.array([phi0]))[0]

    def residual(phi, sign):
        A, B, C = abc(fb, np.array([phi]))
        with np.errstate(all="ignore"):
            x = phi2_tan_half(fb, np.array([phi]), sign)[0]
        if not np.isfinite(x):
            return math.inf
        return abs(A[0] * math.cos(x) + B[0] * math.sin(x) - C[0]) / math.hypot(A[0], B[0])

    # approaching A + C = 0 the lost root's error grows like eps / |A + C|
    errs = [residual(phi0 + d, -1) for d in (1e-4, 1e-8, 1e-12)]
    assert errs[0] < 1e-9 < errs[2]
    assert errs[2] > 1e-6
    # the atan2 form stays exact at the same angles
    for d in (1e-4, 1e-8, 1e-12):
        assert loop_residual_mm(fb, solve(fb, np.array([phi0 + d])))[0] < tol.CLOSURE_RESIDUAL_MM
    for b in (1, -1):
        fbb = FourBar(l1, l2, l3, 0.0, l5, 40.0, 0.3, b)
        pose = solve(fbb, np.array([phi0]))
        assert loop_residual_mm(fbb, pose)[0] < tol.CLOSURE_RESIDUAL_MM


def test_closure_failure_is_named_with_phi1():
    fb = FourBar(60.0, 20.0, 20.0, 0.0, 50.0, 10.0, 0.0, 1)  # crank too long: cannot close everywhere
    with pytest.raises(ClosureError, match=r"phi1 in \["):
        solve(fb, np.linspace(0, 2 * np.pi, 100))
    rc = check_range(fb, 0.0, 2 * np.pi - 0.01)
    assert not rc.closes and rc.closure_gap_deg is not None
    with pytest.raises(ClosureError):
        require_range(fb, 0.0, 2 * np.pi - 0.01)


def test_toggle_inside_range_is_detected_with_its_angle():
    """l1 = 40, l2 = 30, l3 = 40, l5 = 50: at phi1 = 0 the crank pin A2 is l5 - l1 = 10 mm from
    A4 = l3 - l2, so coupler and rocker fold onto one line (a toggle, sin(phi2 - phi3) = 0);
    the loop closes for |phi1| <= acos(-0.2) = 101.537 deg (|A2A4| = l2 + l3 there). Over
    [-100, 100] deg: it closes, and the toggle is found at phi1 = 0 to the sampling step."""
    fb = FourBar(25.0, 62.5, 62.5, 0.0, 50.0, 125.0, 0.0, -1)
    # the Hoeken crank-rocker is Grashof: no coupler/rocker toggle in 360 deg
    assert check_range(fb, 0.0, 2 * np.pi - 1e-3).toggle_at_deg is None
    fb2 = FourBar(40.0, 30.0, 40.0, 0.0, 50.0, 10.0, 0.0, 1)
    full = check_range(fb2, 0.0, 2 * np.pi, samples=20001)
    assert full.closure_gap_deg[0] == pytest.approx(math.degrees(math.acos(-0.2)), abs=0.02)
    lo, hi, n = math.radians(-100.0), math.radians(100.0), 2000  # 0 deg falls between samples
    rc = check_range(fb2, lo, hi, samples=n)
    assert rc.closes and rc.closure_gap_deg is None and rc.branch_jump_at_deg is None
    assert abs(rc.toggle_at_deg) <= 200.0 / (n - 1)
    with pytest.raises(ToggleError, match=r"toggle inside the range at phi1 = -0\.050 deg"):
        require_range(fb2, lo, hi, samples=n)


def test_velocity_ratio_raises_at_toggle():
    fb = FourBar(40.0, 30.0, 40.0, 0.0, 50.0, 10.0, 0.0, 1)
    phi = np.linspace(0, 2 * np.pi, 20001)
    m = closure_margin(fb, phi)
    k = int(np.argmin(np.where(m >= 0, m, np.inf)))  # closable sample closest to a toggle
    pose = solve(fb, phi[k:k + 1])
    assert abs(math.sin(pose.phi2_rad[0] - pose.phi3_rad[0])) < tol.TOGGLE_SIN
    with pytest.raises(ToggleError, match="phi1 ="):
        velocity_ratios(fb, pose)


def test_branch_jump_across_unsampled_gap():
    """Samples that straddle a closure gap narrower than the step: every sample closes but phi2
    jumps between branches; check_range names it. (l1 + l5 > l2 + l3: the loop cannot close
    for phi1 in about 177.57..182.43 deg.)"""
    fb = FourBar(40.02, 30.0, 60.0, 0.0, 50.0, 10.0, 0.0, 1)
    lo, hi = math.radians(165.0), math.radians(195.0)
    grid = np.linspace(lo, hi, 4)  # 165, 175, 185, 195 deg: none inside the gap
    assert (closure_margin(fb, grid) >= 0).all()
    rc = check_range(fb, lo, hi, samples=4)
    assert rc.closes and rc.toggle_at_deg is None
    assert rc.branch_jump_at_deg == pytest.approx(165.0)  # the jump lies between 165 and 185 deg
    with pytest.raises(BranchJumpError, match="between phi1 = 165.000 and 185.000 deg"):
        require_range(fb, lo, hi, samples=4)
    dense = check_range(fb, lo, hi, samples=20001)
    assert not dense.closes
    # closed form: |A2A4| = l2 + l3 at cos(phi1) = (l1^2 + l5^2 - (l2 + l3)^2) / (2 l1 l5)
    edge = math.degrees(math.acos((40.02**2 + 50.0**2 - 90.0**2) / (2 * 40.02 * 50.0)))
    assert dense.closure_gap_deg[0] == pytest.approx(edge, abs=0.01)  # 177.57
    assert dense.closure_gap_deg[1] == pytest.approx(360.0 - edge, abs=0.01)


@pytest.mark.parametrize(
    "kwargs, field",
    [({"l1_mm": 0.0}, "l1_mm"), ({"l3_mm": -1.0}, "l3_mm"), ({"branch": 0}, "branch"),
     ({"le_mm": -2.0}, "le_mm"), ({"l2_mm": float("nan")}, "l2_mm")],
)
def test_invalid_linkages_name_the_field(kwargs, field):
    base = dict(l1_mm=25.0, l2_mm=62.5, l3_mm=62.5, l4_mm=0.0, l5_mm=50.0, le_mm=125.0,
                phi_e_rad=0.0, branch=1)
    base.update(kwargs)
    with pytest.raises(DesignError, match=field):
        FourBar(**base)


@given(closing_linkages())
def test_fused_point_and_jacobian_equal_separate(case):
    from cad.kinematics.fourbar import coupler_point_and_jacobian

    fb, phi = case
    pose = solve(fb, np.array([phi]))
    assume(abs(math.sin(pose.phi2_rad[0] - pose.phi3_rad[0])) > 0.05)
    P, J = coupler_point_and_jacobian(fb, np.array([phi]))
    assert np.allclose(P, pose.P_mm, atol=1e-9)
    Jref = jacobian_mm_per_rad(fb, pose)
    assert np.allclose(J, Jref, atol=1e-9 * (1 + np.abs(Jref).max()))
