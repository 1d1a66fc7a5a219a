"""Design files: TOML in, validated frozen dataclasses out.

``load_design(path)`` reads a TOML file and dispatches on
``[mechanism].family`` to the module that owns that family's schema
(the registry row's ``design_module``, :mod:`cad.data.families`). Each module exposes
``parse(raw, source) -> design``.
Every problem is a :class:`cad.errors.DesignError` naming the dotted field.
"""

from __future__ import annotations

import importlib
from pathlib import Path
from typing import Any

from cad.data.families import FAMILIES
from cad.design.bounds import check_raw_design, warn
from cad.design.fields import load_toml, optional_table, require_str, require_table
from cad.design.prices import price_table
from cad.design.transmission import warn_transmissions
from cad.errors import DesignError


def family_of(raw: dict[str, Any]) -> str:
    """Return ``[mechanism].family`` of a raw design, validated."""
    mech = require_table(raw, "mechanism", "")
    fam = require_str(mech, "family", "mechanism")
    if fam not in FAMILIES:
        known = ", ".join(sorted(FAMILIES))

        raise DesignError("mechanism.family", f"unknown family {fam!r} (known: {known})")
    return fam


def design_prices(raw: dict[str, Any]) -> dict | None:
    """The design's ``[prices]`` table, validated (:func:`cad.design.prices.price_table`:
    ``"designation" = unit price``, optional ``currency``), or None without one."""
    if "prices" not in raw:
        return None
    return price_table(optional_table(raw, "prices", ""), "prices")


def parse_design(raw: dict[str, Any], source: str = "<design>"):
    """Validate a raw design mapping and return the family's design object."""
    fam = family_of(raw)
    check_raw_design(raw)  # every number against cad/design/bounds.py, before the schema
    design_prices(raw)  # [prices] (any family): cad.design.prices.price_table
    module = importlib.import_module(FAMILIES[fam].design_module)
    design = module.parse(raw, source)
    warn_transmissions(getattr(design, "transmissions", ()), warn)  # every family's capstans
    return design


def load_design(path: str | Path):
    """Load and validate a TOML design file (see docs/design-files.md).

    Numbers outside their bounds (:mod:`cad.design.bounds`) raise :class:`DesignError`;
    implausible ones are recorded as warnings (:func:`cad.design.bounds.collected`).
    """
    raw = load_toml(path)
    return parse_design(raw, str(path))
