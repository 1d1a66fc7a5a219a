"""The haptic pen as part instances on bodies (:class:`cad.assembly.model.AssemblyModel`).

Layout and frames: :mod:`cad.families.pen.layout`. Every kind is a
:class:`cad.parts.PartKind`; the link hardware is the twin pantograph's part scripts, the
waist bracket, gimbal and pen are :mod:`cad.parts.pen`.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from cad.assembly.model import AssemblyModel
from cad.data.catalog import clearance_hole_mm, get_cap_screw, get_motor, tap_drill_mm
from cad.data.fits import fit
from cad.device import parts_motor
from cad.families.pantograph.build import screw_plan
from cad.families.pantograph.layout import leg_xy
from cad.families.pen import capstan_solids as PCS
from cad.families.pen import layout as L
from cad.families.pen import shoulder_capstan as SC
from cad.families.pen.fasteners import bracket_bolt_xz_mm, place_screws, screw_kinds
from cad.kinematics import haptic_pen as hp
from cad.parts import PartInstance, PartKind, base, joints, translation
from cad.parts import motor as pm
from cad.parts import pantograph as pp
from cad.parts import pen as pp2


@dataclasses.dataclass(frozen=True)
class PenLayout:
    """The pen's layout record (``AssemblyModel.extra``): its numbers ``layout_mm``, the
    ground and bench ``ground_mm``, the home task pose ``home_task`` and the swept ones
    ``motion_task``."""

    layout_mm: dict
    ground_mm: dict
    home_task: Any
    motion_task: Any



def _rot(axis: str, deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    T = np.eye(4)
    i, j = {"x": (1, 2), "y": (2, 0), "z": (0, 1)}[axis]
    T[i, i], T[i, j], T[j, i], T[j, j] = c, -s, s, c
    return T


def _tr(x=0.0, y=0.0, z=0.0) -> np.ndarray:
    return translation(x, y, z)


def _link_kinds(design, lay: dict, fidelity: str, add) -> None:
    """Clevises, tubes, pins, bearings, shoulder motors (the twin pantograph's hardware)."""
    p = design.parts
    _b, mot = lay["bearing"], get_motor(p.motor)
    cl = dict(length_mm=p.clevis_length_mm, width_mm=p.clevis_width_mm,
              height_mm=p.clevis_height_mm, socket_depth_mm=p.socket_depth_mm,
              tube_od_mm=p.tube_od_mm)
    cm = p.clevis_material
    axles = bool(SC.pairs(design))  # shoulder capstans: each proximal link on its own axle
    add("clevis_hub", pp.clevis_shape("hub", bore_mm=mot.shaft_diameter_mm, **cl), cm, True,
        "clevis on the proximal link's own axle" if axles else "clevis on the lower shoulder motor shaft",
        "CNC milled; ream shaft bore", fits=(fit("hub shaft bore", mot.shaft_diameter_mm, "shaft bore"),))
    if not axles:
        _spigot_kind(design, lay, cl, add)
    _link_rest_kinds(design, lay, cl, fidelity, add)


def _spigot_kind(design, lay: dict, cl: dict, add) -> None:
    """The upper hub clevis with a spigot reaching layer 2 on the upper shoulder motor shaft."""
    mot = get_motor(design.parts.motor)
    cm = design.parts.clevis_material
    z2 = lay["layers_mm"]["proximal_upper"]
    top = lay["spigot_mm"][1] - z2
    eng = lay["spigot_mm"][1] - lay["shoulder_shaft_tip_mm"]
    add("clevis_hub_spigot", pp2.spigot_hub_shape(cl, mot.shaft_diameter_mm, 12.0, top, eng), cm,
        True, "clevis with a spigot on the upper shoulder motor shaft (reaches layer 2)",
        "CNC milled + turned; ream shaft bore",
        fits=(fit("hub shaft bore", mot.shaft_diameter_mm, "shaft bore"),))


def _link_rest_kinds(design, lay: dict, cl: dict, fidelity: str, add) -> None:
    """Pin and bearing clevises, tubes, pins, bearings, shoulder motors."""
    p = design.parts
    b = lay["bearing"]
    cm = p.clevis_material
    add("clevis_pin", pp.clevis_shape("pin", bore_mm=b.d_mm, **cl), cm, True,
        "clevis at the elbow, pin pressed in", "CNC milled; ream pin bore",
        fits=(fit("pin bore", b.d_mm),))
    add("clevis_bearing", pp.clevis_shape("bearing", bore_mm=b.D_mm, **cl), cm, True,
        "clevis with two ball bearings", "CNC milled; bore bearing seat (both bearings)",
        fits=(fit("bearing seat", b.D_mm),))
    for which in ("proximal", "distal"):
        n = lay[f"tube_{which}_mm"]
        add(f"tube_{which}", pp.tube_shape(n, p.tube_od_mm, p.tube_id_mm), p.tube_material, True,
            f"tube {p.tube_od_mm:g}/{p.tube_id_mm:g} x {n:g} mm, {which} links",
            "cut to length, bonded")
    for side in ("lower", "upper"):
        z0, z1 = lay[f"pin_{side}_mm"]
        add(f"pin_{side}", pp.pin_shape(b.d_mm, z1 - z0), p.pin_material, True,
            f"elbow pin d{b.d_mm:g} x {z1 - z0:g}, {side} chain", "ground dowel, cut",
            fits=(fit("pin", b.d_mm),))
    add("bearing", joints.bearing_shape(p.bearing, fidelity == "fabrication"), "steel-1018", False,
        f"ball bearing {b.designation} ({p.bearing})", "bought", mass_kg=b.mass_kg,
        inertia_model="ring", ring_mm=(b.d_mm / 2, b.D_mm / 2, b.B_mm),
        hull=joints.ring_shape(b.d_mm / 2, b.D_mm / 2, b.B_mm))

    for fld, tag in (("motor", "shoulder"), ("waist_motor", "waist")):
        m = parts_motor(design, fld)[0]  # [motor] applied: the motor the datasheet uses
        add(f"motor_{tag}", pm.motor_housing_shape(m), "steel-1018", False, m.bom_description(),
            f"bought ({tag} joint); face tapped {m.bolt_size.split('-')[0]} x{m.bolt_count}; with "
            f"its shaft (solid motor_{tag}_shaft in assembly.step)", mass_kg=m.mass_kg)
        add(f"motor_{tag}_shaft", pm.motor_shaft_shape(m), "steel-1018", False, "motor shaft",
            "part of the motor", inertia_model="none", listed=False)


def _gimbal_kinds(design, lay: dict, add) -> None:
    """Yoke (with its journal), ring, ring pins, pen hub, pen rod."""
    p = design.parts
    b = lay["bearing"]
    gm = p.gimbal_material
    ri, ro = lay["ring_inner_mm"], lay["ring_outer_mm"]
    add("yoke", pp2.yoke_shape(lay["yoke_arm_x_mm"], L.YOKE_ARM_MM, p.clevis_width_mm,
                               lay["yoke_base_mm"], lay["journal_mm"][1], b.d_mm, b.D_mm, b.B_mm),
        gm, True, "gimbal yoke with its journal (runs in the distal clevises' bearings)",
        "CNC milled + turned; bore both bearing seats; grind the journal",
        fits=(fit("bearing seat", b.D_mm), fit("journal", b.d_mm)))
    add("ring", pp2.ring_shape(ri, ro, L.RING_THICKNESS_MM, b.d_mm), gm, True,
        f"gimbal ring {2 * ri:g}/{2 * ro:g} x {L.RING_THICKNESS_MM:g}, four pins pressed in",
        "turned; drill and ream four pin bores", fits=(fit("pin bore", b.d_mm),))
    pa = lay["yoke_arm_x_mm"] + b.B_mm - ri
    pb = ro - (lay["pen_hub_half_mm"] - b.B_mm)
    add("pin_ring_a", pp.pin_shape(b.d_mm, pa), p.pin_material, True,
        f"ring pin d{b.d_mm:g} x {pa:g} (axis a, in the yoke's bearings)", "ground dowel, cut",
        fits=(fit("pin", b.d_mm),))
    add("pin_ring_b", pp.pin_shape(b.d_mm, pb), p.pin_material, True,
        f"ring pin d{b.d_mm:g} x {pb:g} (axis b, in the pen hub's bearings)", "ground dowel, cut",
        fits=(fit("pin", b.d_mm),))
    boss, sock = 2 * lay["pen_hub_radius_mm"], lay["pen_hub_radius_mm"]
    add("pen_hub", pp2.pen_hub_shape(lay["pen_hub_half_mm"], lay["pen_hub_radius_mm"], b.D_mm,
                                     b.B_mm, p.pen_diameter_mm, boss, sock),
        gm, True, "pen hub (two bearings on the ring's b pins, holds the pen rod)",
        "turned + milled; bore both bearing seats and the rod socket",
        fits=(fit("bearing seat", b.D_mm),))
    rod = design.mechanism.pen_mm - 2 * (boss - sock)
    add("pen_rod", pp2.rod_shape(rod, p.pen_diameter_mm), p.pen_material, True,
        f"pen rod d{p.pen_diameter_mm:g} x {rod:g} (l6 = {design.mechanism.pen_mm:g} mm between "
        "the gimbal centres)", "turned; bonded into both hubs")


def _ground_kinds(design, lay: dict, gl: dict, add) -> None:
    """Waist bracket and hub (moving with the waist), base plate, waist motor mounts, legs."""
    p = design.parts
    sm, wm = get_motor(p.motor), get_motor(p.waist_motor)
    l1 = design.mechanism.shoulder_base_mm
    side = lay["motor_plate_side_mm"]
    hub_d = gl["waist_hub_d_mm"]
    st = SC.motor_xz_mm(design)  # shoulder capstans: the motors moved off their axes
    for arm in L.ARMS if st else ("A",):  # arm B's bracket the mirror image of A's (moved motors)
        moved = [st[j] for j in st if j.startswith(arm)]
        holes = [(x, z, clearance_hole_mm(sm.bolt_size)) for x, z in bracket_bolt_xz_mm(design, arm)]
        holes += [(x, z, sm.pilot_diameter_mm + 2.0) for x, z in moved]
        if moved:
            holes += SC.plate_holes_xz_mm(design, lay, screw_plan(design)["mount"], arm)
        top = max([l1 / 2] + [abs(z) for _, z in moved]) + side / 2
        add("waist_bracket" + ("_B" if arm == "B" else ""),
            pp2.waist_bracket_shape(gl["foot_mm"], lay["motor_plate_mm"], side, hub_d, hub_d,
                                    () if moved else (-l1 / 2, l1 / 2), sm.pilot_diameter_mm + 2.0,
                                    wm.shaft_diameter_mm + 1.0, top, holes),
            p.plate_material, True,
            "waist bracket: motor plate for both shoulder motors, foot under the links, boss"
            + (f" (arm {arm}'s)" if moved else ""),
            "CNC milled from block; bore both pilot seats", fits=(fit("pilot bore", sm.pilot_diameter_mm),))
    h0, h1 = gl["waist_hub_mm"]
    on_axle = gl["waist_shaft_engagement_mm"] == 0.0  # a waist capstan: the hub on its own axle
    add("waist_hub", pp2.waist_hub_shape(hub_d, h1 - h0, wm.shaft_diameter_mm,
                                         h1 - h0 if on_axle else gl["waist_shaft_engagement_mm"]),
        p.plate_material, True,
        "waist hub pinned on the waist axle (bracket screwed on)" if on_axle else
        "waist hub on the waist motor shaft (bracket screwed on)",
        "turned; ream the axle bore, cross-drill for the pin" if on_axle else "turned; ream shaft bore",
        fits=(fit("hub shaft bore", wm.shaft_diameter_mm, "shaft bore"),))
    add("motor_mount", pm.motor_mount_shape(wm, p.motor_mount_thickness_mm), p.plate_material, True,
        "waist motor mount plate", "waterjet/laser plate; bore the pilot seat", plate=True,
        fits=(fit("pilot bore", wm.pilot_diameter_mm),))
    l4 = design.mechanism.l4_mm
    # the waist motor face screws' heads sit in the opening (as the pantographs' motors)
    opening = max(wm.pilot_diameter_mm + 2 * pp.OPENING_MARGIN_MM,
                  wm.bolt_circle_mm + get_cap_screw(wm.bolt_size, "parts.waist_motor").dk_mm
                  + 2 * pp.OPENING_MARGIN_MM)
    st = PCS.stations_xy_mm(design)  # the waist motors' axes: on the waist axes or moved by a capstan
    moved = [st[a] for a in L.ARMS] if PCS.waist_sides(design) else []
    axes = [(s * l4 / 2, 0.0) for s in (-1, 1)]
    holes = [(x, y, opening) for x, y in axes if not moved]
    holes += [(x, y, max(opening, PCS.opening_mm(design))) for x, y in moved]
    holes += [(x, y, PCS.axle_hole_mm(design)) for x, y in axes if moved]
    holes += [(bx + x, by + y, tap_drill_mm(pm.MOUNT_SCREW)) for bx, by in axes + moved
              for x, y in pm.mount_hole_xy_mm(wm)]
    holes += [(x, y, clearance_hole_mm(base.LEG_SCREW)) for x, y in leg_xy(gl)]
    add("base_plate", pp.plate_shape(gl["base_plate_x_mm"], gl["base_plate_y_mm"],
                                     p.plate_thickness_mm, holes),
        p.plate_material, True, "base plate (waist motors under, legs at the corners)",
        f"waterjet/laser plate; tap {pm.MOUNT_SCREW.split('-')[0]} x{2 * len(pm.mount_hole_xy_mm(wm))}",
        plate=True)
    add("leg", base.leg_shape(gl["leg_height_mm"]), p.plate_material, True,
        f"leg standoff d{base.LEG_DIAMETER_MM:g} x {gl['leg_height_mm']:g}",
        f"turned; tap {base.LEG_SCREW.split('-')[0]} both ends")


def _link_parts(which: str, side: str, lay: dict, design) -> list[tuple[str, np.ndarray]]:
    """``[(kind, tf_body_part)]`` of one link (link frame, module docstring of layout)."""
    p = design.parts
    z = lay["layers_mm"][f"{which}_{side}"]
    Lc, s, h = p.clevis_length_mm, p.socket_depth_mm, p.clevis_height_mm
    if which == "proximal":
        n = design.params["proximal_mm"]
        z0 = lay[f"pin_{side}_mm"][0]
        axle = bool(L.shoulder_band_mm(design))  # shoulder capstans: the hub on its own axle
        hub = "clevis_hub" if side == "lower" or axle else "clevis_hub_spigot"
        out = [(hub, _tr(0, 0, z)), ("tube_proximal", _tr(Lc - s, 0, z)),
               ("clevis_pin", _tr(n, 0, z) @ _rot("z", 180)), (f"pin_{side}", _tr(n, 0, z0))]
        return out if axle else out + [("motor_shoulder_shaft", _tr(0, 0, lay["motor_plate_mm"][1]) @ _rot("x", 180))]
    n = design.params["distal_mm"]
    B = lay["bearing"].B_mm
    out = [("clevis_bearing", _tr(0, 0, z)), ("tube_distal", _tr(Lc - s, 0, z)),
           ("clevis_bearing", _tr(n, 0, z) @ _rot("z", 180))]
    return out + [("bearing", _tr(x, 0, z + dz)) for x in (0.0, n) for dz in (-h / 2, h / 2 - B)]


def _gimbal_parts(lay: dict) -> dict[str, list[tuple[str, np.ndarray]]]:
    """``{yoke|ring|pen_end: [(kind, tf_body_part)]}`` of one gimbal (yoke, ring frames; the
    pen hub in the pen frame at arm A's end)."""
    B = lay["bearing"].B_mm
    ax, ri, hh = lay["yoke_arm_x_mm"], lay["ring_inner_mm"], lay["pen_hub_half_mm"]
    yoke = [("yoke", np.eye(4)), ("bearing", _tr(ax, 0, 0) @ _rot("y", 90)),
            ("bearing", _tr(-ax, 0, 0) @ _rot("y", -90))]
    ring = [("ring", np.eye(4)), ("pin_ring_a", _tr(0, 0, ri)), ("pin_ring_a", _tr(0, 0, -ri) @ _rot("x", 180)),
            ("pin_ring_b", _tr(0, hh - B, 0) @ _rot("x", -90)),
            ("pin_ring_b", _tr(0, -(hh - B), 0) @ _rot("x", 90))]
    pen_end = [("pen_hub", np.eye(4)), ("bearing", _tr(0, 0, hh - B)), ("bearing", _tr(0, 0, -hh))]
    return {"yoke": yoke, "ring": ring, "pen_end": pen_end}


def _waist_parts(design, lay: dict, gl: dict, arm: str) -> list[tuple[str, np.ndarray]]:
    """``[(kind, tf_body_part)]`` of a waist body (waist frame): the waist motor's shaft, or
    with a waist capstan the waist axle (:mod:`cad.families.pen.capstan_solids`)."""
    p = design.parts
    l1 = design.mechanism.shoulder_base_mm
    y1 = lay["motor_plate_mm"][1]
    face = gl["base_top_z_mm"] - p.plate_thickness_mm - p.motor_mount_thickness_mm
    shaft = (("motor_waist_shaft", _tr(0, 0, face)) if gl["waist_shaft_engagement_mm"] else
             (PCS.CARRIER["axle"], _tr(0, 0, PCS.axle_z_mm(design, gl))))
    st = SC.motor_xz_mm(design)  # shoulder capstans: the motors moved off their axes
    lo, up = (st.get(f"{arm}_q_{r}", (0.0, z)) for r, z in (("lower", -l1 / 2), ("upper", l1 / 2)))
    bracket = "waist_bracket_B" if st and arm == "B" else "waist_bracket"
    return [(bracket, np.eye(4)), ("waist_hub", _tr(0, 0, gl["waist_hub_mm"][0])),
            ("motor_shoulder", _tr(lo[0], y1, lo[1]) @ _rot("x", 90)),
            ("motor_shoulder", _tr(up[0], y1, up[1]) @ _rot("x", 90)), shaft]


def _ground_parts(design, gl: dict) -> list[tuple[str, str, np.ndarray]]:
    """``[(instance, kind, tf_world_part)]`` of the fixed parts."""
    p = design.parts
    zb, pt, mt = gl["base_top_z_mm"], p.plate_thickness_mm, p.motor_mount_thickness_mm
    out = [("base_plate", "base_plate", _tr(0, 0, zb - pt))]
    for arm, (x, y) in PCS.stations_xy_mm(design).items():  # on the waist axis or moved by a capstan
        out.append((f"{arm}_waist_motor_mount", "motor_mount", _tr(x, y, zb - pt - mt)))
        out.append((f"{arm}_waist_motor", "motor_waist", _tr(x, y, zb - pt - mt)))
    for i, (x, y) in enumerate(leg_xy(gl)):
        out.append((f"leg_{i + 1}", "leg", _tr(x, y, gl["bench_z_mm"])))
    return out


def kinds(design, lay: dict, gl: dict, fidelity: str) -> dict:
    """``{kind name: PartKind}`` of every distinct part of the pen (and ``"_screws"``: the
    cap screw kind of each screw group; ``"_capstan"``: the waist capstans' kinds by the shared
    solids' keys, :func:`cad.families.pen.capstan_solids.kinds`, empty for direct waists;
    ``"_shoulder"``: the shoulder capstans' kinds by role, :func:`cad.families.pen.shoulder_capstan.kinds`,
    empty for direct shoulders)."""
    K: dict = {}

    def add(name, shape, material, made, description, process, **kw):
        K[name] = PartKind(name=name, shape=shape, material=material, made=made,
                           description=description, process=process, **kw)

    _link_kinds(design, lay, fidelity, add)
    _gimbal_kinds(design, lay, add)
    _ground_kinds(design, lay, gl, add)
    K["_screws"] = screw_kinds(design, add)
    K["_capstan"] = PCS.kinds(design, gl, screw_plan(design)["mount"]) if PCS.waist_sides(design) else {}
    if K["_capstan"]:
        K[PCS.CARRIER["axle"]] = K["_capstan"]["proximal_axle"]
    K["_shoulder"] = SC.kinds(design, lay, screw_plan(design)["mount"])
    return K


def assemble(design, fidelity: str = "fabrication"):
    """The haptic pen as an :class:`cad.assembly.model.AssemblyModel` (mm).

    Bodies: ``ground``; per arm ``X`` in (A, B): ``X_waist``, ``X_proximal_lower``,
    ``X_proximal_upper``, ``X_distal_lower``, ``X_distal_upper``, ``X_yoke``, ``X_ring``; and
    ``pen``. ``tf_world_body`` at home (the workspace centre, pen along +x); ``motion`` over
    :func:`cad.families.pen.layout.motion_task` (home first) with its labels. ``extra``:
    ``layout_mm``, ``ground_mm``, ``home_task`` and ``motion_task`` (x, y, z mm, yaw, pitch
    rad). Raises DesignError for hardware that does not fit (layout) or a pose of the motion
    that cannot be reached (``workspace``).
    """
    lay = L.layout(design)
    X, labels = L.motion_task(design)
    ws = design.workspace
    grid = hp.workspace_grid(ws["center_mm"], ws["size_mm"], ws["grid"], ws["rotation_deg"],
                             ws["rotation_grid"])
    reach = np.vstack([X, grid[L.ik_elbows_ok(design, grid)]])
    st = PCS.stations_xy_mm(design)
    gl = L.ground_layout(design, lay, L.lowest_link_z_mm(design, lay, reach), PCS.band_mm(design),
                         [st[a] for a in L.ARMS] if PCS.waist_sides(design) else ())
    K = kinds(design, lay, gl, fidelity)
    motion = L.body_poses(design, X)
    inst: list = []

    def place(name, kind, body, tf, fastener=None):
        inst.append(PartInstance(name, K[kind], body, np.asarray(tf, dtype=float),
                                 fastener=fastener))

    for name, kind, tf in _ground_parts(design, gl):
        place(name, kind, "ground", tf)
    gp = _gimbal_parts(lay)
    for arm in L.ARMS:
        for k, (kind, tf) in enumerate(_waist_parts(design, lay, gl, arm)):
            place(f"{arm}_waist.{kind.removesuffix('_B')}{k}", kind, f"{arm}_waist", tf)
        for which in ("proximal", "distal"):
            for side in ("lower", "upper"):
                body = f"{arm}_{which}_{side}"
                for k, (kind, tf) in enumerate(_link_parts(which, side, lay, design)):
                    place(f"{body}.{kind}{k}", kind, body, tf)
        for part in ("yoke", "ring"):
            for k, (kind, tf) in enumerate(gp[part]):
                place(f"{arm}_{part}.{kind}{k}", kind, f"{arm}_{part}", tf)
    l6 = design.mechanism.pen_mm
    for arm, T in (("A", np.eye(4)), ("B", _tr(l6) @ _rot("z", 180))):
        for k, (kind, tf) in enumerate(gp["pen_end"]):
            place(f"pen.{arm}_{kind}{k}", kind, "pen", T @ tf)
    sock = lay["pen_hub_radius_mm"]
    place("pen.pen_rod", "pen_rod", "pen", _tr(2 * sock - sock))
    holes = place_screws(design, lay, gl, K["_screws"], place, _rot)
    home = {b: T[0] for b, T in motion.items()}
    if K["_capstan"]:  # the waist capstans (the 5-bar's solids about each waist axis)
        more, h = PCS.instances(design, K["_capstan"], gl, screw_plan(design)["mount"],
                                K[K["_screws"]["mount"]], K["motor_waist_shaft"], home)
        inst += more
        holes.update(h)
    if K["_shoulder"]:  # the shoulder capstans (the 5-bar's solids on each waist bracket's motor plate)
        more, h = SC.instances(design, lay, K["_shoulder"], screw_plan(design)["mount"], K["motor_shoulder_shaft"], home)
        inst += more
        holes.update(h)
    return AssemblyModel(
        design=design, instances=tuple(inst), tf_world_body=home, motion=motion,
        pose_labels=labels, holes=holes,
        extra=PenLayout(lay, gl, X[0], X))
