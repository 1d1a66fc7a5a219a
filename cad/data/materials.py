"""Material table: density (kg/m^3), display colour and the source of each density.

Pure data, no CAD import. Densities are nominal room-temperature values from the
sources named in each entry; real stock varies by roughly +-1 % for metals and
+-5 % for printed and composite parts (infill, fibre fraction), which the
inertia report should be read against.

Keys are lower-case with hyphens (``aluminium-6061``). :func:`get_material`
also accepts the US spelling ``aluminum-...`` and any letter case.
"""

from __future__ import annotations

from dataclasses import dataclass

from cad.errors import DesignError


@dataclass(frozen=True)
class Material:
    """One engineering material.

    Parameters
    ----------
    name : key, e.g. ``"aluminium-6061"``.
    density_kg_m3 : nominal density, kg/m^3 (> 0).
    color_rgb : display colour (r, g, b), sRGB-encoded (as a hex code is), each in 0..1:
        STEP ``COLOUR_RGB`` as it is, glTF ``baseColorFactor`` decoded to linear.
    source : where the density comes from (datasheet / handbook).
    """

    name: str
    density_kg_m3: float
    color_rgb: tuple[float, float, float]
    source: str


_ASM = "ASM Handbook Vol. 2 (1990) / MatWeb datasheet"

_TABLE: tuple[Material, ...] = (
    Material(
        "aluminium-6061",
        2700.0,
        (0.78, 0.80, 0.83),
        f"6061-T6: 2.70 g/cm^3, {_ASM}",
    ),
    Material(
        "aluminium-7075",
        2810.0,
        (0.72, 0.74, 0.78),
        f"7075-T6: 2.81 g/cm^3, {_ASM}",
    ),
    Material(
        "steel-1018",
        7870.0,
        (0.45, 0.46, 0.48),
        "AISI 1018 cold drawn: 7.87 g/cm^3, ASM Handbook Vol. 1 / MatWeb datasheet",
    ),
    Material(
        "stainless-304",
        8000.0,
        (0.66, 0.67, 0.69),
        "AISI 304 annealed: 8.00 g/cm^3, ASM Handbook Vol. 1 / MatWeb datasheet",
    ),
    Material(
        "brass-360",
        8500.0,
        (0.85, 0.68, 0.30),
        "C36000 free-cutting brass: 8.50 g/cm^3, Copper Development Association datasheet",
    ),
    Material(
        "copper",
        8960.0,
        (0.85, 0.50, 0.30),
        "pure Cu (C11000 ETP 8.89-8.94; pure 8.96 g/cm^3), CRC Handbook of Chemistry and Physics",
    ),
    Material(
        "soft-iron",
        7870.0,
        (0.35, 0.35, 0.38),
        "pure / low-carbon iron (e.g. Armco): 7.87 g/cm^3, CRC Handbook of Chemistry and Physics",
    ),
    Material(
        "ndfeb-n42",
        7500.0,
        (0.60, 0.60, 0.64),
        "sintered NdFeB N42: 7.4-7.6 g/cm^3 (7.5 nominal), Arnold Magnetic / Magnequench datasheet",
    ),
    Material(
        "titanium-6al4v",
        4430.0,
        (0.55, 0.56, 0.58),
        "Ti-6Al-4V (grade 5) annealed: 4.43 g/cm^3, ASM Handbook Vol. 2 / MatWeb datasheet",
    ),
    Material(
        "carbon-fibre",
        1550.0,
        (0.12, 0.12, 0.13),
        "quasi-isotropic CFRP plate, ~60 % fibre volume: 1.5-1.6 g/cm^3, Toray T300/epoxy datasheet",
    ),
    Material(
        "pla",
        1240.0,
        (0.95, 0.95, 0.90),
        "PLA bulk (100 % infill): 1.24 g/cm^3, NatureWorks Ingeo 4043D datasheet",
    ),
    Material(
        "petg",
        1270.0,
        (0.30, 0.55, 0.85),
        "PETG bulk (100 % infill): 1.27 g/cm^3, Eastman Spectar / Prusament PETG datasheet",
    ),
    Material(
        "abs",
        1040.0,
        (0.90, 0.90, 0.88),
        "ABS bulk (100 % infill): 1.04 g/cm^3, MatWeb generic ABS / Prusament ASA-ABS datasheet",
    ),
    Material(
        "delrin",
        1410.0,
        (0.97, 0.97, 0.95),
        "POM homopolymer (DuPont Delrin 150): 1.41-1.42 g/cm^3, DuPont datasheet",
    ),
)

#: Every known material by key.
MATERIALS: dict[str, Material] = {m.name: m for m in _TABLE}

#: Material used when none is given (e.g. ``hapticad massprops`` without flags).
DEFAULT_MATERIAL = "aluminium-6061"


def _normalise(name: str) -> str:
    key = name.strip().lower().replace("_", "-").replace(" ", "-")
    if key.startswith("aluminum-"):
        key = "aluminium-" + key[len("aluminum-") :]
    if key == "carbon-fiber":
        key = "carbon-fibre"
    return key


def get_material(name: str, field: str = "material") -> Material:
    """Return the material called ``name``.

    Parameters
    ----------
    name : material key (case-insensitive; ``aluminum``/``aluminium`` and ``_``/``-`` both accepted).
    field : dotted design-file path used in the error message.

    Raises
    ------
    DesignError(field, "unknown material 'x' (known: ...)") when ``name`` is not in the table.
    """
    if not isinstance(name, str):
        raise DesignError(field, f"must be a material name, got {name!r}")
    mat = MATERIALS.get(_normalise(name))
    if mat is None:
        known = ", ".join(sorted(MATERIALS))
        raise DesignError(field, f"unknown material {name!r} (known: {known})")
    return mat
