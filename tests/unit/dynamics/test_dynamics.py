"""Dynamics: D(phi1) (eq 14) against kinetic energy, apparent mass (eq 22, Fig. 6), eq (25)."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from cad.dynamics.inertia import (
    PAPER_H,
    PlanarLinkInertia,
    apparent_mass_matrix,
    apparent_mass_summary,
    equivalent_inertia,
    h_from_links,
)
from cad.dynamics.stiffness import StiffnessInputs, stiffness_range_N_per_m
from cad.errors import SingularJacobianError
from cad.kinematics.families import FAMILIES, family_linkage
from cad.kinematics.fourbar import FourBar, solve
from cad.kinematics.linkgeom import tf_world_link
from cad.kinematics.metrics import path_frame


def test_paper_H_gives_fig6_apparent_mass():
    """§III.B.2 / Fig. 6: with H11..H33 from the paper's CAD, M11 spans 27.5..42.8 g,
    M12 0.5..-0.4 g and M22 is very small."""
    fb, lo, hi = family_linkage("hoeken")
    pose = solve(fb, np.linspace(lo, hi, 2001))
    am = apparent_mass_summary(apparent_mass_matrix(fb, pose, PAPER_H, path_frame(fb, lo, hi)))
    assert am["M11_min_g"] == pytest.approx(27.5, rel=0.01)
    assert am["M11_max_g"] == pytest.approx(42.8, rel=0.01)
    assert am["M12_max_g"] == pytest.approx(0.5, abs=0.1)
    assert am["M12_min_g"] == pytest.approx(-0.4, abs=0.1)
    assert am["M22_max_g"] < 0.05


def _kinetic_energy_two_ways(fb, links, Jm, phi1):
    """2T / phi1'^2 from each posed link's velocity, by finite differences of the pose."""
    h = 1e-6
    phis = np.array([phi1 - h, phi1, phi1 + h])
    pose = solve(fb, phis)
    two_T = Jm  # rotor spins at phi1'
    for name, li in links.items():
        tf = tf_world_link(fb, pose, name)  # (3,3,3) mm
        com = np.array([li.lG_m * math.cos(li.beta_rad), li.lG_m * math.sin(li.beta_rad), 1e-3]) * 1e3
        g = tf @ np.array([com[0], com[1], 1.0])  # mm
        v = (g[2, :2] - g[0, :2]) / (2 * h) * 1e-3  # m/rad
        ang = np.arctan2(tf[:, 1, 0], tf[:, 0, 0])
        w = (np.unwrap(ang)[2] - np.unwrap(ang)[0]) / (2 * h)
        two_T += li.mass_kg * (v @ v) + li.Jzz_com_kg_m2 * w * w
    return two_T


link_inertia = st.builds(
    PlanarLinkInertia,
    st.floats(0.005, 0.2), st.floats(0.0, 0.12), st.floats(-math.pi, math.pi), st.floats(1e-7, 1e-4),
)


@given(st.sampled_from(list(FAMILIES)), link_inertia, link_inertia, link_inertia,
       st.floats(0.0, 1e-5), st.floats(0.05, 0.95))
def test_D_equals_twice_kinetic_energy(family, crank, coupler, rocker, Jm, frac):
    """Eq (14) generalized with the coupler COM angle equals 2T computed from each posed
    link's velocity (finite differences of the posed links), to 1e-6 relative."""
    fb, lo, hi = family_linkage(family)
    phi = lo + frac * (hi - lo)
    H = h_from_links(fb, crank, coupler, rocker, Jm)
    D = equivalent_inertia(fb, solve(fb, np.array([phi])), H)[0]
    ref = _kinetic_energy_two_ways(fb, {"crank": crank, "coupler": coupler, "rocker": rocker}, Jm, phi)
    assert D == pytest.approx(ref, rel=1e-6)


def test_zero_offset_reduces_to_paper_eq16_19():
    fb, _, _ = family_linkage("hoeken")
    m1, m2, m3, lg1, lg2, lg3, J1, J2, J3, Jm = 0.02, 0.05, 0.03, 0.01, 0.06, 0.03, 1e-6, 5e-5, 1e-5, 6.5e-6
    H = h_from_links(fb, PlanarLinkInertia(m1, lg1, 0.0, J1), PlanarLinkInertia(m2, lg2, 0.0, J2),
                     PlanarLinkInertia(m3, lg3, 0.0, J3), Jm)
    l1 = fb.l1_mm * 1e-3
    assert H.H11_kg_m2 == pytest.approx(m1 * lg1**2 + m2 * l1**2 + Jm + J1, rel=1e-15)
    assert H.H22_kg_m2 == pytest.approx(m2 * lg2**2 + J2, rel=1e-15)
    assert H.H33_kg_m2 == pytest.approx(m3 * lg3**2 + J3, rel=1e-15)
    assert H.H12_kg_m2 == pytest.approx(m2 * l1 * lg2, rel=1e-15)
    assert H.beta2_rad == 0.0


def test_apparent_mass_is_kinetic_energy_in_operational_space():
    """Eq (21): T = 1/2 v^T M v with v = J phi1' equals 1/2 D phi1'^2."""
    fb, lo, hi = family_linkage("roberts")
    pose = solve(fb, np.linspace(lo, hi, 7))
    fr = path_frame(fb, lo, hi)
    M = apparent_mass_matrix(fb, pose, PAPER_H, fr)
    from cad.kinematics.fourbar import jacobian_mm_per_rad

    v = fr.rotate(jacobian_mm_per_rad(fb, pose)) * 1e-3
    lhs = np.einsum("ni,nij,nj->n", v, M, v)
    assert np.allclose(lhs, equivalent_inertia(fb, pose, PAPER_H), rtol=1e-12)


def test_singular_jacobian_is_named():
    """A coupler point at the crank pivot's image... J = 0 where P is momentarily at rest."""
    fb = FourBar(20.0, 60.0, 60.0, 0.0, 60.0, 0.0, 0.0, 1)  # P = A2: J = l1 * (-sin, cos) never 0
    pose = solve(fb, np.array([0.5, 1.0]))
    apparent_mass_matrix(fb, pose, PAPER_H)  # fine
    # le chosen so that P is at the instant centre of the coupler at phi1 = phi*: J(phi*) = 0
    from cad.kinematics.fourbar import velocity_ratios

    phi = 1.0
    p = solve(fb, np.array([phi]))
    a2, _ = velocity_ratios(fb, p)
    # J = l1 e1' + le a2 e(phi2+phi_e)' = 0  <=>  le a2 e(phi2 + phi_e) = -l1 e(phi1)
    le = fb.l1_mm / abs(a2[0])
    phi_e = (phi + (math.pi if a2[0] > 0 else 0.0)) - p.phi2_rad[0]
    fb2 = FourBar(20.0, 60.0, 60.0, 0.0, 60.0, le, phi_e, 1)
    with pytest.raises(SingularJacobianError, match="phi1 ="):
        apparent_mass_matrix(fb2, solve(fb2, np.array([0.9, phi, 1.1])), PAPER_H)


def test_eq25_stiffness_range_paper():
    """§III.B.4: Te = 0.33 ms, Delta = 5.46e-5 m, xdot_max = 0.04 m/s, Fv = 0.12, Fs = 8.3e-2
    give a theoretical stiffness of about 2500 N/m."""
    kmin, kmax = stiffness_range_N_per_m(StiffnessInputs(0.12, 0.083, 0.33e-3, 5.46e-5, 0.04))
    assert kmax == pytest.approx(2500, rel=0.05)
    assert kmin == pytest.approx(2 * 0.12 / 0.33e-3, rel=1e-12)
