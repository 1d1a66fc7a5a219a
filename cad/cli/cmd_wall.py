"""``hapticad wall DESIGN [--K-N-per-m K] [--B-N-s-per-m B] [--Te-s T] [--encoder-counts-per-rev N] [--model reduced|mujoco] [--build-dir DIR] [--json]``.

Virtual-wall (Z-width) simulation of a four-bar (issue 14, :mod:`cad.sim.wall`): the
largest stable stiffness ``K_max_stable_N_per_m`` for damping B, beside eq (25) and the
Colgate-Schenkel passivity bound; with ``--K-N-per-m`` also whether that wall is stable.
Defaults: Te and the encoder step Delta of the design's ``[stiffness]`` table; without one, the
design's encoder (``parts.encoder`` / ``encoder_counts_per_rev``, else the default encoder), the
datasheet's Coulomb friction estimate, Fv = 0, and the Hoeken prototype's Te and xdot_max
(:func:`cad.sim.device.wall_inputs`; ``inputs`` in the JSON says which).
"""

from __future__ import annotations

from pathlib import Path

import typer

from cad.cli.app import print_json


def register(app: typer.Typer) -> None:
    @app.command("wall")
    def wall_cmd(
        design: Path = typer.Argument(..., help="Four-bar TOML design ([stiffness] table optional)."),
        K: float = typer.Option(None, "--K-N-per-m", help="Wall stiffness to test (N/m)."),
        B: float = typer.Option(0.0, "--B-N-s-per-m", help="Wall damping (N s/m)."),
        Te: float = typer.Option(None, "--Te-s", help="Sampling period (s; default [stiffness] Te_s)."),
        counts: int = typer.Option(None, "--encoder-counts-per-rev",
                                   help="Crank encoder counts per turn (default: [stiffness] Delta)."),
        model: str = typer.Option("reduced", "--model", help="reduced (1-DOF, fast) | mujoco (exported MJCF)."),
        build_dir: Path = typer.Option(None, "--build-dir",
                                       help="a finished `build --formats mjcf` of DESIGN (default: cached build)."),
        json_out: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Largest stable virtual-wall stiffness (sampled data, quantized encoder, friction)."""
        from cad.cli import flags
        from cad.design import load_design
        from cad.sim.wall import MODELS

        flags.choice("--model", model, MODELS)
        flags.number("--K-N-per-m", K)
        flags.number("--B-N-s-per-m", B)
        flags.number("--Te-s", Te)
        flags.number("--encoder-counts-per-rev", counts)
        from cad.api import wall

        res = wall(load_design(design), K, B, Te, counts, model, build_dir)
        if json_out:
            print_json(res, indent=1)
            return
        from rich.console import Console
        from rich.table import Table

        t = Table(title=f"{res['design']}: virtual wall, {model} model, B = {B:g} N s/m")
        t.add_column("quantity")
        t.add_column("value", justify="right")

        def fmt(v):
            return "-" if v is None else f"{v:.4g}"

        for k in ("K_max_stable_N_per_m", "eq25_K_max_N_per_m", "passivity_K_max_N_per_m",
                  "Te_s", "encoder_counts_per_rev", "encoder_resolution_m", "M11_wall_g", "tau_max_Nm"):
            t.add_row(k, fmt(res[k]))
        if res.get("K_max_sampling_error_rel") is not None:
            lo, hi = res["K_band_N_per_m"]
            t.add_row("K_max sampling error", f"+/-{100 * res['K_max_sampling_error_rel']:.1f} %")
            t.add_row("stable and unstable walls interleave", f"{fmt(lo)} .. {fmt(hi)}")
        if "stable" in res:
            t.add_row(f"wall K = {K:g} N/m", ("stable" if res["stable"] else "UNSTABLE")
                      + f" ({res['amplitude_counts']:.2f} counts p-p)")
        t.add_row("wall time (s)", f"{res['wall_s']:.1f}")
        Console().print(t)
        Console().print(res["criterion"])
