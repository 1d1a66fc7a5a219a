"""DXF profiles of plate parts for laser or waterjet cutting (ezdxf, DXF R2000, mm).

The profile is the section of the plate by the plane half-way through its
thickness (plates are 2.5-D: every feature goes through), so the DXF holds the
outline and every hole. Lines become LINE, full circles CIRCLE, circular arcs ARC
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


def plate_profile_dxf(shape, name: str) -> str:
    """DXF text of a plate's cutting profile (section at mid-thickness, z up)."""
    import ezdxf
    from OCP.Bnd import Bnd_Box
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.BRepBndLib import BRepBndLib
    from OCP.GCPnts import GCPnts_QuasiUniformDeflection
    from OCP.GeomAbs import GeomAbs_Circle, GeomAbs_Line

    box = Bnd_Box()
    BRepBndLib.Add_s(shape, box)
    _, _, z0, _, _, z1 = box.Get()
    edges = _section_edges(shape, 0.5 * (z0 + z1))

    old = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        doc = ezdxf.new("R2000", setup=False)
        doc.header["$INSUNITS"] = 4  # millimetres
        msp = doc.modelspace()
        for e in edges:
            c = BRepAdaptor_Curve(e)
            u0, u1 = c.FirstParameter(), c.LastParameter()
            p0, p1 = c.Value(u0), c.Value(u1)
            kind = c.GetType()
            if kind == GeomAbs_Line:
                msp.add_line((p0.X(), p0.Y()), (p1.X(), p1.Y()), dxfattribs={"layer": "CUT"})
            elif kind == GeomAbs_Circle:
                circ = c.Circle()
                ctr, r = circ.Location(), circ.Radius()
                if abs(u1 - u0 - 2 * math.pi) < 1e-9:
                    msp.add_circle((ctr.X(), ctr.Y()), r, dxfattribs={"layer": "CUT"})
                    continue
                a0 = math.degrees(math.atan2(p0.Y() - ctr.Y(), p0.X() - ctr.X()))
                a1 = math.degrees(math.atan2(p1.Y() - ctr.Y(), p1.X() - ctr.X()))
                if circ.Axis().Direction().Z() < 0:  # clockwise in the plate plane
                    a0, a1 = a1, a0
                msp.add_arc((ctr.X(), ctr.Y()), r, a0 % 360.0, a1 % 360.0, dxfattribs={"layer": "CUT"})
            else:
                samp = GCPnts_QuasiUniformDeflection(c, DXF_SAMPLE_DEFLECTION_MM)
                pts = [(samp.Value(i).X(), samp.Value(i).Y()) for i in range(1, samp.NbPoints() + 1)]
                msp.add_lwpolyline(pts, dxfattribs={"layer": "CUT"})
        buf = io.StringIO()
        doc.write(buf)
        return buf.getvalue()
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = old


def dxf_profile_area_mm2(text: str) -> float:
    """Net area enclosed by a profile written by :func:`plate_profile_dxf` (mm^2).

    Rebuilds closed loops from the DXF entities with ezdxf's path tools and returns
    the outer area minus the holes (the largest loop is the outline). Used by tests
    to check a DXF against the solid's volume / thickness.
    """
    import ezdxf
    from ezdxf import path as ezpath

    doc = ezdxf.read(io.StringIO(text))
    paths = [ezpath.make_path(e) for e in doc.modelspace()]
    loops = _chain(paths)
    areas = sorted((abs(_shoelace(lp)) for lp in loops), reverse=True)
    if not areas:
        raise GeometryError("DXF has no closed loop")
    return areas[0] - sum(areas[1:])


def _shoelace(pts) -> float:
    a = 0.0
    for (x0, y0), (x1, y1) in zip(pts, pts[1:] + pts[:1], strict=True):
        a += x0 * y1 - x1 * y0
    return 0.5 * a


def _chain(paths, tol: float = 1e-6):
    """Join path pieces end to end into closed point loops."""
    pieces = []
    for p in paths:
        pts = [(v.x, v.y) for v in p.flattening(0.001)]
        if len(pts) >= 2:
            pieces.append(pts)
    loops = []
    while pieces:
        cur = pieces.pop(0)
        grown = True
        while grown and math.dist(cur[0], cur[-1]) > tol:
            grown = False
            for i, q in enumerate(pieces):
                if math.dist(cur[-1], q[0]) <= tol:
                    cur = cur + q[1:]
                elif math.dist(cur[-1], q[-1]) <= tol:
                    cur = cur + q[::-1][1:]
                else:
                    continue
                pieces.pop(i)
                grown = True
                break
        loops.append(cur[:-1] if math.dist(cur[0], cur[-1]) <= tol else cur)
    return loops
