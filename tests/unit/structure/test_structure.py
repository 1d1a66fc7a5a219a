"""Structure: beam frame and finite elements against closed forms (Euler-Bernoulli,
Timoshenko cantilever, first bending mode), and the ``structure`` entry of a build report."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from cad.structure import fem
from cad.structure.frame import Frame, Section, rect_torsion_J

E, NU, RHO = 69e9, 0.33, 2700.0
G = E / (2 * (1 + NU))


def _section(w=10e-3, t=5e-3):
    return Section(A=w * t, Iz=t * w**3 / 12, Iy=w * t**3 / 12, J=rect_torsion_J(w, t),
                   cy=w / 2, cz=t / 2, t_torsion=min(w, t), E=E, G=G, rho=RHO)


def test_frame_cantilever_is_the_closed_form_in_both_planes():
    s = _section()
    fr = Frame()
    a, b = fr.node((0, 0)), fr.node((0.06, 0.08))  # 100 mm, oblique in the plane
    fr.element(a, b, s, "bar", n_sub=5)
    fr.fixed[a] = (0, 1, 2, 3, 4, 5)
    L = 0.1
    uz = fr.solve({b: np.r_[0, 0, 1.0, 0, 0, 0]})
    assert uz[6 * b + 2] == pytest.approx(L**3 / (3 * E * s.Iy), rel=1e-9)
    n = np.array([-0.8, 0.6])  # in-plane normal of the bar
    uy = fr.solve({b: np.r_[n[0], n[1], 0, 0, 0, 0]})
    assert uy[6 * b:6 * b + 2] @ n == pytest.approx(L**3 / (3 * E * s.Iz), rel=1e-9)
    # stress at the root: M c / I = P L (t/2) / Iy
    assert fr.element_stress_Pa(uz).max() == pytest.approx(L * s.cz / s.Iy, rel=1e-9)


def test_frame_first_mode_converges_to_the_closed_form():
    s = _section()
    fr = Frame()
    a, b = fr.node((0, 0)), fr.node((0.1, 0.0))
    fr.element(a, b, s, "bar", n_sub=24)
    fr.fixed[a] = (0, 1, 2, 3, 4, 5)
    ref = fem.euler_bernoulli_first_mode_Hz(0.1, E, s.Iy, RHO, s.A)
    assert fr.modes_Hz(1)[0] == pytest.approx(ref, rel=0.01)


@pytest.mark.parametrize("direction,inertia", [("z", 10e-3 * 5e-3**3 / 12), ("y", 5e-3 * 10e-3**3 / 12)])
def test_fem_cantilever_against_timoshenko(direction, inertia):
    g = fem.BarGeometry(100.0, 10.0, 5.0)
    c = fem.cantilever(g, E, NU, direction)
    ref = fem.timoshenko_tip_m_per_N(0.1, E, inertia, G, 5e-5)
    assert c == pytest.approx(ref, rel=0.006)


def test_fem_stubby_bar_needs_the_shear_term():
    """L / w = 2: Euler-Bernoulli misses the shear compliance, Timoshenko keeps it."""
    g = fem.BarGeometry(20.0, 10.0, 5.0)
    i_z, L = 5e-3 * 10e-3**3 / 12, 0.02
    c = fem.cantilever(g, E, NU, "y", (16, 4))
    assert c == pytest.approx(fem.timoshenko_tip_m_per_N(L, E, i_z, G, 5e-5), rel=0.04)
    assert c > 1.15 * fem.euler_bernoulli_tip_m_per_N(L, E, i_z)


def test_fem_first_mode_against_the_closed_form():
    g = fem.BarGeometry(100.0, 10.0, 5.0)
    ref = fem.euler_bernoulli_first_mode_Hz(0.1, E, 10e-3 * 5e-3**3 / 12, RHO, 5e-5)
    assert fem.first_mode_Hz(g, E, NU, RHO, "z") == pytest.approx(ref, rel=0.01)


def test_fem_slot_softens_the_bar_and_bad_geometry_is_refused():
    solid = fem.cantilever(fem.BarGeometry(62.5, 20.0, 6.0), E, NU, "y")
    slotted = fem.cantilever(fem.BarGeometry(62.5, 20.0, 6.0, 14.0, 11.0), E, NU, "y")
    assert slotted > 2 * solid  # two webs joined only at the ends (Vierendeel action)
    with pytest.raises(ValueError, match="slot_w_mm"):
        fem.BarGeometry(50, 10, 5, 12.0, 5.0).check()
    with pytest.raises(ValueError, match="L_mm"):
        fem.BarGeometry(0, 10, 5).check()


def test_structure_in_report_json_read_back(tmp_path):
    out = tmp_path / "b"
    r = subprocess.run(
        [sys.executable, "-m", "cad", "build", "designs/hoeken.toml", "--out", str(out),
         "--fidelity", "preview", "--formats", "dxf"],
        capture_output=True, text=True, cwd=Path(__file__).resolve().parents[3],
    )
    assert r.returncode == 0, r.stderr
    st = json.loads((out / "report.json").read_text())["structure"]
    assert set(st["compliance_um_per_N"]) == {"x", "z"}
    assert st["method"] == "fem"
    assert 0 < st["compliance_um_per_N"]["x"] < st["compliance_um_per_N"]["z"]
    assert 50 < st["first_mode_Hz"] < 2000 and 0 < st["max_stress_MPa"] < st["strength_MPa"]
    assert st["limits"]["first_mode_min_Hz"] == 150.0
    assert st["ok"] == (st["first_mode_Hz"] >= 150.0
                        and st["max_stress_MPa"] <= st["strength_MPa"] / 3)
    assert math.isfinite(st["handle_mode_x_Hz"])
    # the bearings' Palmgren estimate sits beside the FE numbers, not in them (docs/structure.md)
    est = st["bearing_compliance_estimate"]
    assert est["included_in_compliance_um_per_N"] is False and est["bearing"] == "M8-16-4"
    assert 0 < est["x_um_per_N"] < st["compliance_um_per_N"]["x"]


# ------------------------------------------- the link graph and the pantograph families
def test_plane_modes_of_a_cantilever_with_a_tip_mass_are_the_closed_forms():
    """A 100 mm beam (nearly massless) clamped at one end, 50 g at the other: the lowest
    in-plane mode sqrt(3 E Iz / (L^3 m)) / 2 pi, out of plane the same with Iy (w != t, so the
    two differ and the classification by kinetic energy must not swap them)."""
    from dataclasses import replace

    from cad.structure.graph import Beam, LinkGraph, Lumped, frame_at, plane_modes

    s = replace(_section(), rho=1e-2)  # beam 5e-8 kg: 1e-6 of the tip mass (1e-6 kg/m^3 ill-conditions eigh)
    g = LinkGraph({"bar": {"A": np.zeros(2), "B": np.array([100.0, 0.0])}}, [Beam("bar", "A", "B", s)],
                  fixed={("bar", "A"): (0, 1, 2, 3, 4, 5)}, handle=("bar", "B"))
    fr, _ = frame_at(g, {"bar": np.eye(3)}, [Lumped("bar", (100.0, 0.0), 0.050)])
    m = plane_modes(fr)
    L = 0.1
    # rel 1e-5: the eigensolver's round-off with sub-node masses 1e-9 of the tip mass
    assert m["in_plane_Hz"] == pytest.approx(math.sqrt(3 * E * s.Iz / (L**3 * 0.050)) / (2 * math.pi), rel=1e-5)
    assert m["out_of_plane_Hz"] == pytest.approx(math.sqrt(3 * E * s.Iy / (L**3 * 0.050)) / (2 * math.pi), rel=1e-5)


def _panto(name):
    from cad.design import load_design

    return load_design(Path(__file__).resolve().parents[3] / "designs" / name)


def test_pantograph_lumped_masses_keep_each_body_mass_and_first_moment():
    """The lever rule of :func:`cad.structure.pantograph.lumped_from_bodies`: each body's
    mass less its tube, at its two joints, with the body's first moment along the link."""
    from cad.structure import pantograph as sp

    d = _panto("pantograph.toml")
    g, lengths = sp.link_graph(d, sp.WEB_WIDTH_MIN_MM)
    bodies = {k: {"mass_kg": 0.025, "com_mm": [0.4 * L, 0.0, 0.0]} for k, L in lengths.items()}
    lumped = sp.lumped_from_bodies(g, bodies, lengths)
    for link, L in lengths.items():
        mine = [lp for lp in lumped if lp.link == link]
        mt = sp.tube_mass_kg(d, L)
        assert sum(lp.mass_kg for lp in mine) == pytest.approx(0.025 - mt)
        assert sum(lp.mass_kg * lp.xy_mm[0] for lp in mine) + mt * L / 2 == pytest.approx(0.025 * 0.4 * L)


def test_twin_pantograph_is_stiffer_than_its_knob_pantograph_alone():
    """The mouse's crank pantograph adds a parallel path to the main journal through the
    crankshaft: at home the handle compliance is at most the knob 5-bar's alone (the plain
    5-bar with the same links), strictly below it along y and out of plane; along x the two
    agree to round-off (1e-11 relative, either side with the BLAS threads: the crankshaft's
    path adds no support along x at home in this model)."""
    from cad.structure import pantograph as sp

    twin, plain = _panto("haptic_mouse.toml"), _panto("pantograph.toml")
    assert (twin.params["base_mm"], twin.params["proximal_mm"], twin.params["distal_mm"]) == (
        plain.params["base_mm"], plain.params["proximal_mm"], plain.params["distal_mm"])
    ct = sp.analyse(twin, {}, 1.0, sp.WEB_WIDTH_MIN_MM)["per_pose"]["home"]["compliance_um_per_N"]
    cp = sp.analyse(plain, {}, 1.0, sp.WEB_WIDTH_MIN_MM)["per_pose"]["home"]["compliance_um_per_N"]
    assert ct["y"] < cp["y"] and ct["z"] < cp["z"]
    assert ct["x"] == pytest.approx(cp["x"], rel=1e-9)


def test_pantograph_datasheet_rows_state_boundaries_and_warn_below_the_mode_limit():
    """The 5-bar's structure rows (no build: bodies given): every structural row states motors
    held; first_mode_Hz is the lower of the in-plane and out-of-plane modes and is judged
    against FIRST_MODE_MIN_HZ, the stress against the tube's strength / 3; a miss is a warning
    line naming the keys to change."""
    from cad.datasheet import datasheet
    from cad.datasheet.limits import FIRST_MODE_MIN_HZ
    from cad.structure import pantograph as sp
    from cad.structure.elastic import get_elastic

    d = _panto("pantograph.toml")
    _, lengths = sp.link_graph(d, sp.WEB_WIDTH_MIN_MM)
    bodies = {k: {"mass_kg": 0.025, "com_mm": [L / 2, 0.0, 0.0]} for k, L in lengths.items()}
    bodies["handle"] = {"mass_kg": 0.015, "com_mm": [0.0, 0.0, 0.0]}
    ds = datasheet(d, {"bodies": bodies}, simulate_wall=False)
    rows = {r["key"]: r for r in ds["rows"]}
    keys = ("first_mode_Hz", "first_mode_in_plane_Hz", "first_mode_out_of_plane_Hz", "compliance_x_um_per_N",
            "compliance_y_um_per_N", "compliance_z_um_per_N", "max_stress_MPa")
    assert all("motors held" in rows[k]["boundary"] for k in keys)
    f1 = rows["first_mode_Hz"]["value"]
    assert f1 == min(rows["first_mode_in_plane_Hz"]["value"], rows["first_mode_out_of_plane_Hz"]["value"])
    assert rows["first_mode_Hz"]["limit"]["value"] == FIRST_MODE_MIN_HZ
    assert rows["max_stress_MPa"]["limit"]["value"] == pytest.approx(get_elastic(d.parts.tube_material).strength_MPa / 3)
    assert rows["first_mode_Hz"]["verdict"] == ("ok" if f1 >= FIRST_MODE_MIN_HZ else "miss")
    assert (f1 < FIRST_MODE_MIN_HZ) == any(w.startswith("first structural mode") and "parts.tube_od_mm" in w
                                           for w in ds["warnings"])
