"""A design's ``[prices]`` table, validated at load (no CAD import; the BOM prices it in
:func:`cad.export.order.apply_prices`)."""

from __future__ import annotations

import math

from cad.design.fields import check_text
from cad.errors import DesignError
from cad.io.escape import one_line
from cad.tolerances import PRICE_MAX


def price_table(table: dict, field: str = "prices") -> dict:
    """A design's ``[prices]`` table (``"designation" = unit price``, optional
    ``currency = "EUR"``) in the form of :func:`load_prices`; DesignError naming the key."""
    prices = {}
    for k, v in table.items():
        if k == "currency":
            if not isinstance(v, str) or not v:
                raise DesignError(f"{field}.currency", f"must be a non-empty string, got {v!r}")
            check_text(v, f"{field}.currency")
            continue
        check_text(str(k), f"{field}.{one_line(str(k))[:80]}")
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise DesignError(f"{field}.{k}", f"must be a number (unit price), got {v!r}")
        if not math.isfinite(float(v)) or not 0 <= v <= PRICE_MAX:
            raise DesignError(f"{field}.{k}", f"must be a price in 0..{PRICE_MAX:g} "
                              f"(cad/tolerances.py PRICE_MAX), got {v!r}")
        prices[str(k)] = float(v)
    return {"prices": prices, "currency": table.get("currency", ""), "source": f"[{field}]"}
