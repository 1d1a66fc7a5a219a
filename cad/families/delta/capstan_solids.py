"""The delta's capstans as solids (issue 36 item 1): on each upper arm a drum sector about its
motor axis, the arm on its own axle, the motor and its bracket moved outwards (along the arm's
radial direction u_i) by the centre distance C with the capstan on its shaft, the two runs of
rope, added to the one instance list so the interference check over the workspace grid, the
mass properties (Lambda from the solids), the BOM and assembly.md read them.

Layout (mm, the upper arm's body frame of :mod:`cad.families.delta.layout`: x along the arm,
y the motor axis t_i, 0 = the arm's plane): the capstan starts 1 mm past the motor bracket's
near face on the motor shaft; the rope's plane is the middle of its turns; the drum sector,
:data:`cad.families.fourbar.capstan.DRUM_THICKNESS_MM` thick, is centred on that plane round
the arm's hub (its bore the hub's diameter). The drum's arc covers both tangent points over
the design's whole motor-angle range plus an anchor at each end
(:func:`cad.actuators.capstan_geometry.drum_arc_link_deg`: span 2 gamma + range + 2 anchor
arcs). The runs are fixed in the base frame between the external tangent points of the two
pitch circles (:func:`cad.actuators.capstan_geometry.external_tangent_points_mm`). The drum's
rim carries the rope's groove between its anchors as the four-bar's (:func:`cad.parts.capstan.
drum_sector_shape`: the groove's bottom the rope's inner side, the crests
:func:`cad.actuators.capstan_geometry.groove_depth_mm` above it, the arc
:func:`cad.assembly.capstan_hardware.drum_groove_arc_deg`), the capstan its helical groove.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from cad.actuators import capstan as cap
from cad.actuators import capstan_geometry as cg
from cad.assembly import capstan_hardware as fcs
from cad.data import catalog as cat
from cad.data.fits import fit
from cad.datasheet import capstan_rows as cr
from cad.families.delta import hardware as hw
from cad.families.delta import parts as dp
from cad.families.delta.capstan import shared
from cad.families.delta.layout import ARMS, body_poses, rot_x, rot_z
from cad.kinematics.delta import ik
from cad.parts import PartInstance, PartKind, joints, translation
from cad.parts import capstan as shapes
from cad.parts import motor as pm

#: The capstan's gap to the motor bracket's near face along the shaft, mm (a layout choice).
BRACKET_GAP_MM = 1.0
#: The moved motor's direction from the arm's axis, above the horizontal outwards (deg; a
#: layout choice): its bracket clears the arm's own bracket (C cos(35 deg) > the 55 mm plate) and stays
#: above the parallelogram's rods at every workspace point.
MOTOR_ELEVATION_DEG = 35.0


def motor_direction(d, i: int) -> np.ndarray:
    """(3,) unit base-frame direction from arm i's motor axis to its moved motor."""
    a = math.radians(MOTOR_ELEVATION_DEG)
    return math.cos(a) * d.radial[i] + math.sin(a) * np.array([0.0, 0.0, 1.0])


#: Part z -> part -x (a radial screw pointing at the axis, head out), as the four-bar's.
RY90 = np.array([[0.0, 0.0, 1.0, 0.0], [0.0, 1.0, 0.0, 0.0], [-1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]])
#: The drum's and capstan's part frame (z their axis) -> the upper arm's body frame (z -> y).
ALONG_Y = rot_x(-90.0)


def rope_plane_mm(design, t, stack: dict) -> tuple[float, float]:
    """(the capstan's start along the motor axis, the rope's plane), mm in the arm's frame."""
    y0 = stack["bracket_near"] + BRACKET_GAP_MM
    turns = cg.GROOVE_PITCH_D * t.cable_diameter_mm * t.wraps
    return y0, y0 + cg.CAPSTAN_HUB_MM + 0.5 * turns


def link_angle_deg(design, i: int, direction_world) -> tuple[float, float]:
    """(phi0, slope) of a base-frame direction in the drum's part angle (ccw from the arm in
    the drum's plane) as the motor angle theta turns: phi = phi0 + slope theta (deg)."""
    d = design.mechanism
    P = np.asarray(design.workspace["center_mm"], float)
    X = np.vstack([P, P + np.array([0.0, 0.0, 10.0])])
    th = np.degrees(ik(d, X).theta_rad[:, i])
    T = body_poses(d, X, design.parallelogram_width_mm)[f"upper_{i}"]
    phis = []
    for k in range(2):
        v = (T[k][:3, :3] @ ALONG_Y[:3, :3]).T @ np.asarray(direction_world, float)
        phis.append(math.degrees(math.atan2(v[1], v[0])))
    slope = (phis[1] - phis[0]) / (th[1] - th[0])
    slope = 1.0 if slope > 0 else -1.0
    return phis[0] - slope * th[0], slope


def arm_parts(design, i: int, t, K: dict, stack: dict) -> list[tuple[str, PartKind, np.ndarray]]:
    """The drum sector (with its two anchor screws) of upper_i, in its body frame."""
    d = design.mechanism
    dd, dc, rope = t.drum_diameter_mm, t.capstan_diameter_mm, t.cable_diameter_mm
    C = cap.centre_distance_mm(dc, dd, t.centre_distance_mm)
    g = cg.tangent_half_angle_rad(dd, dc, C)
    anchor = math.degrees(2.0 * cr.ANCHOR_LENGTH_MM / dd)
    phi0, s = link_angle_deg(design, i, motor_direction(d, i))
    lo, hi = sorted((phi0 + s * math.degrees(d.theta_min_rad), phi0 + s * math.degrees(d.theta_max_rad)))
    # the motor direction in link angles runs over [lo, hi]: the arc covers lo - g .. hi + g
    gd = math.degrees(g)
    start, span = lo - gd - anchor, (hi - lo) + 2 * gd + 2 * anchor
    _, yr = rope_plane_mm(design, t, stack)
    th = fcs.DRUM_THICKNESS_MM
    rd, h = cg.rim_radius_mm(dd, rope), cg.groove_depth_mm(rope)  # the groove's bottom, its depth
    anchors = (start + 0.5 * anchor, start + span - 0.5 * anchor)
    tap, depth = cat.tap_drill_mm(fcs.ANCHOR_SCREW), fcs.ANCHOR_SCREW_LENGTH_MM + pm.TAP_LEADOUT_MM
    desc, process = fcs.grooved_drum_texts(dd, rd, rope, span, th, "round the arm hub (bonded)",
                                           "bonded round the arm hub")
    kind = K.get("capstan_drum") or PartKind(
        "capstan_drum", shapes.drum_sector_shape(rd, hw.HUB_D_MM / 2, start, span, th,
                                                 tuple((a, tap, depth) for a in anchors), rope_diameter_mm=rope,
                                                 groove_arc_deg=fcs.drum_groove_arc_deg(rd, rope, anchors)),
        material=fcs.DRUM_MATERIAL, made=True,
        description=desc, process=process)
    K["capstan_drum"] = kind
    tf = translation(0, yr - th / 2, 0) @ ALONG_Y
    seat = rd + h  # the heads and the tensioner's nut sit on the crests
    at = [tf @ translation(0, 0, th / 2) @ rot_z(a) @ translation(seat, 0, 0) @ RY90 for a in anchors]
    return [(f"upper_{i}.capstan_drum", kind, tf), *_anchor_parts(i, t, K, at)]


def _anchor_parts(i: int, t, K: dict, at) -> list[tuple[str, PartKind, np.ndarray]]:
    """The rope's anchor screw at anchor 1 and the tensioner (a longer screw whose shank the
    rope's end winds on, and its lock nut on the rim) at anchor 2
    (:func:`cad.families.fourbar.capstan_solids.tensioner_screw_mm`)."""
    L, out = fcs.tensioner_screw_mm(t)
    if "capstan_anchor_screw" not in K:
        K["capstan_anchor_screw"] = dataclasses.replace(
            joints.cap_screw_kind(fcs.ANCHOR_SCREW, fcs.ANCHOR_SCREW_LENGTH_MM, "transmission",
                                  note="rope anchor on the drum"), name="capstan_anchor_screw")
        K["capstan_tensioner_screw"] = dataclasses.replace(
            joints.cap_screw_kind(fcs.ANCHOR_SCREW, L, "transmission",
                                  note="rope tensioner: the rope's end wound on its shank"),
            name="capstan_tensioner_screw")
        K["capstan_tensioner_nut"] = PartKind(
            "capstan_tensioner_nut", joints.nut_shape(fcs.ANCHOR_SCREW), material=cat.FASTENER_MATERIAL,
            made=False, description=f"hex nut ISO 4032 {fcs.ANCHOR_SCREW} (locks the rope tensioner)",
            process="bought", revolution=True)
    p = f"upper_{i}"
    return [(f"{p}.capstan_anchor_1", K["capstan_anchor_screw"], at[0]),
            (f"{p}.capstan_tensioner", K["capstan_tensioner_screw"], at[1] @ translation(0, 0, out)),
            (f"{p}.capstan_tensioner_nut", K["capstan_tensioner_nut"], at[1])]


def ground_parts(design, i: int, t, K: dict, stack: dict, motor) -> list[tuple[str, PartKind, np.ndarray]]:
    """The capstan on the moved motor's shaft and the two runs of rope of arm i (base frame)."""
    d = design.mechanism
    dd, dc, rope = t.drum_diameter_mm, t.capstan_diameter_mm, t.cable_diameter_mm
    C = cap.centre_distance_mm(dc, dd, t.centre_distance_mm)
    u, tt = d.radial[i], d.tangential[i]
    z = np.array([0.0, 0.0, 1.0])
    axis = d.base_radius_mm * u + d.axis_offset_mm * tt
    y0, yr = rope_plane_mm(design, t, stack)
    rc = cg.rim_radius_mm(dc, rope)
    length = cg.capstan_length_mm(rope, t.wraps)
    ck = K.get("capstan") or PartKind(
        "capstan", shapes.capstan_shape(rc, motor.shaft_diameter_mm, length, cg.CAPSTAN_HUB_MM / 2, pm.SET_SCREW,
                                        rope_diameter_mm=rope, wraps=t.wraps),
        material=cg.CAPSTAN_MATERIAL, made=True,
        description=(f"capstan {dc:g} mm pitch (rim {2 * rc:g} mm) on the motor shaft "
                     f"({motor.shaft_diameter_mm:g} mm bore), {length:g} mm long: {t.wraps:g} turns"),
        process=f"turned; tap {pm.SET_SCREW.split('-')[0]} x1 (radial)")
    K["capstan"] = ck
    frame = np.eye(4)
    frame[:3, 0], frame[:3, 1], frame[:3, 2] = u, np.cross(tt, u), tt
    frame[:3, 3] = axis + C * motor_direction(d, i) + y0 * tt
    size, Ls = fcs.capstan_set_screw(design, t)
    sk = K.get("capstan_set_screw") or PartKind(
        "capstan_set_screw", pm.set_screw_shape(Ls, size), material=cat.FASTENER_MATERIAL, made=False,
        description=f"set screw ISO 4026 {size.split('-')[0]} x {Ls:g} (capstan on the motor shaft)",
        process="bought")
    K["capstan_set_screw"] = sk
    out = [(f"capstan_{i}", ck, frame),
           (f"capstan_set_screw_{i}", sk, frame @ translation(0, 0, cg.CAPSTAN_HUB_MM / 2) @ RY90
            @ translation(0, 0, motor.shaft_diameter_mm / 2))]
    a = math.radians(MOTOR_ELEVATION_DEG)
    tang = cg.external_tangent_points_mm((0.0, 0.0), 0.5 * dd, (C * math.cos(a), C * math.sin(a)), 0.5 * dc)
    for k in range(2):
        p0, p1 = (axis + p[0] * u + p[1] * z + yr * tt for p in tang[k])
        kind = fcs.rope_run_kind(f"capstan_rope_run_{i}_{k + 1}", p0, p1, t, ROPE_TRIM_CLEARANCE_MM,
                                 f"free run {k + 1} of arm {i}'s rope",
                                 groove_depth_mm=cg.groove_depth_mm(t.cable_diameter_mm))
        out.append((kind.name, kind, np.eye(4)))
    return out


#: Clearance at which a rope run's collision envelope stops short of its pulleys (mm,
#: :func:`cad.assembly.capstan_hardware.run_trim_mm`).
ROPE_TRIM_CLEARANCE_MM = 0.2


def add_capstans(design, K: dict, inst: list[PartInstance], device, stack: dict) -> tuple[list, dict]:
    """(``inst`` with every capstan arm's solids, ``{name: TappedHole}`` of the capstans' set
    screws) (module docstring): the motor and its bracket moved out by C, the base plate grown
    to carry them, the motor shaft in the arm become the arm's axle, the drum sector on the
    arm, the capstan (its set screw's record: :func:`cad.assembly.capstan_hardware.
    capstan_set_screw_fastening`) and the rope runs on the ground.
    ``stack``: :func:`cad.families.delta.assembly.stack_mm` of the design."""
    d = design.mechanism
    mspec = cat.get_motor(design.parts.motor)
    brg = fcs.axle_bearing(mspec.shaft_diameter_mm)
    out, holes = list(inst), {}
    one = shared(device)
    for i in ARMS:
        t = device.transmission(f"theta_{i}")
        if not t.is_capstan:
            continue
        # arms with their own transmissions get their own capstan kinds (names "..._i")
        Ki = K if one else {k: v for k, v in K.items() if not k.startswith("capstan")}
        C = cap.centre_distance_mm(t.capstan_diameter_mm, t.drum_diameter_mm, t.centre_distance_mm)
        shift = translation(*(C * motor_direction(d, i)))
        new = []
        for k, x in enumerate(out):
            if x.name == f"motor_{i}":
                out[k] = dataclasses.replace(x, tf_body_part=shift @ x.tf_body_part)
            elif x.name == f"motor_bracket_{i}":  # moved for the motor; the arm's own: a bearing seat
                new.append(dataclasses.replace(x, name=f"capstan_motor_bracket_{i}", kind=_bracket(design, Ki, C),
                                               tf_body_part=shift @ x.tf_body_part))
                out[k] = dataclasses.replace(x, kind=_bearing_bracket(design, K, brg))
            elif x.name == f"upper_{i}.motor_shaft":
                out[k] = dataclasses.replace(x, name=f"upper_{i}.arm_axle", kind=_axle(K, x.kind, mspec),
                                             part_of=None)  # made, no longer the motor's
                out.append(PartInstance(f"capstan_motor_shaft_{i}", x.kind, "ground",
                                        shift @ _body_at_zero(design, i) @ x.tf_body_part, part_of=f"motor_{i}"))
        new += [PartInstance(n, k, f"upper_{i}", tf) for n, k, tf in arm_parts(design, i, t, Ki, stack)]
        f, hole = fcs.capstan_set_screw_fastening(design, t, f"capstan_{i}", f"capstan_motor_shaft_{i}")
        holes[hole.name] = hole
        new += [PartInstance(n, k, "ground", tf, fastener=f if n == f"capstan_set_screw_{i}" else None)
                for n, k, tf in ground_parts(design, i, t, Ki, stack, mspec)]
        out += new if one else [_tagged(x, f"_{i}") for x in new]
        out.append(_bearing(design, i, K, brg, stack))
    return _grown_base(design, K, out, device, stack), holes


def _tagged(x: PartInstance, tag: str) -> PartInstance:
    """``x`` with its capstan kind named for its arm (rope runs are per arm already)."""
    if "rope_run" in x.kind.name:
        return x
    return dataclasses.replace(x, kind=dataclasses.replace(x.kind, name=x.kind.name + tag))


def _bracket(design, K: dict, C: float) -> PartKind:
    """The moved motor's bracket: the arm's bracket shortened by the motor's rise, so it still
    hangs from the base plate's underside."""
    if "capstan_motor_bracket" not in K:
        d = design.mechanism
        m = cat.get_motor(design.parts.motor)
        side = pm.mount_side_mm(m)
        zb = hw.base_plate_z_mm(d.upper_arm_mm, d.theta_min_rad, d.joint_offset_mm,
                                hw.design_ball_joint(design).socket_d_mm) - C * math.sin(
            math.radians(MOTOR_ELEVATION_DEG))
        holes = [(x, -y, cat.clearance_hole_mm(m.bolt_size)) for x, y in pm.motor_bolt_xy_mm(m)]
        K["capstan_motor_bracket"] = dataclasses.replace(
            K["motor_bracket"], name="capstan_motor_bracket",
            shape=dp.bracket_shape(side, -side / 2, zb, hw.BRACKET_THICKNESS_MM, m.pilot_diameter_mm, holes),
            description=f"motor bracket {side:g} x {zb + side / 2:.1f} x {hw.BRACKET_THICKNESS_MM:g} "
                        "(the capstan's motor)")
    return K["capstan_motor_bracket"]


def _bearing_bracket(design, K: dict, brg) -> PartKind:
    """The arm's own bracket with the axle's bearing seat (the bearing's outer diameter) where
    the motor's pilot sat, no motor screw holes."""
    if "arm_bracket" not in K:
        d = design.mechanism
        side = pm.mount_side_mm(cat.get_motor(design.parts.motor))
        zb = hw.base_plate_z_mm(d.upper_arm_mm, d.theta_min_rad, d.joint_offset_mm,
                                hw.design_ball_joint(design).socket_d_mm)
        K["arm_bracket"] = dataclasses.replace(
            K["motor_bracket"], name="arm_bracket",
            shape=dp.bracket_shape(side, -side / 2, zb, hw.BRACKET_THICKNESS_MM, brg.D_mm, []),
            description=f"arm bracket {side:g} x {zb + side / 2:.1f} x {hw.BRACKET_THICKNESS_MM:g} "
                        f"(the arm axle's {brg.designation} bearing seat)",
            process="waterjet/laser plate; bore the bearing seat",
            fits=(fit("bearing seat", brg.D_mm),))
    return K["arm_bracket"]


def _bearing(design, i: int, K: dict, brg, stack: dict) -> PartInstance:
    """The arm axle's bearing in the arm bracket's seat, centred on the plate (outer ring on
    the ground, inner ring on upper_i)."""
    if "arm_bearing" not in K:
        rings = joints.bearing_rings(brg.size)
        K["arm_bearing"] = PartKind(
            "arm_bearing", joints.bearing_shape(brg.size, True), material=cat.BEARING_MATERIAL,
            made=False, description=f"deep groove ball bearing {brg.designation} ({brg.d_mm:g}x"
            f"{brg.D_mm:g}x{brg.B_mm:g}), the arm axle", process="bought", inertia_model="ring",
            mass_kg=brg.mass_kg, ring_mm=(brg.d_mm / 2, brg.D_mm / 2, brg.B_mm),
            collision=(("other", rings[0]), ("self", rings[1])), revolution=True,
            hull=joints.bearing_shape(brg.size, False))
    d = design.mechanism
    y = stack["bracket_near"] - 0.5 * hw.BRACKET_THICKNESS_MM - 0.5 * brg.B_mm
    u, tt = d.radial[i], d.tangential[i]
    frame = np.eye(4)
    frame[:3, 0], frame[:3, 1], frame[:3, 2] = u, np.cross(tt, u), tt
    frame[:3, 3] = d.base_radius_mm * u + d.axis_offset_mm * tt + y * tt
    return PartInstance(f"arm_bearing_{i}", K["arm_bearing"], "ground", frame, f"upper_{i}",
                        translation(0, y, 0) @ ALONG_Y)


def _axle(K: dict, shaft: PartKind, m) -> PartKind:
    if "arm_axle" not in K:
        K["arm_axle"] = dataclasses.replace(
            shaft, name="arm_axle", made=True, listed=True, material="steel-1018", inertia_model="solid",
            description=f"arm axle d{m.shaft_diameter_mm:g} (ground steel; the hub on it, in the "
                        "bracket's bore where the motor's pilot sat)", process="ground dowel, cut")
    return K["arm_axle"]


def _body_at_zero(design, i: int) -> np.ndarray:
    """tf_world_body of upper_i at motor angle 0 (the motor shaft's ground placement)."""
    d = design.mechanism
    u, tt = d.radial[i], d.tangential[i]
    T = np.eye(4)
    T[:3, 0], T[:3, 1] = u, tt
    T[:3, 2] = np.cross(u, tt)
    T[:3, 3] = d.base_radius_mm * u + d.axis_offset_mm * tt
    return T


def _grown_base(design, K: dict, inst: list[PartInstance], device, st: dict) -> list[PartInstance]:
    d = design.mechanism
    Cs = [cap.centre_distance_mm(t.capstan_diameter_mm, t.drum_diameter_mm, t.centre_distance_mm)
          for t in device.transmissions if t.is_capstan]
    side = pm.mount_side_mm(cat.get_motor(design.parts.motor))
    r = math.hypot(d.base_radius_mm + abs(d.axis_offset_mm) + max(Cs) + side / 2, -st["motor_face"]) + hw.PLATE_RIM_MM
    kind = dataclasses.replace(K["base_plate"], shape=dp.disk_plate_shape(r, hw.PLATE_THICKNESS_MM),
                               description=f"base plate d{2 * r:.0f} x {hw.PLATE_THICKNESS_MM:g}")
    return [dataclasses.replace(x, kind=kind) if x.name == "base_plate" else x for x in inst]
