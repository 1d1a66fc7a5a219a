"""The delta's stress rows (issue 36 §4: datasheet rows as for every family): the frame's beam
stresses and rod forces under the motors' peak torque (cad/families/delta/structure.py
``peak_stress``) against independent references:

(1) a cantilever of the arm's section under a tip load: root moment P L, von Mises stress
    6 P L / (t w^2) (beam theory, bending about the section's thickness axis);
(2) the delta at its workspace centre with f = J^T tau (J from the closed-form kinematics):
    the clamp moment of each arm about its motor axis is that arm's tau (statics of the arm:
    the motor holds it), and the rod forces balance the effector's load (sum N_k u_k = -f,
    u_k from the rod's effector end to its elbow end, N_k tension);
(3) the rods' buckling load against Euler's pin-ended column pi^2 E I / L^2 by hand.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from cad.design import load_design
from cad.families.delta import hardware as hw
from cad.families.delta.structure import (
    Frame3D,
    default_sections,
    delta_frame,
    euler_buckling_N,
    peak_stress,
    peak_torque_loads_N,
    rect_section,
)
from cad.kinematics.delta import jacobian_rad_per_m
from cad.structure.frame import von_mises_of_end_forces

ROOT = Path(__file__).resolve().parents[3]
DELTA = ROOT / "designs" / "delta.toml"


def test_cantilever_of_the_arm_section():
    w, t, L, P = 16e-3, 6e-3, 0.11, 7.0
    s = rect_section(w, t, hw.ARM_MATERIAL)
    f = Frame3D()
    a, b = f.node([0, 0, 0]), f.node([L, 0, 0])
    f.clamped.add(a)
    f.beam(a, b, s, [0, 0, 1.0], n_sub=3, label="arm")
    u = f.solve({b: [0, P, 0]})            # along the width: bending about local z (Iz = t w^3 / 12)
    fe = f.beam_end_forces(u)
    assert abs(fe[0, 5]) == pytest.approx(P * L, rel=1e-9)
    vm = von_mises_of_end_forces(fe, [x[2] for x in f.beams])
    assert vm.max() == pytest.approx(6 * P * L / (t * w * w), rel=1e-9)


def test_clamp_moments_are_the_joint_torques_and_rods_balance_the_load():
    d = load_design(DELTA)
    c = np.asarray(d.workspace["center_mm"], float)
    tau = 0.5
    loads = peak_torque_loads_N(d.mechanism, c, tau)
    J, _ = jacobian_rad_per_m(d.mechanism, c.reshape(1, 3))
    f, node = delta_frame(d.mechanism, c, d.parallelogram_width_mm,
                          default_sections(d.mechanism.effector_radius_mm, d.parallelogram_width_mm))
    roots = [k for k, lab in enumerate(f.beam_labels) if lab.startswith("upper arm")][::4]
    for F in loads:
        u = f.solve({node: F})
        fe = f.beam_end_forces(u)
        tau_k = np.linalg.solve(J[0].T, F)         # the joint torques that give F (f = J^T tau)
        assert np.allclose(np.abs(tau_k), tau, rtol=1e-9)
        for i, k in enumerate(roots):             # the arm's clamp moment about its motor axis
            assert abs(fe[k, 5]) == pytest.approx(abs(tau_k[i]), rel=1e-6)
        N = f.truss_forces_N(u)
        pull = sum(n * (f.nodes[i] - f.nodes[j]) / np.linalg.norm(f.nodes[i] - f.nodes[j])
                   for n, (i, j, _, _) in zip(N, f.trusses))
        assert np.allclose(pull, -F, atol=1e-9 * np.linalg.norm(F))  # the rods' pull balances F


def test_rod_buckling_against_euler_by_hand():
    E = 200e9
    I = math.pi / 64 * (0.004 ** 4 - 0.003 ** 4)
    assert euler_buckling_N(4.0, 3.0, 190.0, E) == pytest.approx(math.pi ** 2 * E * I / 0.19 ** 2, rel=1e-12)


def test_bundled_delta_stress_rows_and_verdicts():
    from cad.structure.elastic import get_elastic

    d = load_design(DELTA)
    c = np.asarray(d.workspace["center_mm"], float)
    from cad.data.catalog import get_motor

    tau = get_motor("maxon-re40").torque_peak_mNm * 1e-3  # the design's parts.motor, its catalog data
    r = peak_stress(d.mechanism, c, d.parallelogram_width_mm, peak_torque_loads_N(d.mechanism, c, tau))
    el = get_elastic(hw.ROD_MATERIAL, "test")
    assert r["rod_buckling_N"] == pytest.approx(euler_buckling_N(4.0, 3.0, 190.0, el.E_Pa), rel=1e-12)
    assert r["rod_buckling_margin"] == pytest.approx(r["rod_buckling_N"] / r["rod_compression_max_N"], rel=1e-12)
    # the arm root's in-plane moment is tau: 6 tau / (t w^2) is a floor of its von Mises stress
    assert r["max_stress_MPa"] >= 6 * tau / (6e-3 * 16e-3 ** 2) * 1e-6 * (1 - 1e-9)
    # regression pins (recorded from this build, 2026-12-05): 12.2 MPa (arm 1), margin 4.05
    assert r["max_stress_MPa"] == pytest.approx(12.24, abs=0.01)
    assert r["rod_buckling_margin"] == pytest.approx(4.05, abs=0.01)


def _rod_compression_by_statics(d, P, tau):
    """Largest rod compression (N) at effector point P under every motor at +-tau, by the
    effector's statics alone: six pin-ended rods (each parallelogram's two, +-w/2 along its
    motor axis) hold the effector against F = J^T tau applied at its centre: the rods' forces
    sum to -F and their moments about the centre to zero (6 equations, 6 unknowns)."""
    from cad.families.delta.layout import arm_points_mm
    from cad.kinematics.delta import ik

    pose = ik(d.mechanism, np.asarray(P, float).reshape(1, 3))
    pts = arm_points_mm(d.mechanism, pose.P_mm, pose.theta_rad)
    half = d.parallelogram_width_mm / 2
    A = np.zeros((6, 6))
    k = 0
    for i in range(3):
        for sgn in (-1.0, 1.0):
            off = sgn * half * d.mechanism.tangential[i]
            top, bot = pts["top"][i, 0] + off, pts["bottom"][i, 0] + off
            e = (top - bot) / np.linalg.norm(top - bot)  # tension pulls the effector toward top
            A[:3, k], A[3:, k] = e, np.cross((bot - np.asarray(P, float)) * 1e-3, e)
            k += 1
    worst = 0.0
    for F in peak_torque_loads_N(d.mechanism, P, tau):
        N = np.linalg.solve(A, np.r_[-F, 0.0, 0.0, 0.0])
        worst = max(worst, float(-N.min()))
    return worst


def test_over_the_workspace_the_worst_point_is_found_and_is_the_statics():
    """The datasheet's stress rows are the worst over the workspace grid (a tester found the
    centre alone hid the cube's corners): the largest rod compression equals the statics of the
    three parallelograms at the worst point, and no grid point is worse."""
    from cad.data.catalog import get_motor
    from cad.families.delta.structure import peak_stress_over

    d = load_design(DELTA)
    tau = get_motor("maxon-re40").torque_peak_mNm * 1e-3  # the stall torque, no drive limit
    X = d.workspace_points()
    r = peak_stress_over(d.mechanism, X, d.parallelogram_width_mm, tau)
    by_hand = [_rod_compression_by_statics(d, P, tau) for P in X]
    assert r["rod_compression_max_N"] == pytest.approx(max(by_hand), rel=1e-6)
    assert r["buckling_at_mm"] == pytest.approx(X[int(np.argmax(by_hand))].tolist())
    assert r["points"] == len(X) == 125
    # at the stall torque the cube's top corners buckle the rods below the margin of 3
    assert r["rod_buckling_margin"] < 3.0 < peak_stress(
        d.mechanism, np.asarray(d.workspace["center_mm"], float), d.parallelogram_width_mm,
        peak_torque_loads_N(d.mechanism, np.asarray(d.workspace["center_mm"], float), tau))["rod_buckling_margin"]
    # the bundled design's drive limit ([motor] torque_peak_mNm) keeps every point above it
    from cad.device import resolve_device

    t_lim = resolve_device(d).motor.spec.torque_peak_mNm * 1e-3
    assert t_lim == 1.5
    lim = peak_stress_over(d.mechanism, X, d.parallelogram_width_mm, t_lim)
    assert lim["rod_buckling_margin"] >= 3.0
    # regression pins (recorded from this code, 2026-12-05; docs/families/delta.md types them):
    assert r["rod_compression_max_N"] == pytest.approx(55.3, abs=0.05)
    assert r["rod_buckling_margin"] == pytest.approx(1.91, abs=0.005)
    assert (lim["max_stress_MPa"], lim["rod_buckling_margin"]) == (pytest.approx(17.54, abs=0.01),
                                                                    pytest.approx(3.26, abs=0.005))
