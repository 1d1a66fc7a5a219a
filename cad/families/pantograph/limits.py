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
from cad.design.targets import Target
from cad.structure.elastic import get_elastic

PANTO_FORCE_CHANGE = ("parts.motor or [motor] (a stronger motor), a capstan reduction ([transmission] kind = \"capstan\", or a larger ratio / drum_diameter_mm), "
                      "actuators.force_max_N or the link lengths")
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


def _weakest_strength_MPa(design) -> float | None:
    """The smallest strength (MPa) of the link materials a pantograph-family candidate names
    (``parts.tube_material``; the twin pantograph's ``parts.crank_material``): the stress limit
    the fit holds every link to (conservative: the datasheet judges the critical link's own)."""
    names = [design.parts.tube_material]
    if design.family == "twin-pantograph":
        names.append(design.parts.crank_material)
    strengths = [get_elastic(n).strength_MPa for n in names]
    return min((s for s in strengths if s is not None), default=None)


def default_limit_targets(design) -> tuple:
    """Every default limit of a 5-bar, twin pantograph or haptic-pen candidate (:func:`pantograph_limits`:
    first mode, stress of the weakest link material, continuous force from the ordered motors)
    as ``[targets]`` bounds, except keys its targets set: the constraints of ``hapticad fit``
    (a candidate that misses one ranks after every candidate that misses fewer)."""
    lim = pantograph_limits(design, design.actuators.get("force_max_N"), _weakest_strength_MPa(design),
                            structure=True)
    return tuple(Target(k, min=v.value) if v.op.startswith(">") else Target(k, max=v.value)
                 for k, v in lim.items() if v.origin == "default")
