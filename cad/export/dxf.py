"""DXF profiles of plate parts for laser or waterjet cutting (ezdxf, DXF R2000, mm).

Layers: ``CUT`` is the through profile -- the plate's section at the level (between two
consecutive z levels of its flat faces) with the most material, i.e. outline and through
holes only; every other level with less material (a bearing seat counterbored into a
bar, say) is written on its own layer ``MILL_Z<lo>_<hi>`` (z in mm from the plate's
bottom face) for the machining after cutting -- only the edges that differ from the
through profile (the seat, not the outline repeated). A plain 2.5-D plate has only
``CUT``. A bore finished by reaming (or boring) is cut undersize by the stock the shop
needs (:data:`cad.data.fits.REAM_ALLOWANCE_MM`, source there) and noted ``ream to 8
H7``; a milled bearing seat is noted with its fit, depth and layer; a tapped hole is cut at
its tap drill (d - P) with its thread note. The layer ``NOTES`` (TEXT under the part) holds
the part name, units, material, thickness and quantity, the ISO 286 fits and those notes. Lines become LINE, full circles CIRCLE, circular arcs ARC
(counter-clockwise, as DXF requires), anything else an LWPOLYLINE sampled at
:data:`DXF_SAMPLE_DEFLECTION_MM`. Metadata is fixed
(``ezdxf.options.write_fixed_meta_data_for_testing``): no time stamps or random
GUIDs, so the file is the same every run.
"""

from __future__ import annotations

import io
import math

from cad.data.fits import REAM_ALLOWANCE_SOURCE, TAP_DRILL_SOURCE, fmt_mm
from cad.errors import GeometryError
from cad.export.shapes import make_compound
from cad.occ.boolean import common
from cad.occ.compound import deep_copy

#: Chordal deflection used to sample edges that are neither lines nor circles (mm).
DXF_SAMPLE_DEFLECTION_MM = 0.005
#: A profile circle is a listed hole when their diameters agree this closely (mm): the solid's
#: holes are made at the listed diameter, so only round-off separates them.
DXF_MATCH_MM = 1e-6
#: Finishes whose bores the profile cuts at :attr:`cad.data.fits.ShopHole.cut_d_mm`.
CUT_FINISHES = ("ream", "bore", "tap")


def _section_edges(shape, z_mm: float):
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Section
    from OCP.gp import gp_Dir, gp_Pln, gp_Pnt
    from OCP.TopAbs import TopAbs_EDGE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS


    # on a copy, as cad.occ.boolean: the plate's solid is shared with its other exports and
    # must keep its tolerances
    sec = BRepAlgoAPI_Section(deep_copy(shape), gp_Pln(gp_Pnt(0, 0, z_mm), gp_Dir(0, 0, 1)))
    sec.Build()
    if not sec.IsDone():
        raise GeometryError("DXF: section of the plate failed")
    edges = []
    exp = TopExp_Explorer(sec.Shape(), TopAbs_EDGE)
    while exp.More():
        edges.append(TopoDS.Edge_s(exp.Current()))
        exp.Next()
    if not edges:
        raise GeometryError(f"DXF: the plane z = {z_mm:g} mm does not cut the plate")
    return edges


def _z_levels(shape) -> list[float]:
    """Heights of the plate's faces normal to z (sorted, merged within 1e-7 mm)."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAbs import GeomAbs_Plane
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    zs: list[float] = []
    exp = TopExp_Explorer(shape, TopAbs_FACE)
    while exp.More():
        srf = BRepAdaptor_Surface(TopoDS.Face_s(exp.Current()))
        exp.Next()
        if srf.GetType() != GeomAbs_Plane:
            continue
        pln = srf.Plane()
        if abs(abs(pln.Axis().Direction().Z()) - 1.0) < 1e-9:
            zs.append(pln.Location().Z())
    out: list[float] = []
    for z in sorted(zs):
        if not out or z - out[-1] > 1e-7:
            out.append(z)
    return out


#: Heights (fractions of the through band) the ``CUT`` section is taken at, the middle first:
#: the one with the most material wins (:func:`cut_height_mm`).
CUT_HEIGHT_FRACTIONS = (0.5, 0.05, 0.95)
#: Half-height of the thin slab that measures a section's area (mm).
SECTION_SLAB_MM = 0.01


def cut_height_mm(shape, z0: float, z1: float) -> float:
    """The height (mm) of the through band [z0, z1] whose section holds the most material, of
    :data:`CUT_HEIGHT_FRACTIONS` (the middle unless another holds more): a hole drilled in the
    plate's plane (a screw tapped into its edge) crosses the middle section and would be cut
    into the profile as a slot; near a face the section keeps the outline, and the hole is
    noted as "not on this profile" (drilled after cutting)."""
    zs = [z0 + f * (z1 - z0) for f in CUT_HEIGHT_FRACTIONS]
    areas = [_slab_area_mm2(shape, z - SECTION_SLAB_MM, z + SECTION_SLAB_MM) for z in zs]
    best = max(range(len(zs)), key=lambda i: (round(areas[i], 6), -i))
    return zs[best]


def _slab_area_mm2(shape, z0: float, z1: float) -> float:
    """Mean cross-section area of ``shape`` between z0 and z1 (volume of the slab / height)."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib
    from OCP.BRepGProp import BRepGProp
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox
    from OCP.gp import gp_Pnt
    from OCP.GProp import GProp_GProps


    box = Bnd_Box()
    BRepBndLib.Add_s(shape, box)
    x0, y0, _, x1, y1, _ = box.Get()
    slab = BRepPrimAPI_MakeBox(gp_Pnt(x0 - 1, y0 - 1, z0), gp_Pnt(x1 + 1, y1 + 1, z1)).Shape()
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(common(shape, slab), props)
    return props.Mass() / (z1 - z0)


def _add_edges(msp, edges, layer: str, resize=None) -> None:
    """Write ``edges`` on ``layer``; ``resize(r_mm) -> r_mm`` changes a full circle's radius
    (a bore cut undersize for reaming)."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.GCPnts import GCPnts_QuasiUniformDeflection
    from OCP.GeomAbs import GeomAbs_Circle, GeomAbs_Line

    att = {"layer": layer}
    for e in edges:
        c = BRepAdaptor_Curve(e)
        u0, u1 = c.FirstParameter(), c.LastParameter()
        p0, p1 = c.Value(u0), c.Value(u1)
        kind = c.GetType()
        if kind == GeomAbs_Line:
            msp.add_line((p0.X(), p0.Y()), (p1.X(), p1.Y()), dxfattribs=att)
        elif kind == GeomAbs_Circle:
            circ = c.Circle()
            ctr, r = circ.Location(), circ.Radius()
            if abs(u1 - u0 - 2 * math.pi) < 1e-9:
                msp.add_circle((ctr.X(), ctr.Y()), resize(r) if resize else r, dxfattribs=att)
                continue
            a0 = math.degrees(math.atan2(p0.Y() - ctr.Y(), p0.X() - ctr.X()))
            a1 = math.degrees(math.atan2(p1.Y() - ctr.Y(), p1.X() - ctr.X()))
            if circ.Axis().Direction().Z() < 0:  # clockwise in the plate plane
                a0, a1 = a1, a0
            msp.add_arc((ctr.X(), ctr.Y()), r, a0 % 360.0, a1 % 360.0, dxfattribs=att)
        else:
            samp = GCPnts_QuasiUniformDeflection(c, DXF_SAMPLE_DEFLECTION_MM)
            pts = [(samp.Value(i).X(), samp.Value(i).Y()) for i in range(1, samp.NbPoints() + 1)]
            msp.add_lwpolyline(pts, dxfattribs=att)


def _full_circle_radii(edges) -> list[float]:
    """Radii of the full circles among ``edges`` (mm)."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.GeomAbs import GeomAbs_Circle

    out = []
    for e in edges:
        c = BRepAdaptor_Curve(e)
        if c.GetType() == GeomAbs_Circle and abs(
            c.LastParameter() - c.FirstParameter() - 2 * math.pi
        ) < 1e-9:
            out.append(c.Circle().Radius())
    return out


def _match(holes, r_mm: float, finishes) -> object | None:
    """The :class:`cad.data.fits.ShopHole` of ``finishes`` whose diameter is ``2 r_mm``."""
    for h in holes:
        if h.finish in finishes and abs(h.d_mm - 2.0 * r_mm) < DXF_MATCH_MM:
            return h
    return None


def _on_profile(edge, profile) -> bool:
    """Does ``edge`` lie on the ``profile`` edges (its mid point within 1e-6 mm)?"""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeVertex
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape

    c = BRepAdaptor_Curve(edge)
    mid = BRepBuilderAPI_MakeVertex(
        c.Value(0.5 * (c.FirstParameter() + c.LastParameter()))
    ).Vertex()
    dist = BRepExtrema_DistShapeShape(mid, profile)
    return dist.IsDone() and dist.Value() < 1e-6


def _mill_edges(shape, z_mm: float, cut_edges, z_cut: float) -> list:
    """Edges of the section at ``z_mm`` that are not on the through profile (moved to its z)."""
    from OCP.gp import gp_Trsf, gp_Vec
    from OCP.TopLoc import TopLoc_Location


    tr = gp_Trsf()
    tr.SetTranslation(gp_Vec(0.0, 0.0, z_mm - z_cut))
    profile = make_compound(cut_edges).Moved(TopLoc_Location(tr))
    return [e for e in _section_edges(shape, z_mm) if not _on_profile(e, profile)]


def plate_profile_dxf(
    shape, name: str, notes=(), holes=(), *, material: str = "", quantity: int | None = None,
    stock: str = "",
) -> str:
    """DXF text of a plate's cutting profile (layer ``CUT``), milled levels (``MILL_*``, only
    what differs from the profile) and the ``NOTES`` layer.

    holes : :class:`cad.data.fits.ShopHole` of the part: a ``CUT`` circle of a reamed or
        bored hole's diameter is cut at its ``cut_d_mm`` (the finishing stock left), a tapped
        hole's circle (already the tap drill) keeps its size; each hole found gets a note
        (count, cut size, finish; a milled seat its depth and layer).
    NOTES : part, units, material, thickness, quantity, stock (the BOM's, when given),
    ``notes`` (the fits), the hole notes.
    """
    import ezdxf

    levels = _z_levels(shape)
    if len(levels) < 2:
        raise GeometryError(f"{name}: not a plate (needs flat faces normal to z)")
    bands = list(zip(levels[:-1], levels[1:], strict=True))
    areas = [_slab_area_mm2(shape, a, b) for a, b in bands] if len(bands) > 1 else [1.0]
    i_cut = max(range(len(bands)), key=lambda i: (areas[i], -i))
    z_bottom, z_top = levels[0], levels[-1]
    old = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        doc = ezdxf.new("R2000", setup=False)
        doc.header["$INSUNITS"] = 4  # millimetres
        msp = doc.modelspace()
        z_cut = cut_height_mm(shape, *bands[i_cut])
        cut_edges = _section_edges(shape, z_cut)
        found: dict = {}  # ShopHole -> [count, detail]
        for i, (a, b) in enumerate(bands):
            if i != i_cut and areas[i] >= areas[i_cut] - 1e-9:
                continue  # same material as the through profile: nothing to mill there
            layer = "CUT" if i == i_cut else f"MILL_Z{a - z_bottom:.2f}_{b - z_bottom:.2f}"
            if layer not in doc.layers:
                doc.layers.add(layer)
            edges = cut_edges if i == i_cut else _mill_edges(shape, 0.5 * (a + b), cut_edges, z_cut)
            if i == i_cut:
                _add_edges(msp, edges, layer, _resizer(holes, found))
                continue
            _add_edges(msp, edges, layer)
            face = "top" if abs(b - z_top) < 1e-7 else "bottom" if abs(a - z_bottom) < 1e-7 else ""
            for r in _full_circle_radii(edges):
                h = _match(holes, r, ("mill",))
                if h is not None:
                    depth = f"{b - a:.2f} deep from the {face} face" if face else f"{b - a:.2f} thick"
                    found.setdefault(h, [0, f"{depth}, layer {layer}"])[0] += 1
        head = [f"part: {name}", "units: mm", f"material: {material or 'unstated'}",
                f"thickness: {z_top - z_bottom:.2f} mm",
                f"quantity: {quantity if quantity is not None else 'unstated'}",
                *([f"stock: {stock}"] if stock else [])]
        _add_notes(doc, msp, shape, [*head, *notes, *_hole_notes(holes, found)])
        buf = io.StringIO()
        doc.write(buf)
        return buf.getvalue()
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = old


def _resizer(holes, found: dict):
    """``r -> r`` of the ``CUT`` layer: a reamed or bored hole at its cut size (counted in
    ``found``), a tapped hole counted, anything else unchanged."""

    def resize(r: float) -> float:
        h = _match(holes, r, CUT_FINISHES)
        if h is None:
            return r
        found.setdefault(h, [0, ""])[0] += 1
        return 0.5 * h.cut_d_mm

    return resize


def _hole_notes(holes, found: dict) -> list[str]:
    """One line per hole of ``holes`` (how many the profile has, its cut size and finish),
    then the source of each allowance used."""
    out, sources = [], []
    for h in holes:
        n, detail = found.get(h, [0, ""])
        if n == 0:
            out.append(f"{h.label} {h.spec}: not on this profile")
        elif h.finish in ("ream", "bore"):
            out.append(f"{h.label} x{n}: cut at {fmt_mm(h.cut_d_mm)} "
                       f"({fmt_mm(h.d_mm - h.cut_d_mm)} mm stock); {h.note()}")
            sources.append(f"stock for reaming or boring: {REAM_ALLOWANCE_SOURCE}")
        elif h.finish == "tap":
            depth = f", full thread {fmt_mm(h.depth_mm)} deep" if h.depth_mm is not None else ""
            out.append(f"{h.spec} x{n}: cut at the tap drill {fmt_mm(h.d_mm)}; {h.note()}{depth}")
            sources.append(TAP_DRILL_SOURCE)
        else:
            out.append(f"{h.label} x{n}: {h.note()} (ISO 286), {detail}")
    return out + list(dict.fromkeys(sources))


#: Text height of the DXF notes (mm).
NOTE_HEIGHT_MM = 2.5


def _add_notes(doc, msp, shape, notes) -> None:
    """One TEXT line per note on layer ``NOTES``, below the part's outline."""
    if not notes:
        return
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    box = Bnd_Box()
    BRepBndLib.Add_s(shape, box)
    x0, y0, _, _, _, _ = box.Get()
    doc.layers.add("NOTES")
    for k, text in enumerate(notes):
        y = y0 - (k + 1.5) * 1.6 * NOTE_HEIGHT_MM
        msp.add_text(text, height=NOTE_HEIGHT_MM, dxfattribs={"layer": "NOTES", "insert": (x0, y)})


def dxf_profile_area_mm2(text: str, layer: str = "CUT") -> float:
    """Net area enclosed by one layer of a profile written by :func:`plate_profile_dxf` (mm^2).

    Exact for LINE / ARC / CIRCLE entities (Green's theorem per entity, pieces chained end
    to end into closed loops; polylines by their vertices). The largest loop is the
    outline, every other loop a hole. Used by tests to check a DXF against the solid.
    """
    import ezdxf

    doc = ezdxf.read(io.StringIO(text))
    pieces = []  # (start, end, 0.5 * integral of x dy - y dx along start -> end)
    areas = []
    for e in doc.modelspace():
        if e.dxf.layer != layer:
            continue
        kind = e.dxftype()
        if kind == "CIRCLE":
            areas.append(math.pi * e.dxf.radius**2)
        elif kind == "LINE":
            p0, p1 = (e.dxf.start.x, e.dxf.start.y), (e.dxf.end.x, e.dxf.end.y)
            pieces.append((p0, p1, 0.5 * (p0[0] * p1[1] - p1[0] * p0[1])))
        elif kind == "ARC":
            cx, cy, r = e.dxf.center.x, e.dxf.center.y, e.dxf.radius
            a0 = math.radians(e.dxf.start_angle)
            a1 = math.radians(e.dxf.end_angle)
            if a1 <= a0:
                a1 += 2 * math.pi
            w = 0.5 * (
                r * r * (a1 - a0)
                + cx * r * (math.sin(a1) - math.sin(a0))
                - cy * r * (math.cos(a1) - math.cos(a0))
            )
            pieces.append(
                (
                    (cx + r * math.cos(a0), cy + r * math.sin(a0)),
                    (cx + r * math.cos(a1), cy + r * math.sin(a1)),
                    w,
                )
            )
        elif kind == "LWPOLYLINE":
            pts = [(x, y) for x, y, *_ in e.get_points()]
            for q0, q1 in zip(pts[:-1], pts[1:], strict=True):
                pieces.append((q0, q1, 0.5 * (q0[0] * q1[1] - q1[0] * q0[1])))
    areas += _loop_areas(pieces)
    if not areas:
        raise GeometryError("DXF has no closed loop")
    areas.sort(reverse=True)
    return areas[0] - sum(areas[1:])


def _loop_areas(pieces, tol: float = 1e-6) -> list[float]:
    """Chain directed pieces (reversing as needed) into closed loops; |signed area| of each."""
    pieces = list(pieces)
    out = []
    while pieces:
        start, end, w = pieces.pop(0)
        total = w
        while math.dist(start, end) > tol:
            for i, (p0, p1, wi) in enumerate(pieces):
                if math.dist(end, p0) <= tol:
                    end, total = p1, total + wi
                elif math.dist(end, p1) <= tol:
                    end, total = p0, total - wi
                else:
                    continue
                pieces.pop(i)
                break
            else:
                raise GeometryError(
                    f"DXF profile has an open loop near ({end[0]:.4f}, {end[1]:.4f})"
                )
        out.append(abs(total))
    return out
