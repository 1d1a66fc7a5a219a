"""The frame model of a delta with Stamper's knee (the Falcon, g = 22.5 mm;
cad/families/delta/structure.py ``knee_arm``) against independent references:

(1) a second assembly of the stiffness matrix: every released end (the knee pin, the rods'
    hinges at the knee and their balls at the effector) as its own coincident node joined to
    its member's node by a master-slave transformation (translations shared, the rotations
    about the released axes free coordinates), every element the full unreleased 12 x 12
    beam -- instead of the model's element-level static condensation; the effector's
    compliance, every node's displacement and the lowest modes agree to round-off;
(2) statics by virtual work at every point of the Falcon's workspace grid: under f = J^T tau
    (J from the closed-form kinematics with the knee, :mod:`cad.kinematics.delta`) each
    arm's clamp moment about its motor axis is that arm's tau (the pins and balls do no work
    in the mechanism's own motion, so the held motors carry exactly the kinematics' torque);
(3) the Falcon's figures at the workspace centre: regression pins (labelled).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import eigh

from cad.design import load_design
from cad.families.delta.structure import (
    default_sections,
    delta_frame,
    element_axes,
    first_mode,
    peak_torque_loads_N,
)
from cad.kinematics.delta import jacobian_rad_per_m
from cad.structure.frame import local_stiffness

ROOT = Path(__file__).resolve().parents[3]
FALCON = load_design(ROOT / "designs" / "delta_falcon.toml")


def _frame(P):
    d = FALCON
    sec = default_sections(d.mechanism.effector_radius_mm, d.parallelogram_width_mm)
    return delta_frame(d.mechanism, P, d.parallelogram_width_mm, sec)


def master_slave(f):
    """(K_q, T, n_orig): the stiffness over q = [u of the frame's nodes (6 each); one rotation
    per released axis], assembled with unreleased elements on duplicate end nodes
    u_dup = T_dup q (translations of the original node; its rotation less its components
    on the released axes e_a, plus q_a e_a)."""
    n = len(f.nodes)
    extra = [(k, end, a) for k, rel in f.releases.items() for end in (0, 1)
             for a in sorted(r for r in rel if 6 * end + 3 <= r < 6 * end + 6)]
    nq = 6 * n + len(extra)
    blocks = []        # per element: (T_i (6, nq), T_j (6, nq)) mapping q to its end DOFs
    for k, (i, j, _, ref) in enumerate(f.beams):
        R = element_axes(f.nodes[i], f.nodes[j], ref)
        ends = []
        for end, node in ((0, i), (1, j)):
            T = np.zeros((6, nq))
            T[:, 6 * node:6 * node + 6] = np.eye(6)
            for m, (kk, ee, a) in enumerate(extra):
                if kk == k and ee == end:
                    e = R[a - 6 * end - 3]
                    T[3:, 6 * node + 3:6 * node + 6] -= np.outer(e, e)
                    T[3:, 6 * n + m] = e
            ends.append(T)
        blocks.append(ends)
    K = np.zeros((nq, nq))
    for k, (i, j, s, ref) in enumerate(f.beams):
        Te = np.kron(np.eye(4), element_axes(f.nodes[i], f.nodes[j], ref)) @ np.vstack(blocks[k])
        K += Te.T @ local_stiffness(float(np.linalg.norm(f.nodes[j] - f.nodes[i])), s) @ Te
    assert not f.trusses
    return K, n


def test_second_assembly_equals_the_condensed_elements():
    """(1) at the centre and a top corner of the Falcon's cube."""
    for P in (FALCON.workspace["center_mm"], [45.0, -45.0, -66.0]):
        f, c = _frame(P)
        assert len(f.releases) == 3 + 6                     # three knee pins, six rods
        K, n = master_slave(f)
        fixed = {6 * a + q for a in f.clamped for q in range(6)}
        free = np.array([q for q in range(K.shape[0]) if q not in fixed])
        U = np.zeros((K.shape[0], 3))
        U[free] = np.linalg.solve(K[np.ix_(free, free)], np.eye(K.shape[0])[free][:, 6 * c:6 * c + 3])
        for d in range(3):
            u = f.solve({c: np.eye(3)[d]})
            scale = np.abs(u).max()
            tr = np.r_[[6 * p + q for p in range(n) for q in range(3)]]
            assert np.abs(U[tr, d] - u[tr]).max() < 1e-9 * scale
        # the lowest modes: lumped translational masses, rotations condensed (Guyan)
        m = np.zeros(K.shape[0])
        m[[6 * p + q for p in range(n) for q in range(3)]] = np.repeat(f.masses(), 3)
        t = free[m[free] > 0]
        r = free[m[free] == 0]
        Kc = K[np.ix_(t, t)] - K[np.ix_(t, r)] @ np.linalg.solve(K[np.ix_(r, r)], K[np.ix_(r, t)])
        w2 = eigh(0.5 * (Kc + Kc.T), np.diag(m[t]), eigvals_only=True, subset_by_index=[0, 2])
        hz = np.sqrt(w2) / (2 * np.pi)
        assert np.allclose(hz, first_mode(FALCON.mechanism, P, FALCON.parallelogram_width_mm)["modes_Hz"],
                           rtol=1e-9)


def test_clamp_moments_are_the_knee_kinematics_torques_over_the_grid():
    """(2) at every point of the Falcon's 5 x 5 x 5 grid, eight torque-box corners each."""
    X = FALCON.workspace_points()
    tau = 0.5
    for P in X:
        J, status = jacobian_rad_per_m(FALCON.mechanism, P.reshape(1, 3))
        assert status[0] == 0
        f, node = _frame(P)
        roots = [k for k, lab in enumerate(f.beam_labels) if lab.startswith("upper arm")][::4]
        for F in peak_torque_loads_N(FALCON.mechanism, P, tau):
            fe = f.beam_end_forces(f.solve({node: F}))
            tau_k = np.linalg.solve(J[0].T, F)
            for i, k in enumerate(roots):
                assert abs(fe[k, 5]) == pytest.approx(abs(tau_k[i]), rel=1e-6)
                assert abs(tau_k[i]) == pytest.approx(tau, rel=1e-9)


#: Regression pins (our own run, 2026-12-05): the Falcon at its workspace centre with the
#: family's hardware (fork of two 16 x 6 mm plates, knee plate 16 x 6 mm, rods 4/3 mm carbon)
#: and the default sections' ball joint at each rod end (the build counts the knee hinges'
#: drawn parts instead: tests/families/delta/test_delta_joint_masses.py).
PIN_HZ = 322.67555564772516
PIN_UM_PER_N = 2.0371965131197682


def test_falcon_figures_at_the_centre():
    r = first_mode(FALCON.mechanism, FALCON.workspace["center_mm"], FALCON.parallelogram_width_mm)
    C = r["compliance_m_per_N"]
    np.testing.assert_allclose(C, C.T, rtol=1e-9, atol=1e-15)
    assert np.all(np.linalg.eigvalsh(C) > 0)
    assert r["first_mode_Hz"] == pytest.approx(PIN_HZ, rel=1e-6)
    assert r["compliance_max_um_per_N"] == pytest.approx(PIN_UM_PER_N, rel=1e-6)


def test_falcon_stress_rows_at_the_default_motors_peak_torque():
    """The datasheet's stress rows of the Falcon with the resolved default motor (RE 35) at its
    peak torque over the grid: regression pins (our own run, 2026-12-05), and the rods'
    bending counted in their stress (larger than the axial stress alone)."""
    from cad.device import resolve_device
    from cad.families.delta.structure import peak_stress_over

    tau = resolve_device(FALCON).motor.spec.torque_peak_mNm * 1e-3
    ps = peak_stress_over(FALCON.mechanism, FALCON.workspace_points(), FALCON.parallelogram_width_mm, tau)
    assert ps["max_stress_MPa"] == pytest.approx(32.87, abs=0.01)
    assert ps["rod_buckling_margin"] == pytest.approx(4.583, abs=0.001)
    assert not ps["critical_member"].startswith("rod")
    axial = ps["rod_compression_max_N"] / (np.pi / 4 * (4.0**2 - 3.0**2))
    assert ps["rod_stress_max_MPa"] > axial
