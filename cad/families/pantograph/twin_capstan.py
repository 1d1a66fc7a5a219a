"""The capstans of a twin-pantograph haptic mouse (issue 35 §1): a capstan on any of its four
motors (knob left, knob right, crank left, crank right: :meth:`PantographDesign.motor_joints`).
Pure numpy (no CAD import); the rows, BOM lines and winding steps are the shared ones
(:mod:`cad.datasheet.capstan_rows`, through :mod:`cad.families.pantograph.capstan`), this
module only says where the twin's joints turn and how its ropes reach the handle.

* each joint's range: the proximal link's angle over the workspace grid (x, y and the full
  crank turn, ``[workspace]``, boundary included), widened by
  :data:`cad.tolerances.CAPSTAN_RANGE_MARGIN_DEG` on each side, as on the 5-bar;
* the ropes at the handle: with the motors held and the links rigid, each rope a torsional
  spring ``k_q`` at its joint, the handle's stiffness is ``K_X = J^T diag(k_q) J`` (J = dq/dX,
  (4, 3), rad/m and rad/rad, :func:`cad.kinematics.twin_pantograph.jacobian_si`: four springs
  on three task coordinates, the redundant actuation of isotropy paper §4.1); a force at the
  main journal with the knob's moment free sees the translational block of ``K_X^-1``. A
  direct-drive joint holds rigidly: the handle then moves only in the null space of its rows.

The solids (drums on the links, moved motors on the bridge or under the base plate) are the
5-bar's (:mod:`cad.families.pantograph.capstan_solids`), laid out for each of the twin's 5-bars
by :func:`cad.families.pantograph.twin_placement.group_layout`, which refuses in one line naming
``transmission`` a 5-bar whose drums cannot be placed.
"""

from __future__ import annotations

import numpy as np

from cad.datasheet import capstan_rows as cr
from cad.device import resolve_device
from cad.kinematics import fivebar as fb5
from cad.kinematics import twin_pantograph as ktwin

#: How the ropes' stiffness at the handle is computed (the datasheet row's model text).
HANDLE_STIFFNESS_SOURCE = (
    "1 / lambda_max of the (x, y) block of (J^T diag(k_q) J)^-1, J = dq/dX (4 x 3), the knob's moment free, "
    "weakest direction and pose over the workspace grid (links rigid, motors held; a direct-drive joint rigid)")
#: The twin's motor joints in the resolved device's order (knob pantograph first).
JOINTS = ("knob_q_left", "knob_q_right", "crank_q_left", "crank_q_right")


def has_capstan(design) -> bool:
    """True when a motor of the twin pantograph drives its joint through a capstan."""
    return design.family == "twin-pantograph" and any(
        t.is_capstan for t in resolve_device(design).transmissions)


def joint_ranges_deg(design) -> np.ndarray:
    """(4, 2) [[q_min, q_max]] of the four proximal links (:data:`JOINTS` order) over the
    workspace grid, deg, widened by :data:`CAPSTAN_RANGE_MARGIN_DEG` (module docstring).
    DesignError (``workspace``) when a sample cannot be reached."""
    ik = ktwin.ik(design.mechanism, design.workspace_points())
    return cr.ik_ranges_deg(ik.q_rad, ik.status)


def capstan_joints(design) -> tuple:
    """Each capstan-driven motor of the twin as a :class:`cad.datasheet.capstan_rows.CapstanJoint`
    (its link's range, :func:`joint_ranges_deg`; rows, BOM lines and assembly steps suffixed
    ``_1`` .. ``_4`` in :data:`JOINTS` order); empty for direct drive."""
    if not has_capstan(design):
        return ()
    labels = [f"{j.split('_')[0]} {j.split('_')[2]} proximal link" for j in JOINTS]
    return cr.capstan_joints_of(resolve_device(design), JOINTS, joint_ranges_deg(design), labels,
                                "the effective mass at home")


def handle_compliance_m_per_N(J: np.ndarray, kinv: np.ndarray, n_trans: int = 2) -> np.ndarray:
    """Translational compliance (n_trans, n_trans) m/N at the handle of one pose, the other
    coordinates' generalized forces (moments) free: the leading block of ``K_X^-1``,
    ``K_X = J^T diag(1 / kinv) J`` restricted to the null space of the rigid joints' rows
    (``kinv`` 0; zero when they hold the handle, three direct motors of the twin). ``J`` (m, d)
    dq/dX (SI; the twin's (4, 3) with ``n_trans`` 2 at the main journal, the pen's (6, 5) with
    ``n_trans`` 3 at its centre, :mod:`cad.families.pen.capstan`), ``kinv`` (m,) rad/(N m)."""
    rope = kinv > 0
    basis = np.eye(J.shape[1])
    if not rope.all():
        _, s, vt = np.linalg.svd(J[~rope])
        basis = vt[int(np.sum(s > s.max() * 1e-12)):].T  # (3, r) null space of the held joints
        if basis.shape[1] == 0:  # the held joints hold the handle: the ropes add nothing there
            return np.zeros((n_trans, n_trans))
    Jr = J[rope] @ basis
    K = Jr.T @ (Jr / kinv[rope][:, None])
    C = basis @ np.linalg.inv(K) @ basis.T
    return C[:n_trans, :n_trans]


def rope_compliance_m_per_N(design, k_q: dict) -> np.ndarray:
    """The handle's compliance from the ropes alone over the workspace grid, largest eigenvalue
    of :func:`handle_compliance_m_per_N` (m/N, (N,) over the reachable samples): the links rigid,
    the motors held, each rope a torsional spring ``k_q[joint]`` (N m/rad) at its joint."""
    J, st = ktwin.jacobian_si(design.mechanism, design.workspace_points())
    ok = np.asarray(st) == fb5.STATUS_OK
    kinv = np.array([1.0 / k_q[j] if k_q.get(j) else 0.0 for j in JOINTS])
    return np.array([np.linalg.eigvalsh(handle_compliance_m_per_N(Ji, kinv))[-1] for Ji in np.asarray(J)[ok]])
