"""Fidelity per scene, measured: what each simplification costs on the Hoeken design.

Builds ``designs/hoeken.toml`` at ``fabrication``, ``inertia`` and ``preview``
fidelity (no cache, fresh temporary folders) and reports, against
fabrication (the reference: every feature, exact integration, exact
interference confirmation): wall time, total moving mass, H11..H33, M11 max,
minimum clearance, and the time saved.
"""

from __future__ import annotations

import json
import statistics
import tempfile
import time
from pathlib import Path

from cad.design import load_design
from cad.pipeline import build_design

REPO = Path(__file__).resolve().parents[2]
FIDELITIES = ("fabrication", "inertia", "preview")


def _build(design, fidelity: str, formats: set[str]) -> tuple[float, dict]:
    with tempfile.TemporaryDirectory() as tmp:
        t = time.perf_counter()
        rep = build_design(design, Path(tmp) / "out", formats, fidelity=fidelity, use_cache=False)
        return time.perf_counter() - t, rep


def run(quick: bool, out_dir: Path, design_path: Path | None = None) -> dict:
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    d = load_design(design_path or REPO / "designs" / "hoeken.toml")
    formats = {"step", "stl", "dxf"}
    _build(d, "preview", set())  # warm-up: CAD imports are not a fidelity cost
    rows = {}
    for fid in FIDELITIES:
        times, rep = [], None
        for _ in range(1 if quick else 3):
            t, rep = _build(d, fid, formats)
            times.append(t)
        moving = sum(v["mass_g"] for k, v in rep["links"].items() if k != "ground")
        rows[fid] = {
            "wall_s": statistics.median(times),
            "moving_mass_g": moving,
            **{k: rep[k] for k in ("H11_kg_m2", "H12_kg_m2", "H22_kg_m2", "H33_kg_m2")},
            "M11_max_g": rep["apparent_mass"]["M11_max_g"],
            "min_clearance_mm": rep["min_clearance_mm"],
        }
    ref = rows["fabrication"]
    for fid in FIDELITIES:
        r = rows[fid]
        r["delta_mass_g"] = r["moving_mass_g"] - ref["moving_mass_g"]
        r["delta_H11_rel"] = (r["H11_kg_m2"] - ref["H11_kg_m2"]) / ref["H11_kg_m2"]
        r["delta_M11_max_g"] = r["M11_max_g"] - ref["M11_max_g"]
        r["delta_min_clearance_mm"] = r["min_clearance_mm"] - ref["min_clearance_mm"]
        r["time_saved_s"] = ref["wall_s"] - r["wall_s"]
    res = {
        "topic": "fidelity",
        "reference": "fabrication fidelity (every feature, exact checks)",
        "design": d.name,
        "rows": rows,
    }
    (out_dir / "fidelity.json").write_text(json.dumps(res, indent=1))
    return res


if __name__ == "__main__":  # pragma: no cover
    print(json.dumps(run(True, REPO / ".bench"), indent=1))
