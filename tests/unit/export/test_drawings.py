"""Issue 25 section 1: one drawing sheet per made part (``--formats …,drawings``), read back.

Every number a sheet prints about a hole or boss (its axis, centre from the datum, diameter
or radius) is compared with the part's STEP read back by build123d: each cylindrical face
(``faces().filter_by(GeomType.CYLINDER)``, its ``axis_of_rotation`` and ``radius``) must be
a row of the sheet's feature table within half the last printed digit (0.005 mm), and each
row a face. The title block states the BOM's material and quantity and ISO 2768-m; fits and
threads are the BOM's and report.json's; ``drawings.pdf`` has one page per made part.
"""

from __future__ import annotations

import csv
import json
import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
#: Half the last digit of a position printed with 2 decimals (mm).
PRINTED_MM = 0.005 + 1e-9
ROW = re.compile(r"^([HB])(\d+) axis ([xyz]) ([xyz])=(-?\d+\.\d+) ([xyz])=(-?\d+\.\d+) "
                 r"([ØR])(\d+\.\d+) [xyz]=(-?\d+\.\d+)\.\.(-?\d+\.\d+)$")
#: A row of an oblique axis: direction, the axis point nearest the datum, size, extent.
ROW_N = re.compile(r"^([HB])(\d+) axis n=\((-?[\d.]+),(-?[\d.]+),(-?[\d.]+)\) "
                   r"x=(-?[\d.]+) y=(-?[\d.]+) z=(-?[\d.]+) ([ØR])([\d.]+) t=")
#: Half the last digit of a printed direction component.
PRINTED_DIR = 5e-5 + 1e-12


def sheet_texts(path: Path) -> list[str]:
    """Every text element of an SVG sheet (xml.etree), in document order."""
    ns = "{http://www.w3.org/2000/svg}"
    return ["".join(t.itertext()) for t in ET.parse(path).getroot().iter(f"{ns}text")]


def pdf_pages(path: Path) -> int:
    """Page objects of a PDF (``/Type /Page``, not ``/Pages``): matplotlib keeps the object
    dictionaries uncompressed."""
    return len(re.findall(rb"/Type\s*/Page(?![a-zA-Z])", path.read_bytes()))


def bom(out: Path) -> dict[str, dict]:
    with open(out / "bom.csv", newline="") as fh:
        return {r["part"]: r for r in csv.DictReader(fh)}


def _axis_faces(step: Path, geom: str):
    """``(face, direction, k, position, lo)`` of each face of type ``geom`` ("CYLINDER",
    "CONE") of a STEP (build123d): its axis direction, the index ``k`` of the axis' largest
    component, its position from the part's bounding-box minimum corner ``lo``."""
    import build123d as bd

    shape = bd.import_step(step)
    box = shape.bounding_box(optimal=True)
    lo = (box.min.X, box.min.Y, box.min.Z)
    for f in shape.faces().filter_by(getattr(bd.GeomType, geom)):
        ax = f.axis_of_rotation
        d = (ax.direction.X, ax.direction.Y, ax.direction.Z)
        k = max(range(3), key=lambda i: abs(d[i]))
        yield f, d, k, (ax.position.X - lo[0], ax.position.Y - lo[1], ax.position.Z - lo[2]), lo


def solid_features(step: Path) -> set[tuple]:
    """``{(axis, u, v, d_or_r, full)}`` of the cylindrical faces of a STEP (build123d):
    centre from the bounding box's minimum corner; full circles by diameter, arcs by radius."""
    from OCP.BRepTools import BRepTools

    out = []
    for f, d, k, p, _ in _axis_faces(step, "CYLINDER"):
        r = f.radius if f.radius is not None else f.geom_adaptor().Radius()
        u0, u1, _, _ = BRepTools.UVBounds_s(f.wrapped)  # angle range of the face (rad)
        if abs(abs(d[k]) - 1.0) < 1e-9:
            i, j = [q for q in range(3) if q != k]
            out.append(("xyz"[k], round(p[i], 3), round(p[j], 3), round(r, 4), u1 - u0))
            continue
        sgn = math.copysign(1.0, next(c for c in d if abs(c) > 1e-9))
        n = tuple(round(sgn * c, 6) for c in d)
        t = sum(a * b for a, b in zip(p, n, strict=True))
        foot = tuple(round(a - t * b, 3) for a, b in zip(p, n, strict=True))
        out.append((n, *foot, round(r, 4), u1 - u0))
    # faces of one feature (a cylinder split in halves) add up to a full turn
    spans: dict = {}
    for *key, span in out:
        spans[tuple(key)] = spans.get(tuple(key), 0.0) + span
    return {(*key, span > 2 * math.pi - 1e-6) for key, span in spans.items()}


#: A chamfer row: axis, centre, extent along the axis, then C size x 45 deg or legs x angle.
CHAMFER_ROW = re.compile(r"^C\d+ chamfer ([xyz]) [xyz]=(-?\d+\.\d+) [xyz]=(-?\d+\.\d+) "
                         r"[xyz]=(-?\d+\.\d+)\.\.(-?\d+\.\d+)$")
CHAMFER_SIZE = re.compile(r"^(?:bore|edge) (?:C(\d+\.\d+) x 45 deg|(\d+\.\d+) x "
                          r"(\d+\.\d+) deg \(radial (\d+\.\d+)\))$")


def chamfer_table(texts: list[str]) -> list[tuple]:
    """``(axis, u, v, lo, hi, axial leg)`` of every chamfer row (geometry line, then its
    callout line below)."""
    out = []
    for t, note in zip(texts, texts[1:], strict=False):
        m = CHAMFER_ROW.match(t)
        if m:
            c = CHAMFER_SIZE.match(note)
            assert c, note
            axial = float(c[1] or c[2])
            out.append((m[1], *(float(m[k]) for k in range(2, 6)), axial))
    return out


def solid_chamfers(step: Path) -> list[tuple]:
    """``(axis, u, v, lo, hi, axial leg)`` of the conical faces of a STEP (build123d):
    centre from the cone's axis, extent and axial leg from the face's bounding box, all from
    the part's bounding-box minimum corner."""
    out = []
    for f, _, k, p, lo in _axis_faces(step, "CONE"):
        i, j = [q for q in range(3) if q != k]
        fb = f.bounding_box(optimal=True)
        a0, a1 = (fb.min.X, fb.min.Y, fb.min.Z)[k] - lo[k], (fb.max.X, fb.max.Y, fb.max.Z)[k] - lo[k]
        out.append(("xyz"[k], p[i], p[j], a0, a1, a1 - a0))
    return out


def table_rows(texts: list[str]) -> list[tuple]:
    """``(axis, u, v, size, full, kind, text)``; an oblique axis: ``(direction, x, y, z, size,
    full, kind, text)``."""
    rows = []
    for t in texts:
        m, n = ROW.match(t), ROW_N.match(t)
        if m:
            kind, _, axis, _, u, _, v, sym, size, _, _ = m.groups()
            rows.append((axis, float(u), float(v), float(size), sym == "Ø", kind, t))
        elif n:
            kind, _, dx, dy, dz, x, y, z, sym, size = n.groups()
            rows.append(((float(dx), float(dy), float(dz)), float(x), float(y), float(z),
                         float(size), sym == "Ø", kind, t))
    return rows


def _hits(rows, feat):
    """The table rows that state the solid's feature ``feat`` (within the printed digits)."""
    if isinstance(feat[0], str):
        axis, u, v, r, full = feat
        size = 2 * r if full else r
        return [x for x in rows if x[0] == axis and x[4] == full
                and abs(x[1] - u) <= PRINTED_MM and abs(x[2] - v) <= PRINTED_MM
                and abs(x[3] - size) <= PRINTED_MM]
    n, px, py, pz, r, full = feat
    size = 2 * r if full else r
    return [x for x in rows if not isinstance(x[0], str) and x[5] == full
            and all(abs(a - b) <= PRINTED_DIR for a, b in zip(x[0], n, strict=True))
            and all(abs(a - b) <= PRINTED_MM for a, b in zip(x[1:4], (px, py, pz), strict=True))
            and abs(x[4] - size) <= PRINTED_MM]


@pytest.fixture(scope="module")
def hoeken_drawings(tmp_path_factory):
    """The bundled Hoeken with STEP and drawings (inertia fidelity: the cheapest with every
    feature of the made parts)."""
    from cad.design import load_design
    from cad.pipeline import build_design

    out = tmp_path_factory.mktemp("drawings") / "out"
    d = load_design(ROOT / "designs" / "hoeken.toml")
    build_design(d, out, {"step", "drawings"}, fidelity="inertia", use_cache=False)
    return d, out


def _check_sheet(out: Path, part: str, row: dict):
    """One sheet against its part's STEP and BOM row."""
    texts = sheet_texts(out / "drawings" / f"{part}.svg")
    rows = table_rows(texts)
    faces = solid_features(out / "parts" / f"{part}.step")
    matched = set()
    for feat in faces:
        hit = _hits(rows, feat)
        assert hit, (part, feat)
        matched |= {x[-1] for x in hit}
    assert matched == {x[-1] for x in rows}, part  # no row without a face
    chamfer_rows = chamfer_table(texts)
    cones = solid_chamfers(out / "parts" / f"{part}.step")
    assert len(chamfer_rows) == len(cones), (part, chamfer_rows, cones)
    for cone in cones:  # each conical face printed with its place and legs, once
        hit = [r for r in chamfer_rows if r[0] == cone[0]
               and all(abs(a - b) <= PRINTED_MM for a, b in zip(r[1:5], cone[1:5], strict=True))
               and abs(r[5] - cone[5]) <= PRINTED_MM]
        assert hit, (part, cone, chamfer_rows)
    assert f"part: {part}" in texts
    assert f"material: {row['material']}" in texts
    assert f"quantity: {row['quantity']}" in texts
    assert "general tolerance: ISO 2768-m" in texts
    return texts, rows


def test_hoeken_sheets_print_the_solids_holes_fits_and_threads(hoeken_drawings):
    design, out = hoeken_drawings
    rows = bom(out)
    made = sorted(p for p, r in rows.items() if r["made_or_bought"] == "made")
    assert sorted(p.stem for p in (out / "drawings").glob("*.svg")) == made
    assert pdf_pages(out / "drawings.pdf") == len(made)
    rep = json.loads((out / "report.json").read_text())
    for part in made:
        texts, table = _check_sheet(out, part, rows[part])
        assert f"design: {design.name}" in texts
        joined = "\n".join(texts)
        for f in filter(None, rows[part]["fits"].split("; ")):
            *label, d, cls = f.split()
            assert f"Ø{d} {cls} ({' '.join(label)})" in joined, (part, f)
        for h in rep["tapped_holes"].values():  # in the kind itself or an instance leg_1 ...
            if h["part"] == part or re.fullmatch(rf"{re.escape(part)}_\d+", h["part"]):
                size = h["size"].split("-")[0]
                assert re.search(rf"{size} tap drill Ø[\d.]+, thread [\d.]+ deep", joined), part
    # the bars: an H7 pin bore, J7 seats, the coupler's M4 at P (BOM process column)
    coupler = "\n".join(sheet_texts(out / "drawings" / "coupler.svg"))
    assert "Ø16 J7 (bearing seat), 4 deep" in coupler
    assert "Ø8 H7 (pin bore), thru" in coupler
    assert "M4 tap drill Ø3.3" in coupler and "SECTION A-A" in coupler


def test_sheets_are_byte_identical_run_to_run(hoeken_drawings, tmp_path):
    from cad.pipeline import build_design

    design, out = hoeken_drawings
    again = tmp_path / "again"
    build_design(design, again, {"step", "drawings"}, fidelity="inertia", use_cache=False)
    for p in sorted((out / "drawings").glob("*.svg")) + [out / "drawings.pdf"]:
        assert (again / p.relative_to(out)).read_bytes() == p.read_bytes(), p.name


@pytest.mark.parametrize("fam", ["pantograph", "twin-pantograph", "powermouse", "delta"])
def test_every_made_part_of_every_family_has_a_sheet(request, fam):
    from tests.conftest import family_build

    _, out, _ = family_build(request, fam)
    folders = [out] + ([out / "rig"] if fam == "powermouse" else [])
    for f in folders:
        rows = bom(f)
        made = sorted(p for p, r in rows.items() if r["made_or_bought"] == "made")
        assert made, f
        assert sorted(p.stem for p in (f / "drawings").glob("*.svg")) == made
        assert pdf_pages(f / "drawings.pdf") == len(made)
        for part in made:
            _check_sheet(f, part, rows[part])


POCKET_ROW = re.compile(r"^P\d+ pocket z x=(-?\d+\.\d+) y=(-?\d+\.\d+) (\d+\.\d+) x "
                        r"(\d+\.\d+) x (\d+\.\d+) z=(-?\d+\.\d+)\.\.(-?\d+\.\d+)$")
POCKET_NOTE = re.compile(r"^(through|blind \(floor\)); corners R(\d+\.\d+); length along "
                         r"(-?\d+\.\d) deg from x$")


def test_bar_pockets_are_dimensioned_from_the_solid(tmp_path):
    """hoeken_light (``bar_pockets = true``): each bar's sheet prints every through slot
    (length x width x depth, corner radius, centre) as its solid shows it, read
    independently with build123d (the inner wires of the bar's top face: their bounding
    box and arc radii, the bar's thickness), and the width is the design's closed form
    ``bar_width - 2 web`` with round ends of half that (cad/parts/bars.py)."""
    import build123d as bd

    from cad.design import load_design
    from cad.export.drawings import SheetPart, write_drawings
    from cad.families.fourbar import assemble

    d = load_design(ROOT / "designs" / "hoeken_light.toml")
    assert d.parts.bar_pockets
    width = d.parts.bar_width_mm - 2 * d.parts.bar_pocket_web_mm
    kinds = {i.kind.name: i.kind for i in assemble(d, "preview").instances}
    bars = [kinds[n] for n in ("crank", "coupler", "rocker")]
    write_drawings([SheetPart(k.name, k.shape, k.material, 1, k.process, k.plate) for k in bars],
                   tmp_path, d.name)
    total = 0
    for k in bars:
        texts = sheet_texts(tmp_path / "drawings" / f"{k.name}.svg")
        rows = []
        for t, note in zip(texts, texts[1:], strict=False):
            if m := POCKET_ROW.match(t):
                n = POCKET_NOTE.match(note)
                assert n, note
                assert n[1] == "through" and float(n[3]) == 0.0  # along the bar (link x)
                rows.append((*(float(x) for x in m.groups()), float(n[2])))
        solid = bd.Solid(k.shape)
        box = solid.bounding_box(optimal=True)
        top = solid.faces().sort_by(bd.Axis.Z)[-1]
        slots = []
        for w in top.inner_wires():
            arcs = [e for e in w.edges() if e.geom_type == bd.GeomType.CIRCLE]
            if len(w.edges()) == 1:
                continue  # a round hole (a cylinder row of its own)
            wb = w.bounding_box(optimal=True)
            slots.append((wb.center().X - box.min.X, wb.center().Y - box.min.Y, wb.size.X,
                          wb.size.Y, box.size.Z, 0.0, box.size.Z, min(e.radius for e in arcs)))
        assert len(rows) == len(slots) >= 1, (k.name, rows, slots)
        for sl in slots:
            hit = [r for r in rows if all(abs(a - b) <= PRINTED_MM for a, b in
                                          zip(r, sl, strict=True))]
            assert len(hit) == 1, (k.name, sl, rows)
            assert hit[0][3] == pytest.approx(width, abs=PRINTED_MM)
            assert hit[0][7] == pytest.approx(width / 2, abs=PRINTED_MM)
        total += len(slots)
    assert total >= 3


def test_pocket_with_a_floor_and_sharp_corners_is_blind():
    """A 30 x 20 x 10 block with a 12 x 6 x 4 deep pocket (sharp corners, centre (10, 8)):
    detected blind with its sizes; a cylinder with a C1.5 chamfer on its top edge: one
    external conical chamfer, legs 1.5 and 1.5 at 45 deg, z 6.5..8 (build123d made both)."""
    import build123d as bd

    from cad.export.drawings.features import chamfers, pockets

    block = bd.Box(30, 20, 10, align=(bd.Align.MIN,) * 3)
    cut = bd.Pos(10, 8, 8) * bd.Box(12, 6, 4)
    (p,) = pockets((block - cut).wrapped)
    assert (p.axis, p.through, p.corner_r_mm) == ("z", False, None)
    assert (p.length_mm, p.width_mm, p.depth_mm) == pytest.approx((12, 6, 4), abs=1e-9)
    assert (p.u_mm, p.v_mm, p.lo_mm, p.hi_mm) == pytest.approx((10, 8, 6, 10), abs=1e-9)
    round_block = bd.Cylinder(10, 8, align=(bd.Align.CENTER, bd.Align.CENTER, bd.Align.MIN))
    round_block = bd.chamfer(round_block.edges().sort_by(bd.Axis.Z)[-1], 1.5)
    (c,) = chamfers(round_block.wrapped)
    assert (c.axial_mm, c.radial_mm, c.angle_deg) == pytest.approx((1.5, 1.5, 45.0), abs=1e-9)
    assert (c.lo_mm, c.hi_mm, c.internal) == (pytest.approx(6.5), pytest.approx(8.0), False)


#: A thread callout: size, the thread text (one depth, or one per record on the axis), drill.
THREAD_NOTE = re.compile(r"^(M\d+(?:\.\d+)?) tap drill Ø[\d.]+(?:, thread (.+))?, drill (.+)$")


def _record_on_row(h: dict, row: tuple, datum: tuple) -> bool:
    """Does report.json's hole ``h`` (axis and point in the part frame) lie on the sheet row's
    axis (an aligned axis; centre from the datum, printed to 0.01 mm)?"""
    axis, u, v = row[0], row[1], row[2]
    k = "xyz".index(axis)
    a = h["axis"]
    if abs(abs(a[k]) - math.sqrt(sum(c * c for c in a))) > 1e-9:
        return False
    i, j = [q for q in range(3) if q != k]
    return (abs(h["point_mm"][i] - datum[i] - u) <= PRINTED_MM
            and abs(h["point_mm"][j] - datum[j] - v) <= PRINTED_MM)


def test_hoeken_thread_depths_are_each_holes_own_record(hoeken_drawings):
    """Each tapped hole printed on each Hoeken sheet states the full-thread depth of its own
    record in report.json (``tapped_holes``), found by the record's place (axis and a point,
    part frame) on the hole's axis as the sheet prints it from the datum (the STEP's
    bounding-box minimum, build123d); a record without a place: the one depth of the
    part's records of that size, or else "(from the solid)" with the drill's depth. The crank
    hub's radial set-screw hole (its record 6.887 mm) and its axial M3 screw holes (6 mm) are
    both M3: matching by size alone printed 6 on the radial one. Every placed record lies on
    exactly one printed hole."""
    import build123d as bd

    _, out = hoeken_drawings
    rep = json.loads((out / "report.json").read_text())
    made = [p for p, r in bom(out).items() if r["made_or_bought"] == "made"]
    checked = set()
    for part in made:
        texts = sheet_texts(out / "drawings" / f"{part}.svg")
        box = bd.import_step(out / "parts" / f"{part}.step").bounding_box(optimal=True)
        datum = (box.min.X, box.min.Y, box.min.Z)
        mine = [h for h in rep["tapped_holes"].values()
                if h["part"] == part or re.fullmatch(rf"{re.escape(part)}_\d+", h["part"])]
        placed_hits = {h["name"]: 0 for h in mine if "axis" in h}
        for geom, note in zip(texts, texts[1:], strict=False):
            m, t = ROW.match(geom), THREAD_NOTE.match(note)
            if not (m and t):
                continue
            row = table_rows([geom])[0]
            same = [h for h in mine if h["size"].split("-")[0] == t[1]]
            on = [h for h in same if "axis" in h and _record_on_row(h, row, datum)]
            for h in on:
                placed_hits[h["name"]] += 1
            pool = on or [h for h in same if "axis" not in h]
            want = sorted({round(h["depth_mm"], 9) for h in pool})
            assert t[2] is not None, (part, note)
            got = [float(x) for x in re.findall(r"(\d+(?:\.\d+)?) deep", t[2])]
            if len(want) > 1 and not on:  # no record says which: the solid's depth
                lo, hi = float(m[10]), float(m[11])
                assert t[2].endswith("(from the solid)") and got == [pytest.approx(hi - lo, abs=PRINTED_MM)]
            else:
                assert want, (part, note)
                assert sorted(got) == [pytest.approx(d, abs=PRINTED_MM) for d in want], (part, note, want)
            checked.add((part, geom))
        assert all(n == 1 for n in placed_hits.values()), (part, placed_hits)
    hub = [g for p, g in checked if p == "crank_hub"]
    assert len(hub) == 4 and any(g.split()[2] != "z" for g in hub)  # 3 axial, 1 radial


def test_thread_depth_of_an_unplaced_ambiguous_record_is_the_solids():
    """Records without a place (:func:`cad.export.drawings.notes.thread_depths`): one depth of
    the size, that one; two the hole can hold, neither (the solid's drill depth printed); two
    of which the hole holds one (a 7 mm hole, records 6 and 9 mm), that one."""
    from cad.export.drawings.features import Cylinder
    from cad.export.drawings.notes import callout

    hole = Cylinder("z", 5.0, 5.0, 2.5, 3.0, 10.0, True, 360.0)  # M3 tap drill, 7 deep
    one = (("M3-0.5", 6.0, "p:a", None, None), ("M3-0.5", 6.0, "p:b", None, None))
    assert callout(hole, (), one, 20.0) == "M3 tap drill Ø2.5, thread 6 deep, drill 7 deep"
    two = (("M3-0.5", 6.0, "p:a", None, None), ("M3-0.5", 6.8, "p:b", None, None))
    assert callout(hole, (), two, 20.0) == \
        "M3 tap drill Ø2.5, thread 7 deep (from the solid), drill 7 deep"
    held = (("M3-0.5", 6.0, "p:a", None, None), ("M3-0.5", 9.0, "p:b", None, None))
    assert callout(hole, (), held, 20.0) == "M3 tap drill Ø2.5, thread 6 deep, drill 7 deep"
    # placed on another axis (x = 1 from a datum at the origin): not this hole's record
    away = (("M3-0.5", 6.0, "p:a", (0.0, 0.0, 1.0), (1.0, 5.0, 0.0)),
            ("M3-0.5", 6.8, "p:b", (0.0, 0.0, 1.0), (5.0, 5.0, 0.0)))
    assert callout(hole, (), away, 20.0) == "M3 tap drill Ø2.5, thread 6.8 deep, drill 7 deep"
