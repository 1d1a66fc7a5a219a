"""Swap a four-bar to another straight-line family on the same joint hardware (``hapticad
swap``, :func:`cad.api.swap`): the whole ``[parts]`` table kept, the bar set of the new family
scaled to the same stroke (Hoeken paper §III.A), checked by the build's pre-CAD layout check
before anything is written. No CAD import (the layout check is planar)."""

from __future__ import annotations

import copy
from pathlib import Path

SWAP_FAMILIES = ("hoeken", "roberts", "chebyshev", "chebyshev-v")
#: Sections of a design that describe the old mechanism only and are dropped by a swap.
DROPPED_SECTIONS = ("inertia",)


def stroke_of(design) -> float:
    """|P(phi1_max) - P(phi1_min)| of a design, mm."""
    import numpy as np

    from cad.kinematics.fourbar import solve

    P = solve(design.linkage, np.array([design.phi1_min_rad, design.phi1_max_rad])).P_mm
    return float(np.linalg.norm(P[1] - P[0]))


def swap_raw(design, family: str, out_path: Path) -> dict:
    """The raw TOML mapping of ``design`` swapped to ``family`` (same stroke, same [parts])."""
    from cad.errors import DesignError

    if family not in SWAP_FAMILIES:
        raise DesignError("--to", f"must be one of {', '.join(SWAP_FAMILIES)}, got {family!r}")
    from cad.design.writer import drop_source_targets, rebase_paths

    raw = copy.deepcopy(design.raw)
    for s in DROPPED_SECTIONS:
        raw.pop(s, None)
    drop_source_targets(raw)
    mech = raw.get("mechanism", {})
    force = mech.get("force_N", design.force_N)
    raw["mechanism"] = {"family": family, "stroke_mm": stroke_of(design), "force_N": force}
    raw["name"] = f"{design.name.split('__')[0]}__{family.replace('-', '_')}"
    raw["description"] = (
        f"{family} bar set on the joint hardware of {Path(design.source).name} "
        f"(hapticad swap, stroke {stroke_of(design):.3f} mm)"
    )
    return rebase_paths(raw, design.source, out_path)


def replan(raw: dict, target: Path, family: str):
    """Parse the swapped ``raw`` and run the build's pre-CAD layout check on it
    (:func:`cad.families.fourbar.build.check_layout`, at the design's ``[parts]`` fidelity), so a
    swap never writes a design ``build`` refuses. A ``parts.layer_order`` copied from the
    source that is not clear for the new bar set is dropped from ``raw`` (a warning on
    stderr names it) and the planner chooses; when no layer order is clear the build's
    one-line DesignError (naming the joint, both parts and the stroke that clears) is
    raised: the CLI exits 2 and writes nothing, with no unit-slip hint about the stroke swap
    computed (:func:`cad.design.bounds.computed`)."""
    from cad.design import parse_design
    from cad.design.bounds import computed, warn
    from cad.errors import DesignError
    from cad.families.fourbar.build import check_layout

    new = parse_design(raw, str(target))
    computed(*(f"mechanism.{k}" for k in raw["mechanism"]))  # swap's numbers, not typed
    try:
        check_layout(new, new.parts.fidelity, False)
        return new
    except DesignError as e:
        if e.field != "parts.layer_order":
            raise
    order = raw["parts"].pop("layer_order")
    new = parse_design(raw, str(target))
    computed(*(f"mechanism.{k}" for k in raw["mechanism"]))
    check_layout(new, new.parts.fidelity, False)
    warn(f"parts.layer_order: {', '.join(order)} (copied from the source) is not clear for "
         f"the {family} bar set; dropped, the planner chooses the layer order")
    return new


def metric_rows(design) -> dict:
    from cad.analysis import METRIC_KEYS
    from cad.kinematics.metrics import compute_metrics

    m = compute_metrics(
        design.linkage,
        design.phi1_min_rad,
        design.phi1_max_rad,
        force_N=design.force_N,
        samples=design.samples,
    ).as_dict()
    out = {k: m[k] for k in METRIC_KEYS if k in m}
    out.update(design.resolved_linkage())
    return out


def swap(design, family: str, target: Path, name: str | None = None) -> dict:
    """``design`` swapped to ``family`` as a file at ``target`` would hold it (``name``: the
    design's name there, default ``<name>__<family>``): ``old`` / ``new`` metrics
    (:func:`metric_rows`), ``layers`` (the planner's order bottom to top, conflicts, the
    smallest planar clearance in mm over ``parts.interference_poses`` poses), ``design`` (the
    new validated design), ``raw`` (its TOML mapping) and ``dropped`` (source targets not
    carried over). Raises DesignError (``--to``, the layout check's one line)."""
    import numpy as np

    from cad.families.fourbar.layers import choose_layers
    from cad.families.fourbar.pose import planar_transforms
    from cad.kinematics.linkgeom import link_joints_mm

    raw = swap_raw(design, family, target)
    if name is not None:
        raw["name"] = name
    dropped = [k for k in (design.raw.get("targets") or {}) if k not in (raw.get("targets") or {})]
    new = replan(raw, target, family)  # validates before anything is written
    phi = np.linspace(new.phi1_min_rad, new.phi1_max_rad, new.parts.interference_poses)
    plan = choose_layers(link_joints_mm(new.linkage), new.parts, planar_transforms(new.linkage, phi))
    return {
        "old": metric_rows(design),
        "new": metric_rows(new),
        "layers": {
            "order": list(plan.order),
            "conflicts": list(plan.conflicts),
            "min_planar_clearance_mm": plan.min_planar_clearance_mm,
        },
        "design": new, "raw": raw, "dropped": dropped,
    }
