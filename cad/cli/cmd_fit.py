"""``hapticad fit DESIGN --target KEY=VALUE [...] [--free parts.KEY[=LO:HI] ...] [--out NEW.toml] [--json]``."""

from __future__ import annotations

import copy
from pathlib import Path

import typer

from cad.cli.app import print_json


def register(app: typer.Typer) -> None:
    @app.command("fit")
    def fit_cmd(
        design: Path = typer.Argument(..., help="four-bar TOML design."),
        target: list[str] = typer.Option(None, "--target", help="KEY=VALUE, KEY<=V or KEY>=V (repeatable); default: the design's [targets]."),
        free: list[str] = typer.Option(None, "--free", help="parts.KEY or parts.KEY=LO:HI (repeatable); default: the design's [fit] free."),
        out: Path = typer.Option(None, "--out", help="Fitted design (default: <design>.fit.toml beside it)."),
        fidelity: str = typer.Option("inertia", "--fidelity", help="inertia | fabrication."),
        json_out: bool = typer.Option(False, "--json", help="Print one JSON object."),
        allow_scripts: bool = typer.Option(
            False, "--allow-scripts", help="Run the design's [parts] handle_script (inside its folder)."
        ),
        allow_scripts_anywhere: bool = typer.Option(
            False, "--allow-scripts-anywhere", help="Run handle_script from any path."
        ),
    ) -> None:
        """Adjust the design's free part parameters to meet the targets; write the fitted design."""
        from cad.parts.handle import set_script_policy

        set_script_policy(allow_scripts, allow_scripts_anywhere)
        run_fit(design, target, free, out, fidelity, json_out)


def run_fit(design: Path, target: list[str] | None, free: list[str] | None, out: Path | None,
            fidelity: str, json_out: bool) -> None:
    """``hapticad fit``: check the flags, search, write the fitted design, print the rows.

    Raises DesignError on bad input, TargetMissed when the best design misses a target.
    """
    from cad.checks import evaluate
    from cad.cli import flags
    from cad.design import load_design, parse_design
    from cad.design.fourbar import FourBarDesign
    from cad.design.writer import dumps_design, rebase_paths
    from cad.errors import TargetMissed
    from cad.fit import fit
    from cad.io.atomic import write_text_atomic
    from cad.io.outdir import check_out_file

    flags.choice("--fidelity", fidelity, ("inertia", "fabrication"))
    flags.out_path("--out", out, folder=False)
    d = load_design(design)
    four_bar = isinstance(d, FourBarDesign)
    cli_targets, targets, params = _fit_inputs(d, four_bar, target, free)
    dst = out if out is not None else design.with_suffix(".fit.toml")
    replaced = check_out_file(dst, design)
    limits, values_of = _fit_evaluator(four_bar, params, targets, fidelity)
    raw = {k: v for k, v in d.raw.items()}
    if four_bar:
        raw.setdefault("parts", {})
    echo = None if json_out else (lambda s: print(s, flush=True))
    if echo:
        echo(f"fit {d.name}: {len(params)} free parameter(s), {len(targets)} target(s)")
    res = fit(raw, str(design), targets, params, values_of, echo=echo, limit_targets=limits)
    fitted = rebase_paths(copy.deepcopy(res.raw), d.source, dst)
    fitted["name"] = f"{d.name}_fit" if out is None else out.name.split(".")[0]
    if cli_targets:  # keep the targets the fit was made for
        fitted["targets"] = _with_cli_targets(fitted.get("targets", {}), cli_targets)
    final_design = parse_design(fitted, str(dst))
    final_vals = values_of(final_design)
    # the design file last: it is the command's output (cad.io.signals commit point)
    write_text_atomic(dst, dumps_design(fitted, f"Fitted by `hapticad fit {design}`: "
                                        + ", ".join(f"{k}={v}" for k, v in res.values.items())),
                      final=True)
    rows = evaluate(tuple(targets) + (limits(final_design) if limits else ()), final_vals)
    payload = {"name": d.name, "out": str(dst), "replaced": replaced, "start": res.start, "fitted": res.values,
               "met": all(r.ok for r in rows), "max_violation": res.objective,
               "evaluations": len(res.log), "iterations": res.log, "rows": [r.as_dict() for r in rows]}
    if json_out:
        print_json(payload, indent=1, default=str)
    else:
        for k, v in res.values.items():
            print(f"{k}: {res.start[k]} -> {v}")
        for r in rows:
            comp = "—" if r.computed is None else f"{r.computed:.4g}"
            print(f"  {r.key}: {comp} (target {r.target}) {'ok' if r.ok else 'MISSED'}")
        print(f"{'replaced' if replaced else 'wrote'} {dst}")
    if not payload["met"]:
        raise TargetMissed("targets not met within the free parameters' bounds (the best design was written)")


def _fit_inputs(d, four_bar: bool, target: list[str] | None, free: list[str] | None) -> tuple:
    """(targets from --target, targets to meet, free parameters) of ``hapticad fit``.

    Raises DesignError for a family fit does not serve, no targets, no free
    parameter or one given twice.
    """
    from cad.checks import merge_targets
    from cad.cli.cmd_gii import PANTOGRAPH_FAMILIES
    from cad.cli.families import refusal
    from cad.design.targets import PANTOGRAPH_TARGET_KEYS, TARGET_KEYS, parse_cli_target
    from cad.errors import DesignError
    from cad.fit import parse_free, parse_free_pantograph

    if not four_bar and d.family not in PANTOGRAPH_FAMILIES:
        raise DesignError("mechanism.family", refusal("fit", d.family))
    if four_bar:
        d.check_buildable()
    keys = TARGET_KEYS if four_bar else PANTOGRAPH_TARGET_KEYS
    cli_targets = tuple(parse_cli_target(t, keys) for t in (target or []))
    targets = cli_targets if cli_targets else merge_targets(d.targets, ())
    if not targets:
        raise DesignError("--target", "no targets: give --target KEY=VALUE or a [targets] table")
    specs = list(free) if free else list(getattr(d, "fit_free", ()))
    if not specs:
        raise DesignError("--free", "no free parameters: give --free parts.KEY (four-bars), "
                                    "mechanism.KEY / parts.KEY (pantographs) or [fit] free")
    params = [parse_free(s, d.parts) if four_bar else parse_free_pantograph(s, d) for s in specs]
    seen = [q.path for q in params]
    twice = next((k for i, k in enumerate(seen) if k in seen[:i]), None)
    if twice is not None:
        raise DesignError("--free", f"{twice} is given twice; give each free parameter once")
    return cli_targets, targets, params


def _fit_evaluator(four_bar: bool, params: list, targets: tuple, fidelity: str) -> tuple:
    """(structural limit targets or None, values_of(design) -> {target key: value})."""
    from cad.datasheet.limits import STRUCTURE_FREE, structure_targets
    from cad.pipeline.inertia import pantograph_target_values, target_values

    # a free bar material: the candidates must also meet the default structural limits
    limits = structure_targets if four_bar and any(q.path in STRUCTURE_FREE for q in params) else None
    need_clear = limits is not None or any(t.key == "min_clearance_mm" for t in targets)
    wanted = {t.key for t in targets}

    def values_of(dd) -> dict:
        if four_bar:
            return target_values(dd, fidelity, need_clear)[0]
        return pantograph_target_values(dd, fidelity, wanted)[0]

    return limits, values_of


def _with_cli_targets(targets: dict, cli_targets: tuple) -> dict:
    """The design's [targets] table with the --target flags written over it."""
    tt = dict(targets)
    for t in cli_targets:
        tt[t.key] = ({"value": t.value, "tol_rel": t.tol_rel} if t.value is not None and t.tol_abs is None
                     else {"value": t.value, "tol_abs": t.tol_abs} if t.value is not None
                     else {k: v for k, v in (("min", t.min), ("max", t.max)) if v is not None})
    return tt
