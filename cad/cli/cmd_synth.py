"""``hapticad synth DESIGN --objective max-stroke|min-torque-variation [...]``: optimized link lengths."""

from __future__ import annotations

import math
from pathlib import Path

import typer

from cad.cli.app import print_json


def synth_flags(objective: str, free: str, dy_tol_mm: float, mu_min_deg: float,
                stroke_mm: float | None) -> str:
    """Every flag that shaped the result, for the written design's provenance line."""
    flags = (f"--objective {objective} --free {free} --dy-tol-mm {dy_tol_mm:g} "
             f"--mu-min-deg {mu_min_deg:g}")
    return flags + (f" --stroke-mm {stroke_mm:g}" if stroke_mm is not None else "")


def _print_table(res: dict, title: str) -> None:
    """The start and the optimized linkage side by side (text output)."""
    from rich.console import Console
    from rich.table import Table

    t = Table(title=title)
    t.add_column("quantity")
    t.add_column("start", justify="right")
    t.add_column("optimized", justify="right")
    s, o = res["start"], res["result"]
    for k in ("l1_mm", "l2_mm", "l3_mm", "l5_mm", "le_mm", "phi_e_deg", "phi1_min_deg", "phi1_max_deg",
              "stroke_mm", "dy_max_mm", "slope_max", "torque_mean_mNm", "torque_variation",
              "min_transmission_angle_deg"):
        t.add_row(k, f"{s[k]:.4g}", f"{o[k]:.4g}")
    Console().print(t)


def register(app: typer.Typer) -> None:
    @app.command("synth")
    def synth_cmd(
        design: Path = typer.Argument(..., help="four-bar TOML design (the start)."),
        objective: str = typer.Option("max-stroke", "--objective", help="max-stroke | min-torque-variation."),
        free: str = typer.Option("range", "--free", help="range (crank range only) | all (ratios, phi_e and range)."),
        dy_tol_mm: float = typer.Option(0.2, "--dy-tol-mm", help="max-stroke: allowed max |y| (mm)."),
        mu_min_deg: float = typer.Option(30.0, "--mu-min-deg", help="Minimum transmission angle (deg)."),
        stroke_mm: float = typer.Option(None, "--stroke-mm", help="Stroke the result must have, under every objective (mm; default: the design's mechanism.stroke_mm, else max-stroke chooses it and min-torque-variation keeps the start's)."),
        out: Path = typer.Option(None, "--out", help="Write the optimized design (family custom) here."),
        json_out: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Choose link lengths and the crank range for a stated objective (see docs/synthesis.md)."""
        import copy
        import time

        from cad.cli import flags
        from cad.cli.families import refusal
        from cad.design import load_design, parse_design
        from cad.design.fourbar import FourBarDesign
        from cad.design.writer import (
            drop_source_targets,
            dropped_targets_note,
            dumps_design,
            rebase_paths,
        )
        from cad.errors import DesignError
        from cad.io.atomic import write_text_atomic
        from cad.io.outdir import check_out_file
        from cad.kinematics.synthesis import FREE_SETS, OBJECTIVES

        flags.choice("--objective", objective, OBJECTIVES)
        flags.choice("--free", free, FREE_SETS)
        flags.number("--dy-tol-mm", dy_tol_mm)
        flags.number("--mu-min-deg", mu_min_deg)
        flags.number("--stroke-mm", stroke_mm)
        flags.out_path("--out", out, folder=False)
        d = load_design(design)
        if not isinstance(d, FourBarDesign):
            raise DesignError("mechanism.family", refusal("synth", d.family))
        replaced = check_out_file(out, design) if out is not None else False
        from cad.api import synth

        syn = synth(d, objective, free, dy_tol_mm, mu_min_deg, stroke_mm)
        mech, held_mm = syn.pop("mechanism"), syn["stroke_mm_held"]
        res = {
            **{k: syn[k] for k in ("objective", "free", "feasible", "evaluations", "stroke_mm_held",
                                 "stroke_upper_bound_mm")},
            "command": f"hapticad synth {design} {synth_flags(objective, free, dy_tol_mm, mu_min_deg, stroke_mm)}",
            "measured": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
            "start": syn["start"], "result": syn["result"],
        }
        if out is not None:
            raw = rebase_paths(copy.deepcopy(d.raw), d.source, out)
            raw["mechanism"] = mech
            raw["name"] = out.stem
            held = f", stroke {held_mm:g} mm" if held_mm is not None else ""
            raw["description"] = f"{objective} synthesis ({free}{held}) from {d.name} ({d.family})"
            dropped = drop_source_targets(raw)
            parse_design(raw, str(out))  # must validate before anything is written
            header = (f"Synthesized by `hapticad synth {design.name} {synth_flags(objective, free, dy_tol_mm, mu_min_deg, stroke_mm)}` "
                      f"from {d.family}" + dropped_targets_note(dropped))
            res["out"] = str(out)
            res["replaced"] = replaced
            text = dumps_design(raw, header)
        if out is not None:  # last: the command's output (cad.io.signals commit point)
            write_text_atomic(out, text, final=True)
        if json_out:
            print_json(res, indent=1)
            return
        _print_table(res, f"synth {objective} ({free}) — feasible: {res['feasible']}")
        if res["stroke_upper_bound_mm"] is not None:
            print(f"no crank window of this linkage is longer than "
                  f"{res['stroke_upper_bound_mm']:.3f} mm (branch and bound over every window)")
        if out is not None:
            print(f"{'replaced' if replaced else 'wrote'} {out}")
        if not math.isfinite(res["result"]["stroke_mm"]):
            raise DesignError("synth", "no feasible result")
