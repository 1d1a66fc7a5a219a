"""``hapticad tolerance DESIGN --hole-mm T [...]``: Monte Carlo of manufacturing tolerances (four-bar).

Pure numpy unless M11 needs the solids (no `--inertia` or `[inertia]`: the parts `check` builds, via the derived cache); see :mod:`cad.kinematics.tolerance` and docs/tolerances.md.
"""

from __future__ import annotations

import json
from pathlib import Path

import typer

from cad.cli.app import print_json

OWNED = ("tolerance.json", "tolerance.png")


def _print(res: dict) -> None:
    from rich.console import Console
    from rich.table import Table

    con = Console(width=max(Console().width, 132))
    t = Table(title=f"{res['name']}: {res['samples']} samples (seed {res['seed']})")
    for c in ("metric", "nominal", "mean", "std (MC)", "std (1st order)", "p01", "p99", "target", "yield"):
        t.add_column(c, justify="left" if c == "metric" else "right")
    for k, v in res["metrics"].items():
        y = res["yield"]["by_target"].get(k)
        t.add_row(k, *(f"{v[x]:.5g}" for x in ("nominal", "mean", "std", "linear_std", "p01", "p99")),
                  y["target"] if y else "", f"{100 * y['yield']:.2f} %" if y else "")
    con.print(t)
    h = res["inertia_kg_m2"]
    con.print(f"M11 from the inertia of {res['inertia_source']}: " + ", ".join(
        f"{k[:3]} = {h[k]:.4g}" for k in ("H11_kg_m2", "H12_kg_m2", "H22_kg_m2", "H33_kg_m2")) + " kg.m^2", soft_wrap=True)
    if res["yield"]["overall"] is not None:
        con.print(f"yield (every target met): {100 * res['yield']['overall']:.2f} %; "
                  f"failed samples (no closure / toggle): {res['failed_samples']}")
    for k in res["yield"]["by_target"]:
        top = res["sensitivity"][k][:3]
        con.print(f"{k} is most sensitive to " + ", ".join(
            f"{s['tolerance']} ({100 * s['share']:.0f} %)" for s in top))


def register(app: typer.Typer) -> None:
    @app.command("tolerance")
    def tolerance_cmd(
        design: Path = typer.Argument(..., help="four-bar TOML design."),
        hole_mm: float = typer.Option(None, "--hole-mm", help="± mm on every joint hole of the three bars."),
        hole: list[str] = typer.Option(None, "--hole", help="BAR=T or BAR.HOLE=T[:normal|uniform] (crank.A2, coupler.P, ...); repeatable."),
        pivot_mm: float = typer.Option(None, "--pivot-mm", help="± mm on the base pivots A1 and A4."),
        pivot: list[str] = typer.Option(None, "--pivot", help="A1=T or A4=T[:normal|uniform]; repeatable."),
        length_mm: float = typer.Option(None, "--length-mm", help="± mm on every link length l1, l2, l3, le."),
        length: list[str] = typer.Option(None, "--length", help="l1|l2|l3|le=T[:normal|uniform]; repeatable."),
        distribution: str = typer.Option("normal", "--distribution", help="normal (T = 3 sigma) | uniform (±T)."),
        samples: int = typer.Option(10000, "--samples", help="Monte Carlo samples (100 .. 2e6)."),
        angles: int = typer.Option(401, "--angles", help="Crank angles per sample (extrema are refined)."),
        seed: int = typer.Option(0, "--seed", help="Random seed."),
        target: list[str] = typer.Option(None, "--target", help="KEY=VALUE, KEY<=V, KEY>=V; repeatable (added to the design's targets)."),
        inertia: str = typer.Option(None, "--inertia", help="H11=..,H12=..,H22=..,H33=.. (kg.m^2) for M11 (default: the design's [inertia], else the solids, as check)."),
        out: Path = typer.Option(None, "--out", help="Write tolerance.json and tolerance.png here."),
        json_out: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Monte Carlo of hole, pivot and length tolerances: distributions, yield, sensitivity (no CAD)."""
        from cad.cli import flags
        from cad.cli.cmd_analyze import parse_inertia_option
        from cad.design import bounds, load_design
        from cad.design.targets import parse_cli_target
        from cad.io.outdir import check_out_dir
        from cad.studies.tolerance_study import tolerances_from_flags, write_chart

        for flag, value in (("--hole-mm", hole_mm), ("--pivot-mm", pivot_mm),
                            ("--length-mm", length_mm), ("--seed", seed)):
            flags.number(flag, value)
        flags.out_path("--out", out, folder=True)
        bounds.check_work("tolerance", [("--samples", samples), ("--angles", angles)])  # and product
        tols = tolerances_from_flags(hole_mm, hole or [], pivot_mm, pivot or [], length_mm,
                                     length or [], distribution)
        cli = tuple(parse_cli_target(t) for t in (target or []))
        H = parse_inertia_option(inertia) if inertia is not None else None
        if out is not None:
            check_out_dir(out, str(design))  # only a folder hapticad wrote
        from cad.api import tolerance_run

        res, m, targets = tolerance_run(load_design(design), tols, cli, H, samples, seed, angles)
        if out is not None:  # published whole (the folder's other files kept): an interrupt leaves it as it was
            from cad.export.manifest import write_manifest
            from cad.io.atomic import atomic_dir_update, write_text_atomic

            with atomic_dir_update(out, lambda o: check_out_dir(o, str(design))) as tmp:
                write_chart(res, m, targets, tmp / "tolerance.png")
                write_text_atomic(tmp / "tolerance.json", json.dumps(res, indent=1))
                write_manifest(tmp)
            res["files"] = [str(out / n) for n in (*OWNED, "manifest.json")]
        if json_out:
            print_json(res, indent=1)
        else:
            _print(res)
