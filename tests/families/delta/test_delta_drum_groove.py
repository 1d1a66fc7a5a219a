"""The rope groove on the delta's drum sectors (designs/delta_capstan.toml,
cad/families/delta/capstan_solids.py) against independent references, as the four-bar's drum
(tests/unit/parts/test_capstan_solids.py, tests/families/fourbar/test_capstan_assembly.py):

* the profile read back from OCCT's exact section of the drawn drum with the half-plane
  through its axis at the groove's mid-angle: the crests at r_b + 0.35 d, the groove's bottom
  r_b = (D - d) / 2 at mid-thickness, its width at the crests the chord 2 sqrt(2 rho h - h^2)
  of the rope's circle (rho = d / 2, h = 0.35 d);
* the volume the groove removes (the drawn drum against the same sector to the crests with
  the same anchor holes and no groove, OCCT adaptive) against Pappus by hand: the circular
  segment's area rho^2 (a - sin a cos a), cos a = (rho - h) / rho, its centroid
  4 rho sin^3 a / (3 (2a - sin 2a)) inside the pitch circle, round the groove's arc (between
  the anchors less a land of one tap drill and one rope diameter at each);
* the drum's mass in the build's per-kind mass properties (the grooved solid) against the
  sector to the crests (theta / 2)(r_o^2 - r_i^2) t rho less its two radial anchor holes
  (quadrature of the hole's chord) and the groove by hand.
"""

from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from cad.data.catalog import tap_drill_mm
from cad.data.materials import get_material
from cad.design import parse_design
from cad.device import resolve_device

ROOT = Path(__file__).resolve().parents[3]
RAW = tomllib.loads((ROOT / "designs" / "delta_capstan.toml").read_text())


@pytest.fixture(scope="module")
def drum():
    """(design, the drum's kind, its placement's numbers: rd, h, start, span, anchors, th, d)."""
    from cad.assembly import capstan_hardware as fcs
    from cad.families.delta import capstan_solids as cs
    from cad.families.delta.assembly import assemble

    d = parse_design(copy.deepcopy(RAW), "v.toml")
    inst = assemble(d, "preview").instances
    kind = next(x.kind for x in inst if x.name == "upper_0.capstan_drum")
    t = resolve_device(d).transmission("theta_0")
    rope, dd = t.cable_diameter_mm, t.drum_diameter_mm
    # the arc by hand (2 gamma + the motor range + two anchor arcs), placed by the layout's angle
    C = dd / 2 + t.capstan_diameter_mm / 2 + 2.0  # the 2 mm rim gap
    gamma = math.degrees(math.acos((dd / 2 - t.capstan_diameter_mm / 2) / C))
    anchor = math.degrees(2 * 10.0 / dd)
    phi0, s = cs.link_angle_deg(d, 0, cs.motor_direction(d.mechanism, 0))
    lo, hi = sorted((phi0 + s * -40.0, phi0 + s * 85.0))
    start, span = lo - gamma - anchor, hi - lo + 2 * gamma + 2 * anchor
    return d, kind, {"rd": (dd - rope) / 2, "h": 0.35 * rope, "start": start, "span": span, "d": rope,
                     "anchors": (start + anchor / 2, start + span - anchor / 2), "th": fcs.DRUM_THICKNESS_MM,
                     "D": dd}


def _profile(shape, angle_deg: float, n: int = 400) -> np.ndarray:
    """(z, r) of the solid's outline in the half-plane through the z axis at ``angle_deg``:
    OCCT's exact section (BRepAlgoAPI_Section), each curved edge sampled at ``n`` parameters."""
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Section
    from OCP.GeomAbs import GeomAbs_Line
    from OCP.gp import gp_Dir, gp_Pln, gp_Pnt
    from OCP.TopAbs import TopAbs_EDGE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    a = math.radians(angle_deg)
    u = np.array([math.cos(a), math.sin(a), 0.0])
    sec = BRepAlgoAPI_Section(shape, gp_Pln(gp_Pnt(0, 0, 0), gp_Dir(-math.sin(a), math.cos(a), 0.0)))
    sec.Build()
    ex, pts = TopExp_Explorer(sec.Shape(), TopAbs_EDGE), []
    while ex.More():
        c = BRepAdaptor_Curve(TopoDS.Edge_s(ex.Current()))
        k = 2 if c.GetType() == GeomAbs_Line else n
        pts += [(p.X(), p.Y(), p.Z()) for p in map(c.Value, np.linspace(c.FirstParameter(), c.LastParameter(), k))]
        ex.Next()
    pts = np.asarray(pts)
    r = pts @ u
    return np.column_stack([pts[r > 0, 2], r[r > 0]])


def _segment(p: dict) -> tuple[float, float]:
    """(area mm^2, centroid radius mm) of the groove's section, by hand."""
    rho, h = p["d"] / 2, p["h"]
    a = math.acos((rho - h) / rho)
    return rho * rho * (a - math.sin(a) * math.cos(a)), p["D"] / 2 - 4 * rho * math.sin(a) ** 3 / (
        3 * (2 * a - math.sin(2 * a)))


def _groove_arc(p: dict) -> tuple[float, float]:
    land = math.degrees((tap_drill_mm("M3-0.5") + p["d"]) / p["rd"])
    lo, hi = p["anchors"]
    return lo + land, hi - lo - 2 * land


def test_groove_profile_from_the_exact_section(drum):
    _, kind, p = drum
    g0, gs = _groove_arc(p)
    zr = _profile(kind.shape, g0 + gs / 2)
    outer = zr[zr[:, 1] > p["rd"] - 0.1]
    crest, bottom = p["rd"] + p["h"], p["rd"]
    assert outer[:, 1].max() == pytest.approx(crest, abs=1e-6)
    assert outer[:, 1].min() == pytest.approx(bottom, abs=3e-3)
    low = outer[outer[:, 1] < crest - 1e-6][:, 0]
    assert low.mean() == pytest.approx(p["th"] / 2, abs=1e-3)
    top = outer[np.abs(outer[:, 1] - crest) < 1e-6][:, 0]
    width = top[top > p["th"] / 2].min() - top[top < p["th"] / 2].max()
    rho, h = p["d"] / 2, p["h"]
    assert width == pytest.approx(2 * math.sqrt(2 * rho * h - h * h), abs=1e-6)
    # outside the groove's arc (on an anchor's land) the rim is whole: the crests all through
    zr = _profile(kind.shape, p["anchors"][0] + 0.5 * (g0 - p["anchors"][0]))
    assert zr[zr[:, 1] > p["rd"] - 0.1][:, 1].min() == pytest.approx(crest, abs=1e-6)


def test_groove_volume_and_drum_mass_against_the_closed_forms(drum):
    from cad.actuators import capstan_geometry as cg
    from cad.massprops.occt import volume_props_mm
    from cad.parts.capstan import drum_sector_shape
    from cad.pipeline import family

    _, kind, p = drum
    tap, depth = tap_drill_mm("M3-0.5"), 8.0 + 1.0  # the anchor screw's length + the tap's lead-out
    plain = drum_sector_shape(p["rd"] + p["h"], 6.0, p["start"], p["span"], p["th"],
                              tuple((a, tap, depth + p["h"]) for a in p["anchors"]))
    area, rbar = _segment(p)
    g0, gs = _groove_arc(p)
    groove = area * rbar * math.radians(gs)
    removed = volume_props_mm(plain, eps=1e-9)[0] - volume_props_mm(kind.shape, eps=1e-9)[0]
    assert removed == pytest.approx(groove, rel=1e-8)
    assert cg.ring_groove_volume_mm3(p["D"], p["d"], gs) == pytest.approx(groove, rel=1e-12)
    # the whole drum: the sector to the crests less the two anchor holes and the groove
    r_o, r_i = p["rd"] + p["h"], 6.0
    x, w = np.polynomial.legendre.leggauss(200)
    th = 0.5 * math.pi * x
    y = tap / 2 * np.sin(th)
    chord = np.sqrt(r_o**2 - y**2) - (p["rd"] - depth)
    hole = float(np.sum(w * 2.0 * (tap / 2) ** 2 * np.cos(th) ** 2 * chord) * 0.5 * math.pi)
    rho = get_material("aluminium-6061").density_kg_m3
    m_ref = (math.radians(p["span"]) / 2 * (r_o**2 - r_i**2) * p["th"] - 2 * hole - groove) * 1e-9 * rho
    assert volume_props_mm(kind.shape, eps=1e-9)[0] * 1e-9 * rho == pytest.approx(m_ref, rel=1e-9)
    # the build's mass properties are the grooved solid's (OCCT's default Gauss mode: ~1e-5 off
    # on the holes' B-spline faces, as the four-bar's drum)
    assert family.kind_mass_props(kind).mass_kg == pytest.approx(m_ref, rel=2e-5)
    assert "groove bottom" in kind.description and "turn the rope groove" in kind.process
