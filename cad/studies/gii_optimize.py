"""``hapticad optimize`` of the families searched by their global isotropy index (the
pantographs, the pen, the delta): isotropy paper eq 6 over the design's ``[optimize]`` grid,
then the design's ``[targets]`` evaluated on the optimum through the family's target hooks
(:class:`cad.families.protocol.TargetHooks`)."""

from __future__ import annotations

import copy

from cad.checks import evaluate, miss_line
from cad.datasheet.run import device_datasheet
from cad.design import parse_design
from cad.errors import DesignError
from cad.families import family_package
from cad.isotropy.report import optimize_report

METHODS = ("culling", "brute")


def optimize(design, options: dict) -> dict:
    """The ``hapticad optimize --json`` object (without the file keys) of a GII family:
    ``best``, ``gii``, evaluations ..., ``targets`` (check rows of the design's
    ``[targets]`` on the optimum), ``misses`` (their ``target missed:`` lines and what
    blocks them; the CLI exits 1 when not empty) and ``limit_warnings`` (the datasheet's
    default limits the optimum misses, outside its targets: warning lines, as ``check`` and
    ``fit`` say them). ``options``: ``method`` (culling | brute, default culling),
    ``objective`` (must be None). Raises DesignError naming the flag."""
    if options.get("objective") is not None:
        raise DesignError("--objective", f"min-apparent-mass is for four-bar designs, not "
                                         f"{design.family!r} (use --method)")
    method = options.get("method") or "culling"
    if method not in METHODS:
        raise DesignError("--method", f"must be 'culling' or 'brute', got {method!r}")
    rep = optimize_report(design, method)
    best = optimum_design(design, rep)
    rep["targets"], rep["misses"] = optimum_misses(design, best)
    rep["limit_warnings"] = optimum_limit_warnings(best, {t.key for t in design.targets})
    return rep


def optimum_design(design, rep: dict):
    """``design`` with its ``[mechanism]`` set to the optimum ``rep["best"]`` (parsed: its
    family's schema)."""
    raw = copy.deepcopy(design.raw)
    raw["mechanism"].update(rep["best"])
    return parse_design(raw, str(design.source))


def optimum_limit_warnings(best, checked: set[str]) -> list[str]:
    """The datasheet's warning lines (:func:`cad.datasheet.judge`) of the default limits the
    optimum design ``best`` misses, other than the figures ``checked`` as targets: the GII
    optimum is the best-conditioned layout, not one that meets the limits, and says so."""
    ds = device_datasheet(best, "inertia")
    missed = [r for r in ds["rows"] if r.get("verdict") == "miss"]  # judge's order
    return [w for r, w in zip(missed, ds["warnings"], strict=True) if r["key"] not in checked]


def optimum_misses(design, best) -> tuple[list[dict], list[str]]:
    """(rows, "target missed:" lines) of the design's ``[targets]`` on the optimum design
    ``best`` (:func:`optimum_design`), from the family's target values (a build when a
    target needs one) and, for a miss, the family's blocker lines; none without targets."""
    if not design.targets:
        return [], []
    hooks = family_package(design.family).targets
    vals, report = hooks.values(best, "inertia", {t.key for t in design.targets})
    rows = evaluate(design.targets, vals)
    lines = [miss_line(r.key, r.target, r.computed) for r in rows if not r.ok]
    if lines and hooks.blockers is not None:
        lines += hooks.blockers(best, report, rows)
    return [r.as_dict() for r in rows], lines
