"""``hapticad check DESIGN [--target KEY=VALUE ...] [--fidelity inertia|fabrication] [--json]``.

Computes H11..H33, the apparent mass and the link masses from the solids (and the
kinematic metrics), compares them with the design's ``[targets]`` (CLI targets
replace design targets of the same key) and exits 0 when all are within
tolerance, 1 when any is not, 2 on bad input. A design without targets is checked against
the datasheet's default limits (:mod:`cad.datasheet.limits`: continuous force, first mode,
stress, clearance), exit 1 on a miss.
"""

from __future__ import annotations

from pathlib import Path

import typer

from cad.cli.app import print_json


def gap_text(row: dict) -> str:
    """The ``gap`` cell of one ``check`` row (a :meth:`CheckRow.as_dict`): ``"+8.1%"`` from a
    ``value ± tol`` target; for a met ``min``/``max`` limit the room left in the key's unit
    (``"met, 12.5 to spare"``), not a gap of 0 %; ``"—"`` without a computed value."""
    if row["gap_rel"] is None:
        return "—"
    data = row.get("target") or {}
    if row["ok"] and "value" not in data and row.get("margin") is not None:
        return f"met, {row['margin']:.3g} to spare"
    return f"{100 * row['gap_rel']:+.1f}%"


def register(app: typer.Typer) -> None:
    @app.command("check")
    def check_cmd(
        design: Path = typer.Argument(..., help="Four-bar or pantograph-family TOML design."),
        target: list[str] = typer.Option(None, "--target", help="KEY=VALUE (default tolerance), KEY<=V, KEY>=V; repeatable."),
        fidelity: str = typer.Option("inertia", "--fidelity", help="inertia (default) | fabrication."),
        json_out: bool = typer.Option(False, "--json", help="Print one JSON object."),
        allow_scripts: bool = typer.Option(
            False, "--allow-scripts", help="Run the design's [parts] handle_script (inside its folder)."
        ),
        allow_scripts_anywhere: bool = typer.Option(
            False, "--allow-scripts-anywhere", help="Run handle_script from any path."
        ),
    ) -> None:
        """Inertia and apparent mass from the solids against the design's targets (exit 0 / 1 / 2)."""
        from cad.parts.handle import set_script_policy

        set_script_policy(allow_scripts, allow_scripts_anywhere)
        from cad.api import check
        from cad.cli import flags
        from cad.design import load_design
        from cad.errors import TargetMissed

        flags.choice("--fidelity", fidelity, ("inertia", "fabrication"))
        d = load_design(design)
        if hasattr(d, "check_buildable"):
            d.check_buildable()
        res = check(d, tuple(target or ()), fidelity, merge=True)
        missed = [r for r in res["rows"] if not r["ok"]]
        if json_out:
            print_json(res, indent=1)
        else:
            from rich.console import Console
            from rich.table import Table

            against = "default limits" if res.get("checked") else f"targets ({res['targets_source']})"
            t = Table(title=f"{res['name']}: computed ({fidelity}) against {against}")
            for c in ("target key", "computed", "target", "gap", "ok"):
                t.add_column(c, justify="right" if c != "target key" else "left")
            for r in res["rows"]:
                comp = "—" if r["computed"] is None else f"{r['computed']:.4g}"
                gap = gap_text(r)
                t.add_row(r["key"], comp, r["target_text"], gap,
                          "[green]yes[/]" if r["ok"] else "[red]NO[/]")
            Console().print(t)
        import sys

        for w in res.get("limit_warnings", ()):
            print(f"hapticad: warning: datasheet: {w}", file=sys.stderr)
        if missed:
            raise TargetMissed(f"{len(missed)} of {len(res['rows'])} targets missed: "
                               + ", ".join(r["key"] for r in missed))
