"""Layout of a pantograph-family device from the design only (numpy, no CAD): heights,
plate extents, the screw plans, and the planar transforms the placement uses.

World frame = the kinematic base frame (z up, z = 0 on the base plate's top face; the
bench plane at ``bench_z_mm`` below it); mm throughout. Isotropy paper §3 (Fig. 2, the
plain 5-bar) and §4.1 (Fig. 1, the twin pantograph); the arrangement is described in
:mod:`cad.families.pantograph.build`.
"""

from __future__ import annotations

import math

import numpy as np

from cad.assembly import fasteners as fs
from cad.data.catalog import get_bearing, get_motor, thread_diameter_mm
from cad.device import resolve_device
from cad.errors import DesignError
from cad.families.pantograph import capstan as pcap
from cad.families.pantograph import twin_placement as tpl
from cad.families.pantograph.twin_placement import POST_DX_MM  # noqa: F401 (the post line's offset, re-exported)
from cad.isotropy.gii import workspace_half_mm
from cad.parts import base
from cad.parts import motor as pm
from cad.parts.motor import mount_side_mm

#: Posts: their screws (their offset along x from each actuated joint:
#: :data:`cad.families.pantograph.twin_placement.POST_DX_MM`).
POST_SCREW = "M4-0.7"


POST_TAP_DEPTH_MM = 10.0


#: Depth of the journal / handle pin in the knob's bore (mm).
KNOB_BORE_DEPTH_MM = 15.0


#: Knob diameter of the plain 5-bar's handle (mm); the mouse's is mechanism.knob_diameter_mm.
PLAIN_KNOB_DIAMETER_MM = 20.0


#: Smallest thread engagement of a cap screw in a tapped hole (x thread diameter):
#: 1.5 d in aluminium.
MIN_ENGAGEMENT_D = 1.5


def is_twin(design) -> bool:
    return design.family == "twin-pantograph"


def lower_five_bar(design):
    return design.mechanism.crank if is_twin(design) else design.mechanism


def home_xy_mm(design) -> np.ndarray:
    """End-effector (mouse: main journal) position of the exported pose (mm)."""
    ws = design.workspace
    return np.asarray(ws.get("home_mm", ws["center_mm"]), dtype=float)


def screw_plan(design) -> dict[str, dict]:
    """Every screw group of the device sized from its stack, before any CAD
    (:func:`cad.assembly.fasteners.size_cap_screw`: catalog ISO 4762 length, engagement
    between 1.5 d in aluminium -- the maker's minimum in the motor face -- and the hole's
    full-thread depth). Group -> size, clamp_mm, length_mm, engagement_mm, depth_mm,
    min_engagement_mm, joint, clamps (parts clamped, head side first). DesignError naming
    the joint when no catalog length fits."""
    p = design.parts
    m = get_motor(p.motor)
    pt, mt = p.plate_thickness_mm, p.motor_mount_thickness_mm
    face = min(m.bolt_thread_depth_mm, fs.MIN_ENGAGEMENT_BOUGHT_MM)
    groups = {
        "leg": (base.LEG_SCREW, pt, base.STANDOFF_TAP_DEPTH_MM - fs.TAP_LEADOUT_MM, None,
                "leg to base plate", "parts.plate_thickness_mm", ("base_plate",)),
        "mount": (pm.MOUNT_SCREW, mt, pt, None, "motor mount plate to base/bridge plate",
                  "parts.motor_mount_thickness_mm", ("motor_mount",)),
        "motor": (m.bolt_size, mt, m.bolt_thread_depth_mm, face, "motor face to mount plate",
                  "parts.motor_mount_thickness_mm", ("motor_mount",)),
    }
    if is_twin(design):
        groups["post"] = (POST_SCREW, pt, POST_TAP_DEPTH_MM - fs.TAP_LEADOUT_MM, None,
                          "bridge post to base/bridge plate", "parts.plate_thickness_mm",
                          ("plate",))
    out = {}
    for g, (size, clamp, depth, need, joint, field, clamps) in groups.items():
        hole = fs.alu_hole(g, g, size, depth)
        if need is not None:
            hole = fs.TappedHole(g, g, size, depth, need)
        L, e = fs.size_cap_screw(size, clamp, hole, joint, field)
        out[g] = {"size": size, "clamp_mm": clamp, "length_mm": L, "engagement_mm": e,
                  "depth_mm": depth, "min_engagement_mm": hole.min_engagement_mm,
                  "joint": joint, "clamps": clamps}
    return out


#: ISO 4026 set screws that may lock a hub clevis on its motor shaft, largest first tried.
SET_SCREW_SIZES = ("M3-0.5", "M2.5-0.45", "M2-0.4")


def set_screw_plan(design) -> dict:
    """The set screw locking each hub clevis on its motor shaft, before any CAD: radial, at
    the clevis mid-plane, tapped through the round end's wall (``clevis_width_mm / 2`` minus
    the shaft radius) with its flat point touching the shaft and its end inside the clevis
    outer surface (:func:`cad.assembly.fasteners.size_set_screw`: the largest of
    :data:`SET_SCREW_SIZES` with a bd_warehouse ISO 4026 length 1.5 d <= L <= full-thread
    depth). Returns size, length_mm, engagement_mm (= L), depth_mm, wall_mm, shaft_radius_mm,
    min_engagement_mm. DesignError naming ``parts.clevis_width_mm`` when no size fits,
    ``parts.clevis_height_mm`` when the shaft ends short of the screw."""
    p = design.parts
    m = get_motor(p.motor)
    r_in, r_out = m.shaft_diameter_mm / 2, p.clevis_width_mm / 2
    size, L, depth = fs.size_set_screw(r_in, r_out, SET_SCREW_SIZES,
                                       "hub clevis set screw onto the motor shaft",
                                       "parts.clevis_width_mm")
    d = thread_diameter_mm(size)
    # shaft length inside a hub clevis (the same for the crank and knob pantographs); a link
    # turned through a capstan sits on its own axle, cut to the hub's top (no such bound)
    engaged = m.shaft_length_mm - p.plate_thickness_mm - p.motor_mount_thickness_mm - p.layer_gap_mm
    direct = any(not t.is_capstan for t in resolve_device(design).transmissions)
    if direct and engaged - p.clevis_height_mm / 2 < d / 2:
        raise DesignError(
            "parts.clevis_height_mm",
            f"the {p.motor} shaft ends {engaged:g} mm into the {p.clevis_height_mm:g} mm hub "
            f"clevis, short of its {size.split('-')[0]} set screw at mid-height",
        )
    return {"size": size, "length_mm": L, "engagement_mm": L, "depth_mm": depth,
            "wall_mm": r_out - r_in, "shaft_radius_mm": r_in,
            "min_engagement_mm": fs.MIN_ENGAGEMENT_ALU_D * d}


def layout(design) -> dict:
    """Heights and plate extents of the assembly (mm), from the design only (no CAD)."""
    twin = is_twin(design)
    p = design.parts
    a = design.params["base_mm"]
    l2 = design.params["proximal_mm"]
    l6 = design.mechanism.crank_mm if twin else 0.0
    b = get_bearing(p.bearing)
    m = get_motor(p.motor)
    h, g = p.clevis_height_mm, p.layer_gap_mm
    pitch = h + g
    cap = pcap.layout(design)  # a capstan on each motor: the drums' band under the linkage
    tcap = tpl.group_layout(design)  # the twin's: each 5-bar's band next to its motors' plate
    lifts = {k: v["lift_mm"] for k, v in tcap.get("groups", {}).items()}
    L0 = g + h / 2 + cap.get("lift_mm", 0.0) + lifts.get("crank", 0.0)
    L = [L0, L0 + pitch, L0 + 2 * pitch]
    ms = mount_side_mm(m)
    ws = design.workspace
    cx, cy = ws["center_mm"]
    half_x, half_y = workspace_half_mm(ws)
    reach_x = a / 2 + l2 + p.clevis_width_mm
    margin = base.LEG_INSET_MM + base.LEG_DIAMETER_MM / 2 + 4.0
    post_y = tcap.get("post_y_mm", tpl.post_line_y_mm(design))
    y_back = (post_y - p.post_diameter_mm / 2) if twin else -ms / 2
    base_x = (
        min(-reach_x, cx - half_x - l6 - 20, -a / 2 - ms / 2) - margin,
        max(reach_x, cx + half_x + l6 + 20, a / 2 + ms / 2) + margin,
    )
    base_y = (y_back - margin, cy + half_y + l6 + p.clevis_width_mm + 20 + margin)
    base_x, base_y = _grown(base_x, base_y, cap, ms / 2 + margin)
    base_x, base_y = _grown(base_x, base_y, tcap.get("groups", {}).get("crank", {}), ms / 2 + margin)
    leg_h = p.motor_mount_thickness_mm + m.body_length_mm + base.LEG_GROUND_CLEARANCE_MM
    pt, mt = p.plate_thickness_mm, p.motor_mount_thickness_mm
    shaft_tip = -pt - mt + m.shaft_length_mm
    out = {
        "layer_pitch_mm": pitch,
        "lower_layers_z_mm": L,
        "base_plate_x_mm": base_x,
        "base_plate_y_mm": base_y,
        "leg_height_mm": leg_h,
        "bench_z_mm": -pt - leg_h,
        "journal_d_mm": b.d_mm,
        "pin_short_mm": 2 * h + g,
        "pin_long_mm": 3 * h + 2 * g,
        "tube_proximal_mm": l2 - 2 * (p.clevis_length_mm - p.socket_depth_mm),
        "tube_distal_mm": design.params["distal_mm"] - 2 * (p.clevis_length_mm - p.socket_depth_mm),
        "lower_shaft_engagement_mm": shaft_tip - (L[0] - h / 2),
        "motor_mount_side_mm": ms,
        "screws": screw_plan(design),
        "set_screw": set_screw_plan(design),
    }
    _with_capstan(out, cap)
    if not twin:
        knob_z = L[2] + h / 2 + g
        out.update(
            knob_bottom_z_mm=knob_z,
            handle_pin_z_mm=L[1] - h / 2,
            handle_pin_mm=knob_z + KNOB_BORE_DEPTH_MM - (L[1] - h / 2),
        )
        return out
    _twin_heights(out, design, tcap, post_y)
    return out


def _twin_heights(out: dict, design, tcap: dict, post_y: float) -> None:
    """The twin's upper half in ``out`` (:func:`layout`): the crankshaft's web over the crank
    pantograph, the knob pantograph's layers over it (mirrored), the bridge over them (its
    5-bar's drums' band between, when it has capstans), the posts on the line ``post_y``, the
    bridge plate's extent (grown over moved motors) and, with capstans, ``twin_capstan``."""
    p = design.parts
    b, m = get_bearing(p.bearing), get_motor(p.motor)
    h, g, t = p.clevis_height_mm, p.layer_gap_mm, p.crank_thickness_mm
    pt, mt, ms = p.plate_thickness_mm, p.motor_mount_thickness_mm, out["motor_mount_side_mm"]
    L, pitch = out["lower_layers_z_mm"], out["layer_pitch_mm"]
    zW = L[2] + h / 2 + g + t / 2
    U2 = zW + t / 2 + g + h / 2
    U = [U2 + 2 * pitch, U2 + pitch, U2]  # U0 (proximal, top), U1, U2
    z_bridge = U[0] + h / 2 + g + tcap.get("groups", {}).get("knob", {}).get("lift_mm", 0.0)
    posts = tpl.posts_xy_mm(design, post_y)
    bridge_x, bridge_y = _grown(
        (min(x for x, _ in posts) - p.post_diameter_mm, max(x for x, _ in posts) + p.post_diameter_mm),
        (post_y - p.post_diameter_mm, ms / 2 + 5), tcap.get("groups", {}).get("knob", {}), ms / 2 + 5.0)
    out.update(
        web_z_mm=zW,
        upper_layers_z_mm=U,
        bridge_bottom_z_mm=z_bridge,
        knob_bottom_z_mm=U[0] + h / 2 + g,
        posts_xy_mm=posts,
        bridge_x_mm=bridge_x,
        bridge_y_mm=bridge_y,
        journal_up_mm=(U[0] + h / 2 + g + KNOB_BORE_DEPTH_MM) - (zW + t / 2),
        crank_pin_down_mm=(zW - t / 2) - (L[1] - h / 2),
        web_width_mm=max(b.d_mm + 6.0, 10.0),
        upper_shaft_engagement_mm=(U[0] + h / 2) - (z_bridge + pt + mt - m.shaft_length_mm),
    )
    _with_twin_capstan(out, tcap, design)


def _with_twin_capstan(out: dict, tcap: dict, design) -> None:
    """The layout ``out`` of a twin with capstans (``tcap``,
    :func:`cad.families.pantograph.twin_placement.group_layout`): each capstan 5-bar's layout
    under ``twin_capstan[group]`` in world z (``rope_z_mm``, ``drum_z_mm`` (bottom, top) of
    band 1, ``side_z_mm`` each side's ``(rope_z_mm, (drum bottom, top))`` in its own band,
    ``mirror_z_mm``: None for the crank pantograph on the base plate, the bridge's bottom for
    the knob pantograph hanging under it, its parts the crank side's mirrored about z), no
    motor shaft in that group's hubs (each link sits on its own axle)."""
    g, th = design.parts.layer_gap_mm, pcap.DRUM_THICKNESS_MM
    zb = out["bridge_bottom_z_mm"]
    groups = {}
    for grp, v in tcap.get("groups", {}).items():
        zm = None if grp == "crank" else zb
        sz = []
        for band in v["bands"]:
            rope, drum = tpl.band_rope_offset_mm(design, band), (band * g + (band - 1) * th, band * (g + th))
            sz.append((rope, drum) if zm is None else (zm - rope, (zm - drum[1], zm - drum[0])))
        groups[grp] = {**v, "rope_z_mm": sz[0][0], "drum_z_mm": sz[0][1], "side_z_mm": tuple(sz), "mirror_z_mm": zm}
        del out["lower_shaft_engagement_mm" if zm is None else "upper_shaft_engagement_mm"]
    if groups:
        out["twin_capstan"] = groups


def _with_capstan(out: dict, cap: dict) -> None:
    """The layout ``out`` of a 5-bar with capstans (``cap``, :func:`cad.families.pantograph.capstan.layout`):
    their layout under ``capstan``, no motor shaft in the hubs (each sits on its link's axle)."""
    if cap:
        out["capstan"] = cap
        del out["lower_shaft_engagement_mm"]


def _grown(base_x, base_y, cap: dict, half: float):
    """The base plate's extents grown to carry each capstan drive's moved motor mount plate
    (a square of ``half`` side plus margin round the motor axis)."""
    for sd in cap.get("sides", ()):
        mx, my = sd.motor_xy_mm
        base_x = (min(base_x[0], mx - half), max(base_x[1], mx + half))
        base_y = (min(base_y[0], my - half), max(base_y[1], my + half))
    return base_x, base_y


def rz(angle: float, x: float = 0.0, y: float = 0.0, z: float = 0.0) -> np.ndarray:
    T = np.eye(4)
    c, s = math.cos(angle), math.sin(angle)
    T[:2, :2] = [[c, -s], [s, c]]
    T[:3, 3] = (x, y, z)
    return T


def flip_matrix() -> np.ndarray:
    T = np.eye(4)
    T[1, 1] = T[2, 2] = -1.0
    return T


def leg_xy(lay: dict) -> list[tuple[float, float]]:
    (x0, x1), (y0, y1) = lay["base_plate_x_mm"], lay["base_plate_y_mm"]
    return base.leg_xy_mm((x0, y0, x1, y1))


def workspace_square(ws: dict) -> np.ndarray:
    """Closed outline (5, 2) mm of the planar workspace (square or rectangle), world frame."""
    (cx, cy), (hx, hy) = ws["center_mm"], workspace_half_mm(ws)
    return np.array(
        [[cx - hx, cy - hy], [cx + hx, cy - hy], [cx + hx, cy + hy], [cx - hx, cy + hy], [cx - hx, cy - hy]]
    )


def group_lay(lay: dict, group: str) -> dict:
    """The layout ``lay`` as the 5-bar's capstan solids read it for the twin's ``group``
    (:mod:`cad.families.pantograph.capstan_solids`): its capstans under ``capstan`` and its
    proximal layer's height on the crank side's terms (the knob pantograph's measured down from
    the bridge's bottom) under ``lower_layers_z_mm``."""
    cap = lay["twin_capstan"][group]
    L0 = lay["lower_layers_z_mm"][0] if cap["mirror_z_mm"] is None else cap["mirror_z_mm"] - lay["upper_layers_z_mm"][0]
    return {**lay, "capstan": cap, "lower_layers_z_mm": [L0]}
