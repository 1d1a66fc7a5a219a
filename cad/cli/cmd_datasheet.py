"""``hapticad datasheet DESIGN [--fidelity inertia|fabrication|preview] [--strict] [--json]``.

The device datasheet (:mod:`cad.datasheet`): every figure with its value over the workspace,
unit, model or source and verdict against its limit (:mod:`cad.datasheet.limits`); every
missed limit is one ``warning:`` line. Computed from a build without exports and kept in the
derived cache: an unchanged design and code print it without importing a CAD library.
Exit 0, or 1 with ``--strict`` when a limit is missed; 2 on bad input.
"""

from __future__ import annotations

from pathlib import Path

import typer

from cad.cli.app import print_json


def register(app: typer.Typer) -> None:
    @app.command("datasheet")
    def datasheet_cmd(
        design: Path = typer.Argument(..., help="TOML design file (any family that builds)."),
        fidelity: str = typer.Option("inertia", "--fidelity", help="inertia (default) | fabrication | preview."),
        strict: bool = typer.Option(False, "--strict", help="Exit 1 when a figure misses its limit."),
        json_out: bool = typer.Option(False, "--json", help="Print one JSON object."),
        allow_scripts: bool = typer.Option(
            False, "--allow-scripts", help="Run the design's [parts] handle_script (inside its folder)."
        ),
    ) -> None:
        """The device datasheet: force, resolution, friction, masses, structure, stiffness; verdicts."""
        from cad.cli import flags
        from cad.cli.cmd_build import datasheet_table, datasheet_warnings
        from cad.design import load_design
        from cad.parts.handle import set_script_policy
        from cad.pipeline import FIDELITIES

        set_script_policy(allow_scripts, False)
        flags.choice("--fidelity", fidelity, FIDELITIES)
        from cad.api import device_datasheet

        rep = device_datasheet(load_design(design), fidelity)
        ds = rep["datasheet"]
        if json_out:
            datasheet_warnings(rep, False)  # in the JSON's warnings list
            print_json(rep, indent=1)
        else:
            from rich.console import Console

            Console().print(datasheet_table(ds, f"{rep['name']} ({rep['family']}): datasheet ({fidelity})"))
        datasheet_warnings(rep, strict, notes=not json_out)
