"""Pure-numpy rigid-body algebra checked against direct integration of point-mass clouds.

Reference: for point masses m_i at r_i, m = sum m_i, G = sum m_i r_i / m,
I_P = sum m_i (|r_i - P|^2 E - (r_i - P)(r_i - P)^T) -- evaluated directly here,
independently of cad.massprops.props.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from cad.errors import GeometryError
from cad.massprops.props import (
    InertiaError,
    MassProps,
    check_rotation,
    combine,
    from_principal,
    point_mass,
    rot_x,
    rot_y,
    rot_z,
    rt_from_homogeneous_mm,
    shares_about_kg_m2,
    validate_inertia,
)


def direct(masses: np.ndarray, pts: np.ndarray, about=None):
    """Direct sums over a point-mass cloud: (m, G, I about `about` or about G)."""
    m = masses.sum()
    G = (masses[:, None] * pts).sum(0) / m
    P = G if about is None else np.asarray(about)
    inert = np.zeros((3, 3))
    for mi, ri in zip(masses, pts, strict=True):
        d = ri - P
        inert += mi * (d @ d * np.eye(3) - np.outer(d, d))
    return m, G, inert


def cloud_props(masses, pts) -> MassProps:
    m, G, inert = direct(masses, pts)
    return MassProps(m, G, inert)


def random_cloud(rng, n=40):
    return rng.uniform(0.001, 0.05, n), rng.normal(0, 0.03, (n, 3)) + rng.normal(0, 0.1, 3)


def rel(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return float(np.abs(a - b).max() / max(np.abs(b).max(), 1e-300))


def test_combine_equals_direct_integration():
    rng = np.random.default_rng(1)
    masses, pts = random_cloud(rng, 60)
    groups = np.array_split(np.arange(60), [7, 20, 41])
    parts = [cloud_props(masses[g], pts[g]) for g in groups]
    c = combine(parts)
    m, G, inert = direct(masses, pts)
    assert c.mass_kg == pytest.approx(m, rel=1e-14)
    assert rel(c.com_m, G) < 1e-13
    assert rel(c.inertia_com_kg_m2, inert) < 1e-12
    # point masses combine to the same thing
    c2 = combine([point_mass(mi, ri) for mi, ri in zip(masses, pts, strict=True)])
    assert rel(c2.inertia_com_kg_m2, inert) < 1e-12


def test_two_point_masses_dumbbell_closed_form():
    # two masses m at +-a on x: Iyy = Izz = 2 m a^2, Ixx = 0 (an ideal rod: triangle limit)
    m, a = 0.01, 0.05
    c = combine([point_mass(m, [a, 0, 0]), point_mass(m, [-a, 0, 0])])
    np.testing.assert_allclose(
        c.inertia_com_kg_m2, np.diag([0, 2 * m * a * a, 2 * m * a * a]), atol=1e-20
    )
    assert np.allclose(c.com_m, 0)


def test_parallel_axis_equals_direct():
    rng = np.random.default_rng(2)
    masses, pts = random_cloud(rng)
    p = cloud_props(masses, pts)
    P = np.array([0.2, -0.1, 0.05])
    assert rel(p.inertia_about_kg_m2(P), direct(masses, pts, about=P)[2]) < 1e-12
    shares = shares_about_kg_m2(
        [cloud_props(masses[:10], pts[:10]), cloud_props(masses[10:], pts[10:])], P
    )
    assert rel(shares.sum(0), direct(masses, pts, about=P)[2]) < 1e-12


def test_transformed_equals_direct_on_moved_cloud():
    rng = np.random.default_rng(3)
    masses, pts = random_cloud(rng)
    R = rot_z(0.7) @ rot_y(-1.1) @ rot_x(0.3)
    t = np.array([0.1, 0.2, -0.3])
    moved = cloud_props(masses, pts @ R.T + t)
    got = cloud_props(masses, pts).transformed(R, t)
    assert rel(got.com_m, moved.com_m) < 1e-13
    assert rel(got.inertia_com_kg_m2, moved.inertia_com_kg_m2) < 1e-12


def test_elementary_rotations_match_scipy():
    for f, ax in ((rot_x, "x"), (rot_y, "y"), (rot_z, "z")):
        np.testing.assert_allclose(f(0.4), Rotation.from_euler(ax, 0.4).as_matrix(), atol=1e-15)


def test_homogeneous_split_planar_and_spatial():
    th = 0.3
    T = np.array([[np.cos(th), -np.sin(th), 12.0], [np.sin(th), np.cos(th), -4.0], [0, 0, 1]])
    R, t = rt_from_homogeneous_mm(T)
    np.testing.assert_allclose(R, rot_z(th), atol=1e-15)
    np.testing.assert_allclose(t, [0.012, -0.004, 0.0])
    T4 = np.eye(4)
    T4[:3, :3] = rot_x(1.0)
    T4[:3, 3] = [1, 2, 3]
    R4, t4 = rt_from_homogeneous_mm(T4)
    np.testing.assert_allclose(t4, [0.001, 0.002, 0.003])
    with pytest.raises(GeometryError):
        rt_from_homogeneous_mm(np.eye(2))


def test_check_rotation_rejects_reflection_and_shear():
    with pytest.raises(GeometryError, match="reflection"):
        check_rotation(np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(GeometryError, match="not a rotation"):
        check_rotation(np.diag([1.0, 1.0, 1.01]))


@pytest.mark.parametrize(
    "inert, match",
    [
        (np.diag([1.0, 1.0, -0.1]), "positive definite"),
        (np.diag([1.0, 1.0, 2.5]), "triangle"),
        (np.diag([0.1, 0.1, 1.0]), "triangle"),
        (np.array([[1.0, 0.2, 0], [0.0, 1, 0], [0, 0, 1]]), "symmetric"),
        (np.array([[1.0, 0, 0], [0, np.nan, 0], [0, 0, 1]]), "non-finite"),
        (np.eye(2), "3x3"),
    ],
)
def test_validate_inertia_rejects(inert, match):
    with pytest.raises(InertiaError, match=match):
        validate_inertia(inert, "test part")
    # and MassProps refuses to carry it
    if np.shape(inert) == (3, 3) and np.all(np.isfinite(inert)):
        with pytest.raises(GeometryError):
            MassProps(1.0, np.zeros(3), inert)


def test_validate_inertia_accepts_physical_limits():
    validate_inertia(np.zeros((3, 3)), "point mass")
    validate_inertia(np.diag([0.0, 2.0, 2.0]), "thin rod")
    validate_inertia(np.diag([1.0, 1.0, 2.0]), "thin disc (equality)")
    # a cube's tensor rotated arbitrarily
    R = Rotation.from_quat([0.1, 0.7, -0.3, 0.6]).as_matrix()
    validate_inertia(R @ np.diag([1.0, 2.0, 2.5]) @ R.T, "rotated")


def test_massprops_validates_and_freezes():
    with pytest.raises(GeometryError):
        MassProps(-1.0, np.zeros(3), np.eye(3))
    with pytest.raises(GeometryError):
        MassProps(1.0, np.zeros(2), np.eye(3))
    p = MassProps(1.0, [0, 0, 0], np.eye(3))
    with pytest.raises(ValueError):
        p.com_m[0] = 1.0
    with pytest.raises(GeometryError):
        combine([])
    with pytest.raises(GeometryError, match="zero"):
        combine([point_mass(0.0, [0, 0, 0])])


def test_scaled_and_from_principal():
    R = rot_z(0.5) @ rot_x(0.2)
    p = from_principal(0.2, [0.01, 0, 0], [1e-6, 2e-6, 2.5e-6], R)
    np.testing.assert_allclose(p.principal_moments_kg_m2, [1e-6, 2e-6, 2.5e-6], rtol=1e-12)
    q = p.scaled(2.0)
    assert q.mass_kg == 0.4
    np.testing.assert_allclose(q.inertia_com_kg_m2, 2 * p.inertia_com_kg_m2, rtol=1e-15)
    d = p.to_dict()
    assert d["com_mm"] == pytest.approx([10.0, 0, 0])
    assert d["inertia_com_kg_m2"][0][0] == p.inertia_com_kg_m2[0, 0]  # not rounded


def _rigid(seed: int):
    rng = np.random.default_rng(seed)
    q = rng.normal(size=4)
    R = Rotation.from_quat(q / np.linalg.norm(q)).as_matrix()
    return R, rng.uniform(-0.5, 0.5, 3)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(seed=st.integers(0, 2**32 - 1))
def test_rigid_transform_invariants(seed):
    rng = np.random.default_rng(seed ^ 0x5EED)
    masses, pts = random_cloud(rng, 12)
    parts = [
        cloud_props(masses[:5], pts[:5]),
        cloud_props(masses[5:], pts[5:]),
        point_mass(0.02, [0.1, 0, 0]),
    ]
    R, t = _rigid(seed)
    whole = combine(parts)
    moved = whole.transformed(R, t)
    assert moved.mass_kg == pytest.approx(whole.mass_kg, rel=1e-15)
    np.testing.assert_allclose(
        moved.principal_moments_kg_m2,
        whole.principal_moments_kg_m2,
        rtol=1e-10,
        atol=1e-13 * whole.principal_moments_kg_m2.max(),
    )
    # transforming then combining equals combining then transforming
    alt = combine([p.transformed(R, t) for p in parts])
    assert rel(alt.com_m, moved.com_m) < 1e-12
    assert rel(alt.inertia_com_kg_m2, moved.inertia_com_kg_m2) < 1e-11
    # inverse transform brings it back
    back = moved.transformed(R.T, -R.T @ t)
    assert rel(back.inertia_com_kg_m2, whole.inertia_com_kg_m2) < 1e-11


def test_props_import_is_cad_free():
    code = (
        "import sys, cad.massprops, cad.massprops.props; "
        "print(any(m.split('.')[0] in ('OCP','build123d','cadquery','trimesh','manifold3d') for m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
