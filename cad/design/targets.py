"""The ``[targets]`` table: what a design must achieve, with tolerances.

Each key is a quantity that hapticad computes (units in the name). A value is
either a number (target value, default tolerance ``tol_rel = 0.05``) or a
table with ``value`` and one of ``tol_rel`` / ``tol_abs``, or with ``max``
and/or ``min`` bounds::

    [targets]
    H11_kg_m2 = { value = 2.97e-5, tol_rel = 0.25 }
    M11_max_g = { max = 45.0 }
    coupler_mass_g = 40.0

Allowed keys: :data:`TARGET_KEYS`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from cad.design.bounds import TARGETS, check_number
from cad.errors import DesignError
from cad.tolerances import TARGET_TOL_REL_DEFAULT

TARGET_KEYS: tuple[str, ...] = (
    "H11_kg_m2", "H12_kg_m2", "H22_kg_m2", "H33_kg_m2",
    "M11_min_g", "M11_max_g", "M12_min_g", "M12_max_g", "M22_max_g",
    "crank_mass_g", "coupler_mass_g", "rocker_mass_g", "moving_mass_g",
    "stroke_mm", "dy_max_mm", "slope_max", "torque_mean_mNm", "torque_variation",
    "min_transmission_angle_deg", "min_clearance_mm",
    "first_mode_Hz", "max_stress_MPa", "compliance_x_um_per_N", "compliance_z_um_per_N",
    "D_min_kg_m2", "D_max_kg_m2",
    # datasheet figures (cad/datasheet): bounds replace their default limits
    "continuous_force_N", "peak_force_N", "resolution_um", "K_max_N_per_m", "friction_N",
)

#: Targets of the pantograph families (isotropy paper): the GII (eq 5) over the design's
#: workspace, and for built designs the effective mass at home from the solids
#: ("apparent" = 1/(M^-1)_ii with the other task axes free, "diag" = M_ii with them held).
PANTOGRAPH_TARGET_KEYS: tuple[str, ...] = (
    "gii", "moving_mass_g",
    "mass_x_g_apparent", "mass_y_g_apparent", "inertia_theta_g_cm2_apparent",
    "mass_x_g_diag", "mass_y_g_diag", "inertia_theta_g_cm2_diag",
    # datasheet figures (cad/families/pantograph/datasheet.py): bounds replace their default limits
    *(PANTOGRAPH_DATASHEET_KEYS := (
        "continuous_force_N", "peak_force_N", "force_any_dir_N", "force_best_dir_N", "resolution_um",
        "first_mode_Hz", "first_mode_in_plane_Hz", "first_mode_out_of_plane_Hz",
        "compliance_x_um_per_N", "compliance_y_um_per_N", "compliance_z_um_per_N",
        "max_stress_MPa", "min_clearance_mm", "total_mass_g")),
)

DEFAULT_TOL_REL = TARGET_TOL_REL_DEFAULT  # the old name


@dataclass(frozen=True)
class Target:
    """One target. Exactly one mode: value +/- tol, or bounds (min and/or max)."""

    key: str
    value: float | None = None
    tol_rel: float | None = None
    tol_abs: float | None = None
    min: float | None = None
    max: float | None = None

    def describe(self) -> str:
        if self.value is not None:
            if self.tol_abs is not None:
                return f"{self.value:.6g} ± {self.tol_abs:.3g}"
            return f"{self.value:.6g} ± {100 * (self.tol_rel or 0):.3g}%"
        parts = []
        if self.min is not None:
            parts.append(f">= {self.min:.6g}")
        if self.max is not None:
            parts.append(f"<= {self.max:.6g}")
        return " and ".join(parts)

    def as_data(self) -> dict[str, float]:
        """The target as data: ``{"value", "tol_rel" | "tol_abs"}`` or ``{"min"?, "max"?}``."""
        if self.value is not None:
            if self.tol_abs is not None:
                return {"value": self.value, "tol_abs": self.tol_abs}
            return {"value": self.value, "tol_rel": self.tol_rel or 0.0}
        return {k: v for k, v in (("min", self.min), ("max", self.max)) if v is not None}

    def margin(self, computed: float) -> float:
        """Distance to the nearest limit in the key's unit: > 0 inside, < 0 outside.

        For ``value ± tol`` the limits are ``value - tol`` and ``value + tol``.
        """
        if self.value is not None:
            tol = self.tol_abs if self.tol_abs is not None else abs(self.value) * (self.tol_rel or 0.0)
            return tol - abs(computed - self.value)
        m = math.inf
        if self.min is not None:
            m = min(m, computed - self.min)
        if self.max is not None:
            m = min(m, self.max - computed)
        return m

    def gap(self, computed: float) -> float:
        """Signed relative gap (computed - reference) / |reference|, reference = value or violated bound."""
        ref = self.value
        if ref is None:
            if self.max is not None and computed > self.max:
                ref = self.max
            elif self.min is not None and computed < self.min:
                ref = self.min
            else:
                return 0.0
        return (computed - ref) / abs(ref) if ref else float("inf")

    def ok(self, computed: float) -> bool:
        if not math.isfinite(computed):
            return False
        if self.value is not None:
            tol = self.tol_abs if self.tol_abs is not None else abs(self.value) * (self.tol_rel or 0.0)
            return abs(computed - self.value) <= tol
        if self.min is not None and computed < self.min:
            return False
        return not (self.max is not None and computed > self.max)


def _num(v: Any, field: str) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(float(v)):
        raise DesignError(field, f"must be a finite number, got {v!r}")
    return float(v)


def parse_target(key: str, spec: Any, prefix: str = "targets",
                 allowed_keys: tuple[str, ...] = TARGET_KEYS) -> Target:
    field = f"{prefix}.{key}"
    if key not in allowed_keys:
        raise DesignError(field, f"unknown target (allowed: {', '.join(allowed_keys)})")
    if not isinstance(spec, dict):
        return Target(key, value=_num(spec, field), tol_rel=DEFAULT_TOL_REL)
    allowed = {"value", "tol_rel", "tol_abs", "min", "max"}
    for k in spec:
        if k not in allowed:
            raise DesignError(f"{field}.{k}", f"unknown key (allowed: {', '.join(sorted(allowed))})")
    vals = {k: _num(v, f"{field}.{k}") for k, v in spec.items()}
    if "value" in vals:
        if "min" in vals or "max" in vals:
            raise DesignError(field, "give either value (+ tol_rel/tol_abs) or min/max, not both")
        if "tol_rel" in vals and "tol_abs" in vals:
            raise DesignError(field, "give tol_rel or tol_abs, not both")
        for k in ("tol_rel", "tol_abs"):
            if k in vals and vals[k] < 0:
                raise DesignError(f"{field}.{k}", f"must be >= 0, got {vals[k]!r}")
        if "tol_abs" in vals:
            return Target(key, value=vals["value"], tol_abs=vals["tol_abs"])
        return Target(key, value=vals["value"], tol_rel=vals.get("tol_rel", DEFAULT_TOL_REL))
    if "min" not in vals and "max" not in vals:
        raise DesignError(field, "needs value, min or max")
    if "tol_rel" in vals or "tol_abs" in vals:
        raise DesignError(field, "tol_rel/tol_abs only apply with value")
    if "min" in vals and "max" in vals and vals["min"] > vals["max"]:
        raise DesignError(field, f"min {vals['min']} > max {vals['max']}")
    return Target(key, min=vals.get("min"), max=vals.get("max"))


#: ``[targets]`` / ``--target`` keys of a PowerMouse: its datasheet's figures (``hapticad check``
#: and ``fit`` compute them on a build, :mod:`cad.studies.build_targets`).
POWERMOUSE_TARGET_KEYS = ("continuous_force_N", "peak_force_N", "force_per_At_N", "torque_per_At_mNm",
                          "flotor_mass_g", "peak_acceleration_G", "min_clearance_mm", "total_mass_g",
                          "moving_mass_g")

#: ``[targets]`` / ``--target`` keys of a delta: its datasheet's figures (``hapticad check`` and
#: ``fit`` compute them on a build, :mod:`cad.studies.build_targets`;
#: :mod:`cad.families.delta.datasheet`).
DELTA_TARGET_KEYS = ("continuous_force_N", "peak_force_N", "resolution_um", "eq25_K_max_N_per_m",
                     "apparent_mass_max_g", "apparent_mass_min_g", "first_mode_Hz",
                     "compliance_max_um_per_N", "moving_mass_g", "total_mass_g",
                     "overlap_volume_mm3", "max_stress_MPa", "rod_buckling_margin",
                     "ball_joint_tilt_max_deg", "gravity_torque_max_Nm", "gravity_torque_share",
                     "reachable_volume_cm3", "well_conditioned_volume_cm3")


def parse_targets(table: dict[str, Any], prefix: str = "targets",
                  allowed_keys: tuple[str, ...] = TARGET_KEYS) -> tuple[Target, ...]:
    return tuple(parse_target(k, v, prefix, allowed_keys) for k, v in table.items())


def parse_cli_target(text: str, allowed_keys: tuple[str, ...] = TARGET_KEYS) -> Target:
    """``KEY=VALUE`` (default tolerance), ``KEY<=VALUE`` or ``KEY>=VALUE`` from the command line."""
    for op in ("<=", ">=", "="):
        if op in text:
            key, _, val = text.partition(op)
            key = key.strip()
            try:
                v = float(val)
            except ValueError:
                raise DesignError(f"--target {text}", f"value {val!r} is not a number") from None

            if key in TARGETS:
                check_number(f"--target {key}", v, TARGETS[key])
            spec: Any = v if op == "=" else ({"max": v} if op == "<=" else {"min": v})
            return parse_target(key, spec, "--target", allowed_keys)
    raise DesignError(f"--target {text}", "expected KEY=VALUE, KEY<=VALUE or KEY>=VALUE")
