"""Defects found by trying ``parts.process = "laser"`` (issue 25 §3) as a new user (tryit
session), each with the check that failed before its fix.

* ``laser_sheet_mm = [0.6, 0.4]`` (metres) was refused without the unit slip being named.
* A part larger than ``laser_sheet_mm`` was refused as "a 145.0 x 20.0 mm part does not fit",
  not naming which part.
* ``order.csv`` listed every laser-cut part as an order line of its own (group
  ``stock: nested``, designation "nested on sheet_01 (sheet stock line)", quantity 1) beside
  the sheet it is cut from, and counted them as unpriced lines: the sheet was ordered twice.
* ``process = "laser"`` on a pantograph design: "parts.process: unknown key" with no word
  that the process is a four-bar key (on the PowerMouse: "parts: unknown key").
* A PLA post under ``process = "laser"``: warned as ``parts.process = "printed"`` (not what
  the design says) while the laser warning said the post "stays turned (machined)".
* The acrylic pilot-seat warning named no key to change and read "seat are".
* ``laser_sheet_mm`` set without ``process = "laser"`` was ignored without a word.
* A label placed at 90 deg on a part nested turned by 90 deg was engraved at 180 deg (upside
  down; the rocker of designs/hoeken_laser.toml on sheet_01).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from cad.errors import DesignError

ROOT = Path(__file__).resolve().parents[2]


def _design(tmp_path, family: str, parts: str) -> Path:
    p = tmp_path / "d.toml"
    p.write_text(f'name = "t"\n[mechanism]\nfamily = "{family}"\nforce_N = 5.0\n[parts]\n{parts}\n')
    return p


def _load(path):
    from cad.design import bounds, load_design

    bounds.reset()
    try:
        d = load_design(path)
        return d, list(bounds.collected())
    finally:
        bounds.reset()


def test_sheet_size_in_metres_names_the_slip(tmp_path):
    """0.6 m typed for 600 mm: refused naming the field and the slip (0.6 m = 600 mm)."""
    p = _design(tmp_path, "chebyshev", 'process = "laser"\nlaser_sheet_mm = [0.6, 0.4]')
    with pytest.raises(DesignError) as e:
        _load(p)
    assert e.value.field == "parts.laser_sheet_mm"
    assert "did you give metres? (0.6 metres = 600 mm)" in str(e.value)


def _box_kind(name: str, w: float, h: float, t: float):
    """A laser-cut kind whose solid is a w x h x t mm box (OCCT), on a 100 x 100 mm sheet."""
    from types import SimpleNamespace

    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox

    shape = BRepPrimAPI_MakeBox(w, h, t).Shape()
    return SimpleNamespace(name=name, shape=shape, material="aluminium-5083",
                           sheet_mm=(100.0, 100.0))


def test_part_too_large_for_the_sheet_is_named():
    """A 145 x 20 mm coupler cannot lie on a 100 x 100 mm sheet less 10 mm margins (80 mm
    usable either way round): the refusal names the coupler and the key."""
    from types import SimpleNamespace

    from cad.export.nesting import plan_sheets

    small = _box_kind("crank", 40.0, 20.0, 6.0)
    big = _box_kind("coupler", 145.0, 20.0, 6.0)
    insts = [SimpleNamespace(name="crank", kind=small), SimpleNamespace(name="coupler", kind=big)]
    with pytest.raises(DesignError) as e:
        plan_sheets(insts)
    assert e.value.field == "parts.laser_sheet_mm"
    assert "the coupler 145.0 x 20.0 mm part does not fit a 100 x 100 mm sheet" in str(e.value)


def _rows():
    """BOM rows as :func:`cad.pipeline.family.bom_rows` writes them for two laser-cut parts
    on one sheet, the sheet's stock line, and one bought bearing."""
    from cad.export.nesting import Sheet
    from cad.export.order import NESTED_STOCK
    from cad.pipeline.family import sheet_rows

    made = [{"part": n, "designation": n, "made_or_bought": "made", "quantity": 1,
             "group": "made", "order_code": "", "stock": f"{NESTED_STOCK}sheet_01, ordered as sheet 6 x 400 x 300 mm aluminium-5083"}
            for n in ("crank", "coupler")]
    bearing = {"part": "bearing", "designation": "618/8", "made_or_bought": "bought",
               "quantity": 3, "group": "ball bearings", "order_code": "SKF 618/8", "stock": ""}
    sheet = Sheet("aluminium-5083", 6.0, (400.0, 300.0))
    return made + [bearing] + sheet_rows([sheet])


def test_order_lists_the_sheet_not_each_nested_part():
    """order.csv: the bearing and the one sheet are the two order lines (a laser-cut part is
    bought as its sheet); the price summary counts the same two lines."""
    import csv
    import io

    from cad.export.order import apply_prices, order_csv

    rows = _rows()
    summary = apply_prices(rows, {"prices": {"618/8": 4.0}, "currency": "EUR"})
    lines = list(csv.DictReader(io.StringIO(order_csv(rows, summary))))
    body = [r for r in lines if r["group"] != "total"]
    assert [r["designation"] for r in body] == ["618/8", "sheet 6 x 400 x 300 mm aluminium-5083"]
    assert summary["priced_lines"] == 1 and summary["unpriced_lines"] == 1
    assert summary["unpriced"] == ["sheet_6x400x300mm_aluminium-5083"]
    assert summary["total_price"] == 3 * 4.0


def test_laser_on_a_pantograph_says_it_is_a_fourbar_key(tmp_path):
    """``process`` in a pantograph's [parts]: still refused, now saying why."""
    text = (ROOT / "designs" / "pantograph.toml").read_text()
    p = tmp_path / "p.toml"
    p.write_text(text + '\n[parts]\nprocess = "laser"\n' if "[parts]" not in text
                 else text.replace("[parts]", '[parts]\nprocess = "laser"', 1))
    with pytest.raises(DesignError) as e:
        _load(p)
    assert e.value.field == "parts.process"
    assert "four-bar [parts] key" in str(e.value) and "unknown key" in str(e.value)


def test_pla_post_under_laser_is_said_printed_not_turned(tmp_path):
    """A PLA post under process "laser" is FDM printed (cad.printing.is_printed): the
    warnings say so with the design's own process and do not call the post turned."""
    from cad.printing import is_printed

    assert is_printed("laser", "pla")
    p = _design(tmp_path, "chebyshev", 'process = "laser"\npost_material = "pla"')
    _, warns = _load(p)
    assert not any('process = "printed"' in w for w in warns)
    post = [w for w in warns if w.startswith("parts.post_material = 'pla'")]
    assert len(post) == 1 and "FDM printed" in post[0] and '"laser" cuts the plate parts only' in post[0]
    turned = [w for w in warns if "stay turned" in w]
    assert len(turned) == 1 and "post" not in turned[0].split(":")[1]


def test_acrylic_pilot_seat_warning_names_the_key(tmp_path):
    """The warning for a 5 mm acrylic motor mount names the part, the feature and the key
    that gives an H7 back, in one line."""
    p = _design(tmp_path, "chebyshev", 'process = "laser"\nmotor_mount_material = "acrylic-cast"')
    _, warns = _load(p)
    w = [x for x in warns if "pilot seat" in x]
    assert len(w) == 1 and "\n" not in w[0]
    assert "motor mount (acrylic-cast)" in w[0] and "pilot seat is laser-cut" in w[0]
    assert "parts.motor_mount_material" in w[0]


def test_sheet_size_without_laser_process_warns(tmp_path):
    """``laser_sheet_mm`` with the default process "machined" was silently ignored (no sheets,
    no word): now one warning naming both keys."""
    p = _design(tmp_path, "chebyshev", "laser_sheet_mm = [600.0, 400.0]")
    _, warns = _load(p)
    w = [x for x in warns if "laser_sheet_mm" in x]
    assert len(w) == 1 and "parts.process = 'machined'" in w[0] and "not used" in w[0]


def test_label_of_a_turned_part_reads_upright():
    """A tall 10 x 100 mm part gets its label at 90 deg (the only way it fits); nested turned
    by 90 deg, the label was written at 180 deg (upside down). Read back with ezdxf: 0 deg,
    its centre still on the part's centre line (x = 50 on the sheet, in material)."""
    import io
    from types import SimpleNamespace

    import ezdxf

    from cad.export.nesting import Placed, Sheet, sheet_dxf

    prof = ezdxf.new("R2000")
    prof.layers.add("CUT")
    prof.modelspace().add_lwpolyline([(0, 0), (10, 0), (10, 100), (0, 100)], close=True,
                                     dxfattribs={"layer": "CUT"})
    kind = SimpleNamespace(name="rocker")
    sheet = Sheet("aluminium-5083", 6.0, (200.0, 100.0),
                  [Placed("rocker", kind, (0.0, 0.0, 10.0, 100.0), 0.0, 10.0, True)])
    doc = ezdxf.read(io.StringIO(sheet_dxf(sheet, 0, 1, {"rocker": prof})))
    (t,) = doc.modelspace().query("TEXT[layer=='ENGRAVE']")
    assert t.dxf.rotation == 0.0
    # turned: part x in [0, 10] -> sheet y in [10, 20]; part y in [0, 100] -> sheet x in [0, 100]
    assert 10.0 < t.dxf.align_point.y < 20.0 and 0.0 < t.dxf.align_point.x < 100.0


def test_laser_on_the_powermouse_says_it_is_a_fourbar_key(tmp_path):
    """The PowerMouse has no [parts] table: ``[parts] process = "laser"`` is refused as the
    unknown table ``parts``, now saying that ``process`` is a four-bar key."""
    p = tmp_path / "p.toml"
    p.write_text((ROOT / "designs" / "powermouse.toml").read_text() + '\n[parts]\nprocess = "laser"\n')
    with pytest.raises(DesignError) as e:
        _load(p)
    assert e.value.field == "parts"
    assert "process is a four-bar [parts] key" in str(e.value) and "chebyshev-v" in str(e.value)


def test_laser_build_without_sheet_size_orders_the_smallest_stock(tmp_path):
    """Issue 34 §5: designs/hoeken_laser.toml without ``laser_sheet_mm`` ordered two 1000 x
    2000 mm sheets for a ~170 mm device; its plates (largest: the 153 x 168 mm base plate)
    fit the 304.8 x 609.6 mm quarter sheet with room, one per thickness (6 and 5 mm), and the
    BOM's sheet lines say why that size."""
    import csv

    from cad.api import build_design, load_design

    text = (ROOT / "designs" / "hoeken_laser.toml").read_text()
    p = tmp_path / "auto.toml"
    p.write_text("\n".join(x for x in text.splitlines() if not x.startswith("laser_sheet_mm")))
    rep = build_design(load_design(p), tmp_path / "out", formats=("dxf",), fidelity="preview")
    sheets = rep["sheets"]["sheets"]
    assert sorted(s["thickness_mm"] for s in sheets) == [5.0, 6.0]
    assert all(s["size_mm"] == [304.8, 609.6] for s in sheets)
    with open(tmp_path / "out" / "bom.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    stock = [r for r in rows if r["group"] == "sheet stock"]
    assert len(stock) == 2 and all("least sheet area" in r["description"] for r in stock)
    # issue 34 §3: the motor line names the catalog values no public source states, as
    # report.json's device does
    motor = next(r for r in rows if r["part"].startswith("motor_"))
    unv = sorted(k for k, c in rep["device"]["motors"][0]["constants"].items() if c.get("unverified"))
    assert "unverified data" in motor["description"] and unv
    assert all(k in motor["description"] for k in unv)
