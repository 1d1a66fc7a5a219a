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
