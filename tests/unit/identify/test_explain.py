"""The explanation of a miss follows the size of the gap, not its sign (a tester found the
delta's negative gravity loads explained the wrong way round): a load 15 % larger in size is a
heavier part, and a heavier-looking device can be a weaker torque constant."""

from __future__ import annotations

from cad.sim.identify_device import EXPLAIN, figure_row


def test_a_larger_negative_gravity_load_is_a_heavier_part():
    r = figure_row("gravity_load0_mNm", "load", -72.5, 0.4, "mN m", -63.0, tol_rel=0.1, explain="gravity")
    assert r["verdict"] == "MISS" and r["explain"] == EXPLAIN["gravity"][0]
    r = figure_row("gravity_load0_mNm", "load", -53.5, 0.4, "mN m", -63.0, tol_rel=0.1, explain="gravity")
    assert r["explain"] == EXPLAIN["gravity"][1]


def test_a_heavier_looking_device_names_a_weaker_torque_constant():
    r = figure_row("Mxx_g@home", "mass", 119.2, 1.0, "g", 96.4, tol_rel=0.1, explain="apparent_mass")
    assert "weaker torque constant" in r["explain"]
