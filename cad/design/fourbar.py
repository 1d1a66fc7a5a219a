"""Four-bar design files (families hoeken, roberts, chebyshev, chebyshev-v, custom).

Schema (units in key names; see docs/design-files.md)::

    name = "hoeken"                  # top level, required: output folder name

    [mechanism]
    family = "hoeken"                # hoeken | roberts | chebyshev | chebyshev-v | custom
    stroke_mm = 50.0                 # named families: scale the paper's Fig. 2 proportions
                                     # to this stroke (omit: the paper's own dimensions)
    force_N = 5.0                    # force along the path for the torque metrics
    force_basis = "continuous"       # continuous (default) | peak: which motor torque must
                                     # give force_N over the stroke (datasheet verdict)
    # custom only (all required):
    # l1_mm, l2_mm, l3_mm, l4_mm, l5_mm, le_mm, phi_e_deg, phi1_min_deg, phi1_max_deg, branch

    [analysis]   samples = 2001      # optional
    [inertia]    H11_kg_m2 = ...     # optional given inertia coefficients (all four)
    [stiffness]  Fv_N_s_per_m, Fs_N, Te_s, encoder_resolution_m, xdot_max_m_per_s (optional, eq 25)
    [parts]      part parameters (see cad/design/parts.py)
    [motor]      the user's own motor data (see cad/design/motor.py)
    [targets]    see cad/design/targets.py
    [fit]        free = ["parts.bar_thickness_mm", ...] (see `hapticad fit`)
    [firmware]   plane, encoders, wall of the generated firmware (cad/design/firmware.py)
    [transmission]  the crank's drive: direct (default) or a capstan (cad/design/transmission.py)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from cad import tolerances as tol
from cad.data.catalog import DEFAULT_ENCODER, get_bearing
from cad.design.bounds import LINK_MM, STROKE_MM, warn
from cad.design.fields import (
    check_name,
    check_unknown,
    optional_int,
    optional_number,
    optional_positive,
    optional_table,
    require_number,
    require_positive,
    require_str,
    require_table,
)
from cad.design.firmware import FirmwareOptions, parse_firmware
from cad.design.motor import parse_motor_table, resolve_motor
from cad.design.parts import parse_parts
from cad.design.replace import ValidatedReplace
from cad.design.targets import Target, parse_targets
from cad.design.transmission import Transmission, parse_transmissions
from cad.device import stated_encoder_counts
from cad.dynamics.inertia import InertiaCoefficients
from cad.dynamics.stiffness import StiffnessInputs
from cad.errors import DesignError, KinematicsError
from cad.kinematics.encoder_counts import mid_stroke_lever_m_per_rad, stiffness_counts
from cad.kinematics.families import FAMILIES, family_linkage
from cad.kinematics.fourbar import FourBar, require_range

FOURBAR_FAMILIES = (*FAMILIES, "custom")
CUSTOM_KEYS = ("l1_mm", "l2_mm", "l3_mm", "l4_mm", "l5_mm", "le_mm", "phi_e_deg",
               "phi1_min_deg", "phi1_max_deg", "branch")
TOP_KEYS = ("name", "description", "mechanism", "analysis", "inertia", "stiffness", "parts",
            "targets", "fit", "firmware", "motor", "prices", "transmission")
#: ``[mechanism] force_basis``: which motor torque must deliver ``force_N`` (datasheet verdict).
FORCE_BASES = ("continuous", "peak")


@dataclass(frozen=True)
class FourBarDesign(ValidatedReplace):
    """A validated four-bar design. Lengths mm, angles rad."""

    name: str
    source: str
    family: str
    linkage: FourBar
    phi1_min_rad: float
    phi1_max_rad: float
    force_N: float
    stroke_mm_requested: float | None
    samples: int
    inertia: InertiaCoefficients | None
    stiffness: StiffnessInputs | None
    parts: Any
    targets: tuple[Target, ...]
    fit_free: tuple[str, ...]
    raw: dict = field(repr=False, compare=False, hash=False, default_factory=dict)
    firmware: FirmwareOptions = field(default_factory=FirmwareOptions)
    force_basis: str = "continuous"
    motor: tuple = ()

    @property
    def transmissions(self) -> tuple[Transmission, ...]:
        """One :class:`cad.design.transmission.Transmission` per motor (the crank's): the
        ``[transmission]`` table of the design file (validated at load), direct drive without
        one. Read from ``raw`` (not a field of its own: a direct design's hash is unchanged)."""
        return parse_transmissions(self.raw.get("transmission"), 1)

    def motor_spec(self):
        """The motor this design drives: ``parts.motor`` with the ``[motor]`` overrides."""

        return resolve_motor(self.parts.motor, self.motor)

    def resolved_linkage(self) -> dict[str, float | int | str]:
        """The resolved linkage in design-file units (report.json / analyze --json)."""
        fb = self.linkage
        return {
            "family": self.family,
            "l1_mm": fb.l1_mm, "l2_mm": fb.l2_mm, "l3_mm": fb.l3_mm, "l4_mm": fb.l4_mm,
            "l5_mm": fb.l5_mm, "le_mm": fb.le_mm, "phi_e_deg": math.degrees(fb.phi_e_rad),
            "phi1_min_deg": math.degrees(self.phi1_min_rad),
            "phi1_max_deg": math.degrees(self.phi1_max_rad),
            "branch": fb.branch,
        }

    def hardware_gaps(self) -> list[tuple[str, float, float, float]]:
        """Links shorter than the joint hardware: ``(link, length_mm, bore_mm, seat_mm)``.

        The coupler and the rocker carry a bearing seat (outside diameter D) or a pin hole
        (bore d) at each of their two joints; below D two seats of one bar can overlap, below d
        even the pin holes do. The crank has the hub at A1 and one joint (A2), never two
        seats: it is listed only below the pin bore; whether the A2 hardware clears the hub
        is the layer planner's check (:func:`cad.families.fourbar.build.check_layout`, before CAD).
        """

        brg = get_bearing(self.parts.bearing, "parts.bearing")
        fb = self.linkage
        lengths = (("l1_mm", fb.l1_mm, brg.d_mm), ("l2_mm", fb.l2_mm, brg.D_mm),
                   ("l3_mm", fb.l3_mm, brg.D_mm))
        return [(k, v, brg.d_mm, brg.D_mm) for k, v, lim in lengths if v < lim]

    def _hardware_text(self, gaps: list[tuple[str, float, float, float]]) -> str:

        s = self.stroke_mm_requested
        if s is not None:
            slip = STROKE_MM.slip_hint(s)
            hint = f"; stroke_mm = {s:g}{slip}" if slip else ""
        else:
            hint = LINK_MM.slip_hint(min(g[1] for g in gaps))
        links = ", ".join(f"{k} = {v:.4g} mm" for k, v, _, _ in gaps)
        seat = gaps[0][3]
        return (f"{links} shorter than the joint hardware ({self.parts.bearing} bearing seats "
                f"need >= {seat:g} mm between the joints of a bar){hint}")

    def motor_joints(self) -> tuple[tuple[str, str], ...]:
        """(joint, parts field naming its motor): the crank's motor."""
        return (("crank", "motor"),)

    def default_encoder(self) -> tuple[str, str]:
        """(catalog encoder, hint) a design that states no encoder gets."""
        return DEFAULT_ENCODER, "; set parts.encoder"

    def stiffness_encoder(self) -> tuple[int, str] | None:
        """The counts per turn ``[stiffness] encoder_resolution_m`` implies, with its source
        (:func:`cad.kinematics.encoder_counts.stiffness_counts`); None without the table."""
        return stiffness_counts(self)

    def check_buildable(self) -> None:
        """Raise DesignError (before any CAD import) when a link cannot carry its joints.

        A link shorter than the pin bore puts its two joint holes on top of each other:
        no part can be made (``stroke_mm = 0.08`` typed in metres built for 130 s, then
        reported a collision). Links between the bore and the bearing seat are warned
        about at load (:func:`parse`).
        """
        gaps = [g for g in self.hardware_gaps() if g[1] < g[2]]
        if gaps:
            raise DesignError("mechanism", self._hardware_text(gaps)
                              + f"; below the {gaps[0][2]:g} mm pin bore no part can be made")


def _parse_linkage(mech: dict[str, Any], family: str) -> tuple[FourBar, float, float, float | None]:
    p = "mechanism"
    if family == "custom":
        allowed = ("family", "force_N", *CUSTOM_KEYS)
        check_unknown(mech, (*allowed, "force_basis"), p)
        lengths = {k: require_positive(mech, k, p) for k in ("l1_mm", "l2_mm", "l3_mm")}
        l4 = require_number(mech, "l4_mm", p)
        l5 = require_number(mech, "l5_mm", p)
        le = require_number(mech, "le_mm", p)
        if le < 0:
            raise DesignError("mechanism.le_mm", f"must be >= 0, got {mech['le_mm']!r}")
        phi_e = math.radians(require_number(mech, "phi_e_deg", p))
        lo = math.radians(require_number(mech, "phi1_min_deg", p))
        hi = math.radians(require_number(mech, "phi1_max_deg", p))
        if "branch" not in mech:
            raise DesignError("mechanism.branch", "missing (the assembly mode must be explicit: +1 or -1)")
        branch = mech["branch"]
        if isinstance(branch, bool) or branch not in (1, -1):
            raise DesignError("mechanism.branch", f"must be +1 or -1, got {branch!r}")
        fb = FourBar(lengths["l1_mm"], lengths["l2_mm"], lengths["l3_mm"], l4, l5, le, phi_e, int(branch))
        return fb, lo, hi, None
    check_unknown(mech, ("family", "force_N", "stroke_mm", "force_basis"), p)
    stroke = optional_positive(mech, "stroke_mm", p, None)
    if stroke is not None and not tol.LENGTH_MIN_MM <= stroke <= tol.LENGTH_MAX_MM:
        raise DesignError("mechanism.stroke_mm",
                          f"must lie in [{tol.LENGTH_MIN_MM:g}, {tol.LENGTH_MAX_MM:g}] mm, got {stroke!r}")
    fb, lo, hi = family_linkage(family, stroke)
    return fb, lo, hi, stroke


def _parse_inertia(tab: dict[str, Any]) -> InertiaCoefficients | None:
    if not tab:
        return None
    keys = ("H11_kg_m2", "H12_kg_m2", "H22_kg_m2", "H33_kg_m2", "beta2_deg")
    check_unknown(tab, keys, "inertia")
    vals = {k: require_number(tab, k, "inertia") for k in keys[:4]}
    for k in ("H11_kg_m2", "H22_kg_m2", "H33_kg_m2"):
        if vals[k] <= 0:
            raise DesignError(f"inertia.{k}", f"must be > 0, got {vals[k]!r}")
    beta = math.radians(optional_number(tab, "beta2_deg", "inertia", 0.0) or 0.0)
    return InertiaCoefficients(vals["H11_kg_m2"], vals["H12_kg_m2"], vals["H22_kg_m2"],
                               vals["H33_kg_m2"], beta)


def _parse_stiffness(tab: dict[str, Any]) -> StiffnessInputs | None:
    if not tab:
        return None
    keys = ("Fv_N_s_per_m", "Fs_N", "Te_s", "encoder_resolution_m", "xdot_max_m_per_s")
    check_unknown(tab, keys, "stiffness")
    # physical ranges: far outside them eq (25) over/underflows (inf or NaN stiffness)
    ranges = {"Fv_N_s_per_m": (1e-9, 1e6), "Fs_N": (1e-9, 1e6), "Te_s": (1e-9, 10.0),
              "encoder_resolution_m": (1e-12, 1.0), "xdot_max_m_per_s": (1e-9, 1e3)}
    vals = []
    for k in keys:
        v = require_positive(tab, k, "stiffness")
        lo, hi = ranges[k]
        if not lo <= v <= hi:
            raise DesignError(f"stiffness.{k}", f"must lie in [{lo:g}, {hi:g}], got {v!r}")
        vals.append(v)
    return StiffnessInputs(*vals)


def _delta_of_the_encoder(design: FourBarDesign) -> FourBarDesign:
    """``[stiffness] encoder_resolution_m`` (eq 25's Delta) as the step of the encoder the
    design states (``parts.encoder``, ``parts.encoder_counts_per_rev``, ``[firmware]``) at
    mid-stroke, with a warning when the table gave another encoder's step: one encoder in
    the BOM, the firmware, eq (25), the simulated K_max and the wall sketch."""
    from dataclasses import replace

    counts = stated_encoder_counts(design) if design.stiffness is not None else None
    if counts is None:
        return design
    lever = mid_stroke_lever_m_per_rad(design)
    delta = design.stiffness.encoder_resolution_m
    if round(2 * math.pi * lever / delta) == counts:
        return design
    own = 2 * math.pi * lever / counts

    warn(f"stiffness.encoder_resolution_m = {delta:g} m is the mid-stroke step of "
         f"{round(2 * math.pi * lever / delta)} counts/rev, not of the design's encoder ({counts} "
         f"counts/rev): eq (25), the simulated K_max and the firmware use its step, {own:.4g} m")
    return replace(design, stiffness=replace(design.stiffness, encoder_resolution_m=own))


def parse(raw: dict[str, Any], source: str = "<design>") -> FourBarDesign:
    """Validate a raw four-bar design mapping (see module docstring)."""
    check_unknown(raw, TOP_KEYS, "")
    name = check_name(require_str(raw, "name", ""))
    mech = require_table(raw, "mechanism", "")
    family = require_str(mech, "family", "mechanism")
    if family not in FOURBAR_FAMILIES:
        raise DesignError("mechanism.family", f"unknown four-bar family {family!r}")
    force = optional_positive(mech, "force_N", "mechanism", 5.0)
    if force > tol.FORCE_MAX_N:
        raise DesignError("mechanism.force_N", f"must be <= {tol.FORCE_MAX_N:g} N, got {force!r}")
    fb, lo, hi, stroke = _parse_linkage(mech, family)
    basis = mech.get("force_basis", "continuous")
    if basis not in FORCE_BASES:
        raise DesignError("mechanism.force_basis", f"must be one of {', '.join(FORCE_BASES)}, got {basis!r}")
    if not hi > lo:
        raise DesignError("mechanism.phi1_max_deg",
                          f"must be > phi1_min_deg ({math.degrees(lo):g}), got {math.degrees(hi):g}")
    if hi - lo >= 2 * math.pi:
        raise DesignError("mechanism.phi1_max_deg", "the crank range must be less than 360 deg")
    try:
        require_range(fb, lo, hi)
    except KinematicsError as exc:  # ClosureError, ToggleError, BranchJumpError
        raise DesignError("mechanism", f"impossible range: {exc}") from None
    analysis = optional_table(raw, "analysis", "")
    check_unknown(analysis, ("samples",), "analysis")
    samples = optional_int(analysis, "samples", "analysis", 2001, minimum=3)
    if samples > tol.SAMPLES_MAX:
        raise DesignError("analysis.samples", f"must be <= {tol.SAMPLES_MAX}, got {samples}")

    parts = parse_parts(optional_table(raw, "parts", ""), "parts")
    targets = parse_targets(optional_table(raw, "targets", ""), "targets")
    fit = optional_table(raw, "fit", "")
    check_unknown(fit, ("free",), "fit")
    free = fit.get("free", [])
    if not isinstance(free, list) or not all(isinstance(s, str) for s in free):
        raise DesignError("fit.free", f"must be a list of parameter names, got {free!r}")
    design = FourBarDesign(
        name=name, source=source, family=family, linkage=fb, phi1_min_rad=lo, phi1_max_rad=hi,
        force_N=float(force), stroke_mm_requested=stroke, samples=samples,
        inertia=_parse_inertia(optional_table(raw, "inertia", "")),
        stiffness=_parse_stiffness(optional_table(raw, "stiffness", "")),
        parts=parts, targets=targets, fit_free=tuple(free), raw=raw,
        firmware=parse_firmware(optional_table(raw, "firmware", ""), 1),
        force_basis=basis, motor=parse_motor_table(optional_table(raw, "motor", ""), "motor"),
    )
    parse_transmissions(raw.get("transmission"), 1)  # refused here, at load (DesignError)
    design = _delta_of_the_encoder(design)

    gaps = design.hardware_gaps()
    if gaps:
        warn(f"mechanism: {design._hardware_text(gaps)}")
    return design

