"""The delta's fasteners: each placed with its :class:`cad.assembly.fasteners.Fastener` record and
the :class:`cad.assembly.fasteners.TappedHole` it engages, sized before any CAD by the shared
rules (:func:`cad.assembly.fasteners.size_cap_screw`: the shortest ISO 4762 catalog length with
an engagement between its minimum -- 1.5 d in aluminium, the maker's depth (at most
:data:`cad.assembly.fasteners.MIN_ENGAGEMENT_BOUGHT_MM`) in a motor face -- and the hole's full
thread; :func:`cad.assembly.fasteners.size_set_screw`: the ISO 4026 set screw through a round
boss onto a shaft), the holes cut into the parts that take them (:func:`cad.families.delta.
parts.drilled`). Groups (:func:`screw_plan`):

* ``motor``: the motor's face screws (its ``bolt_count`` x ``bolt_size``, catalog) through the
  motor bracket into the face's tapped holes, heads on the bracket's arm side (direct-drive
  arms; a capstan's motor has its capstan there: not fastened yet);
* ``bracket``: :data:`BRACKET_SCREWS` screws per bracket (motor, arm or capstan motor
  bracket) from the base plate's top through its clearance holes into holes tapped in the
  bracket's top edge (:data:`BRACKET_SCREW`);
* ``hub``: the arm hub's set screw on the motor shaft, radial, in a boss at the hub's bracket
  end (:data:`HUB_BOSS_D_MM`), as the four-bar's crank hub (direct-drive arms);
* ``handle``: one screw from the effector plate's top through its centre into the handle's
  axial tapped hole;
* ``effector_bar``: one screw per effector cross bar from under the effector plate into a
  hole tapped radially through the bar's middle (the elbow cross bars sit in their arm's
  reamed bore and stay as they were).

Frames: each hole's axis and point in its part's own frame (mm). No CAD import here.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from cad.assembly.fasteners import (
    MIN_ENGAGEMENT_ALU_D,
    MIN_ENGAGEMENT_BOUGHT_MM,
    TAP_LEADOUT_MM,
    Fastener,
    TappedHole,
    alu_hole,
    size_cap_screw,
    size_set_screw,
)
from cad.data import catalog as cat
from cad.device import resolve_device
from cad.errors import DesignError
from cad.families.delta import hardware as hw
from cad.families.delta import parts as dp
from cad.parts import PartInstance, PartKind, joints, translation
from cad.parts import motor as pm

#: Bracket to base plate: ISO 4762 M2.5 into the bracket's top edge (a layout choice: the
#: 2.05 mm tap drill leaves 1.5 mm of wall each side in the 5 mm bracket; an M3's 2.5 mm
#: drill 1.25 mm), :data:`BRACKET_SCREWS` per bracket at :data:`BRACKET_SCREW_INSET_MM` from
#: its sides, the thread :data:`BRACKET_TAP_DEPTH_MM` deep (full thread).
BRACKET_SCREW = "M2.5-0.45"
BRACKET_SCREWS = 2
BRACKET_SCREW_INSET_MM = pm.MOUNT_HOLE_INSET_MM
BRACKET_TAP_DEPTH_MM = 8.0
#: ISO 4026 set screws that may lock an arm hub on its motor shaft, largest first tried.
HUB_SET_SCREW_SIZES = (pm.SET_SCREW, "M2.5-0.45", "M2-0.4")
#: The hub's set-screw boss (a layout choice): a collar at the hub's bracket end, the least even
#: diameter whose wall holds an ISO 4026 screw on a 6 mm shaft by
#: :func:`cad.assembly.fasteners.size_set_screw` (M2.5 x 4; the 12 mm hub itself holds none),
#: 6 mm long (2.4 d of M2.5 round the hole). Only the boss is this wide: the Falcon's rods pass
#: 6.2 mm from its motor axes along the rest of the hub.
HUB_BOSS_D_MM = 16.0
HUB_BOSS_LENGTH_MM = 6.0
#: Effector plate to handle: ISO 4762 M3 into the handle's axial tapped hole, thread depth.
HANDLE_SCREW = "M3-0.5"
HANDLE_TAP_DEPTH_MM = 10.0
#: Effector cross bar to effector plate: ISO 4762 M3 from under the plate into a hole tapped
#: radially through the bar's middle.
EFFECTOR_BAR_SCREW = "M3-0.5"
#: A screw turned over (part z -> -z): its head under a plate, the shank up.
FLIP = np.diag([1.0, -1.0, -1.0, 1.0])
#: Part z -> part +x (a radial set screw, its flat point at the origin end).
RY90 = np.array([[0.0, 0.0, 1.0, 0.0], [0.0, 1.0, 0.0, 0.0], [-1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]])


def screw_plan(design) -> dict[str, dict]:
    """Every screw group sized from its stack, before any CAD: ``{group: {size, length_mm,
    engagement_mm, depth_mm, min_engagement_mm, clamp_mm}}`` (mm). DesignError when no catalog
    length fits (module docstring): naming ``parts.motor`` for the motor face and the hub (its
    bolts and shaft), ``parts`` for the family's fixed plates (a layout bug, never a user's)."""
    m = cat.get_motor(design.parts.motor)
    face = TappedHole("motor:face", "motor", m.bolt_size, m.bolt_thread_depth_mm,
                      min(m.bolt_thread_depth_mm, MIN_ENGAGEMENT_BOUGHT_MM))
    stacks = {
        "motor": (m.bolt_size, hw.BRACKET_THICKNESS_MM, face, "motor face to motor bracket", "parts.motor"),
        "bracket": (BRACKET_SCREW, hw.PLATE_THICKNESS_MM,
                    alu_hole("motor_bracket:top", "motor_bracket", BRACKET_SCREW, BRACKET_TAP_DEPTH_MM),
                    "motor bracket to base plate", "parts"),
        "handle": (HANDLE_SCREW, hw.EFFECTOR_THICKNESS_MM,
                   alu_hole("handle:top", "handle", HANDLE_SCREW, HANDLE_TAP_DEPTH_MM),
                   "handle to effector plate", "parts"),
    }
    # a hole tapped through the round bar from its bottom: the thread's first R - sqrt(R^2 - (d/2)^2)
    # (0.29 mm for M3 in the 8 mm bar) is partial, under the curve, so the minimum counts it on top
    # of 1.5 d, and the full thread ends as far past the axis: R + sqrt(R^2 - (d/2)^2) from the bottom
    R, d = hw.CROSS_BAR_D_MM / 2, cat.thread_diameter_mm(EFFECTOR_BAR_SCREW)
    chord = (R**2 - (d / 2) ** 2) ** 0.5
    stacks["effector_bar"] = (EFFECTOR_BAR_SCREW, hw.EFFECTOR_THICKNESS_MM,
                              TappedHole("cross_bar:screw", "cross_bar", EFFECTOR_BAR_SCREW, R + chord,
                                         MIN_ENGAGEMENT_ALU_D * d + R - chord),
                              "effector cross bar to effector plate", "parts")
    out = {}
    for g, (size, clamp, hole, joint, field) in stacks.items():
        L, e = size_cap_screw(size, clamp, hole, joint, field)
        out[g] = {"size": size, "length_mm": L, "engagement_mm": e, "depth_mm": hole.depth_mm,
                  "min_engagement_mm": hole.min_engagement_mm, "clamp_mm": clamp}
    size, L, depth = size_set_screw(m.shaft_diameter_mm / 2, HUB_BOSS_D_MM / 2, HUB_SET_SCREW_SIZES,
                                    "the arm hub's set screw onto the motor shaft", "parts.motor")
    out["hub"] = {"size": size, "length_mm": L, "engagement_mm": L, "depth_mm": depth,
                  "min_engagement_mm": MIN_ENGAGEMENT_ALU_D * cat.thread_diameter_mm(size), "clamp_mm": 0.0}
    return out


def screw_counts(design) -> dict[str, int]:
    """``{group: number of screws}`` of :func:`place_fasteners` (closed form): per direct-drive
    arm its motor's bolts and one hub set screw, per bracket hanging from the base plate
    (three, and three more for capstans' moved motors) :data:`BRACKET_SCREWS`, one handle
    screw and one per effector cross bar."""
    m = cat.get_motor(design.parts.motor)
    direct = len(direct_arms(design))
    brackets = 3 + (3 - direct)
    return {"motor": m.bolt_count * direct, "hub": direct, "bracket": BRACKET_SCREWS * brackets, "handle": 1,
            "effector_bar": 3}


def direct_arms(design) -> list[int]:
    """The arms (0, 1, 2) whose motor drives the arm's hub on its own shaft (the resolved
    device's transmission is not a capstan)."""
    dev = resolve_device(design)
    return [i for i in range(3) if not dev.transmission(f"theta_{i}").is_capstan]


def _kind(K: dict, group: str, sp: dict) -> PartKind:
    """The bought screw's kind of ``group`` (ISO 4762 cap screw or ISO 4026 set screw)."""
    if group == "hub":
        name = f"set_screw_{sp['size']}x{sp['length_mm']:g}"
        if name not in K:
            K[name] = PartKind(name, pm.set_screw_shape(sp["length_mm"], sp["size"]),
                               material=cat.FASTENER_MATERIAL, made=False, process="bought",
                               description=f"set screw ISO 4026 {sp['size']} x {sp['length_mm']:g} "
                                           "(locks the arm hub on the motor shaft)")
        return K[name]
    k = joints.cap_screw_kind(sp["size"], sp["length_mm"], "parts")
    return K.setdefault(k.name, k)


def _drill(K: dict, inst: PartInstance, tag: str, holes) -> PartKind:
    """``inst``'s kind with ``holes`` ``[(point, into-material axis, diameter, depth)]`` (part
    frame, mm) cut (:func:`cad.families.delta.parts.drilled`), one kind per ``tag``."""
    key = f"{inst.kind.name}:{tag}"
    if key not in K:
        K[key] = dataclasses.replace(inst.kind, shape=dp.drilled(inst.kind.shape, holes))
    return K[key]


def _face_and_bracket(design, K, by, plan, place) -> None:
    """The motor face screws of the direct-drive arms and every bracket's screws into its top
    edge (the bracket kinds tapped, the base plate's clearance holes cut)."""
    m = cat.get_motor(design.parts.motor)
    direct = direct_arms(design)
    sp = plan["motor"]
    for i in direct:
        T = by[f"motor_{i}"].tf_body_part
        for k, (x, y) in enumerate(pm.motor_bolt_xy_mm(m)):
            h = TappedHole(f"motor_{i}:face_{k + 1}", f"motor_{i}", sp["size"], sp["depth_mm"],
                           sp["min_engagement_mm"], axis=(0.0, 0.0, 1.0), point_mm=(x, y, 0.0))
            place(f"motor_screw_{i}_{k + 1}", "motor", "ground",
                  T @ translation(x, y, hw.BRACKET_THICKNESS_MM), h, (f"motor_bracket_{i}",))
    sp, plate = plan["bracket"], by["base_plate"]
    z_plate = plate.tf_body_part[2, 3]
    side = pm.mount_side_mm(m)
    drill = cat.tap_drill_mm(sp["size"])
    plate_holes = []
    for b in [x for x in by.values() if x.body == "ground" and x.kind.name.split(":")[0].endswith("bracket")]:
        T = b.tf_body_part
        y_top = z_plate - T[2, 3]  # part y is up (cad.families.delta.assembly._ground_parts)
        xs = [s * (side / 2 - BRACKET_SCREW_INSET_MM) for s in (-1.0, 1.0)][:BRACKET_SCREWS]
        tap = [((x, y_top, hw.BRACKET_THICKNESS_MM / 2), (0.0, -1.0, 0.0), drill,
                sp["depth_mm"] + TAP_LEADOUT_MM) for x in xs]
        by[b.name] = dataclasses.replace(b, kind=_drill(K, b, "top", tap))
        for k, x in enumerate(xs):
            p = T @ np.array([x, y_top, hw.BRACKET_THICKNESS_MM / 2, 1.0])
            h = TappedHole(f"{b.name}:top_{k + 1}", b.name, sp["size"], sp["depth_mm"], sp["min_engagement_mm"],
                           axis=(0.0, 1.0, 0.0), point_mm=(x, y_top, hw.BRACKET_THICKNESS_MM / 2))
            place(f"bracket_screw_{b.name.removeprefix('motor_bracket_')}_{k + 1}"
                  if b.name.startswith("motor_bracket_") else f"{b.name}_screw_{k + 1}",
                  "bracket", "ground", translation(p[0], p[1], z_plate + hw.PLATE_THICKNESS_MM),
                  h, ("base_plate",))
            plate_holes.append(((p[0], p[1], 0.0), (0.0, 0.0, 1.0), cat.clearance_hole_mm(sp["size"]),
                                hw.PLATE_THICKNESS_MM))
    by["base_plate"] = dataclasses.replace(plate, kind=_drill(K, plate, "screws", plate_holes))


def _hub(design, K, by, plan, place, stack) -> None:
    """The hub's radial set screw on each direct-drive arm, in the boss at the hub's bracket end
    (:data:`HUB_BOSS_D_MM`), point on the shaft (the hub kind with its boss and tap drill)."""
    m = cat.get_motor(design.parts.motor)
    sp = plan["hub"]
    r_s, R = m.shaft_diameter_mm / 2, HUB_BOSS_D_MM / 2
    z0 = -stack["hub_length"] / 2  # the hub's part z = body y - hub_mid: its bracket end
    z = z0 + HUB_BOSS_LENGTH_MM / 2
    if stack["motor_face"] + m.shaft_length_mm < stack["hub_mid"] + z + cat.thread_diameter_mm(sp["size"]):
        raise DesignError("parts.motor", f"the {m.key} shaft ends short of the arm hub's set screw")
    direct = direct_arms(design)
    for i in direct:
        hub = by[f"upper_{i}.hub"]
        if "hub:set_screw" not in K:
            tap = [((R, 0.0, z), (-1.0, 0.0, 0.0), cat.tap_drill_mm(sp["size"]), R - r_s + 0.5)]
            K["hub:set_screw"] = dataclasses.replace(  # its own name beside a capstan arm's plain hub
                hub.kind, name="hub" if len(direct) == 3 else "hub_bossed", shape=dp.drilled(dp.bossed_hub_shape(hw.HUB_D_MM, stack["hub_length"], m.shaft_diameter_mm,
                                                               2 * R, z0, HUB_BOSS_LENGTH_MM), tap),
                description=f"{hub.kind.description}, set-screw boss d{2 * R:g} x {HUB_BOSS_LENGTH_MM:g} at the "
                            "bracket end",
                process=f"{hub.kind.process}; tap {sp['size'].split('-')[0]} radial in the boss")
        by[hub.name] = hub = dataclasses.replace(hub, kind=K["hub:set_screw"])
        h = TappedHole(f"{hub.name}:set_screw", hub.name, sp["size"], sp["depth_mm"], sp["min_engagement_mm"],
                       axis=(1.0, 0.0, 0.0), point_mm=(0.0, 0.0, z))
        place(f"upper_{i}.hub_set_screw", "hub", f"upper_{i}",
              hub.tf_body_part @ translation(0.0, 0.0, z) @ RY90 @ translation(0.0, 0.0, r_s), h,
              (f"upper_{i}.motor_shaft",))


def _effector(design, K, by, plan, place) -> None:
    """The handle's screw (head on the effector plate's top at its centre, into the handle's
    top) and each effector cross bar's screw (head under the plate, up through it into a radial
    hole tapped through the bar's middle); the plate, the handle and the bars drilled."""
    sp = plan["handle"]
    plate, handle = by["effector.effector_plate"], by["effector.handle"]
    top = hw.HANDLE_LENGTH_MM / 2  # the handle's part frame: centred, axis z
    tap = [((0.0, 0.0, top), (0.0, 0.0, -1.0), cat.tap_drill_mm(sp["size"]), sp["depth_mm"] + TAP_LEADOUT_MM)]
    by[handle.name] = dataclasses.replace(handle, kind=_drill(K, handle, "top", tap))
    through = [((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), cat.clearance_hole_mm(sp["size"]), hw.EFFECTOR_THICKNESS_MM)]
    h = TappedHole(f"{handle.name}:top", handle.name, sp["size"], sp["depth_mm"], sp["min_engagement_mm"],
                   axis=(0.0, 0.0, 1.0), point_mm=(0.0, 0.0, top))
    place("effector.handle_screw", "handle", "effector",
          plate.tf_body_part @ translation(0.0, 0.0, hw.EFFECTOR_THICKNESS_MM), h, (plate.name,))
    sp, R = plan["effector_bar"], hw.CROSS_BAR_D_MM / 2
    for i in range(3):
        bar = by[f"effector.arm_{i}.cross_bar"]
        if "effector_cross_bar" not in K:  # part y is down (-z of the effector), the bar's bottom at y = R
            K["effector_cross_bar"] = dataclasses.replace(
                _drill(K, bar, "screw", [((0.0, R, 0.0), (0.0, -1.0, 0.0), cat.tap_drill_mm(sp["size"]), 2 * R)]),
                name="effector_cross_bar", description=f"{bar.kind.description}; {sp['size'].split('-')[0]} "
                "tapped through its middle (screwed on the effector plate)")
        by[bar.name] = bar = dataclasses.replace(bar, kind=K["effector_cross_bar"])
        at = bar.tf_body_part @ np.array([0.0, R, 0.0, 1.0])  # the bar's bottom on the plate's top
        h = TappedHole(f"{bar.name}:screw", bar.name, sp["size"], sp["depth_mm"], sp["min_engagement_mm"],
                       axis=(0.0, 1.0, 0.0), point_mm=(0.0, R, 0.0))
        place(f"effector.arm_{i}.bar_screw", "effector_bar", "effector",
              translation(at[0], at[1], at[2] - hw.EFFECTOR_THICKNESS_MM) @ FLIP, h, (plate.name,))
        p = np.linalg.inv(plate.tf_body_part) @ at
        through.append(((p[0], p[1], 0.0), (0.0, 0.0, 1.0), cat.clearance_hole_mm(sp["size"]),
                        hw.EFFECTOR_THICKNESS_MM))
    by[plate.name] = dataclasses.replace(plate, kind=_drill(K, plate, "screws", through))


def place_fasteners(design, K: dict, inst: list[PartInstance], stack: dict) -> tuple[list, dict]:
    """(``inst`` with the drilled parts and every screw of :func:`screw_plan` placed, ``{hole
    name: TappedHole}``) (module docstring). ``stack``: :func:`cad.families.delta.assembly.
    stack_mm` of the design."""
    plan = screw_plan(design)
    by = {x.name: x for x in inst}
    new: list[PartInstance] = []
    holes: dict = {}

    def place(name, group, body, tf, hole, clamps):
        holes[hole.name] = hole
        sp = plan[group]
        new.append(PartInstance(name, _kind(K, group, sp), body, np.asarray(tf, float), fastener=Fastener(
            "ISO 4026" if group == "hub" else "ISO 4762", sp["size"], sp["length_mm"], tuple(clamps), hole.name,
            sp["engagement_mm"])))

    _face_and_bracket(design, K, by, plan, place)
    _hub(design, K, by, plan, place, stack)
    _effector(design, K, by, plan, place)
    return [by[x.name] for x in inst] + new, holes
