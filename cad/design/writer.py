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


def dumps_design(raw: dict[str, Any], header: str = "") -> str:
    import tomli_w

    text = tomli_w.dumps(raw)
    if header:
        text = "".join(f"# {line}\n" for line in header.splitlines()) + text
    return text


def write_design(path: str | Path, raw: dict[str, Any], header: str = "") -> Path:
    """Validate-free TOML write (callers validate by re-parsing); atomic."""
    return write_text_atomic(path, dumps_design(raw, header))
