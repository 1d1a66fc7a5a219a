"""By-hand references of the capstan solids for the tests (independent of
:mod:`cad.actuators.capstan_geometry` and :mod:`cad.parts.capstan`): OCCT's exact section of a
solid in a meridian half-plane (:func:`section_profile`), a radial hole's volume by quadrature
(:func:`radial_hole_mm3`), and a grooved capstan's inertia (:func:`grooved_capstan_izz_kg_m2`): a steel tube from the bore to the crests (pitch less one
rope diameter, plus the groove depth 0.35 d), 1.5 d per wrap + an 8 mm hub long, less the helical
groove: the circle of radius d / 2 on the pitch circle, the part of it inside the crests, its
int r^3 dA by Gauss-Legendre over the radial offset u (chord 2 sqrt(rho^2 - u^2)), swept round
2 pi per wrap and stretched along the helix by sqrt(1 + (p / 2 pi r_bar)^2)."""

from __future__ import annotations

import math

import numpy as np


def grooved_capstan_izz_kg_m2(dc_mm: float, rope_d_mm: float, wraps: float, bore_mm: float,
                              density_kg_m3: float) -> float:
    rho, h = rope_d_mm / 2, 0.35 * rope_d_mm
    r_p = dc_mm / 2
    ro, ri = (dc_mm - rope_d_mm) / 2 + h, bore_mm / 2
    L = 1.5 * rope_d_mm * wraps + 8.0
    m = math.pi * (ro * ro - ri * ri) * L * 1e-9 * density_kg_m3
    tube = 0.5 * m * (ro * ro + ri * ri) * 1e-6
    x, w = np.polynomial.legendre.leggauss(2000)
    u = -rho + 0.5 * h * (x + 1.0)
    chord = 2.0 * np.sqrt(np.maximum(rho * rho - u * u, 0.0))
    area = 0.5 * h * np.sum(w * chord)
    rbar = 0.5 * h * np.sum(w * chord * (r_p + u)) / area
    r3 = 0.5 * h * np.sum(w * chord * (r_p + u) ** 3)
    stretch = math.sqrt(1.0 + (1.5 * rope_d_mm / (2 * math.pi * rbar)) ** 2)
    return tube - density_kg_m3 * 1e-15 * 2 * math.pi * wraps * stretch * r3


def radial_hole_mm3(r_h: float, r_rim: float, depth: float) -> float:
    """A radial hole of radius r_h drilled from a rim of radius r_rim to depth (flat bottom at
    r_rim - depth): the integral over the hole's disc of sqrt(r_rim^2 - y^2) - (r_rim - depth),
    Gauss-Legendre in theta with y = r_h sin(theta)."""
    x, w = np.polynomial.legendre.leggauss(200)
    th = 0.5 * math.pi * x
    y = r_h * np.sin(th)
    chord = np.sqrt(r_rim ** 2 - y ** 2) - (r_rim - depth)
    return float(np.sum(w * 2.0 * r_h ** 2 * np.cos(th) ** 2 * chord) * 0.5 * math.pi)


def section_profile(shape, angle_deg: float = 0.0, n: int = 400) -> np.ndarray:
    """(z, r) (N, 2) mm of the solid's outline in the meridian half-plane at ``angle_deg`` about
    z (r > 0 along (cos a, sin a)): OCCT's exact section of the solid with that plane
    (BRepAlgoAPI_Section), each edge sampled at ``n`` parameters, a straight edge at its ends (a
    0.002 mm tessellation took 45 s for the same profile)."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Section
    from OCP.GeomAbs import GeomAbs_Line
    from OCP.gp import gp_Dir, gp_Pln, gp_Pnt
    from OCP.TopAbs import TopAbs_EDGE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    a = math.radians(angle_deg)
    c, s = math.cos(a), math.sin(a)
    sec = BRepAlgoAPI_Section(getattr(shape, "wrapped", shape), gp_Pln(gp_Pnt(0, 0, 0), gp_Dir(-s, c, 0)))
    sec.Build()
    ex, pts = TopExp_Explorer(sec.Shape(), TopAbs_EDGE), []
    while ex.More():
        cv = BRepAdaptor_Curve(TopoDS.Edge_s(ex.Current()))
        k = 2 if cv.GetType() == GeomAbs_Line else n  # a straight edge: its two ends
        pts += [(p.X(), p.Y(), p.Z()) for p in map(cv.Value, np.linspace(cv.FirstParameter(), cv.LastParameter(), k))]
        ex.Next()
    pts = np.asarray(pts)
    r = pts[:, 0] * c + pts[:, 1] * s
    keep = r > 0
    return np.column_stack([pts[keep, 2], r[keep]])


def sector_distance_mm(p, s, q_deg: float, reach_mm: float, margin_deg: float) -> float:
    """Distance (mm) from plan point ``p`` to drum side ``s``'s swept sector (radius 0 ..
    ``reach_mm``, its arc widened by ``margin_deg`` at both ends) at link angle ``q_deg``: past
    the rim inside the arc, else to the nearer end radius (plane geometry by hand, a second
    method beside the sampled masks of :mod:`cad.families.pantograph.twin_placement`)."""
    v = np.asarray(p, float) - np.asarray(s.b_mm, float)
    a0 = s.arc_start_deg + q_deg - margin_deg
    span = s.arc_span_deg + 2 * margin_deg
    if (math.degrees(math.atan2(v[1], v[0])) - a0) % 360.0 <= span:
        return max(float(np.hypot(*v)) - reach_mm, 0.0)
    out = math.inf
    for a in (a0, a0 + span):
        u = np.array([math.cos(math.radians(a)), math.sin(math.radians(a))])
        out = min(out, float(np.hypot(*(v - np.clip(v @ u, 0.0, reach_mm) * u))))
    return out
