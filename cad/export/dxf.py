"""DXF profiles of plate parts for laser or waterjet cutting (ezdxf, DXF R2000, mm).

Layers: ``CUT`` is the through profile -- the plate's section at the level (between two
consecutive z levels of its flat faces) with the most material, i.e. outline and through
holes only; every other level with less material (a bearing seat counterbored into a
bar, say) is written on its own layer ``MILL_Z<lo>_<hi>`` (its full section, z in mm from
the plate's bottom face) for the machining after cutting. A plain 2.5-D plate has only
``CUT``. Lines become LINE, full circles CIRCLE, circular arcs ARC
(counter-clockwise, as DXF requires), anything else an LWPOLYLINE sampled at
:data:`DXF_SAMPLE_DEFLECTION_MM`. Metadata is fixed
(``ezdxf.options.write_fixed_meta_data_for_testing``): no time stamps or random
GUIDs, so the file is the same every run.
"""

from __future__ import annotations

import io
import math

from cad.errors import GeometryError

#: Chordal deflection used to sample edges that are neither lines nor circles (mm).
DXF_SAMPLE_DEFLECTION_MM = 0.005


def _section_edges(shape, z_mm: float):
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Section
    from OCP.gp import gp_Dir, gp_Pln, gp_Pnt
    from OCP.TopAbs import TopAbs_EDGE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    sec = BRepAlgoAPI_Section(shape, gp_Pln(gp_Pnt(0, 0, z_mm), gp_Dir(0, 0, 1)))
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


def _slab_area_mm2(shape, z0: float, z1: float) -> float:
    """Mean cross-section area of ``shape`` between z0 and z1 (volume of the slab / height)."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Common
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
    BRepGProp.VolumeProperties_s(BRepAlgoAPI_Common(shape, slab).Shape(), props)
    return props.Mass() / (z1 - z0)


def _add_edges(msp, edges, layer: str) -> None:
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
                msp.add_circle((ctr.X(), ctr.Y()), r, dxfattribs=att)
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


def plate_profile_dxf(shape, name: str) -> str:
    """DXF text of a plate's cutting profile (layer ``CUT``) and milled levels (``MILL_*``)."""
    import ezdxf

    levels = _z_levels(shape)
    if len(levels) < 2:
        raise GeometryError(f"{name}: not a plate (needs flat faces normal to z)")
    bands = list(zip(levels[:-1], levels[1:], strict=True))
    areas = [_slab_area_mm2(shape, a, b) for a, b in bands] if len(bands) > 1 else [1.0]
    i_cut = max(range(len(bands)), key=lambda i: (areas[i], -i))
    z_bottom = levels[0]
    old = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        doc = ezdxf.new("R2000", setup=False)
        doc.header["$INSUNITS"] = 4  # millimetres
        msp = doc.modelspace()
        for i, (a, b) in enumerate(bands):
            if i != i_cut and areas[i] >= areas[i_cut] - 1e-9:
                continue  # same material as the through profile: nothing to mill there
            layer = "CUT" if i == i_cut else f"MILL_Z{a - z_bottom:.2f}_{b - z_bottom:.2f}"
            if layer not in doc.layers:
                doc.layers.add(layer)
            _add_edges(msp, _section_edges(shape, 0.5 * (a + b)), layer)
        buf = io.StringIO()
        doc.write(buf)
        return buf.getvalue()
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = old


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
