"""The crank's capstan as solids of the four-bar's assembly (issue 35): the drum sector on the
crank, the capstan on the motor's shaft, the motor moved beside A1, the two free runs of rope
and the two anchors, added to the one instance list (:func:`add_capstan`), so mass properties,
the interference check over the crank range, the files, the BOM and assembly.md read them.

Layout (mm, world R0, z = 0 on the base plate's top): the drum (:mod:`cad.parts.capstan`) is
:data:`cad.families.fourbar.capstan.DRUM_THICKNESS_MM` thick under the crank, round the hub
(z up to the hub's top, its bore the hub's diameter); the motor, its mount plate and their
screws move by the centre distance C (:func:`cad.actuators.capstan.centre_distance_mm`) in the
direction ``alpha`` (:func:`motor_direction_deg`); the base plate opens for the moved motor and
grows to carry its mount plate (the legs move to its corners). The rope's runs lie on the drum's
mid-plane between the external tangent points of the two pitch circles
(:func:`cad.actuators.capstan_geometry.external_tangent_points_mm`), fixed in the world while
the crank turns; each run's collision envelope stops where the rope comes within
``clearance_min_mm`` of the pulley it lies on (:func:`run_trim_mm`). The crank turns on its
own axle at A1 (:func:`a1_support`): a steel axle of the motor shaft's diameter (the hub's
bore and set screw as in direct drive) in two deep groove ball bearings of that bore, seated
in a bearing block screwed under the base plate where the motor mount plate sat (its corner
screws into the same tapped holes; a lip between the bearings).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from cad.actuators import capstan as cap
from cad.actuators import capstan_geometry as cg
from cad.assembly.capstan_hardware import (  # noqa: F401 - re-exported: the four-bar's names
    A1_LIP_MM,
    A1_WALL_MM,
    ANCHOR_SCREW,
    ANCHOR_SCREW_LENGTH_MM,
    TENSIONER_WIND_D,
    capstan_set_screw,
    capstan_set_screw_fastening,
    drum_groove_arc_deg,
    grooved_drum_texts,
    rope_run_kind,
    run_trim_mm,
    tensioner_screw_mm,
)
from cad.assembly.capstan_hardware import axle_bearing as a1_bearing
from cad.data import catalog as cat
from cad.data.fits import fit
from cad.errors import DesignError
from cad.families.fourbar import capstan as fcap
from cad.families.fourbar.mechanism import Assembly
from cad.parts import PartInstance, PartKind, base, joints, motor, translation
from cad.parts import capstan as shapes

#: Candidate motor directions tried by :func:`motor_direction_deg`, deg (every 5 deg).
_ALPHA_STEP_DEG = 5.0
#: Least radius about A2 kept clear of the drum's arc when the motor's direction is chosen (mm): the
#: A2 pin's nut and washer hang under the crank there (the larger of this and the washer's or ring's
#: radius plus ``clearance_min_mm``, :func:`a2_hardware_radius_mm`). A layout choice; the
#: interference check of the build is what proves the drum clear of them.
A2_HARDWARE_RADIUS_MM = 6.0
#: The motor group's instances moved with the motor: names, and prefixes of numbered ones (the
#: direct-drive shaft's envelope at A1 becomes the crank's axle, :func:`a1_support`).
_MOTOR_GROUP = ("motor", "motor_mount")
_MOTOR_SCREWS = ("motor_screw_", "mount_screw_")


@dataclasses.dataclass(frozen=True)
class CapstanPlacement:
    """Where the capstan's parts sit (mm, deg, world): ``alpha_deg`` the motor's direction
    from A1, ``centre_distance_mm`` C, ``motor_xy_mm`` its axis, ``gamma_rad`` the tangent
    points' half angle, ``tangents_mm`` (2, 2, 2) the runs' end points (drum, capstan),
    ``arc_start_deg`` / ``arc_span_deg`` the drum sector in the crank's frame,
    ``anchors_deg`` the anchors' crank-frame angles, ``z_mm`` (bottom, top) of the drum,
    ``capstan_z_mm`` the capstan's bottom (above the motor's face screws, in the base plate's
    opening), ``rope_z_mm`` the rope's plane (the middle of the capstan's turns, above its
    set-screw hub)."""

    alpha_deg: float
    centre_distance_mm: float
    motor_xy_mm: tuple
    gamma_rad: float
    tangents_mm: np.ndarray
    arc_start_deg: float
    arc_span_deg: float
    anchors_deg: tuple
    z_mm: tuple
    capstan_z_mm: float
    rope_z_mm: float


def _segment_distance_mm(p, a, b) -> float:
    """Distance from point ``p`` to the segment ``a``-``b`` (2-D, mm)."""
    ab, ap = b - a, p - a
    s = float(np.clip(ap @ ab / (ab @ ab), 0.0, 1.0))
    return float(np.hypot(*(ap - s * ab)))


def a2_hardware_radius_mm(parts) -> float:
    """Plan radius (mm) of the A2 pin's washer and nut or retaining ring under its lower link:
    the washer's outside diameter (catalog) or the ring's fitted outside diameter, whichever is
    larger (issue 35: an M8 joint's 16 mm washer met the drum kept 6 mm off)."""
    r = cat.get_washer(parts.pin).d2_mm / 2
    if cat.is_dowel(parts.pin):
        r = max(r, cat.get_retaining_ring(cat.dowel_diameter_mm(parts.pin)).d4_mm / 2)
    return r


def motor_direction_deg(design, J, gamma_rad: float, anchor_deg: float, keep_out_deg: float,
                        centre_distance_mm: float, mount_half_mm: float, a4_keep_mm: float,
                        radii_mm=(0.0, 0.0), post_keep_mm: float = 0.0) -> float:
    """The motor's direction from A1 (deg): of the directions every :data:`_ALPHA_STEP_DEG`,
    those whose drum sector leaves the crank's own line (crank-frame angle 0, where A2's
    hardware hangs under the crank) at least ``keep_out_deg`` outside the arc; of these, the one
    whose motor mount plate (a square of half side ``mount_half_mm`` round the motor) stands
    farthest from A4's post screw (at least ``a4_keep_mm``), both runs of rope between the
    pitch circles of ``radii_mm`` (drum, capstan) at least ``post_keep_mm`` from A4's axis
    (the post), and the mount plate clear of the A1 bearing block's flange (the same square at
    A1) by ``design.parts.clearance_min_mm``. DesignError naming
    ``transmission.centre_distance_mm`` when none does."""
    lo, hi = math.degrees(design.phi1_min_rad), math.degrees(design.phi1_max_rad)
    a4 = np.asarray(J["ground"]["A4"], float)
    best, best_d = None, a4_keep_mm
    for alpha in np.arange(-180.0, 180.0, _ALPHA_STEP_DEG):
        start, span = cg.drum_arc_link_deg(float(alpha), gamma_rad, lo, hi, anchor_deg)
        rel = (0.0 - start) % 360.0
        if not (span + keep_out_deg <= rel <= 360.0 - keep_out_deg):
            continue
        a = math.radians(alpha)
        o = centre_distance_mm * np.array([math.cos(a), math.sin(a)])
        if float(np.abs(o).max()) < 2 * mount_half_mm + design.parts.clearance_min_mm:
            continue  # the mount plate on the A1 bearing block's flange
        d = float(np.hypot(*np.maximum(np.abs(o - a4) - mount_half_mm, 0.0)))
        runs = cg.external_tangent_points_mm((0.0, 0.0), radii_mm[0], o, radii_mm[1])
        if min(_segment_distance_mm(a4, r[0], r[1]) for r in runs) < post_keep_mm:
            continue
        if d >= best_d:
            best, best_d = float(alpha), d
    if best is None:
        arc = 2 * math.degrees(gamma_rad) + hi - lo + 2 * anchor_deg
        raise DesignError("transmission.centre_distance_mm",
                          f"{centre_distance_mm:g} mm: no place for the motor clears both the crank's "
                          f"A2 hardware (the drum arc is {arc:.0f} deg), the A4 post and the A1 bearing "
                          f"block (the {2 * mount_half_mm:g} mm mount plate); set a longer "
                          "centre_distance_mm")
    return best


def placement(design, t, J, plan) -> CapstanPlacement:
    """:class:`CapstanPlacement` of the crank's capstan ``t`` (the resolved transmission)."""
    dd, dc, d = t.drum_diameter_mm, t.capstan_diameter_mm, t.cable_diameter_mm
    C = cap.centre_distance_mm(dc, dd, t.centre_distance_mm)
    g = cg.tangent_half_angle_rad(dd, dc, C)
    anchor = math.degrees(2.0 * fcap.ANCHOR_LENGTH_MM / dd)
    a2 = float(np.hypot(*J["crank"]["A2"]))
    r_a2 = max(A2_HARDWARE_RADIUS_MM, a2_hardware_radius_mm(design.parts) + design.parts.clearance_min_mm)
    keep = math.degrees(math.asin(min(1.0, r_a2 / max(a2, r_a2))))

    half = motor.mount_side_mm(cat.get_motor(design.parts.motor)) / 2
    post = cat.get_cap_screw(cat.standoff_screw(design.parts.pin), "parts.pin").dk_mm / 2
    clr = design.parts.clearance_min_mm
    alpha = motor_direction_deg(design, J, g, anchor, keep, C, half, post + clr, (0.5 * dd, 0.5 * dc),
                                0.5 * (design.parts.post_diameter_mm + d) + clr)
    o = (C * math.cos(math.radians(alpha)), C * math.sin(math.radians(alpha)))
    tang = cg.external_tangent_points_mm((0.0, 0.0), 0.5 * dd, o, 0.5 * dc)
    lo, hi = math.degrees(design.phi1_min_rad), math.degrees(design.phi1_max_rad)
    start, span = cg.drum_arc_link_deg(alpha, g, lo, hi, anchor)
    top = plan.hub_z_mm[1]
    zc, zr = _capstan_z_mm(design, t, top - fcap.DRUM_THICKNESS_MM + d)
    if not top - fcap.DRUM_THICKNESS_MM + d <= zr <= top - d:
        raise DesignError("transmission.wraps", f"{t.wraps:g} turns put the rope at z = {zr:.2f} "
                          f"mm, off the drum's rim (z {top - fcap.DRUM_THICKNESS_MM:g} to {top:g} mm); "
                          "use fewer turns")
    return CapstanPlacement(alpha, C, o, g, tang, start, span,
                            cg.anchor_angles_link_deg(alpha, g, lo, hi, anchor),
                            (top - fcap.DRUM_THICKNESS_MM, top), zc, zr)


def _capstan_z_mm(design, t, rope_min_z_mm: float = -math.inf) -> tuple[float, float]:
    """(the capstan's bottom, the rope's plane), mm: the capstan starts ``clearance_min_mm``
    above the heads of the motor's face screws (their heads on the mount plate, under the base
    plate's top), or higher on the shaft when the rope's plane (the middle of its turns above
    the set-screw hub) must reach ``rope_min_z_mm`` (the drum's rim: a tall hub stack), as long
    as the set-screw hub stays on the motor shaft (else the rope is left low: the caller
    refuses it)."""
    p = design.parts
    m = cat.get_motor(p.motor)
    head = cat.get_cap_screw(m.bolt_size, "parts.motor").k_mm
    zc = -p.base_thickness_mm + head + p.clearance_min_mm
    turns = cg.GROOVE_PITCH_D * t.cable_diameter_mm * t.wraps
    lift = rope_min_z_mm - (zc + cg.CAPSTAN_HUB_MM + 0.5 * turns)
    shaft_top = -p.base_thickness_mm - p.motor_mount_thickness_mm + m.shaft_length_mm
    if lift > 0 and zc + lift + cg.CAPSTAN_HUB_MM <= shaft_top:
        zc += lift
    return zc, zc + cg.CAPSTAN_HUB_MM + 0.5 * turns


def add_capstan(asm, design, J, plan, t):
    """``asm`` (:class:`cad.families.fourbar.mechanism.Assembly`) with the crank's capstan
    ``t`` drawn (module docstring); ``asm`` unchanged for direct drive."""
    if not t.is_capstan:
        return asm
    parts = design.parts
    pl = placement(design, t, J, plan)
    ox, oy = pl.motor_xy_mm
    shift = translation(ox, oy, 0.0)
    inst, rect = [], _rect(asm.base_rect_mm, pl, parts)
    for i in asm.instances:
        if i.name in _MOTOR_GROUP or i.name.startswith(_MOTOR_SCREWS):
            i = dataclasses.replace(i, tf_body_part=shift @ i.tf_body_part)
        elif i.name == "base_plate":
            i = dataclasses.replace(i, kind=_base_kind(i.kind, parts, J, rect, pl))
        elif i.name.startswith(("leg_", "leg_screw_")):
            i = _moved_leg(i, rect)
        inst.append(i)
    shaft = next(i for i in asm.instances if i.name == "motor_shaft")
    inst.append(PartInstance("capstan_motor_shaft", shaft.kind, "ground", shift @ shaft.tf_body_part, part_of="motor"))
    inst, holes = a1_support(design, J, inst, asm.instances, asm.holes, plan.shaft_top_mm)
    inst += _capstan_parts(design, t, pl)
    holes += (capstan_set_screw_fastening(design, t, "capstan", "capstan_motor_shaft")[1],)
    return Assembly(tuple(inst), rect, asm.notes, holes)


def a1_support(design, J, inst: list[PartInstance], direct: tuple, holes: tuple, top_mm: float):
    """(``inst`` with the crank's support at A1, ``holes`` with its tapped holes) (module
    docstring): the shaft envelope on the crank becomes ``crank_axle`` (made, steel; the hub's
    set screw now holds it), the ``a1_bearing_block`` takes the motor mount plate's place with
    its four corner screws (``a1_block_screw_i`` into ``base_plate:a1_block_i``; the A4 post
    screw passes through it where it passed through the mount plate), ``a1_bearing_1`` / ``_2``
    in its seats (outer ring ground, inner ring crank). ``top_mm``: the axle's top (world z, mm;
    the layer plan's ``shaft_top_mm``: the motor shaft's top or, when that is short of it, the
    crank hub's, :func:`cad.families.fourbar.layers.plan_for_order` with ``made_axle``)."""
    parts = design.parts
    m = cat.get_motor(parts.motor)
    brg = a1_bearing(m.shaft_diameter_mm)
    bt, h = parts.base_thickness_mm, 2 * brg.B_mm + A1_LIP_MM
    z0 = -bt - h
    axle_len = top_mm - z0
    axle = PartKind(
        "crank_axle", shapes.axle_shape(m.shaft_diameter_mm, axle_len), material=CRANK_AXLE_MATERIAL,
        made=True, description=f"crank axle d{m.shaft_diameter_mm:g} x {axle_len:g} mm at A1 (in "
        f"two {brg.designation} bearings, the crank hub's set screw on it)", process="turned; grind the journals",
        fits=(fit("journal", m.shaft_diameter_mm, "bearing journal"),), revolution=True)
    out = []
    for i in inst:
        if i.name == "motor_shaft":
            i = PartInstance("crank_axle", axle, "crank", translation(0, 0, z0))
        elif i.fastener is not None and "motor_shaft" in i.fastener.clamps:
            i = dataclasses.replace(i, fastener=dataclasses.replace(i.fastener, clamps=("crank_axle",)))
        elif i.name == "post_screw" and "motor_mount" in i.fastener.clamps:
            i = dataclasses.replace(i, fastener=dataclasses.replace(
                i.fastener, clamps=tuple("a1_bearing_block" if c == "motor_mount" else c
                                         for c in i.fastener.clamps)))
        out.append(i)
    through = any(i.name == "post_screw" and "a1_bearing_block" in i.fastener.clamps for i in out)
    out += _a1_block(design, m, brg, z0, J["ground"]["A4"] if through else None)
    by_name = {h.name: h for h in holes}
    new = []
    for i in direct:
        if i.name.startswith("mount_screw_"):
            k = i.name.rsplit("_", 1)[1]
            hole = dataclasses.replace(by_name[i.fastener.hole], name=f"base_plate:a1_block_{k}")
            new.append(hole)
            f = dataclasses.replace(i.fastener, clamps=("a1_bearing_block",), hole=hole.name)
            out.append(dataclasses.replace(i, name=f"a1_block_screw_{k}", fastener=f))
    return out, tuple(holes) + tuple(new)


#: The crank axle's material (a turned steel axle: the capstan's material).
CRANK_AXLE_MATERIAL = cg.CAPSTAN_MATERIAL


def _a1_block(design, m, brg, z0: float, a4_through) -> list[PartInstance]:
    """The bearing block (with a hole for the A4 post screw at ``a4_through``, or None) and
    its two bearings, bottom at ``z0``."""
    parts = design.parts
    extra = (() if a4_through is None else
             ((a4_through[0], a4_through[1], cat.clearance_hole_mm(cat.standoff_screw(parts.pin))),))
    block = PartKind(
        "a1_bearing_block",
        shapes.bearing_block_shape(motor.mount_side_mm(m), parts.motor_mount_thickness_mm,
                                   motor.mount_hole_xy_mm(m), cat.clearance_hole_mm(motor.MOUNT_SCREW),
                                   brg.D_mm, brg.B_mm, A1_LIP_MM, brg.Da_mm, A1_WALL_MM, extra),
        material=parts.motor_mount_material, made=True,
        description=(f"A1 bearing block: {motor.mount_side_mm(m):g} mm square flange, boss with two "
                     f"{brg.designation} bearing seats and a {A1_LIP_MM:g} mm lip (the crank's axle)"),
        process=f"machined from {2 * brg.B_mm + A1_LIP_MM:g} mm plate: mill the boss, bore the seats "
                f"from both sides; drill {motor.MOUNT_SCREW.split('-')[0]} clearance x4",
        fits=(fit("bearing seat", brg.D_mm),))
    rings = joints.bearing_rings(brg.size)
    bk = PartKind(
        f"bearing_{brg.size}", joints.bearing_shape(brg.size, True), material=cat.BEARING_MATERIAL,
        made=False, description=f"deep groove ball bearing {brg.designation} ({brg.d_mm:g}x"
        f"{brg.D_mm:g}x{brg.B_mm:g}), crank axle at A1", process="bought", inertia_model="ring",
        mass_kg=brg.mass_kg, ring_mm=(brg.d_mm / 2, brg.D_mm / 2, brg.B_mm),
        collision=(("other", rings[0]), ("self", rings[1])), revolution=True,
        hull=joints.bearing_shape(brg.size, False))
    h = 2 * brg.B_mm + A1_LIP_MM
    return [PartInstance("a1_bearing_block", block, "ground", translation(0, 0, z0)),
            *[PartInstance(f"a1_bearing_{k + 1}", bk, "ground", translation(0, 0, z),
                           "crank", translation(0, 0, z))
              for k, z in enumerate((z0 + h - brg.B_mm, z0))]]


def _rect(rect, pl: CapstanPlacement, parts):
    """The base plate's rectangle grown to carry the moved motor's mount plate."""
    h = motor.mount_side_mm(cat.get_motor(parts.motor)) / 2
    m = max(parts.base_margin_mm, base.LEG_INSET_MM + base.LEG_DIAMETER_MM / 2)
    ox, oy = pl.motor_xy_mm
    return (min(rect[0], ox - h - m), min(rect[1], oy - h - m),
            max(rect[2], ox + h + m), max(rect[3], oy + h + m))


def _base_kind(kind: PartKind, parts, J, rect, pl: CapstanPlacement) -> PartKind:
    """The base plate with its motor opening and mount holes at the moved motor; the A1
    opening and its tapped corner holes stay for the crank's axle and its bearing block."""
    m = cat.get_motor(parts.motor)
    head_d = cat.get_cap_screw(m.bolt_size, "parts.motor").dk_mm
    opening = max(m.bolt_circle_mm + head_d + 2.0, m.pilot_diameter_mm + 2.0)
    ox, oy = pl.motor_xy_mm
    holes = motor.mount_hole_xy_mm(m) + [(x + ox, y + oy) for x, y in motor.mount_hole_xy_mm(m)]
    shape = base.base_plate_shape(rect, parts.base_thickness_mm, J["ground"]["A4"], opening, holes,
                                  motor.MOUNT_SCREW, cat.standoff_screw(parts.pin),
                                  extra_openings=((ox, oy, opening),))
    ms = motor.MOUNT_SCREW.split("-")[0]
    return dataclasses.replace(kind, shape=shape,
                               process=kind.process.replace(f"tap {ms} x4", f"tap {ms} x{len(holes)}"))


def _moved_leg(i: PartInstance, rect) -> PartInstance:

    k = int(i.name.rsplit("_", 1)[1]) - 1
    x, y = base.leg_xy_mm(rect)[k]
    tf = np.array(i.tf_body_part, float)
    tf[0, 3], tf[1, 3] = x, y
    return dataclasses.replace(i, tf_body_part=tf)


def _rz(deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    R = np.eye(4)
    R[:2, :2] = [[c, -s], [s, c]]
    return R


#: 4x4 rotation by +90 deg about y: a part's +z axis onto +x (a radial screw or hole).
_RY90 = np.array([[0.0, 0.0, 1.0, 0.0], [0.0, 1.0, 0.0, 0.0], [-1.0, 0.0, 0.0, 0.0],
                  [0.0, 0.0, 0.0, 1.0]])


def _capstan_parts(design, t, pl: CapstanPlacement) -> list[PartInstance]:
    """The drum, its anchor screw and the tensioner (crank), the capstan, its set screw and the
    two runs of rope (ground)."""
    parts, d = design.parts, t.cable_diameter_mm
    m = cat.get_motor(parts.motor)
    z0, z1 = pl.z_mm
    th = z1 - z0
    rd = cg.rim_radius_mm(t.drum_diameter_mm, d)
    tap = cat.tap_drill_mm(ANCHOR_SCREW)
    depth = ANCHOR_SCREW_LENGTH_MM + motor.TAP_LEADOUT_MM
    desc, process = grooved_drum_texts(t.drum_diameter_mm, rd, d, pl.arc_span_deg, th,
                                       "round the crank hub at A1", "fixed under the crank")
    drum = PartKind(
        "capstan_drum",
        shapes.drum_sector_shape(rd, parts.hub_diameter_mm / 2, pl.arc_start_deg, pl.arc_span_deg,
                                 th, tuple((a, tap, depth) for a in pl.anchors_deg),
                                 rope_diameter_mm=d, groove_arc_deg=drum_groove_arc_deg(rd, d, pl.anchors_deg)),
        material=fcap.DRUM_MATERIAL, made=True,
        description=desc, process=process)
    out = [PartInstance("capstan_drum", drum, "crank", translation(0, 0, z0))]
    screw = dataclasses.replace(joints.cap_screw_kind(ANCHOR_SCREW, ANCHOR_SCREW_LENGTH_MM,
                                                      "transmission", note="rope anchor on the drum"),
                                name="capstan_anchor_screw")
    seat = rd + cg.groove_depth_mm(d)  # the heads and the tensioner's nut sit on the crests
    at = [translation(0, 0, z0 + th / 2) @ _rz(a) @ translation(seat, 0, 0) @ _RY90 for a in pl.anchors_deg]
    out.append(PartInstance("capstan_anchor_1", screw, "crank", at[0]))
    out += _tensioner(t, at[1])
    out += _capstan_and_set_screw(design, t, pl, m)
    out += _rope_runs(design, t, pl)
    return out


def _tensioner(t, tf_hole) -> list[PartInstance]:
    """The tensioner at anchor 2 (:data:`TENSIONER_WIND_D`): its screw, head out, the lock
    nut on the rim (both on the crank)."""
    L, out = tensioner_screw_mm(t)
    screw = dataclasses.replace(
        joints.cap_screw_kind(ANCHOR_SCREW, L, "transmission",
                              note="rope tensioner: the rope's end wound on its shank"),
        name="capstan_tensioner_screw")
    nut = PartKind("capstan_tensioner_nut", joints.nut_shape(ANCHOR_SCREW), material=cat.FASTENER_MATERIAL,
                   made=False, description=f"hex nut ISO 4032 {ANCHOR_SCREW} (locks the rope tensioner)",
                   process="bought", revolution=True)
    return [PartInstance("capstan_tensioner", screw, "crank", tf_hole @ translation(0, 0, out)),
            PartInstance("capstan_tensioner_nut", nut, "crank", tf_hole)]


def _capstan_and_set_screw(design, t, pl: CapstanPlacement, m) -> list[PartInstance]:

    d = t.cable_diameter_mm
    rc = cg.rim_radius_mm(t.capstan_diameter_mm, d)
    length = cg.capstan_length_mm(d, t.wraps)
    z0 = pl.capstan_z_mm
    z_set = cg.CAPSTAN_HUB_MM / 2
    ox, oy = pl.motor_xy_mm
    ck = PartKind(
        "capstan", shapes.capstan_shape(rc, m.shaft_diameter_mm, length, z_set, motor.SET_SCREW,
                                        rope_diameter_mm=d, wraps=t.wraps),
        material=cg.CAPSTAN_MATERIAL, made=True,
        description=(f"capstan {t.capstan_diameter_mm:g} mm pitch (groove bottom {2 * rc:g} mm, crests "
                     f"{2 * (rc + cg.groove_depth_mm(d)):.4g} mm) on the motor "
                     f"shaft ({m.shaft_diameter_mm:g} mm bore), {length:g} mm long: {t.wraps:g} turns "
                     f"of the {d:g} mm rope in a helical groove at {cg.GROOVE_PITCH_D:g} d pitch above a "
                     f"{cg.CAPSTAN_HUB_MM:g} mm set-screw hub"),
        process=(f"turned; cut the helical rope groove ({cg.GROOVE_PITCH_D * d:.3g} mm pitch, "
                 f"{cg.groove_depth_mm(d):.3g} mm deep); tap {motor.SET_SCREW.split('-')[0]} x1 (radial)"),
        fits=(fit("hub shaft bore", m.shaft_diameter_mm, "shaft bore"),))

    size, L = capstan_set_screw(design, t)
    sk = PartKind("capstan_set_screw", motor.set_screw_shape(L, size),
                  material=cat.FASTENER_MATERIAL, made=False,
                  description=f"set screw ISO 4026 {size.split('-')[0]} x {L:g} "
                              "(capstan on the motor shaft)", process="bought")
    tf_c = translation(ox, oy, z0)
    f, _ = capstan_set_screw_fastening(design, t, "capstan", "capstan_motor_shaft")
    return [PartInstance("capstan", ck, "ground", tf_c),
            PartInstance("capstan_set_screw", sk, "ground",
                         tf_c @ translation(0, 0, z_set) @ _RY90
                         @ translation(0, 0, m.shaft_diameter_mm / 2), fastener=f)]


def _rope_runs(design, t, pl: CapstanPlacement) -> list[PartInstance]:
    """The two free runs of rope on the drum's mid-plane (ground: fixed while the crank turns),
    each with a collision envelope trimmed by :func:`run_trim_mm` at both ends."""
    c = design.parts.clearance_min_mm + 0.1
    out = []
    for k in range(2):
        p0, p1 = (np.append(p, pl.rope_z_mm) for p in pl.tangents_mm[k])
        kind = rope_run_kind(f"capstan_rope_run_{k + 1}", p0, p1, t, c, f"free run {k + 1} of the rope",
                             groove_depth_mm=cg.groove_depth_mm(t.cable_diameter_mm))
        out.append(PartInstance(kind.name, kind, "ground", np.eye(4)))
    return out
