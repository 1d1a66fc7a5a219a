"""``hapticad swap DESIGN --to FAMILY [--out NEW.toml] [--json] [--build]``.

Keeps the joint hardware (the whole ``[parts]`` table: bearings, pins, spacers, motor
mount, base interface, handle) and produces the bar set of another straight-line family
(hoeken, roberts, chebyshev, chebyshev-v) scaled to the same stroke ("provided a
convenient design of the revolute joints, the different straight line mechanisms can
be obtained by fabricating the adequate set of bars", Hoeken paper §III.A). Prints the
old and new metrics side by side and writes the new design atomically (default: beside
DESIGN as ``<stem>_<family>.toml``); never over DESIGN itself, and it says ``replaced``
when the file existed (:func:`cad.io.outdir.check_out_file`). The build's pre-CAD layout
check runs on the new bar set before anything is written (:func:`replan`): a copied
``parts.layer_order`` that is not clear there is dropped (with a warning), and a bar set
no layer order clears is refused (exit 2, the build's one-line error, nothing written).
``--build`` also builds it (and fails if anything collides).
"""

from __future__ import annotations

from pathlib import Path

import typer

from cad.cli.app import print_json
from cad.families.fourbar.swap import (  # noqa: F401 - re-exported
    DROPPED_SECTIONS,
    SWAP_FAMILIES,
    metric_rows,
    replan,
    stroke_of,
    swap_raw,
)


def register(app: typer.Typer) -> None:
    @app.command("swap")
    def swap_cmd(
        design: Path = typer.Argument(..., help="TOML design file (four-bar)."),
        to: str = typer.Option(..., "--to", help="hoeken | roberts | chebyshev | chebyshev-v."),
        out: Path = typer.Option(
            None, "--out", help="New design file (default <stem>_<family>.toml beside DESIGN)."
        ),
        json_out: bool = typer.Option(False, "--json", help="Print one JSON object."),
        build: bool = typer.Option(
            False, "--build", help="Also build the new design into exports/<name>/ (name: the --out file stem)."
        ),
    ) -> None:
        """Same joint hardware, another straight-line bar set; old vs new metrics."""
        import tomli_w

        from cad.cli import flags
        from cad.design import load_design
        from cad.design.fourbar import FourBarDesign
        from cad.design.writer import dropped_targets_note
        from cad.errors import DesignError
        from cad.io.atomic import write_text_atomic
        from cad.io.outdir import check_out_file

        flags.choice("--to", to, SWAP_FAMILIES)
        flags.out_path("--out", out, folder=False)
        d = load_design(design)
        if not isinstance(d, FourBarDesign):
            from cad.cli.families import refusal

            raise DesignError("mechanism.family", refusal("swap", d.family))
        target = (
            out
            if out is not None
            else design.with_name(f"{design.stem}_{to.replace('-', '_')}.toml")
        )
        replaced = check_out_file(target, design)
        from cad.api import swap

        sw = swap(d, to, target, out.stem if out is not None else None)
        new, raw, plan = sw["design"], sw["raw"], sw["layers"]
        text = tomli_w.dumps(raw)
        header = f"written by `hapticad swap {design.name} --to {to}`" + dropped_targets_note(sw["dropped"])
        old_m, new_m = sw["old"], sw["new"]
        result = {"old": old_m, "new": new_m, "out": str(target), "replaced": replaced,
                  "layers": plan}
        if build:
            from cad.export import parse_formats
            from cad.pipeline import build_design

            build_dir = Path("exports") / new.name
            rep = build_design(new, build_dir, parse_formats(None))
            result["build"] = {
                "min_clearance_mm": rep["min_clearance_mm"],
                "overlap_volume_mm3": rep["overlap_volume_mm3"],
                "out": str(build_dir),
            }
        # the design file last: it is the command's output (cad.io.signals commit point)
        write_text_atomic(
            target, "".join(f"# {ln}\n" for ln in header.splitlines()) + text, final=True
        )
        if json_out:
            print_json(result, sort_keys=True, default=float)
            return
        _print_swap(d, new, result, target, replaced)


def _print_swap(d, new, result: dict, target: Path, replaced: bool) -> None:
    """The old and new metrics side by side, the layer order and what was written (text)."""
    from rich.console import Console
    from rich.table import Table

    t = Table(title=f"swap {d.name} ({d.family}) -> {new.name} ({new.family}); hardware kept")
    t.add_column("quantity")
    t.add_column(d.family, justify="right")
    t.add_column(new.family, justify="right")
    for k, v in result["old"].items():
        nv = result["new"].get(k)
        if isinstance(v, (list, tuple)):
            t.add_row(k, " x ".join(f"{x:.1f}" for x in v), " x ".join(f"{x:.1f}" for x in nv))
        elif isinstance(v, str):
            t.add_row(k, v, str(nv))
        else:
            t.add_row(k, f"{v:.5g}", f"{nv:.5g}")
    con = Console()
    con.print(t)
    con.print(
        f"layers {', '.join(result['layers']['order'])} (bottom to top), planar clearance "
        f"{result['layers']['min_planar_clearance_mm']:.2f} mm; {'replaced' if replaced else 'wrote'} {target}"
    )
    if result["layers"]["conflicts"]:
        con.print(f"[yellow]warning:[/] layer conflicts: {'; '.join(result['layers']['conflicts'])}")
    if "build" in result:
        con.print(
            f"built {result['build']['out']}: min clearance {result['build']['min_clearance_mm']:.3f} mm"
        )
