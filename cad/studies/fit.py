"""Inverse design: adjust a four-bar design's free part parameters to meet its targets.

The objective is the largest target violation (0 when every target is met,
:func:`cad.checks.violation`); ties go to the smallest change from the start. The default
datasheet limits (``limit_targets``, :func:`cad.families.fourbar.limits.default_limit_targets` for
four-bars) are hard: a candidate meeting them all ranks before any that misses one. The
pre-CAD checks (:func:`precad_checks`) reject a candidate before any solid is made; it is
counted apart and not in the evaluation budget.
The search runs on optuna, the engine of ``hapticad optimize`` (:mod:`cad.studies.codesign`):

- choice parameters (materials, ``bar_pockets``, and ``bar_thickness_mm``, picked from
  the stock thicknesses of the bar material, :data:`cad.studies.codesign.search.STOCK_THICKNESS_MM`,
  nearest to the start first): when every free parameter is a choice and there are at most
  :data:`GRID_MAX` combinations, all of them are evaluated (optuna ``GridSampler``);
- otherwise (numeric parameters such as ``parts.bar_width_mm=10:30``) a seeded TPE study
  of ``12 + 6 x (number of free parameters)`` evaluations, the start enqueued first.

Every evaluation rebuilds the parts and integrates them exactly
(:func:`cad.families.fourbar.inertia.inertia_model`); a parameter value for which the parts
cannot be built counts as infeasible. The log of every evaluation is returned.

Why not the plate-thickness shortcut alone: a bar's own mass properties scale
exactly linearly with its thickness, but the pins, spacers and layer heights
change with it too, so H is only nearly linear in ``bar_thickness_mm``.
"""

from __future__ import annotations

import copy
import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from cad.checks import evaluate, violation
from cad.data.materials import SHEETS
from cad.design import bounds, parse_design
from cad.design.bounds import FIELDS, check_number
from cad.design.pantograph import OPTIMIZABLE
from cad.design.parts import ALLOWED_KEYS
from cad.design.targets import Target
from cad.errors import DesignError, HapticadError
from cad.families.fourbar.datasheet import force_rows, lever
from cad.printing import FILAMENTS
from cad.studies.codesign import cheap
from cad.studies.codesign.cheap import layer_plan
from cad.studies.codesign.search import STOCK_THICKNESS_MM, layer_problem, optimize_study
from cad.tolerances import FIT_CHANGE_WEIGHT, STOCK_RANGE_SLACK_MM

#: candidates tried for a free material parameter (light to heavy)
MATERIAL_CHOICES = ("carbon-fibre", "delrin", "pla", "petg", "aluminium-6061", "aluminium-7075",
                    "stainless-304", "steel-1018", "brass-360")
NUMERIC_DEFAULT_SPAN = (0.5, 1.5)
#: ``--free parts.layer_order``: the 6 stackings of the moving links, bottom to top (an order
#: the layer planner objects to -- links that clash over the stroke, a stack no catalog pin or
#: screw fastens -- is infeasible, as in ``optimize``: the build would refuse it)
LAYER_ORDER_CHOICES = tuple(list(o) for o in itertools.permutations(("crank", "coupler", "rocker")))
#: all-choice searches up to this many combinations are exhaustive (GridSampler)
GRID_MAX = 64
#: TPE trials at most this many times the evaluation budget (the candidates the pre-CAD checks
#: reject are cheap and do not count in the budget)
PRECAD_TRIALS_FACTOR = 5


@dataclass
class FreeParam:
    """A free parameter: dotted path (``parts.bar_thickness_mm``), kind, bounds or choices."""

    path: str
    kind: str  # "numeric" | "choice"
    lo: float = math.nan
    hi: float = math.nan
    choices: tuple = ()


@dataclass
class FitResult:
    raw: dict
    start: dict[str, Any]
    values: dict[str, Any]
    objective: float
    met: bool
    log: list[dict] = field(default_factory=list)
    linearity_note: str = ""
    rejected_pre_cad: int = 0


def _get(raw: dict, path: str, default: Any) -> Any:
    node = raw
    for k in path.split(".")[:-1]:
        node = node.get(k, {})
    return node.get(path.split(".")[-1], default)


def _set(raw: dict, path: str, value: Any) -> dict:
    out = copy.deepcopy(raw)
    node = out
    *head, last = path.split(".")
    for k in head:
        node = node.setdefault(k, {})
    node[last] = value
    return out


def current_value(design, path: str) -> Any:
    """The design's value of a free parameter: ``parts.KEY`` from its parts spec,
    ``mechanism.KEY`` (pantograph families) from its mechanism parameters, ``TABLE.KEY`` from
    the design's table of that name (the PowerMouse's ``[actuator]``, ``[flotor]``, ...)."""
    section, name = path.split(".", 1)
    if section == "mechanism":
        return design.params[name]
    if name == "layer_order":
        return layer_order_of(design)
    return getattr(getattr(design, section), name)


def layer_order_of(design) -> list[str]:
    """The design's layer order (bottom to top): ``[parts] layer_order`` or the planner's
    automatic choice (:func:`cad.families.fourbar.layers.choose_layers`, numpy only)."""
    if design.parts.layer_order is not None:
        return list(design.parts.layer_order)

    plan = layer_plan(design)
    return list(plan.order) if plan is not None else list(LAYER_ORDER_CHOICES[0])


def parse_free_pantograph(spec: str, design) -> FreeParam:
    """Free parameter of a pantograph-family design: ``mechanism.KEY[=LO:HI]`` (the lengths
    its ``[optimize]`` table may range over) or, for the twin pantograph, ``parts.KEY[=LO:HI]``
    (numeric) / ``parts.*_material`` (choice)."""
    import dataclasses

    key, _, rng = spec.partition("=")
    key = key.strip()
    section, _, name = key.partition(".")
    if section == "mechanism":
        allowed = OPTIMIZABLE[design.family]
    elif section == "parts" and design.parts is not None:
        allowed = tuple(f.name for f in dataclasses.fields(design.parts))
    else:
        allowed = ()
    if name not in allowed:
        raise DesignError(f"--free {spec}", f"not a free parameter of a {design.family} design "
                          f"(mechanism.{{{', '.join(OPTIMIZABLE[design.family])}}}"
                          + (", parts.KEY" if design.parts is not None else "") + ")")
    current = current_value(design, key)
    if name.endswith("_material"):
        return FreeParam(key, "choice", choices=MATERIAL_CHOICES)
    if isinstance(current, (str, bool)):
        raise DesignError(f"--free {spec}", f"{name} is not a numeric or material parameter")
    return numeric_free(spec, key, rng, float(current))


def _range(spec: str, key: str, rng: str, lo: float, hi: float) -> tuple[float, float]:
    """``LO:HI`` of a ``--free`` flag (default ``lo, hi``): numbers, 0 < LO < HI, each within
    the key's bounds (:mod:`cad.design.bounds`)."""
    if not rng:
        return lo, hi
    try:
        lo, hi = (float(x) for x in rng.split(":"))
    except ValueError:
        raise DesignError(f"--free {spec}", "range must be LO:HI (numbers)") from None
    if not (0 < lo < hi):
        raise DesignError(f"--free {spec}", f"need 0 < LO < HI, got {lo}:{hi}")

    bound = FIELDS.get(key)
    if bound is not None:
        for x in (lo, hi):
            check_number(f"--free {key}", x, bound)
    return lo, hi


def numeric_free(spec: str, key: str, rng: str, current: float) -> FreeParam:
    """Numeric free parameter: LO:HI from the flag, else 0.5x..1.5x the current value."""
    lo, hi = _range(spec, key, rng, current * NUMERIC_DEFAULT_SPAN[0],
                    current * NUMERIC_DEFAULT_SPAN[1])
    return FreeParam(key, "numeric", lo=lo, hi=hi)


#: Four-bar plate parts a laser cuts from sheet: their material key -> does the part hold a
#: tapped thread (:func:`cad.design.laser.plate_groups`: the coupler's handle hole, the base
#: plate's motor-mount screws; the motor mount holds none).
LASER_PLATE_KEYS = {"bar_material": True, "base_material": True, "motor_mount_material": False}


def material_choices(parts_spec, name: str) -> tuple[str, ...]:
    """Materials a ``--free parts.<name>`` may take under the design's ``parts.process``:
    laser, for a plate part, the sheets the laser process cuts it from (tappable where the
    part holds a thread: :mod:`cad.design.laser`); printed, the printing filaments
    (:data:`cad.printing.FILAMENTS`) for the made parts; otherwise :data:`MATERIAL_CHOICES`."""
    process = getattr(parts_spec, "process", "machined")
    if process == "laser" and name in LASER_PLATE_KEYS and not (
            name == "bar_material" and getattr(parts_spec, "bar_style", "plate") != "plate"):

        return tuple(k for k, s in SHEETS.items() if s.tappable or not LASER_PLATE_KEYS[name])
    if process == "printed" and name not in ("pin_material",):

        return tuple(FILAMENTS)
    return MATERIAL_CHOICES


def parse_free(spec: str, parts_spec) -> FreeParam:
    """``parts.KEY`` or ``parts.KEY=LO:HI`` (numeric) -> FreeParam with defaults from the spec."""
    key, _, rng = spec.partition("=")
    key = key.strip()
    if not key.startswith("parts."):
        key = "parts." + key
    name = key.split(".", 1)[1]
    if name not in ALLOWED_KEYS:
        raise DesignError(f"--free {spec}", f"unknown part parameter {name!r}")
    current = getattr(parts_spec, name)
    if name == "layer_order":
        if rng:
            raise DesignError(f"--free {spec}", "a layer order takes no range (all 6 orders are tried)")
        return FreeParam(key, "choice", choices=LAYER_ORDER_CHOICES)
    if name.endswith("_material"):
        if rng:
            raise DesignError(f"--free {spec}", "a material takes no range")
        return FreeParam(key, "choice", choices=material_choices(parts_spec, name))
    if isinstance(current, bool):
        return FreeParam(key, "choice", choices=(True, False))
    if name == "bar_thickness_mm":
        return _stock_thickness(spec, key, rng, parts_spec)
    if not isinstance(current, (int, float)) or current is None:
        raise DesignError(f"--free {spec}", f"{name} is not a numeric, material or boolean parameter")
    return numeric_free(spec, key, rng, float(current))


def parse_free_parts(spec: str, design) -> FreeParam:
    """:func:`parse_free` against a four-bar design's ``[parts]`` (the family's
    ``TargetHooks.parse_free``). Raises DesignError naming ``--free``."""
    return parse_free(spec, design.parts)


def _stock_thickness(spec: str, key: str, rng: str, parts_spec) -> FreeParam:
    """Plate thickness: a choice among the stock thicknesses of the bar material
    (:data:`cad.studies.codesign.search.STOCK_THICKNESS_MM`; its sheet's under ``process =
    "laser"``, :data:`cad.data.materials.SHEETS`) inside LO:HI (default 0.5x..1.5x the
    current value), nearest to the current value first (ties go to the smallest change)."""
    cur = parts_spec.bar_thickness_mm
    stock = STOCK_THICKNESS_MM.get(parts_spec.bar_material, STOCK_THICKNESS_MM["aluminium-6061"])
    sheet = SHEETS.get(parts_spec.bar_material) if getattr(parts_spec, "process", "") == "laser" else None
    if sheet is not None:  # laser-cut bars: the sheet's stock thicknesses (cad.design.laser)
        stock = tuple(sheet.thicknesses_mm)
    lo, hi = _range(spec, key, rng, cur * NUMERIC_DEFAULT_SPAN[0], cur * NUMERIC_DEFAULT_SPAN[1])
    inside = sorted((t for t in stock if lo - STOCK_RANGE_SLACK_MM <= t <= hi + STOCK_RANGE_SLACK_MM), key=lambda t: (abs(t - cur), t))
    if not inside:
        raise DesignError(f"--free {spec}", f"no stock {parts_spec.bar_material} thickness in {lo:g}..{hi:g} mm "
                                            f"(stock: {', '.join(f'{t:g}' for t in stock)} mm)")
    return FreeParam(key, "choice", lo=lo, hi=hi, choices=tuple(inside))


def _refuse_unbuildable_order(design, free: list[FreeParam]) -> None:
    """Raise :class:`DesignError` (``parts.layer_order``) when the layer order is free and
    the build's planner (numpy, :func:`cad.studies.codesign.search.layer_problem`) objects to the
    design's order: a fit must not return a design ``build`` refuses."""
    if not any(p.path == "parts.layer_order" for p in free):
        return

    _, why = layer_problem(design)
    if why:
        raise DesignError("parts.layer_order", why)


def fit(raw: dict, source: str, targets: tuple[Target, ...], free: list[FreeParam],
        evaluate_values: Callable[[Any], dict[str, float]], echo: Callable[[str], None] | None = None,
        trials: int | None = None, seed: int = 0,
        limit_targets: Callable[[Any], tuple[Target, ...]] | None = None,
        precad: Callable[[Any], tuple[dict, str | None]] | None = None) -> FitResult:
    """Search ``free`` on the raw design with optuna (see module docstring).

    ``limit_targets(design)``: the default limits a candidate must also meet (e.g.
    :func:`cad.families.fourbar.limits.default_limit_targets`: continuous force, first mode, stress
    for its material, clearance). They are hard: a candidate missing one ranks after every
    candidate that meets them all, whatever its target violation.

    ``precad(design) -> (values, reason or None)``: the cheap checks run before any CAD
    (:func:`precad_checks`). A candidate is rejected before CAD when they give a reason (the
    build would refuse it), or when its limit violation known before CAD (the force figures)
    already exceeds the smallest limit violation of a candidate evaluated so far (it cannot
    rank above it); a rejected candidate does not count in the evaluation budget
    (``FitResult.rejected_pre_cad`` counts it).

    Score of a value set: (limits missed, max target violation, largest limit violation, change
    from the start); the best by that order is returned. Only choices: every combination
    (optuna ``GridSampler``) when there are at most :data:`GRID_MAX` of them; otherwise TPE (seeded) until ``trials``
    candidates were evaluated (default ``12 + 6 x len(free)``), the start evaluated first.
    """
    search = _FitSearch(raw, source, targets, free, evaluate_values, echo, limit_targets, precad)
    _run_study(search, trials, seed)
    _, obj, _, _, vals = min(search.scored.values(), key=lambda t: t[:4])
    cur = search.with_values(vals)
    final_vals = search.objective(cur)[1]
    for text in search.warned.get(search.key(cur), ()):  # the fitted design's own warnings
        bounds.warn(text)  # (every candidate's were muted)
    rows = evaluate(targets, {k: v for k, v in final_vals.items() if isinstance(v, (int, float))})
    return FitResult(raw=cur, start=search.start_vals, values=dict(vals), objective=obj,
                     met=all(r.ok for r in rows), log=search.log,
                     rejected_pre_cad=search.rejected_pre_cad)


def precad_checks(design) -> tuple[dict, str | None]:
    """(values, reason or None) of the checks a four-bar candidate gets before any CAD: the
    layer planner of the build (:func:`cad.studies.codesign.search.layer_problem`, numpy) and
    the tube bars' geometry (a reason: the build would refuse it); ``values``: the force
    figures, which need no CAD (continuous / peak force at the handle, motor torque /
    |dx/dphi1|, :func:`cad.families.fourbar.datasheet.force_rows`)."""
    _, why = layer_problem(design)
    if why:
        return {}, f"layers: {why}"
    why = cheap.tube_problem(design)
    if why:
        return {}, f"tubes: {why}"
    Jx = lever(design)[1]
    return {r["key"]: r["value"] for r in force_rows(design, design.motor_spec(), Jx)
            if r["value"] is not None and r["key"] in ("continuous_force_N", "peak_force_N")}, None


class _FitSearch:
    """The objective of :func:`fit` over value sets of ``free``, with its cache and log.

    ``scored``: every value set the study evaluated, keyed by its sorted items, as
    (limits missed, max target violation, limit violation, change from the start, values);
    ``cad_evaluations`` / ``rejected_pre_cad``: candidates evaluated / rejected before CAD.
    """

    def __init__(self, raw: dict, source: str, targets: tuple[Target, ...], free: list[FreeParam],
                 evaluate_values: Callable[[Any], dict[str, float]],
                 echo: Callable[[str], None] | None,
                 limit_targets: Callable[[Any], tuple[Target, ...]] | None,
                 precad: Callable[[Any], tuple[dict, str | None]] | None = None) -> None:
        self.raw, self.source, self.targets, self.free = raw, source, targets, free
        self.evaluate_values, self.echo, self.limit_targets = evaluate_values, echo, limit_targets
        self.precad = precad
        self.cache: dict[str, tuple[float, dict, float]] = {}
        self.warned: dict[str, list[str]] = {}  # each candidate's own warnings (muted)
        self.log: list[dict] = []
        self.scored: dict[str, tuple] = {}
        self.cad_evaluations = 0
        self.rejected_pre_cad = 0
        self.budget: int | None = None
        #: (limits missed, largest limit violation) of the best candidate evaluated so far
        self.best_limit_rank: tuple[float, float] = (math.inf, math.inf)
        start_design = parse_design(raw, source)
        self.start_vals = {p.path: current_value(start_design, p.path) for p in free}

    def objective(self, r: dict) -> tuple[float, dict]:
        """(max target violation, values) of the raw design ``r`` (cached); ``values["limit
        violation"]``: the largest violation of the limits. A design that cannot be parsed,
        planned or evaluated, or that the pre-CAD checks reject, scores inf."""
        free, targets = self.free, self.targets
        key = self.key(r)
        if key in self.cache:
            return self.cache[key][:2]
        pre_cad = True
        with bounds.muted() as said:  # kept per candidate: fit() re-says the fitted one's
            try:
                d = parse_design(r, self.source)
                _refuse_unbuildable_order(d, free)
                limits = tuple(self.limit_targets(d)) if self.limit_targets is not None else ()
                vals, why = self.precad(d) if self.precad is not None else ({}, None)
                if why:
                    raise DesignError("pre-CAD", why)
                pre = max((violation(t, vals[t.key]) for t in limits if t.key in vals), default=0.0)
                # bound: missing a limit by `pre` it ranks at best (1 missed, pre), after the best so far
                if pre > 0 and (1, pre) > self.best_limit_rank:
                    raise DesignError("pre-CAD", f"a limit violation of {pre:.3g} before CAD, worse than "
                                                 f"{self.best_limit_rank[1]:.3g} of an evaluated candidate")
                pre_cad = False
                vals = {**vals, **self.evaluate_values(d)}
                obj = max((violation(t, vals[t.key]) if t.key in vals else math.inf) for t in targets)
                lim = max((violation(t, vals[t.key]) if t.key in vals else math.inf for t in limits), default=0.0)
                missed = sum(1 for t in limits if t.key not in vals or violation(t, vals[t.key]) > 0)
                vals["limit_violation"], vals["limits_missed"] = lim, missed
                self.best_limit_rank = min(self.best_limit_rank, (missed, lim))
            except HapticadError as exc:
                vals, obj = {"error": str(exc), "limit_violation": math.inf, "limits_missed": math.inf}, math.inf
        self.warned[key] = said
        self.cad_evaluations += not pre_cad
        self.rejected_pre_cad += pre_cad
        entry = {"params": {p.path: _get(r, p.path, None) for p in free}, "objective": obj,
                 "limit_violation": vals["limit_violation"], "pre_cad_rejected": pre_cad,
                 **{t.key: vals.get(t.key) for t in targets}}
        self.log.append(entry)
        if self.echo:
            ps = ", ".join(f"{k.split('.')[-1]}={v}" for k, v in entry["params"].items())
            why = f"  ({vals['error']})" if "error" in vals else ""
            word = "rejected before CAD" if pre_cad else f"max violation {obj:.4g}, limits {vals['limit_violation']:.3g}"
            self.echo(f"  eval {len(self.log):2d}: {ps}  ->  {word}{why}")
        self.cache[key] = (obj, vals, vals["limit_violation"])
        return obj, vals

    def key(self, r: dict) -> str:
        """The cache key of the raw design ``r``: its free parameters' values."""
        return repr([(p.path, _get(r, p.path, None)) for p in self.free])

    def change(self, vals: dict) -> float:
        """Distance from the start: numeric |x - x0| / (hi - lo); choices: rank in the list."""
        out = 0.0
        for p in self.free:
            x, x0 = vals[p.path], self.start_vals[p.path]
            if p.kind == "numeric":
                out += abs(float(x) - float(x0)) / (p.hi - p.lo)
            elif x != x0:
                out += (list(p.choices).index(x) + 1) / (len(p.choices) + 1) if x in p.choices else 1.0
        return out

    def with_values(self, vals: dict) -> dict:
        """A deep copy of the raw design with ``vals`` ({dotted path: value}) set."""
        cur = copy.deepcopy(self.raw)
        for path, v in vals.items():
            cur = _set(cur, path, v)
        return cur

    def suggest(self, trial) -> dict:
        """{path: value} drawn by an optuna trial (parameter ``p<i>`` for free[i])."""
        vals = {}
        for i, p in enumerate(self.free):
            name = f"p{i}"
            if p.kind == "choice":
                vals[p.path] = p.choices[trial.suggest_categorical(name, list(range(len(p.choices))))]
            else:
                vals[p.path] = round(trial.suggest_float(name, p.lo, p.hi), 6)
        return vals

    def study_objective(self, trial) -> float:
        """Optuna's objective: max target violation plus FIT_CHANGE_WEIGHT x change (ties go to
        the smallest change) when every limit is met; 1e6 x limits missed + max target
        violation + largest limit violation when one is missed (among candidates that miss as
        many limits, the targets decide: a limit none can meet must not pull the search off
        them); 1e9 for an infeasible value set."""
        vals = self.suggest(trial)
        obj, got = self.objective(self.with_values(vals))
        lim, missed = got["limit_violation"], got["limits_missed"]
        # fewer limits missed first: a limit no candidate can meet (the motor's force) must not
        # let the search give up another limit the start met
        self.scored[repr(sorted(vals.items(), key=lambda kv: kv[0]))] = (
            missed, obj, lim, self.change(vals), vals)
        if self.budget is not None and self.cad_evaluations >= self.budget:
            trial.study.stop()
        if not (math.isfinite(obj) and math.isfinite(lim)):
            return 1e9
        return obj + FIT_CHANGE_WEIGHT * self.change(vals) if lim == 0 else 1e6 * missed + obj + lim

    def first_trial(self) -> dict:
        """Optuna parameters of the start (choices by index, numbers clipped to their range)."""
        first = {}
        for i, p in enumerate(self.free):
            x0 = self.start_vals[p.path]
            first[f"p{i}"] = list(p.choices).index(x0) if p.kind == "choice" and x0 in p.choices else (
                0 if p.kind == "choice" else float(min(max(x0, p.lo), p.hi)))
        return first


def _run_study(search: _FitSearch, trials: int | None, seed: int) -> None:
    """Exhaustive grid (all choices, at most GRID_MAX combinations) or seeded TPE with the
    start enqueued first; fills ``search.scored``. An interrupt raises KeyboardInterrupt."""
    import warnings

    import optuna

    free = search.free
    n_grid = math.prod(len(p.choices) for p in free) if all(p.kind == "choice" for p in free) else None
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # optuna ExperimentalWarning (multivariate TPE)
        if n_grid is not None and n_grid <= GRID_MAX:
            sampler = optuna.samplers.GridSampler(
                {f"p{i}": list(range(len(p.choices))) for i, p in enumerate(free)}, seed=seed)
            n = n_grid
        else:
            sampler = optuna.samplers.TPESampler(seed=seed, multivariate=True)
            search.budget = trials or 12 + 6 * len(free)
            n = PRECAD_TRIALS_FACTOR * search.budget  # rejected before CAD: not in the budget
        study = optuna.create_study(direction="minimize", sampler=sampler)
        if n_grid is None or n_grid > GRID_MAX:
            study.enqueue_trial(search.first_trial())
        optimize_study(study, search.study_objective, n)  # an interrupt: KeyboardInterrupt, no log
