"""Part scripts particular to the haptic pen (build123d, imported lazily): parameters in,
OCP ``TopoDS_Shape`` out (mm, each in its own frame). The link hardware (clevises, tubes,
pins, bearings, motors, plates, legs) is the twin pantograph's (:mod:`cad.parts.pantograph`,
:mod:`cad.parts.joints`, :mod:`cad.parts.motor`, :mod:`cad.parts.base`).

Frames:

* spigot hub -- a hub clevis (:func:`cad.parts.pantograph.clevis_shape` frame: joint axis z,
  z centred on its layer) with a spigot up the joint axis to ``spigot_top_mm`` holding the
  motor shaft from the top;
* waist bracket -- waist frame (:mod:`cad.families.pen.layout`): z up along the waist axis,
  y = outward; foot strip and boss at z ``foot``, motor plate at y ``plate``;
* waist hub -- axis z, z 0..height, shaft bore from below;
* yoke -- yoke frame: origin at the gimbal centre, z = the journal (outward), x = the ring
  pin axis ``a``; arms at x = +-arm_x, base across at z base0..base1, journal above;
* ring -- ring frame: origin at the centre, x = ring axis (normal), pin bores along z (a)
  and y (b);
* pen hub -- pen frame at one end: axis z (= b), bearing seats at both ends, a boss along
  +x holding the pen rod;
* pen rod -- along +x from x = 0.
"""

from __future__ import annotations

from cad.parts.pantograph import clevis_shape


def _amin():
    from build123d import Align

    return (Align.CENTER, Align.CENTER, Align.MIN)


def _solid(part):
    return part.solids()[0].wrapped


def spigot_hub_shape(clevis_kw: dict, shaft_d_mm: float, spigot_d_mm: float,
                     spigot_top_mm: float, shaft_engaged_mm: float):
    """Hub clevis of the upper proximal link: clevis block (bore = the motor shaft, blind)
    with a spigot on its joint axis from the block's top face to ``spigot_top_mm`` (clevis
    frame), its bore taking ``shaft_engaged_mm`` of the motor shaft from the top."""
    from build123d import Cylinder, Pos, Solid


    h = clevis_kw["height_mm"]
    block = clevis_shape("pin", bore_mm=shaft_d_mm, **clevis_kw)
    body = Solid(block) + Pos(0, 0, h / 2) * Cylinder(spigot_d_mm / 2, spigot_top_mm - h / 2,
                                                      align=_amin())
    body = body - Pos(0, 0, spigot_top_mm - shaft_engaged_mm) * Cylinder(
        shaft_d_mm / 2, shaft_engaged_mm, align=_amin())
    return _solid(body)


def waist_bracket_shape(foot_mm: tuple[float, float], plate_mm: tuple[float, float],
                        plate_side_mm: float, strip_w_mm: float, boss_d_mm: float,
                        motor_z_mm: tuple[float, float], pilot_d_mm: float,
                        shaft_hole_mm: float, top_mm: float, bolt_holes=()):
    """Waist bracket: a foot strip (width ``strip_w_mm``) from the boss on the waist axis out
    to the motor plate, the boss (``boss_d_mm``) and the vertical motor plate (side
    ``plate_side_mm`` wide, from the foot to ``top_mm``) with a pilot bore at each shoulder
    height ``motor_z_mm`` and the motor screws' clearance holes ``bolt_holes`` ``[(x, z,
    diameter)]``. Waist frame, one machined part."""
    from build123d import Box, Cylinder, Pos, Rot

    f0, f1 = foot_mm
    p0, p1 = plate_mm
    t = f1 - f0
    strip = Pos(0, p1 / 2, f0 + t / 2) * Box(strip_w_mm, p1, t)
    boss = Pos(0, 0, f0) * Cylinder(boss_d_mm / 2, t, align=_amin())
    plate = Pos(0, (p0 + p1) / 2, (f0 + top_mm) / 2) * Box(plate_side_mm, p1 - p0, top_mm - f0)
    body = strip + boss + plate
    for z in motor_z_mm:
        body = body - Pos(0, (p0 + p1) / 2, z) * Rot(90, 0, 0) * Cylinder(pilot_d_mm / 2, p1 - p0)
    for x, z, d in bolt_holes:
        body = body - Pos(x, (p0 + p1) / 2, z) * Rot(90, 0, 0) * Cylinder(d / 2, p1 - p0)
    body = body - Pos(0, 0, f0) * Cylinder(shaft_hole_mm / 2, t, align=_amin())
    return _solid(body)


def waist_hub_shape(diameter_mm: float, height_mm: float, shaft_d_mm: float,
                    shaft_engaged_mm: float):
    """Waist hub on the waist motor shaft: cylinder z 0..height, shaft bore from below."""
    from build123d import Cylinder

    hub = Cylinder(diameter_mm / 2, height_mm, align=_amin())
    return _solid(hub - Cylinder(shaft_d_mm / 2, shaft_engaged_mm, align=_amin()))


def yoke_shape(arm_x_mm: float, arm_t_mm: float, arm_w_mm: float, base_mm: tuple[float, float],
               journal_top_mm: float, journal_d_mm: float, seat_d_mm: float, seat_depth_mm: float):
    """Gimbal yoke: two arms at x = +-arm_x (thickness arm_t, width arm_w along y) from
    z = -arm_w / 2 to the base, each with a bearing seat (d ``seat_d``, depth ``seat_depth``)
    on the x axis from its inner face; the base across at z base0..base1; the journal
    (d ``journal_d``) from the base to ``journal_top_mm``."""
    from build123d import Box, Cylinder, Pos, Rot

    b0, b1 = base_mm
    z_lo = -arm_w_mm / 2
    outer = arm_x_mm + arm_t_mm
    body = Pos(0, 0, (b0 + b1) / 2) * Box(2 * outer, arm_w_mm, b1 - b0)
    for s in (-1, 1):
        arm = Pos(s * (arm_x_mm + arm_t_mm / 2), 0, (z_lo + b1) / 2) * Box(arm_t_mm, arm_w_mm,
                                                                          b1 - z_lo)
        arm = arm + Pos(s * (arm_x_mm + arm_t_mm / 2), 0, 0) * Rot(0, 90, 0) * Cylinder(
            arm_w_mm / 2, arm_t_mm)
        body = body + arm
        seat = Pos(s * (arm_x_mm + seat_depth_mm / 2), 0, 0) * Rot(0, 90, 0) * Cylinder(
            seat_d_mm / 2, seat_depth_mm)
        body = body - seat
    body = body + Pos(0, 0, b1) * Cylinder(journal_d_mm / 2, journal_top_mm - b1, align=_amin())
    return _solid(body)


def ring_shape(r_in_mm: float, r_out_mm: float, thickness_mm: float, pin_d_mm: float):
    """Gimbal ring: annulus about x (thickness along x), pin bores (d ``pin_d``) through its
    wall along +-z (axis a) and +-y (axis b)."""
    from build123d import Cylinder, Pos, Rot

    ring = Rot(0, 90, 0) * (Cylinder(r_out_mm, thickness_mm) - Cylinder(r_in_mm, thickness_mm))
    w = r_out_mm - r_in_mm + 2.0  # through both faces of the curved wall
    c = (r_in_mm + r_out_mm) / 2
    for axis in ("z", "y"):
        for s in (-1, 1):
            if axis == "z":
                tool = Pos(0, 0, s * c) * Cylinder(pin_d_mm / 2, w)
            else:  # turned as the pin is placed (a coincident seam: no boolean sliver)
                tool = Pos(0, s * c, 0) * Rot(-90 * s, 0, 0) * Cylinder(pin_d_mm / 2, w)
            ring = ring - tool
    return _solid(ring)


def pen_hub_shape(half_length_mm: float, radius_mm: float, seat_d_mm: float,
                  seat_depth_mm: float, pen_d_mm: float, boss_length_mm: float,
                  socket_depth_mm: float):
    """Pen hub: cylinder along z (= b; length 2 half_length, radius), a bearing seat at each
    end, a boss along +x (d = pen + 4, ``boss_length``) with the pen rod's socket
    (``socket_depth``) in its end."""
    from build123d import Cylinder, Pos, Rot

    hub = Cylinder(radius_mm, 2 * half_length_mm)
    boss_r = pen_d_mm / 2 + 2.0
    hub = hub + Pos(boss_length_mm / 2, 0, 0) * Rot(0, 90, 0) * Cylinder(boss_r, boss_length_mm)
    for s in (-1, 1):
        hub = hub - Pos(0, 0, s * (half_length_mm - seat_depth_mm / 2)) * Cylinder(
            seat_d_mm / 2, seat_depth_mm)
    hub = hub - Pos(boss_length_mm - socket_depth_mm / 2, 0, 0) * Rot(0, 90, 0) * Cylinder(
        pen_d_mm / 2, socket_depth_mm)
    return _solid(hub)


def rod_shape(length_mm: float, diameter_mm: float):
    """Pen rod along +x, x 0..length."""
    from build123d import Cylinder, Pos, Rot

    return _solid(Pos(length_mm / 2, 0, 0) * Rot(0, 90, 0) * Cylinder(diameter_mm / 2, length_mm))
