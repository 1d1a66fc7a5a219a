"""The capstan transmission model (cad.actuators.capstan) against independent references:
the capstan equation integrated as its ODE dT/dtheta = mu T (scipy solve_ivp, a second method
to the closed form), two springs in series against the static deflections adding up, the
cable's torsional spring against the second derivative of the runs' elastic energy, the
reflected inertia against the rotor's kinetic energy, and hand numbers for issue 35 §6
(a WoodenHaptics-class joint: 10 mm capstan, 0.54 mm 7x7 rope, D/d = 18.5)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from cad.actuators import capstan as cap
from cad.data.cables import CABLES, WOODENHAPTICS_SOURCE, get_cable
from cad.errors import DesignError


# ------------------------------------------------------------------ ratio and scaling
def test_ratio_and_torque_scaling_hand_numbers():
    # WoodenHaptics default_woody(): 10 mm capstan, 160 mm drum -> n = 16
    n = cap.ratio(10.0, 160.0)
    assert n == pytest.approx(16.0)
    assert cap.joint_torque_Nm(0.05, n) == pytest.approx(0.8)
    assert cap.motor_torque_Nm(0.8, n) == pytest.approx(0.05)
    # dT = tau_q / r_d = 0.8 / 0.08 = 10 N; and on the capstan dT * r_c = tau_m
    dT = cap.cable_tension_difference_N(0.8, 160.0)
    assert dT == pytest.approx(10.0)
    assert dT * 0.005 == pytest.approx(0.05)


def test_reflected_inertia_equals_the_rotor_kinetic_energy():
    """n^2 J_m: the rotor's kinetic energy J_m (n qdot)^2 / 2 seen as (J qdot^2)/2 at the joint."""
    J_m = 79.2e-7  # the catalog RE 35 rotor, 79.2 g cm^2
    n, qdot = 12.0, 0.7
    J = cap.reflected_inertia_kg_m2(J_m, n)
    assert J == pytest.approx(144 * 79.2e-7)  # 1.1405e-3 kg m^2 by hand
    assert 0.5 * J * qdot**2 == pytest.approx(0.5 * J_m * (n * qdot) ** 2)


def test_add_reflected_inertia_on_the_diagonal_and_into_lambda():
    rng = np.random.default_rng(35)
    A = rng.normal(size=(5, 2, 2))
    M = A @ np.swapaxes(A, -1, -2) * 1e-3 + np.eye(2) * 1e-4  # SPD over 5 poses
    n, J = np.array([8.0, 12.0]), np.array([1e-6, 2e-6])
    out = cap.add_reflected_inertia(M, n, J)
    assert out.shape == M.shape
    np.testing.assert_allclose(out - M, np.broadcast_to(np.diag([64e-6, 288e-6]), M.shape))
    # kinetic energy two ways: links' qdot^T M qdot plus each rotor's J (n qdot)^2
    qd = rng.normal(size=2)
    ke_links = np.einsum("i,pij,j->p", qd, M, qd) / 2
    ke_rotors = 0.5 * np.sum(J * (n * qd) ** 2)
    np.testing.assert_allclose(np.einsum("i,pij,j->p", qd, out, qd) / 2, ke_links + ke_rotors)
    # Lambda = J^-T M J^-1 picks up J^-T diag(n^2 J_m) J^-1 (one Jacobian, by hand)
    Jac = np.array([[0.1, 0.02], [-0.03, 0.08]])
    Ji = np.linalg.inv(Jac)
    lam = Ji.T @ out[0] @ Ji
    np.testing.assert_allclose(lam - Ji.T @ M[0] @ Ji, Ji.T @ np.diag(n**2 * J) @ Ji, atol=1e-15)


def test_direct_drive_joint_adds_the_bare_rotor():
    M = np.array([[2e-3]])
    assert cap.add_reflected_inertia(M, [1.0], [79.2e-7])[0, 0] == pytest.approx(2e-3 + 79.2e-7)


def test_reflected_friction_scales_like_torque():
    # RE 35 friction Kt I0 = 38.9 mN m/A * 0.126 A = 4.90 mN m; at n = 12: 58.8 mN m
    assert cap.reflected_friction_Nm(38.9e-3 * 0.126, 12.0) == pytest.approx(0.0588168)


# ------------------------------------------------------------------ bend ratio (issue 35 §6)
def test_woodenhaptics_joint_warns_at_d_over_d_18_5_and_names_the_fix():
    assert "default_woody" in WOODENHAPTICS_SOURCE
    rope = get_cable("steel-7x7-0.54")
    assert float(cap.bend_ratio(10.0, 0.54)) == pytest.approx(18.518, abs=1e-3)
    w = cap.bend_ratio_warning(rope, 10.0)
    assert w is not None
    assert "steel-7x7-0.54" in w and "D/d = 18.5" in w and "minimum 40" in w
    # the fixes: a capstan of 40 * 0.54 = 21.6 mm, or a 7x19 rope at D/d >= 26 (14.0 mm)
    assert "at least 21.6 mm" in w and "7x19" in w and "14.0 mm" in w
    assert "\n" not in w


def test_no_warning_at_the_rope_minimum():
    rope = get_cable("steel-7x7-0.54")
    assert cap.bend_ratio_warning(rope, 21.6) is None
    assert cap.bend_ratio_warning(get_cable("steel-7x19-0.6"), 15.6) is None
    w = cap.bend_ratio_warning(get_cable("steel-7x19-0.6"), 10.0)
    assert "15.6 mm" in w and "or a 7x19" not in w


# ------------------------------------------------------------------ capstan equation
def test_capstan_equation_against_its_ode():
    """T' = mu T along the wrap (belt friction at slip); integrated numerically = e^{mu theta}."""
    mu, theta = cap.MU_STEEL_ROPE_ON_STEEL, 3 * 2 * math.pi  # three wraps
    sol = solve_ivp(lambda t, T: mu * T, (0.0, theta), [1.0], rtol=1e-10, atol=1e-12)
    assert float(cap.capstan_tension_ratio(mu, theta)) == pytest.approx(sol.y[0, -1], rel=1e-8)
    assert float(cap.capstan_tension_ratio(mu, theta)) == pytest.approx(9.6014, rel=1e-4)
    assert float(cap.wraps(theta)) == pytest.approx(3.0)


def test_pretension_puts_the_joint_exactly_at_slip():
    mu, theta, dT = 0.12, 2.5 * 2 * math.pi, 10.0
    T0 = float(cap.pretension_needed_N(dT, mu, theta))
    Tt, Ts = T0 + dT / 2, T0 - dT / 2
    assert Tt / Ts == pytest.approx(math.exp(mu * theta))
    assert float(cap.slip_margin(dT, T0, mu, theta)) == pytest.approx(1.0)
    assert float(cap.slip_margin(dT, 2 * T0, mu, theta)) > 1.0
    assert float(cap.slip_margin(dT, 0.9 * T0, mu, theta)) < 1.0
    assert float(cap.slip_margin(dT, dT / 4, mu, theta)) == 0.0  # slack run gone slack
    assert float(cap.wrap_angle_needed_rad(dT, T0, mu)) == pytest.approx(theta)


def test_wrap_angle_refuses_a_pretension_below_half_the_load():
    with pytest.raises(DesignError, match="slack run goes slack"):
        cap.wrap_angle_needed_rad(10.0, 5.0, 0.12)


# ------------------------------------------------------------------ strength
def test_cable_strength_verdicts():
    rope = get_cable("steel-7x7-1.6")  # 480 lbf = 2135 N (sourced)
    v, why = cap.cable_strength_verdict(rope, 100.0, 50.0)  # tight run 100 N -> SF 21.4
    assert v == "ok" and "21.4" in why
    v, _ = cap.cable_strength_verdict(rope, 600.0, 300.0)   # 600 N -> SF 3.6 < 5
    assert v == "fails"
    v, why = cap.cable_strength_verdict(get_cable("steel-7x7-0.54"), 10.0, 20.0)
    assert v == "unverified" and "unverified" in why      # scaled, not read
    v, why = cap.cable_strength_verdict(get_cable("steel-7x19-0.6"), 10.0, 20.0)
    assert v == "unverified" and "no breaking load" in why


# ------------------------------------------------------------------ stiffness
def test_cable_spring_against_the_second_derivative_of_its_energy():
    EA, d_drum, L = 2.0e4, 120.0, (40.0, 70.0)
    k = float(cap.cable_torsional_stiffness_Nm_per_rad(EA, d_drum, L))
    r = 0.06

    def energy(dq):
        return sum(0.5 * EA / (Li * 1e-3) * (r * dq) ** 2 for Li in L)

    h = 1e-4
    k_fd = (energy(h) - 2 * energy(0.0) + energy(-h)) / h**2
    assert k == pytest.approx(k_fd, rel=1e-6)
    assert k == pytest.approx(EA * (1 / 0.04 + 1 / 0.07) * r * r)


def test_two_springs_in_series_deflections_add():
    k1, k2, tau = 150.0, 600.0, 0.3
    ks = float(cap.series_stiffness(k1, k2))
    assert ks == pytest.approx(k1 * k2 / (k1 + k2))  # closed form: 120
    assert tau / ks == pytest.approx(tau / k1 + tau / k2)
    assert float(cap.series_stiffness(k1, 1e300)) == pytest.approx(k1)


# ------------------------------------------------------------------ drum range
def test_drum_sector_hand_number_and_refusal():
    # 90 deg joint range, 120 mm drum, 10 mm anchors: each anchor spans 2*10/120 rad = 9.549 deg
    need = cap.check_drum_range(90.0, 120.0, 10.0)
    assert need == pytest.approx(90.0 + 2 * math.degrees(20.0 / 120.0))
    with pytest.raises(DesignError, match=r"transmission.drum_diameter_mm: .*needs a 109.1 deg"):
        cap.check_drum_range(90.0, 120.0, 10.0, sector_available_deg=100.0)
    # the diameter it names fits exactly: 4 L_a / radians(100 - 90)
    d_fit = 4 * 10.0 / math.radians(10.0)
    assert cap.check_drum_range(90.0, d_fit, 10.0, 100.0) == pytest.approx(100.0)
    with pytest.raises(DesignError, match="no drum covers it"):
        cap.check_drum_range(370.0, 120.0, 10.0)


def test_every_catalog_rope_gets_a_one_line_warning_below_its_minimum():
    for rope in CABLES.values():
        w = cap.bend_ratio_warning(rope, 0.5 * rope.min_capstan_diameter_mm())
        assert w and rope.key in w and "\n" not in w


def test_one_joint_figures_by_hand():
    """A WoodenHaptics-like joint: 10 mm capstan, 160 mm drum, RE 35 rotor (79.2 g cm^2), 0.8 N m
    peak at the joint, three wraps: n = 16, n^2 J = 256 * 79.2e-7, dT = 0.8 / 0.08 = 10 N."""
    f = cap.capstan_joint_figures(10.0, 160.0, get_cable("steel-7x7-0.54"), 79.2e-7, 0.8,
                                  3 * 2 * math.pi, motor_friction_Nm=4.9e-3)
    assert f.ratio == pytest.approx(16.0)
    assert f.reflected_inertia_kg_m2 == pytest.approx(256 * 79.2e-7)
    assert f.reflected_friction_Nm == pytest.approx(16 * 4.9e-3)
    assert f.tension_difference_N == pytest.approx(10.0)
    e = math.exp(0.12 * 6 * math.pi)
    assert f.pretension_N == pytest.approx(5.0 * (e + 1) / (e - 1))
    assert f.slip_margin == pytest.approx(1.0) and f.wraps == pytest.approx(3.0)
    assert f.strength[0] == "unverified"
    assert len(f.warnings) == 1 and "D/d = 18.5" in f.warnings[0]
    g = cap.capstan_joint_figures(25.0, 200.0, get_cable("steel-7x7-1.6"), 79.2e-7, 0.8,
                                  2 * math.pi, pretension_given_N=30.0)
    assert g.pretension_N == 30.0 and g.strength[0] == "ok"
    assert g.warnings[0].startswith("cable steel-7x7-1.6 on a 25 mm capstan")  # 25 / 1.5875 < 40


def test_the_docs_page_shows_what_the_warning_prints():
    from pathlib import Path

    page = (Path(__file__).resolve().parents[3] / "docs" / "capstan.md").read_text()
    assert cap.bend_ratio_warning(get_cable("steel-7x7-0.54"), 10.0) in page
