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
winding_rise_at_       <=    100 K (four-bars whose motor gives its        125 C winding at 25 C ambient (maxon
force_K                      thermal resistances; continuous basis)        RE 35 / RE 40 sheets) holding force_N
resolution_um,         only where ``[targets]`` asks                       a resolution or a wall stiffness is a
K_max_N_per_m,                                                             requirement of the application, not
friction_N                                                                 of every device
=====================  ====  ============================================  ==================================

:class:`Limit`, the limits every family shares and :func:`with_targets` live here; each family
builds its own set in its package (:mod:`cad.families.fourbar.limits`: with
``default_limit_targets``, the defaults as ``[targets]`` bounds of ``hapticad fit`` and
``optimize``, and ``prototype_limits``, the Hoeken prototype's figures of ``optimize
--beat-prototype``; :mod:`cad.families.pantograph.limits` for the 5-bar, the twin pantograph
and the pen).
"""

from __future__ import annotations

from dataclasses import dataclass

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
    #: a ``[targets]`` bound looser than the default it replaces: that default's
    #: ``"<op> <value> (<reason>)"``, said beside every verdict it gives (never silent)
    loosens: str = ""

    def met(self, v: float | None) -> bool:
        if v is None:
            return False
        return {">=": v >= self.value, ">": v > self.value, "<=": v <= self.value}[self.op]

    def as_dict(self) -> dict:
        d = {"op": self.op, "value": self.value, "reason": self.reason, "change": self.change,
             "origin": self.origin}
        return {**d, "loosens": self.loosens} if self.loosens else d


FORCE_REASON = ("force_N must be available continuously at every point of the stroke "
                "(mechanism.force_basis = \"peak\" accepts peak-only force)")
MODE_REASON = "above the 150 Hz force bandwidth of the Hoeken prototype (paper §III.B.1)"
STRESS_REASON = f"strength / {STRESS_SAFETY_FACTOR:g} (static safety factor at force_N)"


#: The ``overlap_volume_mm3`` row's limit (every family with that row): no two solids overlap at
#: any pose of the motion. A build refuses such a device; a datasheet read from a build made with
#: ``--allow-interference`` (or a cached one) says MISS instead of leaving the row without a verdict.
OVERLAP_LIMIT = Limit("<=", 0.0, "no two solids may overlap at any pose of the motion (the build's every-pair check)",
                      "the layout: the arm lengths, the transmission's drum and capstan diameters, the parts' sizes")


def with_targets(lim: dict[str, Limit], targets, change: dict[str, str] | None = None) -> dict[str, Limit]:
    """A ``[targets]`` bound of a limited key (``min`` for a ``>=`` figure, ``max`` for a
    ``<=`` one) replaces its default limit; ``value +/- tol`` targets stay check rows only.
    Its keys to change: the design keys of the default it replaces (or ``change[key]``),
    then the target itself. A bound looser than the default (a tube brief's lower first
    mode, a higher stress) carries that default in ``loosens``: the verdict, the datasheet's
    notes and report.html say so."""
    out = dict(lim)
    for t in targets or ():
        op = DATASHEET_TARGETS.get(t.key)
        if op is None:
            continue
        bound = t.min if op == ">=" else t.max
        if bound is not None:
            d = lim.get(t.key)
            keys = d.change if d is not None else (change or {}).get(t.key)
            looser = d is not None and not Limit(op, d.value, "", "").met(float(bound))
            out[t.key] = Limit(op, float(bound), "[targets]",
                               f"{keys}, or targets.{t.key}" if keys else f"targets.{t.key}", "targets",
                               f"{d.op} {d.value:.4g} ({d.reason})" if looser else "")
    return out


def loosened_notes(rows: list[dict]) -> list[str]:
    """One line per judged row whose ``[targets]`` bound loosens its default limit
    (:func:`with_targets`): ``<figure>: judged against [targets] <op> <value> <unit>, looser
    than the default limit <op> <value> (<reason>)``."""
    out = []
    for r in rows:
        lim = r.get("limit") or {}
        if lim.get("loosens"):
            bound = f"{lim['value']:.4g} {r['unit']}" if r["unit"] else f"{lim['value']:.4g}"
            out.append(f"{r['figure']}: judged against [targets] {lim['op']} {bound}, "
                       f"looser than the default limit {lim['loosens']}")
    return out


#: Datasheet rows a [targets] entry may bound (and the side that matters).
DATASHEET_TARGETS = {
    "first_mode_Hz": ">=", "max_stress_MPa": "<=", "min_clearance_mm": ">=",
    "continuous_force_N": ">=", "peak_force_N": ">=", "force_any_dir_N": ">=",
    "resolution_um": "<=", "K_max_N_per_m": ">=", "friction_N": "<=",
    "rod_buckling_margin": ">=",
}
