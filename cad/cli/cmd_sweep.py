"""``hapticad sweep DESIGN --vary KEY=V1,V2,... --vary KEY=LO:HI:N ... --out DIR``: design sweeps on Dask.

See :mod:`cad.sweep.spec` (variants), :mod:`cad.sweep.task` (one variant),
:mod:`cad.sweep.run` (Dask, table, resume) and docs/sweeps.md.
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
        from cad.design.fields import load_toml
        from cad.design.targets import parse_cli_target
        from cad.errors import DesignError
        from cad.sweep.run import SweepSpec, run_sweep
        from cad.sweep.spec import parse_vary
        from cad.sweep.table import check_folder
        from cad.sweep.task import VALUE_KEYS

        if not vary:
            raise DesignError("--vary", "give at least one --vary KEY=V1,V2,... or KEY=LO:HI:N")
        varies = tuple(parse_vary(v) for v in vary)
        from cad.cli import flags
        from cad.design.bounds import FIELDS, check_number

        for v in varies:  # every value of a varied key within its bounds (cad/design/bounds.py)
            if v.key in FIELDS:
                for x in v.grid():
                    if not isinstance(x, (int, float)) or isinstance(x, bool):
                        raise DesignError(f"--vary {v.key}", f"must be a number, got {x!r}")
                    check_number(f"--vary {v.key}", x, FIELDS[v.key])
        flags.number("--seed", seed)
        keys = [v.key for v in varies]
        if len(set(keys)) != len(keys):
            raise DesignError("--vary", "a key is varied twice")
        if samples is not None and not 1 <= samples <= 100_000:
            raise DesignError("--samples", f"must be in [1, 100000], got {samples}")
        if fidelity not in ("inertia", "fabrication"):
            raise DesignError("--fidelity", f"must be inertia or fabrication, got {fidelity!r}")
        if scheduler is None and not 1 <= workers <= 256:
            raise DesignError("--workers", f"must be in [1, 256], got {workers}")
        if scheduler is not None and not scheduler.startswith(("tcp://", "tls://", "inproc://", "ucx://")):
            raise DesignError("--scheduler", f"expected tcp://HOST:PORT, got {scheduler!r}")
        xy = tuple(c.strip() for c in chart.split(","))
        if len(xy) != 2 or not all(c in VALUE_KEYS for c in xy):
            raise DesignError("--chart", f"expected X,Y with X and Y in {', '.join(VALUE_KEYS)}, got {chart!r}")
        cli = tuple(parse_cli_target(t) for t in (target or []))
        flags.out_path("--out", out, folder=True)
        raw = load_toml(design)
        from cad.cli.families import COMMAND_FAMILIES, refusal
        from cad.design import family_of, parse_design

        fam = family_of(raw)
        if fam not in COMMAND_FAMILIES["sweep"]:
            raise DesignError("mechanism.family", refusal("sweep", fam))
        if "handle_script" in (raw.get("parts") or {}) or any(v.key == "parts.handle_script"
                                                                for v in varies):
            raise DesignError("parts.handle_script", "sweep never runs design scripts (its "
                              "workers would run them unseen); sweep a design without one")
        parse_design(raw, str(design))  # the base design as every command loads it (load_design)
        _check_keys(raw, design, varies)
        # only a folder hapticad wrote (docs/reliability.md "Output folders"); a dead run's temporary
        # files removed and its interrupted table write completed first (cad.sweep.table)
        check_folder(out, str(design))
        spec = SweepSpec(design=design.resolve(), raw=raw, varies=varies, samples=samples, seed=seed,
                         fidelity=fidelity, cli_targets=cli, chart=xy,
                         targets_text=";".join(sorted(t or "" for t in (target or []))))
        summary = run_sweep(spec, out, workers, scheduler)
        if json_out:
            from cad.cli.app import print_json

            print_json(summary, indent=1)
        else:
            print(f"{summary['variants']} variants: {summary['ok']} ok, {summary['missed']} missed, "
                  f"{summary['error']} error, {summary['lost']} lost ({summary['resumed']} resumed) "
                  f"in {summary['wall_s']:.1f} s -> {out / 'results.parquet'}")


def _check_keys(raw: dict, design: Path, varies) -> None:
    """Exit 2 on a --vary key the design schema does not know (a typo would fail every variant)."""
    from cad.design import parse_design
    from cad.errors import DesignError
    from cad.sweep.spec import apply

    for v in varies:
        first = v.grid()[0]
        try:
            parse_design(apply(raw, {v.key: first}), str(design))
        except DesignError as exc:
            named = exc.field == v.key or v.key.startswith(exc.field + ".")
            if named and ("unknown key" in exc.reason or "not a table" in exc.reason):
                raise DesignError(f"--vary {v.key}", exc.reason) from None
        except Exception:  # noqa: S110 - other failures are a variant's business (a row with its error)
            pass
