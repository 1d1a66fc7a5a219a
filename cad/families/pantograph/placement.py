"""The part instances of a pantograph-family device and where they are: each link's parts in
its body frame, the fixed parts (base plate, legs, motor stations, the twin's posts and
bridge) with their screws and tapped holes, the bearings carried across their joints.

Body frames are planar (rotation about z, z = 0 on the base plate's top): a moving link's
origin at its first joint, x towards its second; the upper group's parts are turned over
inside their body (``tf_body_part`` carries the flip and the layer height). mm."""

from __future__ import annotations

import math

import numpy as np

from cad.assembly.capstan_hardware import capstan_set_screw_fastening
from cad.assembly.fasteners import Fastener, TappedHole
from cad.data.catalog import get_motor
from cad.device import resolve_device
from cad.families.pantograph import capstan_solids as pcs
from cad.families.pantograph.kinds import part_kinds
from cad.families.pantograph.layout import (
    flip_matrix,
    group_lay,
    home_xy_mm,
    is_twin,
    leg_xy,
    lower_five_bar,
    rz,
)
from cad.kinematics import fivebar as fb5
from cad.kinematics import twin_pantograph as tw
from cad.parts import PartInstance, translation
from cad.parts import motor as pm


def link_parts(which: str, side: str, K: dict, lay: dict, p, elbow_pin: str) -> list:
    """``[(kind, tf in the link's layer frame)]`` of one link (x along the link, z centred)."""
    Lc, s, h = p.clevis_length_mm, p.socket_depth_mm, p.clevis_height_mm
    if which == "proximal":
        length = lay["proximal_mm"]
        return [
            (K["clevis_hub"], np.eye(4)),
            (K["tube_proximal"], rz(0.0, Lc - s)),
            (K["clevis_pin"], rz(math.pi, length)),
            (K[elbow_pin], rz(0.0, length, 0.0, -h / 2)),
        ]
    length = lay["distal_mm"]
    B = K["bearing"].ring_mm[2]
    out = [
        (K["clevis_bearing"], np.eye(4)),
        (K["tube_distal"], rz(0.0, Lc - s)),
        (K["clevis_bearing"], rz(math.pi, length)),
    ]
    return out + [
        (K["bearing"], rz(0.0, x, 0.0, z)) for x in (0.0, length) for z in (-h / 2, h / 2 - B)
    ]


def assembly(design, lay: dict, fidelity: str):
    """The part instances and the world transform of each body at the home pose.

    Returns ``(instances, tf_world_body, home_pose, tapped_holes)``: instances is a list of
    :class:`cad.parts.PartInstance` (screws carry their
    :class:`cad.assembly.fasteners.Fastener` record); tf_world_body maps body -> 4x4 (mm);
    tapped_holes maps hole name -> :class:`cad.assembly.fasteners.TappedHole`.
    """
    p = design.parts
    twin = is_twin(design)
    K = part_kinds(design, lay, fidelity)
    lay = {
        **lay,
        "proximal_mm": design.params["proximal_mm"],
        "distal_mm": design.params["distal_mm"],
    }
    fb = lower_five_bar(design)
    B = [fb.base_left_mm, fb.base_right_mm]
    inst: list = []
    tfs: dict[str, np.ndarray] = {"ground": np.eye(4)}
    set_holes: dict = {}

    def place(name, kind, body, tf, fastener=None, part_of=None):
        inst.append(PartInstance(name, kind, body, np.asarray(tf, dtype=float), fastener=fastener,
                                 part_of=part_of))

    home = home_xy_mm(design)
    if twin:
        th = math.radians(design.workspace["home_theta_deg"])
        X = np.array([[home[0], home[1], th]])
        ik = tw.ik(design.mechanism, X)
        groups = [
            ("crank", ik.crank, lay["lower_layers_z_mm"], False),
            ("knob", ik.knob, lay["upper_layers_z_mm"], True),
        ]
    else:
        groups = [("", fb5.ik(fb, home[None, :]), lay["lower_layers_z_mm"], False)]
    pt, mt = p.plate_thickness_mm, p.motor_mount_thickness_mm
    zb = lay.get("bridge_bottom_z_mm", 0.0)
    tcap = lay.get("twin_capstan", {})
    for grp, fp, zs, upper in groups:
        F = flip_matrix() if upper else np.eye(4)
        pre = f"{grp}_" if grp else ""
        on_axle = "capstan" in lay or grp in tcap  # a link turned through a capstan: on its own axle
        C = [fp.C_left_mm[0], fp.C_right_mm[0]]
        E = fp.E_mm[0]
        shaft_tf = (
            translation(0, 0, zb + pt + mt) @ flip_matrix() if upper else translation(0, 0, -pt - mt)
        )
        for i, side in enumerate(("left", "right")):
            body = f"{pre}proximal_{side}"
            tfs[body] = rz(float(fp.q_rad[0, i]), B[i][0], B[i][1])
            pin = "pin_short" if side == "left" else "pin_long"
            for k, (kind, tf) in enumerate(link_parts("proximal", side, K, lay, p, pin)):
                place(f"{body}.{kind.name}{k}", kind, body, translation(0, 0, zs[0]) @ F @ tf)
            if on_axle:  # the link on its own axle at B (the knob pantograph's mirrored onto the bridge)
                place(f"{body}.axle", K["proximal_axle"], body,
                      pcs.mirrored(translation(0, 0, pcs.axle_z_mm(design)), zb if upper else None))
            else:
                place(f"{body}.motor_shaft", K["motor_shaft"], body, shaft_tf,  # its motor's own solid
                      part_of=f"{'upper' if upper else 'lower'}_motor_{i + 1}")
            place_set_screw(place, set_holes, K, lay, body, translation(0, 0, zs[0]) @ F, on_axle)
            body = f"{pre}distal_{side}"
            tfs[body] = rz(math.atan2(E[1] - C[i][1], E[0] - C[i][0]), C[i][0], C[i][1])
            for k, (kind, tf) in enumerate(link_parts("distal", side, K, lay, p, pin)):
                place(f"{body}.{kind.name}{k}", kind, body, translation(0, 0, zs[1 + i]) @ F @ tf)
    if twin:
        tfs["crankshaft"] = rz(th, home[0], home[1])
        place("crankshaft", K["crankshaft"], "crankshaft", translation(0, 0, lay["web_z_mm"]))
        place("knob", K["knob"], "crankshaft", translation(0, 0, lay["knob_bottom_z_mm"]))
    else:
        tfs["handle"] = translation(home[0], home[1])
        place("handle_pin", K["handle_pin"], "handle", translation(0, 0, lay["handle_pin_z_mm"]))
        place("knob", K["knob"], "handle", translation(0, 0, lay["knob_bottom_z_mm"]))
    holes = fixed_parts(design, place, K, lay, inst, tfs, B)
    return journal_parts(inst, tfs, "crankshaft" if twin else "handle"), tfs, home, {
        **holes, **set_holes}


def fixed_parts(design, place, K: dict, lay: dict, inst: list, tfs: dict, B) -> dict:
    """The ground's parts (:func:`ground_parts`: each motor at its joint ``B`` or, through a
    capstan, moved to its direction) and every capstan drive's (:func:`capstan_parts`: the
    5-bar's, or each of the twin's 5-bars with capstans, the knob pantograph's mirrored onto the
    bridge); returns the tapped holes."""
    tcap = lay.get("twin_capstan", {})
    cap = lay.get("capstan", tcap.get("crank", {}))
    stations = [sd.motor_xy_mm for sd in cap["sides"]] if cap else B
    upper_stations = [sd.motor_xy_mm for sd in tcap["knob"]["sides"]] if "knob" in tcap else B
    raised = [k for k, r in enumerate(tcap.get("crank", {}).get("raise_mm", ())) if r > 0]
    holes = ground_parts(place, K, lay, design.parts, stations, is_twin(design), upper_stations, raised)
    if "capstan" in lay:
        holes.update(capstan_parts(design, K, lay, inst, tfs, B))
    for grp in tcap:  # the twin's 5-bars with capstans: the same solids (the knob's mirrored)
        holes.update(capstan_parts(design, K, group_lay(lay, grp), inst, tfs, B))
    return holes


def capstan_parts(design, K: dict, lay: dict, inst: list, tfs: dict, B) -> dict:
    """A capstan drive's instances appended to ``inst`` (:mod:`cad.families.pantograph.capstan_solids`:
    the bearing blocks at B with their bearings and screws, the drums with their anchors and
    tensioners, the capstans with their set screws, the motor shafts, the rope runs); returns
    the blocks' tapped holes in the base plate."""
    dev = resolve_device(design)
    holes: dict = {}
    cap = lay["capstan"]
    for k, (sd, b) in enumerate(zip(cap["sides"], B, strict=True)):
        side = f"{pcs.joint_group(sd.joint)}{sd.joint.split('_')[-1]}"  # left, knob_left
        body = f"{pcs.joint_group(sd.joint)}proximal_{sd.joint.split('_')[-1]}"
        t, i = dev.transmission(sd.joint), pcs.rope_index(design, sd.joint)
        ls = lay
        if "side_z_mm" in cap:  # the twin: each side in its own band, its motor raised or not
            rope, drum = cap["side_z_mm"][k]
            ls = {**lay, "capstan": {**cap, "rope_z_mm": rope, "drum_z_mm": drum, "raise_mm": cap["raise_mm"][k]}}
        blk, h = pcs.block_parts(design, K, ls, i, side, b, K["_mount_screw"], tfs[body])
        ms = pcs.motor_side_parts(design, K, ls, sd, t, i)
        inst += blk + pcs.drum_parts(design, K, ls, sd, t) + ms
        holes.update(h)
        f = next(x.fastener for x in ms if x.name == f"capstan_{i}.set_screw")  # the capstan's tapped hole
        hole = capstan_set_screw_fastening(design, t, f"capstan_{i}", f.clamps[0])[1]
        holes[hole.name] = hole
    return holes


def journal_parts(inst: list, tfs: dict, end_body: str) -> list:
    """The instances with each distal link's bearings carried across their joint: the inner
    ring moves with the journal's body (``other_body``: the proximal link at the elbow, the
    crankshaft or handle at the end effector), placed there by ``tf_other_part`` (the
    placement at home; the ring is a solid of revolution about the shared axis)."""
    import dataclasses

    out = []
    for i in inst:
        if i.kind.name == "bearing" and "distal_" in i.body:
            pre, side = i.body.split("distal_")
            other = f"{pre}proximal_{side}" if abs(i.tf_body_part[0, 3]) < 1e-9 else end_body
            tf = np.linalg.inv(tfs[other]) @ tfs[i.body] @ i.tf_body_part
            i = dataclasses.replace(i, other_body=other, tf_other_part=tf)
        out.append(i)
    return out


def place_screw(place, holes, K, lay, group: str, name: str, hole: str, part: str, tf, clamps=None):
    """Place one screw of ``group`` (:func:`screw_plan`) with its fastener record, and the
    tapped hole ``hole`` (in the instance ``part``) it engages."""
    sp = lay["screws"][group]
    holes[hole] = TappedHole(hole, part, sp["size"], sp["depth_mm"], sp["min_engagement_mm"])
    f = Fastener("ISO 4762", sp["size"], sp["length_mm"], tuple(clamps or sp["clamps"]), hole,
                 sp["engagement_mm"])
    place(name, K[f"_{group}_screw"], "ground", tf, fastener=f)


def place_set_screw(place, holes, K, lay, body: str, tf_clevis, on_axle: bool | None = None) -> None:
    """The set screw of the hub clevis of ``body`` (clevis frame ``tf_clevis``): axis along
    -x at z = 0, flat point on the shaft surface (x = -shaft radius), its other end at or
    inside the clevis outer surface; the wall's tapped hole is its record's hole. ``on_axle``:
    the link sits on its own axle (a capstan), not on the motor shaft (None: the 5-bar's
    ``capstan`` layout says)."""
    ss = lay["set_screw"]
    clevis = f"{body}.clevis_hub0"
    hole = f"{clevis}:set_screw"
    holes[hole] = TappedHole(hole, clevis, ss["size"], ss["depth_mm"], ss["min_engagement_mm"])
    T = np.eye(4)
    T[:3, :3] = [[0, 0, -1], [0, 1, 0], [1, 0, 0]]  # part z (point -> end) -> clevis -x
    T[0, 3] = -ss["shaft_radius_mm"]
    on_axle = "capstan" in lay if on_axle is None else on_axle
    shaft = f"{body}.axle" if on_axle else f"{body}.motor_shaft"
    f = Fastener("ISO 4026", ss["size"], ss["length_mm"], (shaft,), hole, ss["engagement_mm"])
    place(f"{body}.set_screw", K["set_screw"], body, tf_clevis @ T, fastener=f)


def motor_station(place, holes, K, lay, p, tag: str, i: int, bxy, z_mount: float, upper: bool,
                  raised: bool = False):
    """One motor on its mount plate: the plate, the motor, the plate's screws into the
    base/bridge plate and the motor face screws (through the plate into the face's tapped
    holes; heads in the base/bridge plate's opening). ``raised``: a lower motor whose mount
    plate sits on the base plate's top (``z_mount`` 0), its screws from above, the motor's body
    down through the plate's opening."""
    mot = get_motor(p.motor)
    mt = p.motor_mount_thickness_mm
    bx, by = bxy
    plate = "bridge_plate" if upper else "base_plate"
    place(f"{tag}_motor_mount_{i}", K["motor_mount"], "ground", translation(bx, by, z_mount))
    # upper: plate on the bridge, motor standing on it (face up at z_mount + mt, turned over),
    # its screws from above into the bridge, the face screws from below; lower: mirrored
    z_face = z_mount + mt if upper else z_mount
    # turned over about y: the face's bolt circle (symmetric in x) stays on the plate's holes
    turn = np.diag([-1.0, 1.0, -1.0, 1.0])
    tf_motor = translation(bx, by, z_face) @ (turn if upper else np.eye(4))
    motor = f"{tag}_motor_{i}"
    place(motor, K["motor"], "ground", tf_motor)
    z_mount_head, f_mount = (z_mount + mt, np.eye(4)) if upper or raised else (z_mount, flip_matrix())
    for k, (x, y) in enumerate(pm.mount_hole_xy_mm(mot)):
        place_screw(place, holes, K, lay, "mount", f"{tag}_mount_screw_{i}_{k + 1}",
               f"{plate}:{tag}_mount_{i}_{k + 1}", plate,
               translation(bx + x, by + y, z_mount_head) @ f_mount)
    z_head, f_face = (z_mount, flip_matrix()) if upper else (z_mount + mt, np.eye(4))
    for k, (x, y) in enumerate(pm.motor_bolt_xy_mm(mot)):
        place_screw(place, holes, K, lay, "motor", f"{tag}_motor_screw_{i}_{k + 1}",
               f"{motor}:face_{k + 1}", motor, translation(bx + x, by + y, z_head) @ f_face)


def ground_parts(place, K, lay, p, B, twin, B_upper=None, raised=()) -> dict:
    """The fixed parts: base plate, legs, motors with their mounts (``B`` the lower motors'
    axes, ``B_upper`` the bridge's, ``B`` when None; the lower motors numbered in ``raised``
    (0-based) with their mount plate on the base plate's top, screwed from above, the body
    down through the plate's opening), (mouse) posts and bridge.
    Returns the tapped holes the screws engage ({name: TappedHole})."""
    holes: dict = {}
    pt, mt = p.plate_thickness_mm, p.motor_mount_thickness_mm
    place("base_plate", K["base_plate"], "ground", translation(0, 0, -pt))
    for i, (x, y) in enumerate(leg_xy(lay)):
        place(f"leg_{i + 1}", K["leg"], "ground", translation(x, y, lay["bench_z_mm"]))
        place_screw(place, holes, K, lay, "leg", f"leg_screw_{i + 1}", f"leg_{i + 1}:top",
               f"leg_{i + 1}", translation(x, y, 0.0))
    zb = lay.get("bridge_bottom_z_mm", 0.0)
    stations = [("lower", -pt - mt, False, B)] + ([("upper", zb + pt, True, B_upper or B)] if twin else [])
    for tag, z_mount, upper, axes in stations:
        for i, bxy in enumerate(axes):
            up = not upper and i in raised
            motor_station(place, holes, K, lay, p, tag, i + 1, bxy, 0.0 if up else z_mount, upper, up)
    if not twin:
        return holes
    place("bridge_plate", K["bridge_plate"], "ground", translation(0, 0, zb))
    for k, (x, y) in enumerate(lay["posts_xy_mm"]):
        post = f"post_{k + 1}"
        place(post, K["post"], "ground", translation(x, y, 0.0))
        place_screw(place, holes, K, lay, "post", f"post_screw_{k + 1}_bottom", f"{post}:bottom",
               post, translation(x, y, -pt) @ flip_matrix(), ["base_plate"])
        place_screw(place, holes, K, lay, "post", f"post_screw_{k + 1}_top", f"{post}:top", post,
               translation(x, y, zb + pt), ["bridge_plate"])
    return holes
