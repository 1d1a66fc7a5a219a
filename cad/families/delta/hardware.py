"""The delta's hardware dimensions and materials (pure data, no CAD import), shared by the
part scripts (:mod:`.parts`), the assembly (:mod:`.assembly`) and the frame model
(:mod:`.structure`). mm and catalog keys: the design's ``[parts]`` table chooses the motor,
the encoder and the ball joints (``ball_joint``: :mod:`cad.data.ball_joints`;
:class:`cad.families.delta.design.DeltaParts`); the dimensions below are the family's fixed
choices (the least link lengths they need: :mod:`.sizes`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from cad.data.ball_joints import DEFAULT_BALL_JOINT, GENERIC_BALL_LINK, get_ball_joint
from cad.data.catalog import get_bearing

#: The family's default motor (:data:`cad.data.catalog.MOTORS`); a design's ``[parts] motor``
#: chooses it (:class:`cad.families.delta.design.DeltaParts`).
MOTOR = "maxon-re35"


#: The ball joints' running clearance ball -> socket in the drawn socket (mm, a layout choice).
BALL_CLEARANCE_MM = 0.05
#: Half-angle of the drawn socket's opening about the stud's centred axis (a layout choice,
#: the generic link's as before the catalog): the catalog's range less the neck's half-angle
#: from the ball centre is not drawn as the opening, so the solids' interference check does
#: not stand in for the range; :func:`cad.families.delta.ball_joints.range_check` checks the
#: catalog's range against the rods' angles.
BALL_OPENING_DEG = 78.0


@dataclass(frozen=True)
class BallJoint:
    """A ball stud in a ball socket (the parallelogram's joints; all twelve alike), the
    drawing's record of a catalog joint (:mod:`cad.data.ball_joints`, ``key``).

    ball_d_mm, neck_d_mm, neck_mm: the stud's ball, its neck's diameter and length from the
    ball centre to the shoulder on the bar it is screwed into; socket_d_mm: the socket's
    outer sphere; shank_d_mm, shank_end_mm: the socket's shank towards the rod (the catalog's
    spanner flats as a round) and its end from the ball centre; tube_start_mm: where the
    rod tube starts (the generic link's shank runs inside the tube from the socket's sphere;
    a DIN 71802 socket's female thread takes the rod at its shank end); clearance_mm: radial
    running clearance ball -> socket; cone_deg: half-angle of the drawn opening
    (:data:`BALL_OPENING_DEG`); range_deg: the catalog's tilt range; mass_g: the joint
    (stud + socket + nut); source: the catalog's BOM text and sources.
    """

    key: str
    designation: str
    ball_d_mm: float
    neck_d_mm: float
    neck_mm: float
    socket_d_mm: float
    shank_d_mm: float
    shank_end_mm: float
    tube_start_mm: float
    clearance_mm: float
    cone_deg: float
    range_deg: float
    mass_g: float
    material: str
    socket_material: str
    source: str


def ball_joint(key: str = DEFAULT_BALL_JOINT) -> BallJoint:
    """The :class:`BallJoint` of catalog joint ``key`` (a design's ``parts.ball_joint``;
    DesignError naming the keys for an unknown one)."""
    j = get_ball_joint(key)
    generic = j.key == GENERIC_BALL_LINK.key
    src = j.source_of("*") if generic else f"{j.bom_description()}; dimensions and mass: {j.source_of('ball_d_mm')}"
    return BallJoint(key=j.key, designation=j.designation, ball_d_mm=j.ball_d_mm,
                     neck_d_mm=j.neck_d_mm, neck_mm=j.shoulder_mm, socket_d_mm=j.socket_d_mm,
                     shank_d_mm=j.af_mm, shank_end_mm=j.shank_end_mm,
                     tube_start_mm=j.socket_d_mm / 2 if generic else j.shank_end_mm,
                     clearance_mm=BALL_CLEARANCE_MM, cone_deg=BALL_OPENING_DEG,
                     range_deg=j.range_deg, mass_g=j.mass_g, material=j.material,
                     socket_material=j.socket_material, source=src)


def socket_shank_arg_mm(bj: BallJoint) -> float:
    """The ``shank_mm`` argument of :func:`cad.families.delta.parts.socket_shape` that ends
    the drawn shank at ``bj.shank_end_mm`` from the ball centre: that function's shank runs
    from 0.75 r_s to 1.25 r_s + shank_mm (r_s = socket_d / 2; its docstring says r_s +
    shank_mm), so the generic link keeps its drawn 3 mm."""
    if bj.key == GENERIC_BALL_LINK.key:
        return 3.0
    return bj.shank_end_mm - 1.25 * bj.socket_d_mm / 2


def design_ball_joint(design) -> BallJoint:
    """:func:`ball_joint` of the design's ``parts.ball_joint``."""
    return ball_joint(design.parts.ball_joint)


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
#: Gap between the ball sockets' spheres and the effector plate below them (mm).
EFFECTOR_SOCKET_GAP_MM = 1.0
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


def base_plate_z_mm(upper_arm_mm: float, theta_min_rad: float, joint_offset_mm: float,
                    socket_d_mm: float) -> float:
    """Height of the base plate's underside above the motor axes: the highest elbow (at the
    lowest motor angle), the knee link, half the arm or the ball socket (``socket_d_mm``,
    :attr:`BallJoint.socket_d_mm`), and the clearance."""
    up = upper_arm_mm * max(0.0, math.sin(-theta_min_rad)) + joint_offset_mm
    return up + max(ARM_WIDTH_MM, socket_d_mm) / 2 + PLATE_CLEARANCE_MM


def effector_plate_depth_mm(socket_d_mm: float) -> float:
    """Depth of the effector plate's top below the effector cross bars' axes (mm): on the
    bars' underside, or, when the ball sockets' spheres (``socket_d_mm``) reach lower, under
    them by :data:`EFFECTOR_SOCKET_GAP_MM` (a socket turns about its ball centre, on the bar's
    axis, so its sphere's lowest point stays there; the bars then stand above the plate)."""
    if socket_d_mm / 2 <= CROSS_BAR_D_MM / 2:
        return CROSS_BAR_D_MM / 2  # the plate under the bars, the sockets within them
    return socket_d_mm / 2 + EFFECTOR_SOCKET_GAP_MM


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
