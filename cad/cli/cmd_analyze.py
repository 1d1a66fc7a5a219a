"""``hapticad analyze DESIGN [--json] [--samples N] [--inertia H11=..,H12=..,H22=..,H33=..] [--report DIR]``."""

from __future__ import annotations

from pathlib import Path

import typer

from cad.cli.app import print_json
from cad.errors import DesignError


def parse_inertia_option(text: str, flag: str = "--inertia"):
    """Parse ``H11=2.97e-5,H12=3.22e-5,H22=1.17e-4,H33=7.09e-5`` (kg.m^2).

    Each value is checked against :mod:`cad.design.bounds` (the ``[inertia]`` bounds), so a
    slip such as g cm^2 typed for kg m^2 is an error naming ``--inertia H11``.
    """
    from cad.design.bounds import FIELDS, check_number
    from cad.dynamics.inertia import InertiaCoefficients

    if not text.strip():
        raise DesignError(flag, "is empty; expected H11=..,H12=..,H22=..,H33=.. (kg m^2)")
    vals: dict[str, float] = {}
    for item in text.split(","):
        key, sep, val = item.partition("=")
        key = key.strip().removesuffix("_kg_m2")
        if not sep or key not in ("H11", "H12", "H22", "H33"):
            raise DesignError(flag, f"expected H11=..,H12=..,H22=..,H33=.. got {item!r}")
        if key in vals:
            raise DesignError(f"{flag} {key}", "given twice")
        try:
            x = float(val)
        except ValueError:
            raise DesignError(f"{flag} {key}", f"value {val!r} is not a number") from None
        vals[key] = check_number(f"{flag} {key}", x, FIELDS[f"inertia.{key}_kg_m2"])
    missing = {"H11", "H12", "H22", "H33"} - set(vals)
    if missing:
        raise DesignError(flag, f"missing {', '.join(sorted(missing))}")
    return InertiaCoefficients(vals["H11"], vals["H12"], vals["H22"], vals["H33"])


def _print_table(res: dict) -> None:
    from rich.console import Console
    from rich.table import Table

    con = Console()
    t = Table(title=f"{res['name']} ({res['family']})", show_lines=False)
    t.add_column("quantity")
    t.add_column("ours", justify="right")
    scale = res.get("paper_scale")
    t.add_column("paper" if scale is None else f"paper x scale {scale:.3g}", justify="right")
    paper = res.get("paper", {})
    for k in ("stroke_mm", "dy_max_mm", "slope_max", "linearity", "torque_mean_mNm",
              "torque_variation", "bbox_mm", "min_transmission_angle_deg"):
        v = res[k]
        s = f"{v[0]:.1f} x {v[1]:.1f}" if k == "bbox_mm" else f"{v:.4g}"
        pk = "dimensions" if k == "bbox_mm" else k
        row = paper.get(pk, {})
        pv = row.get("paper_scaled", row.get("paper", ""))
        t.add_row(k, s, pv if isinstance(pv, str) else f"{pv:.4g}")
    for k in ("l1_mm", "l2_mm", "l3_mm", "l4_mm", "l5_mm", "le_mm", "phi_e_deg",
              "phi1_min_deg", "phi1_max_deg", "branch"):
        t.add_row(k, f"{res[k]:.6g}", "")
    con.print(t)
    if "apparent_mass" in res:
        am = res["apparent_mass"]
        con.print("apparent mass (path frame): " + ", ".join(f"{k} = {v:.3f}" for k, v in am.items()))
    if "stiffness" in res:
        s = res["stiffness"]
        con.print(f"eq (25) stiffness range: {s['K_min_N_per_m']:.0f} .. {s['K_max_N_per_m']:.0f} N/m")
    for p in res["range_check"]["problems"]:
        con.print(f"[yellow]warning:[/] {p}")


def register(app: typer.Typer) -> None:
    @app.command("analyze")
    def analyze_cmd(
        design: Path = typer.Argument(..., help="TOML design file."),
        json_out: bool = typer.Option(False, "--json", help="Print one JSON object."),
        samples: int = typer.Option(None, "--samples", help="Crank samples over the range (>= 3)."),
        inertia: str = typer.Option(None, "--inertia", help="H11=..,H12=..,H22=..,H33=.. in kg.m^2."),
        report: Path = typer.Option(None, "--report", help="Also write a Markdown report with plots here."),
    ) -> None:
        """Kinematic metrics (Tables I/II), range checks and apparent mass; no CAD."""
        from cad.analysis import analyze
        from cad.cli import flags
        from cad.design import load_design
        from cad.design.fourbar import FourBarDesign

        flags.number("--samples", samples)
        flags.out_path("--report", report, folder=True)
        H = parse_inertia_option(inertia) if inertia is not None else None
        d = load_design(design)
        if not isinstance(d, FourBarDesign):
            from cad.cli.families import refusal

            raise DesignError("mechanism.family", refusal("analyze", d.family))
        res = analyze(d, samples=samples, inertia=H)
        if report is not None:
            from cad.export.manifest import write_manifest
            from cad.io.outdir import check_out_dir
            from cad.report.fourbar import write_analysis_report

            check_out_dir(report, str(design), flag="--report")  # only a folder hapticad wrote
            res["report"] = str(write_analysis_report(d, res, report, inertia=H or d.inertia))
            write_manifest(report)
        if json_out:
            print_json(res, indent=1)
        else:
            _print_table(res)
