"""Part scripts of the twin-pantograph haptic mouse (isotropy paper §4.1, Fig. 1).

Parameters in, solids out (OCP ``TopoDS_Shape``, mm); build123d is imported
inside each function. Frames:

* clevis -- joint axis = z, z centred on the link's layer (-h/2 .. h/2), the
  link running along +x; the tube socket is a blind bore along x ending at
  x = clevis_length_mm;
* tube -- along +x from x = 0, axis at y = z = 0;
* pin -- axis z, from z = 0 up to its length;
* crankshaft -- origin on the main-journal axis at the web's mid-plane, crank
  pin at (+l6, 0); main journal up (+z), crank pin down (-z);
* knob -- axis z, z 0..height, bore from below;
* plates -- z 0..thickness, features in the plate's xy plane.

Clevis kinds (bore at the joint): ``hub`` (motor shaft, clamped with a set
screw), ``pin`` (press fit of the elbow pin), ``bearing`` (two ball bearings
side by side). Bearings and motors are bought (bd_warehouse / catalogue
envelope, see :mod:`cad.parts.joints` and :mod:`cad.parts.motor`).
"""

from __future__ import annotations

import math

from cad.tolerances import OPENING_MARGIN_MM  # noqa: F401 - read as pp.OPENING_MARGIN_MM by the builder

#: Diametral press-fit interference of the elbow pins in their clevis bore (mm):
#: the bore is drawn at nominal (the interference is a machining note).
PIN_PRESS_FIT_MM = 0.0


def _amin():
    from build123d import Align

    return (Align.CENTER, Align.CENTER, Align.MIN)


def clevis_shape(
    kind: str,
    length_mm: float,
    width_mm: float,
    height_mm: float,
    socket_depth_mm: float,
    tube_od_mm: float,
    bore_mm: float,
    set_screw_drill_mm: float = 2.5,
):
    """Aluminium clevis: rounded block, joint bore (z) at the origin, tube socket along +x.

    kind: "hub" | "pin" | "bearing" (only the bore diameter ``bore_mm`` and, for a
    hub, a radial set-screw tap-drill hole of ``set_screw_drill_mm`` along -x at z = 0, through
    the wall into the bore).
    """
    from build123d import Box, Cylinder, Pos, Rot

    h, w, L = height_mm, width_mm, length_mm
    body = Cylinder(w / 2, h) + Pos(L / 2, 0, 0) * Box(L, w, h)
    body = body - Cylinder(bore_mm / 2, h)
    sock = (
        Pos(L - socket_depth_mm / 2, 0, 0)
        * Rot(0, 90, 0)
        * Cylinder(tube_od_mm / 2, socket_depth_mm)
    )
    body = body - sock
    if kind == "hub":
        # set screw: radial tap-drill hole from the -x side into the shaft bore
        body = body - Pos(-w / 4, 0, 0) * Rot(0, 90, 0) * Cylinder(set_screw_drill_mm / 2, w / 2)
    elif kind not in ("pin", "bearing"):
        raise ValueError(f"unknown clevis kind {kind!r}")
    return body.solids()[0].wrapped


def tube_shape(length_mm: float, od_mm: float, id_mm: float):
    """Carbon-fibre tube along +x, x 0..length."""
    from build123d import Cylinder, Pos, Rot

    t = Cylinder(od_mm / 2, length_mm) - Cylinder(id_mm / 2, length_mm)
    return (Pos(length_mm / 2, 0, 0) * Rot(0, 90, 0) * t).solids()[0].wrapped


def pin_shape(diameter_mm: float, length_mm: float):
    """Steel dowel pin, axis z, z 0..length."""
    from build123d import Cylinder

    return Cylinder(diameter_mm / 2, length_mm, align=_amin()).solids()[0].wrapped


def crankshaft_shape(
    crank_mm: float,
    journal_d_mm: float,
    boss_d_mm: float,
    web_thickness_mm: float,
    journal_up_mm: float,
    pin_down_mm: float,
):
    """Crankshaft: a stadium web (l6 between axes, width boss_d) at z -t/2..t/2, the main
    journal rising journal_up_mm above the web at the origin, the crank pin hanging
    pin_down_mm below it at (l6, 0). One machined part."""
    from build123d import Box, Cylinder, Pos

    t = web_thickness_mm
    web = Cylinder(boss_d_mm / 2, t) + Pos(crank_mm, 0, 0) * Cylinder(boss_d_mm / 2, t)
    web = web + Pos(crank_mm / 2, 0, 0) * Box(crank_mm, boss_d_mm, t)
    up = Pos(0, 0, t / 2) * Cylinder(journal_d_mm / 2, journal_up_mm, align=_amin())
    down = Pos(crank_mm, 0, -t / 2 - pin_down_mm) * Cylinder(
        journal_d_mm / 2, pin_down_mm, align=_amin()
    )
    return (web + up + down).solids()[0].wrapped


def knob_shape(diameter_mm: float, height_mm: float, bore_mm: float, bore_depth_mm: float):
    """Knob (diameter l5 of eq 7): cylinder with a 1 mm top chamfer and a blind bore from below."""
    from build123d import Cylinder, chamfer

    k = Cylinder(diameter_mm / 2, height_mm, align=_amin())
    top = k.edges().sort_by()[-1]
    k = chamfer(top, 1.0)
    k = k - Cylinder(bore_mm / 2, bore_depth_mm, align=_amin())
    return k.solids()[0].wrapped


def plate_shape(
    x_range_mm: tuple[float, float],
    y_range_mm: tuple[float, float],
    thickness_mm: float,
    holes: list[tuple[float, float, float]],
    corner_radius_mm: float = 5.0,
):
    """Flat plate (base plate, bridge) with round holes ``(x, y, diameter)``; z 0..thickness."""
    from build123d import Circle, Pos, RectangleRounded, extrude

    (x0, x1), (y0, y1) = x_range_mm, y_range_mm
    sk = Pos((x0 + x1) / 2, (y0 + y1) / 2) * RectangleRounded(x1 - x0, y1 - y0, corner_radius_mm)
    for x, y, d in holes:
        sk = sk - Pos(x, y) * Circle(d / 2)
    return extrude(sk, amount=thickness_mm).solids()[0].wrapped


def post_shape(diameter_mm: float, height_mm: float, tap_d_mm: float, tap_depth_mm: float):
    """Turned standoff, z 0..height, tapped (tap drill) at both ends."""
    from build123d import Cylinder, Pos

    a = _amin()
    p = Cylinder(diameter_mm / 2, height_mm, align=a)
    p = p - Cylinder(tap_d_mm / 2, tap_depth_mm, align=a)
    p = p - Pos(0, 0, height_mm - tap_depth_mm) * Cylinder(tap_d_mm / 2, tap_depth_mm, align=a)
    return p.solids()[0].wrapped


def ring_solid(r_in_mm: float, r_out_mm: float, height_mm: float):
    """Plain ring z 0..height (bearing stand-in at preview/inertia fidelity)."""
    from build123d import Cylinder

    a = _amin()
    return (
        (Cylinder(r_out_mm, height_mm, align=a) - Cylinder(r_in_mm, height_mm, align=a))
        .solids()[0]
        .wrapped
    )


def tube_length_mm(link_mm: float, clevis_length_mm: float, socket_depth_mm: float) -> float:
    """Length of the tube between two clevises whose joints are ``link_mm`` apart."""
    return link_mm - 2.0 * (clevis_length_mm - socket_depth_mm)


def stadium_area_mm2(length_mm: float, width_mm: float) -> float:
    """Plan area of a stadium (two half-discs joined by a rectangle): check value for the web."""
    return length_mm * width_mm + math.pi * width_mm**2 / 4
