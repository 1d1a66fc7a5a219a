"""optimize chooses among every catalog motor with the constants a build reads (issue 35 §1): the
list comes from the catalog, and the per-trial screen (least rotor inertia first, the first that
meets every check) lands on a non-RE motor when it is the better one.

Reference: a brute force over the catalog's motors for the optimum's fixed linkage and parts, on
the cheap model (each motor's M11 from :func:`cad.studies.codesign.cheap.apparent_mass`) and the
continuous force by hand, T_cont / max|dx/dphi1| with dx/dphi1 by central differences of the
coupler point's path (not the datasheet's lever)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from cad.data.catalog import MOTORS
from cad.design import load_design, parse_design
from cad.kinematics.fourbar import solve
from cad.kinematics.metrics import path_frame
from cad.studies.codesign import cheap, exact, search

ROOT = Path(__file__).resolve().parents[3]
BRIEF = ROOT / "designs" / "hoeken_light_brief.toml"


def test_searched_motors_are_the_complete_catalog_motors():
    """Every catalog motor with each build constant and Kt I0, none typed: the RE 30, the EC 45
    flat and the RE 25 lack sheet values (no public source read states them) and stay out."""
    keys = set(search.searched_motors())
    assert keys == {k for k, m in MOTORS.items() if not m.missing_build_fields() and m.no_load_current_mA}
    assert keys == {"maxon-re35", "maxon-re40", "maxon-dcx22l"}
    assert set(search.MOTOR_CONTINUOUS_TORQUE_MNM) == keys
    j = [MOTORS[k].rotor_inertia_g_cm2 for k in search.searched_motors()]
    assert j == sorted(j)


def _force_by_hand(design, torque_mNm: float) -> float:
    """T / max|dx/dphi1| (N): x along the path frame, central differences, 4001 samples."""
    fb, lo, hi = design.linkage, design.phi1_min_rad, design.phi1_max_rad
    phi = np.linspace(lo, hi, 4001)
    h = 1e-6
    u = path_frame(fb, lo, hi).x_hat

    def x(p):
        return solve(fb, p).P_mm @ u

    dx = (x(phi + h) - x(phi - h)) / (2 * h)  # mm/rad
    return torque_mNm / float(np.max(np.abs(dx)))


def test_a_light_brief_lands_on_the_dcx_the_brute_force_confirms():
    """A 0.8 N brief: the DCX 22 L (27 mN m, 9.37 g cm^2) gives the force with a rotor 8x lighter
    than the RE 35's, so the search's optimum carries it; for that linkage and parts every
    searched motor that gives 0.8 N by hand is heavier in M11 (cheap model) than the DCX."""
    d = load_design(BRIEF)
    raw = dict(d.raw)
    raw["mechanism"] = {**raw["mechanism"], "force_N": 0.8}
    brief = parse_design(raw, str(BRIEF))
    pb = search.problem_from(brief)
    pb.fixed_parts = search.fixed_parts(brief)
    cands, _ = search.run(pb, 20, seed=0)
    best = cands[0]
    assert best.parts["motor"] == "maxon-dcx22l"
    m11 = {}
    for key in search.searched_motors():
        c = search.Candidate(best.number, best.mechanism, {**best.parts, "motor": key}, best.cheap,
                             best.transmission)
        dk = parse_design(exact.candidate_raw(brief, c, "bf"), str(BRIEF))
        if _force_by_hand(dk, MOTORS[key].torque_continuous_mNm) >= 0.8:
            m11[key] = cheap.apparent_mass(dk)["M11_max_g"]
    assert min(m11, key=m11.get) == "maxon-dcx22l" and len(m11) >= 2, m11
    # the search's own M11 of its pick (rel 1e-6: the written mechanism table's rounded lengths)
    assert best.cheap["M11_max_g"] == pytest.approx(m11["maxon-dcx22l"], rel=1e-6)
    assert not math.isnan(best.cheap["continuous_force_N"])
