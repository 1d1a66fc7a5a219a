"""The capstans of a 5-bar pantograph as solids of its one assembly (issue 35): at each joint B
the proximal link's own axle (the hub clevis's set screw on it) in two deep groove ball bearings
seated in a bearing block screwed under the base plate where the motor's mount plate sat; the
drum sector on the link about B in the drums' band with its rope anchor and tensioner; the motor
(with its mount plate and screws) moved to ``B + C (cos alpha, sin alpha)``, the capstan and its
set screw on its shaft in the rope's plane, the two free runs of rope. Where each sits:
:mod:`cad.families.pantograph.capstan`; the solids: :mod:`cad.parts.capstan`; the anchors,
tensioner, capstan set screw and axle bearing as on the four-bar
(:mod:`cad.families.fourbar.capstan_solids`). mm, world z = 0 on the base plate's top.

The twin pantograph (:func:`cad.families.pantograph.twin_placement.group_layout`) uses the same
solids on each of its 5-bars with capstans: the crank pantograph's as the 5-bar's (motors under
the base plate), the knob pantograph's mirrored about z through the bridge's bottom
(:func:`mirrored`: bearing blocks on the bridge, motors on it, shafts down, capstans under it);
a crank drum in a second band has its motor raised (its mount plate on the base plate's top,
``raise_mm``); its joints are named as the resolved device's (``knob_q_left`` ..), its kinds and
instances carry the group in their names.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from cad.actuators import capstan_geometry as cg
from cad.assembly.capstan_hardware import (
    A1_LIP_MM,
    A1_WALL_MM,
    ANCHOR_SCREW,
    ANCHOR_SCREW_LENGTH_MM,
    capstan_set_screw,
    capstan_set_screw_fastening,
    drum_groove_arc_deg,
    grooved_drum_texts,
    rope_run_kind,
    tensioner_screw_mm,
)
from cad.assembly.capstan_hardware import axle_bearing as a1_bearing
from cad.assembly.fasteners import Fastener, TappedHole, size_cap_screw
from cad.data import catalog as cat
from cad.data.fits import fit
from cad.device import resolve_device
from cad.errors import DesignError
from cad.families.pantograph.capstan import DRUM_MATERIAL, DRUM_THICKNESS_MM
from cad.parts import PartInstance, PartKind, joints, motor, translation
from cad.parts import capstan as shapes

#: 4x4 rotation by +90 deg about y: a part's +z onto +x (a radial screw).
_RY90 = np.array([[0.0, 0.0, 1.0, 0.0], [0.0, 1.0, 0.0, 0.0], [-1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]])


def _rz(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    R = np.eye(4)
    R[:2, :2] = [[c, -s], [s, c]]
    return R


def mirrored(tf: np.ndarray, z_mm: float | None) -> np.ndarray:
    """A part's placement ``tf`` (4x4, mm) on the crank side mirrored about z onto the knob
    side: a height z above the base plate's top becomes ``z_mm - z``, the same height under the
    bridge's bottom ``z_mm``; the part turned over (its own y mirrored too, so the result is a
    rotation: parts symmetric about their x-z plane land as their mirror image); ``tf`` itself
    when ``z_mm`` is None."""
    if z_mm is None:
        return tf
    return translation(0, 0, z_mm) @ np.diag([1.0, 1.0, -1.0, 1.0]) @ tf @ np.diag([1.0, -1.0, 1.0, 1.0])


#: What a capstan's axle carries, by default the 5-bar's proximal link (``lay["capstan"]["carrier"]``
#: overrides any key: the haptic pen's waist bracket): the axle kind's name, the body's words (and
#: after the joint's group and side in the drum's words), what fixes the body on the axle, where
#: the axle stands.
CARRIER = {"axle": "proximal_axle", "link": "proximal link", "drum_link": "proximal link",
           "fixing": "the hub clevis's set screw on it", "at": "B"}


def carrier(lay: dict) -> dict:
    """:data:`CARRIER` with ``lay["capstan"]["carrier"]``'s keys over it."""
    return {**CARRIER, **lay.get("capstan", {}).get("carrier", {})}


def motor_key(design, lay: dict) -> str:
    """The catalog key of the motors a capstan layout moves: ``lay["capstan"]["motor"]`` (the
    haptic pen's waist motors), else ``parts.motor``."""
    return lay.get("capstan", {}).get("motor", design.parts.motor)


def joint_group(joint: str) -> str:
    """The twin's 5-bar prefix of a motor joint (``"knob_"`` of ``knob_q_left``); ``""`` on the 5-bar."""
    return joint[: joint.rindex("q_")]


def rope_index(design, joint: str) -> int:
    """The capstan's number in the rows, BOM lines and winding steps (``_1`` ..): the joint's
    place in the design's motor order (:meth:`motor_joints`: the 5-bar's left 1, right 2; the
    twin's knob then crank motors; the haptic pen's arm A then arm B, waist, lower, upper)."""
    return [j for j, _ in design.motor_joints()].index(joint) + 1


def plate_mm(design, lay: dict) -> float:
    """The thickness of the plate the bearing blocks and moved motors hang on (mm):
    ``lay["capstan"]["plate_mm"]`` (the haptic pen's shoulders: the waist bracket's motor
    plate), else ``parts.plate_thickness_mm`` (the base or bridge plate)."""
    return lay.get("capstan", {}).get("plate_mm", design.parts.plate_thickness_mm)


def mount_mm(design, lay: dict) -> float:
    """The thickness of a moved motor's own mount plate under that plate (mm):
    ``lay["capstan"]["mount_mm"]`` (0 for the haptic pen's shoulders: the motor face on the
    bracket's motor plate), else ``parts.motor_mount_thickness_mm``."""
    return lay.get("capstan", {}).get("mount_mm", design.parts.motor_mount_thickness_mm)


#: A through-bolt's thread past its nut, in thread pitches: every thread of the nut engaged
#: with the bolt's chamfered end out of it (rule of thumb; no standard cited: unverified).
BOLT_TAIL_PITCHES = 1.0


def block_fastening(design, lay: dict) -> dict:
    """How the bearing blocks are fastened to the plate they hang on (:func:`plate_mm`), the
    flange ``parts.motor_mount_thickness_mm`` thick: ``lay["screws"]["mount"]`` (the mount
    screws' plan, :func:`cad.families.pantograph.layout.screw_plan`) when the plate holds its
    minimum engagement (cap screws from the flange into tapped holes; resized by
    :func:`cad.assembly.fasteners.size_cap_screw` when the plate is not the plan's), else a
    through-bolt: the plan's thread from the plate's free side through a clearance hole in the
    plate and the flange, an ISO 7089 washer and ISO 4032 nut under the flange (``through``
    True; ``clamp_mm`` plate + flange, ``washer_h_mm``, ``nut_m_mm``, ``length_mm`` the shortest
    catalog length >= clamp + washer + nut + :data:`BOLT_TAIL_PITCHES` pitch, ``engagement_mm``
    the nut's height, ``tail_mm`` past the nut). mm. DesignError (``parts.motor_mount_thickness_mm``)
    when no catalog length reaches."""
    sp = lay["screws"]["mount"]
    pl = plate_mm(design, lay)
    if pl >= sp["min_engagement_mm"] - 1e-9:
        if abs(pl - sp["depth_mm"]) < 1e-9:
            return sp
        hole = TappedHole("block", "plate", sp["size"], pl, sp["min_engagement_mm"])
        L, e = size_cap_screw(sp["size"], sp["clamp_mm"], hole, sp["joint"], "parts.motor_mount_thickness_mm")
        return {**sp, "length_mm": L, "engagement_mm": e, "depth_mm": pl}
    size = sp["size"]
    w, n = cat.get_washer(size, "parts"), cat.get_nut(size, "parts")
    clamp = pl + design.parts.motor_mount_thickness_mm
    tail = BOLT_TAIL_PITCHES * float(size.split("-")[1])
    need = clamp + w.h_mm + n.m_mm + tail
    L = cat.shortest_length(cat.get_cap_screw(size, "parts").lengths_mm, need)
    if L is None:
        raise DesignError("parts.motor_mount_thickness_mm", f"bearing block through-bolts: no ISO 4762 "
                          f"{size.split('-')[0]} length reaches {need:g} mm (plate and flange {clamp:g} mm, "
                          "washer, nut and a thread past it)")
    return {"size": size, "through": True, "clamp_mm": clamp, "washer_h_mm": w.h_mm, "nut_m_mm": n.m_mm,
            "length_mm": L, "engagement_mm": n.m_mm, "tail_mm": L - clamp - w.h_mm - n.m_mm,
            "joint": "bearing block through-bolted to its plate"}


def block_height_mm(design, motor_key: str | None = None) -> float:
    """The bearing block's height (mm): two bearing seats and the lip between them; the
    bearings' bore the shaft's of ``motor_key`` (default ``parts.motor``)."""
    brg = a1_bearing(cat.get_motor(motor_key or design.parts.motor).shaft_diameter_mm)
    return 2 * brg.B_mm + A1_LIP_MM


def axle_kind(design, lay: dict) -> PartKind:
    """The proximal link's axle: the motor shaft's diameter, from the bearing block's bottom to
    the hub clevis's top (``lay["capstan"]["axle_top_mm"]`` when given, and the body it
    carries :func:`carrier`)."""
    p = design.parts
    m = cat.get_motor(motor_key(design, lay))
    brg = a1_bearing(m.shaft_diameter_mm)
    z0 = -plate_mm(design, lay) - block_height_mm(design, m.key)
    top = lay.get("capstan", {}).get("axle_top_mm")
    top = lay["lower_layers_z_mm"][0] + p.clevis_height_mm / 2 if top is None else top
    L = top - z0
    c = carrier(lay)
    return PartKind(c["axle"], shapes.axle_shape(m.shaft_diameter_mm, L), material=cg.CAPSTAN_MATERIAL,
                    made=True, description=f"{c['link']} axle d{m.shaft_diameter_mm:g} x {L:g} mm at {c['at']} (in two "
                    f"{brg.designation} bearings, {c['fixing']})",
                    process="turned; grind the journals",
                    fits=(fit("journal", m.shaft_diameter_mm, "bearing journal"),), revolution=True)


def axle_z_mm(design, motor_key: str | None = None, plate: float | None = None) -> float:
    """The axle's bottom (mm, world z): the bearing block's bottom (:func:`block_height_mm`)
    under a plate ``plate`` mm thick (default ``parts.plate_thickness_mm``)."""
    return -(design.parts.plate_thickness_mm if plate is None else plate) - block_height_mm(design, motor_key)


def capstan_kinds(design, lay: dict) -> dict[str, PartKind]:
    """The capstan drive's part kinds by name (the axle, bearing block and its bearing, each
    side's drum, the anchor screw, the tensioner screw and nut, the capstan and its set screw)."""
    p = design.parts
    m = cat.get_motor(motor_key(design, lay))
    brg = a1_bearing(m.shaft_diameter_mm)
    rings = joints.bearing_rings(brg.size)
    c = carrier(lay)
    K = {"proximal_axle": axle_kind(design, lay)}
    K["bearing_block"] = PartKind(
        "bearing_block",
        shapes.bearing_block_shape(motor.mount_side_mm(m), p.motor_mount_thickness_mm, motor.mount_hole_xy_mm(m),
                                   cat.clearance_hole_mm(motor.MOUNT_SCREW), brg.D_mm, brg.B_mm, A1_LIP_MM,
                                   brg.Da_mm, A1_WALL_MM),
        material=p.plate_material, made=True,
        description=(f"bearing block at {c['at']}: {motor.mount_side_mm(m):g} mm square flange, boss with two "
                     f"{brg.designation} bearing seats and a {A1_LIP_MM:g} mm lip (the {c['link']}'s axle)"),
        process=(f"machined from {block_height_mm(design, m.key):g} mm plate: mill the boss, bore the seats from both "
                 f"sides; drill {motor.MOUNT_SCREW.split('-')[0]} clearance x4"),
        fits=(fit("bearing seat", brg.D_mm),))
    K["axle_bearing"] = PartKind(
        f"bearing_{brg.size}", joints.bearing_shape(brg.size, True), material=cat.BEARING_MATERIAL, made=False,
        description=f"deep groove ball bearing {brg.designation} ({brg.d_mm:g}x{brg.D_mm:g}x{brg.B_mm:g}), "
        f"{c['link']} axle at {c['at']}", process="bought", inertia_model="ring", mass_kg=brg.mass_kg,
        ring_mm=(brg.d_mm / 2, brg.D_mm / 2, brg.B_mm), collision=(("other", rings[0]), ("self", rings[1])),
        revolution=True, hull=joints.bearing_shape(brg.size, False))
    dev = resolve_device(design)
    for sd in lay["capstan"]["sides"]:
        K[f"drum_{sd.joint}"] = _drum_kind(design, dev.transmission(sd.joint), sd, lay)
    for sd in lay["capstan"]["sides"]:
        t = dev.transmission(sd.joint)
        sfx = kind_suffix(design, sd.joint, lay)
        K[f"capstan{sfx}"] = _capstan_kind(design, t, sfx, m.key)
        size, Ls = capstan_set_screw(design, t, m.key)
        K[f"capstan_set_screw{sfx}"] = PartKind(
            f"capstan_set_screw{sfx}", motor.set_screw_shape(Ls, size), material=cat.FASTENER_MATERIAL,
            made=False, process="bought",
            description=f"set screw ISO 4026 {size.split('-')[0]} x {Ls:g} (capstan on the motor shaft)")
        L, _ = tensioner_screw_mm(t)
        K[f"tensioner{sfx}"] = dataclasses.replace(
            joints.cap_screw_kind(ANCHOR_SCREW, L, "transmission",
                                  note="rope tensioner: the rope's end wound on its shank"),
            name=f"capstan_tensioner_screw{sfx}")
    bf = block_fastening(design, lay) if "screws" in lay else {}
    if bf.get("through"):
        K["block_bolt"] = dataclasses.replace(  # named apart from the tapped screws of one length
            joints.cap_screw_kind(bf["size"], bf["length_mm"], "parts", note="bearing block through-bolt, nut under "
                                  "the flange"), name=f"block_bolt_{bf['size']}x{bf['length_mm']:g}")
        w = cat.get_washer(bf["size"], "parts")
        K["block_washer"] = PartKind(f"block_washer_{w.size}", joints.washer_shape(bf["size"]), material=cat.FASTENER_MATERIAL,
                                     made=False, process="bought", revolution=True,
                                     description=f"plain washer ISO 7089 {w.size}",
                                     collision=(("self", joints.ring_shape(0.0, w.d2_mm / 2, w.h_mm)),))
        K["block_nut"] = PartKind(f"block_nut_{bf['size'].split('-')[0]}", joints.nut_shape(bf["size"]),
                                  material=cat.FASTENER_MATERIAL, made=False, process="bought", revolution=True,
                                  description=f"hex nut ISO 4032 {bf['size']} (bearing block through-bolt)")
    K["anchor_screw"] = dataclasses.replace(
        joints.cap_screw_kind(ANCHOR_SCREW, ANCHOR_SCREW_LENGTH_MM, "transmission", note="rope anchor on the drum"),
        name="capstan_anchor_screw")
    K["tensioner_nut"] = PartKind("capstan_tensioner_nut", joints.nut_shape(ANCHOR_SCREW),
                                  material=cat.FASTENER_MATERIAL, made=False, process="bought", revolution=True,
                                  description=f"hex nut ISO 4032 {ANCHOR_SCREW} (locks the rope tensioner)")
    return K


def fivebar_kind_group(joint: str) -> tuple[str, str, str]:
    """(group, suffix when the group's transmissions are the same, suffix when they differ) of a
    motor joint, the 5-bar's and the twin's: the motors of one 5-bar share a part kind (``""`` /
    ``_left``; the twin's ``_knob`` / ``_knob_left``). A family that groups its capstans otherwise
    gives its own function as ``lay["capstan"]["kind_group"]`` (the haptic pen's
    :func:`cad.families.pen.capstan.pen_kind_group`)."""
    grp = joint_group(joint)
    pre = f"_{grp[:-1]}" if grp else ""
    return grp, pre, f"{pre}_{joint.split('_')[-1]}"


def kind_suffix(design, joint: str, lay: dict) -> str:
    """The part-kind suffix of a joint's capstan, tensioner and set screw: one kind for every
    motor of the joint's group when their transmissions are the same, else one per motor
    (:func:`fivebar_kind_group`, or ``lay["capstan"]["kind_group"]``)."""
    group_of = lay.get("capstan", {}).get("kind_group", fivebar_kind_group)
    key, same_sfx, differ_sfx = group_of(joint)
    ts = [t for t in resolve_device(design).transmissions if group_of(t.motor_joint)[0] == key]
    same = all(dataclasses.replace(t, motor_joint="") == dataclasses.replace(ts[0], motor_joint="") for t in ts)
    return same_sfx if same else differ_sfx


def _drum_kind(design, t, sd, lay: dict) -> PartKind:
    d = t.cable_diameter_mm
    rd = cg.rim_radius_mm(t.drum_diameter_mm, d)
    bore = cat.get_motor(motor_key(design, lay)).shaft_diameter_mm / 2
    tap = cat.tap_drill_mm(ANCHOR_SCREW)
    depth = ANCHOR_SCREW_LENGTH_MM + motor.TAP_LEADOUT_MM
    th = DRUM_THICKNESS_MM
    side, grp = sd.joint.split("_")[-1], joint_group(sd.joint)
    desc, process = grooved_drum_texts(t.drum_diameter_mm, rd, d, sd.arc_span_deg, th,
                                       f"on the {grp.replace('_', ' ')}{side} {carrier(lay)['drum_link']}'s axle at {carrier(lay)['at']}",
                                       "ream the axle bore, pinned to the axle")
    return PartKind(
        f"{grp}capstan_drum_{side}",
        shapes.drum_sector_shape(rd, bore, sd.arc_start_deg, sd.arc_span_deg, th,
                                 tuple((a, tap, depth) for a in sd.anchors_deg),
                                 rope_diameter_mm=d, groove_arc_deg=drum_groove_arc_deg(rd, d, sd.anchors_deg)),
        material=DRUM_MATERIAL, made=True,
        description=desc, process=process)


def _capstan_kind(design, t, sfx: str, motor_key: str) -> PartKind:
    m = cat.get_motor(motor_key)
    d = t.cable_diameter_mm
    rc = cg.rim_radius_mm(t.capstan_diameter_mm, d)
    length = cg.capstan_length_mm(d, t.wraps)
    return PartKind(
        f"capstan{sfx}", shapes.capstan_shape(rc, m.shaft_diameter_mm, length, cg.CAPSTAN_HUB_MM / 2, motor.SET_SCREW,
                                           rope_diameter_mm=d, wraps=t.wraps),
        material=cg.CAPSTAN_MATERIAL, made=True,
        description=(f"capstan {t.capstan_diameter_mm:g} mm pitch (rim {2 * rc:g} mm) on the motor shaft, "
                     f"{length:g} mm long: {t.wraps:g} turns of the {d:g} mm rope at {cg.GROOVE_PITCH_D:g} d "
                     f"pitch above a {cg.CAPSTAN_HUB_MM:g} mm set-screw hub"),
        process=f"turned; tap {motor.SET_SCREW.split('-')[0]} x1 (radial)",
        fits=(fit("hub shaft bore", m.shaft_diameter_mm, "shaft bore"),))


def capstan_z_mm(design, t, rope_z_mm: float) -> float:
    """The capstan's bottom (mm, world z): the middle of its turns in the rope's plane."""
    return rope_z_mm - cg.CAPSTAN_HUB_MM - 0.5 * cg.GROOVE_PITCH_D * t.cable_diameter_mm * t.wraps


def capstan_span_mm(design, t, lay: dict) -> tuple[float, float, float]:
    """``(bottom, top, hub top)`` of the capstan on a moved motor's shaft (mm, the layout's z):
    the middle of its turns in the rope's plane, its set-screw hub under the turns (towards the
    motor, :func:`capstan_z_mm`), or turned over, the hub beyond the turns when
    ``lay["capstan"]["hub_out"]`` (a rope plane so near the plate that the hub would reach
    into it: the haptic pen's band by its shoulder motor plate)."""
    zr = lay["capstan"]["rope_z_mm"]
    zc = capstan_z_mm(design, t, zr)
    n = cg.capstan_length_mm(t.cable_diameter_mm, t.wraps)
    if lay["capstan"].get("hub_out"):
        return 2 * zr - zc - n, 2 * zr - zc, 2 * zr - zc
    return zc, zc + n, zc + cg.CAPSTAN_HUB_MM


def block_parts(design, K: dict, lay: dict, i: int, side: str, b, screw_kind,
                tf_world_link: np.ndarray, body: str | None = None) -> tuple[list, dict]:
    """The bearing block at joint ``b`` with its two bearings (inner ring on the proximal link)
    and its four fasteners (:func:`block_fastening`): screws into the plate's tapped holes
    (``screw_kind``), or through-bolts from the plate's free side (their heads there) with a
    washer and nut under the flange, each nut the hole its bolt engages; (instances, holes).
    The plate :func:`plate_mm` thick, its free face at z = 0. On the twin's knob pantograph
    (``lay["capstan"]["mirror_z_mm"]`` set) all of it mirrored onto the bridge (:func:`mirrored`),
    the screws in the bridge plate; ``side`` the link's body name without ``proximal_``
    (``left``, ``knob_left``); ``body`` the body the bearings' inner rings turn with (default:
    that link's); ``lay["capstan"]["plate"]`` the plate's instance name (default
    ``base_plate`` / ``bridge_plate``)."""
    p = design.parts
    m = cat.get_motor(motor_key(design, lay))
    pt = plate_mm(design, lay)
    z0, h = axle_z_mm(design, m.key, pt), block_height_mm(design, m.key)
    zm = lay["capstan"].get("mirror_z_mm")
    plate = lay["capstan"].get("plate", "base_plate" if zm is None else "bridge_plate")
    B = K["axle_bearing"].ring_mm[2]
    name, link = f"bearing_block_{i}", f"proximal_{side}"
    if "_" in side:
        link = f"{side.split('_')[0]}_proximal_{side.split('_')[1]}"
    body = body or link
    out = [PartInstance(name, K["bearing_block"], "ground", mirrored(translation(b[0], b[1], z0), zm))]
    tf_link = np.linalg.inv(tf_world_link)
    for k, z in enumerate((z0 + h - B, z0)):
        tf = mirrored(translation(b[0], b[1], z), zm)
        out.append(PartInstance(f"{name}.bearing_{k + 1}", K["axle_bearing"], "ground", tf, body, tf_link @ tf))
    sp = block_fastening(design, lay)
    holes = {}
    flip = np.diag([1.0, -1.0, -1.0, 1.0])
    for k, (x, y) in enumerate(motor.mount_hole_xy_mm(m)):
        if sp.get("through"):
            nut, washer = f"{name}.nut_{k + 1}", f"{name}.washer_{k + 1}"
            zf = -pt - p.motor_mount_thickness_mm  # the flange's free face
            holes[nut] = TappedHole(nut, nut, sp["size"], sp["nut_m_mm"], sp["nut_m_mm"])
            f = Fastener("ISO 4762", sp["size"], sp["length_mm"], (plate, name, washer), nut, sp["engagement_mm"])
            out += [PartInstance(f"{name}.bolt_{k + 1}", K["block_bolt"], "ground",
                                 mirrored(translation(b[0] + x, b[1] + y, 0.0), zm), fastener=f),
                    PartInstance(washer, K["block_washer"], "ground",
                                 mirrored(translation(b[0] + x, b[1] + y, zf - sp["washer_h_mm"]), zm)),
                    PartInstance(nut, K["block_nut"], "ground", mirrored(
                        translation(b[0] + x, b[1] + y, zf - sp["washer_h_mm"] - sp["nut_m_mm"]), zm))]
            continue
        hole = f"{plate}:block_{i}_{k + 1}"
        holes[hole] = TappedHole(hole, plate, sp["size"], sp["depth_mm"], sp["min_engagement_mm"])
        f = Fastener("ISO 4762", sp["size"], sp["length_mm"], (name,), hole, sp["engagement_mm"])
        out.append(PartInstance(f"{name}.screw_{k + 1}", screw_kind, "ground",
                                mirrored(translation(b[0] + x, b[1] + y, -pt
                                                     - p.motor_mount_thickness_mm) @ flip, zm), fastener=f))
    return out, holes


def drum_parts(design, K: dict, lay: dict, sd, t, body: str | None = None) -> list[PartInstance]:
    """The drum on the proximal link (link frame; ``body`` another body carrying it), its anchor
    screw and the tensioner with its lock nut."""
    side = sd.joint.split("_")[-1]
    body = body or f"{joint_group(sd.joint)}proximal_{side}"
    z0, z1 = lay["capstan"]["drum_z_mm"]
    seat = cg.crest_radius_mm(t.drum_diameter_mm, t.cable_diameter_mm)  # heads and nut on the crests
    out = [PartInstance(f"{body}.capstan_drum", K[f"drum_{sd.joint}"], body, translation(0, 0, z0))]
    at = [translation(0, 0, 0.5 * (z0 + z1)) @ _rz(a) @ translation(seat, 0, 0) @ _RY90 for a in sd.anchors_deg]
    s = f"_{rope_index(design, sd.joint)}"  # the names assembly.md's winding steps use
    out.append(PartInstance(f"capstan_anchor{s}_1", K["anchor_screw"], body, at[0]))
    _, up = tensioner_screw_mm(t)
    out.append(PartInstance(f"capstan_tensioner{s}", K[f"tensioner{kind_suffix(design, sd.joint, lay)}"], body,
                            at[1] @ translation(0, 0, up)))
    out.append(PartInstance(f"capstan_tensioner_nut{s}", K["tensioner_nut"], body, at[1]))
    return out


def motor_side_parts(design, K: dict, lay: dict, sd, t, i: int, motor_name: str | None = None) -> list[PartInstance]:
    """The capstan and its set screw on the moved motor's shaft, the shaft itself, and the two
    free runs of rope (ground), each run's collision envelope trimmed at both ends
    (:func:`cad.assembly.capstan_hardware.run_trim_mm`); on the twin's knob pantograph
    (``lay["capstan"]["mirror_z_mm"]`` set) the capstan, its set screw and the shaft mirrored
    onto the bridge (:func:`mirrored`), the ropes in its rope plane; a motor raised by
    ``lay["capstan"]["raise_mm"]`` (its mount plate on the plate's top) has its shaft that much
    higher. ``motor_name``: the motor's instance name (its shaft is ``<motor_name>.shaft``;
    default ``lower_motor_<n>`` / ``upper_motor_<n>``)."""
    m = cat.get_motor(motor_key(design, lay))
    ox, oy = sd.motor_xy_mm
    zr, zm = lay["capstan"]["rope_z_mm"], lay["capstan"].get("mirror_z_mm")
    zc = capstan_z_mm(design, t, zr if zm is None else zm - zr)  # on the crank side's terms
    tf_c = translation(ox, oy, zc)
    if lay["capstan"].get("hub_out"):  # turned over about the rope's plane (:func:`capstan_span_mm`)
        tf_c = translation(ox, oy, 2 * zr - zc) @ np.diag([1.0, -1.0, -1.0, 1.0])
    sfx = kind_suffix(design, sd.joint, lay)
    shaft = f"{motor_name or ('lower' if zm is None else 'upper') + f'_motor_{(i - 1) % 2 + 1}'}.shaft"
    f, _ = capstan_set_screw_fastening(design, t, f"capstan_{i}", shaft, motor_key(design, lay))  # hole: the caller's
    out = [PartInstance(f"capstan_{i}", K[f"capstan{sfx}"], "ground", mirrored(tf_c, zm)),
           PartInstance(f"capstan_{i}.set_screw", K[f"capstan_set_screw{sfx}"], "ground",
                        mirrored(tf_c @ translation(0, 0, cg.CAPSTAN_HUB_MM / 2) @ _RY90
                                 @ translation(0, 0, m.shaft_diameter_mm / 2), zm), fastener=f),
           PartInstance(shaft, K["motor_shaft"], "ground",
                        mirrored(translation(ox, oy, -plate_mm(design, lay) - mount_mm(design, lay)
                                             + lay["capstan"].get("raise_mm", 0.0)), zm))]
    c = 1.1  # the check's clearance and a tenth
    for k in range(2):
        p0, p1 = (np.append(q, zr) for q in sd.tangents_mm[k])
        kind = rope_run_kind(f"capstan_rope_run_{i}_{k + 1}", p0, p1, t, c, f"free run {k + 1} of rope {i}",
                             groove_depth_mm=cg.groove_depth_mm(t.cable_diameter_mm))
        out.append(PartInstance(kind.name, kind, "ground", np.eye(4)))
    return out


def wraps_that_fit(t, rope_z_mm: float, tip_mm: float, heads_mm: float) -> str:
    """The fix :func:`check_capstan_z` names: the turns of ``t``'s rope whose capstan (its middle
    in the rope's plane ``rope_z_mm``, :func:`capstan_z_mm`) keeps its hub's top at or under the
    shaft's tip ``tip_mm`` and its bottom at or over the face screws' heads ``heads_mm``
    (world z, mm), rounded inwards to 0.1 turn; else a thinner rope."""
    per_turn = 0.5 * cg.GROOVE_PITCH_D * t.cable_diameter_mm
    lo = math.ceil(10.0 * (rope_z_mm - tip_mm) / per_turn - 1e-9) / 10.0  # 1e-9: a float hair
    hi = math.floor(10.0 * (rope_z_mm - cg.CAPSTAN_HUB_MM - heads_mm) / per_turn + 1e-9) / 10.0
    if max(lo, 0.1) <= hi:
        return f"{max(lo, 0.1):g} .. {hi:g} turns of the {t.cable_diameter_mm:g} mm rope fit (transmission.wraps)"
    return f"no number of turns of the {t.cable_diameter_mm:g} mm rope fits: a thinner rope (transmission.cable)"


def check_capstan_z(design, lay: dict) -> None:
    """DesignError (``transmission.wraps``) when a capstan in the rope's plane would leave the
    motor shaft (its set-screw hub above the shaft's tip) or reach down onto the motor face
    screws' heads."""
    m = cat.get_motor(motor_key(design, lay))
    tip = -plate_mm(design, lay) - mount_mm(design, lay) + m.shaft_length_mm
    seat = lay["capstan"].get("face_seat_mm", -plate_mm(design, lay))  # the face screws' heads sit on
    heads = seat + cat.get_cap_screw(m.bolt_size, "parts.motor").k_mm
    only = {sd.joint for sd in lay["capstan"].get("sides", ())} if "motor" in lay["capstan"] else None
    for t in resolve_device(design).transmissions:
        if not t.is_capstan or (only is not None and t.motor_joint not in only):  # a twin's direct 5-bar
            continue
        zc, z1, hub = capstan_span_mm(design, t, lay)
        if hub > tip + 1e-9 or zc < heads - 1e-9:  # a float hair, as wraps_that_fit
            raise DesignError("transmission.wraps", f"{t.wraps:g} turns put the capstan at z {zc:.2f} .. "
                              f"{z1:.2f} mm: its hub must sit on "
                              f"the {m.key} shaft (tip at z {tip:g} mm) above the face screws' heads (z {heads:g} mm); "
                              + wraps_that_fit(t, lay["capstan"]["rope_z_mm"], tip, heads))
