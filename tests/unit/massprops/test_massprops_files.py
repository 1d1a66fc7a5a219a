"""Mass properties of the files people have (issue 12 §2), each case folder a test.

References: closed forms of a 10 x 20 x 30 mm box (V = 6000 mm^3, COM at its centre,
principal moments at 1000 kg/m^3 = m (b^2 + c^2) / 12 ... = [2.5e-7, 5.0e-7, 6.5e-7] kg m^2).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import assert_one_line_error, hapticad

from cad.massprops.mesh import mesh_arrays_mass_props

CASES = Path(__file__).resolve().parents[2] / "cases"  # copies of ../shared/cases
BOX_PRINCIPAL = [2.5e-7, 5.0e-7, 6.5e-7]


def _massprops(path, *extra):
    code, out, err = hapticad("massprops", path, "--density", "1000", "--json", *extra)
    assert code == 0, err
    return json.loads(out), err


@pytest.mark.parametrize(("name", "ignored"), [("box_plus_face.step", "1 face"),
                                               ("solid_plus_open_shell.step", "1 open shell")])
def test_step_loose_surfaces_are_ignored_and_reported(name, ignored):
    res, err = _massprops(CASES / "step-solid-plus-surfaces" / name)
    assert res["volume_mm3"] == pytest.approx(6000.0, rel=1e-12)
    np.testing.assert_allclose(res["com_mm"], [5, 10, 15], atol=1e-9)
    np.testing.assert_allclose(res["principal_moments_kg_m2"], BOX_PRINCIPAL, rtol=1e-9)
    assert res["n_solids"] == 1
    assert any(f"ignored {ignored}" in w for w in res["warnings"])
    assert f"ignored {ignored}" in err


def test_stl_far_from_origin_case():
    for name in ("box10x20x30_at_0.stl", "box10x20x30_at_1e6.stl"):
        res, _ = _massprops(CASES / "stl-far-from-origin" / name)
        np.testing.assert_allclose(res["principal_moments_kg_m2"], BOX_PRINCIPAL, rtol=1e-9)
        off = np.abs(np.asarray(res["inertia_com_kg_m2"]) - np.diag(np.diag(res["inertia_com_kg_m2"])))
        assert off.max() < 1e-9 * 6.5e-7
        assert res["mass_kg"] == pytest.approx(0.006, rel=1e-12)


def _box(size_mm, at_mm):
    """Closed box mesh (8 vertices, 12 outward triangles) with a corner at ``at_mm``."""
    a, b, c = size_mm
    v = np.array([[x, y, z] for x in (0, a) for y in (0, b) for z in (0, c)], float) + at_mm
    f = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                  [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    return v, f


@pytest.mark.parametrize("size", [1.0, 10.0, 100.0])
@pytest.mark.parametrize("dist", [0.0, 1e3, 1e5, 1e6])
def test_stl_accuracy_at_sizes_and_distances(size, dist):
    dims = (size, 2 * size, 3 * size)
    v, f = _box(dims, np.array([dist, -dist, dist]))
    res = mesh_arrays_mass_props(v, f, 1000.0)
    m = 1000.0 * 6 * size**3 * 1e-9
    a, b, c = (d * 1e-3 for d in dims)
    ref = sorted(m / 12 * np.array([b * b + c * c, a * a + c * c, a * a + b * b]))
    np.testing.assert_allclose(res.props.principal_moments_kg_m2, ref, rtol=1e-9)
    np.testing.assert_allclose(np.asarray(res.props.com_m) * 1e3,
                               np.array([dist, -dist, dist]) + np.array(dims) / 2,
                               rtol=0, atol=1e-9 * max(dist, 1))


def test_stl_header_count_cases():
    d = CASES / "stl-header-count"
    ok, _ = _massprops(d / "box_ok.stl")
    assert ok["volume_mm3"] == pytest.approx(6000.0) and ok["warnings"] == []
    res, err = _massprops(d / "box_count0.stl")
    assert res["volume_mm3"] == pytest.approx(6000.0, rel=1e-6)
    np.testing.assert_allclose(res["com_mm"], [5, 10, 15], atol=1e-5)
    assert "header says 0 triangles, the file holds 12" in res["warnings"][0]
    code, out, err = hapticad("massprops", d / "box_truncated.stl", "--density", "1000")
    assert_one_line_error(code, err, "box_truncated.stl", "truncated", "11 complete records")
    assert out == ""


def test_stl_non_finite_coordinates_name_the_file(tmp_path):
    p = tmp_path / "nan.stl"
    p.write_text("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex nan 0 0\n"
                 "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n")
    code, out, err = hapticad("massprops", p, "--density", "1000")
    assert_one_line_error(code, err, "nan.stl", "not finite")


def test_winding_hint_works():
    """The hint of the inconsistent-winding error repairs the mesh (networkx is a dependency)."""
    import trimesh

    from cad.errors import MeshError

    v, f = _box((10.0, 20.0, 30.0), np.zeros(3))
    f = f.copy()
    f[0] = f[0][::-1]
    with pytest.raises(MeshError, match=r"trimesh\.repair\.fix_normals\(m\)") as exc:
        mesh_arrays_mass_props(v, f, 1000.0)
    assert "fix_normals" in str(exc.value)
    m = trimesh.Trimesh(v, f, process=True)
    trimesh.repair.fix_normals(m)  # what the hint says
    res = mesh_arrays_mass_props(m.vertices, m.faces, 1000.0)
    assert res.volume_mm3 == pytest.approx(6000.0, rel=1e-12)


def test_step_box_far_away_is_exact(tmp_path):
    """A STEP box at 1e9 mm used to be refused as "inertia is not positive definite"."""
    from build123d import Box, Location, export_step

    for at in (0.0, 1e6, 1e9):
        p = tmp_path / f"box_{at:g}.step"
        export_step(Location((at, at, at)) * Box(10, 20, 30), str(p))
        res, _ = _massprops(p)
        np.testing.assert_allclose(res["principal_moments_kg_m2"], BOX_PRINCIPAL, rtol=1e-9)
        assert res["volume_mm3"] == pytest.approx(6000.0, rel=1e-9)
        assert math.isclose(res["com_mm"][0], at, rel_tol=1e-12, abs_tol=1e-9)


def test_assembly_one_density_warns(tmp_path):
    from build123d import Box, Compound, Location, export_step

    p = tmp_path / "two.step"
    export_step(Compound([Box(10, 10, 10), Location((50, 0, 0)) * Box(10, 10, 10)]), str(p))
    res, err = _massprops(p)
    assert res["n_solids"] == 2 and res["volume_mm3"] == pytest.approx(2000.0)
    assert any("applied to all 2 solids" in w for w in res["warnings"])


def test_hapticad_assembly_uses_per_solid_materials(tmp_path):
    """assembly.step of a build: each solid with its part's material (report.json beside it).

    Independent reference: the per-part STEP files of the same build, each integrated with
    its BOM material, times its BOM quantity.
    """

    out = tmp_path / "b"
    code, _, err = hapticad("build", Path(__file__).resolve().parents[3] / "designs" /
                            "hoeken.toml", "--out", out, "--formats", "step", "--fidelity",
                            "inertia", "--no-cache")
    assert code == 0, err
    code, stdout, err = hapticad("massprops", out / "assembly.step", "--json")
    assert code == 0, err
    res = json.loads(stdout)
    assert res["material"] == "per-solid" and res["warnings"] == []
    assert res["solid_materials"]["handle"] == "delrin"
    assert res["solid_materials"]["pin_A2"] == "steel-1018"
    report = json.loads((out / "report.json").read_text())
    ref = 0.0
    for row in report["bom"]:
        if row["mass_g"] == 0.0:  # a BOM line with no solid (the encoder): no part file
            assert not (out / "parts" / f"{row['part']}.step").exists()
            continue
        code, stdout, err = hapticad("massprops", out / "parts" / f"{row['part']}.step",
                                     "--material", row["material"], "--json")
        assert code == 0, err
        ref += row["quantity"] * json.loads(stdout)["mass_kg"]
    # the motor shaft is a solid of assembly.step but no BOM line (it is part of the bought
    # motor): a steel cylinder, closed form
    import math

    from cad.data.catalog import get_motor
    from cad.data.materials import get_material
    from cad.parts.motor import SHAFT_ENVELOPE_GAP_MM

    assert res["solid_materials"]["motor_shaft"] == "steel-1018"
    m = get_motor(report["motor"]["key"])
    shaft_mm3 = math.pi * (m.shaft_diameter_mm / 2) ** 2 * (
        m.shaft_length_mm - m.pilot_height_mm - SHAFT_ENVELOPE_GAP_MM)
    ref += shaft_mm3 * 1e-9 * get_material("steel-1018").density_kg_m3
    assert res["mass_kg"] == pytest.approx(ref, rel=1e-9)
    # a single density for every solid would be off by the steel / Delrin parts
    code, stdout, _ = hapticad("massprops", out / "assembly.step", "--density", "2700", "--json")
    one = json.loads(stdout)
    assert one["mass_kg"] != pytest.approx(ref, rel=1e-3)
    assert any("overrides them all" in w for w in one["warnings"])


# ------------------------------------------------------------------ closed shells (issue 21 §4)
# References: closed forms of cubes. A cube of side s at 1000 kg/m^3 has m = s^3 * 1e-6 kg
# (s in mm) and I = m s^2 / 6 about its centre; a cavity subtracts its own cube's values.

def _cube_i(s_mm):
    m = 1000.0 * (s_mm * 1e-3) ** 3
    return m * (s_mm * 1e-3) ** 2 / 6


@pytest.mark.parametrize(("name", "vol", "ixx", "warning"), [
    ("hollow_box.stl", 7000.0, _cube_i(20) - _cube_i(10), None),
    ("both_outward.stl", 7000.0, _cube_i(20) - _cube_i(10),
     "shell 2 of 2 (12 triangles, (5, 5, 5) to (15, 15, 15) mm) lies inside shell 1 but is "
     "wound outwards like a solid: read as a cavity"),
    ("box_duplicated_facets.stl", 8000.0, _cube_i(20), "dropped 12 duplicate triangles"),
])
def test_stl_shells_cases(name, vol, ixx, warning):
    """shared/cases/stl-shells: the right values of its README (closed forms above)."""
    res, err = _massprops(CASES / "stl-shells" / name)
    assert res["volume_mm3"] == pytest.approx(vol, rel=1e-12)
    np.testing.assert_allclose(res["com_mm"], [10, 10, 10], atol=1e-12)
    np.testing.assert_allclose(res["inertia_com_kg_m2"], ixx * np.eye(3), rtol=1e-12,
                               atol=1e-12 * ixx)
    if warning is None:
        assert res["warnings"] == []
    else:
        assert len(res["warnings"]) == 1 and warning in res["warnings"][0]
        assert warning in err


def test_stl_in_metres_case_names_the_unit():
    """A 10 x 20 x 30 mm box written in metres: 0.03 mm across; x1000 it is 30 mm and, in
    aluminium-6061 (2700 kg/m^3), 6000 mm^3 * 2.7e-6 kg/mm^3 = 16.2 g."""
    code, out, err = hapticad("massprops", CASES / "stl-shells" / "box10x20x30_in_metres.stl",
                              "--material", "aluminium-6061", "--json")
    assert code == 0, err
    res = json.loads(out)
    assert res["mass_kg"] == pytest.approx(6e-6 * 2700 * 1e-9, rel=1e-12)
    note = ("box10x20x30_in_metres.stl: the mesh is 0.03 mm across, no device part: is the "
            "file in metres? (x1000: 30 mm, 16.2 g)")
    assert res["warnings"] == [note] and note in err


def test_stl_in_micrometres_names_the_unit():
    """The other side: a 10 mm cube written in um is 1e4 mm across (x0.001: 10 mm, 1 g)."""
    v, f = _box((1e4, 1e4, 1e4), np.zeros(3))
    res = mesh_arrays_mass_props(v, f, 1000.0)
    from cad.massprops.mesh import unit_slip_note

    note = unit_slip_note(v, res.props.mass_kg, "m.stl")
    assert note == ("m.stl: the mesh is 1e+04 mm across, no device part: is the file in "
                    "micrometres? (x0.001: 10 mm, 1 g)")
    assert unit_slip_note(*_box((0.5, 1, 1), np.zeros(3))[:1], 1e-6) is None


def _rigid(seed):
    """A seeded random rotation (QR of a Gaussian matrix, det +1) and translation, mm."""
    rng = np.random.default_rng(seed)
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] *= -1
    return q, rng.uniform(-500, 500, 3)


def _nest(*shells):
    """One soup of cube shells ``(side_mm, corner_mm, wound_out)``, each wound as given."""
    vs, fs = [], []
    for side, corner, out in shells:
        v, f = _box((side,) * 3, np.asarray(corner, float))
        fs.append((f if out else f[:, ::-1]) + 8 * len(vs))
        vs.append(v)
    return np.vstack(vs), np.vstack(fs)


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("windings", [(True, False, True), (True, True, True),
                                      (True, True, False), (True, False, False)])
def test_nested_shells_read_by_their_nesting(seed, windings):
    """Solid 30 mm cube, cavity 20 mm, island 10 mm inside the cavity, shells in any order and
    under a seeded rigid transform: 27000 - 8000 + 1000 = 20000 mm^3 when the cavity is
    wound inwards or outwards (outwards: noted); the island inside the cavity wound inwards
    is inside-out (refused, named)."""
    v, f = _nest((10, (10, 10, 10), windings[2]), (30, (0, 0, 0), windings[0]),
                 (20, (5, 5, 5), windings[1]))
    rot, shift = _rigid(seed)
    v = v @ rot.T + shift
    if not windings[2]:
        from cad.errors import MeshError

        with pytest.raises(MeshError, match=r"shell 1 of 3 \(12 triangles, .*\) is inside-out "
                                            r"\(wound inwards, inside a cavity\)"):
            mesh_arrays_mass_props(v, f, 1000.0)
        return
    res = mesh_arrays_mass_props(v, f, 1000.0)
    assert res.volume_mm3 == pytest.approx(20000.0, rel=1e-9)
    np.testing.assert_allclose(np.asarray(res.props.com_m) * 1e3, rot @ [15, 15, 15] + shift,
                               atol=1e-9)
    ixx = _cube_i(30) - _cube_i(20) + _cube_i(10)
    np.testing.assert_allclose(res.props.principal_moments_kg_m2, [ixx] * 3, rtol=1e-9)
    assert len(res.notes) == int(windings[1])
    if windings[1]:
        assert "shell 3 of 3" in res.notes[0] and "inside shell 2" in res.notes[0]


def test_separate_bodies_and_inside_out_shell():
    """Two disjoint cubes: 1000 + 8000 mm^3, nothing noted; the small one wound inwards is
    inside-out (enclosed by nothing): refused naming it, not 7000."""
    from cad.errors import MeshError

    res = mesh_arrays_mass_props(*_nest((10, (50, 0, 0), True), (20, (0, 0, 0), True)), 1000.0)
    assert res.volume_mm3 == pytest.approx(9000.0, rel=1e-12) and res.notes == ()
    with pytest.raises(MeshError, match=r"shell 1 of 2 .* is inside-out \(wound inwards, "
                                        r"enclosed by no other shell\): its 1000 mm\^3"):
        mesh_arrays_mass_props(*_nest((10, (50, 0, 0), False), (20, (0, 0, 0), True)), 1000.0)


def test_crossing_shells_refused():
    """Two overlapping cubes written as two shells would count the overlap twice (16000 for
    a union of 15000 mm^3): refused, naming both."""
    from cad.errors import MeshError

    with pytest.raises(MeshError, match=r"shell 1 of 2 .* crosses shell 2 of 2"):
        mesh_arrays_mass_props(*_nest((20, (0, 0, 0), True), (20, (10, 10, 10), True)), 1000.0)


def test_crossing_shells_no_vertex_shows_refused():
    """Two 20 mm cubes on one centre, one turned 45 deg about z: every vertex of each lies
    outside the other (the vertex test sees two separate bodies; 16000 mm^3 would be summed)
    but they share a regular octagonal prism of in-radius 10 mm, 20 mm high:
    8 * 10^2 * tan(22.5 deg) * 20 = 6627.42 mm^3 (manifold3d intersection): refused."""
    from cad.errors import MeshError

    v, f = _nest((20, (-10, -10, -10), True), (20, (-10, -10, -10), True))
    c, s = np.cos(np.pi / 4), np.sin(np.pi / 4)
    v[8:] = v[8:] @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]).T
    shared = 8 * 100 * np.tan(np.pi / 8) * 20
    with pytest.raises(MeshError, match=rf"shell 1 of 2 .* crosses shell 2 of 2 .*"
                                        rf"\({shared:.6g} mm\^3 in both\)"):
        mesh_arrays_mass_props(v, f, 1000.0)


def test_duplicates_found_in_any_vertex_order():
    """A facet repeated with its vertices rotated (same winding) is the same facet: dropped;
    one repeated reversed is a different (opposite) facet: kept, and the mesh is then open."""
    from cad.massprops.shells import drop_duplicate_faces

    f = np.array([[0, 1, 2], [1, 2, 0], [2, 0, 1], [0, 2, 1], [3, 4, 5]])
    kept, n = drop_duplicate_faces(f)
    assert n == 2 and kept.tolist() == [[0, 1, 2], [0, 2, 1], [3, 4, 5]]


def test_the_same_solid_written_twice_refused():
    """A cube and a copy of it 1e-6 mm off (not merged: trimesh merges below 1e-8 mm) share
    all of their 8000 mm^3: neither is a cavity of the other; refused, not 0 or 16000."""
    from cad.errors import MeshError

    v, f = _nest((20, (0, 0, 0), True), (20, (1e-6, 1e-6, 1e-6), True))
    with pytest.raises(MeshError, match=r"shell 1 of 2 .* and shell 2 of 2 .* enclose the "
                                        r"same 8000 mm\^3"):
        mesh_arrays_mass_props(v, f, 1000.0)


def test_api_returns_the_warnings():
    """cad.mass_properties gives the command's warnings too (they used to be dropped), each
    call its own: the same file twice warns twice."""
    import cad

    for _ in range(2):
        r = cad.mass_properties(CASES / "stl-shells" / "both_outward.stl", density_kg_m3=1000)
        assert r["volume_mm3"] == pytest.approx(7000.0, rel=1e-12)
        assert len(r["warnings"]) == 1 and "read as a cavity" in r["warnings"][0]
    r = cad.mass_properties(CASES / "stl-shells" / "hollow_box.stl", density_kg_m3=1000)
    assert r["warnings"] == []
