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
