"""The pantograph families' default limits (the table of :mod:`cad.datasheet.limits`):
the 5-bar, the twin pantograph and the haptic pen. No CAD import."""

from __future__ import annotations

from cad.datasheet.limits import (
    FIRST_MODE_MIN_HZ,
    MODE_REASON,
    STRESS_REASON,
    STRESS_SAFETY_FACTOR,
    Limit,
    with_targets,
)

PANTO_FORCE_CHANGE = "parts.motor or [motor] (a stronger motor), actuators.force_max_N or the link lengths"
PANTO_MODE_CHANGE = ("parts.tube_od_mm, parts.tube_id_mm, parts.tube_material (stiffer, lighter links), "
                     "parts.clevis_height_mm / clevis_width_mm (room for a larger tube)")
PANTO_STRESS_CHANGE = "parts.tube_od_mm / parts.tube_id_mm or parts.tube_material (parts.crank_material)"


def pantograph_limits(design, force_N: float | None, strength_MPa: float | None = None,
                      structure: bool = False) -> dict[str, Limit]:
    """Default limits of a pantograph-family design (module table), then its [targets].
    ``structure``: the design has structure rows (the planar families and the haptic pen):
    first-mode limit, and the stress limit from ``strength_MPa`` of the critical link's material."""
    lim: dict[str, Limit] = {}
    if structure:
        lim["first_mode_Hz"] = Limit(">=", FIRST_MODE_MIN_HZ, MODE_REASON, PANTO_MODE_CHANGE)
        if strength_MPa is not None:
            lim["max_stress_MPa"] = Limit("<=", strength_MPa / STRESS_SAFETY_FACTOR, STRESS_REASON,
                                          PANTO_STRESS_CHANGE)
    if force_N is not None:  # judged on the motors the BOM orders, not the GII's normalisation
        lim["continuous_force_N"] = Limit(">=", force_N, "[actuators] force_max_N (S_T, isotropy paper eq 4): "
                                          "the force asked for, in every direction at every point of the "
                                          "workspace, from the continuous torque of the motors the BOM orders",
                                          PANTO_FORCE_CHANGE)
    return with_targets(lim, getattr(design, "targets", ()))
