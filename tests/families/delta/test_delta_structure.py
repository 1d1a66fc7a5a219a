"""The delta's 3-D frame model (cad/families/delta/structure.py) against independent checks.

References: (1) a cantilever in an arbitrary 3-D orientation: tip deflection P L^3 / (3 E I)
in both bending planes and axial P L / (E A) (Euler-Bernoulli, exact for cubic elements), and
its first mode against the clamped-free closed form 1.8751^2 / (2 pi) sqrt(E I / (rho A L^4));
(2) the delta with rigid arms, bars and effector and massless rods: its first mode equals the
hand reduction of a rigid effector of mass m on the twelve rod springs k = E A / L (6x6
rigid-body stiffness sum k [u; r x u][u; r x u]^T, rotations condensed, eig(K_tt_c / m));
(3) the bundled delta's numbers: regression pins (labelled).
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from cad.design import load_design
from cad.families.delta.layout import arm_points_mm
from cad.families.delta.structure import (
    Frame3D,
    default_sections,
    delta_frame,
    first_mode,
    round_section,
)
from cad.kinematics import delta as D
from cad.structure.fem import euler_bernoulli_first_mode_Hz

ROOT = Path(__file__).resolve().parents[3]


def _cantilever(n_sub):
    rng = np.random.default_rng(3)
    d = rng.normal(size=3)
    d /= np.linalg.norm(d)
    ref = np.cross(d, rng.normal(size=3))
    L = 0.2
    s = round_section(0.01, 0.006, "aluminium-6061")
    f = Frame3D()
    a, b = f.node([0.01, 0.02, 0.03]), f.node(np.array([0.01, 0.02, 0.03]) + L * d)
    f.clamped.add(a)
    f.beam(a, b, s, ref, n_sub=n_sub)
    return f, b, d, L, s


def test_cantilever_deflections_in_any_orientation():
    f, tip, d, L, s = _cantilever(3)
    n = np.cross(d, [0.3, -0.2, 0.9])
    n /= np.linalg.norm(n)
    for direction, expected in ((n, L**3 / (3 * s.E * s.Iz)), (np.cross(d, n), L**3 / (3 * s.E * s.Iy)),
                                (d, L / (s.E * s.A))):
        u = f.solve({tip: 2.0 * direction})[6 * tip:6 * tip + 3]
        assert u @ direction == pytest.approx(2.0 * expected, rel=1e-9)


def test_cantilever_first_mode_converges_to_the_closed_form():
    f, _, _, L, s = _cantilever(60)
    hz = f.modes(1)[0][0]
    ref = euler_bernoulli_first_mode_Hz(L, s.E, s.Iz, s.rho, s.A)
    assert hz == pytest.approx(ref, rel=2e-3)


def _rigid_reduction(d, P_mm, w_mm, k_rod, m):
    pose = D.ik(d, np.asarray(P_mm, float).reshape(1, 3))
    pts = {k: v[:, 0] * 1e-3 for k, v in arm_points_mm(d, pose.P_mm, pose.theta_rad).items()}
    P = pose.P_mm[0] * 1e-3
    K = np.zeros((6, 6))
    for i in range(3):
        for s in (-1, 1):
            off = s * w_mm / 2 * 1e-3 * d.tangential[i]
            top, bot = pts["top"][i] + off, pts["bottom"][i] + off
            u = (bot - top) / np.linalg.norm(bot - top)
            g = np.r_[u, np.cross(bot - P, u)]
            K += k_rod * np.outer(g, g)
    Kc = K[:3, :3] - K[:3, 3:] @ np.linalg.solve(K[3:, 3:], K[3:, :3])
    return np.sqrt(np.linalg.eigvalsh(Kc / m)) / (2 * math.pi)


def test_rigid_delta_is_a_mass_on_twelve_rod_springs():
    des = load_design(ROOT / "designs" / "delta.toml")
    d, w = des.mechanism, des.parallelogram_width_mm
    sec = default_sections(d.effector_radius_mm, w)
    stiff = lambda s: replace(s, E=s.E * 1e6, G=s.G * 1e6, rho=0.0)  # noqa: E731
    sec = replace(sec, arm=stiff(sec.arm), cross_bar=stiff(sec.cross_bar),
                  effector=stiff(sec.effector), rod_kg_per_m=0.0, top_joint_kg=0.0, bottom_joint_kg=0.0)
    for P in (des.workspace["center_mm"], [30.0, -20.0, -200.0]):
        f, _ = delta_frame(d, P, w, sec)
        hz = f.modes(3)[0]
        ref = _rigid_reduction(d, P, w, sec.rod_EA_N / (d.lower_arm_mm * 1e-3), sec.effector_kg)
        np.testing.assert_allclose(hz, ref, rtol=1e-5)


def test_bundled_delta_first_mode_regression_pin():
    """Regression pin (our own run, not an outside value): the bundled delta at the
    workspace centre, default hardware."""
    des = load_design(ROOT / "designs" / "delta.toml")
    r = first_mode(des.mechanism, des.workspace["center_mm"], des.parallelogram_width_mm)
    C = r["compliance_m_per_N"]
    np.testing.assert_allclose(C, C.T, rtol=1e-9, atol=1e-15)
    assert np.all(np.linalg.eigvalsh(C) > 0)
    assert r["first_mode_Hz"] == pytest.approx(PIN_HZ, rel=1e-6)
    assert r["compliance_max_um_per_N"] == pytest.approx(PIN_UM_PER_N, rel=1e-6)


PIN_HZ = 195.28967129341603  # Hz, double lateral mode (x-y), 2026-12-05 (a ball joint at each rod end; 199.25 with half of one)
PIN_UM_PER_N = 5.141712297419138  # um/N, worst direction
