"""Write designs back to TOML (tomli_w), atomically. No CAD imports."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from cad.io.atomic import write_text_atomic


def custom_mechanism_table(fb, phi1_min_rad: float, phi1_max_rad: float, force_N: float) -> dict[str, Any]:
    """A ``[mechanism]`` table with ``family = "custom"`` and every length explicit."""
    return {
        "family": "custom",
        "l1_mm": round(fb.l1_mm, 6), "l2_mm": round(fb.l2_mm, 6), "l3_mm": round(fb.l3_mm, 6),
        "l4_mm": round(fb.l4_mm, 6), "l5_mm": round(fb.l5_mm, 6), "le_mm": round(fb.le_mm, 6),
        "phi_e_deg": round(math.degrees(fb.phi_e_rad), 6),
        "phi1_min_deg": round(math.degrees(phi1_min_rad), 6),
        "phi1_max_deg": round(math.degrees(phi1_max_rad), 6),
        "branch": int(fb.branch), "force_N": force_N,
    }


#: Target keys that describe one particular mechanism's inertia (the Hoeken paper's CAD
#: values, measured masses): they do not carry over to a new bar set as value +- tolerance.
MECHANISM_SPECIFIC_TARGETS = (
    "H11_kg_m2", "H12_kg_m2", "H22_kg_m2", "H33_kg_m2",
    "M11_min_g", "M11_max_g", "M12_min_g", "M12_max_g", "M22_max_g",
    "crank_mass_g", "coupler_mass_g", "rocker_mass_g", "moving_mass_g",
)


def drop_source_targets(raw: dict[str, Any]) -> list[str]:
    """Remove from ``raw["targets"]`` (in place) the value +- tolerance targets of
    :data:`MECHANISM_SPECIFIC_TARGETS`; bounds (``{max = ...}``) are requirements and stay.

    Returns the dropped keys, for the new design's header comment. Used by ``swap`` and
    ``synth``, whose output is another mechanism than the one those values describe.
    """
    t = raw.get("targets")
    if not isinstance(t, dict):
        return []
    dropped = [k for k, v in t.items()
               if k in MECHANISM_SPECIFIC_TARGETS and not (isinstance(v, dict) and "value" not in v)]
    for k in dropped:
        del t[k]
    if not t:
        raw.pop("targets")
    return dropped


def dropped_targets_note(dropped: list[str]) -> str:
    """Header line naming the targets :func:`drop_source_targets` removed ('' if none)."""
    if not dropped:
        return ""
    return ("\nTargets of the source design not carried over (they describe its mechanism): "
            + ", ".join(dropped))


def rebase_paths(raw: dict[str, Any], source: str | Path, dest: str | Path) -> dict[str, Any]:
    """Rewrite the design's relative file paths (``[parts] handle_script``) so that a copy
    written to ``dest`` still names the same file as the design read from ``source``.

    In place; returns ``raw``. Absolute paths are kept.
    """
    import os

    parts = raw.get("parts")
    if isinstance(parts, dict) and isinstance(parts.get("handle_script"), str):
        p = Path(parts["handle_script"])
        if not p.is_absolute():
            abs_p = (Path(source).resolve().parent / p).resolve()
            parts["handle_script"] = os.path.relpath(abs_p, Path(dest).resolve().parent)
    return raw


def dumps_design(raw: dict[str, Any], header: str = "") -> str:
    import tomli_w

    text = tomli_w.dumps(raw)
    if header:
        text = "".join(f"# {line}\n" for line in header.splitlines()) + text
    return text


def write_design(path: str | Path, raw: dict[str, Any], header: str = "") -> Path:
    """Validate-free TOML write (callers validate by re-parsing); atomic."""
    return write_text_atomic(path, dumps_design(raw, header))
