"""The capstans of the haptic pen (issue 35): a capstan on any of its six motors (arm A waist,
lower shoulder, upper shoulder, then arm B's: :meth:`PantographDesign.motor_joints`). Pure
numpy (no CAD import); the rows, BOM lines and winding steps are the shared ones
(:mod:`cad.datasheet.capstan_rows`, through :mod:`cad.families.pantograph.capstan`), this
module only says where the pen's joints turn and how its ropes reach the pen.

* each joint's range: the joint angle over the workspace grid (``[workspace]``: the box and
  the rotation square, boundary included, :func:`cad.kinematics.haptic_pen.ik`), widened by
  :data:`cad.tolerances.CAPSTAN_RANGE_MARGIN_DEG` on each side, as on the 5-bar and the twin;
* the ropes at the pen: with the motors held and the links rigid, each rope a torsional spring
  ``k_q`` at its joint, the pen's stiffness in the quasi-velocities v = (x, y, z, w_yaw,
  w_pitch) is ``K_v = J^T diag(k_q) J`` (J = dq/dv, (6, 5),
  :func:`cad.kinematics.haptic_pen.jacobian_si`: six springs on five coordinates, the
  redundant actuation of isotropy paper §4.2); a force at the pen's centre with its moments
  free sees the translational (3, 3) block of ``K_v^-1``
  (:func:`cad.families.pantograph.twin_capstan.handle_compliance_m_per_N`, the twin's
  function: a direct-drive joint holds rigidly, the pen then moves only in the null space of
  its rows).

The waists' solids (drums on the waist brackets, the waist motors moved off their axes) are
:mod:`cad.families.pen.capstan_solids`, the shoulders' (drums on the proximal links, the
shoulder motors moved off their axes on the waist brackets' motor plates)
:mod:`cad.families.pen.shoulder_capstan`; where their motors sit is
:mod:`cad.families.pen.capstan_layout`, whose ``refuse_solids`` refuses every command that
needs them in one line naming ``transmission`` when a pair cannot be laid out.
"""

from __future__ import annotations

import numpy as np

from cad.datasheet import capstan_rows as cr
from cad.device import resolve_device
from cad.families.pantograph.twin_capstan import handle_compliance_m_per_N
from cad.kinematics import haptic_pen as kpen

#: The pen's motor joints in the resolved device's order (arm A first).
JOINTS = tuple(f"{a}_q_{j}" for a in ("A", "B") for j in ("waist", "lower", "upper"))
#: What each joint's drum turns (the rows' words).
LINKS = {"waist": "waist bracket", "lower": "lower proximal link", "upper": "upper proximal link"}
#: How the ropes' stiffness at the pen is computed (the datasheet row's model text).
HANDLE_STIFFNESS_SOURCE = (
    "1 / lambda_max of the (x, y, z) block of (J^T diag(k_q) J)^-1, J = dq/dv (6 x 5, v = (x, y, z, w_yaw, "
    "w_pitch)), the pen's moments free, weakest direction and pose over the workspace grid (links rigid, "
    "motors held; a direct-drive joint rigid)")


def pen_kind_group(joint: str) -> tuple[str, str, str]:
    """(group, suffix when the group's transmissions are the same, suffix when they differ) of
    a pen motor joint (``lay["capstan"]["kind_group"]`` of
    :func:`cad.families.pantograph.capstan_solids.kind_suffix`): both arms' motors of one role
    share a part kind (``_waist``), else one per arm (``_A_waist``)."""
    role = joint.split("_")[-1]
    return role, f"_{role}", f"_{joint[0]}_{role}"


def has_capstan(design) -> bool:
    """True when a motor of the haptic pen drives its joint through a capstan."""
    return design.family == "haptic-pen" and any(t.is_capstan for t in resolve_device(design).transmissions)


def joint_ranges_deg(design) -> np.ndarray:
    """(6, 2) [[q_min, q_max]] of the six motor joints (:data:`JOINTS` order) over the
    workspace grid, deg, widened by :data:`CAPSTAN_RANGE_MARGIN_DEG` (module docstring).
    DesignError (``workspace``) when a sample cannot be reached."""
    q, st = kpen.ik(design.mechanism, design.workspace_points())
    return cr.ik_ranges_deg(q, st)


def capstan_joints(design) -> tuple:
    """Each capstan-driven motor of the pen as a :class:`cad.datasheet.capstan_rows.CapstanJoint`
    (its joint's range, :func:`joint_ranges_deg`; rows, BOM lines and assembly steps suffixed
    ``_1`` .. ``_6`` in :data:`JOINTS` order); empty for direct drive."""
    if not has_capstan(design):
        return ()
    labels = [f"arm {j.split('_')[0]} {LINKS[j.split('_')[2]]}" for j in JOINTS]
    return cr.capstan_joints_of(resolve_device(design), JOINTS, joint_ranges_deg(design), labels,
                                "the effective mass at home and the MJCF armature")


def rope_compliance_m_per_N(design, k_q: dict) -> np.ndarray:
    """The pen's translational compliance from the ropes alone over the workspace grid,
    largest eigenvalue of the (3, 3) block of :func:`handle_compliance_m_per_N` (m/N, (N,)
    over the reachable samples): the links rigid, the motors held, each rope a torsional spring
    ``k_q[joint]`` (N m/rad) at its joint, the pen's moments free."""
    J, st = kpen.jacobian_si(design.mechanism, design.workspace_points())
    ok = np.asarray(st) == 0
    kinv = np.array([1.0 / k_q[j] if k_q.get(j) else 0.0 for j in JOINTS])
    return np.array([np.linalg.eigvalsh(handle_compliance_m_per_N(Ji, kinv, 3))[-1] for Ji in np.asarray(J)[ok]])

