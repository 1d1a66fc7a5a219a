"""Bill of materials: ``bom.csv`` (part, material, quantity, made or bought, process, ISO 286
fits of its seats and bores, mass; then the ordering columns of :mod:`cad.export.order`:
group of a bought part, its standard designation and catalog order code, the stock of a
made part, unit and line price -- empty where no price was given)."""

from __future__ import annotations

import csv
import io
from decimal import Decimal
from pathlib import Path

from cad.export.order import money, unit_money
from cad.io.atomic import write_text_atomic
from cad.io.escape import csv_cell

BOM_COLUMNS = (
    "part",
    "description",
    "material",
    "quantity",
    "made_or_bought",
    "process",
    "fits",
    "mass_g",
    "total_mass_g",
    "group",
    "designation",
    "order_code",
    "stock",
    "unit_price",
    "line_price",
)


#: columns whose text may come from a design (names, motor name and source, designations):
#: written through :func:`cad.io.escape.csv_cell`
_TEXT_COLUMNS = ("part", "description", "material", "designation", "order_code", "process")


def mass_cells(mass_g: float, quantity: int) -> tuple[str, str]:
    """The ``mass_g`` and ``total_mass_g`` cells of a BOM line: the unit mass (g) printed
    to 0.01 g, and ``quantity`` x that printed unit mass, exact (as
    :func:`cad.export.order.line_cents` does for prices), so a reader multiplying the two
    printed columns gets the printed total (0.915 g x 4 -> "0.92", "3.68"; not the unrounded
    3.66). The line total differs from quantity x the exact mass by at most
    quantity x 0.005 g."""
    unit = Decimal(f"{float(mass_g):.2f}")
    return str(unit), str(unit * int(quantity))


def bom_csv(rows: list[dict]) -> str:
    """CSV text of the BOM rows (columns :data:`BOM_COLUMNS`; unit masses to 0.01 g, each
    line's total mass = quantity x the printed unit mass, :func:`mass_cells`)."""
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=BOM_COLUMNS, lineterminator="\n", extrasaction="ignore")
    w.writeheader()
    for r in rows:
        r = dict(r)
        r.setdefault("description", "")
        r.setdefault("process", "")
        r.setdefault("fits", "")
        r["unit_price"] = unit_money(r.get("unit_price", ""))
        r["line_price"] = money(r.get("line_price", ""))
        r["mass_g"], r["total_mass_g"] = mass_cells(r["mass_g"], r["quantity"])
        w.writerow({k: csv_cell(v) if k in _TEXT_COLUMNS and isinstance(v, str) else v
                    for k, v in r.items()})
    return buf.getvalue()


def write_bom(rows: list[dict], out_dir: Path) -> Path:
    """Write ``out_dir/bom.csv`` atomically; rows carry part, material, quantity,
    made_or_bought ("made" or "bought") and mass_g (each), optional description/process."""
    for r in rows:
        if r.get("made_or_bought") not in ("made", "bought"):
            raise ValueError(
                f"BOM row {r.get('part')!r}: made_or_bought must be 'made' or 'bought'"
            )
    return write_text_atomic(Path(out_dir) / "bom.csv", bom_csv(rows))
