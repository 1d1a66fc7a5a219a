"""``hapticad gii DESIGN [--json]``: global isotropy index of a pantograph-family design.

Isotropy paper eq (5) over the design's ``[workspace]`` grid (boundary
included). An unreachable or singular sample gives GII = 0 and is named.
"""

from __future__ import annotations

from pathlib import Path

import typer

from cad.cli.app import print_json
from cad.isotropy.report import PANTOGRAPH_FAMILIES, gii_report  # noqa: F401 - re-exported


def load_pantograph_design(path: Path):
    """Load a design and check it belongs to a pantograph family."""
    from cad.data.families import refusal
    from cad.design import load_design
    from cad.errors import DesignError

    design = load_design(path)
    if getattr(design, "family", None) not in PANTOGRAPH_FAMILIES:
        raise DesignError("mechanism.family", refusal("gii", design.family))
    return design


def workspace_text(rep: dict) -> str:
    """``"100 x 100 x 100 mm workspace"``, a cylinder's ``"d100 x 80 mm cylinder workspace"``
    (report ``workspace_shape``; its ``workspace_size_mm`` is then [D, D, H])."""
    size = rep["workspace_size_mm"]
    if rep.get("workspace_shape") == "cylinder":
        return f"d{size[0]:g} x {size[2]:g} mm cylinder workspace"
    return f"{' x '.join(f'{v:g}' for v in size)} mm workspace"


def point_text(at: dict | None) -> str:
    """A workspace point for a reader: ``{"x_mm": 0.0, "y_mm": 150.0}`` ->
    ``"x = 0 mm, y = 150 mm"`` (a key with a unit suffix ``_<unit>`` prints the unit after
    the value)."""
    if not isinstance(at, dict):
        return str(at)
    parts = []
    for k, v in at.items():
        name, _, unit = k.partition("_")
        val = f"{v:g}" if isinstance(v, (int, float)) else str(v)
        parts.append(f"{name} = {val} {unit}" if unit else f"{k} = {val}")
    return ", ".join(parts)


def register(app: typer.Typer) -> None:
    @app.command("gii")
    def gii_cmd(
        design: Path = typer.Argument(
            ..., help="Design TOML (family pantograph, twin-pantograph or haptic-pen)."
        ),
        json_out: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Global isotropy index (isotropy paper eq 5) over the design's workspace grid."""
        rep = gii_report(load_pantograph_design(design))
        if json_out:
            print_json(rep)
            return
        print(
            f"{rep['design']} ({rep['family']}): GII = {rep['gii']:.6f} over {rep['n_points']} samples "
            f"of a {workspace_text(rep)}"
        )
        print(f"  sigma_min = {rep['sigma_min']:.6g} at {point_text(rep['sigma_min_at'])}")
        print(f"  sigma_max = {rep['sigma_max']:.6g} at {point_text(rep['sigma_max_at'])}")
        if "workspace_volumes" in rep:
            v = rep["workspace_volumes"]
            print(f"  reachable workspace below the base {v['reachable_cm3']:.0f} cm3, well conditioned "
                  f"(sigma_min / sigma_max >= {v['threshold']:g}) {v['well_conditioned_cm3']:.0f} cm3 "
                  f"({v['step_mm']:g} mm cells); worst over the design's workspace "
                  f"{rep['workspace_inverse_condition_min']:.3f}")
        if rep["failure"]:
            at = point_text(rep["failed_at"])
            print(f"  GII = 0: {rep['failure']} at {at} ({rep['n_failed']} samples)")
