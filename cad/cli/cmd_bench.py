"""``hapticad bench [--quick] [--out DIR] [--only TOPIC,...]``: speed against accuracy, charted."""

from __future__ import annotations

from pathlib import Path

import typer

from cad.bench.run import OPT_IN, TOPICS  # noqa: F401 - re-exported


def register(app: typer.Typer) -> None:
    @app.command("bench")
    def bench_cmd(
        quick: bool = typer.Option(False, "--quick", help="Fewer repeats and knobs (all topics: ~4 min of CPU, measured; docs/performance.md)."),
        out: Path = typer.Option(Path("exports/bench"), "--out", help="Output folder for JSON and charts."),
        only: str = typer.Option(None, "--only", help=f"Comma list of topics: {','.join(TOPICS)}."),
    ) -> None:
        """Error-against-time charts for every method with an accuracy knob, and the performance goals."""
        from rich.console import Console
        from rich.table import Table

        from cad.api import run_bench
        from cad.cli import flags

        flags.out_path("--out", out, folder=True)
        con = Console(stderr=True)
        results = run_bench(out, quick, only, echo=lambda t: con.print(f"[bold]bench[/] {t} ..."))
        rows = [(g["goal"], g["measured"], g["target"], g["met"]) for g in results["goals"]]
        total_wall, total_cpu = results["total"]["wall_s"], results["total"]["cpu_s"]
        tab = Table(title="performance goals (medians)")
        for c in ("goal", "measured", "target", "met"):
            tab.add_column(c)
        for g, m, tg, ok in rows:
            tab.add_row(g, m, tg, "-" if ok is None else ("yes" if ok else "NO"))
        Console().print(tab)
        print(f"bench: {total_wall:.0f} s wall, {total_cpu:.0f} s CPU (this process and its children)")
        print(f"wrote {out / 'bench.json'} and charts in {out}")
