"""``hapticad render DESIGN... [--out DIR] [--fidelity F] [--json]``: pictures of devices.

Builds each design into a temporary folder (nothing under ``exports/`` is touched) and
copies the build's ``render.png`` (shaded still of the assembly) and ``animation.gif``
(the mechanism over its stroke) to ``DIR/<name>.png`` and ``DIR/<name>.gif``
(default ``docs/devices``). Every design is loaded and checked before anything is built:
a design whose family has no render yet is refused with exit 2, nothing written; every
design is built before any picture is written, so a build that fails writes none. ``DIR``
is shared with other files: an existing ``<name>.png`` / ``.gif`` is replaced only when
``DIR/manifest.json`` says hapticad wrote it unchanged (:mod:`cad.io.outdir`), else exit 2.
The pictures and the manifest are published at once, the folder whole
(:func:`cad.io.atomic.atomic_dir_update`): an interrupt leaves it as it was.
"""

from __future__ import annotations

from pathlib import Path

import typer

from cad.pipeline.render import RENDER_FILES, render_designs  # noqa: F401 - re-exported


def register(app: typer.Typer) -> None:
    @app.command("render")
    def render_cmd(
        designs: list[Path] = typer.Argument(..., help="TOML design files."),
        out: Path = typer.Option(Path("docs/devices"), "--out", help="Folder of the pictures."),
        fidelity: str = typer.Option(
            None, "--fidelity", help="fabrication | inertia | preview (default: the design's)."
        ),
        json_out: bool = typer.Option(False, "--json", help="Print the written files as JSON."),
    ) -> None:
        """Shaded picture and stroke GIF of each design, from its build."""
        from cad.cli import flags
        from cad.cli.app import print_json
        from cad.pipeline import FIDELITIES

        flags.choice("--fidelity", fidelity, FIDELITIES)
        flags.out_path("--out", out, folder=True)
        from cad.api import render

        rows = render(designs, out, fidelity)
        if json_out:
            print_json({"rendered": rows}, sort_keys=True)
            return
        for r in rows:
            print(f"{r['design']}: wrote {r['png']}, {r['gif']}")
