"""``hapticad fit DESIGN --target KEY=VALUE [...] [--free parts.KEY[=LO:HI] ...] [--out NEW.toml] [--json]``."""

from __future__ import annotations

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
        trials: int = typer.Option(None, "--trials", help="Evaluation budget of the search (default 12 + 6 x the free parameters; a grid of choices is evaluated whole)."),
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
        from cad.api import fit_run, fit_setup
        from cad.cli import flags
        from cad.design import load_design
        from cad.design.writer import dumps_design
        from cad.io.atomic import write_text_atomic
        from cad.io.outdir import check_out_file

        flags.choice("--fidelity", fidelity, ("inertia", "fabrication"))
        flags.number("--trials", trials)
        flags.out_path("--out", out, folder=False)
        d = load_design(design)
        setup = fit_setup(d, tuple(target or ()), tuple(free or ()))
        dst = out if out is not None else design.with_suffix(".fit.toml")
        replaced = check_out_file(dst, design)
        echo = None if json_out else (lambda s: print(s, flush=True))
        name = f"{d.name}_fit" if out is None else out.name.split(".")[0]
        res = fit_run(d, setup, fidelity, dst, name, echo, trials)
        fitted = res.pop("raw")
        res.pop("design")
        # the design file last: it is the command's output (cad.io.signals commit point)
        from cad.checks import best_reached, miss_line

        wanted = {t.key: t for t in setup["targets"]}  # a missed default limit is a warning line below
        built = [e for e in res["iterations"] if not e.get("pre_cad_rejected")]
        # best reached: over every candidate evaluated (as optimize says it), then the written one's
        missed = [miss_line(r["key"], r["target_text"],
                            best_reached(wanted[r["key"]], [e.get(r["key"]) for e in built] + [r["computed"]]),
                            r["computed"])
                  for r in res["rows"] if not r["ok"] and r["key"] in wanted]
        write_text_atomic(dst, dumps_design(fitted, fitted_comment(design, res, missed)), final=True)
        payload = {"name": res["name"], "out": str(dst), "replaced": replaced,
                   **{k: v for k, v in res.items() if k != "name"}}
        if json_out:
            print_json(payload, indent=1, default=str)
        else:
            for k, v in res["fitted"].items():
                print(f"{k}: {res['start'][k]} -> {v}")
            for r in payload["rows"]:
                comp = "—" if r["computed"] is None else f"{r['computed']:.4g}"
                print(f"  {r['key']}: {comp} (target {r['target_text']}) {'ok' if r['ok'] else 'MISSED'}")
            print(f"{payload['evaluations']} candidates evaluated, {payload['rejected_pre_cad']} rejected "
                  "before CAD (the family's pre-CAD checks: the fit log names each reason)")
            print(f"{'replaced' if replaced else 'wrote'} {dst}")
        import sys

        for w in payload["limit_warnings"]:
            print(f"hapticad: warning: the fitted design misses a default datasheet limit: {w}",
                  file=sys.stderr)
        if not payload["met"]:  # one line per missed target: the written (best) design's figure
            for m in missed:
                print(f"hapticad: {m}", file=sys.stderr)
            for b in payload["blockers"]:  # what blocks it and by how much (pantograph first mode)
                print(f"hapticad: {b}", file=sys.stderr)
            raise typer.Exit(1)


def fitted_comment(design, res: dict, missed: list[str]) -> str:
    """The fitted file's comment: the command and the fitted values, each missed target's
    line, what blocks it, and each default datasheet limit the written design misses."""
    return (f"Fitted by `hapticad fit {design}`: " + ", ".join(f"{k}={v}" for k, v in res["fitted"].items())
            + "".join(f"\n{m}" for m in missed) + "".join(f"\n{b}" for b in res["blockers"])
            + "".join(f"\ndefault limit missed: {w}" for w in res["limit_warnings"]))
