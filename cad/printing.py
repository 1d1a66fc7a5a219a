"""FDM printing of made parts: printable materials, print settings, the wall/infill model.

Pure data and closed forms, no CAD import (the per-layer model of a real part is in
:mod:`cad.parts.printed`). Lengths in mm, densities kg/m^3, moduli GPa.

Model of a printed part (what a slicer lays down, printed in the part frame, z up):

* **walls**: ``walls`` perimeters of ``line_width_mm`` around every contour (outer edge and
  every hole) of every layer, solid;
* **top/bottom skins**: ``solid_layers`` layers under every top face and over every bottom
  face, solid;
* **infill**: the rest, at ``infill_percent`` of solid.

Mass = density x (V_solid_shell + f V_core). Stiffness of a printed bar
(:func:`printed_bar_modulus_GPa`): rule of mixtures over the bar section (the shell at
the filament's printed XY modulus, the core at the Gibson-Ashby open-cell scaling
E_core = E_s f^2, Gibson & Ashby, *Cellular Solids*, 2nd ed. 1997, eq. (5.6) with C1 = 1).
"""

from __future__ import annotations

from dataclasses import dataclass

from cad.data.fits import fmt_mm, parse_fit
from cad.tolerances import FDM_TOL_MM, FDM_TOL_REL

#: Made-part processes (``parts.process``); "laser" is checked in :mod:`cad.design.laser`.
PROCESSES = ("machined", "printed", "laser")


@dataclass(frozen=True)
class Filament:
    """A printable material: key of :data:`cad.data.materials.MATERIALS`, printed XY tensile
    modulus (GPa) with its source, and ``machinable``: sold as plate/rod stock a shop can
    machine (ABS), or a filament only (PLA, PETG: a machined design in it is printed)."""

    name: str
    E_xy_GPa: float
    source: str
    machinable: bool


FILAMENTS: dict[str, Filament] = {
    "pla": Filament(
        "pla", 2.539,
        "PLA printed XY, tensile modulus 2539 MPa (ASTM D638), specific gravity 1.264; "
        "Pro3D Composites PLA data sheet, https://pro3dcomposites.com/materials/pla/",
        False),
    "petg": Filament(
        "petg", 2.1,
        "PETG-ESD printed, tensile modulus 2100 MPa (DIN EN ISO 527), density 1.27 g/cm^3; "
        "CR-3D technical data sheet PETG-ESD (an ESD grade: plain PETG unverified)",
        False),
    "abs": Filament(
        "abs", 2.48,
        "Stratasys P400 ABS, tensile modulus 360,000 psi = 2.48 GPa, specific gravity 1.05; "
        "Stratasys FDM 2000 manual, Appendix M1",
        True),
}

#: Pilot hole (mm) of a non-flanged brass heat-set insert per thread: a tapped hole of a
#: machined part becomes one of these in a printed part (source :data:`HEAT_SET_SOURCE`).
HEAT_SET_PILOT_MM = {"M2.5": 3.6, "M3": 4.0, "M4": 5.6, "M5": 6.4, "M6": 8.0}
#: Source of :data:`HEAT_SET_PILOT_MM` (pilot hole, non-flanged heat-set insert).
HEAT_SET_SOURCE = ("heat-set insert pilot hole chart (M3 4.0, M4 5.6, M5 6.4, M6 8.0 mm, -0/+0.1), "
                   "https://www.accu.co.uk/p/488-threaded-insert-hole-size-charts-for-3d-printing-pla-petg-resin; "
                   "M2.5 3.6 mm: Ruthex/CNC Kitchen insert OD, tools.creative3dp.com chart")


@dataclass(frozen=True)
class PrintSettings:
    """Slicer settings of the printed parts (defaults: a 0.4 mm nozzle at 0.2 mm layers,
    the usual "0.20 mm quality" profile of desktop slicers; stated, not measured).

    layer_height_mm, line_width_mm : layer height and extrusion width (mm).
    walls : perimeters per contour; solid_layers : solid layers at every top and bottom.
    infill_percent : infill density of the core (0..100).
    hole_compensation_mm : holes modelled this much over nominal (FDM holes come out about
        0.1-0.2 mm small on a 0.4 mm nozzle; a stated assumption, not measured on one printer).
    press_fit_mm : a bearing seat is modelled at D + compensation - this (the interference).
    """

    layer_height_mm: float = 0.2
    line_width_mm: float = 0.45
    walls: int = 2
    solid_layers: int = 4
    infill_percent: float = 20.0
    hole_compensation_mm: float = 0.2
    press_fit_mm: float = 0.1

    @property
    def wall_mm(self) -> float:
        """Wall thickness: walls x line width (mm)."""
        return self.walls * self.line_width_mm

    @property
    def infill(self) -> float:
        """Infill as a fraction (0..1)."""
        return self.infill_percent / 100.0

    def describe(self, material: str) -> str:
        """The settings as the BOM states them."""
        return (f"FDM print {material.upper()}: {self.layer_height_mm:g} mm layers, "
                f"{self.walls} walls x {self.line_width_mm:g} mm, {self.solid_layers} top/bottom "
                f"layers, {self.infill_percent:g} % infill")


def box_printed_volume_mm3(L: float, W: float, T: float, s: PrintSettings) -> tuple[float, float]:
    """``(solid shell volume, core volume)`` (mm^3) of an L x W x T box printed flat.

    Closed form: core (L - 2w)(W - 2w)(T - 2 n h), w = walls x line width, n solid layers of
    h = T / round(T / layer height); the shell is the rest. A core dimension <= 0: no core.
    """
    n = max(1, round(T / s.layer_height_mm))
    h = T / n
    w = s.wall_mm
    dims = (L - 2 * w, W - 2 * w, T - 2 * s.solid_layers * h)
    core = dims[0] * dims[1] * dims[2] if min(dims) > 0 else 0.0
    return L * W * T - core, core


def printed_bar_modulus_GPa(E_s_GPa: float, W_mm: float, T_mm: float, s: PrintSettings) -> float:
    """Effective modulus (GPa) of a W x T bar section printed flat: rule of mixtures of the
    solid shell (walls, skins) at ``E_s_GPa`` and the core at E_s f^2 (Gibson & Ashby 1997
    eq. 5.6), weighted by section area."""
    n = max(1, round(T_mm / s.layer_height_mm))
    cw, ct = W_mm - 2 * s.wall_mm, T_mm - 2 * s.solid_layers * T_mm / n
    a_core = cw * ct if cw > 0 and ct > 0 else 0.0
    a = W_mm * T_mm
    return E_s_GPa * ((a - a_core) + s.infill**2 * a_core) / a


def filament(material: str) -> Filament | None:
    """The :class:`Filament` of a material key, or None when it is not printable."""
    return FILAMENTS.get(material)


def is_printed(process: str, material: str) -> bool:
    """A made part of ``material`` under ``process`` is printed: printable and either the
    process is "printed" or the material is a filament only (PLA, PETG)."""
    f = FILAMENTS.get(material)
    return f is not None and (process == "printed" or not f.machinable)


def _printed_op(op: str) -> str | None:
    """One machining operation of a BOM process text as done for a printed part (None:
    the operation is the printing itself)."""
    import re

    if op.startswith(("turned", "waterjet", "CNC", "machined", "3D print")):
        return None
    m = re.match(r"tap (M[\d.]+)(.*)", op)
    if m:
        size, rest = m.groups()
        pilot = HEAT_SET_PILOT_MM.get(size)
        if pilot is None:
            return f"{size} nut{rest} instead of the tapped thread (no heat-set insert data)"
        return f"{size} heat-set insert{rest}: drill the printed tap hole to the {pilot:g} mm pilot"
    if op.startswith(("ream ", "bore ", "mill ")):
        return f"{op.split(' ', 1)[1]}: printed at nominal, drill/ream to size after printing"
    return op


def printed_process(machined: str, material: str, s: PrintSettings, flip: bool) -> str:
    """The BOM process text of a printed part: settings, orientation, then each operation of
    its ``machined`` text as done on the print (:func:`_printed_op`)."""
    ops = [o.strip() for o in machined.replace(", tap ", "; tap ").split(";") if o.strip()]
    done = [x for x in map(_printed_op, ops) if x]
    side = "flipped (part z down)" if flip else "as modelled (part z up)"
    return "; ".join([f"{s.describe(material)}, oriented {side}", *done])


#: Where :data:`cad.tolerances.FDM_TOL_MM` / ``FDM_TOL_REL`` come from.
FDM_TOLERANCE_SOURCE = ("FDM Quality Guideline (Imagine That 3D print-service wiki): +-0.5 mm or 1 %, "
                        "whichever is greater, "
                        "https://imaginethat3d.atlassian.net/wiki/spaces/IMAGINETHA/pages/196679/"
                        "FDM+QUALITY+GUIDELINE")


def fdm_tolerance_mm(size_mm: float) -> float:
    """The +- tolerance of a printed size (mm): the greater of :data:`cad.tolerances.FDM_TOL_MM`
    and ``FDM_TOL_REL`` x size (:data:`FDM_TOLERANCE_SOURCE`)."""
    return max(FDM_TOL_MM, FDM_TOL_REL * size_mm)


def printed_fit(text: str) -> str:
    """The fit text of a feature of a printed part: an ISO 286 fit (``"spacer bore 8 H7"``)
    becomes ``"spacer bore 8 printed 8 (FDM +-0.5 mm; drill to 8 after printing, not H7)"``
    (a bore: printed at nominal, drilled to size) or ``"... printed 8 (FDM +-0.5 mm, not
    g6)"`` (a shaft); a text that states no ISO fit (already a printed one) is kept. The
    tolerance: :func:`fdm_tolerance_mm`. A print holds no ISO 286 class."""
    parsed = parse_fit(text)
    if parsed is None:
        return text
    label, d, cls = parsed
    tol = f"FDM +-{fmt_mm(fdm_tolerance_mm(d))} mm"
    how = f"; drill to {fmt_mm(d)} after printing, not {cls}" if cls[:1].isupper() else f", not {cls}"
    return f"{label} {fmt_mm(d)} printed {fmt_mm(d)} ({tol}{how})"
