"""``hapticad identify DESIGN LOG.csv [--json] [--out DIR] [--build-dir DIR]`` and
``hapticad bench-log DESIGN --out LOG.csv [--seed S] [--perturb KEY=VALUE ...] [--model mujoco|reduced]``.

identify: the built device against its prediction (issue 37, docs/identify.md): a table of
every identified figure beside the datasheet's, with its verdict; ``--out`` writes
``identify.json``, ``identify.md`` and the fit and residual plots. bench-log: the virtual
bench (:mod:`cad.sim.bench`, :mod:`cad.sim.bench_fivebar`), the log and ``<LOG>.true.json``.
Four-bars (one motor) and the 5-bar pantograph (two motors); other families are refused in one line. A bad log: one line naming the problem, exit 2.
"""

from __future__ import annotations

from pathlib import Path

import typer

from cad.cli.app import print_json

OUT_HELP = "Folder for identify.json, identify.md and the fit and residual plots (only a folder hapticad wrote)."


def figures_table(res: dict):
    """The terminal's rich Table of ``res["figures"]``: each figure's key whole (a per-motor key
    such as ``friction_motor_3_mNm`` is never cut to fit an 80-column terminal; the unit
    column folds instead)."""
    from rich.table import Table

    t = Table(title=f"{res['design']}: identified against the prediction")
    width = max((len(r["key"]) for r in res["figures"]), default=6)
    t.add_column("figure", no_wrap=True, min_width=width)
    for col, just in (("measured", "right"), ("1 sigma", "right"), ("unit", "left"),
                      ("predicted", "right"), ("verdict", "left")):
        t.add_column(col, justify=just, overflow="fold")

    def f(v):
        return "-" if v is None else (f"{v:.4g}" if isinstance(v, float) else str(v))

    for r in res["figures"]:
        t.add_row(r["key"], f(r.get("value")), f(r.get("sigma")), r.get("unit", ""), f(r.get("predicted")),
                  r["verdict"])
    return t


def _print(res: dict) -> None:
    from rich.console import Console

    c = Console()
    if res.get("stopped"):
        c.print(f"the routine stopped {res['stopped']}")
    c.print(figures_table(res))
    said: dict[str, list[str]] = {}
    for r in res["figures"]:
        if r.get("explain"):
            said.setdefault(r["explain"], []).append(r["key"])
    from rich.markup import escape

    for text, keys in said.items():
        c.print(escape(f"{', '.join(keys)}: {text}"))  # "[firmware]" is text, not markup
    if "delay_samples" in res:
        c.print(f"delay {res['delay_samples']:.2f} periods, rms residual {res['rms_residual_mNm']:.3g} mN m "
                f"over {res['rows_fitted']} fitted rows (log rows x equations, moving)")


def _owned_or_absent(path: Path, prefix: str, flag: str) -> None:
    """DesignError unless ``path`` is absent or a file hapticad wrote (starts with ``prefix``)."""
    import os

    from cad.errors import DesignError
    from cad.io import guard

    if not os.path.lexists(path):
        return
    if path.is_dir() or path.is_symlink():
        raise DesignError(flag, f"{path} is a folder or a symbolic link; name a file")
    head = guard.read_bytes(path, "log", flag)[: len(prefix)]
    if head != prefix.encode():
        raise DesignError(flag, f"{path} exists and is not a log hapticad wrote; name another file")


def register(app: typer.Typer) -> None:
    @app.command("identify")
    def identify_cmd(
        design: Path = typer.Argument(..., help="TOML design the device was built from (a four-bar or a 5-bar pantograph)."),
        log: Path = typer.Argument(..., help="Log in the identification format (docs/identify.md)."),
        out: Path = typer.Option(None, "--out", help=OUT_HELP),
        build_dir: Path = typer.Option(None, "--build-dir",
                                       help="A finished `build --formats mjcf` of DESIGN (default: the cached build)."),
        json_out: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Identify the built device from a bench log and check it against its prediction."""
        from cad.cli import flags
        from cad.design import load_design

        flags.out_path("--out", out, folder=True)
        d = load_design(design)
        if out is not None:
            from cad.io.outdir import check_out_dir

            check_out_dir(out, str(design))
        from cad.api import identify_device

        res = identify_device(d, log, build_dir, out)
        if out is not None:
            from cad.export.manifest import write_manifest

            write_manifest(out)
        if json_out:
            print_json(res, indent=1)
        else:
            _print(res)

    @app.command("bench-log")
    def bench_log_cmd(
        design: Path = typer.Argument(..., help="TOML design to simulate (a four-bar or a 5-bar pantograph)."),
        out: Path = typer.Option(..., "--out", help="The log to write (CSV); <stem>.true.json beside it."),
        seed: int = typer.Option(0, "--seed", help="Seed of the current noise."),
        perturb: list[str] = typer.Option(None, "--perturb",
                                          help="KEY=VALUE, repeatable: mass, rotor, friction, coulomb, viscous, "
                                               "gravity, kt (factors), encoder (1 or -1), offset_mNm, delay "
                                               "(periods), noise (fraction of the continuous current)."),
        model: str = typer.Option(None, "--model", help="mujoco (the exported MJCF, the default) | "
                                                         "reduced (the 1-DOF crank or the 5-bar's joint-space model, fast)."),
        build_dir: Path = typer.Option(None, "--build-dir",
                                       help="A finished `build --formats mjcf` of DESIGN (default: the cached build)."),
        json_out: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Virtual bench: simulate the built device running the identification routine; write its log."""
        from cad.cli import flags
        from cad.design import load_design
        from cad.sim.bench import parse_perturb

        flags.out_path("--out", out, folder=False)
        if model is not None:
            flags.choice("--model", model, ("mujoco", "reduced"))
        parse_perturb(perturb)
        _owned_or_absent(out, "# hapticad identification log", "--out")
        _owned_or_absent(out.with_name(out.stem + ".true.json"), "{", "--out")
        d = load_design(design)
        from cad.api import bench_log

        res = bench_log(d, out, seed, perturb or (), build_dir, model)
        if json_out:
            print_json(res, indent=1)
            return
        print(f"wrote {res['log']} ({res['model']} model, {res['rows']} rows, {res['status']}) and {res['truth']}")
