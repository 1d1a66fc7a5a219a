"""The capstan transmission's solids and their placement geometry (issue 35) against
independent references: the annular sector's area and centroid in closed form, the capstan's
tube minus a radial hole (the hole's volume by quadrature of its chord lengths), the rope run's
cylinder, and the rope's tangent points against the homothety construction of two circles'
external tangents."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from cad.actuators import capstan as cap
from cad.actuators import capstan_geometry as cg
from cad.data.catalog import tap_drill_mm
from cad.data.materials import get_material
from cad.errors import DesignError
from tests.capstan_ref import section_profile

RHO_AL = get_material("aluminium-6061").density_kg_m3
RHO_ST = get_material("steel-1018").density_kg_m3


def _props(shape):
    from cad.massprops.occt import volume_props_mm

    return volume_props_mm(shape)


# ----------------------------------------------------------------------------- masses
@pytest.mark.parametrize("start, span, r_o, r_i, t", [
    (-120.0, 240.0, 31.6, 4.0, 10.0),   # the bundled capstan Hoeken's drum (64 mm pitch, 0.8 mm rope)
    (10.0, 75.0, 59.7, 6.5, 6.0),       # a narrow sector
])
def test_drum_sector_mass_and_centroid_closed_form(start, span, r_o, r_i, t):
    from cad.parts.capstan import drum_sector_shape

    vol, com, _ = _props(drum_sector_shape(r_o, r_i, start, span, t))
    m_ref = cg.sector_mass_kg(span, r_o, r_i, t, RHO_AL)
    assert vol * 1e-9 * RHO_AL == pytest.approx(m_ref, rel=1e-9)
    # centroid of an annular sector on its bisector: (2/3)(r_o^3 - r_i^3)/(r_o^2 - r_i^2) sin(h)/h
    h = math.radians(span) / 2
    rbar = 2.0 / 3.0 * (r_o ** 3 - r_i ** 3) / (r_o ** 2 - r_i ** 2) * math.sin(h) / h
    mid = math.radians(start + span / 2)
    np.testing.assert_allclose(com, [rbar * math.cos(mid), rbar * math.sin(mid), t / 2], atol=1e-9)


def _radial_hole_volume_mm3(r_hole, r_in, r_out):
    """A radial hole of radius r_hole through a tube wall r_in..r_out (axes perpendicular): the
    integral over the hole's cross-section of the chord lengths sqrt(r_o^2 - y^2) - sqrt(r_i^2 - y^2)
    (y across the hole, in the tube's cross-section plane), Gauss-Legendre in theta with
    y = r_hole sin(theta) (smooth integrand: width dy = 2 r_hole^2 cos^2(theta) dtheta)."""
    x, w = np.polynomial.legendre.leggauss(200)
    th = 0.5 * math.pi * x
    y = r_hole * np.sin(th)
    chord = np.sqrt(r_out ** 2 - y ** 2) - np.sqrt(r_in ** 2 - y ** 2)
    return float(np.sum(w * 2.0 * r_hole ** 2 * np.cos(th) ** 2 * chord) * 0.5 * math.pi)


def test_capstan_mass_is_tube_minus_set_screw_hole():
    from cad.parts.capstan import capstan_shape

    r_o, bore, L, z = cg.rim_radius_mm(32.0, 0.8), 6.0, 11.6, 4.0
    vol, com, inertia = _props(capstan_shape(r_o, bore, L, z))
    hole = _radial_hole_volume_mm3(tap_drill_mm("M3-0.5") / 2, bore / 2, r_o)
    tube = cg.tube_mass_kg(r_o, bore / 2, L, 1e9)  # mm^3 at unit density
    # OCCT's default Gauss mode is off by 3e-4 of the hole on its B-spline faces (2e-6 of the
    # part); its adaptive mode matches the quadrature
    assert vol == pytest.approx(tube - hole, rel=1e-5)
    from cad.massprops.occt import volume_props_mm

    exact = volume_props_mm(capstan_shape(r_o, bore, L, z), eps=1e-9)[0]
    assert exact == pytest.approx(tube - hole, rel=1e-9)
    # the hole moves the centroid to -x; the tube alone is centred on its axis
    assert com[0] < 0 and abs(com[1]) < 1e-6 and com[2] == pytest.approx(
        (tube * L / 2 - hole * z) / (tube - hole), rel=1e-5)
    # Izz of the tube (closed form) bounds the drilled capstan's from above
    assert inertia[2, 2] < cg.tube_izz_kg_m2(tube, r_o, bore / 2) * 1e6


def test_rope_run_is_a_cylinder_between_its_end_points():
    from cad.parts.capstan import rope_run_shape

    p0, p1 = np.array([3.0, -4.0, 2.0]), np.array([40.0, 25.0, 2.5])
    vol, com, _ = _props(rope_run_shape(p0, p1, 0.8))
    assert vol == pytest.approx(math.pi * 0.4 ** 2 * np.linalg.norm(p1 - p0), rel=1e-12)
    np.testing.assert_allclose(com, (p0 + p1) / 2, atol=1e-9)


# ----------------------------------------------------------------------------- tangents
def _homothety_tangent_points(c1, r1, c2, r2):
    """Tangent points of the external tangents by the external homothetic centre
    H = (r1 c2 - r2 c1) / (r1 - r2): from H, the tangents to a circle (c, r) touch it at
    c + (r^2 / |H - c|) w +- r sqrt(1 - r^2 / |H - c|^2) w_perp, w = (H - c) / |H - c|."""
    H = (r1 * c2 - r2 * c1) / (r1 - r2)
    pts = []
    for c, r in ((c1, r1), (c2, r2)):
        e = H - c
        dist = np.linalg.norm(e)
        w, wp = e / dist, np.array([-e[1], e[0]]) / dist
        a, b = r * r / dist, r * math.sqrt(1 - (r / dist) ** 2)
        pts.append({tuple(np.round(c + a * w + s * b * wp, 9)) for s in (1, -1)})
    return pts


@pytest.mark.parametrize("seed", range(5))
def test_tangent_points_match_the_homothety_construction(seed):
    rng = np.random.default_rng(seed)
    c1, c2 = rng.uniform(-50, 50, 2), rng.uniform(-50, 50, 2)
    D = np.linalg.norm(c2 - c1)
    r1 = rng.uniform(0.3, 0.9) * D
    r2 = rng.uniform(0.05, 0.9) * r1
    got = cg.external_tangent_points_mm(c1, r1, c2, r2)
    ref1, ref2 = _homothety_tangent_points(c1, r1, c2, r2)
    assert {tuple(np.round(p, 9)) for p in got[:, 0]} == ref1
    assert {tuple(np.round(p, 9)) for p in got[:, 1]} == ref2
    # each free run has the open-belt length of the transmission model
    L = np.linalg.norm(got[:, 1] - got[:, 0], axis=1)
    np.testing.assert_allclose(L, cap.free_run_length_mm(2 * r2, 2 * r1, D), rtol=1e-12)


def test_tangent_points_equal_radii_and_nested_circles():
    got = cg.external_tangent_points_mm((0, 0), 5.0, (20, 0), 5.0)
    np.testing.assert_allclose(got, [[[0, 5], [20, 5]], [[0, -5], [20, -5]]], atol=1e-12)
    with pytest.raises(ValueError, match="no external tangent"):
        cg.external_tangent_points_mm((0, 0), 10.0, (2, 0), 5.0)


# ----------------------------------------------------------------------------- layout
def test_too_short_centre_distance_is_refused_in_one_line():
    C = cg.check_centre_distance(50.0, 32.0, 64.0, 0.8, 2.0)
    assert C == 50.0
    with pytest.raises(DesignError) as e:
        cg.check_centre_distance(45.0, 32.0, 64.0, 0.8, 2.0)
    msg = str(e.value)
    assert "\n" not in msg and msg.startswith("transmission.centre_distance_mm: 45 mm")
    assert "rims overlap by 2.2 mm" in msg and "at least 50.00 mm" in msg


def test_drum_arc_covers_both_tangent_points_over_the_range():
    dd, dc, C = 64.0, 32.0, 50.0
    g = cg.tangent_half_angle_rad(dd, dc, C)
    assert math.cos(g) == pytest.approx(16.0 / 50.0)
    anchor = math.degrees(2 * 10.0 / dd)
    start, span = cg.drum_arc_link_deg(-90.0, g, 30.0, 110.0, anchor)
    # the model's rope arc (range + 2 anchors) plus the 2 gamma facing the capstan
    assert span == pytest.approx(cap.drum_sector_needed_deg(80.0, dd, 10.0) + 2 * math.degrees(g))
    for q in np.linspace(30.0, 110.0, 41):
        for tp in (-90.0 + math.degrees(g) - q, -90.0 - math.degrees(g) - q):
            rel = (tp - start) % 360.0
            assert anchor - 1e-9 <= rel <= span - anchor + 1e-9


# ----------------------------------------------------------------------------- the design key
CAPSTAN_HOEKEN = {"kind": "capstan", "capstan_diameter_mm": 32.0, "drum_diameter_mm": 64.0,
                  "cable": "steel-7x7-0.8", "wraps": 3.0}


def test_centre_distance_key_sets_the_runs_and_is_refused_when_the_pitch_circles_overlap():
    from cad.design.transmission import parse_transmission

    t = parse_transmission({**CAPSTAN_HOEKEN, "centre_distance_mm": 60.0})
    assert t.centre_distance_mm == 60.0
    # run length sqrt(C^2 - (r_d - r_c)^2) = sqrt(3600 - 256)
    assert cap.free_run_length_mm(32.0, 64.0, cap.centre_distance_mm(32.0, 64.0, 60.0)) == \
        pytest.approx(math.sqrt(3344.0))
    assert cap.centre_distance_mm(32.0, 64.0) == 50.0  # r_d + r_c + CAPSTAN_GAP_MM (2 mm)
    with pytest.raises(DesignError) as e:
        parse_transmission({**CAPSTAN_HOEKEN, "centre_distance_mm": 47.0})
    msg = str(e.value)
    assert "\n" not in msg and msg.startswith("transmission.centre_distance_mm: 47 mm")
    assert "rims overlap by 0.2 mm" in msg and "at least 48.00 mm" in msg


def test_too_short_centre_distance_refused_by_the_cli_in_one_line(tmp_path):
    from tests.cli_helpers import assert_one_line_error, hapticad

    src = (Path(__file__).resolve().parents[3] / "designs" / "hoeken_capstan.toml").read_text()
    bad = tmp_path / "short.toml"
    bad.write_text(src.replace('centre_distance_mm = 85.0', 'centre_distance_mm = 40.0'))
    code, _, err = hapticad("check", str(bad))
    assert_one_line_error(code, err, "transmission.centre_distance_mm: 40 mm",
                          "rims overlap by 7.2 mm", "use at least 48.00 mm")


# ----------------------------------------------------------------------------- rope grooves
def test_capstan_groove_pitch_depth_and_volume_from_the_solid():
    """The helical groove measured back from the solid: in a meridian half-plane the outline
    dips to the groove's bottom (the drawn rim, (32 - 0.8) / 2 = 15.6 mm) once per turn, the dips
    1.5 d = 1.2 mm apart and 0.35 d = 0.28 mm below the crests; the volume it removes (OCCT,
    adaptive) is the section's area times the helix its centroid runs on (closed form: the
    circular segment r^2 (a - sin a cos a), centroid 4 r sin^3 a / (3 (2a - sin 2a)))."""
    from cad.parts.capstan import capstan_shape

    d, wraps, bore = 0.8, 4.0, 6.0
    rc, L = (32.0 - d) / 2, 1.5 * d * wraps + 8.0
    grooved = capstan_shape(rc, bore, L, 4.0, "M3-0.5", rope_diameter_mm=d, wraps=wraps)
    plain = capstan_shape(rc + 0.28, bore, L, 4.0, "M3-0.5")
    zx = section_profile(grooved, 180.0)  # at 180 deg: the helix starts and ends at 0 deg
    outer = zx[zx[:, 1] > rc - 0.01]
    assert outer[:, 1].max() == pytest.approx(rc + 0.28, abs=1e-6)
    assert outer[:, 1].min() == pytest.approx(rc, abs=3e-3)  # the bottom of the groove, to the mesh
    bottoms = np.sort(outer[outer[:, 1] < rc + 0.01][:, 0])
    centres = [grp.mean() for grp in np.split(bottoms, np.where(np.diff(bottoms) > 0.3)[0] + 1)]
    assert len(centres) == wraps
    np.testing.assert_allclose(np.diff(centres), 1.5 * d, atol=5e-3)
    # the closed form by hand: the segment of the 0.4 mm circle 0.28 mm deep
    r, h = d / 2, 0.28
    a = math.acos((r - h) / r)
    area = r * r * (a - math.sin(a) * math.cos(a))
    rbar = 32.0 / 2 - 4 * r * math.sin(a) ** 3 / (3 * (2 * a - math.sin(2 * a)))
    helix = wraps * math.hypot(2 * math.pi * rbar, 1.5 * d)
    removed = _props_exact(plain)[0] - _props_exact(grooved)[0]
    assert removed == pytest.approx(area * helix, rel=1e-4)
    assert cg.helix_groove_volume_mm3(32.0, d, wraps) == pytest.approx(area * helix, rel=1e-12)
    assert cg.groove_section_moment(32.0, d, 0) == pytest.approx(area, rel=1e-12)


def test_capstan_closed_form_inertia_is_its_grooved_solids():
    """J_c of the device (:func:`capstan_izz_kg_m2`: tube to the crests less the helical groove)
    against the grooved solid's Izz (OCCT, adaptive), the set screw's hole added back by hand
    (rho pi r_h^2 int r^2 dr from the bore to the crests)."""
    from cad.parts.capstan import capstan_shape

    d, wraps, bore, dc = 0.8, 4.0, 6.0, 32.0
    rc = (dc - d) / 2
    s = capstan_shape(rc, bore, 1.5 * d * wraps + 8.0, 4.0, "M3-0.5", rope_diameter_mm=d, wraps=wraps)
    izz_solid = _props_exact(s)[2][2, 2] * RHO_ST * 1e-15
    r_h = tap_drill_mm("M3-0.5") / 2
    hole = RHO_ST * math.pi * r_h ** 2 * ((rc + 0.28) ** 3 - (bore / 2) ** 3) / 3 * 1e-15
    assert cg.capstan_izz_kg_m2(dc, d, wraps, bore, RHO_ST) - hole == pytest.approx(izz_solid, rel=2e-4)


def test_drum_groove_depth_and_volume_from_the_solid():
    """The drum's groove: the sector's outline at its mid-angle dips from the crests (31.6 + 0.28
    mm) to the groove's bottom (31.6 mm) at mid-thickness, the groove as wide as the chord of the
    0.4 mm circle at the crests, 2 sqrt(2 r h - h^2); its volume Pappus's over the groove's arc."""
    from cad.parts.capstan import drum_sector_shape

    d = 0.8
    grooved = drum_sector_shape(31.6, 4.0, -90.0, 180.0, 10.0, rope_diameter_mm=d, groove_arc_deg=(-80.0, 160.0))
    plain = drum_sector_shape(31.88, 4.0, -90.0, 180.0, 10.0)
    zx = section_profile(grooved)  # the half-plane at 0 deg, mid-arc
    outer = zx[zx[:, 1] > 31.5]
    assert outer[:, 1].max() == pytest.approx(31.88, abs=1e-6)
    assert outer[:, 1].min() == pytest.approx(31.6, abs=3e-3)
    low = outer[outer[:, 1] < 31.88 - 1e-6][:, 0]
    assert low.mean() == pytest.approx(5.0, abs=1e-3)
    crest = outer[np.abs(outer[:, 1] - 31.88) < 1e-6][:, 0]
    width = crest[crest > 5.0].min() - crest[crest < 5.0].max()  # between the groove's edges
    assert width == pytest.approx(2 * math.sqrt(2 * 0.4 * 0.28 - 0.28 ** 2), abs=1e-6)
    removed = _props_exact(plain)[0] - _props_exact(grooved)[0]
    assert removed == pytest.approx(cg.ring_groove_volume_mm3(64.0, d, 160.0), rel=1e-8)


def _props_exact(shape):
    from cad.massprops.occt import volume_props_mm

    return volume_props_mm(shape, eps=1e-9)
