"""Cable (wire rope) catalog for capstan transmissions (pure data, no CAD import).

Each rope is a :class:`CableSpec`: its construction and nominal diameter (what the key names),
then the data a capstan needs -- minimum breaking load, axial stiffness EA, mass per metre and
the rope maker's minimum bend ratio D/d -- each with the source it comes from. A value no public
source that was read states is listed in ``unverified`` with the reason; a value nobody states
at all is None (never invented). Every figure computed from an unverified or missing value says
so (:mod:`cad.actuators.capstan`).

What was searched (issue 35): the stored public pages and docs for the miniature-cable tables of
Carl Stahl Sava Industries (Design Guide for Cable Solutions DG1609), Loos & Co and Lexco, and
the WoodenHaptics repositories. The Sava guide is stored only as a cover page (its tables were
not readable); no sub-millimetre table of breaking load or mass per metre was found. The
one breaking load read from a public page is the 1/16 in (1.59 mm) 7x7 type-304 breaking
strength (480 lbf, :data:`_BREAK_1_16_SOURCE`); the sub-millimetre breaking loads below are that
value scaled by d^2 (same construction and wire grade, area ratio) and so marked unverified.
The axial stiffness EA is the rope maker's own elastic-stretch formula (Loos & Co / Strand Core,
:data:`_EA_SOURCE`): stretch E [% of length] = W [lbf] G / D^2 [in^2] with the maker's G factor
per construction, so EA = W / strain = 100 D^2 / G lbf (:func:`stretch_EA_N`).

Units: diameters mm, forces N, EA N, mass g/m.
"""

from __future__ import annotations

from dataclasses import dataclass

from cad.errors import DesignError

#: CableSpec fields that carry a value with its own source (see CableSpec.sources).
CABLE_DATA_FIELDS = ("diameter_mm", "min_breaking_load_N", "axial_stiffness_EA_N",
                     "mass_g_per_m", "min_bend_ratio")

#: 1 lbf in N (NIST SP 811, 2008 edition, appendix B.8: 1 lbf = 4.448222 N).
LBF_N = 4.448222

_BREAK_1_16_SOURCE = ("https://www.0685.com/continuing-education/be-self-taught/44804.html "
                      "('7X7, 1/16-inch, 304-grade stainless steel cable offers a 480-lb. "
                      "breaking strength'; page read 2026-12; not a rope maker's sheet)")
#: The rope makers' minimum bend ratios as issue 35 quotes them ("about 40 (7x7) or 25-28
#: (7x19)"); the makers' tables themselves were not read.
_BEND_SOURCE = ("issue 35 text: rope makers ask for D/d about 40 (7x7) or 25-28 (7x19); "
                "no maker's table read (no public source found)")
#: Loos & Co's "G" stretch factors for 302/304 stainless rope (% of length x in^2 / lbf); the
#: 7x19 value is also the one aeroassemblies.com's calculator uses in its worked example.
STRETCH_G_FACTOR = {"7x7": 0.0000120, "7x19": 0.0000162}
_EA_SOURCE = ("the rope maker's elastic-stretch formula E% = W G / D^2 (W lbf, D in) with G = {g} "
              "for {c} 302/304 stainless (https://strandcore.com/resources/technical-resources/"
              "wire-rope-stretch/, Loos & Co, 'an approximation'; the 7x19 G also in "
              "https://aeroassemblies.com/elastic-stretch-calculator/): EA = 100 D^2 / G lbf x "
              "4.448222 N/lbf; elastic stretch only (structural stretch, < 1 % once, is taken "
              "out by pretensioning)")
_NOT_FOUND = "no public source found (stored pages and docs searched, issue 35)"
#: WoodenHaptics: 10 mm capstans and 160 / 120 / 120 mm drums (diameter_capstan_a..c,
#: diameter_body_a..c of default_woody()); the 0.54 mm 7x7 rope is as issue 35 states it.
WOODENHAPTICS_SOURCE = ("WoodenHaptics/woody-experimental chai3d-3.0.0-woody/src/devices/"
                        "CWoodenDevice.cpp default_woody() (commit 23f74fd)")


@dataclass(frozen=True)
class CableSpec:
    """A steel wire rope: ``construction`` ("7x7", "7x19"), nominal ``diameter_mm``;
    ``min_breaking_load_N`` (MBL), ``axial_stiffness_EA_N`` (E times metallic area),
    ``mass_g_per_m``, ``min_bend_ratio`` (smallest sheave or capstan diameter over the rope
    diameter the maker allows). ``sources`` maps each of :data:`CABLE_DATA_FIELDS` to where its
    value comes from; ``unverified`` names the fields with no public source read (a derived or
    quoted value), each figure using one says so; None = no value known."""

    key: str
    description: str
    construction: str
    diameter_mm: float
    min_breaking_load_N: float | None
    axial_stiffness_EA_N: float | None
    mass_g_per_m: float | None
    min_bend_ratio: float
    sources: tuple[tuple[str, str], ...]
    unverified: tuple[str, ...]

    def source_of(self, field: str) -> str:
        """Where the value of data field ``field`` comes from ('' when none is recorded)."""
        return dict(self.sources).get(field, "")

    def is_unverified(self, field: str) -> bool:
        """True when ``field`` has no value or a value without a public source that was read."""
        return getattr(self, field) is None or field in self.unverified

    def min_capstan_diameter_mm(self) -> float:
        """Smallest capstan (or drum) diameter the rope's minimum bend ratio allows, mm."""
        return self.min_bend_ratio * self.diameter_mm


def _scaled_break_N(d_mm: float) -> float:
    """MBL scaled by d^2 from the 1/16 in (1.5875 mm) 7x7 value, N (derived, unverified)."""
    return 480.0 * LBF_N * (d_mm / 1.5875) ** 2


def stretch_EA_N(construction: str, d_mm: float) -> float:
    """Axial stiffness E A (N) of a stainless rope of ``construction`` and diameter ``d_mm`` from
    the maker's stretch formula: strain = W G / (100 D^2), so EA = 100 D^2 / G (lbf, D in
    inches), converted with :data:`LBF_N`. KeyError for a construction with no G factor."""
    return 100.0 * (d_mm / 25.4) ** 2 / STRETCH_G_FACTOR[construction] * LBF_N


def _rope(construction: str, d_mm: float, extra: str = "") -> CableSpec:
    seven = construction == "7x7"
    key = f"steel-{construction}-{d_mm:g}"
    mbl = _scaled_break_N(d_mm) if seven else None
    mbl_src = (f"derived: 480 lbf x (d / 1.5875 mm)^2 from {_BREAK_1_16_SOURCE}" if seven
               else _NOT_FOUND)
    return CableSpec(
        key=key,
        description=f"stainless steel wire rope {construction}, {d_mm:g} mm{extra}",
        construction=construction,
        diameter_mm=d_mm,
        min_breaking_load_N=mbl,
        axial_stiffness_EA_N=stretch_EA_N(construction, d_mm),
        mass_g_per_m=None,
        min_bend_ratio=40.0 if seven else 26.0,
        sources=(
            ("diameter_mm", "the catalog key (nominal diameter ordered)"),
            ("min_breaking_load_N", mbl_src),
            ("axial_stiffness_EA_N", _EA_SOURCE.format(g=STRETCH_G_FACTOR[construction],
                                                       c=construction)),
            ("mass_g_per_m", _NOT_FOUND),
            ("min_bend_ratio", _BEND_SOURCE + ("" if seven else "; 26 = middle of 25-28")),
        ),
        unverified=("min_breaking_load_N", "mass_g_per_m", "min_bend_ratio"),
    )


def _rope_1_16() -> CableSpec:
    """The 1/16 in 7x7 type-304 rope: the one breaking load read from a public page."""
    base = _rope("7x7", 1.5875)
    return CableSpec(
        key="steel-7x7-1.6", description="stainless steel (304) wire rope 7x7, 1/16 in (1.59 mm)",
        construction="7x7", diameter_mm=1.5875, min_breaking_load_N=480.0 * LBF_N,
        axial_stiffness_EA_N=base.axial_stiffness_EA_N, mass_g_per_m=None, min_bend_ratio=40.0,
        sources=(("diameter_mm", "1/16 in nominal (the size ordered)"),
                 ("min_breaking_load_N", _BREAK_1_16_SOURCE + "; 480 lbf x 4.448222 N/lbf"),
                 *base.sources[2:]),
        unverified=("mass_g_per_m", "min_bend_ratio"),
    )


#: The rope catalog, keyed ``steel-<construction>-<diameter mm>``.
CABLES: dict[str, CableSpec] = {
    c.key: c
    for c in (
        _rope("7x7", 0.45),
        _rope("7x7", 0.54, " (the WoodenHaptics rope, issue 35)"),
        _rope("7x7", 0.6),
        _rope("7x7", 0.8),
        _rope("7x7", 1.0),
        _rope("7x19", 0.6),
        _rope("7x19", 0.8),
        _rope("7x19", 1.0),
        _rope_1_16(),
    )
}


def get_cable(key: str, field: str = "transmission.cable") -> CableSpec:
    """Catalog entry ``key``; DesignError(field) naming the catalog when unknown."""
    if key not in CABLES:
        raise DesignError(field, f"unknown cable {key!r} (catalog: {', '.join(CABLES)})")
    return CABLES[key]


def largest_rope_for(capstan_diameter_mm: float, construction: str | None = None) -> CableSpec | None:
    """The thickest catalog rope whose minimum bend ratio a capstan of this diameter meets
    (``construction`` to restrict the search); None when none fits."""
    fits = [c for c in CABLES.values()
            if (construction is None or c.construction == construction)
            and c.min_capstan_diameter_mm() <= capstan_diameter_mm]
    return max(fits, key=lambda c: (c.diameter_mm, c.construction), default=None)
