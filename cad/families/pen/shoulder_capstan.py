"""The haptic pen's shoulder capstans as solids of its one assembly (issue 35, stage 2): the
5-bar's capstan solids (:mod:`cad.families.pantograph.capstan_solids`) about each arm's two
shoulder axes, on the waist bracket's motor plate.

Each proximal link turns on its own axle (the shoulder motor's shaft diameter, from the bearing
block's outer end to the far face of the link's hub clevis, the clevis's set screw on it) in two
deep groove ball bearings seated in a bearing block on the outer face of the waist bracket's
motor plate, where the shoulder motor stood; the block is through-bolted to the plate when the
plate holds less thread than the screws' minimum engagement
(:func:`cad.families.pantograph.capstan_solids.block_fastening`: heads on the plate's link
side, washer and nut under the block's flange). The drum sector on each proximal link about
its shoulder axis turns in a band of its own between the lower proximal layer and the motor
plate (the plate moved out by :func:`cad.families.pen.layout.shoulder_band_mm`, two layer gaps
and two drums): the band by the plate (band 1) holds the drum of the pair's ``plate_band``
joint (:func:`cad.families.pen.capstan_layout.layout`), band 2 the other. Each shoulder motor
stands on the plate's outer face (no mount plate of its own) moved off its shoulder axis to
where the layout puts it, its capstan and set screw on its shaft in its drum's rope plane, the
two free runs of rope.

Frames: the shared solids are laid out in a 5-bar frame F of each arm (x = up the waist axis,
y = -x of the waist frame, z from the motor plate's link-side face towards the arm's plane;
the plate from z = -plate to 0), mapped into the waist frame by :func:`tf_waist_f` (a
rotation). For arm B, F's (x, y) is the pair plane's (x5, y5) = (z, rho); arm A's waist frame
is mirrored against it (its link frames' z = n_out is the pair plane's normal, B's the
opposite), so arm A's sides are laid out mirrored in F (:func:`f_side`: y -> -y). The drums
sit in the proximal links' frames (z = n_out = the waist frame's y) with their arcs from
:func:`cad.families.pen.capstan_layout.drum_arc_body_deg`.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from cad.assembly.capstan_hardware import (
    DRUM_THICKNESS_MM,
    axle_bearing,
    capstan_set_screw_fastening,
)
from cad.data import catalog as cat
from cad.device import resolve_device
from cad.families.pantograph import capstan_solids as pcs
from cad.families.pantograph import twin_placement as tp
from cad.families.pen import capstan_layout as cl
from cad.families.pen.capstan import pen_kind_group
from cad.families.pen.layout import ARMS
from cad.parts import motor as pm

ROLES = ("lower", "upper")


def pairs(design) -> dict:
    """``{arm: PairLayout}`` of each arm whose shoulders are capstans and laid out
    (:func:`cad.families.pen.capstan_layout.layout`); empty for direct shoulders."""
    return {p.name.split()[1]: p for p in cl.layout(design)
            if p.name.endswith("shoulders") and p.clash is None}


def band(pair, joint: str) -> int:
    """The drum band of ``joint`` (1 by the motor plate, 2 next to the lower proximal layer)."""
    return 1 if joint == pair.plate_band else 2


def band_z_mm(design, k: int) -> tuple[float, float]:
    """The drums' band ``k`` in frame F (mm, from the plate's link-side face): ``k`` layer gaps
    and ``k - 1`` drums below it (:func:`cad.families.pantograph.twin_placement.band_rope_offset_mm`)."""
    g = design.parts.layer_gap_mm
    z0 = k * g + (k - 1) * DRUM_THICKNESS_MM
    return z0, z0 + DRUM_THICKNESS_MM


def tf_waist_f(plate0_mm: float) -> np.ndarray:
    """4x4 frame F in the waist frame (module docstring): (x, y, z) of F -> (-y, plate0 - z, x),
    ``plate0_mm`` the motor plate's link-side face (the waist frame's y, mm)."""
    return np.array([[0.0, -1.0, 0.0, 0.0], [0.0, 0.0, -1.0, plate0_mm], [1.0, 0.0, 0.0, 0.0],
                     [0.0, 0.0, 0.0, 1.0]])


def f_side(sd):
    """A shoulder's :class:`cad.families.pantograph.capstan.CapstanSide` in frame F: arm B's as
    laid out, arm A's mirrored (y -> -y: its points, and its angles negated)."""
    if cl.arm_sign(sd.joint) > 0:
        return sd
    flip = np.array([1.0, -1.0])
    return dataclasses.replace(
        sd, b_mm=tuple(np.asarray(sd.b_mm, float) * flip), alpha_deg=-sd.alpha_deg,
        motor_xy_mm=tuple(np.asarray(sd.motor_xy_mm, float) * flip),
        tangents_mm=np.asarray(sd.tangents_mm, float) * flip,
        arc_start_deg=-(sd.arc_start_deg + sd.arc_span_deg), anchors_deg=tuple(-a for a in sd.anchors_deg))


def body_side(sd):
    """The side with its drum's arc and anchors in the proximal link's frame
    (:func:`cad.families.pen.capstan_layout.drum_arc_body_deg`)."""
    s0, sp, an = cl.drum_arc_body_deg(sd)
    return dataclasses.replace(sd, arc_start_deg=s0, arc_span_deg=sp, anchors_deg=an)


def carrier(role: str) -> dict:
    """The shoulder axle's words in the shared solids' texts (:data:`pcs.CARRIER`)."""
    return {"axle": f"shoulder_axle_{role}", "link": f"{role} proximal link", "drum_link": "proximal link",
            "fixing": "the hub clevis's set screw on it", "at": f"the {role} shoulder"}


def hub_far_mm(design, lay: dict, role: str) -> float:
    """The far face (towards the arm's plane) of the ``role`` proximal link's hub clevis (mm,
    the waist frame's y = the link frame's z): the axle's end."""
    return lay["layers_mm"][f"proximal_{role}"] - design.parts.clevis_height_mm / 2


def side_lay(design, lay: dict, pair, sd, plan: dict) -> dict:
    """The layout the shared solids read for one shoulder (frame F): its side, rope plane and
    band, motor (``parts.motor``), axle top, carrier words, the motor plate (its thickness
    ``parts.motor_mount_thickness_mm``, the motor on it with no mount plate, the face screws'
    heads on its link-side face), the capstan turned over in band 1 (its hub beyond the turns:
    under them it would reach into the plate, :func:`cad.families.pantograph.capstan_solids.capstan_span_mm`)
    and the mount screws' plan ``plan``."""
    k = band(pair, sd.joint)
    role = sd.joint.split("_")[-1]
    p0 = lay["motor_plate_mm"][0]
    return {"capstan": {"sides": (sd,), "rope_z_mm": tp.band_rope_offset_mm(design, k),
                        "drum_z_mm": band_z_mm(design, k), "motor": design.parts.motor,
                        "axle_top_mm": p0 - hub_far_mm(design, lay, role), "carrier": carrier(role),
                        "plate_mm": design.parts.motor_mount_thickness_mm, "mount_mm": 0.0,
                        "face_seat_mm": 0.0, "plate": f"{sd.joint[0]}_waist.waist_bracket0",
                        "hub_out": k == 1, "kind_group": pen_kind_group},
            "screws": {"mount": plan}}


def kinds(design, lay: dict, plan: dict) -> dict:
    """``{role: {shared key: PartKind}}`` of the shoulder capstans
    (:func:`cad.families.pantograph.capstan_solids.capstan_kinds` per role, both arms' drums;
    the bearing block named ``shoulder_bearing_block``), after each capstan's height check
    (:func:`cad.families.pantograph.capstan_solids.check_capstan_z`); empty when no shoulder
    pair is laid out."""
    pp = pairs(design)
    out = {}
    for role in ROLES if pp else ():
        sides = [s for a in ARMS if a in pp for s in pp[a].sides if s.joint.endswith(role)]
        for sd in sides:
            pcs.check_capstan_z(design, side_lay(design, lay, pp[sd.joint[0]], f_side(sd), plan))
        kl = side_lay(design, lay, pp[sides[0].joint[0]], sides[0], plan)
        kl["capstan"]["sides"] = tuple(body_side(s) for s in sides)
        K = pcs.capstan_kinds(design, kl)
        K["bearing_block"] = dataclasses.replace(K["bearing_block"], name="shoulder_bearing_block")
        out[role] = K
    return out


def instances(design, lay: dict, Ks: dict, plan: dict, motor_shaft_kind, tf_world_body: dict) -> tuple[list, dict]:
    """The shoulder capstans' instances (module docstring; the axles and drums on the proximal
    links, the rest on the waist) and the holes their fasteners engage. ``Ks``: :func:`kinds`;
    ``motor_shaft_kind`` the shoulder motor's shaft; ``tf_world_body`` the bodies at home (mm)."""
    dev = resolve_device(design)
    T = tf_waist_f(lay["motor_plate_mm"][0])
    out, holes = [], {}
    for arm, pair in pairs(design).items():
        waist = f"{arm}_waist"
        for sd in pair.sides:
            role = sd.joint.split("_")[-1]
            link = f"{arm}_proximal_{role}"
            K = {**Ks[role], "motor_shaft": motor_shaft_kind}
            t, i = dev.transmission(sd.joint), pcs.rope_index(design, sd.joint)
            fs = f_side(sd)
            sl = side_lay(design, lay, pair, fs, plan)
            tf_f_link = np.linalg.inv(T) @ np.linalg.inv(tf_world_body[waist]) @ tf_world_body[link]
            blk, h = pcs.block_parts(design, K, sl, i, f"{arm}_{role}", fs.b_mm, None, tf_f_link, body=link)
            motor = f"{waist}.motor_shoulder{2 + ROLES.index(role)}"
            ground = blk + pcs.motor_side_parts(design, K, sl, fs, t, i, motor_name=motor)
            hole = capstan_set_screw_fastening(design, t, f"capstan_{i}", f"{motor}.shaft",
                                               pcs.motor_key(design, sl))[1]  # the capstan's tapped hole
            holes[hole.name] = hole
            out += [dataclasses.replace(x, body=waist, tf_body_part=T @ x.tf_body_part) for x in ground]
            p0 = lay["motor_plate_mm"][0]
            z0, z1 = sl["capstan"]["drum_z_mm"]
            dl = {**sl, "capstan": {**sl["capstan"], "drum_z_mm": (p0 - z1, p0 - z0)}}
            out += pcs.drum_parts(design, K, dl, body_side(sd), t, body=link)
            out.append(pcs.PartInstance(f"{link}.shoulder_axle", K["proximal_axle"], link,
                                        pcs.translation(0.0, 0.0, hub_far_mm(design, lay, role))))
            holes.update(h)
    return out, holes


def motor_xz_mm(design) -> dict:
    """``{joint: (x, z)}`` of each moved shoulder motor's axis in its waist frame (mm;
    :func:`cad.families.pen.capstan_layout.motor_in_body_mm`)."""
    return {sd.joint: cl.motor_in_body_mm(sd) for p in pairs(design).values() for sd in p.sides}


def plate_holes_xz_mm(design, lay: dict, plan: dict, arm: str) -> list[tuple[float, float, float]]:
    """``[(x, z, diameter)]`` (arm ``arm``'s waist frame, mm) its shoulder capstans need through
    the motor plate: each axle's clearance (the bearing's abutment diameter Da) and each block's
    four fastener clearance holes."""
    m = cat.get_motor(design.parts.motor)
    da = axle_bearing(m.shaft_diameter_mm).Da_mm
    T = tf_waist_f(lay["motor_plate_mm"][0])
    out = []
    for p in [pairs(design)[arm]]:
        for sd in p.sides:
            b = f_side(sd).b_mm
            for dx, dy, d in [(0.0, 0.0, da)] + [(x, y, cat.clearance_hole_mm(plan["size"]))
                                                  for x, y in pm.mount_hole_xy_mm(m)]:
                v = T @ np.array([b[0] + dx, b[1] + dy, 0.0, 1.0])
                out.append((float(v[0]), float(v[2]), d))
    return out
