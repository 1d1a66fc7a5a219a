"""Default limits of every device figure, in one place, each with its reason (issue 24).

A datasheet row (:mod:`cad.datasheet`) whose key has a limit here gets a verdict; a missed
limit is a ``warning:`` line of the build (exit 0, exit 1 with ``--strict``), red at the top
of ``report.html``, and a failed row of ``hapticad check`` when the design has no
``[targets]``. A ``[targets]`` entry of the same key replaces the default (its ``min`` /
``max``). No CAD import.

=====================  ====  ============================================  ==================================
figure (row key)       op    default limit                                 reason
=====================  ====  ============================================  ==================================
continuous_force_N     >=    ``force_N`` (four-bars; unless                the force the design asks for must be
                             ``mechanism.force_basis = "peak"``)           available without overheating the
                                                                           motor, at every point of the stroke
peak_force_N           >=    ``force_N`` when ``force_basis = "peak"``     a peak-only design still needs its
                                                                           force at every point, for a moment
continuous_force_N     >=    pantograph families: ``[actuators]            the force asked for must be there in
                             force_max_N`` when given (from the BOM        every direction at every point,
                             motors' continuous torque, not from           without overheating the motors
                             ``force_any_dir_N``, the GII's normalisation)
first_mode_Hz          >=    :data:`FIRST_MODE_MIN_HZ` (four-bars, the     Hoeken paper §III.B.1: 150 Hz force
                             planar pantographs, the haptic pen: same)     bandwidth; a structural mode inside
                                                                           it is rendered as a vibration (the
                                                                           isotropy paper gives no bandwidth of
                                                                           its own: the same limit for the
                                                                           5-bar, the twin pantograph, the pen)
max_stress_MPa         <=    strength / :data:`STRESS_SAFETY_FACTOR`       static safety factor 3 at ``force_N``
                             (pantographs: the strength of the critical    (fatigue, notches, impacts)
                             link's material, force ``[actuators]
                             force_max_N``)
min_clearance_mm       >=    ``parts.clearance_min_mm``                    the build's own clearance rule
resolution_um,         only where ``[targets]`` asks                       a resolution or a wall stiffness is a
K_max_N_per_m,                                                             requirement of the application, not
friction_N                                                                 of every device
=====================  ====  ============================================  ==================================

:func:`default_limit_targets`: these defaults as ``[targets]`` bounds (``hapticad fit`` and
``hapticad optimize`` constrain every candidate with them). :func:`prototype_limits`: the
Hoeken prototype's figures (``hapticad optimize --beat-prototype``), each with its source.
"""

from __future__ import annotations

from dataclasses import dataclass

from cad.design.targets import Target
from cad.structure.elastic import get_elastic

#: First structural mode limit (Hz): above the Hoeken prototype's 150 Hz force bandwidth
#: (paper §III.B.1, which measured its first resonance at 250 Hz).
FIRST_MODE_MIN_HZ = 150.0
#: Peak stress at ``force_N`` at most the material strength over this factor.
STRESS_SAFETY_FACTOR = 3.0


@dataclass(frozen=True)
class Limit:
    """One limit: ``op`` (``">="`` or ``"<="``), its value in the row's unit, why, which
    design key(s) to change, and where the value came from (``"default"`` or ``"targets"``)."""

    op: str
    value: float
    reason: str
    change: str
    origin: str = "default"

    def met(self, v: float | None) -> bool:
        if v is None:
            return False
        return {">=": v >= self.value, ">": v > self.value, "<=": v <= self.value}[self.op]

    def as_dict(self) -> dict:
        return {"op": self.op, "value": self.value, "reason": self.reason, "change": self.change,
                "origin": self.origin}


FORCE_REASON = ("force_N must be available continuously at every point of the stroke "
                "(mechanism.force_basis = \"peak\" accepts peak-only force)")
FORCE_CHANGE = "parts.motor or [motor] (a stronger motor), mechanism.force_N, or mechanism.force_basis = \"peak\""
MODE_REASON = "above the 150 Hz force bandwidth of the Hoeken prototype (paper §III.B.1)"
MODE_CHANGE = "parts.bar_material, parts.bar_thickness_mm, parts.bar_width_mm (stiffer, lighter bars)"
STRESS_REASON = f"strength / {STRESS_SAFETY_FACTOR:g} (static safety factor at force_N)"
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


def with_targets(lim: dict[str, Limit], targets, change: dict[str, str] | None = None) -> dict[str, Limit]:
    """A ``[targets]`` bound of a limited key (``min`` for a ``>=`` figure, ``max`` for a
    ``<=`` one) replaces its default limit; ``value +/- tol`` targets stay check rows only.
    Its keys to change: the design keys of the default it replaces (or ``change[key]``),
    then the target itself."""
    out = dict(lim)
    for t in targets or ():
        op = DATASHEET_TARGETS.get(t.key)
        if op is None:
            continue
        bound = t.min if op == ">=" else t.max
        if bound is not None:
            keys = lim[t.key].change if t.key in lim else (change or {}).get(t.key)
            out[t.key] = Limit(op, float(bound), "[targets]",
                               f"{keys}, or targets.{t.key}" if keys else f"targets.{t.key}", "targets")
    return out


#: Datasheet rows a [targets] entry may bound (and the side that matters).
DATASHEET_TARGETS = {
    "first_mode_Hz": ">=", "max_stress_MPa": "<=", "min_clearance_mm": ">=",
    "continuous_force_N": ">=", "peak_force_N": ">=", "force_any_dir_N": ">=",
    "resolution_um": "<=", "K_max_N_per_m": ">=", "friction_N": "<=",
}


#: ``hapticad fit`` free parameters that change the bar material: with one of them free the
#: fit also meets the default structural limits (a lighter material must stay stiff and strong).
STRUCTURE_FREE = ("parts.bar_material", "parts.bar_style", "parts.tube_material")


def structure_targets(design) -> tuple:
    """The default first-mode and stress limits of a four-bar candidate as ``[targets]``
    bounds (the stress limit from its own bar material), except keys its targets set."""
    from cad.structure.device import link_material

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
    from cad.structure.device import link_material

    lim = fourbar_limits(design, get_elastic(link_material(design.parts)).strength_MPa)
    return tuple(Target(k, min=v.value) if v.op.startswith(">") else Target(k, max=v.value)
                 for k, v in lim.items() if v.origin == "default")


#: The Hoeken prototype's figures a new device must beat at once (issue 24 §4), as
#: ``{row key: (op, value, source)}``; ``hapticad optimize --beat-prototype``. The Coulomb
#: friction is the paper's identified F_s (:data:`cad.families.fourbar.datasheet.PAPER_FS_N`).
PROTOTYPE_M11_MAX_G = 30.0
PROTOTYPE_STROKE_MIN_MM = 50.0
PROTOTYPE_DY_MAX_MM = 0.2
PROTOTYPE_FIRST_MODE_MIN_HZ = 250.0
PROTOTYPE_FORCE_MIN_N = 5.0
PROTOTYPE_K_MAX_MIN_N_PER_M = 15000.0


def prototype_limits() -> dict[str, Limit]:
    """The issue 24 §4 limits (module constants above), each with the paper value it beats."""
    from cad.families.fourbar.datasheet import PAPER_FS_N

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
