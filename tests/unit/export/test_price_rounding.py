"""Order prices below a cent (case outputs-agree/bom-subcent-price-rounding) and price rows
that match no line (issue 34 item 6 / issue 32).

Reference: exact decimal arithmetic by hand from the price file
(``data/subcent_prices.csv``, copied from the case) and the bundled Hoeken's fastener counts
(the case's ``out.txt``): each line = quantity x unit price rounded half-up to the cent
(3 x 0.015 = 0.045 -> 0.05, 5 x 0.045 = 0.225 -> 0.23, 2 x 0.0125 = 0.025 -> 0.03), the
total = the sum of the shown lines = 13.10 EUR (12.60 + 0.03 + 0.03 + 0.06 + 0.05 + 0.05 +
0.04 + 0.23 + 0.01).
"""
from __future__ import annotations

import csv
import io
from decimal import Decimal
from pathlib import Path

from cad.design import bounds
from cad.export.order import apply_prices, load_prices, order_csv, order_md

DATA = Path(__file__).parent / "data"

#: The Hoeken's priced lines: designation -> (quantity, unit price shown, line price shown),
#: quantities from the case's out.txt, unit and line worked by hand (module docstring).
LINES = {
    "618/8 (8x16x4)": (3, "4.20", "12.60"),
    "ISO 4032 M6-1": (2, "0.0125", "0.03"),
    "ISO 4026 M3-0.5 x 6": (1, "0.025", "0.03"),
    "ISO 4762 M3-0.5 x 10": (4, "0.015", "0.06"),
    "ISO 4762 M3-0.5 x 12": (3, "0.015", "0.05"),
    "ISO 4762 M3-0.5 x 8": (3, "0.015", "0.05"),
    "ISO 4762 M4-0.7 x 12": (1, "0.035", "0.04"),
    "ISO 4762 M6-1 x 16": (5, "0.045", "0.23"),
    "ISO 7089 M6": (2, "0.0055", "0.01"),
}


def _rows(extra=()):
    rows = [{"part": f"p{i}", "designation": d, "quantity": q, "made_or_bought": "bought",
             "group": "fastener", "order_code": ""} for i, (d, (q, _, _)) in enumerate(LINES.items())]
    return rows + [{"part": n, "designation": n, "quantity": 1, "made_or_bought": "bought",
                    "group": "x", "order_code": ""} for n in extra]


def test_subcent_unit_prices_shown_as_given_lines_multiply_total_adds_up():
    rows = _rows()
    table = load_prices(DATA / "subcent_prices.csv")
    summary = apply_prices(rows, table)
    order = list(csv.DictReader(io.StringIO(order_csv(rows, summary))))
    shown = {o["designation"]: (o["quantity"], o["unit_price"], o["line_price"]) for o in order[:-1]}
    assert shown == {d: (str(q), u, ln) for d, (q, u, ln) in LINES.items()}
    lines = [Decimal(o["line_price"]) for o in order[:-1]]
    assert order[-1]["line_price"] == "13.10" == str(sum(lines))
    assert "Total: 13.10 EUR (all lines priced)" in order_md(rows, summary)


def test_price_row_matching_no_line_is_a_warning_naming_its_row(tmp_path):
    p = tmp_path / "prices.csv"
    p.write_text("designation,unit_price\nISO 7089 M6,0.0055\nno such part,1.00\n", encoding="utf-8")
    bounds.reset()
    summary = apply_prices(_rows(), load_prices(p))
    assert summary["unused_prices"] == ["no such part"]
    warned = [w for w in bounds.collected() if "no such part" in w]
    assert warned == ["prices.csv row 3: designation 'no such part' matches no BOM or order line "
                      "(a BOM designation or part name); its price is not used"]


def test_design_prices_table_unused_key_is_a_warning_naming_the_key():
    bounds.reset()
    apply_prices(_rows(), {"prices": {"ISO 7089 M6": 0.0055, "gone": 2.0}, "currency": "EUR",
                           "source": "[prices]"})
    assert [w for w in bounds.collected() if "gone" in w] == [
        "[prices] key: designation 'gone' matches no BOM or order line (a BOM designation or "
        "part name); its price is not used"]


def test_identical_stock_is_one_order_line_with_summed_quantity():
    """Two BOM lines of the same stock text (form, section, size, material; each piece with
    its cutting allowance) are one order.csv line: 2 + 3 = 5 pieces of "rod 11 x 21 mm
    aluminium-6061", priced 0.0125 each: 5 x 0.0125 = 0.0625 -> 0.06 (not 0.03 + 0.04 = 0.07);
    a different stock stays its own line (hand arithmetic, csv read-back)."""
    rod = "rod 11 x 21 mm aluminium-6061"
    rows = [{"part": p, "designation": p, "quantity": q, "made_or_bought": "made", "group": "made",
             "order_code": "", "stock": st}
            for p, q, st in (("pin_a", 2, rod), ("pin_b", 3, rod), ("hub", 1, "rod 15 x 23 mm aluminium-6061"))]
    table = {"prices": {"pin_a": 0.0125, "pin_b": 0.0125}, "currency": "EUR", "source": "t"}
    summary = apply_prices(rows, table)
    order = list(csv.DictReader(io.StringIO(order_csv(rows, summary))))
    assert [(o["designation"], o["quantity"], o["unit_price"], o["line_price"], o["parts"])
            for o in order[:-1]] == [(rod, "5", "0.0125", "0.06", "pin_a pin_b"),
                                     ("rod 15 x 23 mm aluminium-6061", "1", "", "", "hub")]
    assert order[-1]["line_price"] == "0.06" and order[-1]["parts"] == "1 unpriced lines"
    assert (summary["priced_lines"], summary["unpriced_lines"]) == (1, 1)
    # the same stock at two unit prices is two lines (a reader multiplies each)
    table["prices"]["pin_b"] = 0.02
    summary = apply_prices(rows, table)
    order = list(csv.DictReader(io.StringIO(order_csv(rows, summary))))
    assert [(o["quantity"], o["line_price"]) for o in order[:-1] if o["designation"] == rod] == [
        ("2", "0.03"), ("3", "0.06")]
