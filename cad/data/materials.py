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
        "aluminium-5083",
        2660.0,
        (0.80, 0.81, 0.84),
        "5083-O/H111: 2.66 g/cm^3 (Aluminum Association typical), MatWeb 'Aluminum 5083-O'",
    ),
    Material(
        "acrylic-cast",
        1190.0,
        (0.80, 0.90, 0.95),
        "cell-cast PMMA sheet: specific gravity 1.19 (ASTM D792), CCT Precision acrylic data sheet "
        "/ Samson cast acrylic technical data",
    ),
    Material(
        "birch-plywood",
        670.0,
        (0.85, 0.72, 0.52),
        "birch plywood, sanded, 1.4 mm veneers: 660-710 kg/m^3 by thickness (6.5 mm: 670), "
        "'Birch Plywood Datasheet' (UK distributor, EN 315 tolerances), vdocuments.site copy",
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


#: Other names of the sheet materials (``acrylic`` is cast PMMA, ``plywood`` birch).
_ALIASES = {"acrylic": "acrylic-cast", "pmma": "acrylic-cast", "plywood": "birch-plywood"}


def _normalise(name: str) -> str:
    key = name.strip().lower().replace("_", "-").replace(" ", "-")
    if key.startswith("aluminum-"):
        key = "aluminium-" + key[len("aluminum-") :]
    if key == "carbon-fiber":
        key = "carbon-fibre"
    key = _ALIASES.get(key, key)
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


# ------------------------------------------------------------------ sheet stock (laser)
@dataclass(frozen=True)
class SheetStock:
    """Sheet stock of one material for laser-cut plate parts (``parts.process = "laser"``).

    material : key of :data:`MATERIALS`.
    thickness_range_mm : ``{nominal thickness: (min, max)}`` mm, the stock thicknesses sold and
        the band a sheet of that nominal thickness may measure (its thickness tolerance).
    sizes_mm : standard sheet sizes ``(width, length)`` mm, smallest first.
    E_GPa, strength_MPa : Young's modulus and working strength (yield or proof stress for
        metals, tensile or bending strength for the rest).
    kerf_mm : width of the laser cut: the DXF is drawn at finished size and the shop
        offsets the beam by kerf / 2 (its CAM's kerf compensation).
    tappable, reamable : a thread can be tapped in it / a bore reamed to H7 and held.
    source : ``{field: source}`` of every value; ``unverified`` where none was found.
    """

    material: str
    thickness_range_mm: dict
    sizes_mm: tuple
    E_GPa: float
    strength_MPa: float
    kerf_mm: float
    tappable: bool
    reamable: bool
    source: dict

    @property
    def stock_sizes_mm(self) -> tuple[tuple[float, float], ...]:
        """Every size a sheet of this material is ordered in, smallest area first: the laser
        services' cut pieces :data:`LASER_CUT_SIZES_MM` and the mill sizes ``sizes_mm``."""
        return tuple(sorted({*LASER_CUT_SIZES_MM, *self.sizes_mm}, key=lambda s: (s[0] * s[1], s)))

    @property
    def thicknesses_mm(self) -> tuple[float, ...]:
        """Stock thicknesses (nominal, mm), ascending."""
        return tuple(sorted(self.thickness_range_mm))

    def nearest_mm(self, t_mm: float, n: int = 2) -> tuple[float, ...]:
        """The ``n`` stock thicknesses nearest ``t_mm`` (ascending)."""
        return tuple(sorted(sorted(self.thicknesses_mm, key=lambda x: abs(x - t_mm))[:n]))


#: Cut sheet pieces a laser service stocks besides the mill's full sheets ((width, length) mm):
#: the quarter (12 x 24 in) and half (24 x 24 in) of the 24 x 48 in full sheet, "many laser
#: systems have a standard bed size of 12 by 24 in, so a quarter sheet fits perfectly".
LASER_CUT_SIZES_MM = ((304.8, 609.6), (609.6, 609.6))
#: Where :data:`LASER_CUT_SIZES_MM` come from (stated for plastic sheet; for metal and plywood
#: sheets the same bed-sized pieces are unverified).
LASER_CUT_SIZES_SOURCE = ("A&E Magazine, 'What is the standard size and thickness of engraving plastic "
                          "sheet?' (a-e-mag.com, question-answers, undated page read 2026-12-04): full "
                          "sheet 24 x 48 in, half 24 x 24 in, quarter 12 x 24 in; unverified for "
                          "aluminium and plywood")


def _pm(table: dict) -> dict:
    """``{t: (t - d, t + d)}`` of a ``{t: +-d}`` table."""
    return {t: (round(t - d, 6), round(t + d, 6)) for t, d in table.items()}


_EN485_4 = ("EN 485-4:1993 Table 1 (cold-rolled sheet), alloy group II (5083, 6061), width over "
            "1000 up to 1250 mm; BS EN 485-4:1994 copy at pdfcoffee.com. Sheets of 6 mm and over "
            "may be hot rolled (EN 485-3, not checked)")
#: EN 485-4 Table 1 thickness tolerance (+-mm), group II, width 1000..1250 mm, by nominal thickness.
_AL_TOL = {1.0: 0.08, 1.5: 0.11, 2.0: 0.13, 3.0: 0.15, 4.0: 0.20, 5.0: 0.22, 6.0: 0.24,
           8.0: 0.30, 10.0: 0.33}
_AL_SIZES = ((1000.0, 2000.0), (1250.0, 2500.0))
_AL_SOURCE_COMMON = {
    "thickness_range_mm": f"tolerance: {_EN485_4}; the thickness list: unverified (common stock)",
    "sizes_mm": "unverified (the 1000 / 1250 mm widths are EN 485-4 Table 1 width classes)",
    "kerf_mm": "fibre laser on aluminium plate: cut seam 0.1-0.2 mm (upper value taken), "
               "mallhometrade.com 'laser cutting of aluminum plate'",
    "tappable": "aluminium alloys are tapped as machined parts are (as the machined process)",
    "reamable": "aluminium alloys are reamed to H7 as machined parts are (as the machined process; "
                "stated design rule)",
}

SHEETS: dict[str, SheetStock] = {
    "aluminium-5083": SheetStock(
        "aluminium-5083", _pm(_AL_TOL), _AL_SIZES, 71.0, 125.0, 0.2, True, True,
        {**_AL_SOURCE_COMMON,
         "E_GPa": "5083-O, 71 GPa (AA typical, tension/compression average), MatWeb 'Aluminum 5083-O'",
         "strength_MPa": "5083 O/H111 sheet 0.2-6.3 mm: 0.2 % proof stress 125 MPa min, EN 485-2 "
                         "(as quoted by cryodeck.com 'Aluminium sheet')"}),
    "aluminium-6061": SheetStock(
        "aluminium-6061", _pm(_AL_TOL), _AL_SIZES, 68.9, 276.0, 0.2, True, True,
        {**_AL_SOURCE_COMMON,
         "E_GPa": "6061-T6, ASM Handbook Vol. 2 / MatWeb (cad.structure.elastic)",
         "strength_MPa": "6061-T6 yield, ASM Handbook Vol. 2 / MatWeb (cad.structure.elastic)"}),
    "acrylic-cast": SheetStock(
        "acrylic-cast",
        {t: (round(t - (0.4 + 0.1 * t), 6), round(t + 0.4 + 0.1 * t, 6))
         for t in (2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0)},
        ((1000.0, 600.0), (2030.0, 3050.0)), 3.10, 72.4, 0.25, False, False,
        {"thickness_range_mm": "tolerance +-(0.4 + 0.1 t) mm, ISO 7823-1 (cell cast PMMA), as "
                               "stated by Evonik/Roehm 'PLEXIGLAS tolerances' FAQ "
                               "(plexiglas.net); the thickness list: unverified (common stock)",
         "sizes_mm": "unverified (3050 x 2030 mm full sheet and 1000 x 600 mm laser-bed cut "
                     "are common retail sizes)",
         "E_GPa": "cast acrylic, tensile modulus 450,000 psi = 3.10 GPa (ASTM D638), Samson "
                  "Supply 'cast acrylic colors' technical data",
         "strength_MPa": "tensile strength 10,500 psi = 72.4 MPa (ASTM D638), same data sheet",
         "kerf_mm": "CO2 laser, 1/4 in acrylic: average kerf 0.010 in = 0.25 mm, laser504.com "
                    "'Kerfs and laser thickness'",
         "tappable": "not tapped here: a thread in PMMA strips and crazes under a screw's "
                     "preload (stated design rule, unverified)",
         "reamable": "an H7 bore is not held in PMMA (thermal expansion 7e-5 /K, CCT Precision "
                     "data sheet 4.0e-5 /F); laser-cut at nominal instead"}),
    "birch-plywood": SheetStock(
        "birch-plywood",
        {4.0: (3.5, 4.1), 6.5: (6.1, 6.9), 9.0: (8.8, 9.5), 12.0: (11.5, 12.5),
         15.0: (14.3, 15.3), 18.0: (17.1, 18.1)},
        ((1220.0, 2440.0), (1525.0, 3050.0)), 8.0, 40.0, 0.25, False, False,
        {"thickness_range_mm": "'Birch Plywood Datasheet' (UK distributor): nominal 4 / 6.5 / 9 / "
                               "12 / 15 / 18 mm with lower and upper limits (EN 315 tolerances), "
                               "vdocuments.site copy",
         "sizes_mm": "same data sheet: 1220 x 2440 and 1525 x 3050 mm",
         "E_GPa": "unverified (no birch plywood data sheet value found; 8 GPa is a low "
                  "bending modulus for birch plywood)",
         "strength_MPa": "unverified (no data sheet value found)",
         "kerf_mm": "CO2 laser, 1/4 in birch plywood: average kerf 0.010 in = 0.25 mm, "
                    "laser504.com 'Kerfs and laser thickness'",
         "tappable": "wood does not hold a machine thread (stated design rule)",
         "reamable": "wood moves with moisture: no H7 bore is held (stated design rule)"}),
}


def sheet_stock(material: str) -> SheetStock | None:
    """The :class:`SheetStock` of a material key, or None when it is not sold as sheet here."""
    return SHEETS.get(material)
