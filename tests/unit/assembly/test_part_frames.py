"""Every part file is written in the frame its instances are placed from (issue 23 §2).

Reference, independent of the build's own mass-property code: each ``parts/<kind>.step``
is read back from disk with OCP's STEP reader, its solids integrated by OCCT
(``BRepGProp.VolumeProperties_s``, unit density) with their locations DROPPED -- what a
reader that ignores a file's nested placements sees, so the files must carry none -- times
the material density of :mod:`cad.data.materials`, placed by report.json's ``placement``
(``tf_body_part`` per instance) and summed per body by the parallel-axis theorem written
out below. The sums must give the body mass properties the report states (mass, COM,
inertia tensor about the COM, body frame) to 1e-9 relative: ``placement.bodies`` and each
family's own keys (four-bar ``links`` and ``ground_mass_g``, pantograph ``bodies``,
PowerMouse ``flotor`` and ``stator_mass_kg``).

Bought parts whose mass is the catalog's are taken as the report states them
(``placement.kinds[k].mass_source``): ``"solid, catalog mass"`` -- the file's solid
scaled to the report's catalog mass; ``"ring"`` (bearings) -- the report's annulus
values, and the file's centroid must be the annulus's centre (axis z, mid-width).

Before the fix, the STEP of a solid carrying a location (tubes, clevises, bearings, the
base plate, set screws) held it as a nested placement: read without it, a tube lay in its
unplaced frame (the pantograph's along z instead of x).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from cad.data.materials import get_material

REL = 1e-9
BUILDS = ("hoeken", "pantograph", "twin-pantograph", "powermouse")


@pytest.fixture(scope="module")
def built(request):
    """``{name: (out_dir, report.json)}`` of the shared builds (tests/conftest.py): the
    Hoeken at preview fidelity, the other families at inertia fidelity, STEP included."""
    out = {}
    _, hoeken_out, hoeken_rep, _ = request.getfixturevalue("hoeken_sim_build")
    out["hoeken"] = (hoeken_out, hoeken_rep)
    for fam, (_, target, _) in request.getfixturevalue("family_builds").items():
        out[fam] = (target, json.loads((target / "report.json").read_text()))
    return out


def read_step_solids(path) -> list:
    """The solids of a STEP file as OCP's reader gives them (with their locations)."""
    from OCP.IFSelect import IFSelect_ReturnStatus
    from OCP.STEPControl import STEPControl_Reader
    from OCP.TopAbs import TopAbs_SOLID
    from OCP.TopExp import TopExp_Explorer

    reader = STEPControl_Reader()
    assert reader.ReadFile(str(path)) == IFSelect_ReturnStatus.IFSelect_RetDone, path
    reader.TransferRoots()
    exp = TopExp_Explorer(reader.OneShape(), TopAbs_SOLID)
    solids = []
    while exp.More():
        solids.append(exp.Current())
        exp.Next()
    assert solids, f"{path}: no solid"
    return solids


def unplaced_volume_props(solids) -> tuple[float, np.ndarray, np.ndarray]:
    """(volume mm^3, centroid mm (3,), inertia about the centroid mm^5 (3, 3)) at unit
    density of the solids with their locations dropped (OCCT's convention: products of
    inertia carry the minus sign, I = integral (|r|^2 E - r r^T) dV)."""
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps
    from OCP.TopLoc import TopLoc_Location

    total = GProp_GProps()
    for s in solids:
        g = GProp_GProps()
        BRepGProp.VolumeProperties_s(s.Located(TopLoc_Location()), g)
        total.Add(g)
    c, m = total.CentreOfMass(), total.MatrixOfInertia()
    inertia = np.array([[m.Value(i, j) for j in (1, 2, 3)] for i in (1, 2, 3)])
    return total.Mass(), np.array([c.X(), c.Y(), c.Z()]), inertia


def kind_props_from_file(out, name: str, kind: dict) -> tuple[float, np.ndarray, np.ndarray]:
    """(mass kg, COM m, inertia about the COM kg m^2) of one kind in its frame, from its
    STEP file and the material density (or as the report states a catalog mass)."""
    stated = kind["mass_props"]
    if kind["file"] is None or kind["mass_source"] == "ring":
        m, com, inertia = (stated["mass_kg"], np.array(stated["com_mm"]) * 1e-3,
                           np.array(stated["inertia_com_kg_m2"]))
        if kind["file"] is not None:  # the annulus's centre is the file's centroid
            _, c_mm, _ = unplaced_volume_props(read_step_solids(out / kind["file"]))
            assert np.abs(c_mm * 1e-3 - com).max() <= 1e-9, (name, c_mm, com)
        return m, com, inertia
    vol_mm3, c_mm, i_mm5 = unplaced_volume_props(read_step_solids(out / kind["file"]))
    rho = get_material(kind["material"]).density_kg_m3
    if kind["mass_source"] == "solid, catalog mass":
        rho = stated["mass_kg"] / (vol_mm3 * 1e-9)
    else:
        assert kind["mass_source"] == "solid", (name, kind["mass_source"])
    return rho * vol_mm3 * 1e-9, c_mm * 1e-3, rho * i_mm5 * 1e-15


def bodies_from_files(out, placement: dict) -> dict:
    """``{body: (mass kg, COM m, inertia about the COM kg m^2)}`` in the body frames: every
    instance's kind from its file, moved by ``tf_body_part`` (com' = R com + t,
    I' = R I R^T) and summed (parallel axes to the body's COM)."""
    kinds = {n: kind_props_from_file(out, n, k) for n, k in placement["kinds"].items()
             if k["mass_props"] is not None}
    per: dict[str, list] = {}
    for inst in placement["instances"].values():
        if inst["kind"] not in kinds:
            continue
        m, com, inertia = kinds[inst["kind"]]
        T = np.array(inst["tf_body_part"])
        R, t = T[:3, :3], T[:3, 3] * 1e-3
        per.setdefault(inst["body"], []).append((m, R @ com + t, R @ inertia @ R.T))
    out_b = {}
    for b, items in per.items():
        m = sum(x[0] for x in items)
        G = sum(x[0] * x[1] for x in items) / m
        inertia = sum(x[2] + x[0] * ((x[1] - G) @ (x[1] - G) * np.eye(3)
                                     - np.outer(x[1] - G, x[1] - G)) for x in items)
        out_b[b] = (m, G, inertia)
    return out_b


def assert_same_body(got, mass_kg, com_mm, inertia_kg_m2, what: str) -> None:
    """Mass, COM and inertia tensor equal to 1e-9 relative (COM relative to the larger of
    |COM| and the body's radius of gyration; the tensor to its largest entry)."""
    m, G, inertia = got
    inertia_ref = np.asarray(inertia_kg_m2, dtype=float)
    assert m == pytest.approx(mass_kg, rel=REL), what
    scale = max(float(np.linalg.norm(np.asarray(com_mm) * 1e-3)),
                float(np.sqrt(np.trace(inertia_ref) / mass_kg)))
    assert np.abs(G - np.asarray(com_mm) * 1e-3).max() <= REL * scale, (what, G, com_mm)
    assert np.abs(inertia - inertia_ref).max() <= REL * np.abs(inertia_ref).max(), what


@pytest.mark.parametrize("name", BUILDS)
def test_part_files_carry_no_placement_and_match_the_report(built, name):
    """Every listed kind has its STEP file, every file is a kind of the report, and no solid
    in a file carries a location (its coordinates are those of the part frame)."""
    out, rep = built[name]
    kinds = rep["placement"]["kinds"]
    files = {p.name for p in (out / "parts").glob("*.step")}
    assert files == {f"{n}.step" for n, k in kinds.items() if k["file"] is not None}
    assert set(rep["placement"]["instances"]) == set(rep["part_materials"])
    for n, k in kinds.items():
        if k["file"] is not None:
            solids = read_step_solids(out / k["file"])
            assert all(s.Location().IsIdentity() for s in solids), n


@pytest.mark.parametrize("name", BUILDS)
def test_part_files_placed_by_the_report_give_its_body_mass_properties(built, name):
    out, rep = built[name]
    got = bodies_from_files(out, rep["placement"])
    stated = rep["placement"]["bodies"]
    assert set(got) == set(stated)
    for b, mp in stated.items():
        assert_same_body(got[b], mp["mass_kg"], mp["com_mm"], mp["inertia_com_kg_m2"], f"{name} {b}")
    # the family's own report keys state the same bodies
    if name == "hoeken":
        for link in ("crank", "coupler", "rocker"):
            lk = rep["links"][link]
            assert_same_body(got[link], lk["mass_kg"], lk["com_mm"], lk["inertia_com_kg_m2"], link)
        assert got["ground"][0] * 1e3 == pytest.approx(rep["ground_mass_g"], rel=REL)
    elif name == "powermouse":
        fl = rep["flotor"]
        assert_same_body(got["flotor"], fl["mass_kg"], fl["com_mm"], fl["inertia_com_kg_m2"], "flotor")
        assert got["ground"][0] == pytest.approx(rep["stator_mass_kg"], rel=REL)
    else:
        assert set(rep["bodies"]) == set(got) - {"ground"}
        for b, mp in rep["bodies"].items():
            assert_same_body(got[b], mp["mass_kg"], mp["com_mm"], mp["inertia_com_kg_m2"], b)


def located_volume_props(solids) -> tuple[float, np.ndarray]:
    """(volume mm^3, centroid mm) of solids as placed (their locations applied by OCCT)."""
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    total = GProp_GProps()
    for s in solids:
        g = GProp_GProps()
        BRepGProp.VolumeProperties_s(s, g)
        total.Add(g)
    c = total.CentreOfMass()
    return total.Mass(), np.array([c.X(), c.Y(), c.Z()])


@pytest.mark.parametrize("name", BUILDS)
def test_part_files_placed_in_the_world_are_the_assembly_step(built, name):
    """Each instance's part file moved by ``tf_world_body[body] @ tf_body_part`` (report.json,
    the exported pose) has the volume and centroid of that instance in ``assembly.step``
    (read back with OCCT's XCAF reader, ``tests/step_pairs.py``) to 1e-9."""
    from step_pairs import read_parts

    out, rep = built[name]
    pl = rep["placement"]
    placed_files = {}
    for n, k in pl["kinds"].items():
        if k["file"] is not None:
            placed_files[n] = unplaced_volume_props(read_step_solids(out / k["file"]))[:2]
    in_step = dict(read_parts(out / "assembly.step"))
    checked = 0
    for inst_name, inst in pl["instances"].items():
        if inst["kind"] not in placed_files:
            continue
        vol, c_part = placed_files[inst["kind"]]
        T = np.array(pl["tf_world_body"][inst["body"]]) @ np.array(inst["tf_body_part"])
        vol_asm, c_asm = located_volume_props(in_step[inst_name])
        assert vol_asm == pytest.approx(vol, rel=REL), inst_name
        c_world = T[:3, :3] @ c_part + T[:3, 3]
        assert np.abs(c_world - c_asm).max() <= REL * max(np.linalg.norm(c_asm), 1.0), inst_name
        checked += 1
    assert checked == sum(1 for i in pl["instances"].values() if i["kind"] in placed_files)


@pytest.mark.parametrize("part", ["bearing_balls", "pantograph_tube", "handle_end_clevis"])
def test_a_located_solid_is_written_in_its_frame(tmp_path, part):
    """Solids that carry a location in memory (a bd_warehouse bearing with its balls -- the
    fabrication fidelity the shared builds skip --, a pantograph tube, the four-bar tube
    bars' handle-end clevis) are written with it applied: read back without locations, the
    same volume, centroid and inertia as the solid in memory (OCCT applies its location)
    to 1e-9."""
    from cad.design.parts import parse_parts
    from cad.export import export_part
    from cad.parts import bars, joints, tubebars
    from cad.parts.pantograph import tube_shape

    tube_parts = parse_parts({"bar_style": "tube", "bar_thickness_mm": 8.0, "tube_od_mm": 6.0,
                              "tube_id_mm": 4.0})
    shape = {
        "bearing_balls": lambda: joints.bearing_shape("M8-16-4", True),
        "pantograph_tube": lambda: tube_shape(80.0, 8.0, 6.0),
        "handle_end_clevis": lambda: tubebars.clevis_shape(
            bars.Feature("tapped", d_mm=3.3), (210.0,), tube_parts),
    }[part]()
    assert not shape.Location().IsIdentity()  # what the case is about
    (path,) = export_part(shape, part, tmp_path, {"step"})
    solids = read_step_solids(path)
    assert all(s.Location().IsIdentity() for s in solids)
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    g = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, g)
    c, mi = g.CentreOfMass(), g.MatrixOfInertia()
    ref_i = np.array([[mi.Value(i, j) for j in (1, 2, 3)] for i in (1, 2, 3)])
    vol, com, inertia = unplaced_volume_props(solids)
    assert vol == pytest.approx(g.Mass(), rel=REL)
    assert np.abs(com - [c.X(), c.Y(), c.Z()]).max() <= REL * max(np.linalg.norm(com), 1.0)
    assert np.abs(inertia - ref_i).max() <= REL * np.abs(ref_i).max()
