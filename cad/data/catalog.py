"""Bought-part catalog data: bearings, fasteners, motors (pure data, no CAD import).

Dimensions of ball bearings and fasteners are read from bd_warehouse 0.4.0's own
CSV tables (the same numbers its part generators use), located on disk without
importing bd_warehouse (which imports build123d, ~3 s). Masses:

* ball bearings: the catalog mass column of bd_warehouse's
  ``single_row_deep_groove_ball_bearing_parameters.csv`` (SKF catalog, kg);
  inertia from that mass spread as a uniform annulus (d..D, width B), see
  :func:`ring_inertia_kg_m2`;
* fasteners (screws, nuts, washers): no catalog mass in bd_warehouse, so their
  mass is their simplified solid (no thread) times the density of steel
  (:data:`FASTENER_MATERIAL`); a design may override any bought-part mass;
* motors: :data:`MOTORS` (catalog weight and rotor inertia, sources inline).

Every length is mm, every mass kg, inertia kg m^2 unless the name says otherwise.
"""

from __future__ import annotations

import csv
import functools
import importlib.util
import math
from dataclasses import dataclass
from pathlib import Path

from cad.errors import DesignError

#: Material of bought steel fasteners (key of :data:`cad.data.materials.MATERIALS`).
FASTENER_MATERIAL = "steel-1018"
#: Material of bearing rings for the exported geometry (colour only; mass is catalog).
BEARING_MATERIAL = "steel-1018"


@functools.lru_cache(maxsize=1)
def bd_warehouse_data_dir() -> Path:
    """Directory of bd_warehouse's CSV tables, found without importing the package."""
    spec = importlib.util.find_spec("bd_warehouse")
    if spec is None or not spec.submodule_search_locations:
        raise DesignError(
            "parts", "bd_warehouse is not installed (pip install bd_warehouse==0.4.0)"
        )
    return Path(list(spec.submodule_search_locations)[0]) / "data"


@functools.cache
def _table(filename: str, prefix: str) -> dict[str, dict[str, str]]:
    """Rows of a bd_warehouse CSV keyed by Size, columns of one type prefix (``SKT``...)."""
    out: dict[str, dict[str, str]] = {}
    with open(bd_warehouse_data_dir() / filename, newline="", encoding="utf-8") as fh:
        for row in csv.DictReader(fh):
            size = row["Size"].strip()
            vals = {}
            for k, v in row.items():
                if k and k.startswith(prefix + ":") and v not in (None, "", "–"):
                    vals[k.split(":", 1)[1].strip()] = v.strip()
            if vals:
                out[size] = vals
    return out


def _num(s: str) -> float:
    return float(s.replace("*", "").strip())


# --------------------------------------------------------------------------- bearings
@dataclass(frozen=True)
class BearingSpec:
    """Single-row deep groove ball bearing (bd_warehouse SKT table = SKF catalog).

    d_mm bore, D_mm outside diameter, B_mm width, d1_mm inner-ring shoulder
    diameter, D1_mm outer-ring shoulder diameter, da_mm / Da_mm abutment
    diameters (shaft min / housing max), mass_kg catalog mass.
    """

    size: str
    designation: str
    d_mm: float
    D_mm: float
    B_mm: float
    d1_mm: float
    D1_mm: float
    da_mm: float
    Da_mm: float
    mass_kg: float


def bearing_sizes() -> list[str]:
    return list(_table("single_row_deep_groove_ball_bearing_parameters.csv", "SKT"))


def _bearing_by_designation() -> dict[str, str]:
    """ISO designation (``"608"``, ``"618/4"``) -> bd_warehouse size (``"M8-22-7"``).

    Source: the ``Designation`` column of the same SKF catalog table that gives the sizes
    (bd_warehouse 0.4.0 ``single_row_deep_groove_ball_bearing_parameters.csv``, SKT)."""
    tab = _table("single_row_deep_groove_ball_bearing_parameters.csv", "SKT")
    return {r["Designation"].replace("*", "").strip(): k for k, r in tab.items()}


def get_bearing(size: str, field: str = "parts.bearing") -> BearingSpec:
    """Catalog data of bearing ``size``: the bd_warehouse form ``M<d>-<D>-<B>`` (``M8-22-7``)
    or its ISO designation (``608``, the common name of 8 x 22 x 7 mm; SKF catalog column).
    ``BearingSpec.size`` is always the ``M`` form. Raises DesignError(field) when unknown."""
    tab = _table("single_row_deep_groove_ball_bearing_parameters.csv", "SKT")
    key = size if size in tab else _bearing_by_designation().get(str(size).strip())
    if key is None:
        raise DesignError(
            field, f"unknown bearing {size!r} (bd_warehouse SKT sizes: {', '.join(tab)}; "
            "or an ISO designation such as 608)"
        )
    size, r = key, tab[key]
    return BearingSpec(
        size,
        r["Designation"].replace("*", "").strip(),
        _num(r["d"]),
        _num(r["D"]),
        _num(r["B"]),
        _num(r["d1"]),
        _num(r["D1"]),
        _num(r["da"]),
        _num(r["Da"]),
        _num(r["mass"]),
    )


def ring_inertia_kg_m2(
    mass_kg: float, r_in_mm: float, r_out_mm: float, width_mm: float
) -> tuple[float, float]:
    """(I_axial, I_transverse) about the COM of a uniform annulus, kg m^2.

    I_axial = m (ri^2 + ro^2) / 2, I_transverse = m (3 (ri^2 + ro^2) + B^2) / 12.
    """
    ri, ro, b = r_in_mm * 1e-3, r_out_mm * 1e-3, width_mm * 1e-3
    s = ri * ri + ro * ro
    return mass_kg * s / 2.0, mass_kg * (3.0 * s + b * b) / 12.0


# --------------------------------------------------------------------------- fasteners
@dataclass(frozen=True)
class ShoulderScrewSpec:
    """ISO 7379 hexagon socket shoulder screw (bd_warehouse ``shoulder_screw.csv``).

    ds_mm shoulder diameter, dk_mm / k_mm head diameter / height, b_mm threaded
    end length below the shoulder (incl. the g2 relief), lengths_mm nominal
    shoulder lengths.
    """

    size: str
    ds_mm: float
    dk_mm: float
    k_mm: float
    b_mm: float
    g2_mm: float
    thread_mm: float
    lengths_mm: tuple[float, ...]


ISO7379_LENGTHS_MM = (10, 12, 16, 20, 25, 30, 40, 50, 60, 70, 80, 90, 100, 120)


def get_shoulder_screw(size: str, field: str = "parts.pin") -> ShoulderScrewSpec:
    """ISO 7379 size ``M6-1``; a plain pin ``dowel-<d>`` in the same form (see
    :func:`dowel_as_shoulder_screw`)."""
    if is_dowel(size):
        return dowel_as_shoulder_screw(size, field)
    tab = _table("shoulder_screw.csv", "iso7379")
    if size not in tab:
        raise DesignError(
            field,
            f"unknown ISO 7379 shoulder screw {size!r} (bd_warehouse sizes: {', '.join(tab)})",
        )
    r = tab[size]
    lo, hi = _num(r["short"]), _num(r["long"])
    return ShoulderScrewSpec(
        size,
        _num(r["ds"]),
        _num(r["dk"]),
        _num(r["k"]),
        _num(r["b"]),
        _num(r["g2"]),
        thread_diameter_mm(size),
        tuple(float(x) for x in ISO7379_LENGTHS_MM if lo <= x <= hi),
    )


def thread_diameter_mm(size: str) -> float:
    """Nominal thread diameter of a metric size ``M6-1`` or ``M6`` (mm); a plain pin's diameter."""
    if is_dowel(size):
        return dowel_diameter_mm(size)
    try:
        return float(size[1:].split("-")[0])
    except ValueError:
        raise DesignError("parts", f"not a metric thread size: {size!r}") from None


@dataclass(frozen=True)
class NutSpec:
    """ISO 4032 hexagon nut: m_mm height, s_mm width across flats."""

    size: str
    m_mm: float
    s_mm: float


def get_nut(size: str, field: str = "parts.pin") -> NutSpec:
    if is_dowel(size):
        return ring_as_nut(size, field)
    tab = _table("hex_nut_parameters.csv", "iso4032")
    if size not in tab:
        raise DesignError(field, f"no ISO 4032 nut for {size!r}")
    return NutSpec(size, _num(tab[size]["m"]), _num(tab[size]["s"]))


@dataclass(frozen=True)
class WasherSpec:
    """ISO 7089 plain washer: d1_mm hole, d2_mm outside, h_mm thickness."""

    size: str
    d1_mm: float
    d2_mm: float
    h_mm: float


def get_washer(size: str, field: str = "parts.pin") -> WasherSpec:
    key = dowel_metric(size) if is_dowel(size) else size.split("-")[0]
    tab = _table("plain_washer_parameters.csv", "iso7089")
    if key not in tab:
        raise DesignError(field, f"no ISO 7089 washer for {size!r}")
    r = tab[key]
    return WasherSpec(key, _num(r["d1"]), _num(r["d2"]), _num(r["h"]))


@dataclass(frozen=True)
class CapScrewSpec:
    """ISO 4762 socket head cap screw: dk_mm head diameter, k_mm head height."""

    size: str
    dk_mm: float
    k_mm: float
    d_mm: float
    lengths_mm: tuple[float, ...]


ISO4762_LENGTHS_MM = (2.5, 3, 4, 5, 6, 8, 10, 12, 16, 20, 25, 30, 35, 40, 45, 50, 55, 60)


def get_cap_screw(size: str, field: str) -> CapScrewSpec:
    tab = _table("socket_head_cap_parameters.csv", "iso4762")
    if size not in tab:
        raise DesignError(
            field, f"unknown ISO 4762 cap screw {size!r} (bd_warehouse sizes: {', '.join(tab)})"
        )
    r = tab[size]
    lo, hi = _num(r["short"]), _num(r["long"])
    return CapScrewSpec(
        size,
        _num(r["dk"]),
        _num(r["k"]),
        thread_diameter_mm(size),
        tuple(float(x) for x in ISO4762_LENGTHS_MM if lo <= x <= hi),
    )


@dataclass(frozen=True)
class SetScrewSpec:
    """ISO 4026 hexagon socket set screw, flat point: d_mm thread diameter, lengths_mm the
    catalog lengths (bd_warehouse ``setscrew_parameters.csv`` short..long of the size, from
    the ISO 4026 list of ``nominal_screw_lengths.csv``)."""

    size: str
    d_mm: float
    lengths_mm: tuple[float, ...]


def get_set_screw(size: str, field: str) -> SetScrewSpec:
    tab = _table("setscrew_parameters.csv", "iso4026")
    if size not in tab:
        raise DesignError(
            field, f"unknown ISO 4026 set screw {size!r} (bd_warehouse sizes: {', '.join(tab)})"
        )
    lo, hi = _num(tab[size]["short"]), _num(tab[size]["long"])
    with open(bd_warehouse_data_dir() / "nominal_screw_lengths.csv", newline="",
              encoding="utf-8") as fh:
        row = next(r for r in csv.DictReader(fh) if r["Screw_Type"].strip() == "iso4026")
    nominal = (float(x) for x in row["Nominal_Sizes"].split(","))
    return SetScrewSpec(size, thread_diameter_mm(size), tuple(x for x in nominal if lo <= x <= hi))


def clearance_hole_mm(size: str, fit: str = "Normal") -> float:
    """ISO 273 clearance hole (bd_warehouse ``clearance_hole_sizes.csv``), mm."""
    key = size.split("-")[0]
    with open(
        bd_warehouse_data_dir() / "clearance_hole_sizes.csv", newline="", encoding="utf-8"
    ) as fh:
        for row in csv.DictReader(fh):
            if row["Size"].strip() == key:
                return _num(row[fit])
    raise DesignError("parts", f"no clearance hole size for {size!r}")


def tap_drill_mm(size: str) -> float:
    """Tap drill of a metric coarse thread: d - pitch (ISO rule of thumb), mm; a plain pin's
    press-fit hole (reamed to d). Without a stated pitch the coarse pitch of ISO 261 (M2 0.4,
    M2.5 0.45, ..., M8 1.25), so ``"M2.5"`` and ``"M2.5-0.45"`` give the same drill."""
    if is_dowel(size):
        return dowel_diameter_mm(size)
    parts = size[1:].split("-")
    d = float(parts[0])
    pitch = (
        float(parts[1])
        if len(parts) > 1
        else {2.0: 0.4, 2.5: 0.45, 3.0: 0.5, 4.0: 0.7, 5.0: 0.8, 6.0: 1.0, 8.0: 1.25}.get(d, 0.15 * d)
    )
    return d - pitch


def shortest_length(lengths: tuple[float, ...], at_least_mm: float) -> float | None:
    for L in lengths:
        if L >= at_least_mm - 1e-9:
            return L
    return None


# --------------------------------------------------------------------------- motors
#: MotorSpec fields that carry a data-sheet value with its own source (see MotorSpec.sources).
MOTOR_DATA_FIELDS = (
    "torque_constant_mNm_per_A", "terminal_resistance_ohm", "torque_continuous_mNm",
    "torque_peak_mNm", "stall_torque_mNm", "current_continuous_A",
    "thermal_resistance_housing_K_per_W", "thermal_resistance_winding_K_per_W",
    "no_load_current_mA", "rotor_inertia_g_cm2", "mass_kg",
)
#: MotorSpec data fields every build reads (datasheet forces, firmware current limits, simulator
#: actuator limits, the rotor in the dynamics, the motor's mass): a catalog motor without one of
#: them builds only when the design's ``[motor]`` table gives it (:func:`missing_build_fields`).
MOTOR_BUILD_FIELDS = (
    "torque_constant_mNm_per_A", "torque_continuous_mNm", "torque_peak_mNm",
    "current_continuous_A", "rotor_inertia_g_cm2", "mass_kg",
)
#: MotorSpec mounting dimensions (the solids of the motor, its mount and the capstan bore).
MOTOR_DIMENSION_FIELDS = (
    "body_diameter_mm", "body_length_mm", "pilot_diameter_mm", "pilot_height_mm",
    "bolt_circle_mm", "bolt_count", "bolt_size", "shaft_diameter_mm", "shaft_length_mm",
    "bolt_thread_depth_mm",
)


@dataclass(frozen=True)
class MotorSpec:
    """A direct-drive motor: catalog data and the mounting interface (mm, kg).

    body_diameter_mm / body_length_mm : housing cylinder below the mounting face.
    pilot_diameter_mm / pilot_height_mm : centring collar on the mounting face.
    bolt_circle_mm, bolt_count, bolt_size : tapped holes in the mounting face;
    bolt_thread_depth_mm : their usable thread depth (maxon RE 35 / RE 40 drawings: M3, 3.5 mm
    deep -- check the sheet of the exact order number).
    shaft_diameter_mm / shaft_length_mm : output shaft, length beyond the mounting face.
    mass_kg : catalog weight. rotor_inertia_g_cm2 : catalog rotor inertia Jm (None, like any
    data field, when no public source read states it: the design's ``[motor]`` must give it).
    dimension_notes : (dimension field, where its number comes from) for every mounting
    dimension of :data:`MOTOR_DIMENSION_FIELDS` that no public drawing read states (a recalled
    or assumed number): the BOM line names them, check the drawing before machining a mount.

    Electrical and thermal data of one winding (``winding``: order number and nominal voltage):

    * torque_constant_mNm_per_A : Kt; terminal_resistance_ohm : R at 25 C;
    * torque_continuous_mNm : maxon "nominal torque (max. continuous torque)";
      current_continuous_A : "nominal current (max. continuous current)";
    * stall_torque_mNm : data-sheet stall torque at nominal voltage;
    * torque_peak_mNm : the torque the drive may command (the actuator limit of the simulator
      exports and of ``hapticad wall``); here the stall torque unless ``sources`` says otherwise;
    * thermal_resistance_housing_K_per_W : housing-ambient; thermal_resistance_winding_K_per_W :
      winding-housing;
    * no_load_current_mA : I0, the current that overcomes brush and bearing friction at no-load
      speed (friction torque Kt * I0).

    ``sources`` maps each of :data:`MOTOR_DATA_FIELDS` to where its value comes from (data sheet
    title, edition, order number); ``unverified`` names the fields whose value has no public
    source that was read (derived or recalled values): every figure using one says so. A field
    is None when no value is known at all.
    """

    key: str
    description: str
    body_diameter_mm: float
    body_length_mm: float
    pilot_diameter_mm: float
    pilot_height_mm: float
    bolt_circle_mm: float
    bolt_count: int
    bolt_size: str
    shaft_diameter_mm: float
    shaft_length_mm: float
    mass_kg: float | None
    rotor_inertia_g_cm2: float | None
    source: str
    bolt_thread_depth_mm: float = 3.5
    winding: str = ""
    torque_constant_mNm_per_A: float | None = None
    terminal_resistance_ohm: float | None = None
    torque_continuous_mNm: float | None = None
    torque_peak_mNm: float | None = None
    stall_torque_mNm: float | None = None
    current_continuous_A: float | None = None
    thermal_resistance_housing_K_per_W: float | None = None
    thermal_resistance_winding_K_per_W: float | None = None
    no_load_current_mA: float | None = None
    #: (field, source) pairs, one per data field (tuple so the spec stays hashable).
    sources: tuple[tuple[str, str], ...] = ()
    unverified: tuple[str, ...] = ()
    dimension_notes: tuple[tuple[str, str], ...] = ()

    @property
    def rotor_inertia_kg_m2(self) -> float:
        if self.rotor_inertia_g_cm2 is None:
            raise DesignError("motor.rotor_inertia_g_cm2",
                              f"{self.key} has no rotor inertia from a public source: give it in [motor]")
        return self.rotor_inertia_g_cm2 * 1e-7

    @property
    def torque_source(self) -> str:
        """Source of ``torque_peak_mNm`` (kept for older callers)."""
        return self.source_of("torque_peak_mNm")

    def source_of(self, field: str) -> str:
        """Where the value of data field ``field`` comes from ('' when none is recorded)."""
        return dict(self.sources).get(field, "")

    def is_unverified(self, field: str) -> bool:
        """True when ``field`` has no value or a value without a public source that was read."""
        return getattr(self, field) is None or field in self.unverified

    def bom_description(self) -> str:
        """The BOM description: ``description``, then the data fields no public source states
        (``unverified``) and the mounting dimensions no drawing read states
        (``dimension_notes``), so an order and a datasheet read from the same line say so."""
        out = self.description
        if self.unverified:
            out += f"; unverified data (no public source read): {', '.join(self.unverified)}"
        if self.dimension_notes:
            out += f"; unverified mount dimensions: {', '.join(f for f, _ in self.dimension_notes)}"
        return out

    def missing_build_fields(self) -> tuple[str, ...]:
        """The fields of :data:`MOTOR_BUILD_FIELDS` without a value (a build refuses the motor
        until the design's ``[motor]`` table gives them)."""
        return tuple(f for f in MOTOR_BUILD_FIELDS if getattr(self, f) is None)

    def friction_torque_mNm(self) -> float | None:
        """Brush and bearing friction of the motor, Kt * I0 (mN m); None without data."""
        if self.torque_constant_mNm_per_A is None or self.no_load_current_mA is None:
            return None
        return self.torque_constant_mNm_per_A * self.no_load_current_mA * 1e-3


#: maxon RE 35, 30 V winding: the values of the public motor-constant file
#: MLohoefener/Mechatronische_Systeme_Master ``RE_35.m`` (commit 6176a66), which lists the
#: RE 35 data-sheet values L 0.34 mH, Kt 0.0389 N m/A, R 1.2 ohm, J 6.81e-6 kg m^2,
#: U_nom 30 V, T_nom 0.0972 N m (the maxon sheet's order number is not given there).
_RE35_SHEET = ("maxon RE 35 (35 mm, graphite brushes, 90 W) data sheet, 30 V winding, as listed in "
               "the public file MLohoefener/Mechatronische_Systeme_Master RE_35.m (commit 6176a66)")
#: maxon RE 40, order number 148877 (48 V): the sheet's tables 'Values at nominal voltage',
#: 'Characteristics', 'Thermal data' as reproduced in a public copy (edition not identified);
#: Kt 0.0603 N m/A and the continuous current 3.12 A 'from datasheet' (an older edition) are
#: also in the RAVEN II surgical robot's motor.h (RE 40 motor constants).
#: Kt of the RE 40 as the RAVEN II surgical robot's control software states it (a public
#: repository at a fixed commit).
_RAVEN_MOTOR_H = ("uw-biorobotics/raven2 include/raven/motor.h (commit 92eb7997, Copyright 2005-2012 "
                  "University of Washington BioRobotics Laboratory)")
_RE40_SHEET = ("maxon RE 40 (40 mm, graphite brushes, 150 W) data sheet, order number 148877, 48 V "
               "(edition not identified; Kt also in RAVEN II motor.h)")

#: Motor catalog. Dimensions are the nominal outline of the maxon data sheets
#: (RE 35: 90 W, graphite brushes; RE 40: 150 W) as used for mounting; check the
#: current sheet of the exact order number before machining a mount.
MOTORS: dict[str, MotorSpec] = {
    "maxon-re35": MotorSpec(
        key="maxon-re35",
        description="maxon RE 35, 90 W, graphite brushes (Hoeken paper prototype, §III.A)",
        body_diameter_mm=35.0,
        body_length_mm=70.9,
        pilot_diameter_mm=22.0,
        pilot_height_mm=2.0,
        bolt_circle_mm=28.0,
        bolt_count=3,
        bolt_size="M3-0.5",
        shaft_diameter_mm=6.0,
        shaft_length_mm=22.0,
        mass_kg=0.340,
        # maxon catalog: rotor inertia 65.2 to 79.2 g cm^2 across the RE 35 windings; the
        # upper value is kept (the conservative one for apparent mass; the 30 V winding below
        # has 68.1 g cm^2). Override with parts.motor_rotor_inertia_g_cm2 for a given order number.
        rotor_inertia_g_cm2=79.2,
        source="maxon motor catalog, RE 35 data sheet (weight 340 g; rotor inertia 65.2-79.2 g cm^2)",
        winding="RE 35, 30 V winding (order number not identified)",
        torque_constant_mNm_per_A=38.9,
        terminal_resistance_ohm=1.2,
        torque_continuous_mNm=97.2,
        # stall torque = Kt * U_N / R (maxon's definition of the stall torque at nominal voltage)
        stall_torque_mNm=972.5,
        torque_peak_mNm=972.5,
        # nominal current = T_N / Kt + I0 (maxon's relation), I0 below
        current_continuous_A=2.63,
        # no-load friction: the same file's viscous friction K_f 6.33e-6 N m s at the no-load
        # speed U_N / K_b = 773 rad/s is 4.9 mN m, i.e. I0 = 4.9 / 38.9 = 126 mA
        no_load_current_mA=126.0,
        sources=(
            ("torque_constant_mNm_per_A", _RE35_SHEET + " (K_m 0.0389 N m/A)"),
            ("terminal_resistance_ohm", _RE35_SHEET + " (R 1.2 ohm)"),
            ("torque_continuous_mNm", _RE35_SHEET + " (T_nom 0.0972 N m)"),
            ("stall_torque_mNm", "derived: Kt * U_N / R = 38.9 mN m/A * 30 V / 1.2 ohm from " + _RE35_SHEET),
            ("torque_peak_mNm", "the stall torque (no drive current limit stated)"),
            ("current_continuous_A", "derived: T_N / Kt + I0 = 97.2 / 38.9 + 0.126 A"),
            ("thermal_resistance_housing_K_per_W", "no public source found"),
            ("thermal_resistance_winding_K_per_W", "no public source found"),
            ("no_load_current_mA", "derived: K_f * U_N / K_b / Kt from " + _RE35_SHEET + " (K_f 6.33e-6 N m s)"),
            ("rotor_inertia_g_cm2", "maxon catalog RE 35 range 65.2-79.2 g cm^2 (upper value; edition not "
             "identified)"),
            ("mass_kg", "maxon catalog RE 35 (weight 340 g; edition not identified)"),
        ),
        unverified=("stall_torque_mNm", "torque_peak_mNm", "current_continuous_A",
                    "no_load_current_mA", "thermal_resistance_housing_K_per_W",
                    "thermal_resistance_winding_K_per_W", "rotor_inertia_g_cm2", "mass_kg"),
    ),
    "maxon-re40": MotorSpec(
        key="maxon-re40",
        description="maxon RE 40, 150 W, graphite brushes",
        body_diameter_mm=40.0,
        body_length_mm=71.0,
        pilot_diameter_mm=26.0,
        pilot_height_mm=2.0,
        bolt_circle_mm=31.0,
        bolt_count=3,
        bolt_size="M3-0.5",
        shaft_diameter_mm=6.0,
        shaft_length_mm=22.0,
        mass_kg=0.480,
        # the 148877 sheet edition read lists 137 g cm^2; 134 g cm^2 (other editions) is kept
        rotor_inertia_g_cm2=134.0,
        source="maxon motor catalog, RE 40 data sheet (weight 480 g; rotor inertia 134 g cm^2)",
        winding="RE 40, order number 148877, 48 V",
        torque_constant_mNm_per_A=60.3,
        terminal_resistance_ohm=1.13,
        torque_continuous_mNm=187.0,
        stall_torque_mNm=2560.0,
        torque_peak_mNm=2560.0,
        current_continuous_A=3.17,
        thermal_resistance_housing_K_per_W=4.65,
        thermal_resistance_winding_K_per_W=1.93,
        no_load_current_mA=68.6,
        sources=(
            ("torque_constant_mNm_per_A", _RAVEN_MOTOR_H + ": T_PER_AMP_RE40 0.0603 Nm/A 'From datasheet' "
             "(the same 60.3 mNm/A as the 148877 sheet copy)"),
            ("terminal_resistance_ohm", _RE40_SHEET + ": terminal resistance 1.13 ohm"),
            ("torque_continuous_mNm", _RE40_SHEET + ": nominal torque (max. continuous torque) 187 mNm"),
            ("stall_torque_mNm", _RE40_SHEET + ": stall torque 2560 mNm"),
            ("torque_peak_mNm", "the stall torque of " + _RE40_SHEET + " (no drive current limit stated)"),
            ("current_continuous_A", _RE40_SHEET + ": nominal current (max. continuous current) 3.17 A"),
            ("thermal_resistance_housing_K_per_W", _RE40_SHEET + ": thermal resistance housing-ambient 4.65 K/W"),
            ("thermal_resistance_winding_K_per_W", _RE40_SHEET + ": thermal resistance winding-housing 1.93 K/W"),
            ("no_load_current_mA", _RE40_SHEET + ": no load current 68.6 mA"),
            ("rotor_inertia_g_cm2", "maxon catalog RE 40 (134 g cm^2; the 148877 sheet read: 137; edition not "
             "identified)"),
            ("mass_kg", "maxon catalog RE 40 (weight 480 g; edition not identified)"),
        ),
        # the sheet copy these were read from names no edition and no public copy stating them
        # was found (issue 34 §3: a search of stored pages and docs for the 148877 sheet found
        # none); Kt is also in RAVEN II motor.h, so it stays verified
        unverified=("terminal_resistance_ohm", "torque_continuous_mNm", "stall_torque_mNm",
                    "torque_peak_mNm", "current_continuous_A", "thermal_resistance_housing_K_per_W",
                    "thermal_resistance_winding_K_per_W", "no_load_current_mA", "rotor_inertia_g_cm2",
                    "mass_kg"),
    ),
}


#: maxon DCX 22 L (coreless, graphite brushes), 9 V configuration: the public motor-constant
#: file mattchg/ELEC441 ``MotorSpecs.m`` (commit 6defeac3), headed "MAXON CONFIGURABLE DCX 22 L
#: Ø22 mm", which lists the configurator's sheet: 9 V, 27 mN m nominal torque, 4 A nominal
#: current, 371 mN m stall torque, 53.4 A stall current, 0.168 ohm, 6.95 mN m/A, 9.37 g cm^2,
#: 95 g, Ø22 x 47.2 mm (no order number: the DCX is configured online).
_DCX22L_FILE = ("mattchg/ELEC441 MotorSpecs.m (commit 6defeac37499, 'MAXON CONFIGURABLE DCX 22 L Ø22 mm', "
                "9 V configuration, order number not stated)")
#: maxon RE 30 of the WoodenHaptics kit: BOM v1.1 "Maxon 30mm (310009) & 500 CPR Encoder
#: combination" and the 2017 edition notes (RE 40 -> RE 30: "RE30 has a 5 mm shaft"; "M3 screws
#: on a Ø22 bolt circle", marked there as shared with the RE 40) of WoodenHaptics/TEI_2015
#: (commit 5b13c398); the torque constant 0.0259 N m/A of the kit's 2016-edition driver
#: configuration WoodenHaptics/woody-experimental ``woodenhaptics_2016ed.json`` (commit
#: 03cf1787), which does not name the winding.
_WOODY_BOM = ("WoodenHaptics/TEI_2015 '2017-edition/bom/WoodenHaptics Bill of Materials - 2017 Edition "
              "(Ver 1.1 with 30mm motors and USB).csv' (commit 5b13c39896bb): 'Maxon 30mm (310009)'")
_WOODY_NOTES = "WoodenHaptics/TEI_2015 2017-edition/README.md (commit 5b13c39896bb)"
_WOODY_JSON = ("WoodenHaptics/woody-experimental woodenhaptics_2016ed.json (commit 03cf1787dc6a): "
               "torque_constant_motor_a/b/c 0.0259 N m/A (winding not named there)")
#: maxon EC 45 flat 50 W, order number 339285: the public constants file vhsabino/MATLAB
#: ``PIDMaxon/constants.m`` (commit f1d40f8f), "Maxon EC-45 flat 50W parameters, Ref. 339285":
#: R 0.464 ohm phase to phase, Kt 25.1 mN m/A, speed constant 380 rpm/V, mechanical time
#: constant 9.92 ms, rotor inertia 135 g cm^2 (no voltage, torque or current values).
_EC45_FILE = ("vhsabino/MATLAB PIDMaxon/constants.m (commit f1d40f8f5cfe, 'Maxon EC-45 flat 50W parameters, "
              "Ref. 339285')")
_NO_SOURCE = "no public source read states it (give it in [motor] from the sheet of your order number)"


def _missing(*fields: str) -> tuple[tuple[str, str], ...]:
    return tuple((f, _NO_SOURCE) for f in fields)


_RECALLED = "recalled from the maxon drawing, not read in a public source: check the drawing"
_ASSUMED = "assumed (no drawing read): check the drawing of the order number"

MOTORS["maxon-dcx22l"] = MotorSpec(
    key="maxon-dcx22l",
    description="maxon DCX 22 L, coreless, graphite brushes, 9 V (configurable)",
    body_diameter_mm=22.0,
    body_length_mm=47.2,
    pilot_diameter_mm=10.0,
    pilot_height_mm=1.0,
    bolt_circle_mm=16.0,
    bolt_count=3,
    bolt_size="M2-0.4",
    shaft_diameter_mm=4.0,
    # the DCX is configured online, its shaft length too: order a 20 mm front shaft
    shaft_length_mm=20.0,
    mass_kg=0.095,
    rotor_inertia_g_cm2=9.37,
    source=_DCX22L_FILE,
    bolt_thread_depth_mm=3.0,
    winding="DCX 22 L, 9 V configuration (configured online; order number not stated)",
    torque_constant_mNm_per_A=6.95,
    terminal_resistance_ohm=0.168,
    torque_continuous_mNm=27.0,
    stall_torque_mNm=371.0,
    torque_peak_mNm=371.0,
    current_continuous_A=4.0,
    # the file's third line, "118 % Nominal Current (mA)", sits where the sheet lists the
    # no-load current (mA) and is one: 27 / 6.95 + 0.118 = 4.003 A, the nominal current
    no_load_current_mA=118.0,
    sources=(
        ("torque_constant_mNm_per_A", _DCX22L_FILE + ": 6.95 Torque Constant mNm/A"),
        ("terminal_resistance_ohm", _DCX22L_FILE + ": 0.168 Term ROhms"),
        ("torque_continuous_mNm", _DCX22L_FILE + ": 27 Nominal Torque (mNm)"),
        ("stall_torque_mNm", _DCX22L_FILE + ": 371 Stall Torque (mNm)"),
        ("torque_peak_mNm", "the stall torque of " + _DCX22L_FILE + " (no drive current limit stated)"),
        ("current_continuous_A", _DCX22L_FILE + ": 4 Nominal Current (A)"),
        ("thermal_resistance_housing_K_per_W", _NO_SOURCE),
        ("thermal_resistance_winding_K_per_W", _NO_SOURCE),
        ("no_load_current_mA", _DCX22L_FILE + ": '118 % Nominal Current (mA)', the no-load current line "
         "of the sheet (mislabelled there; T_N / Kt + I0 = 4.00 A = the nominal current)"),
        ("rotor_inertia_g_cm2", _DCX22L_FILE + ": 9.37 Rotor Inertia gcm^2"),
        ("mass_kg", _DCX22L_FILE + ": 95 Weight g"),
    ),
    unverified=("thermal_resistance_housing_K_per_W", "thermal_resistance_winding_K_per_W",
                "no_load_current_mA"),
    dimension_notes=(
        ("body_diameter_mm", _DCX22L_FILE + ": 22 Diameter mm (read)"),
        ("body_length_mm", _DCX22L_FILE + ": 47.2 Length mm (read)"),
        ("pilot_diameter_mm", _RECALLED), ("pilot_height_mm", _ASSUMED),
        ("bolt_circle_mm", _RECALLED), ("bolt_count", _RECALLED), ("bolt_size", _RECALLED),
        ("bolt_thread_depth_mm", _ASSUMED), ("shaft_diameter_mm", _RECALLED),
        ("shaft_length_mm", "our choice: the DCX is configured online, its front shaft length too "
         "(order 20 mm)"),
    ),
)

MOTORS["maxon-re30"] = MotorSpec(
    key="maxon-re30",
    description="maxon RE 30, 60 W, graphite brushes (WoodenHaptics kit, 2017 edition: 310009)",
    body_diameter_mm=30.0,
    body_length_mm=68.0,
    pilot_diameter_mm=16.0,
    pilot_height_mm=2.0,
    bolt_circle_mm=22.0,
    bolt_count=3,
    bolt_size="M3-0.5",
    shaft_diameter_mm=5.0,
    shaft_length_mm=20.0,
    mass_kg=None,
    rotor_inertia_g_cm2=None,
    source=_WOODY_BOM,
    winding="RE 30 of the WoodenHaptics kit (BOM v1.1: 310009; the driver's Kt names no winding)",
    torque_constant_mNm_per_A=25.9,
    sources=(("torque_constant_mNm_per_A", _WOODY_JSON),
             *_missing("terminal_resistance_ohm", "torque_continuous_mNm", "torque_peak_mNm",
                       "stall_torque_mNm", "current_continuous_A", "thermal_resistance_housing_K_per_W",
                       "thermal_resistance_winding_K_per_W", "no_load_current_mA", "rotor_inertia_g_cm2",
                       "mass_kg")),
    # the Kt is the kit's driver configuration, not a sheet of 310009 (a 48 V winding per the
    # kit's BOM; the value is not stated to be that winding's): unverified for that order number
    unverified=("torque_constant_mNm_per_A",),
    dimension_notes=(
        ("body_diameter_mm", _WOODY_BOM + " (the 30 mm of the name)"),
        ("body_length_mm", _RECALLED),
        ("pilot_diameter_mm", _ASSUMED), ("pilot_height_mm", _ASSUMED),
        ("bolt_circle_mm", _WOODY_NOTES + ": 'M3 screws on a Ø22 bolt circle' (a kit note, not a drawing)"),
        ("bolt_count", _ASSUMED), ("bolt_size", _WOODY_NOTES + ": 'M3 screws'"),
        ("bolt_thread_depth_mm", _ASSUMED),
        ("shaft_diameter_mm", _WOODY_NOTES + ": 'RE30 has a 5 mm shaft'"),
        ("shaft_length_mm", _ASSUMED),
    ),
)

MOTORS["maxon-ec45flat"] = MotorSpec(
    key="maxon-ec45flat",
    description="maxon EC 45 flat, 50 W, brushless, order number 339285",
    body_diameter_mm=42.8,
    body_length_mm=21.3,
    pilot_diameter_mm=18.0,
    pilot_height_mm=1.0,
    bolt_circle_mm=34.0,
    bolt_count=3,
    bolt_size="M3-0.5",
    shaft_diameter_mm=3.0,
    shaft_length_mm=10.0,
    mass_kg=None,
    rotor_inertia_g_cm2=135.0,
    source=_EC45_FILE,
    winding="EC 45 flat 50 W, order number 339285",
    torque_constant_mNm_per_A=25.1,
    terminal_resistance_ohm=0.464,
    sources=(("torque_constant_mNm_per_A", _EC45_FILE + ": Kt = 25.1e-3 N m/A"),
             ("terminal_resistance_ohm", _EC45_FILE + ": R = 0.464 ohm, phase to phase"),
             ("rotor_inertia_g_cm2", _EC45_FILE + ": J = 135e-7 kg m^2"),
             *_missing("torque_continuous_mNm", "torque_peak_mNm", "stall_torque_mNm",
                       "current_continuous_A", "thermal_resistance_housing_K_per_W",
                       "thermal_resistance_winding_K_per_W", "no_load_current_mA", "mass_kg")),
    dimension_notes=(
        ("body_diameter_mm", _RECALLED), ("body_length_mm", _RECALLED),
        ("pilot_diameter_mm", _ASSUMED), ("pilot_height_mm", _ASSUMED),
        ("bolt_circle_mm", _ASSUMED), ("bolt_count", _ASSUMED), ("bolt_size", _ASSUMED),
        ("bolt_thread_depth_mm", _ASSUMED), ("shaft_diameter_mm", _RECALLED),
        ("shaft_length_mm", _ASSUMED),
    ),
)


#: maxon RE 25, 20 W, graphite brushes, order number 118752 (24 V): the public motor-model file
#: oliv5/apbteam ``digital/asserv/models/motor.m`` (commit 4839708f, "Maxon RE25G 20W 24V
#: 118752"): speed constant 407 rpm/V, Kt 23.4 mN m/A, R 2.32 ohm, L 0.24 mH, J 10.3 g cm^2.
#: It states no torque, current, no-load current or weight (nor does any other source read:
#: issue 35 §2), so a build asks the design's [motor] for them and the search leaves it out.
_RE25_FILE = ("oliv5/apbteam digital/asserv/models/motor.m (commit 4839708f1d60, 'Maxon RE25G 20W 24V "
              "118752')")

MOTORS["maxon-re25"] = MotorSpec(
    key="maxon-re25",
    description="maxon RE 25, 20 W, graphite brushes, 24 V, order number 118752",
    body_diameter_mm=25.0,
    body_length_mm=54.0,
    pilot_diameter_mm=10.0,
    pilot_height_mm=1.0,
    bolt_circle_mm=16.0,
    bolt_count=2,
    bolt_size="M2-0.4",
    shaft_diameter_mm=4.0,
    shaft_length_mm=12.0,
    mass_kg=None,
    rotor_inertia_g_cm2=10.3,
    source=_RE25_FILE,
    bolt_thread_depth_mm=3.0,
    winding="RE 25, 20 W, graphite brushes, order number 118752, 24 V",
    torque_constant_mNm_per_A=23.4,
    terminal_resistance_ohm=2.32,
    sources=(("torque_constant_mNm_per_A", _RE25_FILE + ": Km = 23.4 / 1000 N m/A"),
             ("terminal_resistance_ohm", _RE25_FILE + ": R = 2.32 ohm"),
             ("rotor_inertia_g_cm2", _RE25_FILE + ": J = 10.3 g cm^2 (10.3 / 1000 / 10000 kg m^2)"),
             *_missing("torque_continuous_mNm", "torque_peak_mNm", "stall_torque_mNm",
                       "current_continuous_A", "thermal_resistance_housing_K_per_W",
                       "thermal_resistance_winding_K_per_W", "no_load_current_mA", "mass_kg")),
    dimension_notes=(
        ("body_diameter_mm", _RE25_FILE + " (the 25 mm of the name)"),
        ("body_length_mm", _ASSUMED), ("pilot_diameter_mm", _ASSUMED), ("pilot_height_mm", _ASSUMED),
        ("bolt_circle_mm", _ASSUMED), ("bolt_count", _ASSUMED), ("bolt_size", _ASSUMED),
        ("bolt_thread_depth_mm", _ASSUMED), ("shaft_diameter_mm", _ASSUMED), ("shaft_length_mm", _ASSUMED),
    ),
)


def get_motor(key: str, field: str = "parts.motor") -> MotorSpec:
    if key not in MOTORS:
        raise DesignError(field, f"unknown motor {key!r} (catalog: {', '.join(MOTORS)})")
    return MOTORS[key]


# --------------------------------------------------------------------------- encoders
@dataclass(frozen=True)
class EncoderSpec:
    """A shaft encoder on the crank: ``counts_per_rev`` after quadrature decoding, its mass
    (None: not known) and the source of each value."""

    key: str
    description: str
    counts_per_rev: int
    mass_kg: float | None
    source: str


#: Encoder catalog. ``optical-2000``: the Hoeken prototype's "general purpose 2000 counts/rev
#: optical encoder" (paper §III.A); ``maxon-hedl5540-500``: maxon HEDL 5540, 500 counts per turn,
#: 3 channels, the encoder maxon combines with the RE 35 / RE 40 (x4 quadrature = 2000 counts);
#: ``optical-4000``: the haptic mouse's "1000 window (4000 cpt) optical encoder" (isotropy paper
#: §3.2), the default of the pantograph, twin-pantograph and pen designs.
ENCODERS: dict[str, EncoderSpec] = {
    "optical-2000": EncoderSpec(
        "optical-2000", "optical encoder, 2000 counts/rev (quadrature)", 2000, None,
        "Hoeken paper §III.A: 'a general purpose 2000 counts/rev optical encoder' (mass unverified)"),
    "maxon-hedl5540-500": EncoderSpec(
        "maxon-hedl5540-500", "maxon encoder HEDL 5540, 500 CPT, 3 channels (2000 counts/rev x4)",
        2000, None, "maxon catalog, Encoder HEDL 5540, 500 counts per turn (mass unverified)"),
    "optical-4000": EncoderSpec(
        "optical-4000", "optical encoder, 1000 windows, 4000 counts/rev (quadrature)", 4000, None,
        "isotropy paper §3.2: 'sensed by a 1000 window (4000 cpt) optical encoder' (mass unverified)"),
}
#: Encoder assumed when a four-bar design names none (the Hoeken paper prototype's).
DEFAULT_ENCODER = "optical-2000"
#: Encoder of the isotropy paper's devices (pantograph, twin pantograph, pen): §3.2.
PAPER_MOUSE_ENCODER = "optical-4000"


def get_encoder(key: str, field: str = "parts.encoder") -> EncoderSpec:
    if key not in ENCODERS:
        raise DesignError(field, f"unknown encoder {key!r} (catalog: {', '.join(ENCODERS)})")
    return ENCODERS[key]


def polar_points_mm(
    radius_mm: float, count: int, start_deg: float = 90.0
) -> list[tuple[float, float]]:
    """``count`` points evenly on a circle of ``radius_mm`` (first at ``start_deg``)."""
    return [
        (
            radius_mm * math.cos(math.radians(start_deg + 360.0 * i / count)),
            radius_mm * math.sin(math.radians(start_deg + 360.0 * i / count)),
        )
        for i in range(count)
    ]


# --------------------------------------------------------------------------- plain pins
#: Plain joint pins ("dowel-<d>"): ground pins h6/m6 of diameter d (ISO 2338 / ISO 8734
#: sizes) retained by DIN 471 rings in grooves, with an ISO 7089 washer under the lower
#: link. The layer model (:mod:`cad.families.fourbar.layers`) treats a pin like a shoulder screw
#: whose "head" is the upper retaining ring and whose "nut" is the lower ring (see
#: :func:`dowel_as_shoulder_screw`); the pin material is ``parts.pin_material``.
DOWEL_PREFIX = "dowel-"
DOWEL_DIAMETERS_MM = (3.0, 4.0, 5.0, 6.0, 8.0)
#: ISO 2338 / ISO 8734 nominal lengths (mm).
ISO2338_LENGTHS_MM = (6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30, 32, 35, 40, 45, 50, 55, 60)
#: Pin length beyond a ring groove (mm): the groove needs a land to hold the ring.
RING_LAND_MM = 0.5
#: Extra pin below the lower link beyond washer and ring (mm), so the layer model's
#: shoulder entry window (shoulder end 0.5..1 mm above the lower link's bottom) is not empty.
DOWEL_WINDOW_MM = 1.0


def is_dowel(size: str) -> bool:
    """True for a plain pin designation ``dowel-<d>``."""
    return isinstance(size, str) and size.startswith(DOWEL_PREFIX)


def dowel_diameter_mm(size: str, field: str = "parts.pin") -> float:
    """Diameter of ``dowel-<d>`` (mm); DesignError for a size outside :data:`DOWEL_DIAMETERS_MM`."""
    try:
        d = float(size[len(DOWEL_PREFIX):])
    except ValueError:
        d = -1.0
    if d not in DOWEL_DIAMETERS_MM:
        raise DesignError(
            field,
            f"unknown plain pin {size!r} (sizes: {', '.join(f'dowel-{x:g}' for x in DOWEL_DIAMETERS_MM)})",
        )
    return d


@dataclass(frozen=True)
class RetainingRingSpec:
    """DIN 471 external retaining ring (bd_warehouse ``din471.csv``) for shaft d1_mm:
    s_mm thickness, d2_mm groove diameter, m_mm groove width, d4_mm outside diameter when
    fitted (free space needed), mass_kg (table column W, kg per 1000 pieces / 1000)."""

    d1_mm: float
    s_mm: float
    d2_mm: float
    m_mm: float
    d4_mm: float
    mass_kg: float


def get_retaining_ring(d_mm: float, field: str = "parts.pin") -> RetainingRingSpec:
    with open(bd_warehouse_data_dir() / "din471.csv", newline="", encoding="utf-8") as fh:
        for row in csv.DictReader(fh):
            if abs(_num(row["d1"]) - d_mm) < 1e-9:
                return RetainingRingSpec(
                    d_mm, _num(row["s"]), _num(row["d2"]), _num(row["m"]), _num(row["d4"]),
                    _num(row["W"]) * 1e-3,
                )
    raise DesignError(field, f"no DIN 471 retaining ring for a {d_mm:g} mm pin")


def dowel_metric(size: str) -> str:
    """ISO 7089 washer key of a plain pin (``dowel-3`` -> ``M3``)."""
    return f"M{dowel_diameter_mm(size):g}"


def dowel_as_shoulder_screw(size: str, field: str = "parts.pin") -> ShoulderScrewSpec:
    """A plain pin in the shoulder-screw form the layer model uses.

    ds = d; "head" = the upper ring: dk = d4, k = groove width + land; "thread" = the pin
    below the shoulder end at the same diameter: b = washer + lower ring groove + land +
    :data:`DOWEL_WINDOW_MM`; g2 = 0. ``lengths_mm`` are shoulder lengths L with
    k + L + b an ISO 2338 length, so the bought pin has a catalog length.
    """
    d = dowel_diameter_mm(size, field)
    ring = get_retaining_ring(d, field)
    w = get_washer(dowel_metric(size), field)
    k = ring.m_mm + RING_LAND_MM
    b = w.h_mm + ring.m_mm + RING_LAND_MM + DOWEL_WINDOW_MM
    lengths = tuple(round(L - k - b, 6) for L in ISO2338_LENGTHS_MM if L - k - b > 0)
    return ShoulderScrewSpec(size, d, ring.d4_mm, k, b, 0.0, d, lengths)


def dowel_total_length_mm(size: str, shoulder_length_mm: float) -> float:
    """Bought length of a plain pin whose layer-model shoulder is ``shoulder_length_mm``."""
    s = dowel_as_shoulder_screw(size)
    return s.k_mm + shoulder_length_mm + s.b_mm


def ring_as_nut(size: str, field: str = "parts.pin") -> NutSpec:
    """The lower retaining ring in the nut form of the layer model: m = ring thickness,
    s (across flats) chosen so the envelope radius s / sqrt(3) is d4 / 2."""
    ring = get_retaining_ring(dowel_diameter_mm(size, field), field)
    return NutSpec(size, ring.s_mm, ring.d4_mm * math.sqrt(3.0) / 2.0)


def standoff_screw(pin: str) -> str:
    """ISO 4762 size of the post and leg screws: the pin's thread size for a shoulder
    screw (as before), M4 for plain pins (a 3-8 mm press-fit pin has no thread)."""
    return "M4-0.7" if is_dowel(pin) else pin


def pin_description(pin: str, shoulder_length_mm: float) -> str:
    if is_dowel(pin):
        d = dowel_diameter_mm(pin)
        L = dowel_total_length_mm(pin, shoulder_length_mm)
        return f"ground pin ISO 2338 {d:g} m6 x {L:g}, grooved for DIN 471 rings"
    return f"shoulder screw ISO 7379 {pin} x {shoulder_length_mm:g}"


def bearings_with_bore(d_mm: float) -> list[str]:
    """bd_warehouse SKT bearing sizes with bore ``d_mm``."""
    return [s for s in bearing_sizes() if abs(get_bearing(s).d_mm - d_mm) < 1e-9]


def pins_for_bore(d_mm: float) -> list[str]:
    """Pin designations (shoulder screws and plain pins) whose shoulder fits bore ``d_mm``."""
    out = [f"dowel-{d:g}" for d in DOWEL_DIAMETERS_MM if abs(d - d_mm) < 1e-9]
    for s in _table("shoulder_screw.csv", "iso7379"):
        if abs(_num(_table("shoulder_screw.csv", "iso7379")[s]["ds"]) - d_mm) < 1e-9:
            out.append(s)
    return out
