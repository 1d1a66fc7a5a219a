"""Re-evaluate co-design candidates on the exact solids and write the optimum.

Each candidate becomes a design (``family = "custom"`` with the scaled lengths and crank
range, the ``[parts]`` of the trial) and is built at ``inertia`` fidelity without exports
(:func:`cad.pipeline.build_design`): exact B-rep mass properties, H11..H33 and M11, the
interference sweep of the real solids (every pair, every pose) and the ``structure``
entry (FE-calibrated frame, three poses, the solids' masses). A candidate is accepted
when it has zero interference and passes the structural limits; the report gives the
cheap model's error there: (cheap - exact) / exact of M11 max.
"""

from __future__ import annotations

import copy
import tempfile
from pathlib import Path

from cad.checks import miss_line as line
from cad.design import parse_design
from cad.design.writer import rebase_paths, write_design
from cad.io.outdir import check_out_file
from cad.pipeline import build_design


def candidate_raw(design, cand, name: str) -> dict:
    """The raw design mapping of a candidate (source design's other tables kept)."""
    raw = copy.deepcopy(design.raw)
    raw["name"] = name
    raw["mechanism"] = dict(cand.mechanism)
    parts = dict(raw.get("parts") or {})
    parts.update(cand.parts)
    raw["parts"] = parts
    if getattr(cand, "transmission", None) is not None:  # a searched capstan (the brief's was one)
        raw["transmission"] = dict(cand.transmission)
    return raw


def evaluate(design, cand, name: str) -> dict:
    """Exact numbers of one candidate (module docstring)."""
    d = parse_design(candidate_raw(design, cand, name), str(design.source))
    with tempfile.TemporaryDirectory(prefix="hapticad-codesign-") as tmp:
        rep = build_design(d, Path(tmp) / "b", set(), fidelity="inertia", allow_interference=True,
                           simulate_wall=False,
                           use_cache=False)
    am, st = rep["apparent_mass"], rep["structure"]
    overlap = float(rep.get("overlap_volume_mm3") or 0.0)
    return {
        "M11_max_g": am["M11_max_g"], "M11_min_g": am["M11_min_g"],
        "M11_variation": (am["M11_max_g"] - am["M11_min_g"]) / am["M11_max_g"],
        "cheap_M11_max_g": cand.cheap["M11_max_g"],
        "cheap_error_rel": (cand.cheap["M11_max_g"] - am["M11_max_g"]) / am["M11_max_g"],
        "min_clearance_mm": rep["min_clearance_mm"], "overlap_volume_mm3": overlap,
        "interference_free": overlap == 0.0 and rep["min_clearance_mm"] >= d.parts.clearance_min_mm - 1e-9,
        "structure": st, "layers": rep["layers"]["order"],
        "moving_mass_g": sum(rep["links"][k]["mass_g"] for k in ("crank", "coupler", "rocker")),
        "torque_mean_mNm": rep["torque_mean_mNm"], "torque_variation": rep["torque_variation"],
        "dy_max_mm": rep["dy_max_mm"], "stroke_mm": rep["stroke_mm"],
        "min_transmission_angle_deg": rep["min_transmission_angle_deg"],
        "targets": _target_rows(d, rep),
    }


def _target_rows(d, rep: dict) -> list[dict]:
    """The design's ``[targets]`` against this build's figures, by the code ``hapticad check``
    uses (:func:`cad.checks.values_from_report`, :func:`cad.checks.evaluate`): check rows."""
    from cad.checks import evaluate, values_from_report

    return [r.as_dict() for r in evaluate(d.targets, values_from_report(rep))]


def misses(best_ex: dict, checked: list[dict]) -> list[dict]:
    """The design's targets the chosen candidate (``best_ex``, from :func:`evaluate`) misses:
    ``key``, ``target_text``, ``written`` (its figure, the one ``check`` of the written design
    gives) and ``best`` (the best figure of that key over every exactly evaluated candidate in
    ``checked``, towards the target's bound; None when no candidate computed it)."""
    out = []
    for row in best_ex["targets"]:
        if row["ok"]:
            continue
        seen = [r["computed"] for c in checked if "exact" in c for r in c["exact"]["targets"]
                if r["key"] == row["key"] and r["computed"] is not None]
        t = row["target"] or {}
        lower = "max" in t and "min" not in t  # a <= bound: the lowest figure is the best reached
        best = None
        if seen:
            ref = t.get("value")
            best = (min(seen) if lower else max(seen) if "min" in t and "max" not in t
                    else min(seen, key=lambda v: abs(v - (ref if ref is not None else v))))
        out.append({"key": row["key"], "target_text": row["target_text"], "written": row["computed"],
                    "best": best})
    return out


def miss_line(m: dict) -> str:
    """One line for one missed target of :func:`misses` (:func:`cad.checks.miss_line`)."""
    return line(m["key"], m["target_text"], m["best"], m["written"])


def accepted(ex: dict) -> bool:
    return bool(ex["interference_free"] and ex["structure"]["ok"])


def write_optimum(design, cand, out: Path, header: str) -> Path:
    """Write the candidate as a design TOML (validated by re-parsing before writing)."""
    check_out_file(out, Path(design.source))  # never the input design (any link), never a folder
    raw = rebase_paths(candidate_raw(design, cand, out.stem), design.source, out)
    raw["description"] = f"optimum of {design.name}: light co-design (hapticad optimize --objective min-apparent-mass)"
    parse_design(raw, str(out))
    return write_design(out, raw, header)
