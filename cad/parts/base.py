"""Base plate holding A1 (motor mount) and A4 (post), the A4 post, and the legs.

Base plate (z from -thickness to 0, world frame R0): the rectangle covering the
mechanism's swept footprint plus ``base_margin_mm``; an opening at A1 for the motor
pilot, shaft and motor screw heads, four tapped holes for the motor mount plate
screwed from below, a clearance hole at A4 for the post screw, four corner holes for
the legs. Post: turned standoff from the plate to the rocker stack at A4, reamed for
the shoulder then tapped for its thread at the top, tapped at the bottom. Legs: four
turned standoffs under the corners, long enough to clear the motor.
"""

from __future__ import annotations

from cad.data.catalog import clearance_hole_mm, tap_drill_mm
from cad.errors import GeometryError
from cad.parts.part_cache import part_cached

#: Legs: diameter, corner inset of their axis from the plate edges, free space under the motor (mm).
LEG_DIAMETER_MM = 12.0
LEG_INSET_MM = 8.0
LEG_GROUND_CLEARANCE_MM = 10.0
LEG_SCREW = "M6-1"
#: Depth of the tapped holes at the legs' and post's ends (mm).
STANDOFF_TAP_DEPTH_MM = 12.0


def _a():
    from build123d import Align

    return (Align.CENTER, Align.CENTER, Align.MIN)


def base_rect_mm(footprint, a4_xy, mount_side_mm: float, post_d_mm: float, margin_mm: float):
    """(xmin, ymin, xmax, ymax) of the base plate: footprint, motor mount and post plus margin."""
    xmin, ymin, xmax, ymax = footprint
    h = mount_side_mm / 2
    xmin, ymin, xmax, ymax = min(xmin, -h), min(ymin, -h), max(xmax, h), max(ymax, h)
    r = post_d_mm / 2
    xmin, ymin = min(xmin, a4_xy[0] - r), min(ymin, a4_xy[1] - r)
    xmax, ymax = max(xmax, a4_xy[0] + r), max(ymax, a4_xy[1] + r)
    m = max(margin_mm, LEG_INSET_MM + LEG_DIAMETER_MM / 2)
    return xmin - m, ymin - m, xmax + m, ymax + m


def leg_xy_mm(rect) -> list[tuple[float, float]]:
    xmin, ymin, xmax, ymax = rect
    i = LEG_INSET_MM
    return [(xmin + i, ymin + i), (xmax - i, ymin + i), (xmax - i, ymax - i), (xmin + i, ymax - i)]


@part_cached
def base_plate_shape(
    rect,
    thickness_mm: float,
    a4_xy,
    opening_d_mm: float,
    mount_holes_xy,
    mount_screw: str,
    post_screw: str,
    extra_openings=(),
):
    """The base plate, z from -thickness to 0 (world frame); ``extra_openings``:
    ``((x, y, d), ...)`` more round openings (mm), e.g. a capstan's motor beside A1."""
    from build123d import Circle, Pos, Rectangle, extrude

    xmin, ymin, xmax, ymax = rect
    sk = Pos((xmin + xmax) / 2, (ymin + ymax) / 2) * Rectangle(xmax - xmin, ymax - ymin)
    sk = sk - Circle(opening_d_mm / 2)
    for x, y, d in extra_openings:
        sk = sk - Pos(x, y) * Circle(d / 2)
    for x, y in mount_holes_xy:
        sk = sk - Pos(x, y) * Circle(tap_drill_mm(mount_screw) / 2)
    sk = sk - Pos(float(a4_xy[0]), float(a4_xy[1])) * Circle(clearance_hole_mm(post_screw) / 2)
    for x, y in leg_xy_mm(rect):
        sk = sk - Pos(x, y) * Circle(clearance_hole_mm(LEG_SCREW) / 2)
    return (Pos(0, 0, -thickness_mm) * extrude(sk, amount=thickness_mm)).solids()[0].wrapped


@part_cached
def post_shape(
    diameter_mm: float,
    height_mm: float,
    bore_d_mm: float,
    bore_depth_mm: float,
    thread: str,
    thread_depth_mm: float,
    bottom_screw: str,
):
    """A4 post, z 0..height: top reamed bore then tapped hole; bottom tapped hole."""
    from build123d import Cylinder, Pos

    a = _a()
    top = height_mm - bore_depth_mm
    if top - thread_depth_mm < STANDOFF_TAP_DEPTH_MM:
        raise GeometryError(
            f"A4 post: {height_mm:g} mm cannot hold the {bore_depth_mm:g} mm bore, the "
            f"{thread_depth_mm:g} mm top thread and the {STANDOFF_TAP_DEPTH_MM:g} mm bottom thread"
        )
    tools = [
        Pos(0, 0, top) * Cylinder(bore_d_mm / 2, bore_depth_mm, align=a),
        Pos(0, 0, top - thread_depth_mm)
        * Cylinder(tap_drill_mm(thread) / 2, thread_depth_mm, align=a),
        Cylinder(tap_drill_mm(bottom_screw) / 2, STANDOFF_TAP_DEPTH_MM, align=a),
    ]
    p = Cylinder(diameter_mm / 2, height_mm, align=a).cut(*tools)  # one boolean, all tools
    return p.solids()[0].wrapped


@part_cached
def leg_shape(height_mm: float):
    """Leg standoff, z 0..height, tapped at both ends."""
    from build123d import Cylinder, Pos

    a = _a()
    d = tap_drill_mm(LEG_SCREW) / 2
    leg = Cylinder(LEG_DIAMETER_MM / 2, height_mm, align=a).cut(
        Cylinder(d, STANDOFF_TAP_DEPTH_MM, align=a),
        Pos(0, 0, height_mm - STANDOFF_TAP_DEPTH_MM) * Cylinder(d, STANDOFF_TAP_DEPTH_MM, align=a),
    )
    return leg.solids()[0].wrapped
