"""``hapticad check DESIGN [--target KEY=VALUE ...] [--fidelity inertia|fabrication] [--json]``.

Computes H11..H33, the apparent mass and the link masses from the solids (and the
kinematic metrics), compares them with the design's ``[targets]`` (CLI targets
replace design targets of the same key) and exits 0 when all are within
tolerance, 1 when any is not, 2 on bad input.
"""

from __future__ import annotations

import json
from pathlib import Path

import typer


def compute_values(design, fidelity: str, need_clearance: bool) -> tuple[dict, dict]:
    """(flat values for targets, inertia model report) of a four-bar design."""
    from cad.build.inertia import inertia_model
    from cad.checks import values_from_report
    from cad.kinematics.metrics import compute_metrics

    model = inertia_model(design, fidelity=fidelity)
    m = compute_metrics(design.linkage, design.phi1_min_rad, design.phi1_max_rad, force_N=design.force_N)
    report = {**model, **m.as_dict()}
    if need_clearance:
        import tempfile

        from cad.build import build_design

        with tempfile.TemporaryDirectory() as tmp:
            rep = build_design(design, Path(tmp) / "b", set(), fidelity=fidelity, allow_interference=True,
                               use_cache=False)
        report["min_clearance_mm"] = rep["min_clearance_mm"]
        report["overlap_volume_mm3"] = rep["overlap_volume_mm3"]
    return values_from_report(report), report


def register(app: typer.Typer) -> None:
    @app.command("check")
    def check_cmd(
        design: Path = typer.Argument(..., help="four-bar TOML design"),
        target: list[str] = typer.Option(None, "--target", help="KEY=VALUE (default tolerance), KEY<=V, KEY>=V; repeatable"),
        fidelity: str = typer.Option("inertia", "--fidelity", help="inertia (default) | fabrication"),
        json_out: bool = typer.Option(False, "--json", help="print one JSON object"),
        allow_scripts: bool = typer.Option(
            False, "--allow-scripts", help="run the design's [parts] handle_script (inside its folder)"
        ),
        allow_scripts_anywhere: bool = typer.Option(
            False, "--allow-scripts-anywhere", help="run handle_script from any path"
        ),
    ) -> None:
        """Inertia and apparent mass from the solids against the design's targets (exit 0 / 1 / 2)."""
        from cad.parts.handle import set_script_policy

        set_script_policy(allow_scripts, allow_scripts_anywhere)
        from cad.checks import evaluate, merge_targets
        from cad.design import load_design
        from cad.design.fourbar import FourBarDesign
        from cad.design.targets import parse_cli_target
        from cad.errors import DesignError, TargetMissed

        cli = tuple(parse_cli_target(t) for t in (target or []))
        if fidelity not in ("inertia", "fabrication"):
            raise DesignError("--fidelity", f"must be inertia or fabrication, got {fidelity!r}")
        d = load_design(design)
        if not isinstance(d, FourBarDesign):
            raise DesignError("mechanism.family", "check works on four-bar designs")
        targets = merge_targets(d.targets, cli)
        if not targets:
            raise DesignError("targets", "no targets: add a [targets] table or --target KEY=VALUE")
        need_clear = any(t.key == "min_clearance_mm" for t in targets)
        values, report = compute_values(d, fidelity, need_clear)
        rows = evaluate(targets, values)
        missed = [r for r in rows if not r.ok]
        if json_out:
            print(json.dumps({"name": d.name, "ok": not missed, "fidelity": fidelity,
                              "rows": [r.as_dict() for r in rows],
                              "computed": values, "budget": report["budget"]}, indent=1))
        else:
            from rich.console import Console
            from rich.table import Table

            t = Table(title=f"{d.name}: computed from the solids ({fidelity}) against targets")
            for c in ("target key", "computed", "target", "gap", "ok"):
                t.add_column(c, justify="right" if c != "target key" else "left")
            for r in rows:
                comp = "—" if r.computed is None else f"{r.computed:.4g}"
                gap = "—" if r.gap_rel is None else f"{100 * r.gap_rel:+.1f}%"
                t.add_row(r.key, comp, r.target, gap, "[green]yes[/]" if r.ok else "[red]NO[/]")
            Console().print(t)
        if missed:
            raise TargetMissed(f"{len(missed)} of {len(rows)} targets missed: "
                               + ", ".join(r.key for r in missed))
