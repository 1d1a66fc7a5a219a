"""Laser-cut plate parts (``parts.process = "laser"``, issue 25 §3): sheets read back.

* one build of designs/hoeken_laser.toml (``--formats dxf``, preview fidelity) shared by the
  module; every ``sheets/sheet_NN.dxf`` read back with ezdxf and checked by an own geometry
  check (no shapely in the venv): each part outline (a connected chain of CUT entities not
  inside another) lies on the sheet less the edge margin, any two outlines are at least the
  gap apart (their boxes, from the DXF's own flattened geometry, separated), every laser-cut
  instance is placed exactly once (count against the BOM quantity), each ENGRAVE label sits
  in material of the outline it names; NOTES carry material, thickness, size, units, kerf;
* the packer alone on seeded random rectangles (same check);
* a laser part's mass against area x thickness x density by hand (the base plate);
* refusals and warnings naming the part and feature, at design load (no CAD).
"""

from __future__ import annotations

import csv
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]
DESIGN = ROOT / "designs" / "hoeken_laser.toml"


@pytest.fixture(scope="module")
def laser_build(tmp_path_factory):
    from cad.api import build_design, load_design

    out = tmp_path_factory.mktemp("laser")
    report = build_design(load_design(DESIGN), out, formats=("dxf",), fidelity="preview")
    return out, report


# ------------------------------------------------------------------ DXF geometry, by hand
def _points(e) -> list[tuple[float, float]]:
    """Vertices of one CUT entity, arcs and circles sampled every <= 1 degree."""
    t = e.dxftype()
    if t == "LINE":
        return [(e.dxf.start.x, e.dxf.start.y), (e.dxf.end.x, e.dxf.end.y)]
    if t == "LWPOLYLINE":
        return [(x, y) for x, y, *_ in e.get_points()]
    c, r = e.dxf.center, e.dxf.radius
    a0, a1 = (0.0, 360.0) if t == "CIRCLE" else (e.dxf.start_angle, e.dxf.end_angle)
    if a1 <= a0:
        a1 += 360.0
    n = max(2, math.ceil(a1 - a0) + 1)
    return [(c.x + r * math.cos(math.radians(a)), c.y + r * math.sin(math.radians(a)))
            for a in np.linspace(a0, a1, n)]


def _loops(msp) -> list[list[tuple[float, float, float, float]]]:
    """CUT entities grouped into closed loops (entities sharing end points, union-find);
    each loop as its segments (x0, y0, x1, y1)."""
    ents = [e for e in msp if e.dxf.layer == "CUT"]
    parent = list(range(len(ents)))

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    ends: dict = {}
    for i, e in enumerate(ents):
        pts = _points(e)
        if e.dxftype() == "CIRCLE":
            continue
        for p in (pts[0], pts[-1]):
            key = (round(p[0], 4), round(p[1], 4))
            if key in ends:
                parent[find(i)] = find(ends[key])
            else:
                ends[key] = i
    loops: dict = {}
    for i, e in enumerate(ents):
        pts = _points(e)
        loops.setdefault(find(i), []).extend(
            (*a, *b) for a, b in zip(pts[:-1], pts[1:], strict=True))
    return list(loops.values())


def _inside(p, segs) -> bool:
    """Even-odd ray cast of point ``p`` against segments ``segs``."""
    x, y = p
    n = 0
    for x0, y0, x1, y1 in segs:
        if (y0 <= y) != (y1 <= y) and x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
            n += 1
    return n % 2 == 1


def _text_box(t) -> list[tuple[float, float]]:
    """5 x 3 points over a centred TEXT's box: len x 1.0 h wide (no font character is wider
    than its height), h high, turned by its rotation."""
    h, n = t.dxf.height, len(t.dxf.text)
    c, a = t.dxf.align_point, math.radians(t.dxf.rotation)
    out = []
    for u in np.linspace(-n * h / 2, n * h / 2, 5):
        for v in np.linspace(-h / 2, h / 2, 3):
            out.append((c.x + u * math.cos(a) - v * math.sin(a), c.y + u * math.sin(a) + v * math.cos(a)))
    return out


def _box(segs):
    a = np.asarray(segs)
    xs, ys = np.r_[a[:, 0], a[:, 2]], np.r_[a[:, 1], a[:, 3]]
    return xs.min(), ys.min(), xs.max(), ys.max()


def _outlines(loops):
    """Loops that lie in no other loop (part outlines), each with its box."""
    out = []
    for i, lp in enumerate(loops):
        p = lp[0][:2]
        if not any(j != i and _inside(p, other) for j, other in enumerate(loops)):
            out.append((lp, _box(lp)))
    return out


def _check_layout(boxes, W, H, gap, margin):
    """Every box inside [margin, W - margin] x [margin, H - margin]; any two separated by
    >= gap along x or y (separated boxes: the shapes in them are too)."""
    for x0, y0, x1, y1 in boxes:
        assert x0 >= margin - 1e-6 and y0 >= margin - 1e-6
        assert x1 <= W - margin + 1e-6 and y1 <= H - margin + 1e-6
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            sep = max(b[0] - a[2], a[0] - b[2], b[1] - a[3], a[1] - b[3])
            assert sep >= gap - 1e-6, (a, b, sep)


# ---------------------------------------------------------------------------- sheets
def test_sheets_read_back(laser_build):
    """Every sheet: outlines on the sheet less the margin, the gap between any two, every
    laser instance once (BOM quantity), one ENGRAVE label in material of each outline."""
    import ezdxf

    from cad.tolerances import NEST_EDGE_MARGIN_MM, NEST_GAP_MM

    out, report = laser_build
    sheets = report["sheets"]
    assert sheets["count"] == len(sheets["sheets"]) >= 2  # 6 mm and 5 mm stock: two sheets
    with open(out / "bom.csv", newline="") as fh:
        bom = list(csv.DictReader(fh))
    laser = {r["part"]: int(r["quantity"]) for r in bom if r["process"].startswith("laser cut")}
    assert set(laser) == {"crank", "coupler", "rocker", "base_plate", "motor_mount"}
    labelled: dict[str, int] = {}
    for s in sheets["sheets"]:
        doc = ezdxf.readfile(out / s["file"])
        assert doc.header["$INSUNITS"] == 4
        msp = doc.modelspace()
        W, H = s["size_mm"]
        outline = [e for e in msp if e.dxf.layer == "SHEET"][0]
        sx, sy = zip(*[(x, y) for x, y, *_ in outline.get_points()], strict=True)
        assert (max(sx) - min(sx), max(sy) - min(sy)) == (W, H)
        outs = _outlines(_loops(msp))
        assert len(outs) == len(s["parts"])
        _check_layout([b for _, b in outs], W, H, NEST_GAP_MM, NEST_EDGE_MARGIN_MM)
        all_cut = [seg for lp in _loops(msp) for seg in lp]
        labels = [e for e in msp if e.dxf.layer == "ENGRAVE"]
        assert sorted(t.dxf.text for t in labels) == sorted(s["parts"])
        for t in labels:
            p = (t.dxf.align_point.x, t.dxf.align_point.y)
            assert _inside(p, all_cut), t.dxf.text  # in material, not in a hole
            for q in _text_box(t):  # the whole label box (1.0 h per character bounds the font)
                assert _inside(q, all_cut), (t.dxf.text, q)
            assert sum(_inside(p, lp) for lp, _ in outs) == 1
            labelled[t.dxf.text] = labelled.get(t.dxf.text, 0) + 1
        notes = " | ".join(e.dxf.text for e in msp if e.dxf.layer == "NOTES")
        for want in ("units: mm", f"material: {s['material']}",
                     f"thickness: {s['thickness_mm']:g} mm", f"sheet size: {W:g} x {H:g} mm",
                     "kerf: 0.2 mm"):
            assert want in notes
    assert labelled == laser  # every instance placed exactly once (quantity 1 each here)


def test_sheet_stock_in_bom_and_manifest(laser_build):
    """The BOM orders the sheets (quantity = sheets of that stock); the manifest lists them."""
    out, report = laser_build
    with open(out / "bom.csv", newline="") as fh:
        rows = {r["part"]: r for r in csv.DictReader(fh)}
    by_stock: dict = {}
    for s in report["sheets"]["sheets"]:
        key = f"sheet {s['thickness_mm']:g} x {s['size_mm'][0]:g} x {s['size_mm'][1]:g} mm {s['material']}"
        by_stock[key] = by_stock.get(key, 0) + 1
    got = {r["designation"]: int(r["quantity"]) for r in rows.values() if r["group"] == "sheet stock"}
    assert got == by_stock
    files = {f["path"] for f in json.loads((out / "manifest.json").read_text())["files"]}
    assert {s["file"] for s in report["sheets"]["sheets"]} <= files


def test_laser_part_mass_by_hand(laser_build):
    """Base plate (a plain 2.5-D plate: CUT only): BOM mass = profile area x 6 mm x 2660
    kg/m^3 (5083, 2.66 g/cm^3); the area read back from its DXF with ezdxf: the rectangle
    of its four LINEs minus pi r^2 of each CIRCLE."""
    import ezdxf

    out, report = laser_build
    msp = ezdxf.readfile(out / "parts" / "base_plate.dxf").modelspace()
    assert {e.dxf.layer for e in msp} == {"CUT", "NOTES"}

    cut = [e for e in msp if e.dxf.layer == "CUT"]
    lines = [e for e in cut if e.dxftype() != "CIRCLE"]
    assert all(e.dxftype() == "LINE" for e in lines) and len(lines) == 4  # a rectangle
    x0, y0, x1, y1 = _box([seg for e in lines for seg in [(*_points(e)[0], *_points(e)[1])]])
    a = (x1 - x0) * (y1 - y0) - sum(math.pi * e.dxf.radius ** 2 for e in cut if e.dxftype() == "CIRCLE")
    m = {r["part"]: r["mass_g"] for r in report["bom"]}["base_plate"]  # bom.csv rounds to 0.01 g
    assert m == pytest.approx(a * 6.0 * 2.66e-3, rel=1e-9)


def test_pack_random_rectangles():
    """rectpack placements of 40 seeded random parts on 300 x 200 sheets: each once, on its
    sheet less the margin, gaps held (the geometry check above, on the boxes)."""
    from cad.export.nesting import pack

    rng = np.random.default_rng(7)
    sizes = [tuple(rng.uniform(10, 90, 2)) for _ in range(40)]
    spots = pack(sizes, (300.0, 200.0), 3.0, 10.0)
    assert len(spots) == len(sizes)
    per: dict = {}
    for (w, h), (b, x, y, rot) in zip(sizes, spots, strict=True):
        w, h = (h, w) if rot else (w, h)
        per.setdefault(b, []).append((x, y, x + w, y + h))
    for boxes in per.values():
        _check_layout(boxes, 300.0, 200.0, 3.0, 10.0)
    assert len(per) >= math.ceil(sum(w * h for w, h in sizes) / (280 * 180))


# ------------------------------------------------------------------ refusals (no CAD)
@pytest.mark.parametrize("edit,field,words", [
    ('bar_material = "acrylic-cast"', "parts.bar_material",
     ("coupler", "tapped M4 handle hole", "acrylic-cast")),
    ('base_material = "birch-plywood"\nbase_thickness_mm = 6.5', "parts.base_material",
     ("base plate", "tapped motor-mount screw holes x4")),
    ("bar_thickness_mm = 7.0", "parts.bar_thickness_mm", ("7 mm", "nearest: 6 or 8 mm")),
    ('motor_mount_material = "steel-1018"', "parts.motor_mount_material",
     ("motor mount", "not a sheet material")),
    ("laser_sheet_mm = [20.0, 300.0]", "parts.laser_sheet_mm", ("[50, 4000] mm", "got 20")),
    ("laser_sheet_mm = [300.0]", "parts.laser_sheet_mm", ("[width, length]",)),
])
def test_refused_names_part_and_feature(tmp_path, edit, field, words):
    from cad.errors import DesignError

    base = DESIGN.read_text()
    for line in edit.splitlines():  # replace the key's line or add it
        key = line.split(" =")[0]
        lines = [x for x in base.splitlines() if not x.startswith(key + " =")]
        base = "\n".join(lines + [line]) + "\n"
    p = tmp_path / "d.toml"
    p.write_text(base)
    from cad.design import load_design

    with pytest.raises(DesignError) as e:
        load_design(p)
    assert e.value.field == field
    for w in words:
        assert w in str(e.value)


def test_cli_refusal_is_one_line(tmp_path):
    """`hapticad build` on acrylic bars: exit 2, one line naming the field, part and feature."""
    p = tmp_path / "acrylic.toml"
    p.write_text(DESIGN.read_text().replace('bar_material = "aluminium-5083"',
                                            'bar_material = "acrylic-cast"'))
    r = subprocess.run([sys.executable, "-m", "cad", "build", str(p), "--out", str(tmp_path / "o")],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2
    err = [x for x in r.stderr.splitlines() if x.strip()]
    assert len(err) == 1 and "parts.bar_material" in err[0] and "tapped M4 handle hole" in err[0]
    assert not (tmp_path / "o").exists()


def test_acrylic_motor_mount_warns_and_changes_fit(tmp_path):
    """An acrylic motor mount: warning naming the part and the bored H7 pilot seat; the laser
    kind's fit and process say it is laser-cut at nominal (no H7), so its DXF is cut at
    nominal (no ISO fit for the shop to finish)."""
    from cad.assembly.laser import laser_kind
    from cad.data.fits import fit, shop_holes
    from cad.design import bounds, load_design
    from cad.parts import PartKind

    text = DESIGN.read_text().replace('motor_mount_material = "aluminium-5083"',
                                      'motor_mount_material = "acrylic-cast"')
    p = tmp_path / "d.toml"
    p.write_text(text)
    bounds.reset()
    d = load_design(p)
    w = [x for x in bounds.collected() if "motor mount (acrylic-cast)" in x]
    bounds.reset()
    assert len(w) == 1 and "bored 22 H7 pilot seat" in w[0] and "not H7" in w[0]
    k = PartKind("motor_mount", None, "acrylic-cast", True, plate=True,
                 process="waterjet/laser 5 mm plate; bore the pilot seat",
                 fits=(fit("pilot bore", 22.0),))
    got = laser_kind(k, d.parts)
    assert got.process.startswith("laser cut 5 mm acrylic-cast sheet (kerf 0.25 mm")
    assert "not H7" in got.process and "H7" not in got.fits[0].replace("not H7", "")
    assert shop_holes(got.fits) == ()  # nothing to ream: cut at nominal
    assert shop_holes(k.fits)[0].finish == "bore"


def test_sheet_data_against_sources():
    """Thickness bands as the sources state them: cast acrylic +-(0.4 + 0.1 t) (ISO 7823-1),
    6 mm -> 5.0..7.0; 5083 6 mm +-0.24 (EN 485-4 Table 1, group II, 1000-1250 mm wide);
    birch plywood 6.5 mm 6.1..6.9 (data sheet); densities 1.19 / 2.66 / 0.67 g/cm^3."""
    from cad.data.materials import SHEETS, get_material

    assert SHEETS["acrylic-cast"].thickness_range_mm[6.0] == (5.0, 7.0)
    assert SHEETS["aluminium-5083"].thickness_range_mm[6.0] == (5.76, 6.24)
    assert SHEETS["birch-plywood"].thickness_range_mm[6.5] == (6.1, 6.9)
    assert [get_material(m).density_kg_m3 for m in ("acrylic", "aluminium-5083", "plywood")] == \
        [1190.0, 2660.0, 670.0]
    for s in SHEETS.values():  # every value carries a source or says unverified
        assert set(s.source) >= {"thickness_range_mm", "sizes_mm", "E_GPa", "strength_MPa", "kerf_mm"}


def test_machined_report_keys_unchanged():
    from cad.design.parts import parse_parts

    assert "laser_sheet_mm" not in parse_parts({}).as_dict(report=True)
    assert parse_parts({"process": "laser"}).as_dict(report=True)["laser_sheet_mm"] is None


def test_bom_says_when_sheets_are_not_written():
    """A laser build without ``dxf`` in ``--formats`` plans the sheets but writes no
    ``sheets/``: the BOM rows that name the folder (a laser part's process, the sheet stock
    line) say it was not written and how to get it; with dxf they name it plainly."""
    from cad.assembly.laser import laser_process
    from cad.export.nesting import Sheet
    from cad.pipeline.family import SHEETS_NOT_WRITTEN, unwritten_sheets, sheet_rows

    part = {"part": "crank", "description": "crank",
            "process": laser_process("waterjet/laser 8 mm plate; ream pin bore x1",
                                     "acrylic-cast", 8.0)}
    stock = sheet_rows([Sheet("acrylic-cast", 8.0, (1000.0, 600.0))])[0]
    assert "nested: sheets/" in part["process"] and "(sheets/)" in stock["description"]
    for row in (part, stock):
        got = unwritten_sheets(row)
        said = got["process"] + got["description"]
        assert SHEETS_NOT_WRITTEN in said and "add dxf to --formats" in said
        assert "nested: sheets/" not in said and "(sheets/)" not in said


def test_thickness_tolerance_in_report(laser_build):
    """report.json sheets.thickness_tolerance (:mod:`cad.families.fourbar.sheet_tolerance`): a row for
    every ISO 4762 screw that clamps a sheet or engages one, and each pin stack; on
    hoeken_laser all hold over EN 485-4 +-0.24 mm (6 mm) / +-0.22 mm (5 mm). The hub's thread
    is cut for the thinnest crank (12 - 5.76 = 6.24 mm) and the handle screw's tip ends flush
    with the thinnest coupler (engages 5.76 mm, all of it)."""
    _, report = laser_build
    rows = {r["fastener"]: r for r in report["sheets"]["thickness_tolerance"]}
    sheet = {"crank", "coupler", "rocker", "base_plate", "motor_mount"}
    want = {n for n, f in report["fasteners"].items() if f["kind"] == "ISO 4762" and
            (sheet & set(f["clamps"]) or report["tapped_holes"][f["hole"]]["part"] in sheet)}
    assert want == {n for n in rows if not n.startswith("pin_")}
    assert {"pin_A2", "pin_A3", "pin_A4"} <= set(rows)
    assert all(r["verdict"] == "holds" for r in rows.values())
    assert rows["leg_screw_1"]["engagement_worst_mm"] == pytest.approx([10 - 0.24, 10 + 0.24])
    assert rows["post_screw"]["engagement_worst_mm"] == pytest.approx([10 - 0.24, 10 + 0.24])
    assert report["tapped_holes"]["crank_hub:screw_1"]["depth_mm"] == pytest.approx(12 - 5.76)
    assert rows["hub_screw_1"]["engagement_worst_mm"] == pytest.approx([5.76, 6.24])
    assert report["fasteners"]["handle_screw"]["engagement_mm"] == pytest.approx(5.76)
    assert rows["handle_screw"]["window_mm"] == pytest.approx([5.76, 5.76])
