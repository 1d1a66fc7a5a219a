"""Stability of the dynamics layer where its methods break (issue 7 §3).

Edges: the pseudo-inverse of eq (22) as J = dP/dphi1 -> 0 (threshold
behaviour, never NaN or inf returned), D(phi1) of eq (14) as the coupler and
rocker approach a toggle (sin(phi2 - phi3) -> 0, eq 11), and non-physical
inertia inputs (negative, NaN, infinite masses and inertias; eqs 16-19, 25).

References are independent of the code under test: the transmission angle from
the law of cosines on the triangle A2 A3 A4, |J| from a first-order Taylor
expansion about the singular pose, trace(M) = D / |J|^2 (eq 22 with a 2x1 J).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cad import tolerances as tol
from cad.dynamics.inertia import (
    PAPER_H,
    InertiaCoefficients,
    PlanarLinkInertia,
    apparent_mass_matrix,
    equivalent_inertia,
    h_from_links,
)
from cad.dynamics.stiffness import StiffnessInputs, encoder_resolution_m
from cad.errors import DesignError, HapticadError, SingularJacobianError, ToggleError
from cad.kinematics.families import FAMILIES, family_linkage
from cad.kinematics.fourbar import (
    FourBar,
    jacobian_mm_per_rad,
    solve,
    velocity_ratios,
)

# --------------------------------------------------------------------------- eq (22)

PHI_STAR = 1.0  # rad: the pose where the coupler point is made the instant centre


def _singular_linkage() -> FourBar:
    """A four-bar whose coupler point P is at the coupler's instant centre at PHI_STAR.

    J = l1 e'(phi1) + le a2 e'(phi2 + phi_e) (eq 12) vanishes when
    le a2 e(phi2 + phi_e) = -l1 e(phi1): le = l1 / |a2| and phi_e chosen so the
    two vectors are opposite.
    """
    base = FourBar(20.0, 60.0, 60.0, 0.0, 60.0, 0.0, 0.0, 1)
    p = solve(base, np.array([PHI_STAR]))
    a2 = velocity_ratios(base, p)[0][0]
    le = base.l1_mm / abs(a2)
    phi_e = PHI_STAR + (math.pi if a2 > 0 else 0.0) - p.phi2_rad[0]
    return FourBar(20.0, 60.0, 60.0, 0.0, 60.0, le, phi_e, 1)


FB_SING = _singular_linkage()
FAR = PHI_STAR - 0.2  # a regular pose kept in every batch (the threshold is relative to it)


def test_singular_linkage_really_has_J_zero():
    """Reference check of the construction: |J(phi*)| is round-off (1e-13 of l1)."""
    J = jacobian_mm_per_rad(FB_SING, solve(FB_SING, np.array([PHI_STAR])))
    assert np.linalg.norm(J) < 1e-12 * FB_SING.l1_mm


@pytest.mark.parametrize("k", range(1, 15))
def test_pinv_threshold_along_a_sequence_to_the_singular_pose(k):
    """Eq (22) with phi1 = phi* + 10^-k: returned M is finite and exact (trace = D/|J|^2)
    while |J| / max|J| > PINV_RCOND, and SingularJacobianError names phi1 below it.

    |J| vanishes to first order: |J(phi* + e)| = e |dJ/dphi1(phi*)| + O(e^2), so the
    ratio r = |J| / |J(far)| crosses PINV_RCOND = 1e-9 between e = 1e-9 and 1e-10
    (dJ/dphi1 by central differences at phi*; J is smooth there).
    """
    eps = 10.0 ** (-k)
    phi = np.array([FAR, PHI_STAR + eps])
    pose = solve(FB_SING, phi)
    h = 1e-5
    dJ = (
        jacobian_mm_per_rad(FB_SING, solve(FB_SING, np.array([PHI_STAR + h])))
        - jacobian_mm_per_rad(FB_SING, solve(FB_SING, np.array([PHI_STAR - h])))
    )[0] / (2 * h)
    J_far = np.linalg.norm(jacobian_mm_per_rad(FB_SING, solve(FB_SING, np.array([FAR])))[0])
    r_taylor = eps * np.linalg.norm(dJ) / J_far  # independent of eq (22)'s code path
    if r_taylor > 10 * tol.PINV_RCOND:
        M = apparent_mass_matrix(FB_SING, pose, PAPER_H)
        assert np.all(np.isfinite(M))
        D = equivalent_inertia(FB_SING, pose, PAPER_H)
        J_m = jacobian_mm_per_rad(FB_SING, pose) * 1e-3
        np.testing.assert_allclose(
            np.trace(M, axis1=1, axis2=2), D / np.einsum("ni,ni->n", J_m, J_m), rtol=1e-9
        )
        # M grows like 1/eps^2 towards the singular pose (Taylor: |J| ~ eps |dJ|)
        if k >= 3:
            assert np.trace(M[1]) * eps**2 == pytest.approx(
                D[1] / (np.linalg.norm(dJ) * 1e-3) ** 2, rel=1e-2
            )
    elif r_taylor < 0.1 * tol.PINV_RCOND:
        with pytest.raises(SingularJacobianError) as ei:
            apparent_mass_matrix(FB_SING, pose, PAPER_H)
        msg = str(ei.value)
        assert f"phi1 = {np.degrees(PHI_STAR + eps):.3f} deg" in msg and "\n" not in msg
    else:  # within a factor 10 of the threshold: either outcome, never NaN/inf
        try:
            M = apparent_mass_matrix(FB_SING, pose, PAPER_H)
        except SingularJacobianError:
            return
        assert np.all(np.isfinite(M))


def test_exactly_singular_pose_in_a_batch_is_named():
    """J = 0 to round-off at phi*: SingularJacobianError naming phi* (57.296 deg)."""
    with pytest.raises(SingularJacobianError, match=r"phi1 = 57\.296 deg"):
        apparent_mass_matrix(FB_SING, solve(FB_SING, np.array([FAR, PHI_STAR])), PAPER_H)


@pytest.mark.parametrize("n", [1, 4])
def test_singular_pose_detected_alone_as_in_a_batch(n):
    """Detection must not depend on which other poses are in the batch (here: none)."""
    with pytest.raises(SingularJacobianError):
        apparent_mass_matrix(FB_SING, solve(FB_SING, np.full(n, PHI_STAR)), PAPER_H)


# --------------------------------------------------------------------------- D near toggle

#: l1 = 20, l2 = 40, l3 = 30, A4 = (60, 0): coupler and rocker align (a toggle) where
#: |A2 - A4| = l2 + l3 = 70, i.e. 4000 - 2400 cos(phi1) = 4900.
FB_TOG = FourBar(20.0, 40.0, 30.0, 0.0, 60.0, 40.0, 0.3, 1)
PHI_TOGGLE = math.acos(-0.375)


def _sin_transmission(phi1: float) -> float:
    """|sin(phi2 - phi3)| from the law of cosines on triangle A2 A3 A4 (no eq 3 involved)."""
    a2 = np.array([20.0 * math.cos(phi1), 20.0 * math.sin(phi1)])
    r = float(np.linalg.norm(a2 - np.array([60.0, 0.0])))
    c = (40.0**2 + 30.0**2 - r * r) / (2 * 40.0 * 30.0)
    return math.sqrt(max(0.0, 1.0 - c * c))


DELTAS = [10.0 ** (-k / 2) for k in range(2, 21)]  # 1e-1 ... 1e-10 rad before the toggle


def test_toggle_construction_matches_the_solver():
    """The reference transmission angle equals the solver's sin(phi2 - phi3) (eqs 3, 7-8)."""
    for d in DELTAS[:8]:
        p = solve(FB_TOG, np.array([PHI_TOGGLE - d]))
        assert abs(math.sin(p.phi2_rad[0] - p.phi3_rad[0])) == pytest.approx(
            _sin_transmission(PHI_TOGGLE - d), rel=1e-6
        )


def test_D_blows_up_like_one_over_sin_squared_then_toggle_is_named():
    """Eq (14) with eq (11): a1, a3 ~ 1/sin(phi2 - phi3), so D sin^2 -> const at the toggle.

    Above TOGGLE_SIN D is finite, positive and D sin^2 converges; below it
    equivalent_inertia and apparent_mass_matrix raise ToggleError naming phi1.
    """
    scaled = []
    for d in DELTAS:
        phi = PHI_TOGGLE - d
        s = _sin_transmission(phi)
        pose = solve(FB_TOG, np.array([phi]))
        if s > 1.05 * tol.TOGGLE_SIN:
            D = equivalent_inertia(FB_TOG, pose, PAPER_H)[0]
            assert math.isfinite(D) and D > 0
            scaled.append(D * s * s)
            M = apparent_mass_matrix(FB_TOG, pose, PAPER_H)
            assert np.all(np.isfinite(M))
        elif s < 0.95 * tol.TOGGLE_SIN:
            for f in (equivalent_inertia, apparent_mass_matrix):
                with pytest.raises(ToggleError) as ei:
                    f(FB_TOG, pose, PAPER_H)
                assert f"{math.degrees(phi):.3f}" in str(ei.value)
    assert len(scaled) >= 5
    tail = scaled[-3:]
    assert max(tail) / min(tail) < 1.03  # converged to the 1/sin^2 asymptote
    assert scaled[-1] / scaled[0] != pytest.approx(
        1.0, abs=1e-6
    )  # and it was not constant by design


def test_toggle_inside_a_batch_is_named_with_its_angle():
    """One toggled pose among regular ones: ToggleError quotes that pose's phi1."""
    phis = np.array([PHI_TOGGLE - 0.3, PHI_TOGGLE - 0.1, PHI_TOGGLE - 1e-7])
    with pytest.raises(ToggleError, match=f"{math.degrees(PHI_TOGGLE - 1e-7):.3f}"):
        equivalent_inertia(FB_TOG, solve(FB_TOG, phis), PAPER_H)


# --------------------------------------------------------------------------- inputs


@pytest.mark.parametrize(
    "kwargs",
    [
        dict(mass_kg=-0.01, lG_m=0.01, beta_rad=0.0, Jzz_com_kg_m2=1e-6),
        dict(mass_kg=math.nan, lG_m=0.01, beta_rad=0.0, Jzz_com_kg_m2=1e-6),
        dict(mass_kg=0.01, lG_m=-0.01, beta_rad=0.0, Jzz_com_kg_m2=1e-6),
        dict(mass_kg=0.01, lG_m=0.01, beta_rad=0.0, Jzz_com_kg_m2=-1e-6),
        dict(mass_kg=0.01, lG_m=0.01, beta_rad=0.0, Jzz_com_kg_m2=math.nan),
        pytest.param(
            dict(mass_kg=math.inf, lG_m=0.01, beta_rad=0.0, Jzz_com_kg_m2=1e-6),
        ),
        pytest.param(
            dict(mass_kg=0.01, lG_m=math.inf, beta_rad=0.0, Jzz_com_kg_m2=1e-6),
        ),
        pytest.param(
            dict(mass_kg=0.01, lG_m=0.01, beta_rad=math.nan, Jzz_com_kg_m2=1e-6),
        ),
    ],
)
def test_non_physical_link_inertia_is_a_design_error(kwargs):
    """Eqs (16)-(19) need m >= 0, lG >= 0, J >= 0, all finite, and a finite COM angle."""
    with pytest.raises(DesignError):
        PlanarLinkInertia(**kwargs)


LINK = PlanarLinkInertia(0.02, 0.01, 0.0, 1e-6)


@pytest.mark.parametrize("Jm", [-1e-6, math.nan, math.inf])
def test_rotor_inertia_must_be_finite_and_non_negative(Jm):
    fb, _, _ = family_linkage("hoeken")
    with pytest.raises(DesignError):
        h_from_links(fb, LINK, LINK, LINK, Jm)


@pytest.mark.parametrize(
    ("H", "message"),
    [
        ((-2.97e-5, 3.22e-5, 1.17e-4, 7.09e-5), "inertia.H11_kg_m2: must be >= 0"),
        ((2.97e-5, 3.22e-5, math.nan, 7.09e-5), "inertia.H22_kg_m2: must be finite"),
        ((2.97e-5, math.inf, 1.17e-4, 7.09e-5), "inertia.H12_kg_m2: must be finite"),
    ],
)
def test_non_physical_inertia_coefficients_are_rejected(H, message):
    """Refused where they are made (before eq (14) could return a non-physical D), naming the key."""
    with pytest.raises(HapticadError, match=message):
        InertiaCoefficients(*H)


link = st.builds(
    PlanarLinkInertia,
    st.floats(0.0, 0.5),
    st.floats(0.0, 0.2),
    st.floats(-math.pi, math.pi),
    st.floats(0.0, 1e-3),
)


@settings(max_examples=40, deadline=None)
@given(st.sampled_from(list(FAMILIES)), link, link, link, st.floats(0.0, 1e-4))
def test_D_is_positive_and_finite_for_any_physical_inertia(family, crank, coupler, rocker, Jm):
    """2T = D phi1'^2 (eq 14) is a kinetic energy: D >= 0 over the whole stroke, and
    D > 0 as soon as anything has mass or inertia. Never NaN away from toggles."""
    fb, lo, hi = family_linkage(family)
    D = equivalent_inertia(
        fb, solve(fb, np.linspace(lo, hi, 101)), h_from_links(fb, crank, coupler, rocker, Jm)
    )
    assert np.all(np.isfinite(D))
    total = sum(x.mass_kg + x.Jzz_com_kg_m2 for x in (crank, coupler, rocker)) + Jm
    scale = max(total, 1e-300)
    assert np.all(D >= -1e-12 * scale)
    if Jm > 0 or crank.Jzz_com_kg_m2 > 0 or coupler.mass_kg > 0:
        assert np.all(D > 0)


# --------------------------------------------------------------------------- eq (25)


@pytest.mark.parametrize("field", list(StiffnessInputs.__dataclass_fields__))
@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan])
def test_eq25_inputs_must_be_positive(field, bad):
    """Eq (25) divides by Te and by Delta + xdot Te: zero, negative or NaN inputs are named."""
    vals = dict(
        Fv_N_s_per_m=0.12,
        Fs_N=0.083,
        Te_s=0.33e-3,
        encoder_resolution_m=5.46e-5,
        xdot_max_m_per_s=0.04,
    )
    vals[field] = bad
    with pytest.raises(DesignError, match=f"stiffness.{field}"):
        StiffnessInputs(**vals)


def test_eq25_infinite_input_is_rejected():
    with pytest.raises(DesignError, match="stiffness.xdot_max_m_per_s: must be finite"):
        StiffnessInputs(0.12, 0.083, 0.33e-3, 5.46e-5, math.inf)


@pytest.mark.parametrize("counts", [0, -1000, math.nan])
def test_encoder_counts_must_be_positive(counts):
    with pytest.raises(DesignError, match="stiffness.encoder_counts_per_rev: must be finite and > 0"):
        encoder_resolution_m(counts, 0.05)
