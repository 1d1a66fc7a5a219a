"""Every family states its fits: ISO 286 classes of the seats, bores and journals of the
pantograph, the twin pantograph and the PowerMouse in ``bom.csv``, report.json's ``fits``
and the DXF's ``NOTES`` layer (the four-bar's are in tests/unit/assembly/test_assembly_clashes.py).

Read back from disk with second tools (the csv module, OCCT's STEP reader, ezdxf); every
stated diameter is compared with an independent reference: the bearing's d and D read
straight from bd_warehouse's CSV (not through ``cad.data.catalog``), the motor's shaft and
pilot from the catalog entry the design names, the PowerMouse's post and handle diameters
from the design; and each stated diameter must be a cylindrical face of the part's solid
(``parts/<kind>.step``). Which kinds hold a bearing is derived from the assembly's
instances (coaxial cylinder faces of the bearing's outer / inner diameter), not listed.
The builds are the shared ``family_builds`` (conftest), not repeated here.
"""

from __future__ import annotations

import csv
import importlib.util
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

FAMS = ("pantograph", "twin-pantograph", "powermouse")
FIT_RE = re.compile(r"^(?P<feature>[a-z ]+) (?P<d>\d+(?:\.\d+)?) (?P<cls>[A-Za-z]+\d+)$")


def _bd_bearing(size: str) -> tuple[float, float]:
    """(d, D) mm of a bearing, straight from bd_warehouse's SKF CSV."""
    data = Path(importlib.util.find_spec("bd_warehouse").origin).parent / "data"
    with open(data / "single_row_deep_groove_ball_bearing_parameters.csv", newline="") as fh:
        row = next(r for r in csv.DictReader(fh) if r["Size"] == size)
    return float(row["SKT:d"]), float(row["SKT:D"])


def _expected(fam: str, design) -> dict[str, set[tuple[str, float, str]]]:
    """``{kind: {(feature, diameter mm, class)}}`` every seat / bore / journal must state."""
    if fam == "powermouse":
        post, stem = design.stator.post_diameter_mm, design.handle.diameter_mm
        return {
            "pm_housing_body": {("post bore", post, "H7")},
            "pm_post": {("post", post, "g6")},
            "pm_flotor_body": {("handle socket", stem, "H7")},
            "pm_handle": {("handle stem", stem, "g6")},
        }
    from cad.data.catalog import MOTORS

    d, D = _bd_bearing(design.parts.bearing)
    mot = MOTORS[design.parts.motor]
    out = {
        "clevis_bearing": {("bearing seat", D, "J7")},
        "clevis_pin": {("pin bore", d, "H7")},
        "clevis_hub": {("shaft bore", mot.shaft_diameter_mm, "H7")},
        "knob": {("pin bore", d, "H7")},
        "motor_mount": {("pilot bore", mot.pilot_diameter_mm, "H7")},
        "pin_short": {("pin", d, "m6")},
        "pin_long": {("pin", d, "m6")},
    }
    if fam == "twin-pantograph":
        out["crankshaft"] = {("journal", d, "js5")}
    else:
        out["handle_pin"] = {("pin", d, "m6")}
    return out


def _parse(fits: list[str]) -> set[tuple[str, float, str]]:
    out = set()
    for f in fits:
        m = FIT_RE.match(f)
        assert m, f
        out.add((m["feature"], float(m["d"]), m["cls"]))
    return out


def _bom(out: Path) -> dict[str, dict]:
    with (out / "bom.csv").open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert rows and "fits" in rows[0]
    return {r["part"]: r for r in rows}


def _cylinders(shape) -> list[tuple[float, np.ndarray, np.ndarray]]:
    """``[(radius, axis point, unit axis)]`` of every cylindrical face of ``shape`` (mm)."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAbs import GeomAbs_Cylinder
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    out = []
    ex = TopExp_Explorer(shape, TopAbs_FACE)
    while ex.More():
        s = BRepAdaptor_Surface(TopoDS.Face_s(ex.Current()))
        ex.Next()
        if s.GetType() != GeomAbs_Cylinder:
            continue
        c = s.Cylinder()
        p, a = c.Location(), c.Axis().Direction()
        out.append((c.Radius(), np.array([p.X(), p.Y(), p.Z()]), np.array([a.X(), a.Y(), a.Z()])))
    return out


def _read_step(path: Path):
    from OCP.IFSelect import IFSelect_RetDone
    from OCP.STEPControl import STEPControl_Reader

    r = STEPControl_Reader()
    assert r.ReadFile(str(path)) == IFSelect_RetDone, path
    r.TransferRoots()
    return r.OneShape()


@pytest.mark.parametrize("fam", FAMS)
def test_bom_and_report_state_each_seat_and_bore_with_its_class(family_builds, fam):
    design, out, _ = family_builds[fam]
    rows = _bom(out)
    rep = json.loads((out / "report.json").read_text())
    exp = _expected(fam, design)
    stated = {k: _parse(r["fits"].split("; ")) for k, r in rows.items() if r["fits"]}
    assert stated == exp  # every seat / bore / journal kind, nothing else
    assert rep["fits"] == {k: r["fits"].split("; ") for k, r in rows.items() if r["fits"]}


@pytest.mark.parametrize("fam", FAMS)
def test_each_stated_diameter_is_a_cylinder_of_the_part_read_back(family_builds, fam):
    """The part's STEP (read back with OCCT) has a cylindrical face of each stated diameter;
    the PowerMouse's post bore and handle socket run along the diagonal (1, 1, 1)."""
    design, out, _ = family_builds[fam]
    diag = np.ones(3) / math.sqrt(3.0)
    for kind, fits in _expected(fam, design).items():
        cyl = _cylinders(_read_step(out / "parts" / f"{kind}.step"))
        for _, d, _ in fits:
            axes = [a for r, _, a in cyl if abs(r - d / 2) < 1e-6]
            assert axes, (kind, d, sorted({round(r, 4) for r, _, _ in cyl}))
            if fam == "powermouse":
                assert any(abs(abs(a @ diag) - 1.0) < 1e-9 for a in axes), (kind, d)


#: The plates each family's build must cut (a DXF each) and those with a fit on their NOTES
#: (the delta: its bundled build, tests/conftest.py ``delta_build``; none of its plates holds
#: a bearing or a motor pilot with a fit class).
DXF_PLATES = {"pantograph": ({"base_plate", "motor_mount"}, {"motor_mount"}),
              "twin-pantograph": ({"base_plate", "motor_mount"}, {"motor_mount"}),
              "powermouse": ({"rig_base"}, None),
              "delta": ({"base_plate", "motor_bracket", "upper_arm", "effector_plate"}, set())}


@pytest.mark.parametrize("fam", list(DXF_PLATES))
def test_dxf_notes_state_the_fits_and_mill_layers_hold_no_outline(request, fam):
    """Every plate DXF (ezdxf): its NOTES texts are its BOM fits + " (ISO 286)"; a MILL layer
    repeats no edge of the through profile; a plate without one is a plain extrusion (the
    through profile's area x thickness is the solid's volume, OCCT on the part's STEP)."""
    import ezdxf
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    from cad.export.dxf import dxf_profile_area_mm2
    from tests.conftest import family_build

    design, out, _ = family_build(request, fam)
    # the PowerMouse's plates are the Fig. 7 test rig's, in rig/ with its own BOM
    folders = [out] + ([out / "rig"] if fam == "powermouse" else [])
    dxfs = [(p, _bom(f)) for f in folders for p in sorted((f / "parts").glob("*.dxf"))]
    stems = {p.stem for p, _ in dxfs}
    plates, with_fits = DXF_PLATES[fam]
    assert stems >= plates
    noted = set()
    for path, rows in dxfs:
        doc = ezdxf.readfile(path)
        msp = list(doc.modelspace())
        notes = [e.dxf.text for e in msp if e.dxf.layer == "NOTES"]
        fits = [f for f in rows[path.stem]["fits"].split("; ") if f]
        assert notes[:5] == [f"part: {path.stem}", "units: mm",
                             f"material: {rows[path.stem]['material']}", notes[3],
                             f"quantity: {rows[path.stem]['quantity']}"], path.stem
        assert notes[5] == f"stock: {rows[path.stem]['stock']}", path.stem  # the BOM's stock
        assert notes[6 : 6 + len(fits)] == [f"{f} (ISO 286)" for f in fits], path.stem
        noted |= {path.stem} if fits else set()

        def sig(e):
            if e.dxftype() == "CIRCLE":
                return ("C", *np.round([e.dxf.center.x, e.dxf.center.y, e.dxf.radius], 6))
            if e.dxftype() == "LINE":
                ends = [(round(q.x, 6), round(q.y, 6)) for q in (e.dxf.start, e.dxf.end)]
                return ("L", *sorted(ends))
            return (e.dxftype(), e.dxf.handle)

        cut = {sig(e) for e in msp if e.dxf.layer == "CUT"}
        mill = [e for e in msp if e.dxf.layer.startswith("MILL")]
        assert cut and not any(sig(e) in cut for e in mill), path.stem
        if not mill:
            shape = _read_step(path.with_suffix(".step"))
            box = Bnd_Box()
            BRepBndLib.Add_s(shape, box)
            z0, z1 = box.CornerMin().Z(), box.CornerMax().Z()
            g = GProp_GProps()
            BRepGProp.VolumeProperties_s(shape, g)
            area = dxf_profile_area_mm2(path.read_text()) - _stock_area_mm2(msp, fits)
            assert notes[3] == f"thickness: {z1 - z0:.2f} mm"
            edge = _edge_holes_mm3(out, path.stem)  # drilled after cutting: noted, not cut
            assert (edge > 0) == any(n.endswith(": not on this profile") for n in notes), path.stem
            assert area * (z1 - z0) - edge == pytest.approx(g.Mass(), rel=1e-3), path.stem
    if with_fits is not None:  # the 5-bars' only plate with a fit: the motor mount's pilot bore
        assert noted == with_fits


def _edge_holes_mm3(out: Path, kind: str) -> float:
    """Volume (mm^3) of the tapped holes drilled in the plane of one ``kind`` plate (axis
    normal to its thickness: a screw into its edge), report.json's records: each a flat
    cylinder of the tap drill (d - P, ISO 261) and the thread's depth plus the lead-out."""
    from cad.assembly.fasteners import TAP_LEADOUT_MM
    from cad.data.catalog import tap_drill_mm

    rep = json.loads((out / "report.json").read_text())
    inst = rep.get("placement", {}).get("instances", {})
    one = next((n for n, p in sorted(inst.items()) if p.get("kind") == kind), None)
    holes = [h for h in (rep.get("tapped_holes") or {}).values()
             if h.get("part") == one and h.get("axis") is not None and abs(h["axis"][2]) < 1e-9]
    return sum(math.pi * (tap_drill_mm(h["size"]) / 2) ** 2 * (h["depth_mm"] + TAP_LEADOUT_MM) for h in holes)


def _stock_area_mm2(msp, fits) -> float:
    """Area of the finishing stock a profile leaves in its reamed or bored holes: every CUT
    circle of a bore's diameter less the table allowance (mm^2)."""
    from cad.data.fits import finish, parse_fit, ream_allowance_mm

    out = 0.0
    for f in fits:
        label, d, cls = parse_fit(f)
        if finish(label, cls) not in ("ream", "bore"):
            continue
        r = (d - ream_allowance_mm(d)) / 2
        n = sum(e.dxftype() == "CIRCLE" and e.dxf.layer == "CUT"
                and abs(e.dxf.radius - r) < 1e-9 for e in msp)
        assert n > 0, f  # the bore is on the profile, undersize
        out += n * math.pi * ((d / 2) ** 2 - r**2)
    return out


@pytest.mark.parametrize("fam", ["pantograph", "twin-pantograph"])
def test_every_kind_holding_a_bearing_states_its_fit(family_builds, fam):
    """From the assembly's instances: a part with a cylindrical face coaxial with a bearing
    at its outer diameter D holds the outer ring (a bearing seat); one at the bearing's bore
    d is the pin or journal in the inner ring or a bore holding that pin (the elbow clevis,
    the knob); every such kind states a fit of that diameter, the seats J7."""
    from cad.export.shapes import placed
    from cad.families.pantograph import build as pg
    from cad.pipeline.family import world_tf

    design, out, _ = family_builds[fam]
    rows = _bom(out)
    inst, tfs, _, _ = pg.assembly(design, pg.layout(design), "inertia")
    bearings = [i for i in inst if i.kind.ring_mm is not None]
    assert len(bearings) == (16 if fam == "twin-pantograph" else 8)
    cyl = {
        i.name: _cylinders(placed(i.kind.shape, world_tf(i, tfs)))
        for i in inst
        if i.kind.ring_mm is None
    }
    kinds = {i.name: i.kind.name for i in inst}
    outer, inner = set(), set()
    for b in bearings:
        T = world_tf(b, tfs)
        c, z = T[:3, 3], T[:3, 2]
        r_in, r_out, _ = b.kind.ring_mm
        for name, faces in cyl.items():
            for r, p, a in faces:
                if (
                    np.linalg.norm(np.cross(a, z)) > 1e-9
                    or np.linalg.norm(np.cross(p - c, z)) > 1e-6
                ):
                    continue
                if abs(r - r_out) < 1e-6:
                    outer.add(kinds[name])
                elif abs(r - r_in) < 1e-6:
                    inner.add(kinds[name])
    d, D = _bd_bearing(design.parts.bearing)
    assert outer == {"clevis_bearing"}
    assert inner >= {"pin_short", "pin_long"} and inner
    for k in outer:
        assert ("bearing seat", D, "J7") in _parse(rows[k]["fits"].split("; "))
    for k in inner:
        assert any(f[1] == d for f in _parse(rows[k]["fits"].split("; "))), k


def test_write_outputs_puts_fits_in_the_bom_and_on_the_dxf_with_only_the_seat_milled(tmp_path):
    """A plate with a counterbored bearing seat through the families' common writer: bom.csv
    has its fit, the DXF's NOTES layer states it, the MILL layer holds the seat circle only."""
    import build123d as bd
    import ezdxf

    from cad.data.fits import fit
    from cad.parts import PartInstance, PartKind
    from cad.pipeline import family

    d, D = _bd_bearing("M4-9-2.5")
    plate = bd.Box(40, 20, 6, align=(bd.Align.CENTER, bd.Align.CENTER, bd.Align.MIN))
    plate = plate - bd.Cylinder(d / 2 + 0.5, 6, align=(bd.Align.CENTER,) * 2 + (bd.Align.MIN,))
    plate = plate - bd.Pos(0, 0, 3.5) * bd.Cylinder(
        D / 2, 2.5, align=(bd.Align.CENTER,) * 2 + (bd.Align.MIN,)
    )
    kind = PartKind(
        name="seat_plate",
        shape=plate.wrapped,
        material="aluminium-6061",
        made=True,
        plate=True,
        fits=(fit("bearing seat", D),),
    )
    inst = [PartInstance("seat_plate", kind, "ground", np.eye(4))]
    bom = family.bom_rows(inst, {"seat_plate": None})
    family.write_outputs(
        inst, {"ground": np.eye(4)}, tmp_path, {"dxf"}, name="t", title="t", bom=bom, preview=False
    )
    assert _bom(tmp_path)["seat_plate"]["fits"] == "bearing seat 9 J7"
    assert family.fits_report(inst) == {"seat_plate": ["bearing seat 9 J7"]}
    msp = list(ezdxf.readfile(tmp_path / "parts" / "seat_plate.dxf").modelspace())
    notes = [e.dxf.text for e in msp if e.dxf.layer == "NOTES"]
    # the plate's stock: 20 x 40 mm + STOCK_PLATE_MARGIN_MM (5 mm) per side, 6 mm thick
    # (docs/ordering.md), as bom.csv states it
    assert notes[5] == "stock: plate 6 x 30 x 50 mm aluminium-6061" == f"stock: {bom[0]['stock']}"
    assert notes[6] == "bearing seat 9 J7 (ISO 286)"
    assert notes[7] == "bearing seat x1: mill bearing seat 9 J7 (ISO 286), 2.50 deep from the " \
        "top face, layer MILL_Z3.50_6.00"
    mill = [e for e in msp if e.dxf.layer.startswith("MILL")]
    assert [(e.dxftype(), e.dxf.radius) for e in mill] == [("CIRCLE", pytest.approx(D / 2))]
