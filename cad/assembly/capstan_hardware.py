"""What every family's capstan solids share (issue 35): the drum's thickness and material,
the rope anchor and tensioner screws, the joint axle's bearing block constants and bearing,
the capstan's set screw, and the free runs of rope as part kinds with their collision
envelopes. The four-bar's crank (:mod:`cad.families.fourbar.capstan_solids`), the 5-bar's
proximal links (:mod:`cad.families.pantograph.capstan_solids`) and the delta's upper arms
(:mod:`cad.families.delta.capstan_solids`) place them; none keeps its own copy.

Units: mm. A rope run's end points are in the frame of the instance that holds it (world for
the runs fixed in the world while the joint turns).
"""

from __future__ import annotations

import math

import numpy as np

from cad.actuators import capstan_geometry as cg
from cad.assembly.fasteners import (
    MIN_ENGAGEMENT_ALU_D,
    Fastener,
    TappedHole,
    min_boss_radius_mm,
    size_set_screw,
)
from cad.data import catalog as cat
from cad.errors import DesignError
from cad.parts import PartKind, motor
from cad.parts import capstan as shapes

#: Drum (or sector) thickness along the joint axis, mm: room for the rope's turns on the drum
#: side and the anchors' screws. A layout choice.
DRUM_THICKNESS_MM = 10.0
#: The drum sector's material (machined plate): its solid's and the cheap model's.
DRUM_MATERIAL = "aluminium-6061"
#: Anchor screw: ISO 4762 M3 x 8 radial in the drum's rim (a BOM line of the capstan rows,
#: :mod:`cad.datasheet.capstan_rows`).
ANCHOR_SCREW, ANCHOR_SCREW_LENGTH_MM = "M3-0.5", 8.0
#: The tensioner at anchor 2: the same radial tapped hole holds a longer ISO 4762 screw whose
#: shank stands out of the rim by an ISO 4032 lock nut and this many rope diameters; the rope's
#: end is wound on that shank (turning the screw winds it: the tension), the nut locks it.
TENSIONER_WIND_D = 3.0
#: The joint axle's bearing block: the lip between its two bearing seats and the wall round
#: them (mm), layout choices.
A1_LIP_MM, A1_WALL_MM = 2.0, 3.0
#: The rope's material for its solids (steel wire rope; its mass per metre is the rope
#: catalog's, :mod:`cad.data.cables`).
ROPE_MATERIAL = "steel-1018"


def run_trim_mm(pitch_radius_mm: float, clearance_mm: float) -> float:
    """Length by which a run's collision envelope stops short of its tangent point: at s from
    the tangent point the rope's axis is sqrt(r^2 + s^2) from the pulley's centre, so rope and
    rim stand sqrt(r^2 + s^2) - r apart; s = sqrt((r + c)^2 - r^2) gives ``clearance_mm``."""
    r = pitch_radius_mm
    return math.sqrt((r + clearance_mm) ** 2 - r * r)


def drum_groove_arc_deg(r_rim_mm: float, rope_diameter_mm: float, anchors_deg) -> tuple[float, float]:
    """(start, span) deg of the drum's rope groove: between the two anchors' radial holes, a
    land of one anchor tap drill plus one rope diameter of rim (at ``r_rim_mm``) short of each
    hole's axis, so the groove meets neither hole (the rope leaves it for its anchor there)."""
    lo, hi = sorted(float(a) for a in anchors_deg)
    m = math.degrees((cat.tap_drill_mm(ANCHOR_SCREW) + rope_diameter_mm) / r_rim_mm)
    return lo + m, hi - lo - 2.0 * m


def rope_run_kind(name: str, p0_mm, p1_mm, t, clearance_mm: float, what: str,
                  groove_depth_mm: float = 0.0) -> PartKind:
    """The free run of rope ``name`` from its drum tangent point ``p0_mm`` to its capstan
    tangent point ``p1_mm`` ((3,) mm) of transmission ``t`` (:class:`cad.device.Transmission`):
    a cylinder of the rope's diameter, its mass from the rope catalog's mass per metre (None
    when the catalog has none), not a BOM line of its own (``what`` names it in the
    description), its collision envelope trimmed by :func:`run_trim_mm` at both ends so the
    rope on its pulley is not a clash (by ``clearance_mm`` plus ``groove_depth_mm`` on grooved
    pulleys, whose crests stand that much above the rope's inner side). On a grooved capstan
    the drawn run itself stops where it meets the crests (:func:`run_trim_mm` with the groove
    depth): both runs are drawn at one height while the helical groove carries the turns along
    the capstan, so the run's last millimetres would lie on a crest, not in the groove."""
    p0, p1 = np.asarray(p0_mm, float), np.asarray(p1_mm, float)
    d = t.cable_diameter_mm
    L = float(np.linalg.norm(p1 - p0))
    u = (p1 - p0) / L
    s0 = run_trim_mm(0.5 * t.drum_diameter_mm, clearance_mm + groove_depth_mm)
    s1 = run_trim_mm(0.5 * t.capstan_diameter_mm, clearance_mm + groove_depth_mm)
    mpm = t.cable.mass_g_per_m
    p1_drawn = p1 - run_trim_mm(0.5 * t.capstan_diameter_mm, groove_depth_mm) * u
    return PartKind(
        name, shapes.rope_run_shape(tuple(p0), tuple(p1_drawn), d), material=ROPE_MATERIAL,
        made=False, listed=False, mass_kg=None if mpm is None else mpm * L * 1e-6,
        description=f"{what} ({L:.1f} mm; part of the rope's BOM line)",
        collision=(("self", shapes.rope_run_shape(tuple(p0 + s0 * u), tuple(p1 - s1 * u), d)),))


def axle_bearing(shaft_d_mm: float) -> cat.BearingSpec:
    """The joint axle's bearing: the widest catalog deep groove ball bearing of bore
    ``shaft_d_mm`` (626 for the maxon RE 35 / RE 40's 6 mm shaft). DesignError naming
    parts.motor when the catalog has none."""
    sizes = [cat.get_bearing(k) for k in cat.bearing_sizes() if k.startswith(f"M{shaft_d_mm:g}-")]
    if not sizes:
        raise DesignError("parts.motor", f"no catalog bearing of bore {shaft_d_mm:g} mm for the "
                          "joint's axle (capstan drive)")
    return max(sizes, key=lambda b: (b.B_mm, b.D_mm))


def tensioner_screw_mm(t) -> tuple[float, float]:
    """(length, head face's height above the rim) of the tensioner's ISO 4762 screw (mm): its
    thread engaged at least 1.5 d in the anchor's tapped hole (at most the hole's full thread),
    the lock nut and :data:`TENSIONER_WIND_D` rope diameters of shank above the rim; the
    shortest catalog length. DesignError naming transmission.cable when none fits."""
    cs = cat.get_cap_screw(ANCHOR_SCREW, "transmission")
    out = cat.get_nut(ANCHOR_SCREW).m_mm + TENSIONER_WIND_D * t.cable_diameter_mm
    L = cat.shortest_length(cs.lengths_mm, out + 1.5 * cs.d_mm)
    if L is None or L - out > ANCHOR_SCREW_LENGTH_MM:
        raise DesignError("transmission.cable", f"no ISO 4762 {ANCHOR_SCREW} length winds the "
                          f"{t.cable_diameter_mm:g} mm rope on the tensioner and holds in the anchor hole")
    return L, out


def capstan_set_screw(design, t, motor_key: str | None = None) -> tuple[str, float]:
    """(size, length mm) of the ISO 4026 set screw holding the capstan on the shaft of
    ``motor_key`` (default ``parts.motor``) (:func:`cad.assembly.fasteners.size_set_screw`);
    DesignError naming transmission.capstan_diameter_mm when the capstan's wall cannot hold one."""
    m = cat.get_motor(motor_key or design.parts.motor)
    rc = cg.rim_radius_mm(t.capstan_diameter_mm, t.cable_diameter_mm)
    try:
        size, L, _ = size_set_screw(m.shaft_diameter_mm / 2, rc, (motor.SET_SCREW,),
                                    "the capstan's set screw onto the motor shaft",
                                    "transmission.capstan_diameter_mm")
    except DesignError as e:  # the fix in the user's terms: the capstan's pitch diameter
        need = 2 * min_boss_radius_mm(m.shaft_diameter_mm / 2, (motor.SET_SCREW,)) + t.cable_diameter_mm
        raise DesignError(e.field, f"{e.reason}: a capstan of at least {need:.1f} mm (its rim is the "
                          f"pitch diameter less the {t.cable_diameter_mm:g} mm rope)") from None
    return size, L


def capstan_set_screw_fastening(design, t, capstan: str, shaft: str,
                                motor_key: str | None = None) -> tuple[Fastener, TappedHole]:
    """(record, hole) of the set screw holding the capstan instance ``capstan`` on the motor
    shaft instance ``shaft`` (every family's): the ISO 4026 screw of :func:`capstan_set_screw`
    (L engaged, point on the shaft) in the capstan's radial tapped hole ``"<capstan>:set_screw"``
    -- full-thread depth of :func:`cad.assembly.fasteners.size_set_screw`, minimum engagement
    1.5 d, axis +x at :data:`cad.actuators.capstan_geometry.CAPSTAN_HUB_MM` / 2 in the
    capstan's frame (:func:`cad.parts.capstan.capstan_shape`). With the record, assembly.md
    fastens it in the step that puts the capstan on the shaft (:mod:`cad.assembly.steps`).
    ``motor_key``: the shaft's motor (default ``parts.motor``)."""
    size, L = capstan_set_screw(design, t, motor_key)
    m = cat.get_motor(motor_key or design.parts.motor)
    rc = cg.rim_radius_mm(t.capstan_diameter_mm, t.cable_diameter_mm)
    _, _, depth = size_set_screw(m.shaft_diameter_mm / 2, rc, (size,), "the capstan's set screw onto the "
                                 "motor shaft", "transmission.capstan_diameter_mm")
    hole = TappedHole(f"{capstan}:set_screw", capstan, size, depth, MIN_ENGAGEMENT_ALU_D * cat.thread_diameter_mm(size),
                      axis=(1.0, 0.0, 0.0), point_mm=(0.0, 0.0, cg.CAPSTAN_HUB_MM / 2))
    return Fastener("ISO 4026", size, L, (shaft,), hole.name, L), hole


def drum_process(thickness_mm: float, fixing: str, groove: str = "") -> str:
    """The drum sector's process line of every family: the plate it is machined from, the rope
    groove when one is cut (``groove``: its words), the two radial tapped holes of the rope
    anchors (:data:`ANCHOR_SCREW`'s thread), then ``fixing`` (how the family fixes it)."""
    g = f"{groove}; " if groove else ""
    return (f"machined from {thickness_mm:g} mm plate; {g}drill and tap {ANCHOR_SCREW.split('-')[0]} x2 "
            f"radial (rope anchors); {fixing}")


def grooved_drum_texts(drum_diameter_mm: float, rim_radius_mm: float, rope_diameter_mm: float,
                       arc_deg: float, thickness_mm: float, where: str, fixing: str) -> tuple[str, str]:
    """(description, process) of a grooved drum sector, every family's: its pitch, the groove's
    bottom (``rim_radius_mm``, mm) and crests, arc, thickness and ``where`` it sits; the process
    line of :func:`drum_process` with the rope groove turned between the anchors."""
    h = cg.groove_depth_mm(rope_diameter_mm)
    desc = (f"drum sector {drum_diameter_mm:g} mm pitch (groove bottom {2 * rim_radius_mm:g} mm, crests "
            f"{2 * (rim_radius_mm + h):.4g} mm), {arc_deg:.0f} deg arc, {thickness_mm:g} mm thick, {where}")
    groove = (f"turn the rope groove ({rope_diameter_mm:g} mm rope, {h:.3g} mm deep) at mid-thickness "
              "between the anchors")
    return desc, drum_process(thickness_mm, fixing, groove)
