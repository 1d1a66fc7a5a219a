"""A mushroom handle for the coupler point P, written in cadquery (hapticad user part script).

hapticad runs this file and calls ``make_handle(params)``; the returned cadquery
Workplane becomes an OCP shape and goes through the same pipeline as the built-in
parts (mass properties, interference sweep, STEP/STL export). Frame: z = 0 on the
coupler's top face, axis through P, z up, millimetres.

``params`` (from the design's [parts] table): ``diameter_mm``, ``height_mm``,
``screw_clearance_mm``, ``counterbore_mm``, ``floor_mm`` (the ISO 4762 screw from the
top goes through the floor into the tapped coupler).
"""

import cadquery as cq


def make_handle(params):
    d = params["diameter_mm"]
    h = params["height_mm"]
    stem_h = 0.55 * h
    knob = (
        cq.Workplane("XY")
        .circle(0.36 * d)
        .extrude(stem_h)
        .faces(">Z")
        .workplane()
        .circle(d / 2)
        .extrude(h - stem_h)
        .faces(">Z")
        .edges()
        .fillet(0.2 * d)
    )
    passage = cq.Workplane("XY").circle(params["screw_clearance_mm"] / 2).extrude(h)
    counterbore = (
        cq.Workplane("XY")
        .workplane(offset=params["floor_mm"])
        .circle(params["counterbore_mm"] / 2)
        .extrude(h)
    )
    return knob.cut(passage).cut(counterbore)
