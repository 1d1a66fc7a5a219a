"""``hapticad gii DESIGN [--json]``: global isotropy index of a pantograph-family design.

Isotropy paper eq (5) over the design's ``[workspace]`` grid (boundary
included). An unreachable or singular sample gives GII = 0 and is named.
"""

from __future__ import annotations

from pathlib import Path

import typer

from cad.cli.app import print_json

PANTOGRAPH_FAMILIES = ("pantograph", "twin-pantograph", "haptic-pen")


def _point(units: tuple[str, ...], p) -> dict[str, float]:
    return {u: round(float(v), 9) for u, v in zip(units, p, strict=True)}


def gii_report(design) -> dict:
    """JSON-able GII report of a loaded pantograph-family design."""
    import time

    t0 = time.perf_counter()
    r = design.gii()
    dt = time.perf_counter() - t0
    units = design.point_units()
    npos = sum(u.endswith("_mm") for u in units)
    return {
        "design": design.name,
        "family": design.family,
        "gii": r.gii,
        "sigma_min": r.sigma_min,
        "sigma_max": r.sigma_max,
        "sigma_min_at_mm": [float(v) for v in r.sigma_min_at[:npos]],
        "sigma_max_at_mm": [float(v) for v in r.sigma_max_at[:npos]],
        "sigma_min_at": _point(units, r.sigma_min_at),
        "sigma_max_at": _point(units, r.sigma_max_at),
        "n_points": r.n_points,
        "jacobian_evaluations": r.jacobian_evaluations,
        "failure": r.failure,
        "failed_at": None if r.failed_at is None else _point(units, r.failed_at),
        "n_failed": r.n_failed,
        "wall_time_s": dt,
    }


def load_pantograph_design(path: Path):
    """Load a design and check it belongs to a pantograph family."""
    from cad.design import load_design
    from cad.errors import DesignError

    design = load_design(path)
    if getattr(design, "family", None) not in PANTOGRAPH_FAMILIES:
        from cad.cli.families import refusal

        raise DesignError("mechanism.family", refusal("gii", design.family))
    return design


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
            f"{rep['design']} ({rep['family']}): GII = {rep['gii']:.6f} over {rep['n_points']} samples"
        )
        print(f"  sigma_min = {rep['sigma_min']:.6g} at {rep['sigma_min_at']}")
        print(f"  sigma_max = {rep['sigma_max']:.6g} at {rep['sigma_max_at']}")
        if rep["failure"]:
            print(f"  GII = 0: {rep['failure']} at {rep['failed_at']} ({rep['n_failed']} samples)")
