"""Interference sweep: exact clearance and overlap against closed forms; the fast pass's
shortcuts (z culling, pose-invariant joint parts) change nothing; the layer planner."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cad.errors import InterferenceError

R_FIXED = 5.0
H = 5.0


def cylinder(r: float, h: float = H):
    from build123d import Align, Cylinder

    return Cylinder(r, h, align=(Align.CENTER, Align.CENTER, Align.MIN)).solids()[0].wrapped


def translations(xs):
    """(N,4,4) pure x translations (planar motion)."""
    T = np.repeat(np.eye(4)[None], len(xs), axis=0)
    T[:, 0, 3] = xs
    return T


def two_cylinder_sweep(
    r_moving: float, n: int = 7, exact: bool = True, method: str = "auto", tol: float = 0.05
):
    """Fixed cylinder (r = 5) at the origin; a moving one whose centre runs along x with
    x(phi) = 10 + (phi - 0.3)^2: closest at phi = 0.3, centre distance 10 mm."""
    from cad.assembly import interference as itf

    items = [
        ("fixed", "ground", cylinder(R_FIXED), np.eye(4)),
        ("moving", "crank", cylinder(r_moving), np.eye(4)),
    ]
    prep = itf.prepare(items, tol)
    phi = np.linspace(0.0, 1.0, n)  # 0.3 is not a sample

    def x_of(p):
        return 10.0 + (np.asarray(p) - 0.3) ** 2

    tfs = {"ground": translations(np.zeros(n)), "crank": translations(x_of(phi))}

    def tf_at(p):
        return {"ground": np.eye(4), "crank": translations([x_of(p)])[0]}

    return itf.sweep(prep, tfs, phi, clearance_min_mm=0.5, exact=exact, method=method, tf_at=tf_at)


def lens_area(r1: float, r2: float, d: float) -> float:
    """Area of the intersection of two circles (radii r1, r2, centre distance d)."""
    a1 = r1 * r1 * math.acos((d * d + r1 * r1 - r2 * r2) / (2 * d * r1))
    a2 = r2 * r2 * math.acos((d * d + r2 * r2 - r1 * r1) / (2 * d * r2))
    k = 0.5 * math.sqrt((-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2))
    return a1 + a2 - k


def test_exact_clearance_between_samples_is_found():
    rep = two_cylinder_sweep(4.0)
    # gap at the closest pose: 10 - 5 - 4 = 1 mm, reached between the samples (refined)
    assert rep.min_clearance_mm == pytest.approx(1.0, abs=1e-6)
    assert rep.closest["phi1_deg"] == pytest.approx(math.degrees(0.3), abs=0.05)
    assert rep.overlap_volume_mm3 == 0.0 and rep.collisions == []


def test_overlap_volume_is_the_lens_times_the_height():
    r2 = 5.05  # 0.05 mm overlap at the closest pose
    rep = two_cylinder_sweep(r2, n=11)
    assert rep.min_clearance_mm == 0.0
    assert rep.overlap_volume_mm3 == pytest.approx(lens_area(R_FIXED, r2, 10.0) * H, rel=1e-6)
    with pytest.raises(InterferenceError, match="collide"):
        from cad.assembly.interference import raise_on_collision

        raise_on_collision(rep, 0.5)


@pytest.mark.parametrize("r2", [4.0, 4.7, 4.95])
def test_mesh_distance_is_within_twice_the_tolerance_of_the_exact_one(r2):
    """The bound the exact pass relies on to pick the near contacts it confirms."""
    tol = 0.2
    mesh_only = two_cylinder_sweep(r2, n=11, exact=False, tol=tol)
    exact_gap = 10.0 - R_FIXED - r2
    assert abs(mesh_only.pairs[0]["mesh_min_mm"] - exact_gap) <= 2 * tol
    assert mesh_only.method.endswith("(mesh only)")


def test_clearance_below_the_minimum_is_an_interference():
    rep = two_cylinder_sweep(4.7)  # 0.3 mm gap < 0.5 mm minimum
    assert rep.min_clearance_mm == pytest.approx(0.3, abs=1e-6)
    from cad.assembly.interference import raise_on_collision

    with pytest.raises(InterferenceError, match="0.300 mm apart"):
        raise_on_collision(rep, 0.5)


def test_manifold3d_fast_pass_agrees_with_fcl():
    a = two_cylinder_sweep(4.0, method="fcl", exact=False)
    b = two_cylinder_sweep(4.0, method="manifold3d", exact=False)
    assert a.pairs[0]["mesh_min_mm"] == pytest.approx(b.pairs[0]["mesh_min_mm"], abs=2 * 0.05)


def test_joint_shortcut_and_z_culling_change_no_distance():
    """A pin turning inside a ring (solids of revolution about the joint) next to a bar,
    and a far plate below: the sweep with the joint shortcut equals the plain sweep, and
    the exact pass gives the true 0.5 mm gap either way."""
    from build123d import Align, Box, Cylinder, Pos

    from cad.assembly import interference as itf
    from cad.parts import translation

    a = (Align.CENTER, Align.CENTER, Align.MIN)
    ring = (Cylinder(6.0, H, align=a) - Cylinder(4.5, H, align=a)).solids()[0].wrapped
    pin = Cylinder(4.0, H + 4, align=a).solids()[0].wrapped
    bar = (
        (Pos(25, 0, H + 1) * Box(40, 8, 3, align=(Align.CENTER, Align.CENTER, Align.MIN)))
        .solids()[0]
        .wrapped
    )
    plate = (Pos(0, 0, -30) * Box(100, 100, 2)).solids()[0].wrapped
    items = [
        ("ring", "rocker", ring, np.eye(4), True),
        ("bar", "rocker", bar, np.eye(4), False),
        ("pin", "ground", pin, translation(0, 0, -2), True),
        ("plate", "ground", plate, np.eye(4), False),
        (
            "block",
            "ground",
            (Pos(0, -40, H + 1) * Box(6, 6, 3, align=a)).solids()[0].wrapped,
            np.eye(4),
            False,
        ),
    ]
    prep = itf.prepare(items, 0.05)
    phi = np.linspace(-0.6, 0.6, 9)
    c, s = np.cos(phi), np.sin(phi)
    rot = np.repeat(np.eye(4)[None], len(phi), axis=0)
    rot[:, 0, 0], rot[:, 0, 1], rot[:, 1, 0], rot[:, 1, 1] = c, -s, s, c
    tfs = {"ground": translations(np.zeros(len(phi))), "rocker": rot}
    plain = itf.sweep(prep, tfs, phi, 0.5, exact=False)
    fast = itf.sweep(
        prep, tfs, phi, 0.5, exact=False, joints={("ground", "rocker"): [((0, 0), (0, 0))]}
    )
    # exact for the true solids of revolution; the faceted meshes turn against each other,
    # so the two agree to within the mesh deflection of both parts
    assert fast.pairs[0]["mesh_min_mm"] == pytest.approx(
        plain.pairs[0]["mesh_min_mm"], abs=2 * 0.05
    )
    # closest: the pin inside the ring, 0.5 mm (4.0 vs 4.5) at every pose
    assert plain.pairs[0]["mesh_min_mm"] == pytest.approx(0.5, abs=2 * 0.05)
    exact = itf.sweep(
        prep, tfs, phi, 0.4, exact=True, joints={("ground", "rocker"): [((0, 0), (0, 0))]}
    )
    assert exact.min_clearance_mm == pytest.approx(0.5, abs=1e-9)
    assert exact.closest["parts"] == ["pin", "ring"]


def test_non_planar_transforms_are_refused():
    from cad.assembly import interference as itf

    prep = itf.prepare(
        [("a", "ground", cylinder(1.0), np.eye(4)), ("b", "crank", cylinder(1.0), np.eye(4))], 0.1
    )
    T = translations([0.0, 1.0])
    T[:, 2, 3] = [0.0, 1.0]  # moves in z
    with pytest.raises(InterferenceError, match="planar"):
        itf.sweep(prep, {"ground": translations([0.0, 0.0]), "crank": T}, np.array([0.0, 1.0]), 0.5)


# ------------------------------------------------------------ layer planner (numpy only)
@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-50, 50), min_size=12, max_size=12))
def test_hull_distance_matches_dense_sampling(vals):
    """Distance between convex hulls of 3 + 2 points vs sampling both hulls densely."""
    from cad.families.fourbar.layers import hull_distance

    pa = np.array(vals[:6]).reshape(1, 3, 2)
    pb = np.array(vals[6:10]).reshape(1, 2, 2)
    d = float(hull_distance(pa, pb)[0])
    # sample the triangle (barycentric grid) and the segment
    u = np.linspace(0, 1, 41)
    U, V = np.meshgrid(u, u)
    m = (U + V) <= 1
    tri = pa[0, 0] + U[m, None] * (pa[0, 1] - pa[0, 0]) + V[m, None] * (pa[0, 2] - pa[0, 0])
    seg = pb[0, 0] + u[:, None] * (pb[0, 1] - pb[0, 0])
    brute = np.min(np.linalg.norm(tri[:, None, :] - seg[None, :, :], axis=-1))
    span = max(np.ptp(pa[0], axis=0).max(), np.ptp(pb[0], axis=0).max(), 1e-9)
    assert d <= brute + 1e-9
    assert brute - d <= 2.0 * span / 40  # sampling resolution


@pytest.mark.parametrize("fam", ["hoeken", "roberts", "chebyshev", "chebyshev-v"])
def test_layer_plan_is_conflict_free_for_the_paper_families(fam):
    from cad.design.parts import PartsSpec
    from cad.families.fourbar.layers import choose_layers
    from cad.families.fourbar.pose import planar_transforms
    from cad.kinematics.families import family_linkage
    from cad.kinematics.linkgeom import link_joints_mm

    fb, lo, hi = family_linkage(fam)
    p = PartsSpec()
    plan = choose_layers(link_joints_mm(fb), p, planar_transforms(fb, np.linspace(lo, hi, 60)))
    assert plan.conflicts == ()
    assert plan.min_planar_clearance_mm >= p.clearance_min_mm
    assert sorted(plan.order) == ["coupler", "crank", "rocker"]


def _two_cylinder_model(r_moving: float, n: int):
    """The two cylinders of :func:`two_cylinder_sweep` as an AssemblyModel (bodies ground and
    crank; motion over the n crank angles)."""
    from cad.assembly.model import AssemblyModel
    from cad.parts import PartInstance, PartKind

    def kind(name, r):
        return PartKind(name=name, shape=cylinder(r), material="steel-1018", made=True)

    phi = np.linspace(0.0, 1.0, n)
    x = 10.0 + (phi - 0.3) ** 2
    inst = (PartInstance("fixed", kind("fixed", R_FIXED), "ground"),
            PartInstance("moving", kind("moving", r_moving), "crank"))
    motion = {"ground": translations(np.zeros(n)), "crank": translations(x)}
    labels = tuple(f"phi1 = {math.degrees(p):.1f} deg" for p in phi)
    return AssemblyModel(None, inst, {"ground": np.eye(4), "crank": motion["crank"][0]}, motion,
                         labels), phi


@pytest.mark.parametrize("r2", [4.0, 5.05])
def test_check_model_on_crank_angles_equals_the_sweep(r2):
    """The one check over an assembly model, given the crank angles (the four-bar's call),
    reports what :func:`sweep` reports on the same solids: the closest pose refined between
    samples, the overlap (lens x height at the closest pose), the same pairs."""
    from cad.assembly import interference as itf

    model, phi = _two_cylinder_model(r2, 11)

    def tf_at(p):
        return {"ground": np.eye(4), "crank": translations([10.0 + (p - 0.3) ** 2])[0]}

    a = two_cylinder_sweep(r2, n=11)
    b = itf.check_model(model, 0.5, contact_ok=False, phi1_rad=phi, tf_at=tf_at)
    assert b.min_clearance_mm == pytest.approx(a.min_clearance_mm, abs=1e-12)
    assert b.overlap_volume_mm3 == pytest.approx(a.overlap_volume_mm3, rel=1e-12)
    assert b.pairs == a.pairs and b.collisions == a.collisions
    assert b.same_body["collisions"] == []


def test_labelled_six_dof_motion_names_the_clash_pose_and_volume():
    """General (non-planar) motion by label: a 10 mm cube over a fixed 10 mm cube, lowered
    0.5 mm into it at one pose only (overlap 10 x 10 x 0.5 = 50 mm^3, the closed form), tilted
    and clear at another; touching is allowed (contact_ok)."""
    from build123d import Align, Box

    from cad.assembly import interference as itf
    from cad.assembly.model import AssemblyModel
    from cad.parts import PartInstance, PartKind

    cube = Box(10, 10, 10, align=(Align.CENTER, Align.CENTER, Align.MIN)).solids()[0].wrapped
    k = PartKind(name="cube", shape=cube, material="steel-1018", made=True)
    inst = (PartInstance("base", k, "ground"), PartInstance("top", k, "lid"))
    poses = {"resting": (np.eye(3), 10.0), "pressed": (np.eye(3), 9.5)}
    c, s = math.cos(0.3), math.sin(0.3)
    poses["tilted"] = (np.array([[1, 0, 0], [0, c, -s], [0, s, c]]), 20.0)
    T = np.repeat(np.eye(4)[None], 3, axis=0)
    for i, (R, z) in enumerate(poses.values()):
        T[i, :3, :3], T[i, 2, 3] = R, z
    model = AssemblyModel(None, inst, {"ground": np.eye(4), "lid": T[0]}, {"lid": T},
                          tuple(poses))
    rep = itf.check_model(model)
    assert [x["pose"] for x in rep.collisions] == ["pressed"]
    assert rep.collisions[0]["parts_overlap_volume_mm3"] == pytest.approx(50.0, rel=1e-9)
    assert rep.poses["resting"][0] == 0.0 and rep.poses["tilted"][0] > 0.0
    with pytest.raises(InterferenceError, match=r"base / top collide at pose pressed \(overlap 50\.000 mm\^3\)"):
        itf.raise_on_collision(rep, 0.0)


def _ring(r_in: float, r_out: float):
    from build123d import Align, Cylinder

    a = (Align.CENTER, Align.CENTER, Align.MIN)
    return (Cylinder(r_out, H, align=a) - Cylinder(r_in, H, align=a)).solids()[0].wrapped


def _bearing_model(inner_offset_mm: float = 0.0):
    """A bearing at the crank's pivot (outer ring r 4..6 in the ground, inner ring r 1..3 on the
    crank, ``inner_offset_mm`` off its axis along the crank's x), a post r 2 at x = 20 in the
    ground and an arm r 2 at x = 14 on the crank, which turns about z by -0.4 .. 0.4 rad (0 a
    sample); below them a motor (its housing's bore r 3.5) in the ground and its shaft (r 3,
    ``part_of`` the motor) on the crank."""
    from cad.assembly.model import AssemblyModel
    from cad.parts import PartInstance, PartKind, translation

    brg = PartKind(name="bearing", shape=_ring(1.0, 6.0), material="steel-1018", made=False,
                   collision=(("self", _ring(4.0, 6.0)), ("other", _ring(1.0, 3.0))), revolution=True)
    post = PartKind(name="post", shape=cylinder(2.0), material="steel-1018", made=True)
    motor = PartKind(name="motor", shape=_ring(3.5, 5.0), material="steel-1018", made=False)
    shaft = PartKind(name="shaft", shape=cylinder(3.0), material="steel-1018", made=False, listed=False,
                     revolution=True)
    inst = (PartInstance("bearing", brg, "ground", np.eye(4), "crank", translation(inner_offset_mm)),
            PartInstance("post", post, "ground", translation(20.0)),
            PartInstance("arm", post, "crank", translation(14.0)),
            PartInstance("motor", motor, "ground", translation(0, 0, -10.0)),
            PartInstance("motor.shaft", shaft, "crank", translation(0, 0, -10.0), part_of="motor"))
    th = np.linspace(-0.4, 0.4, 9)
    T = np.repeat(np.eye(4)[None], len(th), axis=0)
    T[:, 0, 0], T[:, 0, 1], T[:, 1, 0], T[:, 1, 1] = np.cos(th), -np.sin(th), np.sin(th), np.cos(th)
    motion = {"ground": np.repeat(np.eye(4)[None], len(th), axis=0), "crank": T}
    return AssemblyModel(None, inst, {"ground": np.eye(4), "crank": T[4]}, motion,
                         tuple(f"theta = {t:.1f} rad" for t in th))


def test_smallest_clearance_is_between_two_parts_not_inside_a_bearing():
    """A bearing's own ring gap (1 mm: inner ring's 3 mm to the outer ring's 4 mm) and a motor
    shaft's gap in its housing (0.5 mm: 3 to 3.5 mm) are the maker's, inside one bought part:
    the smallest clearance is the arm's to the post, 20 - 14 - 2 - 2 = 2 mm at theta = 0 (closed
    form; the arm's to the outer ring 14 - 2 - 6 = 6 mm), naming those two parts; the gaps are
    reported apart (own_part_gaps, the smallest 0.5 mm) and still checked: rings pushed 1.5 mm
    off their common axis overlap (3 + 1.5 > 4) and that is a collision naming the bearing's
    rings."""
    from cad.assembly import interference as itf

    rep = itf.check_model(_bearing_model())
    assert rep.min_clearance_mm == pytest.approx(2.0, abs=1e-6)
    assert sorted(rep.closest["parts"]) == ["arm", "post"] and rep.collisions == []
    own = rep.as_dict()["own_part_gaps"]
    assert own["pairs"] == 2 and own["min_gap_mm"] == pytest.approx(0.5, abs=1e-6)
    assert sorted(own["parts"]) == ["motor", "motor.shaft"]
    bad = itf.check_model(_bearing_model(1.5))
    assert bad.min_clearance_mm == pytest.approx(2.0, abs=1e-6)
    assert bad.overlap_volume_mm3 > 0.0
    assert [sorted(c["parts"]) for c in bad.collisions] == [["bearing[inner]", "bearing[outer]"]]
