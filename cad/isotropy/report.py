"""The ``hapticad gii`` and ``hapticad optimize`` (pantograph families) reports as plain dicts.

What the commands print with ``--json`` and :func:`cad.api.gii` / :func:`cad.api.optimize`
return. Pure numpy (through the design's problem); no CAD import, no printing.
"""

from __future__ import annotations

from cad.data.families import command_families

#: The design families the GII is computed for (the registry's ``gii`` column).
PANTOGRAPH_FAMILIES = command_families()["gii"]


def _point(units: tuple[str, ...], p) -> dict[str, float]:
    return {u: round(float(v), 9) for u, v in zip(units, p, strict=True)}


def gii_report(design) -> dict:
    """GII report of a loaded pantograph-family design (isotropy paper eq 5 over its
    ``[workspace]`` grid): ``gii``, ``sigma_min`` / ``sigma_max`` and where they occur (mm
    and the design's point units), the workspace's extents ``workspace_size_mm`` (the design's
    ``workspace_size_mm()``: [W, H] of the planar families, [x, y, z] of the pen, the delta's
    box [W, D, H] or cylinder [D, D, H]), the sample count, Jacobian evaluations, the failure (an
    unreachable or singular sample gives GII = 0 and is named) and the wall time (s)."""
    import time

    t0 = time.perf_counter()
    r = design.gii()
    dt = time.perf_counter() - t0
    units = design.point_units()
    npos = sum(u.endswith("_mm") for u in units)
    return {
        "design": design.name,
        "family": design.family,
        "gii": r.gii,
        "sigma_min": r.sigma_min,
        "sigma_max": r.sigma_max,
        "sigma_min_at_mm": [float(v) for v in r.sigma_min_at[:npos]],
        "sigma_max_at_mm": [float(v) for v in r.sigma_max_at[:npos]],
        "sigma_min_at": _point(units, r.sigma_min_at),
        "sigma_max_at": _point(units, r.sigma_max_at),
        "workspace_size_mm": design.workspace_size_mm(),
        "workspace_shape": design.workspace.get("shape", "box"),
        "n_points": r.n_points,
        "jacobian_evaluations": r.jacobian_evaluations,
        "failure": r.failure,
        "failed_at": None if r.failed_at is None else _point(units, r.failed_at),
        "n_failed": r.n_failed,
        "wall_time_s": dt,
        **gii_extras(design),
    }


def gii_extras(design) -> dict:
    """A family's own rows of its GII report: the design's optional ``gii_extras()`` hook
    (the delta's reachable and well-conditioned workspace,
    :meth:`cad.families.delta.design.DeltaDesign.gii_extras`); ``{}`` when the family gives none."""
    hook = getattr(design, "gii_extras", None)
    return hook() if hook is not None else {}


def optimize_report(design, method: str) -> dict:
    """GII optimization report of a loaded pantograph-family design (isotropy paper eq 6
    over its ``[optimize]`` candidate grid, ``method`` "culling" or "brute"): the best
    candidate, the fixed parameters, the GII, Jacobian evaluations against brute force, the
    parameters whose optimum sits on their range bound."""
    from cad.isotropy.culling import optimize

    problem = design.problem()
    res = optimize(problem, method)
    best = problem.candidate(res.best_index)
    best = {k: v for k, v in best.items() if k in design.optimize or k in design.params}
    at_bound = [
        name
        for name, (lo, hi, count) in design.optimize.items()
        if count > 1 and (best[name] == lo or best[name] == hi)
    ]
    return {
        "design": design.name,
        "family": design.family,
        "method": res.method,
        "best": {k: best[k] for k in design.optimize},
        "fixed": {k: v for k, v in design.params.items() if k not in design.optimize},
        "gii": res.gii,
        "jacobian_evaluations": res.jacobian_evaluations,
        "brute_force_evaluations": res.brute_force_evaluations,
        "evaluation_ratio": res.brute_force_evaluations / res.jacobian_evaluations,
        "wall_time_s": res.wall_time_s,
        "n_candidates": res.n_candidates,
        "n_points": res.n_points,
        "candidates_completed": res.candidates_completed,
        "at_bound": at_bound,
    }
