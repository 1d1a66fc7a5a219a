"""Joint hardware from the catalog tables: bearings from 3 mm bore, plain pins with
DIN 471 rings, pin materials; fit against catalog numbers, masses against closed forms."""

from __future__ import annotations

import math

import pytest

from cad.data import catalog as cat
from cad.design.parts import parse_parts
from cad.errors import DesignError

# bd_warehouse din471.csv rows (shaft d1: thickness s, fitted outside d4) and SKT masses
DIN471 = {3.0: (0.4, 7.0), 4.0: (0.4, 8.6), 5.0: (0.6, 10.2), 6.0: (0.7, 11.7), 8.0: (0.8, 14.7)}
SKT = {"M3-10-4": ("623", 3, 10, 4, 1.5), "M4-9-2.5": ("618/4", 4, 9, 2.5, 0.7),
       "M5-11-3": ("618/5", 5, 11, 3, None), "M6-13-3.5": ("618/6", 6, 13, 3.5, None),
       "M8-16-4": ("618/8", 8, 16, 4, None)}


@pytest.mark.parametrize("d", cat.DOWEL_DIAMETERS_MM)
def test_plain_pin_family_fits_a_bearing_and_has_catalog_length(d):
    size = f"dowel-{d:g}"
    pin = cat.get_shoulder_screw(size)
    assert pin.ds_mm == d and pin.thread_mm == d
    ring = cat.get_retaining_ring(d)
    assert (ring.s_mm, ring.d4_mm) == DIN471[d]
    assert cat.get_nut(size).m_mm == ring.s_mm
    assert cat.get_washer(size).d1_mm > d  # ISO 7089 hole clears the pin
    fits = cat.bearings_with_bore(d)
    assert fits and all(cat.get_bearing(b).d_mm == d for b in fits)
    for L in pin.lengths_mm[:5]:
        assert round(cat.dowel_total_length_mm(size, L), 6) in cat.ISO2338_LENGTHS_MM
    p = parse_parts({"pin": size, "bearing": fits[0], "bar_thickness_mm": 8.0, "bar_width_mm": 24.0})
    assert p.pin == size


@pytest.mark.parametrize("size", list(SKT))
def test_small_bearings_are_the_skt_table(size):
    des, d, D, B, mass_g = SKT[size]
    b = cat.get_bearing(size)
    assert (b.designation, b.d_mm, b.D_mm, b.B_mm) == (des, d, D, B)
    if mass_g is not None:
        assert b.mass_kg * 1e3 == pytest.approx(mass_g)
    assert size in cat.bearings_with_bore(d)


def test_mismatch_lists_the_sizes_that_fit():
    with pytest.raises(DesignError) as e:
        parse_parts({"bearing": "M3-10-4", "pin": "M6-1"})
    msg = str(e.value)
    assert "parts.pin" in msg and "M8-16-4" in msg and "dowel-3" in msg
    with pytest.raises(DesignError, match="dowel-3, dowel-4"):
        parse_parts({"pin": "dowel-7"})


def test_pin_material_is_a_design_key():
    p = parse_parts({"pin": "dowel-3", "bearing": "M3-10-4", "pin_material": "titanium-6al4v"})
    assert p.pin_material == "titanium-6al4v"
    with pytest.raises(DesignError, match="parts.pin_material"):
        parse_parts({"pin_material": "unobtainium"})


@pytest.mark.parametrize("material", ["steel-1018", "aluminium-7075"])
def test_pin_solid_mass_is_the_closed_form(material):
    """Pin cylinder (k + L + b) times the density: its rings are parts of their own."""
    from cad.data.materials import get_material
    from cad.massprops.occt import solid_mass_props
    from cad.parts.joints import shoulder_screw_shape

    size, L = "dowel-3", cat.get_shoulder_screw("dowel-3").lengths_mm[3]
    rho = get_material(material).density_kg_m3
    mp = solid_mass_props(shoulder_screw_shape(size, L), rho)
    vol = math.pi / 4 * 3.0**2 * cat.dowel_total_length_mm(size, L)
    assert mp.mass_kg == pytest.approx(vol * 1e-9 * rho, rel=1e-6)
    assert "ISO 2338 3 m6 x" in cat.pin_description(size, L)


def test_sleeve_lets_a_thinner_pin_carry_the_bearing():
    with pytest.raises(DesignError, match="pin_sleeve_material"):
        parse_parts({"bearing": "M5-11-3", "pin": "dowel-3"})
    with pytest.raises(DesignError, match="parts.pin_sleeve_material: .* -1 mm wall"):
        parse_parts({"bearing": "M3-10-4", "pin": "dowel-5", "pin_sleeve_material": "brass-360"})
    p = parse_parts({"bearing": "M5-11-3", "pin": "dowel-3", "pin_sleeve_material": "brass-360"})
    assert p.pin_sleeve_material == "brass-360"


def test_sleeve_part_mass_is_the_closed_form():
    """A sleeved design's parts: each joint gets a sleeve ds..d x B, mass of the annulus."""
    from pathlib import Path

    from cad.data.materials import get_material
    from cad.design import parse_design
    from cad.families.fourbar.inertia import inertia_model

    raw = {"name": "sleeved", "mechanism": {"family": "hoeken", "stroke_mm": 50.0},
           "parts": {"bearing": "M5-11-3", "pin": "dowel-3", "pin_sleeve_material": "brass-360",
                     "bar_material": "carbon-fibre", "bar_thickness_mm": 5.0, "bar_width_mm": 14.0,
                     "bar_end_radius_mm": 10.0, "handle_screw": "M3-0.5",
                     "hub_shaft_engagement_min_mm": 5.0}}
    rep = inertia_model(parse_design(raw, str(Path("sleeved.toml"))))
    rows = [r for r in rep["budget"] if r["part"].startswith("sleeve_")]
    # A4's pin and sleeve ride on the ground post: only the moving joints are in the budget
    assert sorted(r["part"] for r in rows) == ["sleeve_A2", "sleeve_A3"]
    expect_g = math.pi / 4 * (5.0**2 - 3.0**2) * 3.0 * 1e-9 * get_material("brass-360").density_kg_m3 * 1e3
    for r in rows:
        assert r["mass_g"] == pytest.approx(expect_g, rel=1e-6)
