"""The PowerMouse's handle and stator post are attached, measured in ``assembly.step``.

The handle's stem sits in a socket in the flotor's (+,+,+) corner, its shoulder on a boss
inside that corner, its turned M4 tip screwed through the boss; the post's turned M4 tip is
screwed into the core's faced (-,-,-) corner and the post is locked in the housing's collar by
an ISO 4026 set screw. References, not the build's code path: the design's diameters and the
diagonal axes it states (handle along +(1,1,1), post along -(1,1,1)); ISO 261 thread sizes;
the engagement rules (2 d in a tapped plastic, 1.5 d in a metal); bd_warehouse's ISO 4026
lengths read from its CSV; and the solids re-read from ``assembly.step`` with OCCT
(``tests/step_pairs``): point classification along the axes, exact distances.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from catalog_ref import iso4026_lengths_mm
from families.test_family_fasteners import _refused_before_cad
from step_pairs import radial_screw_mm, read_parts, tip_on_axis_mm

U = np.ones(3) / math.sqrt(3.0)  # the diagonal (1,1,1)/sqrt3 (flotor frame = assembly frame)


@pytest.fixture(scope="module")
def pm(family_builds):
    d, out, rep = family_builds["powermouse"]
    return d, rep, dict(read_parts(out / "assembly.step"))


def _distance_mm(a, b) -> float:
    from OCP.BRep import BRep_Builder
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape
    from OCP.TopoDS import TopoDS_Compound

    def comp(solids):
        c, bb = TopoDS_Compound(), BRep_Builder()
        bb.MakeCompound(c)
        for s in solids:
            bb.Add(c, s)
        return c

    return BRepExtrema_DistShapeShape(comp(a), comp(b)).Value()


@pytest.mark.parametrize(
    "part, hole_part, sign, d_mm, min_d",
    [("handle", "flotor_body", 1.0, 4.0, 2.0), ("post", "core", -1.0, 4.0, 1.5)],
)
def test_turned_tip_engagement_measured_in_the_step_file(pm, part, hole_part, sign, d_mm, min_d):
    """Each tip, read back: its thread fully surrounded by the tapped part over the recorded
    engagement (to 0.01 mm), at least the rule (delrin flotor 2 d = 8 mm, iron core 1.5 d =
    6 mm), the hole deeper than the tip, and the shoulder touching the part it seats on."""
    d, rep, parts = pm
    assert d.flotor.material == "delrin"
    x = rep["fasteners"][part]
    assert x["size"] == "M4-0.7" and x["hole"].startswith(f"{hole_part}:")
    u = sign * U  # outwards along the part; the tip points back, towards -u
    inside = 60.0 if part == "handle" else 40.0  # on the axis, in the stem / the post body
    m = tip_on_axis_mm(parts[part], parts[hole_part], d_mm, np.zeros(3), u, inside)
    assert m["engagement_mm"] == pytest.approx(x["engagement_mm"], abs=0.01), m
    assert m["engagement_mm"] >= min_d * d_mm - 0.01 and m["tip_free"], m
    h = rep["tapped_holes"][x["hole"]]
    assert h["part"] == hole_part and h["min_engagement_mm"] == min_d * d_mm
    assert x["engagement_mm"] <= h["depth_mm"]
    assert _distance_mm(parts[part], parts[hole_part]) < 1e-6  # seated, not floating


def test_handle_shoulder_bears_on_the_flotor(pm):
    """Just below the handle's shoulder (a ring between the thread and the 10 mm stem) is
    flotor, just above it is handle: the stem seats on the boss, not on thread alone."""
    from step_pairs import _classifier

    d, rep, parts = pm
    tip = tip_on_axis_mm(parts["handle"], parts["flotor_body"], 4.0, np.zeros(3), U, 60.0)
    seat = tip["tip_s"] + rep["fasteners"]["handle"]["engagement_mm"]
    w = np.cross(U, [1.0, 0.0, 0.0])
    w /= np.linalg.norm(w)
    r = 0.5 * (2.0 + d.handle.diameter_mm / 2)  # mid-shoulder, between M4 and the stem
    in_h, in_f = _classifier(parts["handle"]), _classifier(parts["flotor_body"])
    for a in np.linspace(0, 2 * math.pi, 8, endpoint=False):
        q = r * (math.cos(a) * w + math.sin(a) * np.cross(U, w))
        assert in_h(*(U * (seat + 0.05) + q)) and in_f(*(U * (seat - 0.05) + q))


def test_post_set_screw_against_the_catalog_and_the_step_file(pm):
    """The collar (post radius + 6 mm = 10 mm) round the 8 mm post: full M3 thread ends at
    sqrt(10^2 - 1.5^2) - 4 = 5.887 mm, so the longest ISO 4026 M3 length not proud of it is
    5 >= 1.5 d = 4.5. Read back: its point on the post (4 mm from the diagonal), the whole
    length in full thread in the housing, its end inside the collar."""
    from cad.families.powermouse import parts as pp

    d, rep, parts = pm
    r, R = d.stator.post_diameter_mm / 2, d.stator.post_diameter_mm / 2 + pp.POST_COLLAR_WALL_MM
    depth = math.sqrt(R**2 - 1.5**2) - r
    L = max(x for x in iso4026_lengths_mm("M3-0.5") if x <= depth)
    assert L == 5.0 and L >= 4.5
    x = rep["fasteners"]["post_set_screw"]
    assert x == {"kind": "ISO 4026", "size": "M3-0.5", "length_mm": L, "clamps": ["post"],
                 "hole": "housing_body:post_set_screw", "engagement_mm": L}
    assert rep["tapped_holes"][x["hole"]]["depth_mm"] == pytest.approx(depth)
    m = radial_screw_mm(parts["post_set_screw"], parts["housing_body"], parts["post"], 3.0,
                        shaft_axis=(np.zeros(3), U))
    assert m["tip_to_axis_mm"] == pytest.approx(r, abs=1e-3) and m["tip_on_shaft"], m
    assert m["length_mm"] == pytest.approx(L, abs=1e-3) and m["rim_to_axis_max_mm"] <= R, m
    assert m["full_thread_mm"] >= L - 0.01, m


def test_thin_handle_or_post_is_refused_before_cad(tmp_path, monkeypatch):
    """A 5 mm stem or post leaves no 1 mm shoulder round the M4 tip's 3.3 mm tap drill."""
    msg = _refused_before_cad(monkeypatch, tmp_path, "powermouse.toml", "handle", diameter_mm=5.0)
    assert msg.startswith("handle.diameter_mm: 5 mm leaves no shoulder") and ">= 5.3 mm" in msg
    msg = _refused_before_cad(monkeypatch, tmp_path / "b", "powermouse.toml", "stator",
                              post_diameter_mm=5.0)
    assert msg.startswith("stator.post_diameter_mm: 5 mm leaves no shoulder"), msg


# ------------------------------------------------------------ corner holes over the motion


@pytest.fixture(scope="module")
def geo():
    from cad.design import load_design
    from cad.families.powermouse.build import actuator_gap_mm
    from cad.families.powermouse import parts as pp

    d = load_design(Path(__file__).resolve().parents[3] / "designs" / "powermouse.toml")
    return d, pp.geometry(d, actuator_gap_mm(d))


def _lp_excursion(g, s_mm, Rs, n_e=36) -> float:
    """Second method for the excursion bound: for each rotation, a linear program (scipy
    HiGHS) per direction e perpendicular to the diagonal maximizes e.(t + (R - I) q) over
    the translations that keep every magnet-footprint corner on the right side of the
    flotor's moved faces (constraints written here from the design's numbers)."""
    from scipy.optimize import linprog

    from cad.actuators.powermouse import coil_layout

    a, dc, d, w, lm = (g.coil_plane_half_mm, g.coil_width_mm, g.gap_mm, g.magnet_width_mm,
                       g.magnet_length_mm)
    best = 0.0
    e1 = np.cross(U, [1.0, 0.0, 0.0])
    e1 /= np.linalg.norm(e1)
    es = [math.cos(x) * e1 + math.sin(x) * np.cross(U, e1)
          for x in np.linspace(0, 2 * math.pi, n_e, endpoint=False)]
    for R in Rs:
        A, b = [], []
        for c in coil_layout(a):
            n, nn = c.normal, R @ c.normal
            for sx in (-1, 1):
                for sy in (-1, 1):
                    p = c.centre_mm + c.R_flotor_act @ (sx * w, sy * lm / 2, 0.0)
                    A.append(nn)  # outer: nn.(m - t) >= a + dc/2
                    b.append(nn @ (p + n * d / 2) - (a + dc / 2))
                    A.append(-nn)  # inner: nn.(m - t) <= a - dc/2
                    b.append((a - dc / 2) - nn @ (p - n * d / 2))
        rot = R @ (s_mm * U) - s_mm * U
        for e in es:
            r = linprog(-e, A_ub=np.array(A), b_ub=np.array(b), bounds=[(-g.range_mm, g.range_mm)] * 3,
                        method="highs")
            assert r.status == 0
            best = max(best, float(e @ (r.x + rot)))
    return best


def test_excursion_bound_holds_against_linear_programs(geo):
    """The vertex bound is never exceeded by an LP optimum over 60 random rotations up to
    5 deg (plus the bound's own worst rotation, which the LP must reach to 1e-6)."""
    from cad.actuators.powermouse import diagonal_excursion_mm, rot_about

    d, g = geo
    s = (g.housing_inner_half_mm + g.housing_wall_mm) * math.sqrt(3.0)
    x = diagonal_excursion_mm(g.coils(), g.magnet_width_mm, g.magnet_length_mm, g.gap_mm,
                              g.coil_width_mm, g.range_mm, g.range_deg, s)
    rng = np.random.default_rng(7)
    Rs = [rot_about(rng.normal(size=3), math.radians(5.0) * rng.uniform() ** 0.3)
          for _ in range(60)]
    assert _lp_excursion(g, s, Rs) <= x.excursion_mm + 1e-6
    assert _lp_excursion(g, s, [x.R], n_e=720) == pytest.approx(x.excursion_mm, abs=0.05)


def test_tester_poses_are_clear_and_the_worst_pose_only_touches(geo):
    """Poses where the 24 mm housing hole used to be struck by the stem while the coils
    were clear (measured by an independent check: -5 deg about (1,-1,0) with t = (1,1,-1)
    mm; +5 deg about (1,0,-1) with (1,-1,1); -5 deg about (1,-1,0) with (0,0,-1)) are clear
    now; at the bound's worst pose for the handle and the post, read exactly with OCCT, the
    coils touch their magnets (the stop, 0 mm) and nothing overlaps."""
    from cad.actuators.powermouse import diagonal_excursion_mm, rot_about
    from cad.families.powermouse import parts as pp

    d, g = geo
    th = math.radians(5.0)
    poses = [("a", rot_about((1, -1, 0), -th), np.array([1.0, 1.0, -1.0])),
             ("b", rot_about((1, 0, -1), th), np.array([1.0, -1.0, 1.0])),
             ("c", rot_about((1, -1, 0), -th), np.array([0.0, 0.0, -1.0]))]
    Ho = g.housing_inner_half_mm + g.housing_wall_mm
    for name, s in (("h", Ho * math.sqrt(3.0)), ("p", g.flotor_edge_mm / 2 * math.sqrt(3.0))):
        x = diagonal_excursion_mm(g.coils(), g.magnet_width_mm, g.magnet_length_mm, g.gap_mm,
                                  g.coil_width_mm, g.range_mm, g.range_deg, s)
        poses.append((name, x.R, x.t_mm))
    c = pp.motion_clearances(g, g.range_mm, g.range_deg, pp.flotor_solids(g),
                             pp.stator_solids(g), poses)
    for k in "abc":
        assert c.poses[k][0] > 0.5, (k, c.poses[k])
    for k in "hp":
        assert c.poses[k][0] == pytest.approx(0.0, abs=2e-3), (k, c.poses[k])


@pytest.mark.parametrize(
    "table, changes, start, needle",
    [
        ("handle", {"diameter_mm": 300.0}, "handle.diameter_mm: 300 mm: its 304 mm boss", "<="),
        ("handle", {"knob_diameter_mm": 5.0}, "handle.knob_diameter_mm: 5 mm is no knob", ">= 12"),
        ("handle", {"length_mm": 0.5}, "handle.length_mm: 0.5 mm: the 24 mm knob", ">="),
        ("flotor", {"corner_hole_mm": 22.0}, "flotor.corner_hole_mm: 22 mm: the 8 mm post moves",
         ">= 25.6"),
        ("stator", {"post_diameter_mm": 21.9}, "stator.post_diameter_mm: 21.9 mm", "<="),
    ],
)
def test_powermouse_limits_are_refused_before_cad(tmp_path, monkeypatch, table, changes, start,
                                                 needle):
    msg = _refused_before_cad(monkeypatch, tmp_path, "powermouse.toml", table, **changes)
    assert msg.startswith(start) and needle in msg, msg


def test_powermouse_stands_on_its_legs(pm):
    """Read back: the four legs' feet are the lowest points, coplanar; everything else (the
    post's collar first) stands at least 2 mm above them; the device's centre of mass (solid
    volumes x material densities) lies inside the legs' support polygon."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    from cad.data.materials import get_material

    d, rep, parts = pm
    low, m, mx = {}, 0.0, np.zeros(3)
    for name, solids in parts.items():
        for s in solids:
            b = Bnd_Box()
            BRepBndLib.AddOptimal_s(s, b, False)
            low[name] = min(low.get(name, math.inf), b.CornerMin().Z())
            g = GProp_GProps()
            BRepGProp.VolumeProperties_s(s, g)
            rho = get_material(rep["part_materials"][name]).density_kg_m3
            c = g.CentreOfMass()
            m, mx = m + rho * g.Mass(), mx + rho * g.Mass() * np.array([c.X(), c.Y(), c.Z()])
    feet = [low[f"leg_{k}"] for k in range(1, 5)]
    assert max(feet) - min(feet) < 1e-6
    others = {k: v for k, v in low.items() if not k.startswith("leg_")}
    lowest_other = min(others, key=others.get)
    assert others[lowest_other] - feet[0] == pytest.approx(2.0, abs=1e-3), lowest_other
    assert lowest_other in ("housing_body", "post")
    com = mx / m
    r = rep["geometry_mm"]["housing_inner_half_mm"] + d.stator.housing_wall_mm - 9.0
    assert abs(com[0]) + abs(com[1]) < r - 5.0, com  # inside the diamond of the 4 mid-side feet


def test_following_the_advice_of_a_refusal_gives_a_valid_geometry(geo):
    """The advised limits are rounded inwards: applying the numbers a refusal gives makes the
    geometry valid (no loop); a motion no post can follow names flotor.edge_mm."""
    import dataclasses
    import re

    from cad.errors import DesignError
    from cad.families.powermouse.build import actuator_gap_mm
    from cad.families.powermouse import parts as pp

    d0, _ = geo

    def geometry(**tables):
        d = d0
        for t, ch in tables.items():
            d = dataclasses.replace(d, **{t: dataclasses.replace(getattr(d, t), **ch)})
        return pp.geometry(d, actuator_gap_mm(d))

    for bad in (25.66, 25.84):
        with pytest.raises(DesignError) as e:
            geometry(flotor={"corner_hole_mm": bad})
        (v,) = re.findall(r"use corner_hole_mm [<>]= ([\d.]+)", str(e.value))
        geometry(flotor={"corner_hole_mm": float(v)})
    with pytest.raises(DesignError) as e:
        geometry(flotor={"edge_mm": 60.0})
    post, hole = re.findall(r"post_diameter_mm <= ([\d.]+) with flotor.corner_hole_mm = ([\d.]+)",
                            str(e.value))[0]
    geometry(flotor={"edge_mm": 60.0, "corner_hole_mm": float(hole)},
             stator={"post_diameter_mm": float(post)})
    with pytest.raises(DesignError) as e:
        geometry(motion={"range_deg": 8.0})
    assert str(e.value).startswith("flotor.edge_mm: 64 mm: over the +-3 mm / +-8 deg motion")
