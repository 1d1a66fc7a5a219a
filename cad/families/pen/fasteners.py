"""The pen's screws: each placed with its :class:`cad.assembly.fasteners.Fastener` record and
the tapped hole it engages, sized by the twin pantograph's screw plan
(:func:`cad.families.pantograph.build.screw_plan`: catalog ISO 4762 lengths from each stack).

Groups: ``leg`` (base plate onto each leg standoff), ``mount`` (each waist motor mount plate
into the base plate, from below), ``motor`` (motor faces: through each waist mount plate from
above, heads in the base plate's opening; through the waist bracket's motor plate from the
link side into each shoulder motor). The waist motors' faces take the shoulder motors' screw
(same thread and depth; DesignError otherwise).
"""

from __future__ import annotations

from cad.assembly.fasteners import Fastener, TappedHole
from cad.data.catalog import FASTENER_MATERIAL, get_cap_screw, get_motor
from cad.errors import DesignError
from cad.families.pantograph.build import screw_plan
from cad.families.pantograph.layout import leg_xy
from cad.families.pen.capstan_solids import stations_xy_mm
from cad.families.pen.shoulder_capstan import motor_xz_mm
from cad.parts import joints
from cad.parts import motor as pm
from cad.parts import translation as tr


def screw_kinds(design, add) -> dict[str, str]:
    """Add the cap screw kinds of every group; returns ``{group: kind name}``."""
    p = design.parts
    sm, wm = get_motor(p.motor), get_motor(p.waist_motor)
    if (wm.bolt_size, wm.bolt_thread_depth_mm) != (sm.bolt_size, sm.bolt_thread_depth_mm):
        raise DesignError("parts.waist_motor", f"{wm.key} face screws ({wm.bolt_size}, "
                          f"{wm.bolt_thread_depth_mm:g} mm deep) differ from {sm.key}'s")
    plan = screw_plan(design)
    out = {}
    for g, sp in plan.items():
        size, L = sp["size"], sp["length_mm"]
        name = f"cap_screw_{size}x{L:g}"
        cs = get_cap_screw(size, "parts")
        add(name, joints.cap_screw_shape(size, L), FASTENER_MATERIAL, False,
            f"socket head cap screw ISO 4762 {size} x {L:g}", "bought",
            collision=(("self", joints.screw_envelope(cs.dk_mm, cs.k_mm, cs.d_mm, L)),))
        out[g] = name
    return out


def bracket_bolt_xz_mm(design, arm: str = "A") -> list[tuple[float, float]]:
    """(x, z) of arm ``arm``'s shoulder motor face screws in its waist frame (mm): about each
    shoulder axis, or about the motor moved off it by a shoulder capstan
    (:func:`cad.families.pen.shoulder_capstan.motor_xz_mm`; the arms' waist frames are mirror
    images, so arm B's motors stand at the mirrored x)."""
    l1 = design.mechanism.shoulder_base_mm
    st = motor_xz_mm(design)  # shoulder capstans: each motor moved off its axis
    centres = [st.get(f"{arm}_q_{r}", (0.0, z)) for r, z in (("lower", -l1 / 2), ("upper", l1 / 2))]
    return [(xs + x, zs + y) for xs, zs in centres
            for x, y in pm.motor_bolt_xy_mm(get_motor(design.parts.motor))]


def place_screws(design, lay: dict, gl: dict, kinds: dict, place, rot) -> dict:
    """Place every screw (``place(name, kind, body, tf, fastener)``; ``rot(axis, deg)`` a 4x4
    rotation); returns ``{hole name: TappedHole}``."""
    plan = screw_plan(design)
    p = design.parts
    holes: dict = {}

    def screw(group, name, body, tf, hole, part, clamps):
        sp = plan[group]
        holes[hole] = TappedHole(hole, part, sp["size"], sp["depth_mm"], sp["min_engagement_mm"])
        place(name, kinds[group], body, tf,
              Fastener("ISO 4762", sp["size"], sp["length_mm"], clamps, hole, sp["engagement_mm"]))


    for i, (x, y) in enumerate(leg_xy(gl)):
        screw("leg", f"leg_screw_{i + 1}", "ground", tr(x, y, gl["base_top_z_mm"]),
              f"leg_{i + 1}:top", f"leg_{i + 1}", ("base_plate",))
    wm = get_motor(p.waist_motor)
    zb, pt, mt = gl["base_top_z_mm"], p.plate_thickness_mm, p.motor_mount_thickness_mm
    flip = rot("x", 180)
    for arm, (bx, by) in stations_xy_mm(design).items():  # each waist motor, on its axis or moved
        for k, (x, y) in enumerate(pm.mount_hole_xy_mm(wm)):
            screw("mount", f"{arm}_mount_screw_{k + 1}", "ground",
                  tr(bx + x, by + y, zb - pt - mt) @ flip, f"base_plate:{arm}_mount_{k + 1}",
                  "base_plate", (f"{arm}_waist_motor_mount",))
        for k, (x, y) in enumerate(pm.motor_bolt_xy_mm(wm)):
            screw("motor", f"{arm}_waist_motor_screw_{k + 1}", "ground", tr(bx + x, by + y, zb - pt),
                  f"{arm}_waist_motor:face_{k + 1}", f"{arm}_waist_motor",
                  (f"{arm}_waist_motor_mount",))
        y0 = lay["motor_plate_mm"][0]
        nb = get_motor(p.motor).bolt_count
        for k, (x, z) in enumerate(bracket_bolt_xz_mm(design, arm)):
            motor = f"{arm}_waist.motor_shoulder{2 + k // nb}"
            screw("motor", f"{arm}_waist.shoulder_screw_{k + 1}", f"{arm}_waist",
                  tr(x, y0, z) @ rot("x", 90), f"{motor}:face_{k % nb + 1}", motor,
                  (f"{arm}_waist.waist_bracket0",))
    return holes

