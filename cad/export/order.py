"""A BOM to order from: stock for made parts, designations and order codes of bought
parts, and an optional price table (``hapticad build --prices FILE.csv`` or a design's
``[prices]`` table) giving line and total cost.

* :func:`stock` -- the stock to order for one made part: its exact bounding box in the part
  frame plus the stated cutting allowance (:mod:`cad.tolerances` ``STOCK_*``), rounded up to
  whole mm. Plates (``PartKind.plate``): thickness x width x length; turned parts (solids of
  revolution, so coaxial with their box; not "turned + milled"): a round bar diameter x
  length (axis = the box axis whose two cross dimensions are closest);
  tubes and ground dowels (bought at the finished diameter): diameter x length; printed
  parts: the filament mass; wound coils: the wire mass; anything else: a block;
* :func:`bought_designation` -- ``(group, designation, order_code)`` of a bought part: the
  ISO/DIN designation read from its BOM description, a bearing's catalog designation
  (bd_warehouse's SKF table), a motor's catalog name and the order number its winding
  states (:data:`cad.data.catalog.MOTORS`); empty order code where no catalog gives one;
* :func:`load_prices` / :func:`price_table` -- a price file / ``[prices]`` table as
  ``{key: unit price}`` (key = a BOM designation or part name), every bad cell refused as
  one :class:`cad.errors.DesignError` naming the file, row, column and value;
* :func:`apply_prices` -- ``unit_price`` and ``line_price`` on the BOM rows; nothing is
  invented: an unpriced line keeps empty cells and the summary counts it;
* :func:`order_csv` -- ``order.csv``: one line per stock or bought designation (identical
  stock of several BOM lines is one line, quantities summed), bought parts grouped by kind,
  made parts by stock form, then a ``total`` line.
"""

from __future__ import annotations

import csv
import io
import math
import re
from decimal import ROUND_HALF_UP, Decimal
from pathlib import Path

from cad import tolerances as tol
from cad.data.catalog import MOTORS
from cad.design import bounds
from cad.design.fields import check_text
from cad.design.prices import price_table  # noqa: F401 - validated where designs are (cad.design)
from cad.errors import DesignError
from cad.io import guard
from cad.io.escape import csv_cell, md
from cad.tolerances import PRICE_FIELD_MAX_CHARS, PRICE_MAX

#: Groups of bought parts by the standard in their designation.
STANDARD_GROUPS = {
    "ISO 4762": "socket head cap screws",
    "ISO 7379": "shoulder screws",
    "ISO 4026": "set screws",
    "ISO 4032": "hex nuts",
    "ISO 7089": "washers",
    "DIN 471": "retaining rings",
    "ISO 2338": "dowel pins",
}
_STANDARD = re.compile(r"\b(?:ISO|DIN|EN) \d+\b[^,()]*")
ORDER_COLUMNS = ("group", "designation", "order_code", "quantity", "unit_price", "line_price",
                 "parts")
#: Start of the stock cell of a laser-cut part (:func:`cad.pipeline.family.bom_rows`): its stock
#: is the sheet it is nested on, ordered on that sheet's own bought line, so the part itself
#: is no order line (it would be ordered twice, as "stock: nested").
NESTED_STOCK = "nested on "


def ordered(row: dict) -> bool:
    """False for a BOM row that is no order line of its own: a laser-cut part (stock
    :data:`NESTED_STOCK`), whose sheet is ordered instead."""
    return not (row["made_or_bought"] == "made" and row.get("stock", "").startswith(NESTED_STOCK))


def _bbox_mm(shape) -> tuple[float, float, float]:
    """Exact (x, y, z) extents of a shape's bounding box, mm (OCCT optimal box)."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    b = Bnd_Box()
    BRepBndLib.AddOptimal_s(getattr(shape, "wrapped", shape), b, False, False)
    lo, hi = b.CornerMin(), b.CornerMax()
    return (hi.X() - lo.X(), hi.Y() - lo.Y(), hi.Z() - lo.Z())


def _turning_axis(shape):
    """``gp_Ax1`` of the largest cylindrical face of ``shape`` (the axis it is turned
    about), or None without one."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.BRepGProp import BRepGProp
    from OCP.GeomAbs import GeomAbs_Cylinder
    from OCP.GProp import GProp_GProps
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    best, axis = 0.0, None
    ex = TopExp_Explorer(getattr(shape, "wrapped", shape), TopAbs_FACE)
    while ex.More():
        face = TopoDS.Face_s(ex.Current())
        surf = BRepAdaptor_Surface(face)
        if surf.GetType() == GeomAbs_Cylinder:
            g = GProp_GProps()
            BRepGProp.SurfaceProperties_s(face, g)
            if g.Mass() > best:
                best, axis = g.Mass(), surf.Cylinder().Axis()
        ex.Next()
    return axis


def coaxial_radii_mm(shape, axis) -> list[float]:
    """Exact radii (mm, sorted, distinct to 1e-6) of the cylindrical faces of ``shape``
    whose axis is ``axis`` (a tube's outer and bore radii, a dowel's radius)."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAbs import GeomAbs_Cylinder
    from OCP.gp import gp_Lin
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    line, radii = gp_Lin(axis), []
    ex = TopExp_Explorer(getattr(shape, "wrapped", shape), TopAbs_FACE)
    while ex.More():
        surf = BRepAdaptor_Surface(TopoDS.Face_s(ex.Current()))
        if surf.GetType() == GeomAbs_Cylinder:
            c = surf.Cylinder()
            if c.Axis().IsParallel(axis, 1e-9) and line.Distance(c.Location()) < 1e-6:
                r = c.Radius()
                if all(abs(r - q) > 1e-6 for q in radii):
                    radii.append(r)
        ex.Next()
    return sorted(radii)


#: Chordal deflection of the mesh that measures a turned part's radius (mm); added back to
#: the largest vertex radius, so the diameter found is never below the solid's.
RADIUS_MESH_DEFLECTION_MM = 0.02


def _about_axis_mm(shape, axis) -> tuple[float, float]:
    """``(diameter, length)`` of a cylinder about ``axis`` holding ``shape``: the largest
    radius of the vertices of a copy meshed at :data:`RADIUS_MESH_DEFLECTION_MM` (+ that
    deflection), and the exact box length along the axis (mm)."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRep import BRep_Tool
    from OCP.BRepBndLib import BRepBndLib
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Transform
    from OCP.BRepMesh import BRepMesh_IncrementalMesh
    from OCP.gp import gp_Ax3, gp_Trsf
    from OCP.TopAbs import TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopLoc import TopLoc_Location
    from OCP.TopoDS import TopoDS

    t = gp_Trsf()
    t.SetTransformation(gp_Ax3(axis.Location(), axis.Direction()))  # part -> axis frame
    moved = BRepBuilderAPI_Transform(getattr(shape, "wrapped", shape), t, True).Shape()
    BRepMesh_IncrementalMesh(moved, RADIUS_MESH_DEFLECTION_MM, False, 0.1, False)
    r2 = 0.0
    ex = TopExp_Explorer(moved, TopAbs_FACE)
    while ex.More():
        loc = TopLoc_Location()
        tri = BRep_Tool.Triangulation_s(TopoDS.Face_s(ex.Current()), loc)
        for i in range(1, (tri.NbNodes() if tri is not None else 0) + 1):
            p = tri.Node(i).Transformed(loc.Transformation())
            r2 = max(r2, p.X() ** 2 + p.Y() ** 2)
        ex.Next()
    b = Bnd_Box()
    BRepBndLib.AddOptimal_s(moved, b, False, False)
    return 2 * (math.sqrt(r2) + RADIUS_MESH_DEFLECTION_MM), b.CornerMax().Z() - b.CornerMin().Z()


def _up(x: float) -> int:
    """Whole mm at or above ``x`` (1e-6 mm of round-off does not add a mm)."""
    return int(math.ceil(x - 1e-6))


#: A printed part's process text: the BOM's "FDM print PLA: ..." (:meth:`cad.printing.
#: PrintSettings.describe`) or "printed" (matching only "print..." ordered PLA plates).
#: "3D print / turned" (a user-script handle: either) keeps its machined stock.
_PRINTED = re.compile(r"^(fdm )?print")


def _grams(mass_g: float) -> str:
    """A mass to order: whole grams, 0.1 g below 10 g (a 0.4 g spacer is not "0 g")."""
    return f"{mass_g:.1f}" if mass_g < 10 else f"{mass_g:.0f}"


def stock_is_mass(kind) -> bool:
    """Is the stock of made part ``kind`` ordered by mass (a printed part's filament, a wound
    coil's wire) rather than by size?"""
    proc = kind.process.lower()
    return _PRINTED.search(proc) is not None or proc.startswith("wound")


def stock(kind, mass_g: float) -> str:
    """Stock to order for one piece of made part ``kind`` (``mass_g``: its mass, used for
    printed parts), e.g. ``"plate 6 x 35 x 130 mm aluminium-6061"``; see the module doc."""
    mat = kind.material
    proc = kind.process.lower()
    if _PRINTED.search(proc) is not None:  # "printed", "FDM print PLA: 0.2 mm layers, ..."
        return f"filament {_grams(mass_g)} g {mat}"
    if proc.startswith("wound"):
        return f"wire {_grams(mass_g)} g {mat}"
    dims = _bbox_mm(kind.shape)
    if kind.plate:
        w, l_ = sorted(dims[:2])
        m = 2 * tol.STOCK_PLATE_MARGIN_MM
        return f"plate {dims[2]:g} x {_up(w + m)} x {_up(l_ + m)} mm {mat}"
    tube = re.match(r"(\w+ )?tube \d", kind.description) is not None
    axis = _turning_axis(kind.shape)
    if axis is not None and (tube or proc.startswith(("turned", "ground dowel"))):
        d, length = _about_axis_mm(kind.shape, axis)
        length = _up(length + tol.STOCK_LENGTH_ALLOWANCE_MM)
        if tube or proc.startswith("ground dowel"):  # bought at the finished size: exact
            radii = coaxial_radii_mm(kind.shape, axis) or [d / 2]
            size = f"{2 * radii[-1]:.6g}"
            if tube and len(radii) > 1:  # outer / bore diameter: the wall to order
                size += f"/{2 * radii[0]:.6g}"
            return f"{'tube' if tube else 'rod'} {size} x {length} mm {mat}"
        return f"rod {_up(d + tol.STOCK_ROD_DIAMETER_ALLOWANCE_MM)} x {length} mm {mat}"
    m = 2 * tol.STOCK_BLOCK_MARGIN_MM
    return "block " + " x ".join(str(_up(x + m)) for x in sorted(dims)) + f" mm {mat}"


def stock_dims_mm(text: str) -> tuple[str, tuple[float, ...]]:
    """``(form, numbers)`` of a :func:`stock` text (``"rod 14 x 91 mm ..."`` ->
    ``("rod", (14.0, 91.0))``; a tube's ``"8/6 x 110"``: ``(8.0, 6.0, 110.0)``), for reading
    ``bom.csv`` back."""
    form, rest = text.split(" ", 1)
    nums = rest.split(" g" if form in ("filament", "wire") else " mm", 1)[0]
    return form, tuple(float(y) for x in nums.split(" x ") for y in x.split("/"))


def bought_designation(kind) -> tuple[str, str, str]:
    """``(group, designation, order_code)`` of bought part ``kind`` (see the module doc).
    A part with no standard designation keeps its description, group ``"other"``."""
    own = getattr(kind, "designation", "")
    if own:
        return (getattr(kind, "group", "") or "other", own, getattr(kind, "order_code", ""))
    desc = kind.description
    m = re.search(r"ball bearing (\S+) \(([^)]*)\)", desc)
    if m:
        return ("ball bearings", f"{m.group(1)} ({m.group(2)})", f"SKF {m.group(1)}")
    motor = _motor_designation(desc)
    if motor is not None:
        return motor
    m = _STANDARD.search(desc)
    if m:
        des = m.group(0).strip()
        group = next((g for s, g in STANDARD_GROUPS.items() if des.startswith(s)), "other")
        return (group, des, "")
    return ("other", desc, "")


#: A motor of a design's ``[motor]`` table on the catalog motor's mount
#: (:func:`cad.design.motor.resolve_motor`): "acme-60 (data of [motor]; mount of maxon-re35)",
#: then its unverified fields when it has any (:meth:`cad.data.catalog.MotorSpec.bom_description`).
_TABLE_MOTOR = re.compile(r"^(.+?) \(data of \[motor\]; mount of ([^)\s]+)\)")


def _motor_designation(desc: str) -> tuple[str, str, str] | None:
    """A catalog motor (its BOM description is the catalog's): name and order number; a
    ``[motor]`` table's motor: its name, no order number (no catalog gives one)."""
    table = _TABLE_MOTOR.match(desc)
    if table is not None:
        return ("motors", table.group(1), "")
    spec = next((sp for sp in MOTORS.values() if desc.startswith(sp.description)), None)
    if spec is None:
        return None
    m = re.search(r"order number (\d+)", spec.winding)
    return ("motors", spec.description.split(",")[0], m.group(1) if m else "")


# --------------------------------------------------------------------------- prices
#: a number as a CSV cell writes it: ASCII digits, a sign, one optional point, an optional
#: exponent, or nan/inf (refused by the range check with their own reason); float() alone
#: also takes "1_000" and full-width digits
_PRICE_TEXT = re.compile(r"\s*[-+]?((\d+\.?\d*|\.\d+)([eE][-+]?\d+)?|nan|inf|infinity)\s*",
                         re.ASCII | re.IGNORECASE)


def _price_value(value, where: str) -> float:
    try:
        if isinstance(value, str) and not _PRICE_TEXT.fullmatch(value):
            raise ValueError(value)
        x = float(value) if not isinstance(value, bool) else math.nan
    except (TypeError, ValueError):
        raise DesignError("--prices" if "row" in where else "prices",
                          f"{where}: value {value!r} is not a number") from None
    if not math.isfinite(x) or not 0 <= x <= PRICE_MAX:
        raise DesignError("--prices" if "row" in where else "prices",
                          f"{where}: value {value!r} must be a price in 0..{PRICE_MAX:g} "
                          "(cad/tolerances.py PRICE_MAX)")
    return x


def load_prices(path: str | Path) -> dict:
    """Read a price CSV: header with columns ``designation`` and ``unit_price`` (optional
    ``currency``, one for the whole file; optional ``source``). Rows are counted as a
    spreadsheet shows them (header = row 1). Returns ``{"prices": {key: float},
    "currency": str, "source": the file's name (never its folder: reports are shared)}``.
    The file goes through :mod:`cad.io.guard` (kind ``prices``: a regular file within its
    size limit, UTF-8); DesignError ``--prices`` naming file, row, column and value for a
    file refused there, a missing column, an empty or repeated designation, a cell over
    :data:`cad.tolerances.PRICE_FIELD_MAX_CHARS` characters, a price that is not a number in
    0..:data:`cad.tolerances.PRICE_MAX`, or a second currency."""
    p = Path(path)
    text = guard.read_text(p, "prices", "--prices", encoding="utf-8-sig")
    reader = csv.DictReader(io.StringIO(text))
    try:
        return _read_prices(reader, p)
    except csv.Error as exc:  # a field over the csv module's own limit, a NUL byte
        raise DesignError("--prices", f"{p} row {reader.line_num + 1}: not a valid CSV row ({exc})") from None


def _read_prices(reader, p: Path) -> dict:
    """:func:`load_prices` on the open ``csv.DictReader`` of ``p``."""
    cols = [c.strip() for c in (reader.fieldnames or [])]
    for need in ("designation", "unit_price"):
        if need not in cols:
            raise DesignError("--prices", f"{p} row 1 (header): column {need!r} missing "
                                          f"(columns: {', '.join(cols) or 'none'})")
    prices, first_row, currency = {}, {}, ("", 0)
    for i, raw in enumerate(reader, start=2):
        row = {(k or "").strip(): (v or "").strip() for k, v in raw.items()
               if k is not None and isinstance(v, str | None)}
        long = next((k for k, v in row.items() if len(v) > PRICE_FIELD_MAX_CHARS), None)
        if long is not None:
            raise DesignError("--prices", f"{p} row {i} column {long}: a value of {len(row[long])} "
                              f"characters, over {PRICE_FIELD_MAX_CHARS} (cad/tolerances.py "
                              "PRICE_FIELD_MAX_CHARS)")
        key = row.get("designation", "")
        where = f"{p} row {i} column"
        for col in ("designation", "currency"):
            check_text(row.get(col, ""), "--prices", f"{where} {col}")
        if not key:
            raise DesignError("--prices", f"{where} designation: value '' is empty")
        if key in prices:
            raise DesignError("--prices", f"{where} designation: value {key!r} repeats row "
                                          f"{first_row[key]}")
        prices[key] = _price_value(row.get("unit_price", ""), f"{where} unit_price")
        first_row[key] = i
        cur = row.get("currency", "")
        if cur and currency[0] and cur != currency[0]:
            raise DesignError("--prices", f"{where} currency: value {cur!r} differs from "
                                          f"{currency[0]!r} (row {currency[1]}): one currency")
        if cur and not currency[0]:
            currency = (cur, i)
    return {"prices": prices, "currency": currency[0], "source": p.name, "rows": first_row}


def _price_of(prices: dict, keys) -> str | None:
    return next((k for k in keys if k and k in prices), None)


def apply_prices(rows: list[dict], table: dict | None) -> dict:
    """Set ``unit_price`` / ``line_price`` (quantity x unit) on every BOM row priced by
    ``table`` (:func:`load_prices`; a row is looked up by its designation, then its part
    name); unpriced rows get empty cells. ``priced_lines`` / ``unpriced_lines`` count the
    lines of ``order.csv`` (:func:`order_lines`: identical stock is one line). Every bought part is its own BOM row (a pin's
    retaining rings are instances of their own), so no line is bought with another. Returns the summary:
    ``total_price`` (sum of the priced order lines, each rounded half-up to the cent:
    :func:`line_cents`), ``currency``, ``priced_lines``,
    ``unpriced_lines``, ``unpriced`` (part names or designations), ``unused_prices`` (keys
    matching no line; each one is also a warning naming its row), ``price_source``.
    """
    prices = (table or {}).get("prices", {})
    used, unpriced = set(), []
    lines = [(r, (r.get("designation", ""), r["part"]), r["part"]) for r in rows if ordered(r)]
    for r in rows:
        if not ordered(r):
            r["unit_price"] = r["line_price"] = ""
    for line, keys, label in lines:
        key = _price_of(prices, keys)
        if key is None:
            line["unit_price"] = line["line_price"] = ""
            unpriced.append(label)
            continue
        used.add(key)
        line["unit_price"] = prices[key]
        line["line_price"] = float(line_cents(prices[key], line["quantity"]))
    _warn_unused(table, sorted(set(prices) - used))
    merged = order_lines(rows)
    n_unpriced = sum(o["unit_price"] in ("", None) for o in merged)
    total = sum((line_cents(o["unit_price"], o["quantity"]) for o in merged
                 if o["unit_price"] not in ("", None)), Decimal(0))
    return {
        "total_price": float(total),
        "currency": (table or {}).get("currency", ""),
        "priced_lines": len(merged) - n_unpriced,
        "unpriced_lines": n_unpriced,
        "unpriced": unpriced,
        "unused_prices": sorted(set(prices) - used),
        "price_source": (table or {}).get("source", ""),
    }


def _warn_unused(table: dict | None, keys: list[str]) -> None:
    """A warning per price row (file row, or ``[prices]`` key) that matches no order line."""
    rows, src = (table or {}).get("rows", {}), (table or {}).get("source", "prices")
    for k in keys:
        where = f"{src} row {rows[k]}" if k in rows else f"{src} key"
        bounds.warn(f"{where}: designation {k!r} matches no BOM or order line (a BOM "
                    "designation or part name); its price is not used")


def _dec(x) -> Decimal:
    """The decimal a price was written as (a float from a CSV cell: its shortest repr)."""
    return Decimal(repr(float(x)))


def line_cents(unit_price, quantity) -> Decimal:
    """An order line's price: ``quantity`` x ``unit_price`` in exact decimal, rounded half-up
    to the cent (3 x 0.015 = 0.045 -> 0.05). The total is the sum of these lines, so the
    printed lines add up to the printed total."""
    return (_dec(unit_price) * int(quantity)).quantize(Decimal("0.01"), rounding=ROUND_HALF_UP)


def money(x) -> str:
    """A line or total price cell: two decimals (half-up), or empty for no price."""
    if x in ("", None):
        return ""
    return str(_dec(x).quantize(Decimal("0.01"), rounding=ROUND_HALF_UP))


def unit_money(x) -> str:
    """A unit price cell as given: two decimals, more when the price has more (0.0125 stays
    0.0125: fasteners bought by the box cost below a cent), or empty for no price."""
    if x in ("", None):
        return ""
    d = _dec(x)
    return str(d.quantize(Decimal("0.01"))) if d.as_tuple().exponent >= -2 else str(d.normalize())


def total_text(summary: dict) -> str:
    """One line: the total and how many lines it leaves unpriced."""
    cur = f" {summary['currency']}" if summary["currency"] else ""
    n, m = summary["unpriced_lines"], summary["priced_lines"] + summary["unpriced_lines"]
    if summary["priced_lines"] == 0:
        return f"no price given: all {m} lines unpriced, no total"
    tail = "all lines priced" if n == 0 else f"{n} of {m} lines unpriced, not in the total"
    return f"{money(summary['total_price'])}{cur} ({tail})"


def order_lines(rows: list[dict]) -> list[dict]:
    """Order lines of the BOM rows: bought parts
    sorted by group then designation, made parts (group ``"stock: <form>"``, designation =
    the stock) after them. BOM rows of the same stock text (form, section, size and material:
    each piece already carries its cutting allowance, :func:`stock`) or the same bought
    designation and order code, at the same unit price, are one line: quantities summed,
    ``parts`` = their part names separated by spaces."""
    out: dict[tuple, dict] = {}
    for r in rows:
        if not ordered(r):
            continue
        made = r["made_or_bought"] == "made"
        group = f"stock: {r['stock'].split(' ', 1)[0]}" if made and r.get("stock") else r.get("group", "")
        o = {"group": group, "designation": r["stock"] if made else r["designation"],
             "order_code": r.get("order_code", ""), "quantity": r["quantity"],
             "unit_price": r.get("unit_price", ""), "line_price": r.get("line_price", ""),
             "parts": r["part"]}
        key = (group, o["designation"], o["order_code"], unit_money(o["unit_price"]))
        if key in out:
            _merge(out[key], o)
        else:
            out[key] = o
    return sorted(out.values(), key=lambda o: (o["group"].startswith("stock:"), o["group"],
                                               o["designation"]))


def _merge(line: dict, other: dict) -> None:
    """Add ``other`` to order ``line`` of the same stock (or designation) at the same unit
    price: quantities summed, the line price = the summed quantity x the unit price
    (:func:`line_cents`, so the printed columns multiply), parts listed in BOM order."""
    line["quantity"] = int(line["quantity"]) + int(other["quantity"])
    if line["unit_price"] not in ("", None):
        line["line_price"] = float(line_cents(line["unit_price"], line["quantity"]))
    line["parts"] = f"{line['parts']} {other['parts']}"


def order_csv(rows: list[dict], summary: dict) -> str:
    """``order.csv`` text (columns :data:`ORDER_COLUMNS`), a last ``total`` line whose
    ``parts`` cell says how many lines are unpriced."""
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=ORDER_COLUMNS, lineterminator="\n")
    w.writeheader()
    for o in order_lines(rows):
        w.writerow({**o, **{k: csv_cell(o[k]) for k in ("group", "designation", "order_code", "parts")},
                    "unit_price": unit_money(o["unit_price"]), "line_price": money(o["line_price"])})
    w.writerow({"group": "total", "designation": csv_cell(summary["currency"]),
                "line_price": money(summary["total_price"]) if summary["priced_lines"] else "",
                "parts": f"{summary['unpriced_lines']} unpriced lines"})
    return buf.getvalue()


def allowance_text() -> str:
    """The cutting allowances the stock column adds (:mod:`cad.tolerances`)."""
    return (f"stock = the part's bounding box + {tol.STOCK_PLATE_MARGIN_MM:g} mm per side (plate), "
            f"+ {tol.STOCK_ROD_DIAMETER_ALLOWANCE_MM:g} mm on the diameter and "
            f"{tol.STOCK_LENGTH_ALLOWANCE_MM:g} mm on the length (rod; tube: length only), "
            f"+ {tol.STOCK_BLOCK_MARGIN_MM:g} mm per side (block), rounded up to whole mm")


def order_md(rows: list[dict], summary: dict) -> str:
    """The "Order" section of ``report.md``: the order lines, the total, the allowances."""
    lines = ["", "## Order (order.csv)", "",
             "| group | designation | order code | qty | unit price | line price | parts |",
             "|---|---|---|---|---|---|---|"]
    for o in order_lines(rows):
        lines.append(f"| {md(o['group'])} | {md(o['designation'])} | {md(o['order_code'])} | "
                     f"{o['quantity']} | {unit_money(o['unit_price'])} | {money(o['line_price'])} | "
                     f"{md(o['parts'])} |")
    src = f" (prices: {md(summary['price_source'])})" if summary["price_source"] else ""
    lines += ["", f"Total: {md(total_text(summary))}{src}.", "", f"Stock: {allowance_text()}."]
    if summary["unused_prices"]:
        lines.append(f"Prices matching no line: {', '.join(map(md, summary['unused_prices']))}.")
    return "\n".join(lines) + "\n"
