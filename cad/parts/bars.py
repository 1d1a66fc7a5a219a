"""The bars (crank, coupler, rocker): plates cut from sheet, one DXF profile each.

Every mechanism-dependent dimension comes from the joint positions in the link's own
frame (:func:`cad.kinematics.linkgeom.link_joints_mm`): origin at the first joint, x
towards the second, z normal (bar from z = 0 to its thickness).

Outline: the union of a disc of ``bar_end_radius_mm`` at every joint, a strip of
``bar_width_mm`` along every edge of the joints' convex hull and, for three
non-collinear points (a coupler with phi_e != 0, e.g. Roberts), the hull triangle:
for ``end_radius = width / 2`` this is exactly the convex hull of the discs (a stadium
for a binary link), area = hull area + r * hull perimeter + pi r^2.

Joint features (:class:`Feature`):

* ``seat`` -- bearing seat: counterbore of the bearing outside diameter D, depth B, from
  the bar's bottom face, and a through hole of the housing abutment diameter Da (the
  lip that locates the outer ring);
* ``pin`` -- reamed hole of the shoulder diameter (the pin's link);
* ``hub`` -- crank on the motor hub: shaft clearance hole and a circle of screw holes;
* ``tapped`` -- tapped hole (modelled at the tap drill), e.g. the handle screw at P;
* ``keep`` -- radius kept free of pockets without a hole (nothing by default).

Lightening pockets (``bar_pockets``): a through slot of width ``bar_width - 2 web``
centred on every hull edge, stopping ``web`` short of the features at its ends and
skipped where another joint would fall inside it or it would be shorter than
``bar_pocket_min_length_mm``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cad.design.parts import PartsSpec
from cad.errors import GeometryError
from cad.parts.part_cache import canonical, part_cached


@dataclass(frozen=True)
class Feature:
    """A joint feature of a bar (module docstring); sizes in mm.

    kind : "seat" | "pin" | "hub" | "tapped" | "keep".
    d_mm : hole diameter (seat: the lip hole Da; pin: shoulder; hub: shaft clearance;
        tapped: tap drill; keep: 0).
    cb_d_mm, cb_depth_mm : counterbore from the bottom face (seat only).
    bolt_circle_mm, bolt_hole_mm, bolt_count : hub screw holes.
    keep_r_mm : radius around the joint kept clear of pockets.
    """

    kind: str
    d_mm: float = 0.0
    cb_d_mm: float = 0.0
    cb_depth_mm: float = 0.0
    bolt_circle_mm: float = 0.0
    bolt_hole_mm: float = 0.0
    bolt_count: int = 0
    keep_r_mm: float = 0.0

    @property
    def outer_r_mm(self) -> float:
        """Radius of the largest cut at the joint (pockets stop ``web`` beyond it)."""
        return max(
            self.d_mm / 2,
            self.cb_d_mm / 2,
            self.bolt_circle_mm / 2 + self.bolt_hole_mm / 2 if self.bolt_count else 0.0,
            self.keep_r_mm,
        )


def hull_points(points: np.ndarray) -> np.ndarray:
    """Vertices of the convex hull of 1-3 points (collinear triples -> the two extremes)."""
    p = np.asarray(points, dtype=float)
    if len(p) <= 2:
        return p
    if len(p) != 3:
        raise GeometryError(f"a bar has 1 to 3 joints, got {len(p)}")
    area2 = (p[1, 0] - p[0, 0]) * (p[2, 1] - p[0, 1]) - (p[1, 1] - p[0, 1]) * (p[2, 0] - p[0, 0])
    scale = max(np.ptp(p[:, 0]), np.ptp(p[:, 1]), 1.0)
    if abs(area2) <= 1e-9 * scale * scale:
        d = np.linalg.norm(p[:, None, :] - p[None, :, :], axis=-1)
        i, j = np.unravel_index(np.argmax(d), d.shape)
        return p[[i, j]]
    return p if area2 > 0 else p[[0, 2, 1]]


def outline_area_mm2(points: np.ndarray, r_mm: float) -> float:
    """Closed-form area of the hull of discs of radius r at ``points`` (width = 2 r):
    hull area + r * hull perimeter + pi r^2."""
    h = hull_points(points)
    if len(h) == 1:
        return math.pi * r_mm**2
    if len(h) == 2:
        return 2 * r_mm * float(np.linalg.norm(h[1] - h[0])) + math.pi * r_mm**2
    u, v = h[1] - h[0], h[2] - h[0]
    a = 0.5 * abs(u[0] * v[1] - u[1] * v[0])
    per = sum(float(np.linalg.norm(h[(i + 1) % 3] - h[i])) for i in range(3))
    return a + r_mm * per + math.pi * r_mm**2


def _strip(p, q, width):
    from build123d import Pos, Rectangle, Rot

    d = q - p
    L = float(np.linalg.norm(d))
    mid = 0.5 * (p + q)
    return (
        Pos(float(mid[0]), float(mid[1]))
        * Rot(0, 0, math.degrees(math.atan2(d[1], d[0])))
        * Rectangle(L, width)
    )


def _slot(p, q, width):
    from build123d import Pos, Rot, SlotCenterToCenter

    d = q - p
    L = float(np.linalg.norm(d))
    mid = 0.5 * (p + q)
    return (
        Pos(float(mid[0]), float(mid[1]))
        * Rot(0, 0, math.degrees(math.atan2(d[1], d[0])))
        * SlotCenterToCenter(L, width)
    )


def _circle(p, r):
    from build123d import Circle, Pos

    return Pos(float(p[0]), float(p[1])) * Circle(r)


def pocket_segments(
    joints: dict[str, tuple[np.ndarray, Feature]], parts: PartsSpec
) -> list[tuple[np.ndarray, np.ndarray, float]]:
    """Centre-to-centre segments and width of the lightening pockets (module docstring)."""
    if not parts.bar_pockets:
        return []
    web = parts.bar_pocket_web_mm
    wp = parts.bar_width_mm - 2 * web
    if wp < 2.0:
        return []
    names = list(joints)
    pts = np.array([joints[n][0] for n in names], dtype=float)
    h = hull_points(pts)
    if len(h) == 1:
        return []
    if len(h) == 2 and len(pts) == 3:
        # collinear: pockets between consecutive joints along the line
        u = (h[1] - h[0]) / np.linalg.norm(h[1] - h[0])
        order = np.argsort((pts - h[0]) @ u)
        edges = [(order[i], order[i + 1]) for i in range(len(order) - 1)]
    elif len(h) == 2:
        edges = [(0, 1)]
    else:
        edges = [(0, 1), (1, 2), (2, 0)]
    out = []
    for i, j in edges:
        pi, pj = pts[i], pts[j]
        L = float(np.linalg.norm(pj - pi))
        if L <= 0:
            continue
        u = (pj - pi) / L
        ri = joints[names[i]][1].outer_r_mm + web + wp / 2
        rj = joints[names[j]][1].outer_r_mm + web + wp / 2
        c2c = L - ri - rj
        if c2c + wp < parts.bar_pocket_min_length_mm or c2c <= 0:
            continue
        a, b = pi + ri * u, pj - rj * u
        ok = True
        for k, n in enumerate(names):
            if k in (i, j):
                continue
            pk = pts[k]
            t = np.clip((pk - a) @ (b - a) / max((b - a) @ (b - a), 1e-12), 0, 1)
            if np.linalg.norm(pk - (a + t * (b - a))) < joints[n][1].outer_r_mm + web + wp / 2:
                ok = False
        if ok:
            out.append((a, b, wp))
    return out


@part_cached
def bar_shape(joints: dict[str, tuple[np.ndarray, Feature]], parts: PartsSpec):
    """The bar solid (TopoDS_Shape) in its link frame, z from 0 to ``bar_thickness_mm``.

    ``joints``: name -> (xy in the link frame (mm), :class:`Feature`). The 2-D profile
    (outline, holes, pockets) does not depend on the thickness and is reused across
    thickness changes (:func:`bar_profile`); only the extrusion and the counterbores are redone.
    """
    from build123d import Align, Cylinder, Pos, extrude

    sk = bar_profile(joints, parts.bar_width_mm, parts.bar_end_radius_mm, parts.bar_pockets,
                     parts.bar_pocket_web_mm, parts.bar_pocket_min_length_mm)
    solid = extrude(sk, amount=parts.bar_thickness_mm)
    cbs = [Pos(float(p[0]), float(p[1]), 0)
           * Cylinder(f.cb_d_mm / 2, f.cb_depth_mm, align=(Align.CENTER, Align.CENTER, Align.MIN))
           for p, f in joints.values() if f.cb_depth_mm > 0]
    if cbs:
        solid = solid.cut(*cbs)  # one boolean for every counterbore
    sols = solid.solids()
    if len(sols) != 1:
        raise GeometryError(f"bar came out as {len(sols)} solids (pockets or holes cut it apart)")
    return sols[0].wrapped


_PROFILES: dict[str, object] = {}


def bar_profile(joints: dict[str, tuple[np.ndarray, Feature]], width_mm: float, end_radius_mm: float,
                pockets: bool, pocket_web_mm: float, pocket_min_length_mm: float):
    """The bar's 2-D profile (build123d Sketch, link frame): outline minus holes and pockets.

    Remembered in this process by its arguments (a few dozen at most per run).
    """
    import json

    from build123d import Polygon


    key = json.dumps(canonical([joints, width_mm, end_radius_mm, pockets, pocket_web_mm,
                                pocket_min_length_mm]), sort_keys=True)
    if key in _PROFILES:
        return _PROFILES[key]
    pts = np.array([p for p, _ in joints.values()], dtype=float)
    h = hull_points(pts)
    sk = None
    for p in pts:
        c = _circle(p, end_radius_mm)
        sk = c if sk is None else sk + c
    if len(h) >= 2:
        for i in range(len(h) if len(h) == 3 else 1):
            sk = sk + _strip(h[i], h[(i + 1) % len(h)], width_mm)
    if len(h) == 3:
        sk = sk + Polygon(*[(float(x), float(y)) for x, y in h], align=None)
    for p, f in joints.values():
        if f.d_mm > 0:
            sk = sk - _circle(p, f.d_mm / 2)
        if f.kind == "hub":
            for k in range(f.bolt_count):
                a = math.radians(90.0 + 360.0 * k / f.bolt_count)
                q = p + 0.5 * f.bolt_circle_mm * np.array([math.cos(a), math.sin(a)])
                sk = sk - _circle(q, f.bolt_hole_mm / 2)
    spec = _PocketSpec(width_mm, pockets, pocket_web_mm, pocket_min_length_mm)
    for a, b, wp in pocket_segments(joints, spec):
        sk = sk - _slot(a, b, wp)
    if len(_PROFILES) > 64:
        _PROFILES.clear()
    _PROFILES[key] = sk
    return sk


@dataclass(frozen=True)
class _PocketSpec:
    """The PartsSpec fields :func:`pocket_segments` reads."""

    bar_width_mm: float
    bar_pockets: bool
    bar_pocket_web_mm: float
    bar_pocket_min_length_mm: float
