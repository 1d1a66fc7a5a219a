"""Motor envelope (bought), motor mount plate and the direct-drive crank hub.

The motor is a catalog entry (:data:`cad.data.catalog.MOTORS`, default maxon RE 35,
the Hoeken paper's prototype motor, §III.A). Its solid is an envelope for the
assembly and the interference sweep: housing cylinder, centring pilot, shaft. Its
mass is the catalog weight; its rotor inertia Jm enters H11 (eq 16) from the
catalog (the shaft solid carries no mass: it is inside Jm).

Frames (mm): motor -- mounting face at z = 0, housing below (-z), pilot and shaft up;
motor mount plate -- z 0..thickness, motor centred at the origin; hub -- z 0..height,
shaft axis z.
"""

from __future__ import annotations

import math

from cad.data.catalog import MotorSpec, clearance_hole_mm, tap_drill_mm
from cad.parts.part_cache import part_cached

#: Axial gap between the motor's pilot face and where the shaft envelope starts (mm):
#: the real shaft leaves the front bearing boss; the envelope only needs to be apart
#: from the housing so that the (rotating) shaft and the (fixed) housing are separate
#: bodies in the interference sweep.
SHAFT_ENVELOPE_GAP_MM = 1.0
#: Motor mount plate border around the motor housing (mm; a plate dimension, not a
#: tolerance) and its corner-hole inset.
MOUNT_BORDER_MM = 10.0
MOUNT_HOLE_INSET_MM = 6.0
#: Screws fixing the motor mount plate under the base plate: M3, so that 1.5 d of thread
#: (4.5 mm) fits in the 6 mm base plate with a catalog length through the 5 mm plate.
MOUNT_SCREW = "M3-0.5"
#: A tapped hole is drilled this much deeper than its full thread (mm).
TAP_LEADOUT_MM = 1.0
#: Set screw locking the hub on the motor shaft (ISO 4026, flat point).
SET_SCREW = "M3-0.5"


def _a():
    from build123d import Align

    return (Align.CENTER, Align.CENTER, Align.MIN)


@part_cached
def motor_housing_shape(m: MotorSpec):
    """Housing + pilot of the motor: z from -body_length to pilot_height (mounting face z = 0),
    with the face's tapped holes (tap drill, ``bolt_thread_depth_mm`` + lead-out deep) that
    the motor screws enter."""
    from build123d import Cylinder, Pos

    body = Pos(0, 0, -m.body_length_mm) * Cylinder(
        m.body_diameter_mm / 2, m.body_length_mm, align=_a()
    )
    pilot = Cylinder(m.pilot_diameter_mm / 2, m.pilot_height_mm, align=_a())
    s = body + pilot
    drill = m.bolt_thread_depth_mm + TAP_LEADOUT_MM
    for x, y in motor_bolt_xy_mm(m):
        s = s - Pos(x, y, -drill) * Cylinder(tap_drill_mm(m.bolt_size) / 2, drill, align=_a())
    return s.solids()[0].wrapped


@part_cached
def motor_shaft_shape(m: MotorSpec):
    """Output shaft from the pilot face (+ gap) to ``shaft_length_mm`` above the mounting face."""
    from build123d import Cylinder, Pos

    z0 = m.pilot_height_mm + SHAFT_ENVELOPE_GAP_MM
    return (
        Pos(0, 0, z0) * Cylinder(m.shaft_diameter_mm / 2, m.shaft_length_mm - z0, align=_a())
    ).wrapped


def mount_side_mm(m: MotorSpec) -> float:
    """Side of the square motor mount plate (mm)."""
    return m.body_diameter_mm + 2 * MOUNT_BORDER_MM


def mount_hole_xy_mm(m: MotorSpec) -> list[tuple[float, float]]:
    """Corner holes of the motor mount plate (mm, plate frame)."""
    c = mount_side_mm(m) / 2 - MOUNT_HOLE_INSET_MM
    return [(c, c), (-c, c), (-c, -c), (c, -c)]


def motor_bolt_xy_mm(m: MotorSpec) -> list[tuple[float, float]]:
    r = m.bolt_circle_mm / 2
    return [
        (
            r * math.cos(math.radians(90 + 360 * k / m.bolt_count)),
            r * math.sin(math.radians(90 + 360 * k / m.bolt_count)),
        )
        for k in range(m.bolt_count)
    ]


@part_cached
def motor_mount_shape(m: MotorSpec, thickness_mm: float, extra_holes=()):
    """Motor mount plate: pilot bore, motor bolt-circle clearance holes, 4 corner holes
    (clearance for the screws that fix it under the base plate), ``extra_holes``
    ``[(x, y, diameter)]`` (the A4 post screw when it passes through); z 0..thickness."""
    from build123d import Circle, Pos, Rectangle, extrude

    s = mount_side_mm(m)
    sk = Rectangle(s, s) - Circle(m.pilot_diameter_mm / 2)
    for x, y, dia in extra_holes:
        sk = sk - Pos(x, y) * Circle(dia / 2)
    for x, y in motor_bolt_xy_mm(m):
        sk = sk - Pos(x, y) * Circle(clearance_hole_mm(m.bolt_size) / 2)
    for x, y in mount_hole_xy_mm(m):
        sk = sk - Pos(x, y) * Circle(clearance_hole_mm(MOUNT_SCREW) / 2)
    return extrude(sk, amount=thickness_mm).solids()[0].wrapped


@part_cached
def hub_shape(
    m: MotorSpec,
    diameter_mm: float,
    height_mm: float,
    bolt_circle_mm: float,
    screw: str,
    screw_depth_mm: float,
    shaft_engaged_mm: float,
    set_screw: str = SET_SCREW,
):
    """Direct-drive crank hub: shaft bore, radial hole for the ``set_screw`` (its tap drill,
    along +x, through the wall) at mid engagement, ``3`` tapped holes (tap drill,
    ``screw_depth_mm`` drilled) on ``bolt_circle_mm`` in the top face."""
    from build123d import Cylinder, Pos, Rot

    a = _a()
    tools = [Cylinder(m.shaft_diameter_mm / 2, height_mm, align=a)]
    r = bolt_circle_mm / 2
    d = tap_drill_mm(screw)
    for k in range(3):
        ang = math.radians(90 + 120 * k)
        tools.append(Pos(r * math.cos(ang), r * math.sin(ang), height_mm - screw_depth_mm)
                     * Cylinder(d / 2, screw_depth_mm, align=a))
    z_set = set_screw_z_mm(height_mm, shaft_engaged_mm)
    tools.append(Pos(0, 0, z_set) * Rot(0, 90, 0)
                 * Cylinder(tap_drill_mm(set_screw) / 2, diameter_mm / 2, align=a))
    hub = Cylinder(diameter_mm / 2, height_mm, align=a).cut(*tools)  # one boolean, all tools
    return hub.solids()[0].wrapped


def set_screw_z_mm(height_mm: float, shaft_engaged_mm: float) -> float:
    """Height of the set screw's axis in the hub frame (mid shaft engagement)."""
    return min(shaft_engaged_mm, height_mm) / 2


@part_cached
def set_screw_shape(length_mm: float, size: str = SET_SCREW):
    """Simplified ISO 4026 set screw of ``size``: a cylinder of the tap drill diameter (the
    thread's minor envelope, like bd_warehouse's ``simple`` screws), z 0..length, flat point
    at z = 0."""
    from build123d import Cylinder

    return Cylinder(tap_drill_mm(size) / 2, length_mm, align=_a()).solids()[0].wrapped
