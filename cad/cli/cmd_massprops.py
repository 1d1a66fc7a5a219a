"""``hapticad massprops FILE [--density KG_M3 | --material NAME] [--json]``.

Mass properties of a STEP solid (exact OCCT B-rep integration) or an STL mesh
(trimesh, with a warning on stderr when the mesh is not watertight). Lengths in the
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
from cad.errors import DesignError, HapticadError
from cad.materials import DEFAULT_MATERIAL, get_material


def _resolve_density(density: str | None, material: str | None) -> tuple[float, str | None, bool]:
    """``(density_kg_m3, material name or None, defaulted)`` from the two exclusive flags."""
    if density is not None and material is not None:
        raise DesignError("--density/--material", "give one of them, not both")
    if density is not None:
        from cad.design.bounds import parse_flag

        return parse_flag("--density", density), None, False
    if material is not None:
        mat = get_material(material, "--material")
        return mat.density_kg_m3, mat.name, False
    mat = get_material(DEFAULT_MATERIAL)
    return mat.density_kg_m3, mat.name, True


def compute(
    file: Path, density: str | None = None, material: str | None = None
) -> tuple[dict, list[str]]:
    """Mass properties of ``file`` as the command's JSON dict, plus stderr notes (no printing)."""
    from cad.massprops import io as mpio

    notes: list[str] = []
    kind = mpio.file_kind(file)
    rho, mat_name, defaulted = _resolve_density(density, material)
    if defaulted:
        notes.append(f"note: no --density or --material given; using {mat_name} ({rho:g} kg/m^3)")
    out: dict = {"file": str(file), "format": kind}
    if kind == "step":
        from cad.massprops import occt

        shape = mpio.read_step(file)
        occt.check_valid(shape, Path(file).name)
        vol, com_mm, inertia_mm5 = occt.volume_props_mm(shape)
        props = occt._to_si(vol, com_mm, inertia_mm5, rho)
        out.update(method="occt-exact", watertight=None, n_solids=len(occt.solids(shape)))
    else:
        from cad.massprops import mesh

        v, f = mpio.read_stl(file)
        res = mesh.mesh_arrays_mass_props(v, f, rho, allow_open=True, what=Path(file).name)
        if not res.watertight:
            notes.append(
                f"warning: {Path(file).name} is not watertight (open or non-manifold edges); "
                "volume and inertia are unreliable"
            )
        props, vol = res.props, res.volume_mm3
        out.update(method="trimesh", watertight=res.watertight, n_triangles=res.n_triangles)
    out.update(
        volume_mm3=vol,
        density_kg_m3=rho,
        material=mat_name,
        **props.to_dict(),
        principal_axes=props.principal_axes.tolist(),
    )
    return out, notes


def _g(values, scale: float | None = None, digits: int = 6) -> str:
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
    rows_t = [_g(r, scale) for r in tensor]
    rows = [
        f"file                     {out['file']}  [{out['format']}, {out['method']}]",
        f"density_kg_m3            {_g([out['density_kg_m3']])}{mat}",
        f"volume_mm3               {_g([out['volume_mm3']])}",
        f"mass_kg                  {_g([out['mass_kg']])}",
        "com_mm                   " + _g(out["com_mm"]),
        "inertia_com_kg_m2        " + rows_t[0],
        *("                         " + r for r in rows_t[1:]),
        "principal_moments_kg_m2  " + _g(out["principal_moments_kg_m2"]),
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
        except HapticadError as exc:
            raise fail(str(exc)) from None
        for note in notes:
            print(f"hapticad: {note}", file=sys.stderr)
        if json_out:
            print_json(out)
        else:
            print(_fmt_text(out))
