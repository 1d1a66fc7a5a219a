"""Shared inputs of the identification tests: the bundled Hoeken design and its prediction
with the Hoeken paper's published inertia coefficients (§III.B.2, the design's [targets]):
no CAD build, so every test runs in seconds."""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]


@pytest.fixture(scope="session")
def hoeken():
    from cad.design import load_design

    return load_design(ROOT / "designs" / "hoeken.toml")


@pytest.fixture(scope="session")
def paper_H():
    """H11..H33 of the Hoeken paper (§III.B.2, kg m^2), beta2 = 0."""
    from cad.dynamics.inertia import InertiaCoefficients

    return InertiaCoefficients(2.97e-5, 3.22e-5, 1.17e-4, 7.09e-5, 0.0)


@pytest.fixture(scope="session")
def pred(hoeken, paper_H):
    from cad.sim.identify_device import predict

    return predict(hoeken, paper_H)


def bar_report(design, handle_kg: float = 0.015, rho_kg_per_m: float = 0.2) -> dict:
    """report.json ``bodies`` of a 5-bar made of uniform bars (closed form: mass rho*l, COM at
    l/2 on the link's x axis -- the distal links 3 and 1 mm off it, bars with a boss --, Izz =
    m l^2/12 about the COM; ``rho_kg_per_m`` per metre) and a handle of ``handle_kg``: the prediction without a CAD build."""
    m = design.mechanism
    rho = rho_kg_per_m  # 0.2 kg/m: a 10 x 8 mm aluminium bar
    bodies = {}
    for name, l_mm, cy in (("proximal_left", m.proximal_left_mm, 0.0), ("proximal_right", m.proximal_right_mm, 0.0),
                           ("distal_left", m.distal_left_mm, 3.0), ("distal_right", m.distal_right_mm, 1.0)):
        mass = rho * l_mm * 1e-3
        izz = mass * (l_mm * 1e-3) ** 2 / 12  # about the COM
        bodies[name] = {"mass_kg": mass, "com_mm": [l_mm / 2, cy, 0.0],
                        "inertia_com_kg_m2": [[0, 0, 0], [0, 0, 0], [0, 0, izz]]}
    bodies["handle"] = {"mass_kg": handle_kg, "com_mm": [0.0, 0.0, 20.0],
                        "inertia_com_kg_m2": [[0, 0, 0], [0, 0, 0], [0, 0, 1e-7]]}
    return {"name": design.name, "bodies": bodies}


@pytest.fixture(scope="session")
def bars():
    """:func:`bar_report` (a fixture: test modules do not import the conftest)."""
    return bar_report


@pytest.fixture(scope="session")
def panto():
    from cad.design import load_design

    return load_design(ROOT / "designs" / "pantograph.toml")


@pytest.fixture(scope="session")
def panto_pred(panto):
    from cad.sim.identify_fivebar import predict

    return predict(panto, bar_report(panto))
