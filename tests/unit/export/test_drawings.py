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


def solid_features(step: Path) -> set[tuple]:
    """``{(axis, u, v, d_or_r, full)}`` of the cylindrical faces of a STEP (build123d):
    centre from the bounding box's minimum corner; full circles by diameter, arcs by radius."""
    import build123d as bd
    from OCP.BRepTools import BRepTools

    shape = bd.import_step(step)
    box = shape.bounding_box(optimal=True)
    lo = (box.min.X, box.min.Y, box.min.Z)
    out = []
    for f in shape.faces().filter_by(bd.GeomType.CYLINDER):
        ax = f.axis_of_rotation
        d = (ax.direction.X, ax.direction.Y, ax.direction.Z)
        k = max(range(3), key=lambda i: abs(d[i]))
        p = (ax.position.X - lo[0], ax.position.Y - lo[1], ax.position.Z - lo[2])
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


@pytest.mark.parametrize("fam", ["pantograph", "twin-pantograph", "powermouse"])
def test_every_made_part_of_every_family_has_a_sheet(family_builds, fam):
    _, out, _ = family_builds[fam]
    folders = [out] + ([out / "rig"] if fam == "powermouse" else [])
    for f in folders:
        rows = bom(f)
        made = sorted(p for p, r in rows.items() if r["made_or_bought"] == "made")
        assert made, f
        assert sorted(p.stem for p in (f / "drawings").glob("*.svg")) == made
        assert pdf_pages(f / "drawings.pdf") == len(made)
        for part in made:
            _check_sheet(f, part, rows[part])
