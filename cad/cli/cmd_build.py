"""``hapticad build DESIGN [--out DIR] [--formats step,stl,dxf] [--fidelity F] [--phi1-deg X] [--allow-interference] [--prices FILE.csv] [--json]``.

Writes every part (STEP, binary STL, DXF for plates), the assembly STEP, ``bom.csv``,
``order.csv`` (docs/ordering.md), ``report.json``, ``report.md``, ``preview.png`` and ``manifest.json`` into
``exports/<name>/`` (or ``--out``), atomically. An unchanged design is not rebuilt
(build cache, no CAD import).

The device datasheet (:mod:`cad.datasheet`) follows the summary; every figure that misses
its limit (:mod:`cad.datasheet.limits`) is one ``hapticad: warning: datasheet: ...`` line on
stderr (and in ``--json`` ``warnings``). Exit 0, or 1 with ``--strict`` when a limit is missed.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import typer

from cad.cli.app import print_json


def _summary(rep: dict, out: Path, wall_s: float) -> None:
    from rich.console import Console
    from rich.table import Table

    con = Console(stderr=False)
    state = "unchanged (cached)" if rep.get("cached") else "built"
    name = rep.get("name") or rep.get("design") or out.name
    t = Table(title=f"{name} ({rep.get('family', '?')}): {state} -> {out}", show_header=False)
    t.add_column("k")
    t.add_column("v", justify="right")
    am = rep.get("apparent_mass") or {}
    for k in ("H11_kg_m2", "H12_kg_m2", "H22_kg_m2", "H33_kg_m2", "gii", "flotor_mass_g",
              "peak_acceleration_G", "moving_mass_g", "min_clearance_mm", "overlap_volume_mm3",
              "total_mass_g"):
        v = rep.get(k)
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            t.add_row(k, f"{v:.4g}")
    if "M11_min_g" in am:
        t.add_row("M11 (g)", f"{am['M11_min_g']:.2f} .. {am['M11_max_g']:.2f}")
    g = rep.get("gii")
    if isinstance(g, dict) and isinstance(g.get("gii"), (int, float)):
        t.add_row("gii", f"{g['gii']:.4g}")
    em = rep.get("effective_mass_home")
    if isinstance(em, dict):
        for k, v in em.items():
            if isinstance(v, (int, float)) and not isinstance(v, bool):
                t.add_row(f"effective mass at home: {k}", f"{v:.4g}")
    sv = rep.get("wrench_map_singular_values")
    if isinstance(sv, list) and sv:
        t.add_row("wrench map singular values", ", ".join(f"{x:.4g}" for x in sv))
    links = rep.get("links")
    if isinstance(links, dict):
        for k, v in links.items():
            if isinstance(v, dict) and "mass_g" in v:
                t.add_row(f"{k} mass (g)", f"{v['mass_g']:.2f}")
    t.add_row("files", str(len(rep.get("files", []))))
    t.add_row("wall time (s)", f"{wall_s:.2f}")
    con.print(t)
    ds = rep.get("datasheet")
    if ds:
        con.print(datasheet_table(ds, f"{name}: datasheet"))


def datasheet_table(ds: dict, title: str):
    """The datasheet as a rich table: figure, value (min .. max), unit, verdict (red on a miss)."""
    from rich.markup import escape
    from rich.table import Table

    from cad.datasheet import fmt_value, verdict_text

    t = Table(title=title)
    for c in ("figure", "value (min .. max)", "unit", "verdict"):
        t.add_column(c, justify="right" if c.startswith("value") else "left")
    for r in ds["rows"]:
        v = escape(verdict_text(r))  # "[targets]" is text, not markup
        style = {"ok": "green", "miss": "bold red"}.get(r["verdict"])
        mark = " *" if r["unverified"] else ""
        t.add_row(escape(r["figure"]) + mark, fmt_value(r), escape(r["unit"]), f"[{style}]{v}[/]" if style else v)
    t.caption = "* uses unverified data; models and sources: report.md / report.html / --json"
    return t


def datasheet_warnings(rep: dict, strict: bool, notes: bool = True) -> None:
    """One ``warning:`` per missed limit (:func:`cad.design.bounds.warn`); ``strict``: exit 1.
    ``notes``: one ``note:`` line on stderr per limit that the design's [targets] loosens
    (:func:`cad.datasheet.limits.loosened_notes`)."""
    from cad.design import bounds
    from cad.errors import TargetMissed

    ds = rep.get("datasheet") or {}
    missed = ds.get("warnings") or []
    for w in missed:
        bounds.warn(f"datasheet: {w}")
    if notes:
        from cad.datasheet.limits import loosened_notes

        for n in loosened_notes(ds.get("rows") or []):
            print(f"hapticad: note: datasheet: {n}", file=sys.stderr)
    if strict and missed:
        raise TargetMissed(f"{len(missed)} datasheet limit(s) missed (--strict)")


def register(app: typer.Typer) -> None:
    @app.command("build")
    def build_cmd(
        design: Path = typer.Argument(..., help="TOML design file."),
        out: Path = typer.Option(None, "--out", help="Output folder (default exports/<name>/)."),
        formats: str = typer.Option(
            "step,stl,dxf",
            "--formats",
            help="Comma list of step, stl, dxf, mjcf, urdf, glb, 3mf, firmware, drawings (mjcf/urdf also "
            "write the STL meshes; firmware: C kinematics, test vectors, wall sketch in firmware/; "
            "drawings: one sheet per made part).",
        ),
        fidelity: str = typer.Option(
            None, "--fidelity", help="fabrication | inertia | preview (default: [parts].fidelity)."
        ),
        phi1_deg: float = typer.Option(
            None, "--phi1-deg", help="Crank angle of the assembly STEP and preview (deg)."
        ),
        allow_interference: bool = typer.Option(
            False, "--allow-interference", help="Export even if parts collide."
        ),
        json_out: bool = typer.Option(False, "--json", help="Print the report as one JSON object."),
        no_cache: bool = typer.Option(False, "--no-cache", help="Rebuild even if nothing changed."),
        allow_scripts: bool = typer.Option(
            False, "--allow-scripts", help="Run the design's [parts] handle_script (inside its folder)."
        ),
        allow_scripts_anywhere: bool = typer.Option(
            False, "--allow-scripts-anywhere", help="Run handle_script from any path."
        ),
        strict: bool = typer.Option(False, "--strict", help="Exit 1 when a datasheet figure misses its limit."),
        prices: Path = typer.Option(
            None, "--prices", help="Price CSV (columns designation, unit_price[, currency, "
            "source]): unit and line prices in bom.csv and order.csv, and the total."
        ),
    ) -> None:
        """Parts, posed assembly, interference check and fabrication exports of a design."""
        from cad.parts.handle import set_script_policy

        set_script_policy(allow_scripts, allow_scripts_anywhere)
        from cad.cli import flags
        from cad.design import load_design
        from cad.errors import DesignError
        from cad.export import parse_formats
        from cad.pipeline import FIDELITIES, build_design

        t0 = time.perf_counter()
        fmts = parse_formats(formats)
        flags.choice("--fidelity", fidelity, FIDELITIES)
        flags.number("--phi1-deg", phi1_deg)
        flags.out_path("--out", out, folder=True)
        d = load_design(design)
        from cad.export.order import load_prices

        price_table = load_prices(prices) if prices is not None else None
        fid = fidelity or getattr(getattr(d, "parts", None), "fidelity", "fabrication")
        if fid not in FIDELITIES:
            raise DesignError("--fidelity", f"must be one of {', '.join(FIDELITIES)}, got {fid!r}")
        check_buildable = getattr(d, "check_buildable", None)
        if check_buildable is not None:
            check_buildable()  # impossible hardware named before the CAD import
        # warnings: before the first progress line (cad.cli.progress), or at the end
        target = out if out is not None else Path("exports") / d.name
        opts = {"fidelity": fid, "allow_interference": allow_interference, "phi1_deg": phi1_deg,
                "use_cache": not no_cache, "prices": price_table}
        if json_out:
            rep = build_design(d, target, fmts, **opts)
            rep.pop("timings_s", None)
            datasheet_warnings(rep, False)  # in the JSON's warnings list
            print_json(rep, sort_keys=True, default=str)
            datasheet_warnings(rep, strict, notes=False)
            return
        from cad.cli.progress import stages

        with stages("build") as progress:
            rep = build_design(d, target, fmts, progress=progress, **opts)
        _summary(rep, target, time.perf_counter() - t0)
        datasheet_warnings(rep, strict)
