"""The datasheet of a design without writing a build: ``hapticad datasheet`` and ``hapticad
check`` without ``[targets]``.

:func:`device_datasheet` builds the design (no exports, interference allowed so that a
colliding design still gets its figures, the clearance row says it) into a temporary folder
and keeps the datasheet in the derived cache (:mod:`cad.io.derived_cache`) under the build's
own cache key (:func:`cad.pipeline.build_key`: design, options, code): while the design and the
code are unchanged it is read back without importing a CAD library.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

from cad.io import derived_cache
from cad.pipeline import build_design, build_key


def device_datasheet(design, fidelity: str = "inertia") -> dict:
    """``report["datasheet"]`` of a build of ``design`` at ``fidelity`` (module docstring)."""
    key = build_key(design, set(), fidelity, True, None, True)

    def make() -> dict:
        with tempfile.TemporaryDirectory(prefix="hapticad-datasheet-") as tmp:
            rep = build_design(design, Path(tmp) / "b", set(), fidelity=fidelity,
                               allow_interference=True, use_cache=False, simulate_wall=True)
        return rep["datasheet"]

    return derived_cache.cached_json("datasheet", key, make)


def limit_rows(ds: dict) -> list[dict]:
    """The datasheet's limited rows in the ``hapticad check`` row form (key, computed, target
    as data, target_text, reason, ok, gap_rel, margin)."""
    out = []
    for r in ds["rows"]:
        lim = r.get("limit")
        if lim is None:
            continue
        v, b = r["value"], lim["value"]
        side = "min" if lim["op"] in (">=", ">") else "max"
        margin = None if v is None else ((v - b) if side == "min" else (b - v))
        out.append({"key": r["key"], "computed": v, "target": {side: b},
                    "target_text": f"{lim['op']} {b:.6g} ({lim['origin']})", "reason": lim["reason"],
                    "ok": r["verdict"] != "miss", "margin": margin,
                    "gap_rel": None if (v is None or b == 0 or r["verdict"] != "miss") else (v - b) / abs(b)})
    return out
