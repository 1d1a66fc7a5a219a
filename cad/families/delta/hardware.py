"""The delta's hardware dimensions and materials (pure data, no CAD import), shared by the
part scripts (:mod:`.parts`), the assembly (:mod:`.assembly`) and the frame model
(:mod:`.structure`). mm and catalog keys. The design's ``[parts]`` table chooses the motor and
the encoder only (:class:`cad.families.delta.design.DeltaParts`); the dimensions below are the
family's fixed choices (the least link lengths they need: :mod:`.sizes`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from cad.data.catalog import get_bearing

#: The family's default motor (:data:`cad.data.catalog.MOTORS`); a design's ``[parts] motor``
#: chooses it (:class:`cad.families.delta.design.DeltaParts`).
MOTOR = "maxon-re35"


@dataclass(frozen=True)
class BallJoint:
    """A ball stud in a ball socket (the parallelogram's joints; all twelve alike).

    ball_d_mm, neck_d_mm, neck_mm: the stud's ball, its neck's diameter and length from
    the ball centre to the bar it is screwed into; socket_d_mm: the socket's outer sphere;
    clearance_mm: radial running clearance ball -> socket; cone_deg: half-angle of the
    socket's opening around its axis (the stud tilts up to about cone_deg - asin(neck_d /
    ball_d) before its neck meets the rim); mass_g: stud + socket.
    """

    designation: str
    ball_d_mm: float
    neck_d_mm: float
    neck_mm: float
    socket_d_mm: float
    clearance_mm: float
    cone_deg: float
    mass_g: float
    source: str


BALL_JOINT = BallJoint(
    designation="ball link, 4.8 mm ball, M2.5 stud (RC-model class)", ball_d_mm=4.8,
    neck_d_mm=2.5, neck_mm=7.0, socket_d_mm=7.5, clearance_mm=0.05, cone_deg=78.0, mass_g=1.2,
    source="unverified: generic dimensions of the 4.8 mm ball-link class, no vendor sheet "
           "read; replace with an ordered part's drawing")

#: Upper arm: a plate bar in the arm's plane (width in that plane x thickness along the motor
#: axis), joint bores at both ends; aluminium.
ARM_WIDTH_MM = 16.0
ARM_THICKNESS_MM = 6.0
ARM_MATERIAL = "aluminium-6061"
#: Hub clamping the arm on the motor shaft (along the axis, from the arm to the bracket less
#: the gap); with a joint offset the arm is a fork of two plates with a spacer between them.
HUB_D_MM = 12.0
#: Cross bars (elbow and effector): round bar along the motor axis, aluminium.
CROSS_BAR_D_MM = 8.0
#: Knee link (Stamper's joint offset g > 0): a plate bar like the upper arm. With a knee the
#: upper arm is a fork of two plates, cranked away from the side the knee folds to (the
#: knee's cross bar crosses the fork's planes when the knee folds back onto the arm): each
#: plate runs from the hub to a vertex seen from the knee pin at CRANK_ANGLE_DEG off the
#: arm line and g + w_a/2 + r_k away (:func:`crank_vertex_mm`; r_k the knee's outline about
#: its cross bar's axis, :func:`knee_outline_radius_mm`), then to the pin, so the knee's
#: cross bar and clevises clear the plates down to a fold of asin((w_a/2 + r_k) / g) -
#: CRANK_ANGLE_DEG (eq 1 of :mod:`.clearance`): -2.5 deg for the Falcon, whose knees fold to
#: 7.9 deg.
CRANK_ANGLE_DEG = 40.0
#: With a knee the motor brackets stand this much farther out along the motor axes (the
#: hub longer by as much): the rods hang from the knee, higher and farther in than from an
#: elbow, and the inner one sweeps the bracket's plane when the arm swings up (23.8 mm is the
#: least that clears the Falcon's 90 mm cube, :func:`.clearance.rod_bracket_gap_mm`; 30 leaves
#: 5.3 mm).
KNEE_BRACKET_OFFSET_MM = 30.0
#: Lower-arm rods: carbon tubes between the sockets.
ROD_OD_MM = 4.0
ROD_ID_MM = 3.0
ROD_MATERIAL = "carbon-fibre"
#: Effector: a disk of the effector radius + margin, thickness; handle: a knob below it.
EFFECTOR_THICKNESS_MM = 5.0
EFFECTOR_RIM_MM = 4.0
HANDLE_D_MM = 20.0
HANDLE_LENGTH_MM = 40.0
#: Ground: base plate thickness, margin past the motor brackets, bracket thickness, the gap
#: between the hub and the bracket, clearance above the arms' highest reach; the bracket
#: stands this far past the outer ball socket along the motor axis.
PLATE_THICKNESS_MM = 6.0
PLATE_RIM_MM = 10.0
BRACKET_THICKNESS_MM = 5.0
HUB_GAP_MM = 1.0
PLATE_CLEARANCE_MM = 5.0
BRACKET_CLEARANCE_MM = 3.0
PLATE_MATERIAL = "aluminium-6061"


def effector_disk_radius_mm(effector_radius_mm: float, width_mm: float) -> float:
    """Radius of the effector plate: past the farthest ball-joint centre by the margin."""
    return math.hypot(effector_radius_mm, width_mm / 2) + EFFECTOR_RIM_MM


def base_plate_z_mm(upper_arm_mm: float, theta_min_rad: float, joint_offset_mm: float) -> float:
    """Height of the base plate's underside above the motor axes: the highest elbow (at the
    lowest motor angle), the knee link, half the arm or socket, and the clearance."""
    up = upper_arm_mm * max(0.0, math.sin(-theta_min_rad)) + joint_offset_mm
    return up + max(ARM_WIDTH_MM, BALL_JOINT.socket_d_mm) / 2 + PLATE_CLEARANCE_MM


def crank_vertex_mm(upper_arm_mm: float, joint_offset_mm: float) -> tuple[float, float]:
    """(x, y) mm of the cranked fork plate's vertex in the plate's frame (x from the motor
    axis to the knee pin at (L_a, 0), y towards the side away from the knee): at
    CRANK_ANGLE_DEG off the arm line seen from the pin, g + w_a/2 + r_k from it (r_k:
    :func:`knee_outline_radius_mm`)."""
    r = joint_offset_mm + ARM_WIDTH_MM / 2 + knee_outline_radius_mm()
    a = math.radians(CRANK_ANGLE_DEG)
    return upper_arm_mm - r * math.cos(a), r * math.sin(a)


#: Stamper's knee hinge (g > 0): each rod's top end turns about the normal n_i of its
#: parallelogram's plane (the analyses' joint: :mod:`cad.families.delta.sim`,
#: :func:`cad.families.delta.structure.knee_arm`). The rod ends in an eye holding a deep
#: groove ball bearing (catalog designation, :func:`cad.data.catalog.get_bearing`) on a
#: ground pin along n_i through a clevis at the knee cross bar's end: two ears beside the
#: eye (an axial gap each side) and a bridge past the eye's radius towards the cross bar.
#: Layout choices (not a vendor part): the eye's wall round the bearing seat, the gaps, the
#: ears' thickness and radius round the pin, the bridge's depth.
KNEE_HINGE_BEARING = "623"
KNEE_EYE_WALL_MM = 1.5
KNEE_HINGE_GAP_MM = 0.5
KNEE_EYE_CLEARANCE_MM = 1.0
KNEE_EAR_THICKNESS_MM = 2.0
KNEE_EAR_RADIUS_MM = 3.5
KNEE_BRIDGE_MM = 3.0
KNEE_PIN_MATERIAL = "steel-1018"


@dataclass(frozen=True)
class KneeHinge:
    """The knee hinge's dimensions (mm), in the clevis's frame (origin the pin's centre, z the
    pin axis n_i, +y towards the cross bar's middle): the pin (the bearing's bore) and its
    length, the bearing (bore d, outside D, width B), the eye's radius, the ears' faces
    (z from ``ear_z0_mm`` to ``ear_z1_mm`` and mirrored), the bridge (y from ``bridge_y0_mm``
    to ``bridge_y1_mm``)."""

    bearing: str
    pin_d_mm: float
    pin_length_mm: float
    D_mm: float
    B_mm: float
    eye_r_mm: float
    ear_z0_mm: float
    ear_z1_mm: float
    bridge_y0_mm: float
    bridge_y1_mm: float


def knee_hinge() -> KneeHinge:
    """:class:`KneeHinge` of :data:`KNEE_HINGE_BEARING` and the layout choices above."""
    b = get_bearing(KNEE_HINGE_BEARING, "delta knee hinge bearing")
    z0 = b.B_mm / 2 + KNEE_HINGE_GAP_MM
    r_eye = b.D_mm / 2 + KNEE_EYE_WALL_MM
    y0 = r_eye + KNEE_EYE_CLEARANCE_MM
    return KneeHinge(b.designation, b.d_mm, 2 * (z0 + KNEE_EAR_THICKNESS_MM), b.D_mm, b.B_mm, r_eye,
                     z0, z0 + KNEE_EAR_THICKNESS_MM, y0, y0 + KNEE_BRIDGE_MM)


def knee_outline_radius_mm() -> float:
    """r_k (mm): the largest radius about the knee cross bar's axis of the knee's parts that
    cross the fork plates' planes -- the cross bar (d_c / 2) and the clevis at each end, whose
    section across the bar is 2 ``KNEE_EAR_RADIUS_MM`` (along the knee link) by 2 ear_z1
    (along the pin, :class:`KneeHinge`): its corner, hypot(r_ear, z1), 5.70 mm with the 623
    bearing. The eye and bearing stay within it where they cross the plates (the slow solid
    checks of ``tests/families/delta/test_delta_clearance.py``)."""
    h = knee_hinge()
    return max(CROSS_BAR_D_MM / 2, math.hypot(KNEE_EAR_RADIUS_MM, h.ear_z1_mm))
