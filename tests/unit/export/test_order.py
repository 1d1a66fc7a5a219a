"""A BOM to order from (issue 25 §5): stock, designations, prices, totals, read back.

Proof read from the files with a second tool: ``bom.csv`` and ``order.csv`` by the csv
module, the totals recomputed here from the price file (read by the csv module, not by
:func:`cad.export.order.load_prices`), the stock of every made part compared with the
bounding box of that part's solid read back from ``parts/<part>.step`` by build123d.
"""

from __future__ import annotations

import csv
import math
import subprocess
import sys
from pathlib import Path

import pytest

from cad.errors import DesignError

ROOT = Path(__file__).resolve().parents[3]

PRICES = (
    "designation,unit_price,currency,source\n"
    "618/8 (8x16x4),4.20,EUR,test value\n"
    "ISO 4762 M3-0.5 x 12,0.15,EUR,test value\n"
    "ISO 4762 M6-1 x 16,0.31,EUR,test value\n"
    "crank,35,EUR,test shop quote\n"
    "not in this design,9.99,EUR,test value\n"
)


def _read(path: Path) -> list[dict]:
    with path.open(newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def priced(tmp_path_factory):
    """The bundled Hoeken built (inertia fidelity, STEP parts) once with ``--prices`` and
    once with the same prices as a ``[prices]`` design table."""
    from cad.design import load_design, parse_design
    from cad.design.fields import load_toml
    from cad.export.order import load_prices
    from cad.pipeline import build_design

    root = tmp_path_factory.mktemp("order")
    pfile = root / "prices.csv"
    pfile.write_text(PRICES, encoding="utf-8")
    d = load_design(ROOT / "designs" / "hoeken.toml")
    out = root / "file"
    rep = build_design(d, out, {"step"}, fidelity="inertia", use_cache=False,
                       prices=load_prices(pfile))
    raw = load_toml(ROOT / "designs" / "hoeken.toml")
    raw["prices"] = {r["designation"]: float(r["unit_price"]) for r in _read(pfile)}
    raw["prices"]["currency"] = "EUR"
    out_t = root / "table"
    rep_t = build_design(parse_design(raw, "hoeken+prices"), out_t, {"step"},
                         fidelity="inertia", use_cache=False)
    return pfile, out, rep, out_t, rep_t


def _expected_total(pfile: Path, bom: list[dict]) -> tuple[float, int]:
    """Total and number of unpriced lines, from the price file and bom.csv only."""
    price = {r["designation"]: float(r["unit_price"]) for r in _read(pfile)}
    total, unpriced = 0.0, 0
    for r in bom:
        p = price.get(r["designation"], price.get(r["part"]))
        if p is None:
            unpriced += 1
        else:
            total += p * int(r["quantity"])
    return total, unpriced


def test_bom_and_order_totals_recomputed_from_the_price_file(priced):
    pfile, out, rep, _, _ = priced
    bom = _read(out / "bom.csv")
    total, unpriced = _expected_total(pfile, bom)
    # 3 bearings x 4.20 + 3 x 0.15 + 5 x 0.31 + 1 crank x 35 (the counts from bom.csv)
    assert total == pytest.approx(12.60 + 0.45 + 1.55 + 35.0)
    for r in bom:
        if r["unit_price"]:
            assert float(r["line_price"]) == pytest.approx(float(r["unit_price"]) * int(r["quantity"]))
        else:
            assert r["line_price"] == ""  # nothing invented
    assert sum(1 for r in bom if not r["unit_price"]) == unpriced
    order = _read(out / "order.csv")
    last = order[-1]
    assert last["group"] == "total" and last["designation"] == "EUR"
    assert float(last["line_price"]) == pytest.approx(total, abs=0.005)
    assert last["parts"] == f"{unpriced} unpriced lines"
    assert sum(float(o["line_price"]) for o in order[:-1] if o["line_price"]) == pytest.approx(total)
    assert rep["order"]["unpriced_lines"] == unpriced
    assert rep["order"]["unused_prices"] == ["not in this design"]
    md = (out / "report.md").read_text()
    assert f"Total: {total:.2f} EUR ({unpriced} of {len(bom)} lines unpriced" in md
    assert "order.csv" in rep["files"]


def test_design_prices_table_gives_the_same_bom(priced):
    _, out, _, out_t, rep_t = priced
    assert _read(out_t / "bom.csv") == _read(out / "bom.csv")
    assert rep_t["order"]["price_source"] == "[prices]"


def test_bought_parts_carry_group_designation_and_catalog_order_code(priced):
    _, out, _, _, _ = priced
    bought = {r["part"]: r for r in _read(out / "bom.csv") if r["made_or_bought"] == "bought"}
    assert all(r["designation"] and r["group"] != "other" for r in bought.values()), bought
    b = bought["bearing_M8-16-4"]
    assert (b["group"], b["designation"], b["order_code"]) == (
        "ball bearings", "618/8 (8x16x4)", "SKF 618/8")
    cs = bought["cap_screw_M3-0.5x12"]
    assert (cs["group"], cs["designation"]) == ("socket head cap screws", "ISO 4762 M3-0.5 x 12")
    m = bought["motor_maxon-re35"]
    # the catalog names no order number for the RE 35 winding: the cell stays empty
    assert (m["designation"], m["order_code"]) == ("maxon RE 35", "")


def _step_bbox_mm(path: Path) -> list[float]:
    from build123d import import_step

    bb = import_step(str(path)).bounding_box()
    return sorted((bb.size.X, bb.size.Y, bb.size.Z))


def _rod_fit_mm(path: Path, length_mm: float) -> float:
    """Smallest radius (mm) about the axis of one of its cylindrical faces (build123d
    ``Face.axis_of_rotation``) holding the solid read back from ``path`` (its build123d
    tessellation vertices, 0.01 mm), among the axes along which it spans at most
    ``length_mm``; inf if none."""
    import numpy as np
    from build123d import GeomType, import_step

    shape = import_step(str(path))
    pts = np.array([(v.X, v.Y, v.Z) for v in shape.tessellate(0.01)[0]])
    best = math.inf
    for face in shape.faces().filter_by(GeomType.CYLINDER):
        ax = face.axis_of_rotation
        o, u = np.array(tuple(ax.position)), np.array(tuple(ax.direction))
        along = (pts - o) @ u
        if np.ptp(along) <= length_mm + 1e-3:
            best = min(best, np.linalg.norm(pts - o - np.outer(along, u), axis=1).max())
    return best


def _check_stock(out: Path) -> set[str]:
    """Every made part's stock (bom.csv) holds the bounding box of its solid read back from
    parts/<part>.step, by at most the stated allowance (+1 mm of rounding); the stock forms."""
    from cad import tolerances as tol
    from cad.export.order import stock_dims_mm

    forms = set()
    for r in (r for r in _read(out / "bom.csv") if r["made_or_bought"] == "made"):
        form, nums = stock_dims_mm(r["stock"])
        forms.add(form)
        assert r["stock"].endswith(r["material"]), r
        if form in ("filament", "wire"):  # by mass, not by size
            assert nums[0] == pytest.approx(float(r["mass_g"]), abs=0.5), r
            continue
        if form in ("plate", "block"):  # holds the box, by at most the allowance (+1 mm)
            box, bb = sorted(nums), _step_bbox_mm(out / "parts" / f"{r['part']}.step")
            # 1e-3 mm: build123d's box of the re-imported solid vs OCCT's optimal box
            assert all(s >= b - 1e-3 for s, b in zip(box, bb, strict=True)), (r["part"], box, bb)
            most = 2 * max(tol.STOCK_PLATE_MARGIN_MM, tol.STOCK_BLOCK_MARGIN_MM) + 1
            assert all(s - b <= most for s, b in zip(box, bb, strict=True)), (r["part"], box, bb)
            if form == "plate":
                assert nums[0] == pytest.approx(bb[0], abs=1e-3)  # thickness = the part's
        else:  # a round bar (its axis may be oblique) holds the solid, by at most the
            # allowance (+1 mm of rounding)
            if form == "tube" and len(nums) == 3:  # outer / bore: a wall to order
                assert 0 < nums[1] < nums[0], (r["part"], nums)
            rad = _rod_fit_mm(out / "parts" / f"{r['part']}.step", nums[-1])
            assert rad <= nums[0] / 2 + 1e-3, (r["part"], nums, rad)
            extra = tol.STOCK_ROD_DIAMETER_ALLOWANCE_MM if form == "rod" else 0.0
            assert nums[0] - 2 * rad <= extra + 1.1, (r["part"], nums, rad)
    return forms


def test_stock_contains_each_made_part_read_back_from_its_step(priced):
    _, out, _, _, _ = priced
    assert _check_stock(out) == {"plate", "rod"}


def test_every_family_lists_stock_and_designations(family_builds):
    forms = set()
    for fam, (_, out, _) in family_builds.items():
        forms |= _check_stock(out)
        for r in _read(out / "bom.csv"):
            if r["made_or_bought"] == "bought":
                assert r["designation"] and r["group"], (fam, r["part"])
        assert _read(out / "order.csv")[-1]["group"] == "total"
    assert forms == {"plate", "rod", "tube", "block", "wire"}
    # the pantograph's bearings and motors are found by their catalog description
    bought = {r["part"]: r for r in _read(family_builds["pantograph"][1] / "bom.csv")}
    assert bought["bearing"]["order_code"] == "SKF 618/4"
    assert bought["motor"]["designation"] == "maxon RE 35"


# --------------------------------------------------------------------------- bad prices
@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("designation,price\nx,1\n", "row 1 (header): column 'unit_price' missing"),
        ("designation,unit_price\nx,abc\n", "row 2 column unit_price: value 'abc' is not a number"),
        ("designation,unit_price\nx,1\ny,-2\n", "row 3 column unit_price: value '-2' must be a"),
        ("designation,unit_price\nx,nan\n", "row 2 column unit_price: value 'nan' must be a"),
        ("designation,unit_price\n,1\n", "row 2 column designation: value '' is empty"),
        ("designation,unit_price\nx,1\nx,2\n", "row 3 column designation: value 'x' repeats row 2"),
        ("designation,unit_price,currency\nx,1,EUR\ny,2,USD\n",
         "row 3 column currency: value 'USD' differs from 'EUR' (row 2)"),
    ],
)
def test_bad_price_file_names_file_row_column_value(tmp_path, text, message):
    from cad.export.order import load_prices

    p = tmp_path / "p.csv"
    p.write_text(text, encoding="utf-8")
    with pytest.raises(DesignError) as exc:
        load_prices(p)
    assert exc.value.field == "--prices"
    assert str(exc.value).startswith(f"--prices: {p} {message}"), str(exc.value)


def test_bad_price_file_on_the_cli_exits_2_one_line_nothing_written(tmp_path):
    p = tmp_path / "p.csv"
    p.write_text("designation,unit_price\n618/8 (8x16x4),abc\n", encoding="utf-8")
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "cad", "build", str(ROOT / "designs" / "hoeken.toml"),
                        "--out", str(out), "--prices", str(p)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2
    assert r.stderr.strip().splitlines() == [
        f"hapticad: error: --prices: {p} row 2 column unit_price: value 'abc' is not a number"]
    assert not out.exists()


def test_bad_design_prices_table_names_the_key():
    from cad.design import parse_design
    from cad.design.fields import load_toml

    raw = load_toml(ROOT / "designs" / "hoeken.toml")
    raw["prices"] = {"618/8 (8x16x4)": "cheap"}
    with pytest.raises(DesignError) as exc:
        parse_design(raw)
    assert exc.value.field == "prices.618/8 (8x16x4)"
    raw["prices"] = {"crank": -math.inf}
    with pytest.raises(DesignError, match=r"price in 0\.\.1e\+09"):
        parse_design(raw)


def test_totals_are_the_decimal_sums_not_float_noise():
    """12.60 + 0.45 + 35 is 48.05 (by hand), and 3 x 0.15 is 0.45: report.json showed
    48.050000000000004 (the binary sum). Lines are exact decimals rounded to the cent."""
    from cad.export.order import apply_prices

    rows = [{"part": p, "designation": p, "quantity": q, "made_or_bought": "bought"}
            for p, q in (("a", 1), ("b", 1), ("c", 1), ("d", 3))]
    table = {"prices": {"a": 12.60, "b": 0.45, "c": 35.0, "d": 0.15}, "currency": "EUR", "source": "hand"}
    s = apply_prices(rows, table)
    assert s["total_price"] == 48.5 and repr(s["total_price"]) == "48.5"
    assert rows[3]["line_price"] == 0.45 and repr(rows[3]["line_price"]) == "0.45"
    s = apply_prices(rows[:3], table)
    assert repr(s["total_price"]) == "48.05"


def test_datasheet_states_the_bom_cost_when_priced(priced, family_builds):
    """Issue 24 §1: the datasheet's BOM cost row (every family) = the total recomputed from the
    price file and bom.csv by hand, in the file's currency, naming the unpriced lines; a build
    without prices has no such row (nothing invented)."""
    pfile, out, rep, _, _ = priced
    total, unpriced = _expected_total(pfile, _read(out / "bom.csv"))
    rows = {r["key"]: r for r in rep["datasheet"]["rows"]}
    assert rows["bom_cost"]["value"] == pytest.approx(total) and rows["bom_cost"]["unit"] == "EUR"
    assert f"{unpriced} of " in rows["bom_cost"]["model"] and "unpriced" in rows["bom_cost"]["model"]
    assert "| BOM cost (priced lines) |" in (out / "report.md").read_text()
    for _, _, frep in family_builds.values():
        assert "bom_cost" not in {r["key"] for r in frep["datasheet"]["rows"]}
