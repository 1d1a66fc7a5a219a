"""Where the twin pantograph's capstans could sit and what stops them
(:mod:`cad.families.pantograph.twin_placement`; the crank side's solids stay refused), on
designs/twin_pantograph_capstan.toml (136 mm drums, 32 mm capstans, 0.8 mm rope,
3 wraps, joints 75 mm apart, RE 35 motors).

References, independent of the direction search's plane grid: each drum's swept sector sampled
in polar coordinates about its joint at every workspace pose (1 deg, 1 mm), its points tested
analytically against the other drum's annular sector; the motors' places, the bands' heights and
the shaft's reach by hand from the design's and the catalog's numbers.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from tests.capstan_ref import sector_distance_mm

ROOT = Path(__file__).resolve().parents[3]
TWIN = ROOT / "designs" / "twin_pantograph_capstan.toml"
#: The drum's reach by hand: crests (136 - 0.8) / 2 + 0.35 x 0.8 = 67.88 mm, and the tensioner out
#: of them: ISO 4032 M3 nut 2.4 mm + 3 rope diameters 2.4 mm + ISO 4762 M3 head 3 mm.
REACH_MM = 67.88 + 2.4 + 2.4 + 3.0
MARGIN_DEG = 2.0  # cad.tolerances.CAPSTAN_RANGE_MARGIN_DEG


@pytest.fixture(scope="module")
def design():
    from cad.design import load_design

    return load_design(TWIN)


def _angles(design, cols):
    from cad.kinematics import twin_pantograph as ktwin

    return np.degrees(np.unwrap(ktwin.ik(design.mechanism, design.workspace_points()).q_rad, axis=0))[:, cols]


def _swept(s, q_deg, step_deg=1.0, step_mm=1.0):
    """(K, N, 2) the drum's sector at each pose, its arc widened by the margin: polar samples."""
    a = np.radians(np.arange(0.0, s.arc_span_deg + 2 * MARGIN_DEG + 1e-9, step_deg))
    r = np.append(np.arange(0.0, REACH_MM, step_mm), REACH_MM)  # out to the rim
    A, Rr = np.meshgrid(a, r)
    start = np.radians(s.arc_start_deg + q_deg - MARGIN_DEG)[:, None]
    ang = start + A.ravel()[None, :]
    return np.stack([s.b_mm[0] + Rr.ravel() * np.cos(ang), s.b_mm[1] + Rr.ravel() * np.sin(ang)], -1)


def _inside(pts, s, q):
    """Points (N, 2) inside the drum ``s``'s widened sector at link angle ``q`` (deg)."""
    d = pts - np.asarray(s.b_mm)
    ang = (np.degrees(np.arctan2(d[:, 1], d[:, 0])) - (s.arc_start_deg + q - MARGIN_DEG)) % 360.0
    return (np.hypot(d[:, 0], d[:, 1]) <= REACH_MM) & (ang <= s.arc_span_deg + 2 * MARGIN_DEG)


@pytest.fixture(scope="module")
def knob(design):
    """The knob pantograph's search: ``(sides, why)``."""
    from cad.families.pantograph import twin_placement as tp

    return tp.group_directions(design, "knob")


def test_the_knob_pantographs_drums_clear_in_one_band(design, knob):
    """The knob pantograph's two drums find a mirrored pair of motor directions in one band: each
    motor at B + C (cos a, sin a), C = 136 / 2 + 32 / 2 + 2 = 86 mm (pitch circles 2 mm apart);
    by the polar samples no point of the left swept drum lies in the right one at any pose, and
    neither reaches within the other joint's hub clevis (14 / 2 mm)."""
    sides, why = knob
    assert sides is not None and why.get(None, 0) >= 1
    for s, b in zip(sides, ((-37.5, 0.0), (37.5, 0.0)), strict=True):
        a = math.radians(s.alpha_deg)
        np.testing.assert_allclose(s.motor_xy_mm, (b[0] + 86.0 * math.cos(a), b[1] + 86.0 * math.sin(a)), atol=1e-9)
    q = _angles(design, [0, 1])
    joint = math.inf
    for k in range(len(q)):
        p0, p1 = _swept(sides[0], q[k:k + 1, 0])[0], _swept(sides[1], q[k:k + 1, 1])[0]
        assert not np.any(_inside(p0, sides[1], q[k, 1])), k
        joint = min(joint, float(np.hypot(*(p0 - (37.5, 0.0)).T).min()), float(np.hypot(*(p1 + (37.5, 0.0)).T).min()))
    assert joint > 7.0


def test_the_crank_pantographs_drums_find_no_mirrored_pair_in_one_band(design):
    """The crank pantograph's (its links turn 96 deg over the workspace and the crank's turn):
    for every mirrored pair of directions every 5 deg the polar samples find a pose where the two
    swept drums share a point, or the two motors' 55 mm mount plates come closer than 55 + 1 mm
    (by hand); the search finds none either."""
    from cad.families.pantograph import capstan as pcap
    from cad.families.pantograph import twin_placement as tp
    from cad.families.pantograph.twin_capstan import joint_ranges_deg

    sides, why = tp.group_directions(design, "crank")
    assert sides is None and None not in why
    from cad.device import resolve_device

    t = resolve_device(design).transmission("crank_q_left")
    rng = joint_ranges_deg(design)[[2, 3]]
    q = _angles(design, [2, 3])
    fb = design.mechanism.crank
    for al in np.arange(-180.0, 180.0, 5.0):
        ar = (180.0 - al + 180.0) % 360.0 - 180.0
        s0, s1 = (pcap.capstan_side(fb, t, i, a, rng[i]) for i, a in enumerate((al, ar)))
        m0, m1 = np.asarray(s0.motor_xy_mm), np.asarray(s1.motor_xy_mm)
        squares = [np.array((-37.5, 0.0)), np.array((37.5, 0.0)), m0, m1]
        mounts = any(np.abs(m - sq).max() < 55.0 + 1.0 for m, own in ((m0, 2), (m1, 3))
                     for j, sq in enumerate(squares) if j != own)
        meet = mounts or any(np.any(_inside(_swept(s0, q[k:k + 1, 0])[0], s1, q[k, 1])) for k in range(len(q)))
        assert meet, al


def test_a_second_band_is_out_of_the_re35_shafts_reach(design):
    """Band 1's rope plane 3 + 10 / 2 = 8 mm from the plate, band 2's 3 + 10 + 3 + 5 = 21 mm;
    the capstan's hub top 1.5 x 0.8 x 3 / 2 = 1.8 mm below it; the RE 35's shaft tip 22 mm from
    its face (maxon's drawing, the catalog) less the 6 mm plate and 5 mm mount plate = 11 mm: band 1
    clears by 4.8 mm, band 2 is 8.2 mm short."""
    from cad.device import resolve_device
    from cad.families.pantograph import twin_placement as tp

    t = resolve_device(design).transmission("crank_q_right")
    assert tp.band_rope_offset_mm(design, 1) == pytest.approx(8.0, abs=1e-12)
    assert tp.band_rope_offset_mm(design, 2) == pytest.approx(21.0, abs=1e-12)
    assert tp.shaft_shortfall_mm(design, t, 1) == pytest.approx(6.2 - 11.0, abs=1e-12)
    assert tp.shaft_shortfall_mm(design, t, 2) == pytest.approx(19.2 - 11.0, abs=1e-12)


def test_every_bridge_post_stands_where_the_knob_drums_sweep(design, knob):
    """The four bridge posts at (+-37.5 +- 22, -(55 / 2 + 12 / 2 + 8) = -41.5) mm, 47.0 mm from
    the nearest joint (< the drum's reach 75.7 mm): the knob pantograph's drums, placed by the
    search, sweep over every one (the post's centre tested against the swept sectors here)."""
    from cad.families.pantograph import twin_placement as tp

    sides, _ = knob
    assert tp.posts_in_swept_drums(design, sides, "knob") == [True] * 4
    q = _angles(design, [0, 1])
    for x, y in [(sx * 37.5 + dx, -41.5) for sx in (-1, 1) for dx in (-22.0, 22.0)]:
        assert math.hypot(22.0, 41.5) < REACH_MM
        assert any(_inside(np.array([[x, y]]), s, q[k, i])[0] for i, s in enumerate(sides) for k in range(len(q)))


def _sector_distance(p, s, q) -> float:
    """:func:`tests.capstan_ref.sector_distance_mm` with this design's reach and margin."""
    return sector_distance_mm(p, s, q, REACH_MM, MARGIN_DEG)


def test_in_two_bands_the_crank_drums_keep_clear_of_the_other_axle(design):
    """With the crank pantograph's drums in two bands, each drum meets only the other link's axle
    (3 mm + 1 mm): the directions that keep it clear are mirror images left / right (the links'
    ranges are, 90..186 and -6..90 deg), a non-empty set pointing away from the other joint
    (left about 180 deg, right about 0 deg); each kept direction's drum stays
    more than 4 mm from the other axle's centre at every pose, and each dropped one comes within
    (the exact distance from a point to the widened annular sector: past the rim inside the arc,
    else to the nearer end radius)."""
    from cad.device import resolve_device
    from cad.families.pantograph import capstan as pcap
    from cad.families.pantograph import twin_placement as tp
    from cad.families.pantograph.twin_capstan import joint_ranges_deg

    left, right = tp.two_band_directions_deg(design, "crank")
    assert left and sorted(left) == sorted(((180.0 - a + 180.0) % 360.0 - 180.0) for a in right)
    assert all(abs(((a - 180.0 + 180.0) % 360.0) - 180.0) <= 90.0 for a in left)
    t = resolve_device(design).transmission("crank_q_left")
    rng = joint_ranges_deg(design)[[2, 3]]
    q = _angles(design, [2, 3])
    for al in np.arange(-180.0, 180.0, 5.0):
        s = pcap.capstan_side(design.mechanism.crank, t, 0, al, rng[0])
        near = min(_sector_distance((37.5, 0.0), s, q[k, 0]) for k in range(len(q)))
        assert (near > 4.0) == (al in left), (al, near)


def test_the_posts_clear_every_drum_once_out_of_its_reach(design, knob):
    """With the knob pantograph's drums in one band (the search's) and the crank pantograph's in
    two bands (directions -175 and -5 deg, kept by :func:`two_band_directions_deg`), a bridge
    post (12 mm, 1 mm clearance) at x = B_x +- 22 and B_x stands clear first where its distance
    to the nearer joint reaches the drum's reach plus 7 mm (the sweeps cover straight back):
    y = -sqrt(82.68^2 - dx^2), dx = 22 or 0 mm, to the 0.05 mm step."""
    from cad.device import resolve_device
    from cad.families.pantograph import capstan as pcap
    from cad.families.pantograph import twin_placement as tp
    from cad.families.pantograph.twin_capstan import joint_ranges_deg

    left, right = tp.two_band_directions_deg(design, "crank")
    assert -175.0 in left and -5.0 in right
    t = resolve_device(design).transmission("crank_q_left")
    rng = joint_ranges_deg(design)[[2, 3]]
    crank = tuple(pcap.capstan_side(design.mechanism.crank, t, i, a, rng[i]) for i, a in enumerate((-175.0, -5.0)))
    both = {"knob": knob[0], "crank": crank}
    for x, dx in ((-59.5, 22.0), (-37.5, 0.0), (-15.5, 22.0)):
        y = tp.clear_post_y_mm(design, x, both)
        assert y == pytest.approx(-math.sqrt((REACH_MM + 7.0) ** 2 - dx * dx), abs=0.051)
