"""Elastic properties of the bar materials (pure data, no CAD import).

E (Young's modulus), nu (Poisson's ratio) and a working strength (yield for metals,
the tensile strength for composites and printed plastics, which fail without
yielding) for every key of :data:`cad.data.materials.MATERIALS` a moving part may use.
Sources inline; printed parts are quoted at 100 % infill, printed flat (XY).
"""

from __future__ import annotations

from dataclasses import dataclass

from cad.data.materials import get_material
from cad.errors import DesignError
from cad.printing import filament, printed_bar_modulus_GPa


@dataclass(frozen=True)
class Elastic:
    """E_GPa Young's modulus, nu Poisson's ratio, strength_MPa yield (metals) or
    tensile strength (composites, plastics), source."""

    E_GPa: float
    nu: float
    strength_MPa: float
    source: str

    @property
    def E_Pa(self) -> float:
        return self.E_GPa * 1e9

    @property
    def G_Pa(self) -> float:
        return self.E_Pa / (2.0 * (1.0 + self.nu))


ELASTIC: dict[str, Elastic] = {
    "aluminium-6061": Elastic(68.9, 0.33, 276.0, "6061-T6, ASM Handbook Vol. 2 / MatWeb"),
    "aluminium-7075": Elastic(71.7, 0.33, 503.0, "7075-T6, ASM Handbook Vol. 2 / MatWeb"),
    "steel-1018": Elastic(205.0, 0.29, 370.0, "AISI 1018 cold drawn, MatWeb"),
    "stainless-304": Elastic(193.0, 0.29, 215.0, "AISI 304 annealed, MatWeb"),
    "brass-360": Elastic(97.0, 0.31, 310.0, "C36000 half hard, Copper Development Association"),
    "titanium-6al4v": Elastic(113.8, 0.34, 880.0, "Ti-6Al-4V annealed, ASM / MatWeb"),
    "carbon-fibre": Elastic(
        45.0, 0.30, 450.0,
        "quasi-isotropic T300/epoxy plate (in-plane modulus ~45 GPa, strength ~450 MPa), Toray / "
        "DragonPlate quasi-isotropic sheet data",
    ),
    "pla": Elastic(
        2.539, 0.36, 26.0,
        "PLA printed XY (FDM, ASTM D638 Type 1): tensile modulus 2539 MPa, tensile strength at "
        "yield 26 MPa; Pro3D Composites PLA data sheet, https://pro3dcomposites.com/materials/pla/ "
        "(Poisson's ratio 0.36 unverified: no printed-PLA source states it)",
    ),
    "petg": Elastic(2.0, 0.38, 45.0, "PETG printed 100 % infill XY, Prusament PETG datasheet"),
    "abs": Elastic(2.2, 0.35, 40.0, "ABS printed 100 % infill XY, MatWeb generic ABS"),
    # sheet materials of the laser process (sources in cad.data.materials.SHEETS)
    "aluminium-5083": Elastic(71.0, 0.33, 125.0, "5083-O/H111 sheet: MatWeb (E), EN 485-2 proof "
                              "stress min (cad.data.materials.SHEETS)"),
    "acrylic-cast": Elastic(3.10, 0.35, 72.4, "cast acrylic, Samson Supply technical data (E, "
                            "tensile strength, Poisson 0.35)"),
    "birch-plywood": Elastic(8.0, 0.30, 40.0, "unverified (no birch plywood data sheet value found; "
                             "cad.data.materials.SHEETS)"),
    "delrin": Elastic(3.1, 0.35, 69.0, "POM homopolymer (Delrin 150), DuPont datasheet"),
}


def get_elastic(material: str, field: str = "parts.bar_material") -> Elastic:
    """Elastic data of ``material`` (a key of :data:`cad.data.materials.MATERIALS`).

    Raises DesignError(field, ...) when the material has no elastic data here.
    """
    key = get_material(material, field).name
    if key not in ELASTIC:
        raise DesignError(
            field, f"no elastic data for {key!r} (known: {', '.join(sorted(ELASTIC))})"
        )
    return ELASTIC[key]


def bar_elastic(parts) -> Elastic:
    """Elastic data of the bars' beams: :func:`get_elastic` of their material, or for printed
    plate bars (``parts.printed``) the filament's printed XY modulus reduced by the wall/infill
    rule of mixtures over the bar section (:func:`cad.printing.printed_bar_modulus_GPa`)."""
    from dataclasses import replace

    mat = parts.tube_material if parts.bar_style == "tube" else parts.bar_material
    el = get_elastic(mat)
    if parts.bar_style == "tube" or not parts.printed(mat):
        return el
    f, s = filament(mat), parts.print_settings()
    E = printed_bar_modulus_GPa(f.E_xy_GPa, parts.bar_width_mm, parts.bar_thickness_mm, s)
    return replace(el, E_GPa=E, source=f"{f.source}; walls/skins solid, {s.infill_percent:g} % "
                   "infill at E f^2 (Gibson & Ashby 1997 eq. 5.6), rule of mixtures over the section")
