"""MuJoCo side of the simulator exports: load an exported MJCF, close its loops, and reduce
its dynamics to the loop-constrained manifold (issue 14).

Everything here is computed by MuJoCo from the MJCF alone -- its mass matrix
(``mj_fullM``, armature included), its equality-constraint rows (``efc_J``, ``efc_pos``)
and its site Jacobians (``mj_jacSite``) -- so it is an independent check of hapticad's
own kinematics and eq (22).

Reduction: with independent joints ``u`` (the crank for a four-bar, the three task DOF
joints for the mouse), the constraint rows ``Jc dq = 0`` give ``dq = N du``,
``N = [E; -Jc_d^+ Jc_u]`` (d = dependent joints); the reduced inertia is ``N^T M N``
and a site's velocity is ``J_site N du``. The operational-space inertia of a 1-DOF
mechanism at a site is ``M_op = J^{+T} D J^{+}`` with ``D = N^T M N`` and ``J = J_site N``
(Hoeken paper eq 22).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from cad.tolerances import CLOSE_TOL_M

#: Newton iterations of :func:`close_loops` (their stopping residual: CLOSE_TOL_M, m).
CLOSE_MAX_ITER = 50


def load(path: Path):
    """(MjModel, MjData) of an MJCF file, dense constraint Jacobian, forward evaluated."""
    import mujoco

    m = mujoco.MjModel.from_xml_path(str(path))
    m.opt.jacobian = mujoco.mjtJacobian.mjJAC_DENSE
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    return m, d


def joint_dof(m, name: str) -> int:
    """DOF address of a hinge joint."""
    return int(m.jnt_dofadr[m.joint(name).id])


def joint_qpos(m, name: str) -> int:
    return int(m.jnt_qposadr[m.joint(name).id])


def joint_torque_drive(m, a: int, tau_max_Nm: float) -> float:
    """The MJCF ``gear`` n of joint motor ``a`` (a capstan's ratio: MuJoCo applies n x ctrl at the
    joint, :mod:`cad.export.sim`; 1 for direct drive), with its control and force range set to the
    joint's torque bound over n (``tau_max_Nm`` N m at the joint, so the motor's at the actuator).
    Drive it with ``ctrl = tau_joint / n``; every MuJoCo plant (the wall, the benches) does."""
    n = float(m.actuator_gear[a, 0])
    m.actuator_ctrlrange[a] = m.actuator_forcerange[a] = (-tau_max_Nm / n, tau_max_Nm / n)
    return n


def equality_rows(m, d) -> tuple[np.ndarray, np.ndarray]:
    """(Jc (n_eq_rows, nv), residual (n_eq_rows,)) of the equality constraints at d."""
    import mujoco

    mujoco.mj_fwdPosition(m, d)
    rows = np.flatnonzero(d.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY)
    J = np.array(d.efc_J).reshape(d.nefc, m.nv)[rows]
    return J, np.array(d.efc_pos)[rows]


def loop_residual_m(m, d) -> float:
    """Largest distance (m) between the two sites of any ``connect`` equality."""
    import mujoco

    mujoco.mj_kinematics(m, d)
    worst = 0.0
    for i in range(m.neq):
        if m.eq_type[i] != mujoco.mjtEq.mjEQ_CONNECT:
            continue
        a, b = int(m.eq_obj1id[i]), int(m.eq_obj2id[i])
        worst = max(worst, float(np.linalg.norm(d.site_xpos[a] - d.site_xpos[b])))
    return worst


def _split(m, indep: list[str]) -> tuple[np.ndarray, np.ndarray]:
    u = np.array([joint_dof(m, j) for j in indep])
    dep = np.setdiff1d(np.arange(m.nv), u)
    return u, dep


def close_loops(m, d, indep: list[str]) -> float:
    """Solve the loop closure for the dependent joints (Newton on MuJoCo's own constraint
    rows), keeping the ``indep`` joints where they are; hinge and ball joints. Returns the
    residual (m)."""
    import mujoco

    u, dep = _split(m, indep)
    for _ in range(CLOSE_MAX_ITER):
        J, r = equality_rows(m, d)
        if np.abs(r).max() < CLOSE_TOL_M:
            break
        dv = np.zeros(m.nv)
        dv[dep] = -np.linalg.lstsq(J[:, dep], r, rcond=None)[0]
        mujoco.mj_integratePos(m, d.qpos, dv, 1.0)  # ball joints: their quaternions turned by dv
    return loop_residual_m(m, d)


def null_basis(m, d, indep: list[str]) -> np.ndarray:
    """N (nv, k): joint velocities of unit independent velocities on the constraint manifold."""
    u, dep = _split(m, indep)
    J, _ = equality_rows(m, d)
    N = np.zeros((m.nv, u.size))
    N[u, np.arange(u.size)] = 1.0
    N[dep] = -np.linalg.lstsq(J[:, dep], J[:, u], rcond=None)[0]
    return N


def full_mass_matrix(m, d) -> np.ndarray:
    """MuJoCo's joint-space inertia matrix (nv, nv), armature included."""
    import mujoco

    mujoco.mj_forward(m, d)
    M = np.zeros((m.nv, m.nv))
    mujoco.mj_fullM(m, d, M)
    return M


def site_jacobian(m, d, site: str) -> tuple[np.ndarray, np.ndarray]:
    """(jacp (3, nv), jacr (3, nv)) of a site, world frame."""
    import mujoco

    jp = np.zeros((3, m.nv))
    jr = np.zeros((3, m.nv))
    mujoco.mj_jacSite(m, d, jp, jr, m.site(site).id)
    return jp, jr


def fourbar_operational_inertia(m, d, phi1_rad: float) -> dict:
    """At crank angle ``phi1_rad``: close the loop, then D (kg m^2), J = dP/dphi1 (2,) m/rad
    and M_op (2, 2) kg at site ``handle`` in R0 axes; ``residual_m`` of the closure."""
    d.qpos[joint_qpos(m, "crank")] = phi1_rad
    res = close_loops(m, d, ["crank"])
    N = null_basis(m, d, ["crank"])
    M = full_mass_matrix(m, d)
    D = float(N[:, 0] @ M @ N[:, 0])
    jp, _ = site_jacobian(m, d, "handle")
    J = (jp @ N)[:2, 0]
    n2 = float(J @ J)
    return {"D_kg_m2": D, "J_m_per_rad": J, "M_op_kg": D * np.outer(J, J) / n2**2, "residual_m": res}


def twin_task_mass_matrix(m, d) -> dict:
    """Task mass matrix (3, 3) of the twin pantograph at the current pose: X = (x, y, theta)
    of site ``handle`` (main journal) and the crankshaft's angle; kg, kg m, kg m^2."""
    indep = ["knob_q_left", "knob_q_right", "theta"]
    close_loops(m, d, indep)
    N = null_basis(m, d, indep)
    M = full_mass_matrix(m, d)
    Mu = N.T @ M @ N
    jp, _ = site_jacobian(m, d, "handle")
    _, jr = site_jacobian(m, d, "crank_pin")
    T = np.vstack([jp[:2], jr[2:3]]) @ N  # task velocity = T u_dot
    Ti = np.linalg.inv(T)
    return {"M_task": Ti.T @ Mu @ Ti, "residual_m": loop_residual_m(m, d)}


def fivebar_task_mass_matrix(m, d) -> dict:
    """Task mass matrix of the plain 5-bar at the current pose, from MuJoCo alone: the
    kinetic-energy matrix (2, 2) kg in the handle's (x, y) velocity with the handle pin not
    spinning (``M_xy``), and the apparent mass (2, 2) kg with the pin free to spin in its
    bearings (``M_apparent`` = inverse of the xy block of the inverse task matrix);
    ``residual_m`` of the loop. Independent joints: ``q_left``, ``q_right``, ``handle_spin``."""
    indep = ["q_left", "q_right", "handle_spin"]
    close_loops(m, d, indep)
    N = null_basis(m, d, indep)
    M = full_mass_matrix(m, d)
    Mu = N.T @ M @ N
    jp, jr = site_jacobian(m, d, "handle")
    T = np.vstack([jp[:2], jr[2:3]]) @ N  # (x, y, spin) velocity = T u_dot
    Ti = np.linalg.inv(T)
    Mt = Ti.T @ Mu @ Ti
    return {"M_xy": Mt[:2, :2], "M_apparent": np.linalg.inv(np.linalg.inv(Mt)[:2, :2]),
            "residual_m": loop_residual_m(m, d)}
