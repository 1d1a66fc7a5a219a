"""Where the haptic pen's capstans would sit (issue 35): for each pair of capstan motors the
5-bar's direction search (:func:`cad.families.pantograph.capstan.search_directions`), in the
pair's own plane. Pure numpy (no CAD import); the pen's capstan analyses are
:mod:`cad.families.pen.capstan`.

The pairs and their planes (mm, deg):

* **waists** (``A_q_waist``, ``B_q_waist``): the world's horizontal plane, the joints on the
  waist axes at (-l4/2, 0) and (+l4/2, 0); each drum on its waist bracket about the waist axis,
  both in one band above the base plate; each waist motor moved off its axis under the base
  plate, its mount plate a square of the waist motor's mount side; the link angle is the
  waist angle psi (the direction e_r of the arm's plane, :func:`cad.kinematics.haptic_pen.ik`);
  the other waist's hub (:data:`cad.families.pen.layout.WAIST_HUB_MM`) is the axle a drum must
  leave free;
* **arm X shoulders** (``X_q_lower``, ``X_q_upper``): the arm's plane in the 5-bar's own frame
  (x along the waist axis, up; y = rho, along e_r towards the pen; :mod:`cad.families.pen.layout`),
  the joints at (-l1/2, 0) and (+l1/2, 0); each drum on its proximal link about its shoulder
  axis, the shoulder motors moved off their axes on the waist bracket's motor plate. The two
  drums turn in bands of their own between the lower proximal layer and the motor plate (they
  may cross in the plane: ``shared_band`` False); the drum in the band by the plate is crossed
  by the other motor's shaft and capstan, which it must leave free (:func:`shaft_clash`, both
  orders tried).

In both, each free run of rope must leave the other joint's axle free too
(:func:`run_clearance_mm`; the search does not look at the runs, so a pair whose best
directions fail this is refused, not searched further).

A motor direction ``alpha`` is measured in its pair's plane from the x axis towards y (the
waists: world x towards y; the shoulders: up the waist axis towards the pen). The search keeps
the motors farthest from the workspace (smallest y). These are plane checks over the workspace
grid: necessary for the solids, not a proof (that is the build's every-pair interference check
over the solids, :mod:`cad.families.pen.capstan_solids` and :mod:`cad.families.pen.shoulder_capstan`).
"""

from __future__ import annotations

import dataclasses
import math
import types

import numpy as np

from cad.actuators import capstan_geometry as cg
from cad.data.catalog import get_motor
from cad.device import resolve_device
from cad.errors import DesignError
from cad.families.pantograph import capstan as pcap
from cad.families.pantograph import twin_placement as tp
from cad.families.pen import capstan as pen_capstan
from cad.families.pen.layout import WAIST_HUB_MM
from cad.kinematics import haptic_pen as kpen
from cad.parts.motor import mount_side_mm


@dataclasses.dataclass(frozen=True)
class PairLayout:
    """One pair of capstan motors of the pen: ``name`` (``waists``, ``arm A shoulders`` ..),
    ``joints`` (two of :data:`cad.families.pen.capstan.JOINTS`), ``sides`` the two
    :class:`cad.families.pantograph.capstan.CapstanSide` the direction search found (None when
    no direction clears), ``clash`` the refusal's words when the pair cannot be laid out (no
    direction, a rope run on the other axle, a capstan in the other drum's arc, a motor shaft
    too short for its capstan's band; None when laid out), ``plate_band`` the joint whose drum
    turns in the band by the motor plate (the shoulders; None for the waists' shared band)."""

    name: str
    joints: tuple
    sides: tuple | None
    clash: str | None
    plate_band: str | None = None


#: What fixes a pair that cannot be laid out, by pair kind.
FIXES = {"waists": "a smaller waist drum (ratio or capstan), a shorter centre_distance_mm, a longer "
                   "mechanism.pen_mm (l4 = l6, the waist axes' distance) or a smaller workspace",
         "shoulders": "a smaller shoulder drum (ratio or capstan), a shorter centre_distance_mm, a longer "
                      "mechanism.shoulder_base_mm or a smaller workspace"}


def _pairs(design) -> list[tuple[str, tuple, tuple, str, float, bool]]:
    """(name, joints, centres (2, 2) mm, motor key, keep radius mm, shared band) of each pair."""
    m, p = design.mechanism, design.parts
    keep_w = WAIST_HUB_MM[1] / 2 + pcap.CLEARANCE_MM
    keep_s = p.clevis_width_mm / 2 + pcap.CLEARANCE_MM
    out = [("waists", ("A_q_waist", "B_q_waist"), ((-m.l4_mm / 2, 0.0), (m.l4_mm / 2, 0.0)),
            p.waist_motor, keep_w, True)]
    for arm in ("A", "B"):
        out.append((f"arm {arm} shoulders", (f"{arm}_q_lower", f"{arm}_q_upper"),
                    ((-m.shoulder_base_mm / 2, 0.0), (m.shoulder_base_mm / 2, 0.0)), p.motor, keep_s, False))
    return out


def shaft_clash(sides, rims, q_deg: np.ndarray, k: int, capstan_rims) -> bool:
    """True when drum ``k``'s swept arc (:func:`cad.families.pantograph.capstan.swept_drum_mask`,
    ``rims[k]`` mm, link angles ``q_deg`` (K, 2) deg) meets the other side's capstan, a disc of
    ``capstan_rims[1 - k]`` + :data:`cad.families.pantograph.capstan.CLEARANCE_MM` / 2 mm about
    its motor (the other motor's shaft and capstan cross drum ``k``'s band)."""
    o = np.asarray(sides[1 - k].motor_xy_mm, float)
    r = capstan_rims[1 - k] + pcap.CLEARANCE_MM / 2
    g = np.arange(-r, r + pcap.SAMPLE_MM, pcap.SAMPLE_MM)
    pts = np.stack(np.meshgrid(g, g), -1).reshape(-1, 2)
    pts = o + pts[np.hypot(pts[:, 0], pts[:, 1]) <= r]
    return bool(np.any(pcap.swept_drum_mask(pts, sides[k], rims[k], q_deg[:, k])))


def run_clearance_mm(sides, rope_diameters_mm) -> float:
    """The least distance (mm) from either side's two free runs of rope (the rope's surface:
    its axis, a segment between the tangent points ``tangents_mm``, less half the rope) to the
    other side's joint: the runs stay put in the pair's plane while the joints turn (motor and
    joint axes are both fixed there), so one distance holds at every pose."""
    out = math.inf
    for k, sd in enumerate(sides):
        c = np.asarray(sides[1 - k].b_mm, float)
        for p0, p1 in np.asarray(sd.tangents_mm, float):
            u = p1 - p0
            t = float(np.clip((c - p0) @ u / (u @ u), 0.0, 1.0))
            out = min(out, float(np.hypot(*(p0 + t * u - c))) - 0.5 * rope_diameters_mm[k])
    return out


def _pair_layout(design, name, joints, centres, motor, keep, shared, ts, rng, q_deg) -> PairLayout:
    """The pair's :class:`PairLayout` (module docstring); DesignError from the capstans' own
    checks (the centre distance against the mount plates)."""
    half = mount_side_mm(get_motor(motor)) / 2
    for t in ts:
        pcap.check_centre_distance(design, t, half)
    fb = types.SimpleNamespace(base_left_mm=centres[0], base_right_mm=centres[1])
    best, why = pcap.search_directions(fb, ts, rng, q_deg, half, keep, shared_band=shared)
    rims = [pcap.swept_radius_mm(t) for t in ts]
    if best is None:
        counts = "; ".join(f"{pcap.CLASHES[k]} in {n}" for k, n in sorted(why.items(), key=lambda kv: -kv[1]))
        gap = math.dist(*centres)
        return PairLayout(name, joints, None,
                          f"{name}: no pair of motor directions (every {pcap.ALPHA_STEP_DEG:g} deg) places the "
                          f"capstans (drum {ts[0].drum_diameter_mm:g} mm, swept radius {max(rims):.1f} mm with "
                          f"the tensioner, joints {gap:g} mm apart): of {sum(why.values())} directions, {counts}; "
                          f"fix: {FIXES['waists' if shared else 'shoulders']}")
    sides = tuple(dataclasses.replace(s, joint=j) for s, j in zip(best, joints, strict=True))
    found = f"{name}: the directions found ({sides[0].alpha_deg:g} and {sides[1].alpha_deg:g} deg)"
    near = run_clearance_mm(sides, [t.cable_diameter_mm for t in ts]) - keep
    if near <= 0.0:
        return PairLayout(name, joints, sides,
                          f"{found} run a rope {-near:.1f} mm into the other joint's axle and hub clevis (radius "
                          f"{keep:g} mm); fix: {FIXES['waists' if shared else 'shoulders']}")
    if shared:  # the waists' band above the base plate, the motors under it and their mount plates
        short = max(tp.shaft_shortfall_mm(design, t, 1, motor) for t in ts)
        if short > 0.0:
            return PairLayout(name, joints, sides, f"{found}: {_short_words(design, motor, 1, short, True)}")
        return PairLayout(name, joints, sides, None)
    crests = [cg.crest_radius_mm(t.capstan_diameter_mm, t.cable_diameter_mm) for t in ts]
    plates = design.parts.motor_mount_thickness_mm  # the shoulder motors stand on the bracket's motor plate
    why = []
    for k in (1, 0):  # the upper drum by the plate first (the lower link's layer is the outer one)
        short = tp.shaft_shortfall_mm(design, ts[1 - k], 2, motor, plates)  # the other motor reaches band 2
        if shaft_clash(sides, rims, q_deg, k, crests):
            why.append("capstan turns in the swept arc of the drum by the plate")
        elif short > 0.0:
            why.append(_short_words(design, motor, 2, short, False))
        else:
            return PairLayout(name, joints, sides, None, joints[k])
    if why[0] == why[1]:
        return PairLayout(name, joints, sides, f"{found}: whichever drum turns by the motor plate, the other motor's "
                          f"{why[0]}")
    return PairLayout(name, joints, sides, f"{found}: " + "; ".join(
        f"with {joints[k]}'s drum by the plate, {joints[1 - k]}'s {w}" for k, w in zip((1, 0), why, strict=True)))


def _short_words(design, motor: str, band: int, short: float, under_base: bool) -> str:
    """The refusal's words for a motor shaft ``short`` mm too short for its capstan's hub in drum
    band ``band`` (:func:`cad.families.pantograph.twin_placement.shaft_shortfall_mm`), with the fix."""
    p = design.parts
    off = tp.band_rope_offset_mm(design, band)
    plates = (f"the {p.plate_thickness_mm:g} mm base plate and the {p.motor_mount_thickness_mm:g} mm mount plate"
              if under_base else f"the {p.motor_mount_thickness_mm:g} mm motor plate")
    fix = (f"parts.motor_mount_thickness_mm <= {p.motor_mount_thickness_mm - short:.2f}, a smaller "
           "parts.layer_gap_mm or fewer wraps" if not under_base else
           f"parts.plate_thickness_mm + motor_mount_thickness_mm <= "
           f"{p.plate_thickness_mm + p.motor_mount_thickness_mm - short:.2f} or fewer wraps")
    return (f"capstan hub in drum band {band} (its rope {off:g} mm past the plate) stands {short:.1f} mm past "
            f"the {motor} shaft's tip ({get_motor(motor).shaft_length_mm:g} mm from its face, through {plates}); "
            f"fix: {fix}")


#: The last design laid out and its layout: the build's pre-CAD check and the commands after it
#: ask for the same design object (the direction searches take seconds).
_LAST: list = [None, None]


def layout(design) -> tuple[PairLayout, ...]:
    """Each pair of the pen's capstan motors (module docstring), in the order waists, arm A
    shoulders, arm B shoulders; a pair of two direct motors is left out, a pair with one capstan
    and one direct motor is not laid out (its ``clash`` says so). Empty for a direct pen.
    DesignError (``workspace``) when a grid sample cannot be reached; DesignError
    (``transmission.centre_distance_mm``) when a motor's mount plate meets its own joint's
    block in every direction."""
    if not pen_capstan.has_capstan(design):
        return ()
    if _LAST[0] is design:
        return _LAST[1]
    out = _layout(design)
    _LAST[:] = [design, out]
    return out


def _layout(design) -> tuple[PairLayout, ...]:
    dev = resolve_device(design)
    q, st = kpen.ik(design.mechanism, design.workspace_points())
    rng = pen_capstan.joint_ranges_deg(design)  # refuses an unreachable sample first
    q_deg = np.degrees(np.unwrap(np.asarray(q, float), axis=0))
    out, done = [], {}
    for name, joints, centres, motor, keep, shared in _pairs(design):
        ts = [dev.transmission(j) for j in joints]
        if not any(t.is_capstan for t in ts):
            continue
        if not all(t.is_capstan for t in ts):
            direct = joints[[t.is_capstan for t in ts].index(False)]
            out.append(PairLayout(name, joints, None, f"{name}: {direct} is direct and its pair's motor turns "
                                  "through a capstan (not laid out); fix: give both a capstan or neither"))
            continue
        cols = [pen_capstan.JOINTS.index(j) for j in joints]
        # the poses' distinct angle pairs (the arms are mirror images over a symmetric grid: one search)
        q_pairs = np.unique(np.round(q_deg[:, cols], 6), axis=0)
        key = (tuple(str(dataclasses.replace(t, motor_joint="")) for t in ts), motor, keep, shared, q_pairs.tobytes(), np.round(rng[cols], 6).tobytes())
        if key not in done:
            done[key] = _pair_layout(design, name, joints, centres, motor, keep, shared, ts, rng[cols], q_pairs)
        out.append(_renamed(done[key], name, joints))
    return tuple(out)


def _renamed(pair: PairLayout, name: str, joints: tuple) -> PairLayout:
    """``pair`` laid out for the pair ``name`` of ``joints`` (the same search's answer)."""
    if pair.name == name:
        return pair
    sides = None if pair.sides is None else tuple(dataclasses.replace(s, joint=j)
                                                   for s, j in zip(pair.sides, joints, strict=True))
    plate = None if pair.plate_band is None else joints[pair.joints.index(pair.plate_band)]
    clash = None if pair.clash is None else name + pair.clash[len(pair.name):]
    for a, b in zip(pair.joints, joints, strict=True):
        clash = None if clash is None else clash.replace(a, b)
    return PairLayout(name, joints, sides, clash, plate)


def describe(pair: PairLayout) -> str:
    """A laid-out pair in words: each motor's direction (deg, in the pair's plane) and its
    centre distance (mm)."""
    s0, s1 = pair.sides
    return (f"{pair.name} at {s0.alpha_deg:g} / {s1.alpha_deg:g} deg, {s0.centre_distance_mm:g} / "
            f"{s1.centre_distance_mm:g} mm off their axes")


def refusal(design) -> str | None:
    """The one line (after ``transmission: ``) refusing the pen's capstan solids, None for a
    direct pen and whenever every pair of capstan motors is laid out (their solids:
    :mod:`cad.families.pen.capstan_solids` for the waists, :mod:`cad.families.pen.shoulder_capstan`
    for the shoulders); else each pair laid out (:func:`describe`) and what stops the others,
    with its count and fix (:func:`layout`)."""
    pairs = layout(design)
    if all(p.clash is None for p in pairs):
        return None
    ok = [describe(p) for p in pairs if p.clash is None]
    bad = [p.clash for p in pairs if p.clash is not None]
    where = f"the layout places the motors of {', '.join(ok)}; " if ok else ""
    return (f"the haptic pen's capstans cannot be laid out ({where}not laid out: {' | '.join(bad)}); see "
            "docs/families/pen.md (Capstan on the pen) for what its capstan analyses give")


def refuse_solids(design) -> None:
    """DesignError (``transmission``) in one line when a pair of the haptic pen's capstan
    motors cannot be laid out (:func:`refusal`; its analyses: :mod:`cad.families.pen.capstan`)."""
    why = refusal(design)
    if why is not None:
        raise DesignError("transmission", why)


def arm_sign(joint: str) -> float:
    """-1 for arm A's joints, +1 for arm B's (:mod:`cad.families.pen.layout`: arm A's waist
    axis at x = -l4/2)."""
    return -1.0 if joint.startswith("A_") else 1.0


def motor_in_body_mm(side) -> tuple[float, float]:
    """Where the moved motor's axis meets the plane of its drum, in the frame of the body that
    carries the motor (mm): a waist motor's (x, y) in the world (the ground; its axis vertical);
    a shoulder motor's (x, z) in its arm's waist frame (x = -sign e_r, z up,
    :func:`cad.families.pen.layout.body_poses`; its axis along the waist frame's y = n_out, the
    motor plate's offset along it is the solids'). From the pair's plane (module docstring):
    a shoulder's (x5, y5) = (z, rho) is the waist frame's (-sign rho, z)."""
    x, y = side.motor_xy_mm
    if side.joint.endswith("_waist"):
        return float(x), float(y)
    return -arm_sign(side.joint) * float(y), float(x)


def drum_arc_body_deg(side) -> tuple[float, float, tuple[float, float]]:
    """``(start, span, anchors)`` of the drum sector in the frame of the body that carries it
    (deg about that frame's z, counter-clockwise): a waist drum in its waist frame (z up,
    x = -sign e_r: the search's link angle psi is e_r's, so angles shift by 0 for arm A and
    180 deg for arm B); a shoulder drum in its proximal link's frame (z = n_out, which is the
    pair plane's normal e_z x e_r for arm A and its opposite for arm B: arm B's angles are
    mirrored, start -> -(start + span))."""
    s0, sp, an = side.arc_start_deg, side.arc_span_deg, tuple(side.anchors_deg)
    sign = arm_sign(side.joint)
    if side.joint.endswith("_waist"):
        off = 0.0 if sign < 0 else 180.0
        return s0 - off, sp, tuple(a - off for a in an)
    if sign < 0:
        return s0, sp, an
    return -(s0 + sp), sp, tuple(-a for a in an)
