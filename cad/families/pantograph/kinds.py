"""Every distinct part (:class:`cad.parts.PartKind`) of a pantograph-family device, by name:
clevises and tubes of the links, pins, bearings, motors and their mounts, plates, legs,
screws, the knob, and the twin's crankshaft, posts and bridge."""

from __future__ import annotations

from cad.data.catalog import (
    FASTENER_MATERIAL,
    clearance_hole_mm,
    get_bearing,
    get_cap_screw,
    tap_drill_mm,
)
from cad.data.fits import fit
from cad.device import parts_motor
from cad.families.pantograph.capstan_solids import capstan_kinds
from cad.families.pantograph.layout import (
    KNOB_BORE_DEPTH_MM,
    PLAIN_KNOB_DIAMETER_MM,
    POST_SCREW,
    POST_TAP_DEPTH_MM,
    group_lay,
    is_twin,
    leg_xy,
    lower_five_bar,
)
from cad.parts import PartKind, base, joints
from cad.parts import motor as pm
from cad.parts import pantograph as pp


def hub_seat(lay: dict) -> str:
    """What the hub clevis sits on, for its and its set screw's descriptions: the link's own
    axle where a capstan turns the link (the 5-bar's ``capstan``; the twin's ``twin_capstan``
    on both 5-bars), the motor shaft under direct drive, both named on a twin mixing them."""
    tcap = lay.get("twin_capstan", {})
    if "capstan" in lay or len(tcap) == 2:
        return "link axle"
    return "link axle (capstan 5-bar) or motor shaft (direct 5-bar)" if tcap else "motor shaft"


def raised_note(lay: dict) -> str:
    """``", one on its top through its opening"`` when a twin's capstan motor is raised
    (its mount plate on the base plate's top, ``raise_mm`` > 0), else ``""``."""
    raised = any(r > 0 for g in lay.get("twin_capstan", {}).values() for r in g.get("raise_mm", ()))
    return ", one on its top through its opening" if raised else ""


def part_kinds(design, lay: dict, fidelity: str) -> dict:
    """Every distinct part (:class:`cad.parts.PartKind`) of the design, by name (in the
    order the part groups below add them)."""
    from types import SimpleNamespace

    p = design.parts
    fb = lower_five_bar(design)
    c = SimpleNamespace(design=design, p=p, lay=lay, brg=get_bearing(p.bearing),
                        mot=parts_motor(design)[0], B=[fb.base_left_mm, fb.base_right_mm],
                        twin=is_twin(design), fidelity=fidelity)
    K: dict[str, PartKind] = {}

    def add(name, shape, material, made, description, process, **kw):
        K[name] = PartKind(
            name=name,
            shape=shape,
            material=material,
            made=made,
            description=description,
            process=process,
            **kw,
        )

    _clevis_kinds(add, K, c)
    _link_kinds(add, K, c)
    _motor_kinds(add, K, c)
    holes = _plate_holes(c, "crank" if c.twin else None)
    _base_kinds(add, K, c, holes)
    _screws_kinds(add, K, c)
    _knob_kinds(add, K, c)
    if c.twin:
        _twin_kinds(add, K, c, _plate_holes(c, "knob"))
    if "capstan" in lay:  # a capstan on each motor (cad.families.pantograph.capstan_solids)
        K.update(capstan_kinds(design, lay))
    for grp in lay.get("twin_capstan", {}):  # the twin's: the same solids per 5-bar
        K.update(capstan_kinds(design, group_lay(lay, grp)))
    return K


def _clevis_kinds(add, K: dict, c) -> None:
    """The three clevises (hub on the motor shaft, pin, bearing) and the hub's set screw."""
    p, lay, brg, mot = c.p, c.lay, c.brg, c.mot
    cl = dict(
        length_mm=p.clevis_length_mm,
        width_mm=p.clevis_width_mm,
        height_mm=p.clevis_height_mm,
        socket_depth_mm=p.socket_depth_mm,
        tube_od_mm=p.tube_od_mm,
    )
    cm = p.clevis_material
    ss = lay["set_screw"]
    sz = ss["size"].split("-")[0]
    add(
        "clevis_hub",
        pp.clevis_shape("hub", bore_mm=mot.shaft_diameter_mm,
                        set_screw_drill_mm=tap_drill_mm(ss["size"]), **cl),
        cm,
        True,
        f"clevis on the {hub_seat(lay)} ({sz} set screw)",
        f"CNC milled; ream shaft bore; tap {sz} x1 (radial)",
        fits=(fit("hub shaft bore", mot.shaft_diameter_mm, "shaft bore"),),
    )
    add(
        "set_screw",
        pm.set_screw_shape(ss["length_mm"], ss["size"]),
        FASTENER_MATERIAL,
        False,
        f"set screw ISO 4026 {ss['size']} x {ss['length_mm']:g} (locks the clevis on the "
        f"{hub_seat(lay)})",
        "bought",
    )
    add(
        "clevis_pin",
        pp.clevis_shape("pin", bore_mm=brg.d_mm, **cl),
        cm,
        True,
        "clevis at the elbow, pin pressed in",
        "CNC milled; ream pin bore",
        fits=(fit("pin bore", brg.d_mm),),
    )
    add(
        "clevis_bearing",
        pp.clevis_shape("bearing", bore_mm=brg.D_mm, **cl),
        cm,
        True,
        "clevis with two ball bearings",
        "CNC milled; bore bearing seat (both bearings)",
        fits=(fit("bearing seat", brg.D_mm),),
    )


def _link_kinds(add, K: dict, c) -> None:
    """The tubes, the elbow pins and the ball bearing of the links."""
    p, lay, brg, fidelity = c.p, c.lay, c.brg, c.fidelity
    tm = p.tube_material
    for which in ("proximal", "distal"):
        L = lay[f"tube_{which}_mm"]
        add(
            f"tube_{which}",
            pp.tube_shape(L, p.tube_od_mm, p.tube_id_mm),
            tm,
            True,
            f"tube {p.tube_od_mm:g}/{p.tube_id_mm:g} x {L:g} mm, {which} links",
            "cut to length, bonded",
        )
    add(
        "pin_short",
        pp.pin_shape(brg.d_mm, lay["pin_short_mm"]),
        p.pin_material,
        True,
        f"elbow pin d{brg.d_mm:g} x {lay['pin_short_mm']:g}, left arm",
        "ground dowel, cut",
        fits=(fit("pin", brg.d_mm),),
        revolution=True,
    )
    add(
        "pin_long",
        pp.pin_shape(brg.d_mm, lay["pin_long_mm"]),
        p.pin_material,
        True,
        f"elbow pin d{brg.d_mm:g} x {lay['pin_long_mm']:g}, right arm",
        "ground dowel, cut",
        fits=(fit("pin", brg.d_mm),),
        revolution=True,
    )
    detailed = fidelity == "fabrication"
    rings = joints.bearing_rings(p.bearing)
    add(
        "bearing",
        joints.bearing_shape(p.bearing, detailed),
        "steel-1018",
        False,
        f"ball bearing {brg.designation} ({p.bearing})",
        "bought",
        mass_kg=brg.mass_kg,
        inertia_model="ring",
        ring_mm=(brg.d_mm / 2, brg.D_mm / 2, brg.B_mm),
        # the interference check: inner ring on the journal's body, outer ring in the seat
        collision=(("other", rings[0]), ("self", rings[1])),
        revolution=True,
        hull=joints.bearing_shape(p.bearing, False) if detailed else None,
    )


def _motor_kinds(add, K: dict, c) -> None:
    """The motor, its shaft (a solid of the motor, not listed) and its mount plate."""
    p, mot = c.p, c.mot
    add(
        "motor",
        pm.motor_housing_shape(mot),
        "steel-1018",
        False,
        mot.bom_description(),
        f"bought; face tapped {mot.bolt_size.split('-')[0]} x{mot.bolt_count}; with its "
        "shaft (solid motor_shaft in assembly.step)",
        mass_kg=mot.mass_kg,
    )
    add(
        "motor_shaft",
        pm.motor_shaft_shape(mot),
        "steel-1018",
        False,
        "motor shaft",
        "part of the motor",
        inertia_model="none",
        listed=False,
        revolution=True,
    )
    add(
        "motor_mount",
        pm.motor_mount_shape(mot, p.motor_mount_thickness_mm),
        p.plate_material,
        True,
        "motor mount plate",
        "waterjet/laser plate; bore the pilot seat",
        plate=True,
        fits=(fit("pilot bore", mot.pilot_diameter_mm),),
    )


def _plate_holes(c, group: str | None) -> tuple:
    """Holes of the base or bridge plate ``(x_mm, y_mm, diameter_mm)``: ``(motor openings,
    mount screw taps, post clearance holes, leg clearance holes, mount screw size, plate
    thickness mm)``; ``group`` the twin's 5-bar whose motors the plate carries (``"crank"``:
    the base plate, ``"knob"``: the bridge), None on the 5-bar."""
    p, lay, mot, B = c.p, c.lay, c.mot, c.B
    pt = p.plate_thickness_mm
    cap = lay.get("capstan", {}) if group is None else lay.get("twin_capstan", {}).get(group, {})
    # a capstan drive: the bearing blocks at B, the motors moved off B (both on mount holes)
    B = list(B) + [sd.motor_xy_mm for sd in cap.get("sides", ())]
    mount_holes = [
        (bx + x, by + y, tap_drill_mm(pm.MOUNT_SCREW))
        for bx, by in B
        for x, y in pm.mount_hole_xy_mm(mot)
    ]
    # the motor face screws' heads sit in the plate's opening (four-bars do the same)
    head_d = get_cap_screw(mot.bolt_size, "parts.motor").dk_mm
    opening = max(mot.pilot_diameter_mm + 2 * pp.OPENING_MARGIN_MM,
                  mot.bolt_circle_mm + head_d + 2 * pp.OPENING_MARGIN_MM)
    openings = [(bx, by, opening) for bx, by in B]
    # a raised motor (its mount plate on the plate's top) passes its body down through its opening
    body = mot.body_diameter_mm + 2 * pp.OPENING_MARGIN_MM
    for sd, up in zip(cap.get("sides", ()), cap.get("raise_mm", ()), strict=False):
        if up > 0:
            openings = [(x, y, max(d, body) if (x, y) == tuple(sd.motor_xy_mm) else d) for x, y, d in openings]
    ms = pm.MOUNT_SCREW.split("-")[0]
    leg_holes = [(x, y, clearance_hole_mm(base.LEG_SCREW)) for x, y in leg_xy(lay)]
    post_holes = [(x, y, clearance_hole_mm(POST_SCREW)) for x, y in lay.get("posts_xy_mm", ())]
    return openings, mount_holes, post_holes, leg_holes, ms, pt


def _base_kinds(add, K: dict, c, holes) -> None:
    """The base plate (motors under it, legs at its corners) and the leg standoffs."""
    p, lay = c.p, c.lay
    openings, mount_holes, post_holes, leg_holes, ms, pt = holes
    add(
        "base_plate",
        pp.plate_shape(
            lay["base_plate_x_mm"],
            lay["base_plate_y_mm"],
            pt,
            openings + mount_holes + post_holes + leg_holes,
        ),
        p.plate_material,
        True,
        f"base plate (motors under{raised_note(lay)}, legs at the corners)",
        f"waterjet/laser plate; tap {ms} x{len(mount_holes)}",
        plate=True,
    )
    lh = lay["leg_height_mm"]
    add(
        "leg",
        base.leg_shape(lh),
        p.plate_material,
        True,
        f"leg standoff d{base.LEG_DIAMETER_MM:g} x {lh:g}, tapped {base.LEG_SCREW} both ends",
        f"turned; tap {base.LEG_SCREW.split('-')[0]} both ends",
    )


def _screws_kinds(add, K: dict, c) -> None:
    """One cap screw kind per screw group of :func:`cad.families.pantograph.layout.screw_plan` (also under the alias ``_<group>_screw``)."""
    lay = c.lay
    steel = FASTENER_MATERIAL

    def screw(size, L):
        name = f"cap_screw_{size}x{L:g}"
        if name not in K:
            cs = get_cap_screw(size, "parts")
            add(
                name,
                joints.cap_screw_shape(size, L),
                steel,
                False,
                f"socket head cap screw ISO 4762 {size} x {L:g}",
                "bought",
                collision=(("self", joints.screw_envelope(cs.dk_mm, cs.k_mm, cs.d_mm, L)),),
            )
        return name

    for g, sp in lay["screws"].items():
        K[f"_{g}_screw"] = K[screw(sp["size"], sp["length_mm"])]


def _knob_kinds(add, K: dict, c) -> None:
    """The knob and, on the plain 5-bar, the handle pin; the mouse's knob rides the crankshaft."""
    design, p, lay, brg, twin = c.design, c.p, c.lay, c.brg, c.twin
    kd = design.mechanism.knob_diameter_mm if twin else PLAIN_KNOB_DIAMETER_MM
    add(
        "knob",
        pp.knob_shape(kd, p.knob_height_mm, brg.d_mm, KNOB_BORE_DEPTH_MM),
        p.knob_material,
        True,
        f"knob, diameter {kd:g} mm",
        "turned; ream pin bore",
        fits=(fit("pin bore", brg.d_mm),),
        revolution=True,
    )
    if not twin:
        add(
            "handle_pin",
            pp.pin_shape(brg.d_mm, lay["handle_pin_mm"]),
            p.pin_material,
            True,
            f"handle pin d{brg.d_mm:g} x {lay['handle_pin_mm']:g} (end effector E)",
            "ground dowel, cut",
            fits=(fit("pin", brg.d_mm),),
            revolution=True,
        )
        return


def _twin_kinds(add, K: dict, c, holes) -> None:
    """The twin pantograph's crankshaft, bridge posts and bridge plate."""
    design, p, lay, brg = c.design, c.p, c.lay, c.brg
    openings, mount_holes, post_holes, leg_holes, ms, pt = holes
    l6 = design.mechanism.crank_mm
    add(
        "crankshaft",
        pp.crankshaft_shape(
            l6,
            brg.d_mm,
            lay["web_width_mm"],
            p.crank_thickness_mm,
            lay["journal_up_mm"],
            lay["crank_pin_down_mm"],
        ),
        p.crank_material,
        True,
        f"crankshaft, l6 = {l6:g} mm (eq 7)",
        "turned + milled; grind both journals",
        fits=(fit("journal", brg.d_mm),),
    )
    add(
        "post",
        pp.post_shape(
            p.post_diameter_mm,
            lay["bridge_bottom_z_mm"],
            tap_drill_mm(POST_SCREW),
            POST_TAP_DEPTH_MM,
        ),
        p.plate_material,
        True,
        f"bridge post d{p.post_diameter_mm:g}, tapped {POST_SCREW} both ends",
        f"turned; tap {POST_SCREW.split('-')[0]} both ends",
    )
    add(
        "bridge_plate",
        pp.plate_shape(
            lay["bridge_x_mm"], lay["bridge_y_mm"], pt, openings + mount_holes + post_holes
        ),
        p.plate_material,
        True,
        "bridge plate (upper motors)",
        f"waterjet/laser plate; tap {ms} x{len(mount_holes)}",
        plate=True,
    )
