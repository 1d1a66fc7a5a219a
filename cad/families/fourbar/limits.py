"""The four-bar's default limits (the table of :mod:`cad.datasheet.limits`), the design keys
that move each figure, the structural limits as ``[targets]`` bounds for ``fit`` and the
Hoeken prototype's figures for ``optimize --beat-prototype``. No CAD import."""

from __future__ import annotations

from cad.datasheet.limits import (
    FIRST_MODE_MIN_HZ,
    FORCE_REASON,
    MODE_REASON,
    STRESS_REASON,
    STRESS_SAFETY_FACTOR,
    Limit,
    with_targets,
)
from cad.design.targets import Target
from cad.structure.device import link_material
from cad.structure.elastic import get_elastic

#: The Hoeken paper's measured Coulomb friction of the prototype (eq 24, Fig. 10), N.
PAPER_FS_N = 0.083

FORCE_CHANGE = ("parts.motor or [motor] (a stronger motor), a capstan reduction ([transmission] kind = \"capstan\", or a larger ratio / drum_diameter_mm), "
                "mechanism.force_N, or mechanism.force_basis = \"peak\"")
MODE_CHANGE = "parts.bar_material, parts.bar_thickness_mm, parts.bar_width_mm (stiffer, lighter bars)"
STRESS_CHANGE = "parts.bar_material or parts.bar_thickness_mm / parts.bar_width_mm"
CLEARANCE_CHANGE = "parts.layer_gap_mm, parts.pin_head_clearance_mm or parts.layer_order"


def fourbar_limits(design, strength_MPa: float | None) -> dict[str, Limit]:
    """Default limits of a four-bar design (module table), then its [targets] bounds."""
    lim: dict[str, Limit] = {}
    F = float(design.force_N)
    if design.force_basis == "peak":
        lim["peak_force_N"] = Limit(">=", F, "force_N at every point of the stroke (force_basis = peak)",
                                    "parts.motor or [motor], or mechanism.force_N")
    else:
        lim["continuous_force_N"] = Limit(">=", F, FORCE_REASON, FORCE_CHANGE)
    lim["first_mode_Hz"] = Limit(">=", FIRST_MODE_MIN_HZ, MODE_REASON, MODE_CHANGE)
    if strength_MPa is not None:
        lim["max_stress_MPa"] = Limit("<=", strength_MPa / STRESS_SAFETY_FACTOR, STRESS_REASON, STRESS_CHANGE)
    lim["min_clearance_mm"] = Limit(">=", float(design.parts.clearance_min_mm),
                                    "parts.clearance_min_mm (the build's clearance rule)", CLEARANCE_CHANGE)
    return with_targets(lim, design.targets, FOURBAR_TARGET_CHANGE)


#: Design keys that move the four-bar figures a ``[targets]`` bound alone limits (the datasheet's
#: models: the resolution from the encoder's counts, ``stiffness.encoder_resolution_m`` when
#: given; the no-load friction from the motor's no-load current (the bearings add nothing
#: unloaded); K_max from the loop period, friction and the encoder).
FOURBAR_TARGET_CHANGE = {
    "resolution_um": "parts.encoder, parts.encoder_counts_per_rev or stiffness.encoder_resolution_m",
    "friction_N": "parts.motor or [motor] (its no-load current)",
    "K_max_N_per_m": "stiffness.Te_s, stiffness.Fv_N_s_per_m, stiffness.encoder_resolution_m or parts.encoder",
}

#: ``hapticad fit`` free parameters that change the bar material: with one of them free the
#: fit also meets the default structural limits (a lighter material must stay stiff and strong).
STRUCTURE_FREE = ("parts.bar_material", "parts.bar_style", "parts.tube_material")


def structure_targets(design) -> tuple:
    """The default first-mode and stress limits of a four-bar candidate as ``[targets]``
    bounds (the stress limit from its own bar material), except keys its targets set."""
    lim = fourbar_limits(design, get_elastic(link_material(design.parts)).strength_MPa)
    mode, stress = lim["first_mode_Hz"], lim["max_stress_MPa"]
    out = []
    if mode.origin == "default":
        out.append(Target("first_mode_Hz", min=mode.value))
    if stress.origin == "default":
        out.append(Target("max_stress_MPa", max=stress.value))
    return tuple(out)


def default_limit_targets(design) -> tuple:
    """Every default limit of a four-bar candidate (:func:`fourbar_limits`, the stress limit
    from its own bar material) as ``[targets]`` bounds, except keys its targets set: the
    constraints of ``hapticad fit`` (issue 24 §2)."""
    lim = fourbar_limits(design, get_elastic(link_material(design.parts)).strength_MPa)
    return tuple(Target(k, min=v.value) if v.op.startswith(">") else Target(k, max=v.value)
                 for k, v in lim.items() if v.origin == "default")


#: The Hoeken prototype's figures a new device must beat at once (issue 24 §4), as
#: ``{row key: (op, value, source)}``; ``hapticad optimize --beat-prototype``. The Coulomb
#: friction is the paper's identified F_s (:data:`PAPER_FS_N`).
PROTOTYPE_M11_MAX_G = 30.0
PROTOTYPE_STROKE_MIN_MM = 50.0
PROTOTYPE_DY_MAX_MM = 0.2
PROTOTYPE_FIRST_MODE_MIN_HZ = 250.0
PROTOTYPE_FORCE_MIN_N = 5.0
PROTOTYPE_K_MAX_MIN_N_PER_M = 15000.0


def prototype_limits() -> dict[str, Limit]:
    """The issue 24 §4 limits (module constants above), each with the paper value it beats."""
    why = "issue 24 §4: beat the Hoeken prototype"
    chg = "hapticad optimize --beat-prototype (the co-design)"
    return {
        "M11_max_g": Limit("<=", PROTOTYPE_M11_MAX_G, f"{why} (27.5 .. 42.8 g CAD, paper §III.B.2)", chg),
        "stroke_mm": Limit(">=", PROTOTYPE_STROKE_MIN_MM, f"{why} (50 mm range of motion, paper §I)", chg),
        "dy_max_mm": Limit("<=", PROTOTYPE_DY_MAX_MM, f"{why} (straight-line error)", chg),
        "first_mode_Hz": Limit(">=", PROTOTYPE_FIRST_MODE_MIN_HZ,
                               f"{why} (250 Hz measured first resonance, paper §III.B.1), crank held", chg),
        "continuous_force_N": Limit(">=", PROTOTYPE_FORCE_MIN_N,
                                    f"{why} (5 N output force goal, 3.3 N continuous, paper §I, §III.A)", chg),
        "K_max_N_per_m": Limit(">=", PROTOTYPE_K_MAX_MIN_N_PER_M,
                               f"{why} (15000 N/m rendered, paper §III.B.4), Te 0.33 ms, 2000 counts/rev", chg),
        "friction_N": Limit("<=", PAPER_FS_N, f"{why} (F_s = 0.083 N identified, paper eq 24, Fig. 10)", chg),
    }
