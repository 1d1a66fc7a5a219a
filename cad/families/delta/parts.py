"""Part scripts of the delta (build123d, imported lazily): parameters in, OCP solids out (mm,
each part in its own frame). Dimensions: :mod:`.hardware`; the motor and its shaft are
:mod:`cad.parts.motor`'s."""

from __future__ import annotations

import math


def _amin():
    from build123d import Align

    return (Align.CENTER, Align.CENTER, Align.MIN)


def disk_plate_shape(radius_mm: float, thickness_mm: float):
    """Round plate (base plate, effector plate), centre at the origin, z 0..thickness."""
    from build123d import Cylinder

    return Cylinder(radius_mm, thickness_mm, align=_amin()).solids()[0].wrapped


def bracket_shape(width_mm: float, y_min_mm: float, y_max_mm: float, thickness_mm: float,
                  pilot_d_mm: float, holes_xyd):
    """Motor bracket: a plate x -width/2..width/2, y y_min..y_max (y up), z 0..thickness,
    with the motor's pilot bore at the origin and holes ``[(x, y, diameter)]``."""
    from build123d import Circle, Pos, Rectangle, extrude

    sk = Pos(0, (y_min_mm + y_max_mm) / 2) * Rectangle(width_mm, y_max_mm - y_min_mm)
    sk = sk - Circle(pilot_d_mm / 2)
    for x, y, dia in holes_xyd:
        sk = sk - Pos(x, y) * Circle(dia / 2)
    return extrude(sk, amount=thickness_mm).solids()[0].wrapped


def arm_shape(length_mm: float, width_mm: float, thickness_mm: float, bore0_mm: float,
              bore1_mm: float):
    """Plate bar: stadium from (0, 0) to (length, 0), width, z -t/2..t/2, bores at both ends."""
    from build123d import Circle, Pos, SlotCenterToCenter, extrude

    sk = Pos(length_mm / 2, 0) * SlotCenterToCenter(length_mm, width_mm)
    sk = sk - Circle(bore0_mm / 2) - Pos(length_mm, 0) * Circle(bore1_mm / 2)
    return (Pos(0, 0, -thickness_mm / 2) * extrude(sk, amount=thickness_mm)).solids()[0].wrapped


def cranked_arm_shape(length_mm: float, vertex_mm, width_mm: float, thickness_mm: float,
                      bore0_mm: float, bore1_mm: float):
    """Cranked plate bar: two stadiums of ``width_mm``, (0, 0) -> ``vertex_mm`` (x, y) ->
    (length, 0), z -t/2..t/2, bores at (0, 0) and (length, 0)."""
    import math

    from build123d import Circle, Pos, Rot, SlotCenterToCenter, extrude

    def slot(p, q):
        dx, dy = q[0] - p[0], q[1] - p[1]
        return (Pos((p[0] + q[0]) / 2, (p[1] + q[1]) / 2) * Rot(0, 0, math.degrees(math.atan2(dy, dx)))
                * SlotCenterToCenter(math.hypot(dx, dy), width_mm))

    v = (float(vertex_mm[0]), float(vertex_mm[1]))
    sk = slot((0.0, 0.0), v) + slot(v, (length_mm, 0.0))
    sk = sk - Circle(bore0_mm / 2) - Pos(length_mm, 0) * Circle(bore1_mm / 2)
    return (Pos(0, 0, -thickness_mm / 2) * extrude(sk, amount=thickness_mm)).solids()[0].wrapped


def bar_shape(diameter_mm: float, length_mm: float, bore_mm: float = 0.0):
    """Round bar (or hub with a bore), axis z, centred on the origin."""
    from build123d import Cylinder

    s = Cylinder(diameter_mm / 2, length_mm)
    if bore_mm > 0:
        s = s - Cylinder(bore_mm / 2, length_mm)
    return s.solids()[0].wrapped


def tube_shape(od_mm: float, id_mm: float, x0_mm: float, x1_mm: float):
    """Tube along x from x0 to x1."""
    from build123d import Cylinder, Pos, Rot

    L = x1_mm - x0_mm
    t = Cylinder(od_mm / 2, L) - Cylinder(id_mm / 2, L)
    return (Pos((x0_mm + x1_mm) / 2, 0, 0) * Rot(0, 90, 0) * t).solids()[0].wrapped


def ball_stud_shape(ball_d_mm: float, neck_d_mm: float, neck_mm: float):
    """Ball stud: the ball centred on the origin, its neck along +z to z = neck_mm."""
    from build123d import Cylinder, Sphere

    s = Sphere(ball_d_mm / 2) + Cylinder(neck_d_mm / 2, neck_mm, align=_amin())
    return s.solids()[0].wrapped


def socket_shape(ball_d_mm: float, clearance_mm: float, socket_d_mm: float, cone_deg: float,
                 shank_d_mm: float, shank_mm: float):
    """Ball socket: a sphere shell around the ball (centre at the origin, running clearance),
    an opening cone of half-angle ``cone_deg`` about +z, a shank along +x from the shell to
    x = socket_d / 2 + shank_mm (the rod tube slides over it)."""
    from build123d import Cone, Cylinder, Pos, Rot, Sphere

    rs = socket_d_mm / 2
    h = rs + 1.0
    cone = Cone(0.0, h * math.tan(math.radians(cone_deg)), h, align=_amin())
    shank = Pos(rs / 2 + (rs + shank_mm) / 2, 0, 0) * Rot(0, 90, 0) * Cylinder(
        shank_d_mm / 2, rs + shank_mm - rs / 2)
    s = Sphere(rs) + shank - Sphere(ball_d_mm / 2 + clearance_mm) - cone
    return s.solids()[0].wrapped


def clevis_shape(ear_r_mm: float, pin_d_mm: float, z0_mm: float, z1_mm: float, y0_mm: float,
                 y1_mm: float):
    """Clevis (the knee hinge's, :class:`cad.families.delta.hardware.KneeHinge`): two ears, each
    a stadium of radius ``ear_r_mm`` round (0, 0) and (0, y1 - r) with the pin's bore at the origin,
    z0..z1 and -z1..-z0; a bridge x -r..r, y y0..y1, z -z1..z1 joining them (the cross bar's
    end sits on its +y face)."""
    from build123d import Box, Circle, Pos, Rot, SlotCenterToCenter, extrude

    c = y1_mm - ear_r_mm  # the ear's far round end at y1, on the bridge
    ear = Pos(0, c / 2) * Rot(0, 0, 90) * SlotCenterToCenter(c, 2 * ear_r_mm) - Circle(pin_d_mm / 2)
    t = z1_mm - z0_mm
    s = (Pos(0, 0, z0_mm) * extrude(ear, amount=t)) + (Pos(0, 0, -z1_mm) * extrude(ear, amount=t))
    s = s + Pos(0, (y0_mm + y1_mm) / 2, 0) * Box(2 * ear_r_mm, y1_mm - y0_mm, 2 * z1_mm)
    return s.solids()[0].wrapped


def eye_shape(eye_r_mm: float, seat_d_mm: float, width_mm: float, shank_d_mm: float, shank_mm: float):
    """Rod eye (the knee hinge's): a disk of radius ``eye_r_mm``, z -w/2..w/2, with the
    bearing's seat (``seat_d_mm``) through it, and a shank along +x from inside the disk to
    x = eye_r + shank_mm (the rod tube slides over it)."""
    from build123d import Cylinder, Pos, Rot

    x0 = seat_d_mm / 2 + 0.5 * (eye_r_mm - seat_d_mm / 2)
    shank = Pos((x0 + eye_r_mm + shank_mm) / 2, 0, 0) * Rot(0, 90, 0) * Cylinder(
        shank_d_mm / 2, eye_r_mm + shank_mm - x0)
    s = Cylinder(eye_r_mm, width_mm) + shank - Cylinder(seat_d_mm / 2, width_mm)
    return s.solids()[0].wrapped


def drilled(shape, holes):
    """``shape`` (an OCP solid, its part frame) with round holes cut: ``holes`` ``[(point, axis,
    diameter, depth)]`` (mm), each a cylinder from ``point`` ``depth`` along the unit ``axis``
    (into the material): a tapped hole's tap drill, a clearance hole through a plate."""
    from build123d import Cylinder, Plane, Solid

    s = Solid(shape)
    for p, a, dia, depth in holes:
        s = s - Plane(origin=tuple(map(float, p)), z_dir=tuple(map(float, a))) * Cylinder(
            dia / 2, depth, align=_amin())
    return s.solids()[0].wrapped


def bossed_hub_shape(diameter_mm: float, length_mm: float, bore_mm: float, boss_d_mm: float,
                     boss_z0_mm: float, boss_length_mm: float):
    """Arm hub with a set-screw boss: a round bar of ``diameter_mm`` (axis z, centred on the
    origin) and a collar of ``boss_d_mm`` from z = ``boss_z0_mm`` over ``boss_length_mm``, the
    shaft bore ``bore_mm`` through both."""
    from build123d import Cylinder, Pos

    s = Cylinder(diameter_mm / 2, length_mm) + Pos(0, 0, boss_z0_mm) * Cylinder(
        boss_d_mm / 2, boss_length_mm, align=_amin())
    return (s - Cylinder(bore_mm / 2, length_mm)).solids()[0].wrapped
