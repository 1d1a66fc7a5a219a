"""Where the capstans of a twin-pantograph haptic mouse could sit (issue 35 §1), and what stops
them: the 5-bar's direction search (:func:`cad.families.pantograph.capstan.search_directions`)
applied to each of the twin's two 5-bars, the reach of a motor shaft into a stack of drum bands,
and the bridge posts against the swept drums. Pure numpy (no CAD import). :func:`group_layout`
is the build's layout of the twin's capstans (the solids:
:mod:`cad.families.pantograph.capstan_solids`, placed by :mod:`cad.families.pantograph.placement`):
each 5-bar with capstans on both motors has its two drums in one band (the 5-bar's search), or
the crank pantograph's, when they meet there, in two (:func:`two_band_sides`: the right drum
over the left, its motor raised by :func:`motor_raise_mm` with its mount plate on the base
plate's top, since a motor under it does not reach band 2's capstan, :func:`shaft_shortfall_mm`);
a 5-bar that fits neither way is refused in one line; the bridge posts step back out of every
drum's sweep (:func:`clear_post_y_mm`).

Frames and units as :mod:`cad.families.pantograph.capstan` (mm, deg, world = the kinematic base
frame, z = 0 on the base plate's top). The knob pantograph hangs under the bridge, its motors on
the bridge, shafts down; the crank pantograph stands on the base plate, its motors under it,
shafts up: a drum band ``k`` (1 next to the plate its motor hangs on) has its rope's plane
:func:`band_rope_offset_mm` from that plate's face, the same measure up from the base plate or
down from the bridge.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from cad.actuators import capstan_geometry as cg
from cad.assembly import capstan_hardware as hwc
from cad.data.catalog import get_motor
from cad.device import resolve_device
from cad.errors import DesignError
from cad.families.pantograph import capstan as pcap
from cad.families.pantograph import twin_capstan as tc
from cad.kinematics import twin_pantograph as ktwin
from cad.parts.motor import mount_side_mm
from cad.tolerances import CAPSTAN_RANGE_MARGIN_DEG

#: Each 5-bar of the twin: its columns in :data:`cad.families.pantograph.twin_capstan.JOINTS`.
GROUPS = {"knob": (0, 1), "crank": (2, 3)}
#: Bridge posts: offset along x from each actuated joint (mm).
POST_DX_MM = 22.0
#: Gap between a bridge post and the motor mount plates in front of it (mm), direct drive.
POST_GAP_MM = 8.0


def post_line_y_mm(design) -> float:
    """The bridge posts' line of a direct-drive twin (mm, world y): :data:`POST_GAP_MM` behind
    the mount plates of the motors at the joints (``-(mount side / 2 + post diameter / 2 + gap)``)."""
    return -(mount_side_mm(get_motor(design.parts.motor)) / 2 + design.parts.post_diameter_mm / 2 + POST_GAP_MM)


def posts_xy_mm(design, y_mm: float) -> list[tuple[float, float]]:
    """The four bridge posts (mm, world): x = each joint's +- :data:`POST_DX_MM`, on the line ``y_mm``."""
    a = design.params["base_mm"]
    return [(sx * a / 2 + dx, float(y_mm)) for sx in (-1, 1) for dx in (-POST_DX_MM, POST_DX_MM)]


def group_directions(design, group: str):
    """``(sides, why)`` of :func:`cad.families.pantograph.capstan.search_directions` on the
    twin's ``group`` 5-bar (``"knob"`` / ``"crank"``), both drums in one band: its links' ranges
    (:func:`cad.families.pantograph.twin_capstan.joint_ranges_deg`) and angles at the workspace
    samples (x, y and the crank turn), the motor's mount plate half side, the other joint kept
    ``clevis_width_mm / 2`` + :data:`cad.families.pantograph.capstan.CLEARANCE_MM` clear.
    ``sides`` None when no mirrored pair of directions clears; ``why`` counts each clash kind."""
    cols = list(GROUPS[group])
    dev = resolve_device(design)
    ts = tuple(dev.transmission(tc.JOINTS[c]) for c in cols)
    rng = tc.joint_ranges_deg(design)[cols]
    q = np.degrees(np.unwrap(ktwin.ik(design.mechanism, design.workspace_points()).q_rad, axis=0))[:, cols]
    half = mount_side_mm(get_motor(design.parts.motor)) / 2
    keep = design.parts.clevis_width_mm / 2 + pcap.CLEARANCE_MM
    return pcap.search_directions(getattr(design.mechanism, group), ts, rng, q, half, keep)


def band_rope_offset_mm(design, band: int) -> float:
    """The rope's plane of drum band ``band`` (1, 2, ...) from the face of the plate its motor
    hangs on (mm): ``band`` layer gaps, ``band - 1`` drums below it and half a drum
    (:data:`cad.families.pantograph.capstan.DRUM_THICKNESS_MM`); band 1 is the 5-bar's
    (:func:`cad.families.pantograph.capstan.rope_plane_z_mm`)."""
    g, th = design.parts.layer_gap_mm, pcap.DRUM_THICKNESS_MM
    return band * g + (band - 1) * th + th / 2


def shaft_shortfall_mm(design, t, band: int, motor: str | None = None, plates_mm: float | None = None) -> float:
    """How far the capstan's set-screw hub in drum band ``band`` stands past the motor shaft's
    tip (mm; > 0: the shaft is too short, as
    :func:`cad.families.pantograph.capstan_solids.check_capstan_z` refuses): the hub's top half
    the turns (:data:`cad.actuators.capstan_geometry.GROOVE_PITCH_D` d per wrap) below the
    rope's plane, the tip the shaft's length from the motor face less ``plates_mm`` (default:
    the plate and the mount plate). ``motor``: the catalog key (default ``parts.motor``)."""
    p = design.parts
    plates = p.plate_thickness_mm + p.motor_mount_thickness_mm if plates_mm is None else plates_mm
    tip = -plates + get_motor(p.motor if motor is None else motor).shaft_length_mm
    hub_top = band_rope_offset_mm(design, band) - 0.5 * cg.GROOVE_PITCH_D * t.cable_diameter_mm * t.wraps
    return float(hub_top - tip)


def posts_in_swept_drums(design, sides, group: str) -> list[bool]:
    """For each bridge post of the direct-drive twin (:func:`posts_xy_mm` on :func:`post_line_y_mm`):
    True when a drum of ``sides`` (the ``group``'s, :func:`group_directions`) sweeps over any
    point of the post's circle (its diameter plus the clearance) at a workspace sample, its arc
    widened by :data:`cad.tolerances.CAPSTAN_RANGE_MARGIN_DEG` at both ends."""
    return [post_in_swept_drums(design, xy, {group: sides}) for xy in posts_xy_mm(design, post_line_y_mm(design))]


def post_in_swept_drums(design, xy_mm, sides_by_group: dict, q_all_deg: np.ndarray | None = None) -> bool:
    """True when a drum of ``sides_by_group`` (group -> its two :class:`CapstanSide`, in any
    band) sweeps over the circle of a bridge post at ``xy_mm`` (its diameter plus
    :data:`cad.families.pantograph.capstan.CLEARANCE_MM`) at a workspace sample, each drum's arc
    widened by :data:`cad.tolerances.CAPSTAN_RANGE_MARGIN_DEG` at both ends. ``q_all_deg`` (K, 4)
    the four links' angles at the samples (deg, :func:`link_angles_deg`; computed when None)."""
    q_all = link_angles_deg(design) if q_all_deg is None else q_all_deg
    dev = resolve_device(design)
    r_post = design.parts.post_diameter_mm / 2 + pcap.CLEARANCE_MM
    ring = np.linspace(0.0, 2 * np.pi, 73)[:-1]
    pts = np.vstack([np.asarray(xy_mm, float) + r_post * np.column_stack([np.cos(ring), np.sin(ring)]), xy_mm])
    for group, sides in sides_by_group.items():
        for col, s in zip(GROUPS[group], sides, strict=True):
            d = pts - np.asarray(s.b_mm, float)
            inside = np.hypot(d[:, 0], d[:, 1]) <= pcap.swept_radius_mm(dev.transmission(tc.JOINTS[col]))
            ang = np.degrees(np.arctan2(d[:, 1], d[:, 0]))
            # each angle once (any pose meeting is the answer; the knob's repeat over the crank turns)
            start = s.arc_start_deg + np.unique(q_all[:, col]) - CAPSTAN_RANGE_MARGIN_DEG
            on_arc = ((ang[None, :] - start[:, None]) % 360.0) <= s.arc_span_deg + 2 * CAPSTAN_RANGE_MARGIN_DEG
            if np.any(inside[None, :] & on_arc):
                return True
    return False


def link_angles_deg(design) -> np.ndarray:
    """(K, 4) the four proximal links' angles (deg, unwrapped, :data:`cad.families.pantograph.twin_capstan.JOINTS`
    order) at the workspace samples (x, y and the crank turn)."""
    return np.degrees(np.unwrap(ktwin.ik(design.mechanism, design.workspace_points()).q_rad, axis=0))


def clear_post_y_mm(design, x_mm: float, sides_by_group: dict, step_mm: float = 0.05) -> float:
    """The first y (mm, world), stepping back by ``step_mm`` from the direct-drive post line
    (:func:`post_line_y_mm`), where a bridge post at ``x_mm`` stands clear of every drum of
    ``sides_by_group`` (:func:`post_in_swept_drums`); drums only: the rope runs, capstans and
    the bridge's own extent are not in it (the build's interference check sees them)."""
    q_all = link_angles_deg(design)
    y = post_line_y_mm(design)
    while post_in_swept_drums(design, (x_mm, y), sides_by_group, q_all):
        y -= step_mm
    return float(y)


def two_band_directions_deg(design, group: str) -> tuple[list[float], list[float]]:
    """The directions (deg, every :data:`cad.families.pantograph.capstan.ALPHA_STEP_DEG`) of the
    ``group``'s left and right motors whose swept drum (its reach
    :func:`cad.families.pantograph.capstan.swept_radius_mm`, its arc widened by
    :data:`cad.tolerances.CAPSTAN_RANGE_MARGIN_DEG`) keeps the other joint's axle (the motor
    shaft's radius + :data:`cad.families.pantograph.capstan.CLEARANCE_MM`) clear at every
    workspace sample: with the two drums in two bands, the other drum is not in its band, the
    other link's axle is (its hub clevis above both bands)."""
    cols = list(GROUPS[group])
    dev = resolve_device(design)
    fb = getattr(design.mechanism, group)
    rng = tc.joint_ranges_deg(design)[cols]
    q = np.degrees(np.unwrap(ktwin.ik(design.mechanism, design.workspace_points()).q_rad, axis=0))[:, cols]
    r_axle = get_motor(design.parts.motor).shaft_diameter_mm / 2 + pcap.CLEARANCE_MM
    ring = np.linspace(0.0, 2 * np.pi, 73)[:-1]
    out: tuple[list[float], list[float]] = ([], [])
    for k in range(2):
        t = dev.transmission(tc.JOINTS[cols[k]])
        other = np.asarray((fb.base_left_mm, fb.base_right_mm)[1 - k], float)
        pts = np.vstack([other + r_axle * np.column_stack([np.cos(ring), np.sin(ring)]), other])
        for al in np.arange(-180.0, 180.0, pcap.ALPHA_STEP_DEG):
            s = pcap.capstan_side(fb, t, k, float(al), rng[k])
            d = pts - np.asarray(s.b_mm, float)
            inside = np.hypot(d[:, 0], d[:, 1]) <= pcap.swept_radius_mm(t)
            ang = np.degrees(np.arctan2(d[:, 1], d[:, 0]))
            start = s.arc_start_deg + q[:, k] - CAPSTAN_RANGE_MARGIN_DEG
            on_arc = ((ang[None, :] - start[:, None]) % 360.0) <= s.arc_span_deg + 2 * CAPSTAN_RANGE_MARGIN_DEG
            if not np.any(inside[None, :] & on_arc):
                out[k].append(float(al))
    return out


#: Step of the bridge posts' search back out of the drums' sweep in the build's layout (mm).
POST_STEP_MM = 0.5
#: Layouts by the design's content (:func:`layout_key`): the build's pre-CAD check, its layout
#: stage and every caller that loads the same file again ask for the same layout (each 5-bar's
#: direction search takes seconds); the last :data:`LAYOUT_CACHE_SIZE` kept.
_CACHE: dict = {}
LAYOUT_CACHE_SIZE = 8


def layout_key(design) -> str:
    """What :func:`group_layout` reads of a design, as one string: the family, the linkage, the
    workspace, the parts and the resolved device's transmissions (frozen dataclasses and plain
    dicts: their ``repr`` is their content)."""
    return repr((design.family, design.mechanism, design.workspace, design.parts,
                 resolve_device(design).transmissions))


def group_layout(design) -> dict:
    """The twin's capstans as the build lays them out: ``{"groups": {group: {"sides", "bands",
    "raise_mm", "rope_offset_mm", "lift_mm"}}, "post_y_mm"}``; ``{}`` for a twin with direct
    drive only (or another family). Each 5-bar (``"knob"`` / ``"crank"``) with capstans on both
    motors has its two drums placed by :func:`group_sides` (``sides`` its two
    :class:`cad.families.pantograph.capstan.CapstanSide` with ``joint`` the resolved device's
    name, :data:`cad.families.pantograph.twin_capstan.JOINTS`), the rope's plane
    ``rope_offset_mm`` (:func:`band_rope_offset_mm` band 1) from the face of the plate its
    motors hang on. The bridge posts' line ``post_y_mm``: the direct-drive line (:func:`post_line_y_mm`) stepped
    back by :data:`POST_STEP_MM` until every post clears every drum's sweep
    (:func:`clear_post_y_mm`). DesignError naming ``transmission`` (with the clash counts or
    the shaft's shortfall, and what fixes it) when a 5-bar cannot be laid out. Each group also
    carries ``bands`` (each side's drum band, 1 or 2: :func:`group_sides`) and ``raise_mm``
    (each side's motor raised by :func:`motor_raise_mm` when its drum is in band 2); its
    layers move off the plate by a drum and a gap per band (``lift_mm``)."""
    if design.family != "twin-pantograph" or not tc.has_capstan(design):
        return {}
    key = layout_key(design)
    if key in _CACHE:
        return _CACHE[key]
    groups = {}
    for g in GROUPS:
        placed = group_sides(design, g)
        if placed:
            sides, bands = placed
            th, gap = pcap.DRUM_THICKNESS_MM, design.parts.layer_gap_mm
            groups[g] = {"sides": sides, "bands": bands, "rope_offset_mm": band_rope_offset_mm(design, 1),
                         "raise_mm": tuple(motor_raise_mm(design) if b > 1 else 0.0 for b in bands),
                         "lift_mm": max(bands) * (th + gap)}
    sbg = {g: v["sides"] for g, v in groups.items()}
    xs = sorted({x for x, _ in posts_xy_mm(design, 0.0)})
    out = {"groups": groups, "post_y_mm": min(clear_post_y_mm(design, x, sbg, POST_STEP_MM) for x in xs)}
    if len(_CACHE) >= LAYOUT_CACHE_SIZE:
        _CACHE.pop(next(iter(_CACHE)))
    _CACHE[key] = out
    return out


def group_sides(design, group: str):
    """``(sides, bands)``: the ``group``'s two :class:`cad.families.pantograph.capstan.CapstanSide`
    (joints named as the resolved device) and each one's drum band, or None for direct drive.
    One band when a mirrored pair of directions clears there (:func:`group_directions`), else,
    on the crank pantograph, two (:func:`two_band_sides`: the right drum over the left, its
    motor raised). DesignError naming ``transmission`` for one capstan and one direct motor on
    a 5-bar, a capstan hub past the shaft's tip in band 1 (:func:`shaft_shortfall_mm`), or no
    layout (the capstans' own checks first: the set screw's wall, the centre distance)."""
    cols = GROUPS[group]
    dev = resolve_device(design)
    ts = [dev.transmission(tc.JOINTS[c]) for c in cols]
    names = " and ".join(tc.JOINTS[c] for c in cols)
    if not any(t.is_capstan for t in ts):
        return None
    if not all(t.is_capstan for t in ts):
        raise DesignError("transmission", f"the twin's {group} pantograph with one motor through a capstan and one "
                          f"direct is not built (its motors would sit at different heights): give {names} both a "
                          "capstan or both direct drive")
    half = mount_side_mm(get_motor(design.parts.motor)) / 2
    for t in ts:
        hwc.capstan_set_screw(design, t)
        pcap.check_centre_distance(design, t, half)
        short = shaft_shortfall_mm(design, t, 1)
        if short > 0:
            raise DesignError("transmission.wraps", f"{t.wraps:g} turns put the {group} pantograph's capstan hub "
                              f"{short:.1f} mm past the {design.parts.motor} shaft's tip: fewer wraps or a thinner rope")
    sides, why = group_directions(design, group)
    bands = (1, 1)
    if sides is None:
        sides, bands = two_band_sides(design, group, ts), (1, 2)
    if sides is None:
        raise DesignError("transmission", one_band_refusal(design, group, ts, why))
    return tuple(dataclasses.replace(s, joint=tc.JOINTS[c]) for s, c in zip(sides, cols, strict=True)), bands


def max_gap_for_band_2_mm(design, short_mm: float, rise_mm: float) -> float | None:
    """The largest ``parts.layer_gap_mm`` (mm, floored to 0.01 mm) at which drum band 2's
    capstan hub is back on a raised motor's shaft: band 2's rope plane sits two layer gaps up
    (:func:`band_rope_offset_mm`), so the hub drops 2 mm per mm of gap; None when no positive
    gap reaches (``short_mm``: :func:`shaft_shortfall_mm` band 2, ``rise_mm``:
    :func:`motor_raise_mm`)."""
    g = design.parts.layer_gap_mm - (short_mm - rise_mm) / 2.0
    g = math.floor(g * 100.0) / 100.0
    return g if g > 0 else None


def motor_raise_mm(design) -> float:
    """How much higher a motor sits with its mount plate on the base plate's top instead of
    under it (mm): the plate and the mount plate, ``plate_thickness_mm + motor_mount_thickness_mm``
    (its body down through the plate's opening)."""
    return design.parts.plate_thickness_mm + design.parts.motor_mount_thickness_mm


def two_band_sides(design, group: str, ts):
    """The crank pantograph's two sides with the right drum in band 2 (over the left's band 1),
    the right motor raised by :func:`motor_raise_mm` so its shaft reaches band 2's capstan; None
    when the raise falls short of :func:`shaft_shortfall_mm` (band 2), on the knob pantograph
    (its motors hang on the bridge), or when no mirrored pair of :func:`two_band_directions_deg`
    keeps the motors' mount plates (squares of the mount side, :data:`CLEARANCE_MM` apart) off
    both bearing blocks and each other. Of the clear pairs, the motors farthest from the
    workspace (the smallest y), as :func:`cad.families.pantograph.capstan.search_directions`."""
    if group != "crank" or max(shaft_shortfall_mm(design, t, 2) for t in ts) > motor_raise_mm(design):
        return None
    fb = getattr(design.mechanism, group)
    rng = tc.joint_ranges_deg(design)[list(GROUPS[group])]
    half = mount_side_mm(get_motor(design.parts.motor)) / 2
    left, right = two_band_directions_deg(design, group)
    best, best_y = None, np.inf
    for al in left:
        ar = (180.0 - al + 180.0) % 360.0 - 180.0
        if not any(abs(ar - a) < 1e-9 for a in right):
            continue
        sides = tuple(pcap.capstan_side(fb, t, i, a, rng[i]) for i, (t, a) in enumerate(zip(ts, (al, ar), strict=True)))
        squares = [np.asarray(fb.base_left_mm, float), np.asarray(fb.base_right_mm, float)] + [
            np.asarray(sd.motor_xy_mm, float) for sd in sides]
        meet = any(np.abs(squares[2 + k] - q).max() < 2 * half + pcap.CLEARANCE_MM
                   for k in range(2) for j, q in enumerate(squares) if j != 2 + k)
        y = max(sd.motor_xy_mm[1] for sd in sides)
        if not meet and y < best_y:
            best, best_y = sides, y
    return best


def one_band_refusal(design, group: str, ts, why: dict) -> str:
    """The one line refusing a twin whose ``group``'s drums meet in one band for every mirrored
    pair of directions: the drum, its swept radius and the joints' distance, the clash counts
    (:data:`cad.families.pantograph.capstan.CLASHES`), the second band's shaft shortfall
    (:func:`shaft_shortfall_mm` band 2; two bands are not built) and what fixes it."""
    counts = "; ".join(f"{pcap.CLASHES[k]} in {n}" for k, n in sorted(why.items(), key=lambda kv: -kv[1]))
    short = max(shaft_shortfall_mm(design, t, 2) for t in ts)
    rise = motor_raise_mm(design)
    second = (f"a second band would put its capstan's hub {short:.1f} mm past the {design.parts.motor} shaft's tip, "
              f"more than the {rise:g} mm a motor gains on the plate's top" if short > rise and group == "crank" else
              "a second band (the crank pantograph's) keeps no clear pair of motor directions" if group == "crank"
              else "a second band is not built under the bridge")
    names = " and ".join(tc.JOINTS[c] for c in GROUPS[group])
    gap = max_gap_for_band_2_mm(design, short, rise) if short > rise and group == "crank" else None
    lower = f"set parts.layer_gap_mm <= {gap:.2f} (band 2 then reaches the raised shaft), " if gap else ""
    return (f"the twin's {group} pantograph's two {ts[0].drum_diameter_mm:g} mm drums (swept radius "
            f"{pcap.swept_radius_mm(ts[0]):.1f} mm with the tensioner, joints {design.params['base_mm']:g} mm apart) "
            f"meet in one band for every mirrored pair of motor directions (every {pcap.ALPHA_STEP_DEG:g} deg: "
            f"{counts}) and {second}: {lower}use a smaller drum (ratio or capstan), or direct drive on {names} "
            "([[transmission]] kind = \"direct\" for those motors)")
