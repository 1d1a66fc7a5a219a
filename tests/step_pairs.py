"""Independent every-pair check of an assembly STEP file read back from disk (test helper).

Not the tool's code path: the file is re-imported with OCCT's XCAF STEP reader (one label
per part, its name from the file), every part's solids are collected, and every pair of
parts whose bounding boxes overlap is intersected with ``BRepAlgoAPI_Common`` on every
pair of their solids; a pair counts as a clash when the common volume exceeds
:data:`CLASH_MM3` (the issue's threshold). Solids of one part (a bearing's rings and
balls) are not compared with each other: a bought part is one part.
"""

from __future__ import annotations

import itertools
from pathlib import Path

#: A common volume above this is a clash (mm^3), issue 10.
CLASH_MM3 = 1e-3


def read_parts(path: Path) -> list[tuple[str, list]]:
    """``[(part name, [TopoDS_Solid, ...])]`` of the STEP file's free shapes' components."""
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPCAFControl import STEPCAFControl_Reader
    from OCP.TCollection import TCollection_ExtendedString
    from OCP.TDataStd import TDataStd_Name
    from OCP.TDF import TDF_LabelSequence
    from OCP.TDocStd import TDocStd_Document
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS
    from OCP.XCAFDoc import XCAFDoc_DocumentTool

    doc = TDocStd_Document(TCollection_ExtendedString("doc"))
    r = STEPCAFControl_Reader()
    r.SetNameMode(True)
    assert r.ReadFile(str(path)) == IFSelect_RetDone, path
    assert r.Transfer(doc)
    st = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
    free = TDF_LabelSequence()
    st.GetFreeShapes(free)
    out = []

    def name_of(lab) -> str:
        attr = TDataStd_Name()
        if lab.FindAttribute(TDataStd_Name.GetID_s(), attr):
            return attr.Get().ToExtString()
        return "?"

    def solids(shape) -> list:
        ex = TopExp_Explorer(shape, TopAbs_SOLID)
        res = []
        while ex.More():
            res.append(TopoDS.Solid_s(ex.Current()))
            ex.Next()
        return res

    for i in range(1, free.Length() + 1):
        root = free.Value(i)
        comps = TDF_LabelSequence()
        st.GetComponents_s(root, comps, False)
        if comps.Length() == 0:
            out.append((name_of(root), solids(st.GetShape_s(root))))
            continue
        for k in range(1, comps.Length() + 1):
            c = comps.Value(k)
            out.append((name_of(c), solids(st.GetShape_s(c))))
    return out


def _box(solids, tight: bool = False):
    """Bounding box of some solids (``tight``: OCCT's optimal box, else the fast loose one)."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    b = Bnd_Box()
    for s in solids:
        if tight:
            BRepBndLib.AddOptimal_s(s, b, False, False)
        else:
            BRepBndLib.Add_s(s, b)
    return b


def clashes(path: Path, threshold_mm3: float = CLASH_MM3) -> list[tuple[str, str, float]]:
    """``[(part a, part b, common volume mm^3)]`` for every pair of parts of the STEP file
    sharing more than ``threshold_mm3``."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Common
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    parts = read_parts(path)
    boxes = [_box(s) for _, s in parts]
    out = []
    for i, j in itertools.combinations(range(len(parts)), 2):
        if boxes[i].IsOut(boxes[j]):
            continue
        vol = 0.0
        for sa in parts[i][1]:
            for sb in parts[j][1]:
                props = GProp_GProps()
                BRepGProp.VolumeProperties_s(BRepAlgoAPI_Common(sa, sb).Shape(), props)
                vol += max(0.0, props.Mass())
        if vol > threshold_mm3:
            out.append((parts[i][0], parts[j][0], vol))
    return out


def _classifier(solids):
    """``inside(x, y, z)``: is the point inside one of ``solids`` (OCCT classifiers, built once)?"""
    from OCP.BRepClass3d import BRepClass3d_SolidClassifier
    from OCP.gp import gp_Pnt
    from OCP.TopAbs import TopAbs_IN

    cls = [BRepClass3d_SolidClassifier(s) for s in solids]

    def inside(x: float, y: float, z: float) -> bool:
        for c in cls:
            c.Perform(gp_Pnt(x, y, z), 1e-7)
            if c.State() == TopAbs_IN:
                return True
        return False

    return inside


def thread_in_part_mm(screw, part, d_mm: float, head_d_mm: float, tol_mm: float = 0.005):
    """Measured from the solids (a vertical screw): ``(engagement, tip_free)``. The screw's
    axis is its box centre; its head end is the end where a point at 0.45 x the head diameter
    off the axis is inside the screw. From the tip towards the head, the engagement is the
    length over which a ring of 6 points at radius d/2 + 0.3 mm (outside the thread, in the
    material a tapped hole leaves) lies inside ``part``: its end found by bisection to
    ``tol_mm``, then checked (ring inside at 8 heights below it, outside 0.05 mm above);
    ``tip_free`` says the point on the axis 0.2 mm beyond the tip is not inside ``part`` (the
    hole goes deeper: no bottoming). Returns (-1, ...) when the ring is not inside the part
    just above the tip."""
    import math

    in_screw, in_part = _classifier(screw), _classifier(part)
    b = _box(screw, tight=True)
    x0, y0, z0, x1, y1, z1 = b.Get()
    cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    head_up = in_screw(cx + 0.45 * head_d_mm, cy, z1 - 0.2)
    tip, sgn = (z0, 1.0) if head_up else (z1, -1.0)
    r = d_mm / 2 + 0.3
    ring = [(cx + r * math.cos(a), cy + r * math.sin(a)) for a in
            (k * math.pi / 3 + 0.1 for k in range(6))]

    def ring_in(h: float) -> bool:
        return all(in_part(x, y, tip + sgn * h) for x, y in ring)

    lo, hi = 0.01, z1 - z0
    if not ring_in(lo):
        return -1.0, False
    while hi - lo > tol_mm:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ring_in(mid) else (lo, mid)
    assert all(ring_in(lo * k / 8) for k in range(1, 8)) and not ring_in(lo + 0.05)
    return lo, not in_part(cx, cy, tip - sgn * 0.2)



def thread_length_mm(screw, tip_xyz, up, tol_mm: float = 0.005) -> float:
    """Length of the screw's threaded end measured from its solid: from the tip point
    ``tip_xyz`` along the unit direction ``up`` (towards the head), the screw's radius just
    above the tip, r0 (bisection on a ray), then the length over which a ring of 6 points at
    0.95 r0 stays inside the screw (the thread relief / neck is thinner) -- bisection to
    ``tol_mm``."""
    import math

    import numpy as np

    in_screw = _classifier(screw)
    tip, u = np.asarray(tip_xyz, dtype=float), np.asarray(up, dtype=float)
    w1 = np.cross(u, [1.0, 0.0, 0.0] if abs(u[0]) < 0.9 else [0.0, 1.0, 0.0])
    w1 /= np.linalg.norm(w1)
    w2 = np.cross(u, w1)
    p0 = tip + 0.3 * u
    lo, hi = 0.0, 50.0
    while hi - lo > tol_mm / 10:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if in_screw(*(p0 + mid * w1)) else (lo, mid)
    r = 0.95 * lo
    ring = [r * (math.cos(a) * w1 + math.sin(a) * w2) for a in
            (k * math.pi / 3 + 0.1 for k in range(6))]

    def ring_in(h: float) -> bool:
        return all(in_screw(*(tip + h * u + q)) for q in ring)

    lo, hi = 0.3, 0.3
    while ring_in(hi):
        hi += 1.0
    while hi - lo > tol_mm:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ring_in(mid) else (lo, mid)
    return lo


def tip_on_axis_mm(screw, part, d_mm: float, a0, u, inside_s: float,
                   tol_mm: float = 0.005) -> dict:
    """A threaded tip on the line ``a0 + s u`` (u unit), screwed in towards -u, measured from
    the solids: ``tip_s`` (where the axis leaves the screw, by bisection from ``inside_s``, a
    point of the axis known inside the screw, towards -u); ``engagement_mm`` (from the tip
    towards +u, the length over which a ring of 6 points at d/2 + 0.3 mm -- in the material a
    tapped hole leaves -- lies inside ``part``); ``tip_free`` (the axis point 0.2 mm beyond
    the tip is not inside ``part``: the hole goes deeper)."""
    import math

    import numpy as np

    a0, u = np.asarray(a0, dtype=float), np.asarray(u, dtype=float)
    in_screw, in_part = _classifier(screw), _classifier(part)
    at = lambda s: a0 + s * u  # noqa: E731
    assert in_screw(*at(inside_s))
    lo, hi = inside_s - 200.0, inside_s  # lo outside the screw, hi inside
    assert not in_screw(*at(lo))
    while hi - lo > tol_mm / 4:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if in_screw(*at(mid)) else (mid, hi)
    tip = hi
    w1 = np.cross(u, [1.0, 0.0, 0.0] if abs(u[0]) < 0.9 else [0.0, 1.0, 0.0])
    w1 /= np.linalg.norm(w1)
    w2 = np.cross(u, w1)
    r = d_mm / 2 + 0.3
    ring = [r * (math.cos(a) * w1 + math.sin(a) * w2) for a in
            (k * math.pi / 3 + 0.1 for k in range(6))]

    def ring_in(h: float) -> bool:
        return all(in_part(*(at(tip + h) + q)) for q in ring)

    lo, hi = 0.01, 100.0
    if not ring_in(lo):
        return {"tip_s": tip, "engagement_mm": -1.0, "tip_free": False}
    while hi - lo > tol_mm:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ring_in(mid) else (lo, mid)
    assert all(ring_in(lo * k / 8) for k in range(1, 8)) and not ring_in(lo + 0.05)
    return {"tip_s": tip, "engagement_mm": lo, "tip_free": not in_part(*at(tip - 0.2))}


def _planar_face_centres(solids) -> list:
    """Centres of mass of the planar faces of ``solids`` (numpy 3-vectors)."""
    import numpy as np
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.BRepGProp import BRepGProp
    from OCP.GeomAbs import GeomAbs_Plane
    from OCP.GProp import GProp_GProps
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    out = []
    for s in solids:
        ex = TopExp_Explorer(s, TopAbs_FACE)
        while ex.More():
            f = TopoDS.Face_s(ex.Current())
            if BRepAdaptor_Surface(f).GetType() == GeomAbs_Plane:
                g = GProp_GProps()
                BRepGProp.SurfaceProperties_s(f, g)
                c = g.CentreOfMass()
                out.append(np.array([c.X(), c.Y(), c.Z()]))
            ex.Next()
    return out


def radial_screw_mm(screw, part, shaft, d_mm: float, tol_mm: float = 0.005,
                    shaft_axis=None) -> dict:
    """A set screw (a plain cylinder: two planar end faces) tapped radially through ``part``
    onto a ``shaft``, measured from the solids: ``length_mm`` (between the end faces'
    centres); ``tip_to_axis_mm`` / ``end_to_axis_mm`` (distance of the point's and the other
    end's centres from the shaft axis: ``shaft_axis`` = (point, unit direction), default the
    vertical line through the shaft's box centre);
    ``rim_to_axis_max_mm`` (largest distance of the end's rim at d/2 from that axis);
    ``full_thread_mm`` (from the tip outwards, the length over which a ring of 24 points
    at d/2 (every 15 degrees) round the screw axis lies inside ``part``, bisection to ``tol_mm``);
    ``tip_on_shaft`` (the axis point 0.05 mm beyond the tip is inside the shaft)."""
    import math

    import numpy as np

    ends = _planar_face_centres(screw)
    assert len(ends) == 2, len(ends)
    if shaft_axis is None:
        sx0, sy0, _, sx1, sy1, _ = _box(shaft, tight=True).Get()
        shaft_axis = (np.array([0.5 * (sx0 + sx1), 0.5 * (sy0 + sy1), 0.0]), np.array([0, 0, 1.0]))
    a0, w1 = (np.asarray(v, dtype=float) for v in shaft_axis)

    def to_axis(p) -> float:
        q = np.asarray(p, dtype=float) - a0
        return float(np.linalg.norm(q - (q @ w1) * w1))

    dist = [to_axis(e) for e in ends]
    tip, end = (ends[0], ends[1]) if dist[0] < dist[1] else (ends[1], ends[0])
    u = (end - tip) / np.linalg.norm(end - tip)
    w2 = np.cross(u, w1)
    ring = [0.5 * d_mm * (math.cos(a) * w1 + math.sin(a) * w2)
            for a in (k * math.pi / 12 for k in range(24))]
    rim = [end + 0.5 * d_mm * (math.cos(a) * w1 + math.sin(a) * w2)
           for a in (k * math.pi / 18 for k in range(36))]
    in_part, in_shaft = _classifier(part), _classifier(shaft)

    def ring_in(h: float) -> bool:
        return all(in_part(*(tip + h * u + r)) for r in ring)

    lo, hi = 0.01, 3.0 * float(np.linalg.norm(end - tip))
    assert ring_in(lo) and not ring_in(hi)
    while hi - lo > tol_mm:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ring_in(mid) else (lo, mid)
    return {
        "length_mm": float(np.linalg.norm(end - tip)),
        "tip_to_axis_mm": min(dist),
        "end_to_axis_mm": max(dist),
        "rim_to_axis_max_mm": max(to_axis(p) for p in rim),
        "full_thread_mm": lo,
        "tip_on_shaft": in_shaft(*(tip - 0.05 * u)),
    }

if __name__ == "__main__":
    import sys

    ps = read_parts(Path(sys.argv[1]))
    print(len(ps), "parts", sum(len(s) for _, s in ps), "solids")
    for a, b, v in clashes(Path(sys.argv[1])):
        print(f"{a} / {b}: {v:.3f} mm^3")
