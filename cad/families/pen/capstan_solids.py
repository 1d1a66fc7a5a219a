"""The haptic pen's waist capstans as solids of its one assembly (issue 35): the 5-bar's
capstan solids (:mod:`cad.families.pantograph.capstan_solids`) about each vertical waist axis.

At each waist axis the waist bracket turns on its own axle (the waist motor's shaft diameter,
from the bearing block's bottom to the waist hub's top, the hub pinned on it) in two deep groove
ball bearings seated in a bearing block screwed under the base plate where the waist motor's
mount plate sat; the drum sector on the axle in the drums' band between the base plate and the
waist hub (z ``layer_gap_mm`` .. + :data:`cad.assembly.capstan_hardware.DRUM_THICKNESS_MM` over
the base plate's top: the base plate, the legs and the bench stand that band lower under the
arms, :func:`cad.families.pen.layout.ground_layout`), with its rope
anchor and tensioner; the waist motor (its mount plate and screws) moved under the base plate to
where :func:`cad.families.pen.capstan_layout.layout` puts it, its capstan and set screw on its
shaft in the rope's plane, the two free runs of rope. The drum's arc in the waist frame:
:func:`cad.families.pen.capstan_layout.drum_arc_body_deg`.

Frames: the 5-bar's capstan solids are laid out with z = 0 on the base plate's top
(:func:`cad.families.pantograph.capstan_solids.block_parts` ...); the pen's world has its base
plate's top at ``ground_mm["base_top_z_mm"]``: the ground's parts are lifted by it
(:func:`lifted`), the drum is placed in the waist frame (z = world z, origin on the waist axis).

The shoulder capstans (drums on the proximal links, motors on the waist bracket's motor plate)
are :mod:`cad.families.pen.shoulder_capstan`.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from cad.actuators import capstan_geometry as cg
from cad.assembly.capstan_hardware import (
    DRUM_THICKNESS_MM,
    axle_bearing,
    capstan_set_screw_fastening,
)
from cad.data import catalog as cat
from cad.device import resolve_device
from cad.families.pantograph import capstan_solids as pcs
from cad.families.pantograph.capstan import CLEARANCE_MM
from cad.families.pen import capstan_layout as cl
from cad.families.pen.capstan import pen_kind_group
from cad.parts import translation

#: The waist axle's words in the shared capstan solids' part texts (:data:`pcs.CARRIER`).
CARRIER = {"axle": "waist_axle", "link": "waist bracket", "drum_link": "bracket",
           "fixing": "the waist hub pinned on it", "at": "the waist axis"}


def waist_sides(design) -> tuple:
    """The waists' two :class:`cad.families.pantograph.capstan.CapstanSide` with the drum's arc
    and anchors in the waist frame (:func:`cad.families.pen.capstan_layout.drum_arc_body_deg`;
    the motor, its tangent points and ``b_mm`` stay in the world's (x, y), mm); ``()`` when the
    waists are direct or not laid out (the build refuses that first)."""
    for pair in cl.layout(design):
        if pair.name == "waists" and pair.clash is None:
            out = []
            for sd in pair.sides:
                s0, sp, an = cl.drum_arc_body_deg(sd)
                out.append(dataclasses.replace(sd, arc_start_deg=s0, arc_span_deg=sp, anchors_deg=an))
            return tuple(out)
    return ()


def band_mm(design) -> float:
    """How much lower the base plate stands under the waist hubs for the waist drums' band
    (mm): a layer gap and a drum; 0 when the waists are direct."""
    return design.parts.layer_gap_mm + DRUM_THICKNESS_MM if waist_sides(design) else 0.0


def stations_xy_mm(design) -> dict[str, tuple[float, float]]:
    """``{arm: (x, y)}`` of each waist motor's axis (mm, world): on its waist axis, or moved by
    its capstan (:func:`waist_sides`)."""
    l4 = design.mechanism.l4_mm
    out = {"A": (-l4 / 2, 0.0), "B": (l4 / 2, 0.0)}
    for sd in waist_sides(design):
        out[sd.joint[0]] = tuple(float(v) for v in sd.motor_xy_mm)
    return out


def capstan_lay(design, gl: dict, mount_plan: dict) -> dict:
    """The layout the 5-bar's capstan solids read (its frame: z = 0 on the base plate's top):
    the waists' sides, the rope's plane and the drums' band over the plate, the waist motor,
    the axle's top (the waist hub's), the carrier's words (:data:`CARRIER`), the mount screws'
    plan (``mount_plan``: :func:`cad.families.pantograph.build.screw_plan`'s ``mount``)."""
    g = design.parts.layer_gap_mm
    zb = gl["base_top_z_mm"]
    return {"capstan": {"sides": waist_sides(design), "rope_z_mm": g + DRUM_THICKNESS_MM / 2,
                        "drum_z_mm": (g, g + DRUM_THICKNESS_MM), "motor": design.parts.waist_motor,
                        "axle_top_mm": gl["waist_hub_mm"][1] - zb, "carrier": CARRIER,
                        "kind_group": pen_kind_group},
            "screws": {"mount": mount_plan}}


def kinds(design, gl: dict, mount_plan: dict) -> dict:
    """The capstan drives' part kinds (:func:`cad.families.pantograph.capstan_solids.capstan_kinds`
    on :func:`capstan_lay`), after the capstans' height check
    (:func:`cad.families.pantograph.capstan_solids.check_capstan_z`: DesignError naming
    ``transmission.wraps``)."""
    lay = capstan_lay(design, gl, mount_plan)
    pcs.check_capstan_z(design, lay)
    return pcs.capstan_kinds(design, lay)


def lifted(inst, zb_mm: float):
    """A ground instance of the 5-bar's frame lifted onto the pen's base plate (its top at
    ``zb_mm``, world z)."""
    return dataclasses.replace(inst, tf_body_part=translation(0, 0, zb_mm) @ inst.tf_body_part)


def instances(design, Kc: dict, gl: dict, mount_plan: dict, screw_kind, motor_shaft_kind,
              tf_world_body: dict) -> tuple[list, dict]:
    """The waist capstans' instances (module docstring) and the bearing blocks' tapped holes in
    the base plate. ``Kc``: :func:`kinds`; ``screw_kind`` the mount screws' kind;
    ``motor_shaft_kind`` the waist motor's shaft; ``tf_world_body`` the bodies at home (mm)."""
    lay = capstan_lay(design, gl, mount_plan)
    zb = gl["base_top_z_mm"]
    K = {**Kc, "motor_shaft": motor_shaft_kind}
    dev = resolve_device(design)
    lift = translation(0, 0, zb)
    out, holes = [], {}
    for sd in lay["capstan"]["sides"]:
        arm = sd.joint[0]
        body = f"{arm}_waist"
        t, i = dev.transmission(sd.joint), pcs.rope_index(design, sd.joint)
        blk, h = pcs.block_parts(design, K, lay, i, arm, sd.b_mm, screw_kind,
                                 np.linalg.inv(lift) @ tf_world_body[body], body=body)
        ground = blk + pcs.motor_side_parts(design, K, lay, sd, t, i, motor_name=f"{arm}_waist_motor")
        hole = capstan_set_screw_fastening(design, t, f"capstan_{i}", f"{arm}_waist_motor.shaft",
                                           pcs.motor_key(design, lay))[1]  # the capstan's tapped hole
        h = {**h, hole.name: hole}
        out += [lifted(x, zb) for x in ground]
        drum_lay = {**lay, "capstan": {**lay["capstan"], "drum_z_mm": tuple(zb + z for z in lay["capstan"]["drum_z_mm"])}}
        out += pcs.drum_parts(design, K, drum_lay, sd, t, body=body)
        holes.update(h)
    return out, holes


def axle_z_mm(design, gl: dict) -> float:
    """The waist axle's bottom (mm, world z = the waist frame's): the bearing block's bottom."""
    return gl["base_top_z_mm"] + pcs.axle_z_mm(design, design.parts.waist_motor)


def opening_mm(design) -> float:
    """The base plate's opening over a moved waist motor (mm): the capstan's crests and
    :data:`cad.families.pantograph.capstan.CLEARANCE_MM` all round, at least the direct pen's
    (pilot and face screws' heads, the caller's)."""
    ts = [resolve_device(design).transmission(sd.joint) for sd in waist_sides(design)]
    return max((2 * cg.crest_radius_mm(t.capstan_diameter_mm, t.cable_diameter_mm) + 2 * CLEARANCE_MM
                for t in ts), default=0.0)


def axle_hole_mm(design) -> float:
    """The base plate's clearance hole for a waist axle (mm): the bearing's housing abutment
    diameter Da (the block's lip bore)."""
    return axle_bearing(cat.get_motor(design.parts.waist_motor).shaft_diameter_mm).Da_mm
