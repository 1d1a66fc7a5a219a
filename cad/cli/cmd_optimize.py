"""``hapticad optimize DESIGN --method culling|brute [--json]``: maximize the GII.

Isotropy paper eq (6) over the design's ``[optimize]`` candidate grid; culling
(Stocco, Salcudean & Sassani 1998) returns the brute-force optimum exactly
while evaluating far fewer Jacobians.
"""

from __future__ import annotations

from pathlib import Path

import typer

from cad.cli.app import print_json


def optimize_report(design, method: str) -> dict:
    """JSON-able optimization report of a loaded pantograph-family design."""
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


def write_optimum(design, rep: dict, out: Path, command: str) -> bool:
    """Write ``design`` with its ``[mechanism]`` set to the optimum, validated first, atomically.

    The ``[optimize]`` ranges are kept (re-running reproduces the search); ``name`` becomes
    the file's stem. Raises DesignError (--out) when ``out`` is the input design itself
    (same path, symbolic or hard link). Returns True when an existing file was replaced.
    """
    import copy

    from cad.design.pantograph import parse
    from cad.design.writer import write_design
    from cad.io.outdir import check_out_file

    replaced = check_out_file(out, Path(design.source))  # never the input design (any link)
    raw = copy.deepcopy(design.raw)
    raw["mechanism"].update(rep["best"])
    raw["name"] = out.stem
    parse(raw, str(out))  # must validate before anything is written
    write_design(out, raw, f"Optimum of `{command}`: GII {rep['gii']:.6f} ({rep['method']})")
    return replaced


def register(app: typer.Typer) -> None:
    @app.command("optimize")
    def optimize_cmd(
        design: Path = typer.Argument(..., help="Design TOML with an [optimize] table."),
        method: str = typer.Option("culling", "--method", help="culling or brute."),
        out: Path = typer.Option(None, "--out", help="Write the optimum as a new design (TOML)."),
        json_out: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Maximize the GII over the [optimize] candidate grid (culling or brute force)."""
        from cad.cli import flags
        from cad.cli.cmd_gii import load_pantograph_design
        from cad.errors import DesignError

        flags.out_path("--out", out, folder=False)
        if method not in ("culling", "brute"):
            raise DesignError("--method", f"must be 'culling' or 'brute', got {method!r}")
        d = load_pantograph_design(design)
        rep = optimize_report(d, method)
        if out is not None:
            rep["replaced"] = write_optimum(
                d, rep, out, f"hapticad optimize {design.name} --method {method}"
            )
            rep["out"] = str(out)
        if json_out:
            print_json(rep)
            return
        print(f"{rep['design']} ({rep['family']}), {rep['method']}: GII = {rep['gii']:.6f}")
        print(f"  best: {rep['best']}")
        print(
            f"  {rep['jacobian_evaluations']} Jacobian evaluations "
            f"(brute force {rep['brute_force_evaluations']}, ratio {rep['evaluation_ratio']:.1f}) "
            f"in {rep['wall_time_s']:.3f} s; {rep['n_candidates']} candidates x {rep['n_points']} samples"
        )
        if rep["at_bound"]:
            print(f"  note: optimum at the range bound of {', '.join(rep['at_bound'])}")
        if out is not None:
            print(f"  {'replaced' if rep['replaced'] else 'wrote'} {out}")
