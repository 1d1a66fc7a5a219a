"""PowerMouse design files (family ``powermouse``; isotropy paper section 5-6, Fig. 6-8, Table 4).

Schema (units in key names; every table but [mechanism] and [actuator] optional)::

    name = "powermouse"              # top level, required: output folder name

    [mechanism]
    family = "powermouse"

    [actuator]                       # one flat-coil actuator, used on all six faces
    magnet_length_mm = 20.0          # l_m (required)
    magnet_width_mm = 8.0            # w_m (required)
    magnet_thickness_mm = 4.0        # t_m (required)
    rattle_mm = 6.0                  # d_r = d - d_c (required); +-d_r/2 of normal travel
    gap_mm = 10.8                    # optional: magnet gap d; omitted -> the eq (8)-(9) optimum
    field_model = "closed-form"      # closed-form | images | magpylib (for the optimum)
    power_W = 8.0                    # continuous coil power (Fig. 8)
    peak_power_W = 36.0              # peak coil power (for peak force / acceleration)
    br_T = 1.2                       # magnet remanence
    resistivity_ohm_m = 1.72e-8      # coil conductor (copper)
    eta_pack = 0.75                  # coil packing efficiency
    plate_alpha = 0.5                # back-iron plate t_s = plate_alpha * w_m (t_s >= alpha w_m)

    [flotor]
    edge_mm = 64.0                   # outer edge of the cubic flotor shell
    material = "delrin"              # shell material (non-conducting: no eddy currents)
    coil_material = "copper"         # coil conductor; coil density = eta_pack * rho_conductor
    corner_hole_mm = 25.8            # the corner hole for the stator post (room for its motion)

    [stator]
    housing_material = "aluminium-6061"
    housing_wall_mm = 4.0
    iron_material = "soft-iron"      # back-iron plates and the inner core
    magnet_material = "ndfeb-n42"
    post_diameter_mm = 8.0          # stator post to the inner core (along -(1,1,1))

    [handle]
    length_mm = 45.0                 # from the flotor corner along +(1,1,1)
    diameter_mm = 10.0
    knob_diameter_mm = 24.0
    material = "delrin"

    [motion]
    range_mm = 3.0                   # translation range +- (Table 4)
    range_deg = 5.0                  # rotation range +- (Table 4)

Geometry derived in :mod:`cad.families.powermouse.parts`; the flotor frame has its
origin at the cube centre and axes normal to the faces.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from cad.actuators.voicecoil import VoiceCoilParams
from cad.data.materials import get_material
from cad.design.fields import (
    check_name,
    check_unknown,
    optional_number,
    optional_positive,
    optional_table,
    require_positive,
    require_str,
    require_table,
)
from cad.design.replace import TableReplace, ValidatedReplace
from cad.design.targets import POWERMOUSE_TARGET_KEYS, parse_targets
from cad.errors import DesignError

TOP_KEYS = ("name", "description", "mechanism", "actuator", "flotor", "stator", "handle", "motion",
            "prices", "targets")
ACTUATOR_KEYS = (
    "magnet_length_mm",
    "magnet_width_mm",
    "magnet_thickness_mm",
    "rattle_mm",
    "gap_mm",
    "field_model",
    "power_W",
    "peak_power_W",
    "br_T",
    "resistivity_ohm_m",
    "eta_pack",
    "plate_alpha",
)
FIELD_MODELS = ("closed-form", "images", "magpylib")


@dataclass(frozen=True)
class ActuatorSpec(TableReplace):
    """[actuator]: magnet sizes (mm), rattle d_r (mm), optional gap (mm), electrical data."""

    magnet_length_mm: float
    magnet_width_mm: float
    magnet_thickness_mm: float
    rattle_mm: float
    gap_mm: float | None
    field_model: str
    power_W: float
    peak_power_W: float
    br_T: float
    resistivity_ohm_m: float
    eta_pack: float
    plate_alpha: float

    @property
    def plate_thickness_mm(self) -> float:
        """Back-iron plate thickness t_s = alpha w_m (paper: t_s >= alpha w_m)."""
        return self.plate_alpha * self.magnet_width_mm

    def params(self, power_W: float | None = None):
        """The :class:`cad.actuators.voicecoil.VoiceCoilParams` of this actuator."""
        return VoiceCoilParams(
            self.magnet_length_mm,
            self.magnet_width_mm,
            self.magnet_thickness_mm,
            self.rattle_mm,
            self.power_W if power_W is None else power_W,
            self.br_T,
            self.resistivity_ohm_m,
            self.eta_pack,
        )


@dataclass(frozen=True)
class FlotorSpec(TableReplace):
    """[flotor]: outer edge (mm), shell and coil materials, corner hole diameter (mm)."""

    edge_mm: float = 64.0
    material: str = "delrin"
    coil_material: str = "copper"
    corner_hole_mm: float = 25.8


@dataclass(frozen=True)
class StatorSpec(TableReplace):
    """[stator]: housing material and wall (mm), iron and magnet materials, post diameter (mm)."""

    housing_material: str = "aluminium-6061"
    housing_wall_mm: float = 4.0
    iron_material: str = "soft-iron"
    magnet_material: str = "ndfeb-n42"
    post_diameter_mm: float = 8.0


@dataclass(frozen=True)
class HandleSpec(TableReplace):
    """[handle]: stem length and diameter, knob diameter (mm), material."""

    length_mm: float = 45.0
    diameter_mm: float = 10.0
    knob_diameter_mm: float = 24.0
    material: str = "delrin"


@dataclass(frozen=True)
class MotionSpec(TableReplace):
    """[motion]: translation range +- (mm) and rotation range +- (deg) (Table 4)."""

    range_mm: float = 3.0
    range_deg: float = 5.0


@dataclass(frozen=True)
class PowerMouseDesign(ValidatedReplace):
    """A validated PowerMouse design (see module docstring for the keys)."""

    name: str
    source: str
    family: str
    actuator: ActuatorSpec
    flotor: FlotorSpec
    stator: StatorSpec
    handle: HandleSpec
    motion: MotionSpec
    raw: dict
    targets: tuple = ()


def _material(table: dict, key: str, prefix: str, default: str) -> str:
    if key not in table:
        return default
    return get_material(require_str(table, key, prefix), f"{prefix}.{key}").name


def _parse_actuator(t: dict) -> ActuatorSpec:
    p = "actuator"
    check_unknown(t, ACTUATOR_KEYS, p)
    lm = require_positive(t, "magnet_length_mm", p)
    wm = require_positive(t, "magnet_width_mm", p)
    tm = require_positive(t, "magnet_thickness_mm", p)
    dr = require_positive(t, "rattle_mm", p)
    gap = optional_positive(t, "gap_mm", p, None)
    if gap is not None and gap <= dr:
        raise DesignError(
            "actuator.gap_mm",
            f"{gap:g} mm must exceed actuator.rattle_mm = {dr:g} mm to leave room for a coil; "
            "raise actuator.gap_mm or lower actuator.rattle_mm",
        )
    model = t.get("field_model", "closed-form")
    if model not in FIELD_MODELS:
        raise DesignError(
            "actuator.field_model", f"unknown model {model!r} (known: {', '.join(FIELD_MODELS)})"
        )
    power = optional_positive(t, "power_W", p, 8.0)
    peak = optional_positive(t, "peak_power_W", p, 36.0)
    if peak < power:
        raise DesignError("actuator.peak_power_W", f"{peak:g} W must be >= actuator.power_W = {power:g} W "
                          "(the peak is the largest power); raise actuator.peak_power_W or lower actuator.power_W")
    eta = optional_positive(t, "eta_pack", p, 0.75)
    if eta > 1:
        raise DesignError("actuator.eta_pack", f"must be in (0, 1], got {eta!r}")
    alpha = optional_number(t, "plate_alpha", p, 0.5)
    if alpha <= 0:
        raise DesignError("actuator.plate_alpha", f"must be > 0, got {alpha!r}")
    return ActuatorSpec(
        lm,
        wm,
        tm,
        dr,
        gap,
        model,
        power,
        peak,
        optional_positive(t, "br_T", p, 1.2),
        optional_positive(t, "resistivity_ohm_m", p, 1.72e-8),
        eta,
        alpha,
    )


def parse(raw: dict[str, Any], source: str = "<design>") -> PowerMouseDesign:
    """Validate a raw PowerMouse design mapping (see module docstring)."""
    if "transmission" in raw:
        raise DesignError("transmission", "the PowerMouse's actuators are voice coils pushing the "
                          "flotor directly (no motor shaft or joint to put a capstan on); remove "
                          "[transmission] (docs/capstan.md)")
    check_unknown(raw, TOP_KEYS, "")
    name = check_name(require_str(raw, "name", ""))
    mech = require_table(raw, "mechanism", "")
    check_unknown(mech, ("family",), "mechanism")
    family = require_str(mech, "family", "mechanism")
    if family != "powermouse":
        raise DesignError("mechanism.family", f"expected 'powermouse', got {family!r}")
    act = _parse_actuator(require_table(raw, "actuator", ""))

    f = optional_table(raw, "flotor", "")
    check_unknown(f, ("edge_mm", "material", "coil_material", "corner_hole_mm"), "flotor")
    fd = FlotorSpec()
    flotor = FlotorSpec(
        optional_positive(f, "edge_mm", "flotor", fd.edge_mm),
        _material(f, "material", "flotor", fd.material),
        _material(f, "coil_material", "flotor", fd.coil_material),
        optional_positive(f, "corner_hole_mm", "flotor", fd.corner_hole_mm),
    )
    s = optional_table(raw, "stator", "")
    check_unknown(
        s,
        (
            "housing_material",
            "housing_wall_mm",
            "iron_material",
            "magnet_material",
            "post_diameter_mm",
        ),
        "stator",
    )
    sd = StatorSpec()
    stator = StatorSpec(
        _material(s, "housing_material", "stator", sd.housing_material),
        optional_positive(s, "housing_wall_mm", "stator", sd.housing_wall_mm),
        _material(s, "iron_material", "stator", sd.iron_material),
        _material(s, "magnet_material", "stator", sd.magnet_material),
        optional_positive(s, "post_diameter_mm", "stator", sd.post_diameter_mm),
    )
    h = optional_table(raw, "handle", "")
    check_unknown(h, ("length_mm", "diameter_mm", "knob_diameter_mm", "material"), "handle")
    hd = HandleSpec()
    handle = HandleSpec(
        optional_positive(h, "length_mm", "handle", hd.length_mm),
        optional_positive(h, "diameter_mm", "handle", hd.diameter_mm),
        optional_positive(h, "knob_diameter_mm", "handle", hd.knob_diameter_mm),
        _material(h, "material", "handle", hd.material),
    )
    m = optional_table(raw, "motion", "")
    check_unknown(m, ("range_mm", "range_deg"), "motion")
    md = MotionSpec()
    motion = MotionSpec(
        optional_positive(m, "range_mm", "motion", md.range_mm),
        optional_positive(m, "range_deg", "motion", md.range_deg),
    )
    if motion.range_mm > act.rattle_mm / 2:
        raise DesignError(
            "motion.range_mm",
            f"{motion.range_mm:g} mm must be <= actuator.rattle_mm/2 = {act.rattle_mm / 2:g} mm with "
            f"actuator.rattle_mm = {act.rattle_mm:g} mm (the coil would hit the magnets); lower "
            f"motion.range_mm or raise actuator.rattle_mm to >= {2 * motion.range_mm:g} mm",
        )
    if motion.range_deg >= 30:
        raise DesignError("motion.range_deg", f"must be < 30 deg, got {motion.range_deg!r}")
    targets = parse_targets(optional_table(raw, "targets", ""), "targets", POWERMOUSE_TARGET_KEYS)
    return PowerMouseDesign(name, source, family, act, flotor, stator, handle, motion, raw, targets)
