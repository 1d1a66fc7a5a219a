"""The 3-DOF delta as part instances on bodies (:class:`cad.assembly.model.AssemblyModel`).

Bodies and frames: :mod:`cad.families.delta.layout`. Hardware: :mod:`.hardware`; part
scripts: :mod:`.parts` and :mod:`cad.parts.motor` (catalog motor, its shaft).

* ground: a round base plate above the arms' highest reach, three motor brackets hanging
  from it (one per motor, in the plane normal to the motor axis), three motors;
* upper_i: the motor shaft, a hub, the arm plate, and (g = 0) the elbow cross bar with two
  ball studs at +-w/2 along the motor axis; with Stamper's joint offset g > 0 the arm is a
  fork of two plates (a spacer between them at the hub) ending in a hinge, and knee_i
  carries the knee pin, one knee plate between the fork plates and the cross bar with its
  studs;
* lower_i_a / lower_i_b: a ball socket at each end (openings towards the cross bars) and
  the carbon tube between them;
* effector: the effector cross bars and their ball studs, the effector plate under them,
  the handle below.

With a ``[transmission]`` capstan the solids of :mod:`.capstan_solids` are added (drum
sectors, arm axles in bearings, moved motors with their capstans, rope runs).

Tangential stack along motor axis i (body y of upper_i, 0 = the arm's plane):
:func:`stack_mm`.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from cad.assembly.model import AssemblyModel
from cad.data import catalog as cat
from cad.data.catalog import clearance_hole_mm
from cad.device import parts_motor, resolve_device
from cad.families.delta import hardware as hw
from cad.families.delta import parts as dp
from cad.families.delta.capstan_solids import add_capstans
from cad.families.delta.fastening import place_fasteners
from cad.families.delta.layout import ARMS, body_poses, rot_x, rot_z
from cad.parts import PartInstance, PartKind, joints, translation
from cad.parts import motor as pm


@dataclasses.dataclass(frozen=True)
class DeltaLayout:
    """The delta's layout record (``AssemblyModel.extra``): the effector points of the
    motion ``workspace_mm`` (N, 3) and the exported one ``home_mm`` (3,), mm, base frame."""

    workspace_mm: np.ndarray
    home_mm: np.ndarray


def _frame(x, z, origin) -> np.ndarray:
    """4x4 with part x -> ``x``, part z -> ``z`` (unit, normal), at ``origin`` (mm)."""
    T = np.eye(4)
    T[:3, 0], T[:3, 2] = x, z
    T[:3, 1] = np.cross(z, x)
    T[:3, 3] = origin
    return T


def stack_mm(width_mm: float, fork: bool, socket_d_mm: float) -> dict[str, float]:
    """Positions along the motor axis (mm, 0 = the arm's plane, towards the motor negative):
    the arm plate (or, ``fork`` with a joint offset, the two fork plates and their spacer),
    the hub from the arm to the bracket less the gap, the bracket past the outer ball
    socket (``socket_d_mm``: :attr:`cad.families.delta.hardware.BallJoint.socket_d_mm`),
    the motor's face."""
    t = hw.ARM_THICKNESS_MM
    fork_mid = t + 0.5
    arm_end = -(fork_mid + t / 2) if fork else -t / 2
    bracket0 = -(width_mm / 2 + socket_d_mm / 2 + hw.BRACKET_CLEARANCE_MM)
    bracket0 = min(bracket0, arm_end - hw.HUB_GAP_MM - 5.0)
    if fork:
        bracket0 -= hw.KNEE_BRACKET_OFFSET_MM
    hub1 = bracket0 + hw.HUB_GAP_MM
    return {"hub_mid": (arm_end + hub1) / 2, "hub_length": arm_end - hub1,
            "bracket_near": bracket0, "motor_face": bracket0 - hw.BRACKET_THICKNESS_MM,
            "fork_mid": fork_mid, "spacer_length": 2 * fork_mid - t}


def kinds(design, fidelity: str = "fabrication") -> dict[str, PartKind]:
    """``{kind name: PartKind}`` of every distinct part of the delta."""
    d, w = design.mechanism, design.parallelogram_width_mm
    m = parts_motor(design)[0]  # parts.motor with the [motor] table (the resolved device's)
    bj = hw.design_ball_joint(design)
    K: dict[str, PartKind] = {}

    def add(name, shape, material, made, description, process, **kw):
        K[name] = PartKind(name=name, shape=shape, material=material, made=made,
                           description=description, process=process, **kw)

    side = pm.mount_side_mm(m)
    zb = hw.base_plate_z_mm(d.upper_arm_mm, d.theta_min_rad, d.joint_offset_mm, bj.socket_d_mm)
    fork = d.joint_offset_mm > 0
    st = stack_mm(w, fork, bj.socket_d_mm)
    r_base = math.hypot(d.base_radius_mm + abs(d.axis_offset_mm) + side / 2,
                        -st["motor_face"]) + hw.PLATE_RIM_MM
    add("base_plate", dp.disk_plate_shape(r_base, hw.PLATE_THICKNESS_MM), hw.PLATE_MATERIAL,
        True, f"base plate d{2 * r_base:.0f} x {hw.PLATE_THICKNESS_MM:g}",
        "waterjet/laser plate", plate=True)
    holes = [(x, -y, clearance_hole_mm(m.bolt_size)) for x, y in pm.motor_bolt_xy_mm(m)]
    add("motor_bracket", dp.bracket_shape(side, -side / 2, zb, hw.BRACKET_THICKNESS_MM,
                                          m.pilot_diameter_mm, holes),
        hw.PLATE_MATERIAL, True, f"motor bracket {side:g} x {zb + side / 2:.1f} x "
        f"{hw.BRACKET_THICKNESS_MM:g}", "waterjet/laser plate; bore the pilot seat", plate=True)
    add("motor", pm.motor_housing_shape(m), "steel-1018", False, m.bom_description(),
        "bought (direct drive, one per arm)", mass_kg=m.mass_kg)
    add("motor_shaft", pm.motor_shaft_shape(m), "steel-1018", False, "motor shaft",
        "part of the motor", inertia_model="none", listed=False)
    add("hub", dp.bar_shape(hw.HUB_D_MM, st["hub_length"], m.shaft_diameter_mm),
        hw.ARM_MATERIAL, True, f"arm hub d{hw.HUB_D_MM:g} x {st['hub_length']:g}",
        "turned; ream the shaft bore; bonded to the arm")
    if fork:
        add("arm_spacer", dp.bar_shape(hw.HUB_D_MM, st["spacer_length"]), hw.ARM_MATERIAL, True,
            f"spacer between the fork plates d{hw.HUB_D_MM:g} x {st['spacer_length']:g}", "turned")
    if fork:  # cranked away from the knee (hardware.CRANK_ANGLE_DEG)
        shape = dp.cranked_arm_shape(d.upper_arm_mm, hw.crank_vertex_mm(d.upper_arm_mm,
                                                                         d.joint_offset_mm),
                                     hw.ARM_WIDTH_MM, hw.ARM_THICKNESS_MM, m.shaft_diameter_mm,
                                     hw.CROSS_BAR_D_MM)
    else:
        shape = dp.arm_shape(d.upper_arm_mm, hw.ARM_WIDTH_MM, hw.ARM_THICKNESS_MM,
                             m.shaft_diameter_mm, hw.CROSS_BAR_D_MM)
    add("upper_arm", shape, hw.ARM_MATERIAL, True,
        f"upper arm{', cranked' if fork else ''}, {d.upper_arm_mm:g} mm between bores",
        "waterjet/laser plate; ream both bores", plate=True)
    bar = w - 2 * bj.neck_mm
    add("cross_bar", dp.bar_shape(hw.CROSS_BAR_D_MM, bar), hw.ARM_MATERIAL, True,
        f"cross bar d{hw.CROSS_BAR_D_MM:g} x {bar:g}, tapped for the ball studs both ends", "turned")
    if fork:
        add("knee_plate", dp.arm_shape(d.joint_offset_mm, hw.ARM_WIDTH_MM, hw.ARM_THICKNESS_MM,
                                       hw.CROSS_BAR_D_MM, hw.CROSS_BAR_D_MM),
            hw.ARM_MATERIAL, True, f"knee plate, {d.joint_offset_mm:g} mm between bores",
            "waterjet/laser plate; ream both bores", plate=True)
        pin = 2 * (st["fork_mid"] + hw.ARM_THICKNESS_MM / 2)
        add("knee_pin", dp.bar_shape(hw.CROSS_BAR_D_MM, pin), "steel-1018", True,
            f"knee pin d{hw.CROSS_BAR_D_MM:g} x {pin:g}", "ground dowel, cut")
        _knee_hinge_kinds(K, w)
    _joint_and_rod_kinds(K, design, bj)
    r_eff = hw.effector_disk_radius_mm(d.effector_radius_mm, w)
    add("effector_plate", dp.disk_plate_shape(r_eff, hw.EFFECTOR_THICKNESS_MM),
        hw.PLATE_MATERIAL, True, f"effector plate d{2 * r_eff:.1f} x {hw.EFFECTOR_THICKNESS_MM:g}",
        "waterjet/laser plate", plate=True)
    add("handle", dp.bar_shape(hw.HANDLE_D_MM, hw.HANDLE_LENGTH_MM), hw.PLATE_MATERIAL, True,
        f"handle d{hw.HANDLE_D_MM:g} x {hw.HANDLE_LENGTH_MM:g}", "turned")
    return K


def _joint_and_rod_kinds(K: dict, design, bj) -> None:
    """The ball stud and socket of catalog joint ``bj`` (:class:`cad.families.delta.hardware.
    BallJoint`) and the rod tubes between them (with a knee, from the eye to the socket)."""
    d, fork = design.mechanism, design.mechanism.joint_offset_mm > 0

    def add(name, shape, material, made, description, process, **kw):
        K[name] = PartKind(name=name, shape=shape, material=material, made=made,
                           description=description, process=process, **kw)

    # the catalog joint: stud and socket each half its mass (the split is not stated: assumed)
    add("ball_stud", dp.ball_stud_shape(bj.ball_d_mm, bj.neck_d_mm, bj.neck_mm), bj.material,
        False, f"{bj.designation}: stud ({bj.source})", "bought", mass_kg=bj.mass_g / 2e3)
    add("ball_socket", dp.socket_shape(bj.ball_d_mm, bj.clearance_mm, bj.socket_d_mm, bj.cone_deg,
                                       bj.shank_d_mm, hw.socket_shank_arg_mm(bj)),
        bj.socket_material, False, f"{bj.designation}: socket ({bj.source})", "bought",
        mass_kg=bj.mass_g / 2e3)
    rs = bj.tube_start_mm
    inside = rs < bj.shank_end_mm  # the socket's shank inside the tube (the generic link)
    if fork:
        r_eye = hw.knee_hinge().eye_r_mm
        add("knee_rod", dp.tube_shape(hw.ROD_OD_MM, hw.ROD_ID_MM, r_eye, d.lower_arm_mm - rs),
            hw.ROD_MATERIAL, True, f"rod tube {hw.ROD_OD_MM:g}/{hw.ROD_ID_MM:g} x "
            f"{d.lower_arm_mm - rs - r_eye:g}", "cut to length, bonded on the eye's and the socket's shanks" if inside else
            "cut to length, bonded on the eye's shank, joined to the socket's female thread")
    add("rod", dp.tube_shape(hw.ROD_OD_MM, hw.ROD_ID_MM, rs, d.lower_arm_mm - rs),
        hw.ROD_MATERIAL, True, f"rod tube {hw.ROD_OD_MM:g}/{hw.ROD_ID_MM:g} x "
        f"{d.lower_arm_mm - 2 * rs:g}", "cut to length, bonded on the socket shanks" if inside else
        "cut to length, joined to the sockets' female threads")


def _knee_hinge_kinds(K: dict, w: float) -> None:
    """The knee hinge's kinds (:func:`cad.families.delta.hardware.knee_hinge`): the knee's cross
    bar between the two clevises, the clevis, its pin, the bearing, the rod's eye."""
    h = hw.knee_hinge()
    bar = w - 2 * h.bridge_y1_mm

    def add(name, shape, material, made, description, process, **kw):
        K[name] = PartKind(name=name, shape=shape, material=material, made=made,
                           description=description, process=process, **kw)

    add("knee_cross_bar", dp.bar_shape(hw.CROSS_BAR_D_MM, bar), hw.ARM_MATERIAL, True,
        f"knee cross bar d{hw.CROSS_BAR_D_MM:g} x {bar:g}, the clevises bonded on both ends", "turned")
    add("knee_clevis", dp.clevis_shape(hw.KNEE_EAR_RADIUS_MM, h.pin_d_mm, h.ear_z0_mm, h.ear_z1_mm,
                                       h.bridge_y0_mm, h.bridge_y1_mm), hw.ARM_MATERIAL, True,
        f"knee clevis: ears {hw.KNEE_EAR_THICKNESS_MM:g} mm, gap {2 * h.ear_z0_mm:g} mm, pin bore "
        f"d{h.pin_d_mm:g} (the rod's hinge about the parallelogram's normal)",
        "milled; ream the pin bore through both ears")
    add("knee_hinge_pin", dp.bar_shape(h.pin_d_mm, h.pin_length_mm), hw.KNEE_PIN_MATERIAL, True,
        f"knee hinge pin d{h.pin_d_mm:g} x {h.pin_length_mm:g}", "ground dowel, cut")
    brg = cat.get_bearing(hw.KNEE_HINGE_BEARING, "delta knee hinge bearing")
    rings = joints.bearing_rings(brg.size)
    add("knee_bearing", joints.bearing_shape(brg.size, True), cat.BEARING_MATERIAL, False,
        f"deep groove ball bearing {brg.designation} ({brg.d_mm:g}x{brg.D_mm:g}x{brg.B_mm:g}), the "
        "knee hinge", "bought", inertia_model="ring", mass_kg=brg.mass_kg,
        ring_mm=(brg.d_mm / 2, brg.D_mm / 2, brg.B_mm), collision=(("other", rings[0]), ("self", rings[1])),
        revolution=True, hull=joints.bearing_shape(brg.size, False))
    add("rod_eye", dp.eye_shape(h.eye_r_mm, h.D_mm, h.B_mm, hw.ROD_ID_MM, 3.0), hw.ARM_MATERIAL, True,
        f"rod eye d{2 * h.eye_r_mm:g} x {h.B_mm:g}, the {brg.designation} bearing's seat d{h.D_mm:g}",
        "turned and milled; bore the bearing seat; the rod tube bonded on its shank")


def _ground_parts(design) -> list[tuple[str, str, np.ndarray]]:
    d = design.mechanism
    sd = hw.design_ball_joint(design).socket_d_mm
    st = stack_mm(design.parallelogram_width_mm, d.joint_offset_mm > 0, sd)
    zb = hw.base_plate_z_mm(d.upper_arm_mm, d.theta_min_rad, d.joint_offset_mm, sd)
    out = [("base_plate", "base_plate", translation(0, 0, zb))]
    for i in ARMS:
        u, t = d.radial[i], d.tangential[i]
        axis = d.base_radius_mm * u + d.axis_offset_mm * t
        out.append((f"motor_bracket_{i}", "motor_bracket",
                    _frame(u, -t, axis + st["bracket_near"] * t)))
        out.append((f"motor_{i}", "motor", _frame(u, t, axis + st["motor_face"] * t)))
    return out


def _studs(prefix: str, T_bar: np.ndarray, half_w: float) -> list[tuple[str, str, np.ndarray]]:
    """Cross bar at ``T_bar`` (its axis = part z) and a ball stud at each end, necks inwards."""
    out = [(f"{prefix}.cross_bar", "cross_bar", T_bar)]
    for side, s in (("a", -1.0), ("b", 1.0)):
        out.append((f"{prefix}.ball_stud_{side}", "ball_stud",
                    T_bar @ translation(0, 0, s * half_w) @ rot_x(0.0 if s < 0 else 180.0)))
    return out


def _upper_parts(design, i: int) -> list[tuple[str, str, np.ndarray]]:
    """``[(instance, kind, tf_body_part)]`` of upper_i (and knee_i's at key ``knee``)."""
    d, w = design.mechanism, design.parallelogram_width_mm
    fork = d.joint_offset_mm > 0
    st = stack_mm(w, fork, hw.design_ball_joint(design).socket_d_mm)
    along_y = rot_x(-90.0)  # part z -> body y
    p = f"upper_{i}"
    out = [(f"{p}.motor_shaft", "motor_shaft", translation(0, st["motor_face"], 0) @ along_y),
           (f"{p}.hub", "hub", translation(0, st["hub_mid"], 0) @ along_y)]
    if not fork:
        out.append((f"{p}.upper_arm", "upper_arm", rot_x(90.0)))
        return out + _studs(p, translation(d.upper_arm_mm, 0, 0) @ along_y, w / 2)
    out += [(f"{p}.upper_arm_{k}", "upper_arm", translation(0, s * st["fork_mid"], 0) @ rot_x(90.0))
            for k, s in enumerate((-1.0, 1.0))]
    return out + [(f"{p}.arm_spacer", "arm_spacer", along_y)]


def _knee_parts(design, i: int) -> list[tuple[str, str, np.ndarray]]:
    """knee_i: its pin in the fork, its plate, the cross bar and at each end a clevis with
    its hinge pin along the knee's z (the parallelogram's normal n_i = k_i x t_i), centred on
    the rod's joint point (g, -+w/2, 0); each clevis's bridge towards the bar's middle."""
    d, w = design.mechanism, design.parallelogram_width_mm
    along_y = rot_x(-90.0)
    p, g = f"knee_{i}", d.joint_offset_mm
    out = [(f"{p}.knee_pin", "knee_pin", along_y), (f"{p}.knee_plate", "knee_plate", rot_x(90.0)),
           (f"{p}.cross_bar", "knee_cross_bar", translation(g, 0, 0) @ along_y)]
    for side, s in (("a", -1.0), ("b", 1.0)):
        at = knee_hinge_tf(g, w, side)
        out += [(f"{p}.clevis_{side}", "knee_clevis", at @ (np.eye(4) if s < 0 else rot_z(180.0))),
                (f"{p}.hinge_pin_{side}", "knee_hinge_pin", at)]
    return out


def knee_hinge_tf(g_mm: float, w_mm: float, side: str) -> np.ndarray:
    """tf_knee_hinge: the hinge of rod ``side`` (``a`` at -w/2, ``b`` at +w/2) in knee_i's
    frame of :mod:`cad.families.delta.layout` (mm): origin the rod's joint point (g, -+w/2, 0),
    z the pin axis = the knee's z = the parallelogram's normal n_i."""
    return translation(g_mm, (-0.5 if side == "a" else 0.5) * w_mm, 0.0)


def _rod_parts(design, body: str, side: str) -> list[tuple[str, str, np.ndarray]]:
    """Sockets open towards the cross bar (+y for side a, -y for side b) and the tube; with
    Stamper's knee (g > 0) the top end is the hinge's eye about the rod's z (the
    parallelogram's normal) instead of a socket."""
    Lb = design.mechanism.lower_arm_mm
    open_y = rot_x(-90.0 if side == "a" else 90.0)
    if design.mechanism.joint_offset_mm > 0:
        return [(f"{body}.eye", "rod_eye", np.eye(4)), (f"{body}.rod", "knee_rod", np.eye(4)),
                (f"{body}.socket_bottom", "ball_socket", translation(Lb, 0, 0) @ open_y @ rot_z(180.0))]
    return [(f"{body}.socket_top", "ball_socket", open_y),
            (f"{body}.rod", "rod", np.eye(4)),
            (f"{body}.socket_bottom", "ball_socket", translation(Lb, 0, 0) @ open_y @ rot_z(180.0))]


def _effector_parts(design) -> list[tuple[str, str, np.ndarray]]:
    d, w = design.mechanism, design.parallelogram_width_mm
    zc = -hw.effector_plate_depth_mm(hw.design_ball_joint(design).socket_d_mm)
    out = [("effector.effector_plate", "effector_plate",
            translation(0, 0, zc - hw.EFFECTOR_THICKNESS_MM)),
           ("effector.handle", "handle",
            translation(0, 0, zc - hw.EFFECTOR_THICKNESS_MM - hw.HANDLE_LENGTH_MM / 2))]
    for i in ARMS:
        u, t = d.radial[i], d.tangential[i]
        out += _studs(f"effector.arm_{i}", _frame(u, t, d.effector_radius_mm * u), w / 2)
    return out


def assemble(design, fidelity: str = "fabrication") -> AssemblyModel:
    """The delta as an :class:`cad.assembly.model.AssemblyModel` (mm).

    Bodies: :func:`cad.families.delta.layout.body_names`. ``tf_world_body`` with the
    effector at the workspace centre; ``motion`` over the design's workspace grid
    (:meth:`DeltaDesign.workspace_points`, joint angles from the IK, elbow out), labelled
    ``"P = (x, y, z) mm"``. ``extra``: :class:`DeltaLayout` (the motion's effector points
    ``workspace_mm`` (N, 3), the exported one ``home_mm``). Raises :class:`cad.errors.KinematicsError` naming a
    workspace point that is unreachable, singular or outside the joint limits.
    """
    d = design.mechanism
    K = kinds(design, fidelity)
    X = design.workspace_points()
    home = np.asarray(design.workspace["center_mm"], float)
    motion = body_poses(d, X, design.parallelogram_width_mm)
    tf_home = {b: T[0] for b, T in body_poses(d, home, design.parallelogram_width_mm).items()}
    inst: list[PartInstance] = []

    def place(items, body):
        for name, kind, tf in items:  # an arm's motor shaft is its motor's own solid
            own = f"motor_{body.split('_')[1]}" if kind == "motor_shaft" else None
            inst.append(PartInstance(name, K[kind], body, np.asarray(tf, float), part_of=own))

    place(_ground_parts(design), "ground")
    for i in ARMS:
        place(_upper_parts(design, i), f"upper_{i}")
        if d.joint_offset_mm > 0:
            place(_knee_parts(design, i), f"knee_{i}")
        for side in ("a", "b"):
            place(_rod_parts(design, f"lower_{i}_{side}", side), f"lower_{i}_{side}")
    place(_effector_parts(design), "effector")
    if d.joint_offset_mm > 0:  # the knee hinges' bearings: outer ring in the eye, inner on the pin
        b_mm = K["knee_bearing"].ring_mm[2]
        inst += [PartInstance(f"lower_{i}_{s}.knee_bearing", K["knee_bearing"], f"lower_{i}_{s}",
                              translation(0, 0, -b_mm / 2), f"knee_{i}",
                              knee_hinge_tf(d.joint_offset_mm, design.parallelogram_width_mm, s)
                              @ translation(0, 0, -b_mm / 2))
                 for i in ARMS for s in ("a", "b")]
    holes: dict = {}
    if any(t.is_capstan for t in design.transmissions):  # the capstans' solids
        inst, holes = add_capstans(design, K, inst, resolve_device(design),
                            stack_mm(design.parallelogram_width_mm, d.joint_offset_mm > 0,
                                     hw.design_ball_joint(design).socket_d_mm))
    inst, screw_holes = place_fasteners(design, K, inst, stack_mm(design.parallelogram_width_mm,
                                                                  d.joint_offset_mm > 0,
                                                                  hw.design_ball_joint(design).socket_d_mm))
    holes = {**holes, **screw_holes}
    labels = tuple(f"P = ({x:.1f}, {y:.1f}, {z:.1f}) mm" for x, y, z in X)
    return AssemblyModel(design=design, instances=tuple(inst), tf_world_body=tf_home,
                         motion={b: T for b, T in motion.items() if b != "ground"},
                         pose_labels=labels, holes=holes, extra=DeltaLayout(X, home))
