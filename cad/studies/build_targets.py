"""Targets checked on a family's build and datasheet (``hapticad check`` / ``fit`` of a family
whose figures all come from its solids, e.g. the PowerMouse): the values are the datasheet
rows of a build (:mod:`cad.datasheet`) and the report's masses; the free parameters of
``fit`` are the numeric keys and the materials of the design's tables. No CAD import here (the
build imports it when a solid is missing)."""

from __future__ import annotations

import dataclasses
import tempfile
from pathlib import Path

from cad.errors import DesignError
from cad.pipeline import build_design
from cad.studies.fit import MATERIAL_CHOICES, FreeParam, numeric_free


def build_target_values(design, fidelity: str, wanted: set[str]) -> tuple[dict, dict]:
    """(``{key: value}`` of every datasheet row with a value, plus ``moving_mass_g`` and
    ``total_mass_g`` of the report; the build report) of ``design`` built at ``fidelity``
    into a temporary folder (no files kept). Raises what the build raises."""
    with tempfile.TemporaryDirectory() as tmp:
        rep = build_design(design, Path(tmp) / "b", set(), fidelity=fidelity, use_cache=False,
                           simulate_wall=False)
    values = {r["key"]: float(r["value"]) for r in rep["datasheet"]["rows"] if r["value"] is not None}
    for k in ("moving_mass_g", "total_mass_g"):
        if isinstance(rep.get(k), (int, float)):
            values.setdefault(k, float(rep[k]))
    return values, rep


def _tables(design) -> dict[str, object]:
    """``{table name: spec}`` of the design's dataclass tables (``[actuator]``, ``[flotor]``,
    ...): the sections ``--free`` may name."""
    return {f.name: getattr(design, f.name) for f in dataclasses.fields(design)
            if dataclasses.is_dataclass(getattr(design, f.name))}


def parse_free_tables(spec: str, design) -> FreeParam:
    """Free parameter ``TABLE.KEY[=LO:HI]`` of a design whose tables are dataclasses: a
    numeric key (range ``LO:HI``, default 0.5x .. 1.5x the current value, within the key's bounds) or a
    ``*material`` key (choice). DesignError naming ``--free SPEC`` otherwise."""
    key, _, rng = spec.partition("=")
    key = key.strip()
    section, _, name = key.partition(".")
    tables = _tables(design)
    fields = {f.name for f in dataclasses.fields(tables[section])} if section in tables else set()
    if name not in fields:
        raise DesignError(f"--free {spec}", f"not a free parameter of a {design.family} design "
                          f"(TABLE.KEY of the tables {', '.join(tables)})")
    current = getattr(tables[section], name)
    if name.endswith("material"):
        return FreeParam(key, "choice", choices=MATERIAL_CHOICES)
    if not isinstance(current, (int, float)) or isinstance(current, bool):
        raise DesignError(f"--free {spec}", f"{name} is not a numeric or material parameter")
    return numeric_free(spec, key, rng, float(current))
