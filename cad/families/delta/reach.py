"""Whether the delta reaches its ``[workspace]`` grid, checked before any solid is made (no
CAD import): the build's :func:`cad.families.delta.build.check_options` calls
:func:`check_workspace`, so a workspace out of reach or a motor range too narrow is one
line naming the field to change and how, not a kinematics error after the parts.

Which field is named (first match):

* ``workspace.center_mm``: the centre is above the base (the effector hangs below it, z < 0),
  or the centre itself is out of reach or singular; the line gives the z range the delta
  reaches on its axis (x = y = 0);
* ``mechanism.motor_angle_min_deg`` / ``motor_angle_max_deg``: every grid point is reachable
  and regular but some need a motor angle outside the range, or the centre does; the line
  gives the range the grid's reachable points need (the elbow-out IK of :mod:`cad.kinematics.delta`);
* ``workspace.size_mm`` (box) or ``workspace.diameter_mm`` / ``height_mm`` (cylinder): some grid
  points are out of reach, singular or out of the motor range while the centre is fine; the
  line gives the largest workspace of the same proportions about the same centre whose grid
  points are all ok (bisection on the scale to 1e-3).
"""

from __future__ import annotations

import math

import numpy as np

from cad.errors import DesignError
from cad.kinematics.delta import (
    STATUS_JOINT_LIMIT,
    STATUS_NAMES,
    STATUS_OK,
    ik,
    reach_box_mm,
)

#: Step (mm) of the axis scan that states the reachable z range in the centre's message.
AXIS_STEP_MM = 1.0


def axis_reach_mm(d) -> tuple[float, float] | None:
    """(lowest, highest) z (mm) on the base's axis (x = y = 0) where every arm reaches, no
    singularity and inside the motor range (``AXIS_STEP_MM`` grid), None when nowhere."""
    lo, _ = reach_box_mm(d)
    z = np.arange(lo[2], 0.0, AXIS_STEP_MM)
    ok = ik(d, np.column_stack([np.zeros_like(z), np.zeros_like(z), z])).ok
    return (float(z[ok].min()), float(z[ok].max())) if ok.any() else None


def largest_scale(d, X: np.ndarray, c: np.ndarray, tol: float = 1e-3) -> float:
    """The largest s in [0, 1] with every point c + s (X - c) ok (bisection to ``tol``; 0 when
    the centre is not ok)."""
    lo, hi = 0.0, 1.0
    if not ik(d, c[None, :]).ok[0]:
        return 0.0
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if np.all(ik(d, c + mid * (X - c)).ok) else (lo, mid)
    return lo


def _reach_text(d) -> str:
    zr = axis_reach_mm(d)
    return ("the delta reaches nowhere on its axis: check the link lengths" if zr is None else
            f"move it within reach: on the axis (x = y = 0) the delta reaches z = {zr[0]:g} .. {zr[1]:g} mm")


def _size_error(design, s: float, n_bad: int, first: str) -> DesignError:
    ws = design.workspace
    if ws["shape"] == "box":
        field, now = "workspace.size_mm", ws["size_mm"]
        fit = [math.floor(v * s * 10) / 10 for v in now]
        to = f"shrink it to at most [{', '.join(f'{v:g}' for v in fit)}] mm"
    else:
        field, now = "workspace.diameter_mm", f"{ws['diameter_mm']:g} (height_mm {ws['height_mm']:g})"
        fit = [math.floor(v * s * 10) / 10 for v in (ws["diameter_mm"], ws["height_mm"])]
        to = f"shrink diameter_mm / height_mm to at most {fit[0]:g} / {fit[1]:g} mm"
    return DesignError(field, f"{now} mm: {n_bad} of the {design.workspace_points().shape[0]} grid points "
                              f"are not ok, first {first}; {to} (about the same centre: every grid point "
                              "reached, regular and inside the motor range), or move workspace.center_mm")


def _motor_range_error(design, theta: np.ndarray, bad: np.ndarray, first: str) -> DesignError:
    d = design.mechanism
    need_lo, need_hi = (math.degrees(float(f(theta))) for f in (np.min, np.max))
    lo, hi = math.degrees(d.theta_min_rad), math.degrees(d.theta_max_rad)
    if need_lo < lo:
        return DesignError("mechanism.motor_angle_min_deg",
                           f"{lo:g} deg: the workspace needs the motors down to {need_lo:.1f} deg "
                           f"({int(bad.sum())} grid points outside {lo:g} .. {hi:g} deg, first {first}); "
                           f"set motor_angle_min_deg <= {math.floor(need_lo):g}, or move or shrink the workspace")
    return DesignError("mechanism.motor_angle_max_deg",
                       f"{hi:g} deg: the workspace needs the motors up to {need_hi:.1f} deg "
                       f"({int(bad.sum())} grid points outside {lo:g} .. {hi:g} deg, first {first}); "
                       f"set motor_angle_max_deg >= {math.ceil(need_hi):g}, or move or shrink the workspace")


def check_workspace(design) -> None:
    """Refuse a ``[workspace]`` grid the delta does not reach (module docstring):
    :class:`DesignError` naming the field to change, with the value that would do. Cost: one
    IK over the grid, and on a refusal an axis scan and a bisection (milliseconds)."""
    d = design.mechanism
    X = design.workspace_points()
    pose = ik(d, X)
    if pose.ok.all():
        return
    c = np.asarray(design.workspace["center_mm"], float)
    bad = ~pose.ok
    first = pose.describe(int(np.flatnonzero(bad)[0]))
    centre = ik(d, c[None, :])
    if c[2] >= 0:
        raise DesignError("workspace.center_mm", f"{c.tolist()} mm: the effector hangs below the base "
                                                 f"(z < 0, base frame z up); {_reach_text(d)}")
    if centre.status[0] not in (STATUS_OK, STATUS_JOINT_LIMIT):
        raise DesignError("workspace.center_mm", f"{c.tolist()} mm: the centre is "
                                                 f"{STATUS_NAMES[int(centre.status[0])]}; {_reach_text(d)}")
    limited = np.isin(pose.status, (STATUS_OK, STATUS_JOINT_LIMIT))
    if centre.status[0] == STATUS_JOINT_LIMIT or limited.all():
        lim = pose.status == STATUS_JOINT_LIMIT
        raise _motor_range_error(design, pose.theta_rad[limited], lim, pose.describe(int(np.flatnonzero(lim)[0])))
    raise _size_error(design, largest_scale(d, X, c), int(bad.sum()), first)
