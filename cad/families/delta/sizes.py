"""The least link lengths and width the delta's parts can be made at, checked when a design
loads (no CAD import): a value below one of them (most often metres typed for mm, 0.19 for
190) is refused with one line naming the field, the value, the least value and the part
that sets it, before any solid is made -- a tube or cross bar of zero or negative length
would otherwise stop OpenCASCADE with a construction error.

Each minimum comes from the parts of :mod:`cad.families.delta.hardware` (the design's ball
joint, :func:`cad.families.delta.hardware.ball_joint`, the arm hub, the cross bars, the knee
hinge of Stamper's joint offset g > 0) as :mod:`cad.families.delta.assembly` lays them out:

* ``lower_arm_mm`` (L_b, ball centre to ball centre): the rod tube is bonded on the shanks of
  its two end fittings, each starting ``tube_start_mm`` from its ball centre, so
  L_b >= 2 (tube_start + shank) = 13.5 mm with the 4.8 mm ball link (tube_start = socket_d / 2
  = 3.75 mm, 3 mm shank); with a knee (g > 0) the top fitting is the rod eye (radius r_eye):
  L_b >= r_eye + tube_start + 2 shank.
* ``parallelogram_width_mm`` (w, ball centre to ball centre along the motor axis): the cross
  bar between the studs' necks is w - 2 neck long, so w > 2 neck = 14 mm; with a knee the
  knee's cross bar between its clevises is w - 2 y1 long (y1: the clevis's bridge), w > 21 mm.
* ``upper_arm_mm`` (L_a): the hub (d 12) round the motor shaft and the elbow's cross bar
  (d 8) sit in the arm's two bores, so L_a > (d_hub + d_bar) / 2 = 10 mm.
* ``joint_offset_mm`` (g > 0): the knee plate holds the knee pin and the knee's cross bar
  (d 8 each) in its two bores, g > d_bar = 8 mm.
* ``effector_radius_mm`` (r): the effector's three cross bars lie on the sides of an
  equilateral triangle of inradius r (half side r sqrt 3), their ball links at +-w/2 from
  each side's middle; two adjacent arms' sockets near a corner are r sqrt 3 - w/2 apart, so
  r >= (w/2 + socket_d) / sqrt 3 (13.0 mm at w = 30).
* ``base_radius_mm`` (R): the motor axes are the sides of a triangle of inradius R and each
  arm's motor bracket stands w/2 + socket_d/2 + the bracket clearance from the arm's plane
  along its axis (30 mm farther with a knee); it must stand inside the triangle:
  R sqrt 3 > that (12.6 mm at w = 30).

These are the least sizes at which every part exists; the build's interference check over
the workspace (every pair of solids) still judges whether the parts clear each other.
"""

from __future__ import annotations

import math

from cad.data.ball_joints import DEFAULT_BALL_JOINT
from cad.errors import DesignError
from cad.families.delta import hardware as hw

#: The shank of a ball socket (and of the knee's rod eye) the rod tube is bonded on (mm):
#: the length :func:`cad.families.delta.assembly.kinds` gives ``socket_shape`` / ``eye_shape``.
SHANK_MM = 3.0


def minimums_mm(width_mm: float, joint_offset_mm: float,
                ball_joint: str = DEFAULT_BALL_JOINT) -> dict[str, tuple[float, bool, str]]:
    """{field: (least value mm, strict, the part that sets it)} of the delta's lengths for
    a parallelogram width ``width_mm``, a joint offset ``joint_offset_mm`` and the ball joint
    ``ball_joint`` (a key of :data:`cad.data.ball_joints.BALL_JOINTS`, the design's
    ``parts.ball_joint``; module docstring); ``strict``: the value must exceed the least one,
    else reach it."""
    bj, knee = hw.ball_joint(ball_joint), joint_offset_mm > 0
    rs = bj.socket_d_mm / 2
    top = (hw.knee_hinge().eye_r_mm if knee else bj.tube_start_mm) + SHANK_MM
    w_min = 2 * (hw.knee_hinge().bridge_y1_mm if knee else bj.neck_mm)
    bracket = width_mm / 2 + rs + hw.BRACKET_CLEARANCE_MM + (hw.KNEE_BRACKET_OFFSET_MM if knee else 0.0)
    out = {
        "lower_arm_mm": (top + bj.tube_start_mm + SHANK_MM, False,
                         ("the rod tube is bonded on the shanks of its rod eye and ball socket: r_eye + socket_d/2"
                          if knee else "the rod tube is bonded on the shanks of its two ball sockets: socket_d")
                         + f" + 2 x {SHANK_MM:g} mm shank ({bj.designation})"),
        "parallelogram_width_mm": (w_min, True,
                                   "the knee's cross bar between its clevises is w - 2 x "
                                   f"{w_min / 2:g} mm long" if knee else
                                   f"the cross bar between the ball studs' necks is w - 2 x {bj.neck_mm:g} mm "
                                   f"long ({bj.designation})"),
        "upper_arm_mm": ((hw.HUB_D_MM + hw.CROSS_BAR_D_MM) / 2, True,
                         f"the arm's bores hold the d{hw.HUB_D_MM:g} hub and the d{hw.CROSS_BAR_D_MM:g} "
                         "elbow cross bar"),
        "effector_radius_mm": ((width_mm / 2 + bj.socket_d_mm) / math.sqrt(3), False,
                               f"adjacent arms' d{bj.socket_d_mm:g} ball sockets at the effector must not "
                               f"meet: r >= (w/2 + socket_d) / sqrt 3 with parallelogram_width_mm = "
                               f"{width_mm:g}"),
        "base_radius_mm": (bracket / math.sqrt(3), True,
                           "each motor bracket must stand inside the triangle of the motor axes: "
                           f"R sqrt 3 > {bracket:g} mm (w/2 + socket_d/2 + the bracket clearance"
                           f"{' + the knee offset' if knee else ''}) with parallelogram_width_mm = {width_mm:g}"),
    }
    if knee:
        out["joint_offset_mm"] = (hw.CROSS_BAR_D_MM, True,
                                  f"the knee plate's bores hold the d{hw.CROSS_BAR_D_MM:g} knee pin and cross bar")
    return out


def check_sizes(values_mm: dict[str, float], ball_joint: str = DEFAULT_BALL_JOINT) -> None:
    """Refuse the first of ``values_mm`` ({mechanism field: mm}, with
    ``parallelogram_width_mm`` and ``joint_offset_mm``) below its least value
    (:func:`minimums_mm`): :class:`DesignError` naming ``mechanism.<field>``, the value, the
    least value and why. The width is checked first (the effector and base radii's least
    values depend on it)."""
    mins = minimums_mm(values_mm["parallelogram_width_mm"], values_mm.get("joint_offset_mm", 0.0), ball_joint)
    order = ["parallelogram_width_mm", "joint_offset_mm", "lower_arm_mm", "upper_arm_mm",
             "effector_radius_mm", "base_radius_mm"]
    for key in order:
        if key not in mins or key not in values_mm:
            continue
        least, strict, why = mins[key]
        v = values_mm[key]
        if v < least or (strict and v <= least):
            more = "" if key not in ("effector_radius_mm", "base_radius_mm") else (
                f" (or narrow parallelogram_width_mm, or a parts.ball_joint with a smaller housing than {ball_joint}'s)")
            raise DesignError(f"mechanism.{key}", f"must be {'>' if strict else '>='} {least:.4g} mm{more}, "
                                                  f"got {v:g}: {why}")
