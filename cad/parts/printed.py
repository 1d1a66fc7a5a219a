"""The wall/infill model of one printed part, layer by layer (build123d sections).

What a slicer does, reduced to areas (model in :mod:`cad.printing`): the part is cut into
N = round(T / layer height) layers of its height T in its print frame (part frame, z up;
a part printed flipped has the same layers upside down: the model is symmetric as the
top and bottom skins are equal). Layer k has infill where the part has material in every
layer from k - n to k + n (n solid layers; otherwise it is a top or bottom skin), shrunk
by the wall thickness w (walls x line width) from every contour. The part's core volume
is the sum over layers of that area x layer height; the rest of the solid is solid shell.

A part bounded by planes and cylinders parallel or normal to z (plates, turned parts) is
prismatic between the heights of its horizontal faces: one section per such slab. Within
the height range of any other face (a fillet, a cone, a radial hole) every layer is its
own section.
"""

from __future__ import annotations

import math

from cad.errors import DesignError
from cad.occ.boolean import common
from cad.printing import PrintSettings
from cad.tolerances import (
    PRINT_CHORD_MM,
    PRINT_CIRCLE_FIT_REL,
    PRINT_CONTOUR_MAX_POINTS,
    PRINT_LAYERS_MAX,
)
from cad.tolerances import PRINT_SECTION_EPS_MM as _EPS_MM


def _b3d(shape):
    """A build123d shape of an OCP shape, a build123d shape or a deferred part solid."""
    from build123d import Shape

    if hasattr(shape, "solid_for_props"):  # cad.parts.part_cache.DeferredShape
        shape = shape.solid_for_props()
    return shape if hasattr(shape, "faces") else Shape.cast(shape)


def _section(shape, z: float, size: float) -> list:
    """The faces of ``shape`` cut by the plane at height ``z`` (mm), moved down to z = 0 (so
    that sections at different heights intersect)."""
    from build123d import Face, Location, Plane, Shape

    plane = Face.make_rect(size, size, Plane.XY).moved(Location((0, 0, z)))
    cut = common(shape, plane.wrapped)  # on a copy: ``shape`` keeps its tolerances
    down = Location((0, 0, -z))
    return [f.moved(down) for f in Shape.cast(cut).faces() if f.area > 1e-12]


def _common(a: list, b: list) -> list:
    """Faces of the region in both ``a`` and ``b`` (coplanar face lists)."""
    if not a or not b:
        return []
    from build123d import Compound

    out = Compound(a) & Compound(b)
    return [f for f in out.faces() if f.area > 1e-12]


def _bounded_wire(wire):
    """``wire`` itself when all its edges are lines and circles; the exact circle through it
    when it is one (within :data:`cad.tolerances.PRINT_CIRCLE_FIT_REL` of its radius: a
    turned part cut through a fillet or a cone, which OCCT returns as a B-spline); else the
    closed polygon of chords of at most :data:`cad.tolerances.PRINT_CHORD_MM` through it (at
    most :data:`~cad.tolerances.PRINT_CONTOUR_MAX_POINTS` vertices). OCCT's 2D offset of the
    B-spline cut of a 12 mm knob ran for 20 minutes; of a circle it is immediate."""
    from build123d import Edge, GeomType, Plane, Wire

    if all(e.geom_type in (GeomType.LINE, GeomType.CIRCLE) for e in wire.edges()):
        return wire
    n = min(PRINT_CONTOUR_MAX_POINTS, max(16, math.ceil(wire.length / PRINT_CHORD_MM)))
    pts = wire.positions([k / n for k in range(n)])
    cx, cy = sum(p.X for p in pts) / n, sum(p.Y for p in pts) / n
    r = [math.hypot(p.X - cx, p.Y - cy) for p in pts]
    r_mean = sum(r) / n
    if r_mean > 0 and max(abs(x - r_mean) for x in r) <= PRINT_CIRCLE_FIT_REL * r_mean:
        return Wire([Edge.make_circle(r_mean, Plane.XY.offset(pts[0].Z).shift_origin((cx, cy, pts[0].Z)))])
    return Wire.make_polygon(pts, close=True)


def _offset_face(wire, w: float, grow: bool):
    """The face inside ``wire`` offset by ``w`` outward (``grow``) or inward, whatever the
    wire's orientation (the smaller / larger of the two offsets); None when it closes up.
    A contour of curves other than lines and circles is offset as a polygon
    (:func:`_bounded_wire`)."""
    from build123d import Face

    wire = _bounded_wire(wire)
    base = Face(wire).area
    got = []
    for d in (w, -w):
        try:
            f = Face(wire.offset_2d(d))
        except Exception:  # noqa: BLE001,S112 -- OCCT offsets fail exactly when a region closes up
            continue
        if (f.area > base) == grow and f.area > 1e-12:
            got.append(f)
    return max(got, key=lambda f: f.area) if grow and got else (min(got, key=lambda f: f.area)
                                                                 if got else None)


def _shrunk_area_mm2(faces: list, w: float) -> float:
    """Area (mm^2) of ``faces`` shrunk by ``w`` from every contour (outer edges inward,
    holes outward); a contour that closes up leaves nothing."""
    total = 0.0
    for f in faces:
        region = _offset_face(f.outer_wire(), w, grow=False)
        if region is None:
            continue
        holes = [h for h in (_offset_face(i, w, grow=True) for i in f.inner_wires()) if h is not None]
        if holes:  # one cut by all the grown holes: they may overlap or swallow the region
            region = region.cut(*holes)
        total += sum(x.area for x in region.faces() if x.area > 1e-12)
    return total


def _vertical(f) -> bool:
    """A face that is the same in every section across its height: a plane parallel or
    normal to z, or a cylinder about a z-parallel axis."""
    from build123d import GeomType

    if f.geom_type == GeomType.PLANE:
        nz = abs(f.normal_at().Z)
        return nz < 1e-9 or nz > 1 - 1e-9
    if f.geom_type == GeomType.CYLINDER:
        return abs(abs(f.axis_of_rotation.direction.Z) - 1) < 1e-9
    return False


def _slabs(part, zs: list) -> list:
    """Slab key of every layer: layers with the same key have the same section. Between the
    heights of horizontal faces a part of :func:`_vertical` faces is prismatic (key: how many
    such heights lie below); a layer within the height range of any other face (a fillet, a
    cone, a radial hole) is its own slab."""
    from build123d import GeomType

    cuts, ranges = set(), []
    for f in part.faces():
        if f.geom_type == GeomType.PLANE and abs(f.normal_at().Z) > 0.5:
            cuts.add(round(f.center().Z, 9))
        elif not _vertical(f):
            bb = f.bounding_box()
            ranges.append((bb.min.Z, bb.max.Z))
            cuts.update((round(bb.min.Z, 9), round(bb.max.Z, 9)))
    cuts = sorted(cuts)
    return [("layer", k) if any(lo - _EPS_MM <= z <= hi + _EPS_MM for lo, hi in ranges)
            else ("slab", sum(z > c + _EPS_MM for c in cuts)) for k, z in enumerate(zs)]


def printed_core_mm3(shape, s: PrintSettings) -> float:
    """Core (infill) volume, mm^3, of a part (``TopoDS_Shape`` or build123d shape, mm,
    printed in its own frame z up), model in the module docstring."""
    part = _b3d(shape)
    bb = part.bounding_box()
    z0, T = bb.min.Z, bb.max.Z - bb.min.Z
    n_layers = max(1, round(T / s.layer_height_mm))
    if n_layers > PRINT_LAYERS_MAX:  # refused before any section is cut: the work is per layer

        raise DesignError("parts.print_layer_height_mm", f"{s.layer_height_mm:g} mm layers make "
                          f"{n_layers} layers of a {T:.4g} mm tall printed part, over "
                          f"{PRINT_LAYERS_MAX} (cad/tolerances.py PRINT_LAYERS_MAX): use thicker "
                          "layers or a shorter part")
    h = T / n_layers
    zs = [z0 + (k + 0.5) * h for k in range(n_layers)]
    size = 4 * max(bb.size.X, bb.size.Y) + 10
    slab = _slabs(part, zs)
    sections: dict[tuple, list] = {}
    for k, i in enumerate(slab):
        if i not in sections:
            sections[i] = _section(part.wrapped, zs[k], size)
    cache: dict[tuple[int, ...], float] = {}
    core = 0.0
    n = s.solid_layers
    for k in range(n_layers):
        if k - n < 0 or k + n >= n_layers:
            continue
        key = tuple(dict.fromkeys(slab[k - n : k + n + 1]))
        if key not in cache:
            faces = sections[key[0]]
            for i in key[1:]:
                faces = _common(faces, sections[i])
            cache[key] = _shrunk_area_mm2(faces, s.wall_mm)
        core += cache[key] * h
    return core


def printed_mass_kg(shape, density_kg_m3: float, s: PrintSettings) -> float:
    """Mass (kg) of the printed part: density x (solid volume - (1 - infill) x core)."""
    part = _b3d(shape)
    core = printed_core_mm3(part, s)
    v = part.volume - (1.0 - s.infill) * core
    if not math.isfinite(v) or v <= 0:
        raise ValueError(f"printed volume {v!r} mm^3 of a {part.volume:g} mm^3 part")
    return density_kg_m3 * v * 1e-9


def print_flip(shape, s: PrintSettings) -> bool:
    """True when the part prints better flipped (part z down): its top layer has more area
    than its bottom one (the larger face goes on the bed, a counterbore opens upward)."""
    part = _b3d(shape)
    bb = part.bounding_box()
    h = (bb.max.Z - bb.min.Z) / max(1, round((bb.max.Z - bb.min.Z) / s.layer_height_mm))
    size = 4 * max(bb.size.X, bb.size.Y) + 10
    bottom = sum(f.area for f in _section(part.wrapped, bb.min.Z + h / 2, size))
    top = sum(f.area for f in _section(part.wrapped, bb.max.Z - h / 2, size))
    return top > bottom * (1 + 1e-6)
