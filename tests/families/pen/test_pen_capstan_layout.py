"""Where the haptic pen's capstans would sit (:mod:`cad.families.pen.capstan_layout`, issue 35):
each pair of capstan motors laid out in its own plane by the 5-bar's direction search, the
build's refusal naming where the motors would sit or what stops them.

References, each independent of the plane layout under test:

* the pen's 3-D body frames over the workspace grid (:func:`cad.families.pen.layout.body_poses`,
  the frames the solids and the MJCF use): the moved motor put in its body's frame by
  :func:`motor_in_body_mm` stands the centre distance off its joint's axis (by hand: the pitch
  radii and the 2 mm gap, 64 + 16 + 2 = 82 mm on the shoulders, 60 + 20 + 2 on the waists), and
  the rope's two tangent points, at +-gamma (gamma = acos((r_d - r_c) / C) by hand) about the
  motor's direction seen from the drum's body frame, stay on the drum's arc
  (:func:`drum_arc_body_deg`) inside its anchors, with exactly the range margin to spare at
  the extreme pose;
* the swept drums in those 3-D frames, sampled as annular sectors out to the crests and the
  tensioner (the sampling's worst error subtracted): each stays off the other joint's axis by
  more than the kept radius (its hub clevis's half width or the waist hub's radius, and the
  1 mm gap) at every pose, and the two waist drums (one band) stay more than 1 mm apart.
"""

from __future__ import annotations

import copy
import math
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

from cad.design import parse_design
from cad.device import resolve_device
from cad.errors import DesignError
from cad.families.pantograph.capstan import swept_radius_mm
from cad.families.pen import capstan_layout as cl
from cad.families.pen.build import check_options
from cad.families.pen.layout import body_poses

ROOT = Path(__file__).resolve().parents[3]
BUNDLED = ROOT / "designs" / "haptic_pen_capstan.toml"
RAW = tomllib.loads(BUNDLED.read_text())
#: The bundled file's pulleys (pitch diameters, mm) and the shared 2 mm gap between them.
PULLEYS = {"waist": (120.0, 40.0), "lower": (128.0, 32.0), "upper": (128.0, 32.0)}
GAP_MM = 2.0
#: The anchors' arc on the drum: 10 mm of rope each end (cad.datasheet.capstan_rows).
ANCHOR_MM = 10.0
#: The drum arcs are the range over the grid widened by 2 deg each side (cad.tolerances).
MARGIN_DEG = 2.0


@pytest.fixture(scope="module")
def bundled():
    d = parse_design(copy.deepcopy(RAW), "pen")
    return d, cl.layout(d)


def _grid_poses(d):
    return body_poses(d, d.workspace_points())


def _wrap(a):
    return (np.asarray(a) + 180.0) % 360.0 - 180.0


def _refusal_line(d) -> str:
    with pytest.raises(DesignError) as e:
        check_options(d, "fabrication", None)
    msg = str(e.value)
    assert "\n" not in msg and msg.startswith("transmission: the haptic pen's capstans cannot be laid out")
    return msg


def test_with_a_5_mm_plate_the_shoulder_capstans_are_2_2_mm_past_the_shaft():
    """The bundled file with a 5 mm motor plate: the waists are laid out; each arm's shoulder directions are found, but
    whichever shoulder drum turns by the motor plate, the other's turns in band 2, its rope's
    plane 2 gaps + a drum + half a drum = 2 x 3 + 10 + 5 = 21 mm past the plate, the capstan's
    hub half the turns below it (1.5 x 0.8 x 3 / 2 = 1.8 mm), at 19.2 mm; the RE 35's shaft
    reaches 22 - 5 = 17 mm past the 5 mm motor plate: 2.2 mm short, fixed by a motor plate of at
    most 5 - 2.2 = 2.8 mm (the bundled file's plate). The build's pre-CAD line says all of it."""
    raw = copy.deepcopy(RAW)
    raw["parts"]["motor_mount_thickness_mm"] = 5.0
    d = parse_design(raw, "thick")
    pairs = cl.layout(d)
    assert [p.name for p in pairs] == ["waists", "arm A shoulders", "arm B shoulders"]
    assert all(p.sides is not None for p in pairs)
    assert [p.clash is None for p in pairs] == [True, False, False]
    short = (2 * 3.0 + 10.0 + 5.0) - 1.5 * 0.8 * 3.0 / 2 - (22.0 - 5.0)
    assert short == pytest.approx(2.2)
    msg = _refusal_line(d)
    assert "the layout places the motors of waists at" in msg
    for arm in ("A", "B"):
        seg = msg.split(f"arm {arm} shoulders: ")[1]
        assert "whichever drum turns by the motor plate" in seg
        assert f"stands {short:.1f} mm past the maxon-re35 shaft's tip" in seg
        assert f"parts.motor_mount_thickness_mm <= {5.0 - short:.2f}" in seg


def test_with_a_2_5_mm_motor_plate_every_pair_is_laid_out():
    """A 2.5 mm motor plate lets the RE 35's shaft reach 19.5 mm >= 19.2 mm (the bundled 2.8 mm:
    19.2 mm, just): the three pairs are laid out, each arm's upper drum by the plate, and the
    build is not refused."""
    raw = copy.deepcopy(RAW)
    raw["parts"]["motor_mount_thickness_mm"] = 2.5
    d = parse_design(raw, "thin")
    pairs = cl.layout(d)
    assert all(p.clash is None for p in pairs)
    assert [p.plate_band for p in pairs] == [None, "A_q_upper", "B_q_upper"]
    assert cl.refusal(d) is None
    check_options(d, "fabrication", None)
    assert [p.plate_band for p in cl.layout(parse_design(copy.deepcopy(RAW), "bundled"))] == [
        None, "A_q_upper", "B_q_upper"]


def test_moved_motors_and_rope_tangents_against_the_3d_frames(bundled):
    """Second method: in the pen's 3-D body frames at every grid pose, each moved motor stands C
    off its joint's axis (by hand) and both tangent points lie on the drum's arc inside the
    anchors, the extreme pose exactly the 2 deg margin inside (module docstring)."""
    d, pairs = bundled
    T = _grid_poses(d)
    l1 = d.mechanism.shoulder_base_mm
    for pair in pairs:
        for sd in pair.sides:
            arm, _, which = sd.joint.split("_")
            dd, dc = PULLEYS[which]
            C = 0.5 * (dd + dc) + GAP_MM
            gamma = math.degrees(math.acos(0.5 * (dd - dc) / C))
            mx, my = cl.motor_in_body_mm(sd)
            if which == "waist":  # the motor on the ground, the drum on the waist bracket
                motor_w = np.array([mx, my, 0.0, 1.0])
                Tb = T[f"{arm}_waist"]
                axis_pt = Tb[:, :3, 3]
            else:  # the motor on the waist frame's plate (any offset along y = n_out), the drum on the link
                z_b = -l1 / 2 if which == "lower" else l1 / 2
                motor_w = np.einsum("nij,j->ni", T[f"{arm}_waist"], [mx, 7.0, my, 1.0])
                Tb = T[f"{arm}_proximal_{which}"]
                axis_pt = np.einsum("nij,j->ni", T[f"{arm}_waist"], [0.0, 0.0, z_b, 1.0])[:, :3]
                assert np.allclose(Tb[:, :3, 3], axis_pt, atol=1e-9)
            local = np.einsum("nij,nj->ni", np.linalg.inv(Tb), np.broadcast_to(motor_w, (len(Tb), 4)))
            assert np.allclose(np.hypot(local[:, 0], local[:, 1]), C, rtol=1e-12), sd.joint
            phi = np.degrees(np.arctan2(local[:, 1], local[:, 0]))
            start, span, anchors = cl.drum_arc_body_deg(sd)
            anchor = math.degrees(2 * ANCHOR_MM / dd)
            lo, hi = start + anchor, start + span - anchor
            slack = []
            for t in (phi - gamma, phi + gamma):
                a = lo + (t - lo) % 360.0
                assert np.all(a <= hi + 1e-9), sd.joint
                slack += [np.min(a - lo), np.min(hi - a)]
            assert min(slack) == pytest.approx(MARGIN_DEG, abs=1e-6), sd.joint
            # each anchor half an anchor arc beyond the rope's extreme tangent point
            assert sorted(_wrap(np.array(anchors) - start) % 360.0) == pytest.approx(
                [0.5 * anchor, span - 0.5 * anchor], abs=1e-9)


def _sector_points(sd, r_out: float, n_r: int, n_a: int) -> tuple[np.ndarray, float]:
    """(M, 2) points of the drum's annular sector (axis to ``r_out``) in its body frame on an
    n_r x n_a polar grid, and the farthest any point of the sector lies from one of them (half
    the grid cell's diagonal at the rim, mm)."""
    start, span, _ = cl.drum_arc_body_deg(sd)
    r, a = np.meshgrid(np.linspace(0.0, r_out, n_r), np.radians(np.linspace(start, start + span, n_a)))
    e = 0.5 * math.hypot(r_out / (n_r - 1), r_out * math.radians(span) / (n_a - 1))
    return np.column_stack([(r * np.cos(a)).ravel(), (r * np.sin(a)).ravel()]), e


def _boundary_points(sd, r_out: float, n: int = 2000) -> tuple[np.ndarray, float]:
    """(M, 2) points on the sector's boundary (the crest arc and both radial edges) and the
    farthest any boundary point lies from one of them (mm): two sectors that do not overlap
    are nearest on their boundaries."""
    start, span, _ = cl.drum_arc_body_deg(sd)
    a = np.radians(np.linspace(start, start + span, n))
    r = np.linspace(0.0, r_out, n // 4)
    pts = [np.column_stack([r_out * np.cos(a), r_out * np.sin(a)])]
    pts += [np.column_stack([r * math.cos(e), r * math.sin(e)]) for e in (a[0], a[-1])]
    return np.vstack(pts), 0.5 * max(r_out * math.radians(span) / (n - 1), r_out / (n // 4 - 1))


def _to_world(T, P) -> np.ndarray:
    """(N, M, 3) world points of body-frame plane points ``P`` (M, 2) at the poses ``T`` (N, 4, 4)."""
    return np.einsum("nij,mj->nmi", T, np.column_stack([P, np.zeros(len(P)), np.ones(len(P))]))[..., :3]


def test_swept_drums_in_3d_leave_the_other_axle_free_and_the_waist_drums_apart(bundled):
    """Each drum (out to its crests and tensioner) at every grid pose, in the 3-D frames: the
    other joint's axis stays more than the kept radius away (a shoulder: the hub clevis's half
    width + 1 mm; a waist: the 26 mm hub's radius + 1 mm); the two waist drums, in one band,
    share no point."""
    d, pairs = bundled
    T = _grid_poses(d)
    keep = {"waist": 13.0 + 1.0, "lower": d.parts.clevis_width_mm / 2 + 1.0}
    keep["upper"] = keep["lower"]
    dev = resolve_device(d)
    for pair in pairs:
        rims = []
        for k, sd in enumerate(pair.sides):
            arm, _, which = sd.joint.split("_")
            body = f"{arm}_waist" if which == "waist" else f"{arm}_proximal_{which}"
            rims.append((body, swept_radius_mm(dev.transmission(sd.joint))))
            P, e = _sector_points(sd, rims[-1][1], 25, 150)
            Pw = _to_world(T[body], P)
            other = pair.sides[1 - k].joint.split("_")
            ob = f"{other[0]}_waist" if other[2] == "waist" else f"{other[0]}_proximal_{other[2]}"
            o, ax = T[ob][:, :3, 3], T[ob][:, :3, 2]  # the other joint's axis: its body's z
            rel = Pw - o[:, None, :]
            dist = np.linalg.norm(rel - np.einsum("nmi,ni->nm", rel, ax)[..., None] * ax[:, None, :], axis=-1)
            assert dist.min() - e > keep[which], (sd.joint, dist.min(), e)
        if pair.name == "waists":  # one band: the two sectors' boundaries apart at each pose
            (b0, r0), (b1, r1) = rims
            (P0, e0), (P1, e1) = _boundary_points(pair.sides[0], r0), _boundary_points(pair.sides[1], r1)
            W0, W1 = _to_world(T[b0], P0), _to_world(T[b1], P1)
            gaps = [cKDTree(W1[n, :, :2]).query(W0[n, :, :2])[0].min() for n in range(len(W0))]
            assert min(gaps) - e0 - e1 > 1.0, min(gaps)


def _variant(**per_kind):
    """The bundled design with its shoulder (``s``) or waist (``w``) tables changed."""
    raw = copy.deepcopy(RAW)
    for i, t in enumerate(raw["transmission"]):
        t.update(per_kind.get("w" if i in (0, 3) else "s", {}))
    return raw


def test_a_clashing_shoulder_pair_is_refused_with_its_counts_and_fix():
    """Shoulder motors 140 mm off their axes (the arc 2 gamma grows with C): no direction
    clears, the line counts every one of the 360 / 5 = 72 directions by clash and says what
    fixes it, for both arms; the waists (direct here) are not named."""
    raw = _variant(s={"centre_distance_mm": 140.0}, w={"kind": "direct"})
    for i in (0, 3):
        raw["transmission"][i] = {"kind": "direct"}
    d = parse_design(raw, "clash")
    msg = _refusal_line(d)
    assert "waists" not in msg
    for arm in ("A", "B"):
        seg = msg.split(f"arm {arm} shoulders: ")[1]
        counts = [int(n) for n in re.findall(r" in (\d+)", seg.split("; fix:")[0])]
        assert sum(counts) == 72, seg
        assert "of 72 directions" in seg and "a swept drum meets the other joint's axle" in seg
        assert "fix: a smaller shoulder drum" in seg and "mechanism.shoulder_base_mm" in seg


def test_a_pair_with_one_direct_motor_is_named_and_the_others_laid_out():
    """Arm A's waist direct, arm B's through a capstan: the waists are not laid out (named, with
    the fix), both arms' shoulders are."""
    raw = copy.deepcopy(RAW)
    raw["transmission"][0] = {"kind": "direct"}
    d = parse_design(raw, "mixed")
    pairs = cl.layout(d)
    assert [(p.name, p.sides is None) for p in pairs] == [
        ("waists", True), ("arm A shoulders", False), ("arm B shoulders", False)]
    msg = cl.refusal(d)
    assert "waists: A_q_waist is direct" in msg and "fix: give both a capstan or neither" in msg


def _shoulder_sides(alphas, q_range=(-2.0, 2.0)):
    """Two shoulder sides of the bundled file's 128 / 32 mm capstan at joints (-30, 0) and
    (30, 0), motors at ``alphas`` (deg), each link's range ``q_range`` (deg)."""
    import types

    from cad.families.pantograph.capstan import capstan_side

    d = parse_design(copy.deepcopy(RAW), "pen")
    t = resolve_device(d).transmission("A_q_lower")
    fb = types.SimpleNamespace(base_left_mm=(-30.0, 0.0), base_right_mm=(30.0, 0.0))
    return t, tuple(capstan_side(fb, t, i, a, q_range) for i, a in enumerate(alphas))


def test_the_other_motors_capstan_in_a_drums_arc_by_hand():
    """Left motor at 0 deg: 82 mm from (-30, 0), at (52, 0), 22 mm beyond the right joint. The
    right drum facing it (alpha 0, arc 0 +- (gamma + 2 deg + an anchor), out to 71.7 mm) covers
    its capstan (its crests 15.88 mm and the 0.5 mm half gap: a 16.4 mm disc 22 mm away); facing
    away (alpha 180) it does not (the disc lies within asin(16.4 / 22) = 48 deg of 0 deg, the
    arc within 180 +- 65 deg)."""
    t, facing = _shoulder_sides((0.0, 0.0))
    _, away = _shoulder_sides((0.0, 180.0))
    assert facing[0].motor_xy_mm == pytest.approx((52.0, 0.0))
    crest = [16.0 - 0.8 / 2 + 0.35 * 0.8] * 2  # the capstan's crests: pitch radius less half a rope plus the groove depth
    rims = [swept_radius_mm(t)] * 2
    q = np.zeros((1, 2))
    assert cl.shaft_clash(facing, rims, q, 1, crest)
    assert not cl.shaft_clash(away, rims, q, 1, crest)


def test_rope_runs_clearance_against_sampled_runs(bundled):
    """The least distance from a rope run to the other joint, by projection
    (:func:`run_clearance_mm`), against 20001 points sampled along each run."""
    d, pairs = bundled
    dev = resolve_device(d)
    for pair in pairs:
        ds = [dev.transmission(s.joint).cable_diameter_mm for s in pair.sides]
        ref = math.inf
        for k, sd in enumerate(pair.sides):
            c = np.asarray(pair.sides[1 - k].b_mm)
            for p0, p1 in np.asarray(sd.tangents_mm):
                s = np.linspace(0.0, 1.0, 20001)[:, None]
                ref = min(ref, np.min(np.linalg.norm(p0 + s * (p1 - p0) - c, axis=1)) - ds[k] / 2)
        assert cl.run_clearance_mm(pair.sides, ds) == pytest.approx(ref, abs=0.02)
