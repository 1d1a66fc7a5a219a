"""``hapticad massprops FILE [--density KG_M3 | --material NAME] [--json]``.

Mass properties of a STEP solid (exact OCCT B-rep integration) or an STL mesh
(trimesh, with a warning on stderr when the mesh is not watertight; every closed shell
checked on its own, :mod:`cad.massprops.shells`; a warning when the part is implausibly
small or large for mm, :func:`cad.massprops.mesh.unit_slip_note`). Lengths in the
file are taken as millimetres. Output (JSON with ``--json``, exactly one object):
``volume_mm3``, ``mass_kg``, ``com_mm`` (file frame), ``inertia_com_kg_m2`` (3x3 about
the COM, file axes, positive-definite convention), ``principal_moments_kg_m2``
(ascending), plus ``principal_axes`` (columns), ``density_kg_m3``, ``material``,
``method``, ``watertight``, ``file``, ``format``. Nothing is rounded.
"""

from __future__ import annotations

import sys
from pathlib import Path

import typer

from cad.cli.app import print_json
from cad.data.materials import DEFAULT_MATERIAL
from cad.errors import HapticadError
from cad.pipeline.file_props import compute, file_materials  # noqa: F401 - re-exported


def format_g(values, scale: float | None = None, digits: int = 6) -> str:
    """``digits`` significant digits; entries below 1e-9 of ``scale`` (default: the group's
    largest) print as 0 (round-off of the integration, not data). ``--json`` keeps all digits."""
    vals = [float(v) for v in values]
    if scale is None:
        scale = max((abs(v) for v in vals), default=0.0)
    return "  ".join("0" if abs(v) <= 1e-9 * scale else f"{v:.{digits}g}" for v in vals)


def _fmt_text(out: dict) -> str:
    mat = f" ({out['material']})" if out["material"] else ""
    tensor = out["inertia_com_kg_m2"]
    scale = max(abs(float(x)) for r in tensor for x in r)
    rows_t = [format_g(r, scale) for r in tensor]
    rows = [
        f"file                     {out['file']}  [{out['format']}, {out['method']}]",
        f"density_kg_m3            {format_g([out['density_kg_m3']])}{mat}",
        f"volume_mm3               {format_g([out['volume_mm3']])}",
        f"mass_kg                  {format_g([out['mass_kg']])}",
        "com_mm                   " + format_g(out["com_mm"]),
        "inertia_com_kg_m2        " + rows_t[0],
        *("                         " + r for r in rows_t[1:]),
        "principal_moments_kg_m2  " + format_g(out["principal_moments_kg_m2"]),
    ]
    if out["watertight"] is not None:
        rows.append(f"watertight               {out['watertight']}")
    return "\n".join(rows)


def register(app: typer.Typer) -> None:
    @app.command("massprops")
    def massprops(
        file: Path = typer.Argument(..., help="STEP (.step/.stp) or STL file, lengths in mm."),
        density: str = typer.Option(None, "--density", help="Density in kg/m^3."),
        material: str = typer.Option(
            None, "--material", help=f"Material name from the table (default {DEFAULT_MATERIAL})."
        ),
        json_out: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Mass, centre of mass and inertia tensor of a STEP solid or STL mesh."""
        from cad.cli.app import fail

        try:
            out, notes = compute(file, density, material)
        except HapticadError as exc:  # every refusal names the file it is about
            msg = str(exc)
            raise fail(msg if str(file) in msg or file.name in msg else f"{file}: {msg}") from None
        from cad.design import bounds

        for note in notes:
            print(f"hapticad: {note}", file=sys.stderr)
        bounds.flush()  # data warnings (also in --json); printed here for in-process callers too
        if json_out:
            print_json(out)
        else:
            print(_fmt_text(out))
