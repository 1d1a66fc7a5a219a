"""Exact B-rep mass properties (OCCT) against closed forms; mesh methods against exact.

Closed forms (uniform density rho, about the COM):
box a x b x c: I = m/12 diag(b^2+c^2, a^2+c^2, a^2+b^2);
cylinder R, h (axis z): Izz = m R^2/2, Ixx = m (3R^2 + h^2)/12;
tube Ro, Ri, h: Izz = m (Ro^2+Ri^2)/2, Ixx = m (3(Ro^2+Ri^2) + h^2)/12;
plate with holes: plate minus cylinders, parallel-axis theorem for each hole.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from build123d import Box, Cylinder, Pos, Rot
from scipy.spatial.transform import Rotation

from cad.bench.massprops import stadium_bar_closed_form
from cad.errors import GeometryError, MeshError
from cad.massprops import combine, occt, rot_z
from cad.massprops import mesh as mpmesh
from cad.massprops.occt import solid_mass_props, solids, volume_mm3
from cad.parts.reference_solids import stadium_bar

RHO = 2700.0
TOL = 1e-9


def rel_tensor(got, ref):
    return float(np.abs(np.asarray(got) - ref).max() / np.abs(ref).max())


def box_ref(a, b, c, rho=RHO):
    m = rho * a * b * c * 1e-9
    return m, m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b]) * 1e-6


def cyl_axis_ref(Ro, Ri, h, rho=RHO):
    m = rho * math.pi * (Ro**2 - Ri**2) * h * 1e-9
    ixx = m * (3 * (Ro**2 + Ri**2) + h**2) / 12 * 1e-6
    return m, np.diag([ixx, ixx, m * (Ro**2 + Ri**2) / 2 * 1e-6])


def test_box_rotated_translated_full_tensor_and_sign_convention():
    # A box rotated 30 deg about z: the off-diagonal Ixy is nonzero and its sign checks
    # that OCCT's MatrixOfInertia is already the positive-definite tensor R I0 R^T
    # (products of inertia negated), taken about the COM, not the origin.
    a, b, c = 10.0, 20.0, 30.0
    shape = Pos(100, 50, -20) * Rot(0, 0, 30) * Box(a, b, c)
    p = solid_mass_props(shape, RHO)
    m, I0 = box_ref(a, b, c)
    R = rot_z(math.radians(30))
    assert p.mass_kg == pytest.approx(m, rel=TOL)
    np.testing.assert_allclose(p.com_m, [0.1, 0.05, -0.02], rtol=TOL)
    assert rel_tensor(p.inertia_com_kg_m2, R @ I0 @ R.T) < TOL
    assert p.inertia_com_kg_m2[0, 1] > 0  # = (Iyy0 - Ixx0) sin cos > 0 for b > a
    assert volume_mm3(shape) == pytest.approx(a * b * c, rel=TOL)


def test_cylinder():
    p = solid_mass_props(Cylinder(7.5, 42.0), RHO)
    m, inert = cyl_axis_ref(7.5, 0.0, 42.0)
    assert p.mass_kg == pytest.approx(m, rel=TOL)
    assert rel_tensor(p.inertia_com_kg_m2, inert) < TOL
    assert np.abs(p.com_m).max() < 1e-15


def test_tube():
    shape = Cylinder(10.0, 40.0) - Cylinder(6.0, 40.0)
    p = solid_mass_props(shape, RHO)
    m, inert = cyl_axis_ref(10.0, 6.0, 40.0)
    assert p.mass_kg == pytest.approx(m, rel=TOL)
    assert rel_tensor(p.inertia_com_kg_m2, inert) < TOL


def test_plate_with_off_centre_holes():
    # 60 x 30 x 4 plate, holes r=3 at (-20, 5) and r=5 at (15, -4): COM shifts, Ixy != 0.
    a, b, c = 60.0, 30.0, 4.0
    holes = [((-20.0, 5.0), 3.0), ((15.0, -4.0), 5.0)]
    shape = Box(a, b, c)
    for (x, y), r in holes:
        shape = shape - Pos(x, y, 0) * Cylinder(r, c)
    mp, Ip = box_ref(a, b, c)
    # about the origin: plate minus each hole's (own tensor + parallel-axis term)
    I_o = Ip.copy()
    m_tot, mom = mp, np.zeros(3)
    for (x, y), r in holes:
        mh, Ih = cyl_axis_ref(r, 0.0, c)
        d = np.array([x, y, 0.0]) * 1e-3
        I_o -= Ih + mh * (d @ d * np.eye(3) - np.outer(d, d))
        m_tot -= mh
        mom -= mh * d
    G = mom / m_tot
    I_G = I_o - m_tot * (G @ G * np.eye(3) - np.outer(G, G))
    p = solid_mass_props(shape, RHO)
    assert p.mass_kg == pytest.approx(m_tot, rel=TOL)
    np.testing.assert_allclose(p.com_m, G, rtol=0, atol=TOL * 0.03)  # 0.03 m ~ part size
    assert rel_tensor(p.inertia_com_kg_m2, I_G) < TOL


def test_stadium_bar_matches_bench_closed_form():
    dims = {"L_mm": 80.0, "R_mm": 8.0, "r_mm": 3.0, "T_mm": 6.0}
    p = solid_mass_props(stadium_bar(**dims), RHO)
    m, Idiag = stadium_bar_closed_form(**dims, density_kg_m3=RHO)
    assert p.mass_kg == pytest.approx(m, rel=TOL)
    assert rel_tensor(p.inertia_com_kg_m2, np.diag(Idiag)) < TOL


def _occt_transform(shape, R, t_mm):
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Transform
    from OCP.gp import gp_Trsf

    tr = gp_Trsf()
    tr.SetValues(*R[0], t_mm[0], *R[1], t_mm[1], *R[2], t_mm[2])
    return BRepBuilderAPI_Transform(shape.wrapped, tr, True).Shape()


@pytest.mark.parametrize("seed", [11, 12, 13, 14, 15])
def test_invariance_under_seeded_rigid_transforms(seed):
    rng = np.random.default_rng(seed)
    q = rng.normal(size=4)
    R = Rotation.from_quat(q / np.linalg.norm(q)).as_matrix()
    t_mm = rng.uniform(-200, 200, 3)
    shape = stadium_bar(L_mm=50.0, R_mm=6.0, r_mm=2.5, T_mm=5.0) + Pos(0, 0, 4) * Cylinder(4.0, 6.0)
    base = solid_mass_props(shape, RHO)
    moved = solid_mass_props(_occt_transform(shape, R, t_mm), RHO)  # raw TopoDS_Shape accepted
    pred = base.transformed(R, t_mm * 1e-3)
    assert moved.mass_kg == pytest.approx(base.mass_kg, rel=TOL)
    np.testing.assert_allclose(moved.com_m, pred.com_m, rtol=0, atol=TOL * np.abs(pred.com_m).max())
    assert rel_tensor(moved.inertia_com_kg_m2, pred.inertia_com_kg_m2) < TOL
    np.testing.assert_allclose(
        moved.principal_moments_kg_m2, base.principal_moments_kg_m2, rtol=TOL
    )


def test_combined_parts_in_link_frame_equal_fused_solid():
    # A link made of a bar, a boss and a pin block, each built in its OWN frame, placed by
    # (R, t) into the link frame. combine() of the transformed parts must equal the exact
    # properties of the fused solid built in place (parallel-axis + tensor rotation).
    bar = stadium_bar(L_mm=60.0, R_mm=7.0, r_mm=2.0, T_mm=5.0)
    boss = Cylinder(5.0, 8.0) - Cylinder(2.0, 8.0)
    block = Box(12.0, 6.0, 4.0)
    placements = [
        (np.eye(3), np.zeros(3), bar),
        (np.eye(3), np.array([30.0, 0.0, 6.5]), boss),
        (rot_z(math.radians(35.0)), np.array([0.0, 0.0, -4.5]), block),
    ]
    parts = []
    placed = None
    for R, t, s in placements:
        parts.append(solid_mass_props(s, RHO).transformed(R, t * 1e-3))
        ang = math.degrees(math.atan2(R[1, 0], R[0, 0]))
        ps = Pos(*t) * Rot(0, 0, ang) * s
        placed = ps if placed is None else placed + ps
    assert len(solids(placed)) == 1  # really fused
    fused = solid_mass_props(placed, RHO)
    comb = combine(parts)
    assert comb.mass_kg == pytest.approx(fused.mass_kg, rel=TOL)
    np.testing.assert_allclose(comb.com_m, fused.com_m, rtol=0, atol=TOL * 0.03)
    assert rel_tensor(comb.inertia_com_kg_m2, fused.inertia_com_kg_m2) < TOL


def test_compound_of_disjoint_solids_equals_combine():
    from build123d import Compound

    a = Pos(-30, 0, 0) * Box(10, 12, 14)
    b = Pos(25, 10, 3) * Rot(40, 0, 10) * Cylinder(6, 20)
    comp = Compound([a, b])
    assert len(solids(comp)) == 2
    whole = solid_mass_props(comp, RHO)
    comb = combine([solid_mass_props(a, RHO), solid_mass_props(b, RHO)])
    assert whole.mass_kg == pytest.approx(comb.mass_kg, rel=TOL)
    assert rel_tensor(whole.inertia_com_kg_m2, comb.inertia_com_kg_m2) < TOL


def test_bad_inputs():
    from build123d import Rectangle

    with pytest.raises(GeometryError, match="no solid"):
        solid_mass_props(Rectangle(10, 10), RHO)
    with pytest.raises(GeometryError, match="density"):
        solid_mass_props(Box(1, 1, 1), 0.0)
    with pytest.raises(GeometryError, match="expected"):
        solid_mass_props("box", RHO)


def test_mesh_methods_converge_to_exact():
    shape = Cylinder(10.0, 40.0) - Cylinder(6.0, 40.0)
    exact = solid_mass_props(shape, RHO)
    errs_m, errs_i = [], []
    for tol in (0.1, 0.03, 0.01):
        a = mpmesh.occt_triangulation_mass_props(shape, RHO, tol, check_watertight=True)
        b = mpmesh.trimesh_mass_props(shape, RHO, tol)
        c = mpmesh.manifold_shape_volume_mm3(shape, tol)
        assert a.watertight and b.watertight and c.watertight
        # same polyhedron, two integrators: OCCT and trimesh agree to round-off
        assert b.props.mass_kg == pytest.approx(a.props.mass_kg, rel=1e-9)
        assert rel_tensor(b.props.inertia_com_kg_m2, a.props.inertia_com_kg_m2) < 1e-9
        assert c.volume_mm3 == pytest.approx(b.volume_mm3, rel=1e-9)
        errs_m.append(abs(a.props.mass_kg / exact.mass_kg - 1))
        errs_i.append(abs(a.props.inertia_com_kg_m2[2, 2] / exact.inertia_com_kg_m2[2, 2] - 1))
        # a chordal mesh of a tube loses volume on the outside, gains on the inside bore:
        # net it lies below (outer circumference dominates)
        assert a.props.mass_kg < exact.mass_kg
    assert errs_m[0] > errs_m[1] > errs_m[2] and errs_i[0] > errs_i[1] > errs_i[2]
    # chordal error ~ tol / R: at 0.01 mm on R = 6..10 mm the mass is within 1e-3
    assert errs_m[2] < 1e-3 and errs_i[2] < 3e-3


def test_non_watertight_mesh_raises():
    v, f = occt.extract_arrays(occt.triangulate(Box(10, 20, 30), 0.1))
    f_open = f[1:]  # drop one triangle: an open hole
    with pytest.raises(MeshError, match="not watertight"):
        mpmesh.mesh_arrays_mass_props(v, f_open, RHO)
    with pytest.raises(MeshError):
        mpmesh.manifold_volume_mm3(v, f_open)
    res = mpmesh.mesh_arrays_mass_props(v, f_open, RHO, allow_open=True)
    assert res.watertight is False
    closed = mpmesh.mesh_arrays_mass_props(v, f, RHO)
    assert closed.watertight and closed.volume_mm3 == pytest.approx(6000.0, rel=1e-12)


def test_mesh_bad_tolerance():
    with pytest.raises(GeometryError, match="tolerance"):
        occt.triangulate(Box(1, 1, 1), 0.0)
    with pytest.raises(GeometryError, match="angular"):
        occt.triangulate(Box(1, 1, 1), 0.1, 4.0)
