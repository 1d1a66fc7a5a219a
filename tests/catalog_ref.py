"""Catalog numbers read straight from bd_warehouse's CSV files, as an independent reference
for the tests (not through :mod:`cad.data.catalog`)."""

from __future__ import annotations

import csv
from pathlib import Path


def iso4026_lengths_mm(size: str) -> list[float]:
    """The ISO 4026 set screw lengths of ``size`` (e.g. ``"M3-0.5"``): the nominal list of
    ``nominal_screw_lengths.csv`` between the size's short and long lengths of
    ``setscrew_parameters.csv``."""
    from bd_warehouse import fastener

    data = Path(fastener.__file__).parent / "data"
    with (data / "setscrew_parameters.csv").open() as fh:
        row = next(r for r in csv.DictReader(fh) if r["Size"] == size)
    with (data / "nominal_screw_lengths.csv").open() as fh:
        nom = next(r for r in csv.DictReader(fh) if r["Screw_Type"] == "iso4026")
    lo, hi = float(row["iso4026:short"]), float(row["iso4026:long"])
    return [float(x) for x in nom["Nominal_Sizes"].split(",") if lo <= float(x) <= hi]
