"""Tube bars (``[parts] bar_style = "tube"``): carbon tube bonded into aluminium clevises.

References: the tube's mass and inertia from the closed forms of a hollow cylinder, the
clevis volume from its primitives (half disc + block - bore - socket - seat counterbore),
the tube beam's tip compliance from Euler-Bernoulli PL^3 / (3 E I) with
I = pi (D^4 - d^4) / 64, and a tube-style Hoeken's assembly.step read back with OCCT's
XCAF reader and every pair of parts intersected (``tests/step_pairs.py``).
"""

from __future__ import annotations

import csv
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from step_pairs import clashes

from cad.data.materials import get_material
from cad.design.parts import parse_parts
from cad.errors import DesignError

ROOT = Path(__file__).resolve().parents[3]
TUBE = {"bar_style": "tube", "bar_thickness_mm": 8.0, "tube_od_mm": 6.0, "tube_id_mm": 4.0}
DESIGN = """name = "hoeken_tube"
[mechanism]
family = "hoeken"
force_N = 5.0
stroke_mm = 110.0
[parts]
bar_style = "tube"
bar_thickness_mm = 8.0
tube_od_mm = 6.0
tube_id_mm = 4.0
fidelity = "inertia"
interference_poses = 8
"""


def _props(shape, material):
    from cad.massprops.occt import cached_solid_mass_props

    return cached_solid_mass_props(shape, get_material(material).density_kg_m3)


def test_tube_mass_and_inertia_match_the_hollow_cylinder():
    from cad.parts import tubebars as tb

    parts = parse_parts(TUBE)
    L = 60.0
    mp = _props(tb.tube_shape(L, parts), parts.tube_material)
    rho = get_material(parts.tube_material).density_kg_m3
    R, r, Lm = 3e-3, 2e-3, L * 1e-3
    m = rho * math.pi * (R**2 - r**2) * Lm
    assert mp.mass_kg == pytest.approx(m, rel=1e-6)
    inertia = mp.inertia_com_kg_m2
    assert inertia[0, 0] == pytest.approx(m * (R**2 + r**2) / 2, rel=1e-6)  # about the tube axis x
    assert inertia[1, 1] == pytest.approx(m * (3 * (R**2 + r**2) + Lm**2) / 12, rel=1e-6)
    assert np.asarray(mp.com_m)[0] == pytest.approx(Lm / 2, rel=1e-9)


def test_clevis_volume_matches_its_primitives():
    """Seat clevis (one socket) and a two-socket pin clevis against their closed-form volumes."""
    from cad.parts import bars
    from cad.parts import tubebars as tb

    parts = parse_parts(TUBE)
    rho = get_material(parts.clevis_material).density_kg_m3
    t, w, Lc, sd = 8.0, 20.0, parts.clevis_length_mm, parts.socket_depth_mm
    ds = parts.tube_od_mm + 2 * tb.BOND_GAP_MM
    arm = t * (math.pi * (w / 2) ** 2 / 2 + Lc * w) - math.pi * ds**2 / 4 * sd  # one socketed arm
    seat = bars.Feature("seat", d_mm=13.0, cb_d_mm=16.0, cb_depth_mm=4.0)
    v_seat = arm - math.pi * 13.0**2 / 4 * t - math.pi * (16.0**2 - 13.0**2) / 4 * 4.0
    mp = _props(tb.clevis_shape(seat, (30.0,), parts), parts.clevis_material)
    assert mp.mass_kg == pytest.approx(v_seat * 1e-9 * rho, rel=1e-6)
    pin = bars.Feature("pin", d_mm=8.0)
    # two opposite arms: their blocks cover both half discs -> a 2 Lc x w block
    v_pin = 2 * Lc * w * t - 2 * math.pi * ds**2 / 4 * sd - math.pi * 8.0**2 / 4 * t
    mp2 = _props(tb.clevis_shape(pin, (0.0, 180.0), parts), parts.clevis_material)
    assert mp2.mass_kg == pytest.approx(v_pin * 1e-9 * rho, rel=1e-6)
    # symmetric two-socket clevis: COM on the joint axis, at mid-height
    assert np.allclose(np.asarray(mp2.com_m), [0, 0, t / 2 * 1e-3], atol=1e-9)


def test_tube_cantilever_compliance_is_the_beam_closed_form():
    from cad.structure.device import tube_section
    from cad.structure.elastic import get_elastic
    from cad.structure.frame import Frame

    parts = parse_parts(TUBE)
    el = get_elastic(parts.tube_material)
    fr = Frame()
    a, b = fr.node((0.0, 0.0)), fr.node((0.08, 0.0))
    fr.element(a, b, tube_section(parts, el.E_Pa, el.G_Pa, 1600.0), "rocker", n_sub=4)
    fr.fixed[a] = (0, 1, 2, 3, 4, 5)
    uy = fr.solve({b: np.r_[0, 1.0, 0, 0, 0, 0]})[6 * b + 1]
    uz = fr.solve({b: np.r_[0, 0, 1.0, 0, 0, 0]})[6 * b + 2]
    i_m4 = math.pi * (6e-3**4 - 4e-3**4) / 64
    c = 0.08**3 / (3 * el.E_Pa * i_m4)
    assert uy == pytest.approx(c, rel=1e-9)
    assert uz == pytest.approx(c, rel=1e-9)


@pytest.mark.parametrize(
    "table, field",
    [
        ({**TUBE, "bar_style": "rod"}, "parts.bar_style"),
        ({**TUBE, "tube_id_mm": 6.0}, "parts.tube_id_mm"),
        ({**TUBE, "tube_od_mm": 7.0}, "parts.tube_od_mm"),
        ({**TUBE, "socket_depth_mm": 15.0}, "parts.socket_depth_mm"),
    ],
)
def test_bad_tube_keys_name_the_field(table, field):
    with pytest.raises(DesignError) as e:
        parse_parts(table)
    assert field in str(e.value)


@pytest.fixture(scope="module")
def tube_build(tmp_path_factory):
    d = tmp_path_factory.mktemp("tube")
    (d / "hoeken_tube.toml").write_text(DESIGN)
    out = d / "out"
    r = subprocess.run(
        [sys.executable, "-m", "cad", "build", str(d / "hoeken_tube.toml"), "--out", str(out),
         "--formats", "step", "--json"],
        capture_output=True, text=True, cwd=ROOT,
    )
    assert r.returncode == 0, r.stderr[-2000:]
    return out


def test_tube_hoeken_step_has_no_overlapping_pair(tube_build):
    import json

    rep = json.loads((tube_build / "report.json").read_text())
    assert rep["overlap_volume_mm3"] == 0.0
    assert rep["structure"]["compliance_um_per_N"]["x"] > 0
    assert clashes(tube_build / "assembly.step") == []


def test_tube_hoeken_bom_lists_tubes_and_bonded_clevises(tube_build):
    with (tube_build / "bom.csv").open(newline="") as fh:
        rows = {r["part"]: r for r in csv.DictReader(fh)}
    tubes = [p for p in rows if "_tube_" in p]
    clevises = [p for p in rows if "_clevis_" in p]
    assert sorted(tubes) == ["coupler_tube_A2A3", "coupler_tube_A3P", "crank_tube_A1A2",
                             "rocker_tube_A4A3"], tubes
    assert len(clevises) == 7, clevises  # 2 crank + 3 coupler + 2 rocker
    for p in tubes + clevises:
        assert "bond" in rows[p]["process"], rows[p]
    assert all(rows[p]["material"] == "carbon-fibre" for p in tubes)
    assert not any(p in rows for p in ("crank", "coupler", "rocker"))  # no plate bars


def test_cheap_tube_model_against_the_exact_solids(tube_build):
    """The optimizer's cheap tube-bar model (``cad/studies/codesign/cheap.py``) against the solids'
    M11 max of the same design (build report) -- docs/codesign.md: -0.4 % on this Hoeken."""
    import json

    from cad.api import load_design
    from cad.studies.codesign import cheap

    rep = json.loads((tube_build / "report.json").read_text())
    exact = rep["apparent_mass"]["M11_max_g"]
    est = cheap.apparent_mass(load_design(tube_build.parent / "hoeken_tube.toml"))["M11_max_g"]
    assert abs(est - exact) / exact < 0.05


def test_optimizer_searches_stock_tubes_when_the_brief_asks(tmp_path):
    """A brief with ``bar_style = "tube"``: every feasible candidate is a stock tube in a
    clevis that holds it with 1 mm walls and whose socket clears the joint features; its
    parts table parses and the tube check passes on its linkage."""
    from dataclasses import replace

    from cad.api import load_design
    from cad.data import catalog as cat
    from cad.kinematics.linkgeom import link_joints_mm
    from cad.studies.codesign import cheap, search

    p = tmp_path / "brief.toml"
    p.write_text(DESIGN.replace("force_N = 5.0", "force_N = 1.5").replace("stroke_mm = 110.0", "stroke_mm = 150.0")
                 + "[targets]\ndy_max_mm = { max = 0.5 }\nfirst_mode_Hz = { min = 40.0 }\n")
    d = load_design(p)
    pb = search.problem_from(d)
    pb.fixed_parts = search.fixed_parts(d)
    assert pb.fixed_parts["bar_style"] == "tube"
    cands, records = search.run(pb, 16, seed=0)
    assert len(records) == 16 and cands
    for c in cands:
        ps = parse_parts(c.parts)
        assert ps.bar_style == "tube"
        assert (ps.tube_od_mm, ps.tube_id_mm) in search.TUBE_STOCK_MM
        assert ps.tube_od_mm + 2.0 <= ps.bar_thickness_mm
        assert ps.clevis_length_mm - ps.socket_depth_mm >= cat.get_bearing(ps.bearing).D_mm / 2 + 1.0
        # the cheap model of the candidate is the tube model, not the plate one
        J = link_joints_mm(replace(d, parts=ps).linkage)
        a, b = cheap.bar_props(ps, J, "rocker"), cheap.tube_bar_props(ps, J, "rocker")
        assert a[0] == b[0] and a[2] == b[2]
