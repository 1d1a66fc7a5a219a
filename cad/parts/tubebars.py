"""Tube bars: a carbon-fibre tube bonded into aluminium clevises (``[parts] bar_style = "tube"``).

The construction of the isotropy paper's haptic mouse (§4.1: "aluminum clevises, carbon
fibre links"), applied to the four-bar's crank, coupler and rocker. The part functions
are the twin pantograph's (:func:`cad.parts.pantograph.clevis_shape`,
:func:`cad.parts.pantograph.tube_shape`); this module only adds the joint features of the
plate bars (:class:`cad.parts.bars.Feature`) and several sockets per clevis.

Frames: a clevis in the link frame with its joint at the origin, z from 0 to
``bar_thickness_mm`` (the plate bar's layer: the joint hardware, layer heights and the
handle screw are unchanged); one tube socket per neighbouring joint, pointing at it.
A tube runs along +x from x = 0, axis at y = z = 0 (placed at the layer's mid-height).

The bond: the socket is ``2 * BOND_GAP_MM`` wider than the tube (the adhesive line, no
touching faces) and the tube ends stop ``TUBE_END_GAP_MM`` short of the socket bottoms.
Only links whose joints are collinear (Hoeken, Chebyshev; crank and rocker always) can
be tubes: a triangular coupler needs a plate.
"""

from __future__ import annotations

import math

import numpy as np

from cad.design.parts import PartsSpec
from cad.errors import DesignError
from cad.parts.bars import Feature, hull_points
from cad.parts.pantograph import clevis_shape as pantograph_clevis
from cad.parts.pantograph import tube_length_mm as base
from cad.parts.pantograph import tube_shape as pantograph_tube
from cad.parts.part_cache import part_cached

#: Radial adhesive gap between tube and socket (mm): 0.05-0.1 mm is the bond line of a
#: structural epoxy (3M Scotch-Weld DP460 datasheet: 0.05-0.13 mm optimum).
BOND_GAP_MM = 0.05
#: Shortest bare tube between two clevises (mm).
MIN_TUBE_MM = 2.0
#: Axial gap between a tube end and the socket bottom (mm).
TUBE_END_GAP_MM = 0.1


def tube_length_mm(joint_distance_mm: float, parts: PartsSpec) -> float:
    """Length of the tube between two clevises ``joint_distance_mm`` apart (mm)."""
    return base(joint_distance_mm, parts.clevis_length_mm, parts.socket_depth_mm) - 2 * TUBE_END_GAP_MM


def segments(link: str, pts: dict[str, np.ndarray]) -> list[tuple[str, str]]:
    """Consecutive joint pairs along the link's line; DesignError if not collinear."""
    names = list(pts)
    arr = np.array([pts[n] for n in names], dtype=float)
    if len(hull_points(arr)) != 2 or len(arr) < 2:
        raise DesignError(
            "parts.bar_style",
            f'"tube" needs collinear joints, but the {link} joints form a triangle '
            '(phi_e != 0, e.g. Roberts): use bar_style = "plate"',
        )
    a = arr[0]
    far = arr[int(np.argmax(np.linalg.norm(arr - a, axis=1)))]
    u = (far - a) / np.linalg.norm(far - a)
    order = sorted(names, key=lambda n: float((pts[n] - a) @ u))
    return [(order[i], order[i + 1]) for i in range(len(order) - 1)]


def check_link(link: str, pts: dict[str, tuple[np.ndarray, Feature]], parts: PartsSpec) -> None:
    """Raise DesignError when a socket would cut a joint feature or a tube is too short."""
    free = parts.clevis_length_mm - parts.socket_depth_mm
    for n, (_, f) in pts.items():
        r = max(f.d_mm / 2, f.cb_d_mm / 2,
                f.bolt_circle_mm / 2 + f.bolt_hole_mm / 2 if f.bolt_count else 0.0)
        if free < r + 1.0:
            raise DesignError(
                "parts.clevis_length_mm",
                f"the tube socket of the {link} clevis at {n} starts {free:g} mm from the joint, "
                f"inside its {2 * r:g} mm feature (+1 mm wall): lengthen the clevis "
                "or shorten socket_depth_mm",
            )
    for a, b in segments(link, {n: p for n, (p, _) in pts.items()}):
        L = float(np.linalg.norm(pts[b][0] - pts[a][0]))
        if L - 2 * parts.clevis_length_mm < MIN_TUBE_MM:
            raise DesignError(
                "parts.clevis_length_mm",
                f"the {link} joints {a}-{b} are {L:.2f} mm apart: two {parts.clevis_length_mm:g} mm "
                f"clevises leave under {MIN_TUBE_MM:g} mm of bare tube; shorten the clevises, "
                'scale the linkage up (stroke_mm) or use bar_style = "plate"',
            )


@part_cached
def clevis_shape(feature: Feature, directions_deg: tuple[float, ...], parts: PartsSpec):
    """The clevis at one joint (module docstring frame), with the plate bar's joint feature:
    bore ``feature.d_mm``, the bearing seat counterbore from the bottom face, hub screw holes."""
    from build123d import Align, Cylinder, Pos, Rot, Solid


    t, w = parts.bar_thickness_mm, 2 * parts.bar_end_radius_mm
    body = None
    for a in directions_deg:
        s = Rot(0, 0, a) * Solid(pantograph_clevis(
            "pin", parts.clevis_length_mm, w, t, parts.socket_depth_mm,
            parts.tube_od_mm + 2 * BOND_GAP_MM, feature.d_mm))
        body = s if body is None else body + s
    body = Pos(0, 0, t / 2) * body
    amin = (Align.CENTER, Align.CENTER, Align.MIN)
    cuts = []
    if feature.cb_depth_mm > 0:
        cuts.append(Cylinder(feature.cb_d_mm / 2, feature.cb_depth_mm, align=amin))
    for k in range(feature.bolt_count):
        a = math.radians(90.0 + 360.0 * k / feature.bolt_count)
        r = feature.bolt_circle_mm / 2
        cuts.append(Pos(r * math.cos(a), r * math.sin(a), 0)
                    * Cylinder(feature.bolt_hole_mm / 2, t, align=amin))
    if cuts:
        body = body.cut(*cuts)
    return body.solids()[0].wrapped


@part_cached
def tube_shape(length_mm: float, parts: PartsSpec):
    """The tube (module docstring frame)."""
    return pantograph_tube(length_mm, parts.tube_od_mm, parts.tube_id_mm)


def tube_placement(pa: np.ndarray, pb: np.ndarray, z_mid_mm: float, parts: PartsSpec) -> np.ndarray:
    """4x4 placement (link frame, mm) of the tube from joint ``pa`` towards ``pb``."""
    d = np.asarray(pb, float) - np.asarray(pa, float)
    u = d / np.linalg.norm(d)
    start = np.asarray(pa, float) + u * (parts.clevis_length_mm - parts.socket_depth_mm + TUBE_END_GAP_MM)
    T = np.eye(4)
    T[:2, 0] = u
    T[:2, 1] = (-u[1], u[0])
    T[:3, 3] = (start[0], start[1], z_mid_mm)
    return T


def directions_deg(joint: str, pts: dict[str, np.ndarray], segs: list[tuple[str, str]]) -> tuple[float, ...]:
    """Socket directions of the clevis at ``joint`` (towards each neighbour), deg in the link frame."""
    out = []
    for a, b in segs:
        if joint in (a, b):
            other = b if joint == a else a
            d = pts[other] - pts[joint]
            out.append(round(math.degrees(math.atan2(d[1], d[0])), 9))
    return tuple(out)
