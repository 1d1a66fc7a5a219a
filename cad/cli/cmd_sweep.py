"""``hapticad sweep DESIGN --vary KEY=V1,V2,... --vary KEY=LO:HI:N ... --out DIR``: design sweeps on Dask.

See :mod:`cad.studies.sweep.spec` (variants), :mod:`cad.studies.sweep.task` (one variant),
:mod:`cad.studies.sweep.run` (Dask, table, resume) and docs/sweeps.md.
"""

from __future__ import annotations

from pathlib import Path

import typer


def register(app: typer.Typer) -> None:
    @app.command("sweep")
    def sweep_cmd(
        design: Path = typer.Argument(..., help="four-bar TOML design."),
        vary: list[str] = typer.Option(None, "--vary", help="KEY=V1,V2,... or KEY=LO:HI:N (dotted design key); repeatable."),
        samples: int = typer.Option(None, "--samples", help="N Latin-hypercube samples instead of every combination."),
        fidelity: str = typer.Option("inertia", "--fidelity", help="inertia (default) | fabrication (adds the interference sweep)."),
        workers: int = typer.Option(2, "--workers", help="Worker processes of the embedded LocalCluster."),
        scheduler: str = typer.Option(None, "--scheduler", help="tcp://HOST:PORT of an existing Dask scheduler."),
        out: Path = typer.Option(..., "--out", help="Folder of results.parquet/.csv, sweep.json, chart.png (resumes)."),
        target: list[str] = typer.Option(None, "--target", help="KEY=VALUE, KEY<=V, KEY>=V; repeatable (added to the design's targets)."),
        chart: str = typer.Option("torque_variation,M11_max_g", "--chart", help="X,Y columns of the chart."),
        seed: int = typer.Option(0, "--seed", help="Seed of the Latin hypercube."),
        json_out: bool = typer.Option(False, "--json", help="Print the summary as one JSON object."),
    ) -> None:
        """Evaluate many variants of a design on Dask: Parquet/CSV table, chart, resumable."""
        from cad.api import sweep_design
        from cad.cli import flags

        flags.number("--seed", seed)
        flags.out_path("--out", out, folder=True)
        summary = sweep_design(design, vary or (), out, samples=samples, fidelity=fidelity,
                        workers=workers, scheduler=scheduler, targets=target or (), chart=chart,
                        seed=seed)
        if json_out:
            from cad.cli.app import print_json

            print_json(summary, indent=1)
        else:
            print(f"{summary['variants']} variants: {summary['ok']} ok, {summary['missed']} missed, "
                  f"{summary['error']} error, {summary['lost']} lost ({summary['resumed']} resumed) "
                  f"in {summary['wall_s']:.1f} s -> {out / 'results.parquet'}")
