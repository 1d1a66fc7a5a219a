"""Stability of the mass properties where their methods break (issue 7 §3).

Edges: meshes that are open, inside-out, inconsistently wound, flat (zero
volume), made of or containing zero-area triangles, non-finite, or indexed out
of range (trimesh, manifold3d and ``hapticad massprops`` on STL); B-rep shapes
with no solid, empty booleans, booleans that fail on an invalid operand, and
invalid solids that OCCT integrates without complaint (BRepCheck must catch
them); inertia tensors that are not physical, in any frame.

References: closed forms of the box and the unit right tetrahedron
(V = 1/6, COM = (1/4, 1/4, 1/4), I_xx,G = 1/80, I_xy,G = 1/480 per unit density,
from integral x^2 dV = 1/60 and integral x y dV = 1/120), and the box volume
that an invalid solid gets wrong.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from build123d import Box, Cylinder, Face, Polyline, Pos, Shell, Solid, Wire, extrude
from cli_helpers import assert_one_line_error, hapticad
from scipy.spatial.transform import Rotation

from cad.errors import GeometryError, MeshError
from cad.massprops import mesh as mpmesh
from cad.massprops import occt
from cad.massprops.props import InertiaError, MassProps, validate_inertia

RHO = 1000.0  # kg/m^3

# unit right tetrahedron, outward (counter-clockwise seen from outside) winding
TET_V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
TET_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def _tet_reference():
    """Mass properties of the unit tetrahedron at RHO, SI (closed form, see module doc)."""
    m = RHO * (1 / 6) * 1e-9
    inert = np.full((3, 3), 1 / 480) + np.eye(3) * (1 / 80 - 1 / 480)  # mm^5, unit density
    return m, np.full(3, 0.25e-3), RHO * inert * 1e-15


def _box_mesh():
    b = trimesh.creation.box((10.0, 20.0, 30.0))
    return np.asarray(b.vertices, float), np.asarray(b.faces, np.int64)


# --------------------------------------------------------------------------- meshes


def test_tetrahedron_reference_is_right():
    """The trimesh path reproduces the closed form exactly (the reference used below)."""
    m, com, inert = _tet_reference()
    r = mpmesh.mesh_arrays_mass_props(TET_V, TET_F, RHO)
    assert r.props.mass_kg == pytest.approx(m, rel=1e-12)
    np.testing.assert_allclose(r.props.com_m, com, rtol=1e-12)
    np.testing.assert_allclose(r.props.inertia_com_kg_m2, inert, rtol=1e-10, atol=1e-30)


def test_zero_area_triangle_in_a_closed_mesh_changes_nothing():
    """Split the edge 0-1 at its midpoint and close the crack with a zero-area triangle
    (0, 1, m): still watertight and consistently wound; volume and inertia are exactly
    the tetrahedron's (a degenerate triangle adds nothing to the divergence integrals)."""
    V = np.vstack([TET_V, [[0.5, 0.0, 0.0]]])
    F = np.array([[0, 2, 1], [0, 4, 3], [4, 1, 3], [0, 3, 2], [1, 2, 3], [0, 1, 4]])
    r = mpmesh.mesh_arrays_mass_props(V, F, RHO)
    m, com, inert = _tet_reference()
    assert r.watertight and r.props.mass_kg == pytest.approx(m, rel=1e-12)
    np.testing.assert_allclose(r.props.inertia_com_kg_m2, inert, rtol=1e-10, atol=1e-30)
    assert mpmesh.manifold_volume_mm3(V, F).volume_mm3 == pytest.approx(1 / 6, rel=1e-12)


@pytest.mark.parametrize(
    "V, F, needle",
    [
        (TET_V, TET_F[:, ::-1], "inside-out"),  # every triangle flipped: volume -1/6
        (np.vstack([TET_V[:3], [[0.3, 0.3, 0.0]]]), TET_F, "inside-out or degenerate"),  # flat
        (np.array([[0.0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 0, 1]]), TET_F, "degenerate"),
    ],
    ids=["inside-out", "zero-volume", "zero-area-triangles"],
)
def test_degenerate_closed_meshes_are_mesh_errors(V, F, needle):
    """Inside-out or zero volume: both integrators refuse, even with allow_open; no NaN
    (trimesh divides by the volume for the COM: it used to emit RuntimeWarnings and NaN)."""
    for call in (
        lambda: mpmesh.mesh_arrays_mass_props(V, F, RHO),
        lambda: mpmesh.mesh_arrays_mass_props(V, F, RHO, allow_open=True),
        lambda: mpmesh.manifold_volume_mm3(V, F),
    ):
        with pytest.raises(MeshError, match=needle):
            call()


def test_one_flipped_triangle_is_caught():
    """A closed box with one triangle wound inwards is still 'watertight' to trimesh and
    integrates to 3000 of 6000 mm^3; the tool names the inconsistent winding instead."""
    V, F = _box_mesh()
    assert mpmesh.mesh_arrays_mass_props(V, F, RHO).volume_mm3 == pytest.approx(6000.0, rel=1e-12)
    F = F.copy()
    F[0] = F[0, ::-1]
    with pytest.raises(MeshError, match="inconsistent winding"):
        mpmesh.mesh_arrays_mass_props(V, F, RHO)
    with pytest.raises(MeshError):
        mpmesh.manifold_volume_mm3(V, F)


def test_open_mesh_refused_unless_allowed_and_never_nan():
    """Non-watertight: MeshError by default; with allow_open trimesh gives a finite result
    flagged watertight=False, and manifold3d (which has no volume for it) raises instead of
    the NaN volume it used to return."""
    V, F = _box_mesh()
    F_open = F[1:]
    with pytest.raises(MeshError, match="not watertight"):
        mpmesh.mesh_arrays_mass_props(V, F_open, RHO)
    r = mpmesh.mesh_arrays_mass_props(V, F_open, RHO, allow_open=True)
    assert r.watertight is False and np.isfinite(r.volume_mm3) and r.volume_mm3 > 0
    assert np.all(np.isfinite(r.props.inertia_com_kg_m2))
    with pytest.raises(MeshError, match="manifold3d rejects"):
        mpmesh.manifold_volume_mm3(V, F_open, allow_open=True)


@pytest.mark.parametrize(
    "mutate, needle",
    [
        (
            lambda V, F: (np.where(np.arange(V.size).reshape(V.shape) == 4, np.nan, V), F),
            "vertex 1 is not finite",
        ),
        (
            lambda V, F: (np.where(np.arange(V.size).reshape(V.shape) == 0, np.inf, V), F),
            "vertex 0 is not finite",
        ),
        (lambda V, F: (V * 1e12, F), "beyond"),
        (lambda V, F: (V, F + 8), "face indices must lie in"),
        (lambda V, F: (V, F - 1), "face indices must lie in"),
        (lambda V, F: (V, F + 0.5), "must be integers"),
        (lambda V, F: (V[:, :2], F), "must be (N, 3) vertices"),
        (lambda V, F: (V, F[:0]), "M>0"),
    ],
    ids=["nan", "inf", "huge", "index-high", "index-negative", "float-index", "2d", "empty"],
)
def test_malformed_mesh_arrays_are_mesh_errors(mutate, needle):
    """Used to be IndexError, silent truncation of float indices, or RuntimeWarnings."""
    V, F = mutate(*_box_mesh())
    for call in (
        lambda: mpmesh.mesh_arrays_mass_props(V, F, RHO, allow_open=True),
        lambda: mpmesh.manifold_volume_mm3(V, F, allow_open=True),
    ):
        with pytest.raises(MeshError, match=needle.replace("(", r"\(").replace(")", r"\)")):
            call()


@pytest.mark.parametrize(
    "mutate, needle",
    [
        (lambda V, F: F[:, ::-1], "inside-out"),
        (lambda V, F: np.vstack([F[:1, ::-1], F[1:]]), "inconsistent winding"),
    ],
)
def test_cli_stl_degenerate_exit_2_one_line(tmp_path, mutate, needle):
    """``hapticad massprops`` on an inside-out or mis-wound STL: exit 2, one line, no output
    (an open STL only warns: tests/cli/test_massprops_cli.py)."""
    V, F = _box_mesh()
    p = tmp_path / "bad.stl"
    trimesh.Trimesh(V, mutate(V, F), process=False).export(p)
    code, out, err = hapticad("massprops", p, "--density", "1000", "--json")
    assert_one_line_error(code, err, needle)
    assert out == ""


# --------------------------------------------------------------------------- B-rep


def _open_box():
    """A 'solid' whose shell lacks one face of the 10 x 20 x 30 box."""
    return Solid(Shell(Box(10, 20, 30).faces()[:5]))


def _bowtie_prism():
    """A prism on a self-intersecting (bow-tie) profile: BRepCheck SelfIntersectingWire."""
    return extrude(Face(Wire(Polyline((0, 0), (10, 10), (10, 0), (0, 10), close=True).edges())), 5)


def test_invalid_solids_integrate_silently_without_the_check():
    """Why the check exists: OCCT's volume integration raises nothing on invalid solids and
    returns a wrong volume (open box: 4800 instead of 6000 mm^3)."""
    vol = occt.solid_mass_props(_open_box(), RHO, check=False).mass_kg / RHO * 1e9
    assert vol == pytest.approx(4800.0, rel=1e-9) and vol != pytest.approx(6000.0, rel=0.1)


@pytest.mark.parametrize(
    "make, needle",
    [
        (_open_box, "shell 0: NotClosed"),
        (_bowtie_prism, "SelfIntersectingWire"),
        (lambda: Box(30, 30, 30) - _bowtie_prism(), "SelfIntersectingWire"),
        (lambda: _open_box() + Pos(5, 0, 0) * Box(10, 10, 10), "NotClosed"),
    ],
    ids=["open-shell", "self-intersecting", "cut-by-invalid-tool", "fuse-with-open-solid"],
)
def test_invalid_solids_and_failed_booleans_are_geometry_errors(make, needle):
    """BRepCheck names what is wrong. Without it: the cut by a self-intersecting tool keeps
    all 27000 mm^3 of the box, the fuse with an open solid gives 5409 mm^3."""
    with pytest.raises(GeometryError, match=needle) as ei:
        occt.solid_mass_props(make(), RHO)
    assert "not a valid solid" in str(ei.value) and "\n" not in str(ei.value)


@pytest.mark.parametrize(
    "make, needle",
    [
        (lambda: Box(1, 1, 1) & (Pos(10, 0, 0) * Box(1, 1, 1)), "empty"),
        (lambda: Box(10, 10, 10) - Box(20, 20, 20), "no solid"),
        (lambda: Shell(Box(10, 20, 30).faces()), "no solid"),
        (lambda: Box(10, 20, 30).faces()[0], "no solid"),
        (lambda: Box(10, 20, 30).edges()[0], "no solid"),
    ],
    ids=["intersection-of-disjoint", "cut-everything", "shell", "face", "edge"],
)
def test_shapes_without_a_solid_are_geometry_errors(make, needle):
    """An empty boolean used to escape as build123d's bare AssertionError."""
    for call in (lambda s: occt.solid_mass_props(s, RHO), occt.volume_mm3):
        with pytest.raises(GeometryError, match=needle):
            call(make())


def test_valid_booleans_pass_the_check_with_exact_values():
    """The check rejects nothing valid: a bored plate integrates to its closed form."""
    plate = Box(40, 20, 6) - Pos(10, 0, 0) * Cylinder(4, 6)
    assert occt.validity_problems(plate) == []
    mp = occt.solid_mass_props(plate, RHO)
    vol = 40 * 20 * 6 - np.pi * 16 * 6
    assert mp.mass_kg == pytest.approx(RHO * vol * 1e-9, rel=1e-12)
    assert mp.com_m[0] == pytest.approx(-(np.pi * 16 * 6 * 10.0) / vol * 1e-3, rel=1e-12)


# --------------------------------------------------------------------------- tensors


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize(
    "moments, needle",
    [
        ((1.0, 1.0, -0.1), "positive definite"),
        ((1.0, 1.0, 2.5), "triangle"),
        ((0.1, 0.1, 1.0), "triangle"),
    ],
)
def test_non_physical_tensors_are_caught_in_any_frame(seed, moments, needle):
    """The checks are frame-free (eigenvalues): the same defect under seeded random
    rotations is named the same way, and MassProps refuses it."""
    R = Rotation.random(random_state=seed).as_matrix()
    inert = R @ np.diag(moments) @ R.T
    with pytest.raises(InertiaError, match=needle):
        validate_inertia(inert, "rotated")
    with pytest.raises(GeometryError):
        MassProps(1.0, np.zeros(3), inert)


def test_triangle_inequality_threshold():
    """Eps = INERTIA_REL_EPS * trace: a thin disc (I3 = I1 + I2) and a violation of 1e-12
    relative are accepted (round-off), a violation of 1e-6 relative is not."""
    validate_inertia(np.diag([1.0, 1.0, 2.0 * (1 + 1e-12)]), "disc + round-off")
    with pytest.raises(InertiaError, match="triangle"):
        validate_inertia(np.diag([1.0, 1.0, 2.0 * (1 + 1e-6)]), "disc + 1e-6")


@pytest.mark.parametrize(
    "inert, needle",
    [
        (np.diag([1.0, np.inf, 1.0]), "non-finite"),
        (np.full((3, 3), np.nan), "non-finite"),
        (np.eye(3) + np.array([[0, 1e-6, 0], [0, 0, 0], [0, 0, 0]]), "not symmetric"),
        (np.zeros((3, 2)), "3x3"),
    ],
)
def test_malformed_tensors_are_named(inert, needle):
    with pytest.raises(InertiaError, match=needle):
        validate_inertia(inert, "part X")
    with pytest.raises(InertiaError, match="part X"):
        validate_inertia(inert, "part X")
