"""Where the capstans of a 5-bar pantograph sit (issue 35): one per motor, each motor moved off
its joint B by the centre distance C, the drum sector on the proximal link about B, the link on
its own axle at B. Pure numpy (no CAD import); the solids are
:mod:`cad.families.pantograph.capstan_solids`.

Frames and units (mm, deg; world = the kinematic base frame, z = 0 on the base plate's top):

* the drums lie in one band above the base plate, z ``layer_gap_mm`` .. + :data:`DRUM_THICKNESS_MM`
  (the linkage's layers rise by the band and one more gap, :func:`lift_mm`); the rope's plane is
  the band's middle;
* each motor hangs under the base plate at ``B + C (cos alpha, sin alpha)``, its capstan on its
  shaft in the rope's plane; ``C``: the design's ``transmission.centre_distance_mm`` or the
  pitch circles :data:`cad.actuators.capstan.CAPSTAN_GAP_MM` apart;
* the joint's range ``[q_min, q_max]``: the proximal link's angle over the workspace grid
  (``[workspace]``, boundary included) widened by :data:`CAPSTAN_RANGE_MARGIN_DEG` on each side; the drum's
  arc in the link's frame spans 2 gamma + range + two anchors
  (:func:`cad.actuators.capstan_geometry.drum_arc_link_deg`), so over the range it sweeps
  ``span + range`` of world angles about B.

``alpha`` of each motor (:func:`motor_directions_deg`): of the directions every
:data:`ALPHA_STEP_DEG`, mirrored about the y axis for the right motor, the pair whose two drums
(the rope groove's crests plus the tensioner standing out of them) share no point of the plane at any pose of the
workspace grid (each arc widened by :data:`CAPSTAN_RANGE_MARGIN_DEG`) and leave the other joint's axle and
hub clevis (radius ``clevis_width_mm / 2`` + ``clearance``) free, whose motor mount plates stand clear of both bearing blocks and of each
other, the motors farthest from the workspace (the smallest y). The build's interference check
over the motion is what proves the solids clear.

Each capstan motor is also a :class:`cad.datasheet.capstan_rows.CapstanJoint`
(:func:`capstan_joints`, suffix ``_1`` left, ``_2`` right): its datasheet rows and limits at the
peak load and the ropes' stiffness at the handle (:func:`capstan_rows`), its rope's BOM line
(:func:`bom_lines`) and assembly.md's winding steps (:func:`winding_steps`), all from the shared
module.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cad.actuators import capstan as cap
from cad.actuators import capstan_geometry as cg
from cad.assembly import capstan_hardware as hwc
from cad.assembly.capstan_hardware import ANCHOR_SCREW, TENSIONER_WIND_D
from cad.data.catalog import get_cap_screw, get_motor, get_nut
from cad.datasheet import capstan_rows as cr
from cad.datasheet import row
from cad.device import resolve_device
from cad.errors import DesignError
from cad.families.pantograph import twin_capstan
from cad.families.pen import capstan as pen_capstan
from cad.kinematics import fivebar as fb5
from cad.parts.motor import mount_side_mm
from cad.tolerances import CAPSTAN_RANGE_MARGIN_DEG

#: The drum sector's thickness along its axis (mm; the rope's plane at its middle, the anchors'
#: M3 radial screws) and its material: the four-bar's.
DRUM_THICKNESS_MM, DRUM_MATERIAL = hwc.DRUM_THICKNESS_MM, hwc.DRUM_MATERIAL
#: Arc an anchor takes on the drum at each end, mm: the capstan rows' (their drum arc and cut length).
ANCHOR_LENGTH_MM = cr.ANCHOR_LENGTH_MM
#: Candidate motor directions (deg) tried by :func:`motor_directions_deg`.
ALPHA_STEP_DEG = 5.0
#: Clearance kept between parts by the direction search (mm): the interference check's gap.
CLEARANCE_MM = 1.0
#: Plane sampling of the swept drums in the direction search (mm).
SAMPLE_MM = 1.5
SIDES = ("left", "right")


@dataclass(frozen=True)
class CapstanSide:
    """One motor's capstan (mm, deg, world): ``joint`` (``q_left`` / ``q_right``), ``b_mm`` the
    joint B, ``alpha_deg`` the motor's direction from B, ``centre_distance_mm`` C,
    ``motor_xy_mm``, ``gamma_rad`` the tangent points' half angle, ``tangents_mm`` (2, 2, 2) the
    rope runs' end points (drum, capstan), ``q_range_deg`` (min, max) the link's range,
    ``arc_start_deg`` / ``arc_span_deg`` the drum sector in the link's frame, ``anchors_deg``
    the anchors' link-frame angles."""

    joint: str
    b_mm: tuple
    alpha_deg: float
    centre_distance_mm: float
    motor_xy_mm: tuple
    gamma_rad: float
    tangents_mm: np.ndarray
    q_range_deg: tuple
    arc_start_deg: float
    arc_span_deg: float
    anchors_deg: tuple


def is_capstan(design) -> bool:
    """True when a motor of the 5-bar drives its joint through a capstan."""
    return design.family == "pantograph" and any(t.is_capstan for t in _transmissions(design))


def _transmissions(design):
    dev = resolve_device(design)
    return tuple(dev.transmission(j) for j in ("q_left", "q_right"))


def lift_mm(design) -> float:
    """How much the linkage's layers rise for the drums' band (mm; 0 for direct drive)."""
    return DRUM_THICKNESS_MM + design.parts.layer_gap_mm if is_capstan(design) else 0.0


def rope_plane_z_mm(design) -> float:
    """The rope's plane (mm, world z): the middle of the drums' band."""
    return design.parts.layer_gap_mm + DRUM_THICKNESS_MM / 2


def joint_ranges_deg(design) -> np.ndarray:
    """(2, 2) [[q_min, q_max] left, right] of the proximal links over the workspace grid, deg,
    widened by :data:`CAPSTAN_RANGE_MARGIN_DEG` (module docstring). DesignError (``workspace``) when a
    sample cannot be reached."""
    ik = fb5.ik(design.mechanism, design.workspace_points())
    if np.any(ik.status != 0):
        raise DesignError("workspace", "a capstan's drum needs the whole workspace reachable: "
                          f"{int(np.sum(ik.status != 0))} grid points are not")
    q = np.degrees(np.unwrap(ik.q_rad, axis=0))
    return np.column_stack([q.min(axis=0) - CAPSTAN_RANGE_MARGIN_DEG, q.max(axis=0) + CAPSTAN_RANGE_MARGIN_DEG])


def _swept_mask(pts: np.ndarray, b, r_in: float, r_out: float, start_deg: float, span_deg: float) -> np.ndarray:
    """Points (N, 2) inside the annular sector about ``b`` (world angles from ``start_deg``,
    counter-clockwise over ``span_deg``)."""
    d = pts - np.asarray(b, float)
    r = np.hypot(d[:, 0], d[:, 1])
    a = (np.degrees(np.arctan2(d[:, 1], d[:, 0])) - start_deg) % 360.0
    return (r >= r_in) & (r <= r_out) & (a <= span_deg)


def swept_drum_mask(pts: np.ndarray, side: CapstanSide, rim_mm: float, q_deg: np.ndarray) -> np.ndarray:
    """(K, N) bool: which plane points ``pts`` (N, 2) mm the drum of ``side`` covers at each of
    the link angles ``q_deg`` (K,) deg: within ``rim_mm`` + :data:`CLEARANCE_MM` / 2 of its
    joint and inside its arc (link frame ``arc_start_deg`` + q, over ``arc_span_deg``) widened
    by :data:`CAPSTAN_RANGE_MARGIN_DEG` at both ends (the motion between samples)."""
    d = pts - np.asarray(side.b_mm, float)
    near = np.hypot(d[:, 0], d[:, 1]) <= rim_mm + CLEARANCE_MM / 2
    ang = np.degrees(np.arctan2(d[:, 1], d[:, 0]))
    start = side.arc_start_deg + np.asarray(q_deg, float) - CAPSTAN_RANGE_MARGIN_DEG  # (K,) world start of the arc
    idx = np.flatnonzero(near)  # the arc's test on the points within reach only (the same mask, half the work)
    out = np.zeros((len(start), len(pts)), dtype=bool)
    out[:, idx] = ((ang[None, idx] - start[:, None]) % 360.0) <= side.arc_span_deg + 2 * CAPSTAN_RANGE_MARGIN_DEG
    return out


def capstan_side(fb, t, i: int, alpha: float, rng) -> CapstanSide:
    b = (fb.base_left_mm, fb.base_right_mm)[i]
    dd, dc = t.drum_diameter_mm, t.capstan_diameter_mm
    C = cap.centre_distance_mm(dc, dd, t.centre_distance_mm)
    g = cg.tangent_half_angle_rad(dd, dc, C)
    anchor = math.degrees(2.0 * ANCHOR_LENGTH_MM / dd)
    a = math.radians(alpha)
    o = (b[0] + C * math.cos(a), b[1] + C * math.sin(a))
    lo, hi = float(rng[0]), float(rng[1])
    start, span = cg.drum_arc_link_deg(alpha, g, lo, hi, anchor)
    return CapstanSide(("q_left", "q_right")[i], tuple(b), float(alpha), C, o, g,
                       cg.external_tangent_points_mm(b, 0.5 * dd, o, 0.5 * dc), (lo, hi), start, span,
                       cg.anchor_angles_link_deg(alpha, g, lo, hi, anchor))


def anchor_protrusion_mm(t) -> float:
    """How far the tensioner stands out of the drum's crests (mm): its lock nut, the rope's
    ``TENSIONER_WIND_D`` diameters of shank and its screw head (the four-bar's anchors and
    tensioner, :mod:`cad.families.fourbar.capstan_solids`)."""
    return (get_nut(ANCHOR_SCREW).m_mm + TENSIONER_WIND_D * t.cable_diameter_mm
            + get_cap_screw(ANCHOR_SCREW, "transmission").k_mm)


def _clear(sides, rims, keep: float, half: float, q_deg: np.ndarray, shared_band: bool = True) -> str | None:
    """None when the pair of sides' drums are clear of each other (when they share one band,
    ``shared_band``) and of the other joint's axle
    and hub clevis at every pose of the workspace grid (``q_deg`` (K, 2) the links' angles
    there), each drum's arc widened by :data:`CAPSTAN_RANGE_MARGIN_DEG` at both ends (the motion
    between grid samples), and the motor mount plates clear of the bearing blocks and of each
    other (module docstring); else what meets (one of :data:`CLASHES`' keys)."""
    b = [np.asarray(s.b_mm, float) for s in sides]
    m = [np.asarray(s.motor_xy_mm, float) for s in sides]
    squares = b + m  # bearing blocks at B, mount plates at the motors: squares of half side `half`
    for k, mk in enumerate(m):
        for j, q in enumerate(squares):
            if j != 2 + k and np.abs(mk - q).max() < 2 * half + CLEARANCE_MM:
                return "mounts"
    R = max(rims) + keep
    lo, hi = np.minimum(*b) - R, np.maximum(*b) + R
    xs, ys = np.arange(lo[0], hi[0], SAMPLE_MM), np.arange(lo[1], hi[1], SAMPLE_MM)
    pts = np.stack(np.meshgrid(xs, ys), -1).reshape(-1, 2)
    if any(s.arc_span_deg + 2 * CAPSTAN_RANGE_MARGIN_DEG >= 360.0 for s in sides):
        return "circle"
    # each test on the plane points that can meet (within both drums' reach, within the other
    # axle's): the same answer as on the whole grid, a fraction of the work
    reach = [np.hypot(*(pts - b[k]).T) <= rims[k] + CLEARANCE_MM / 2 for k in range(2)]
    # the poses a block of POSE_BLOCK at a time, stopping at the first that meets: the same rows
    # of the same masks, so the same answer, without the rest of the poses once one meets
    blocks = [slice(i, i + POSE_BLOCK) for i in range(0, len(q_deg), POSE_BLOCK)]
    if shared_band:
        p = pts[reach[0] & reach[1]]
        if any(np.any(swept_drum_mask(p, sides[0], rims[0], q_deg[r, 0]) & swept_drum_mask(p, sides[1], rims[1], q_deg[r, 1]))
               for r in blocks):
            return "drums"
    for k in range(2):  # the other joint's axle and hub clevis
        p = pts[np.hypot(*(pts - b[1 - k]).T) <= keep]
        if any(np.any(swept_drum_mask(p, sides[k], rims[k], q_deg[r, k])) for r in blocks):
            return "joint"
    return None


#: Poses per block of :func:`_clear`'s sweep (a working-set size only: the answer is the same).
POSE_BLOCK = 48


#: What :func:`_clear` finds meeting, as the refusal words it.
CLASHES = {"mounts": "a motor's mount plate meets a bearing block or the other mount",
           "circle": "a drum's swept arc closes a full circle",
           "drums": "the two swept drums meet",
           "joint": "a swept drum meets the other joint's axle and hub clevis"}


def check_centre_distance(design, t, half: float) -> None:
    """DesignError naming ``transmission.centre_distance_mm`` when the motor's mount plate (half
    side ``half`` mm) would meet its own joint's bearing block in every direction: the centre
    distance C below 2 half + :data:`CLEARANCE_MM` (the mount square's side, plus the gap)."""
    C = cap.centre_distance_mm(t.capstan_diameter_mm, t.drum_diameter_mm, t.centre_distance_mm)
    need = 2 * half + CLEARANCE_MM
    if C < need:
        how = ("given" if t.centre_distance_mm is not None else
               f"the pitch circles of the {t.capstan_diameter_mm:g} mm capstan and the "
               f"{t.drum_diameter_mm:g} mm drum")
        raise DesignError("transmission.centre_distance_mm",
                          f"{C:g} mm ({how}) puts each motor's {2 * half:g} mm mount plate on its own "
                          f"link's bearing block in every direction: give centre_distance_mm >= {need:g} "
                          "or a larger drum (ratio or drum_diameter_mm)")


def motor_directions_deg(design) -> tuple[CapstanSide, CapstanSide]:
    """The two sides' :class:`CapstanSide` (module docstring). Direct-drive sides are None.
    First the capstans' own checks (the set screw's wall, the centre distance against the mount
    plates); DesignError naming ``transmission`` with what met in each direction tried when no
    pair of directions clears."""
    ts = _transmissions(design)
    rng = joint_ranges_deg(design)
    q_deg = np.degrees(np.unwrap(fb5.ik(design.mechanism, design.workspace_points()).q_rad, axis=0))
    half = mount_side_mm(get_motor(design.parts.motor)) / 2
    for t in ts:
        hwc.capstan_set_screw(design, t)
        check_centre_distance(design, t, half)
    keep = design.parts.clevis_width_mm / 2 + CLEARANCE_MM
    best, why = search_directions(design.mechanism, ts, rng, q_deg, half, keep)
    if best is None:
        rims = [swept_radius_mm(t) if t.is_capstan else 0.0 for t in ts]
        raise DesignError("transmission", _placement_refusal(design, ts, rims, why))
    return best


def swept_radius_mm(t) -> float:
    """How far a drum of transmission ``t`` reaches from its joint (mm): the rope groove's crests
    and the tensioner standing out of them (:func:`anchor_protrusion_mm`)."""
    return cg.crest_radius_mm(t.drum_diameter_mm, t.cable_diameter_mm) + anchor_protrusion_mm(t)


def search_directions(fb, ts, rng, q_deg: np.ndarray, half: float, keep: float, shared_band: bool = True):
    """``(sides, why)`` of the direction search on the 5-bar ``fb`` (``base_left_mm``,
    ``base_right_mm``; a twin's crank or knob pantograph alike): of the left motor's directions
    every :data:`ALPHA_STEP_DEG`, the right's its mirror about the y axis, the clear pair
    (:func:`_clear`: mount plates of half side ``half`` mm, the other joint kept ``keep`` mm
    clear) whose motors are farthest from the workspace; ``sides`` None when none clears.
    ``ts`` the two transmissions, ``rng`` (2, 2) their links' ranges (deg), ``q_deg`` (K, 2)
    the links' angles at the workspace samples; ``why`` counts each clash kind
    (:data:`CLASHES`; None for a clear pair) over the directions tried. ``shared_band`` False:
    the two drums turn in bands of their own (the haptic pen's shoulders,
    :mod:`cad.families.pen.capstan_layout`), so they may cross in the plane."""
    rims = [swept_radius_mm(t) if t.is_capstan else 0.0 for t in ts]
    # each pose once: _clear asks whether any pose meets, so a repeated row of angles (the
    # twin's knob 5-bar: the same (x, y) at every crank turn, 49 distinct rows of 392) adds
    # nothing but work; the rows kept are the same floats, so every answer is unchanged
    q_deg = np.unique(np.asarray(q_deg, float), axis=0)
    best, best_y, why = None, math.inf, {}
    for al in np.arange(-180.0, 180.0, ALPHA_STEP_DEG):
        ar = (180.0 - al + 180.0) % 360.0 - 180.0  # the mirror about the y axis
        sides = [capstan_side(fb, t, i, a, rng[i]) if t.is_capstan else None
                 for i, (t, a) in enumerate(zip(ts, (al, ar), strict=True))]
        if any(s is None for s in sides):
            continue
        y = max(s.motor_xy_mm[1] for s in sides)
        if y < best_y:
            clash = _clear(sides, rims, keep, half, q_deg, shared_band)
            why[clash] = why.get(clash, 0) + 1
            if clash is None:
                best, best_y = tuple(sides), y
    return best, why


def _placement_refusal(design, ts, rims, why: dict) -> str:
    """The one line of :func:`motor_directions_deg`'s refusal: the drums' swept radius, the
    joints' distance and, for the directions tried, how many met in each way."""
    counts = "; ".join(f"{CLASHES[k]} in {n}" for k, n in sorted(why.items(), key=lambda kv: -kv[1]))
    return (f"no pair of motor directions (every {ALPHA_STEP_DEG:g} deg) places the capstans "
            f"(drum {ts[0].drum_diameter_mm:g} mm, swept radius {max(rims):.1f} mm with the "
            f"tensioner, joints {design.params['base_mm']:g} mm apart): of {sum(why.values())} "
            f"directions, {counts}; use a smaller drum (ratio or capstan), a shorter "
            "centre_distance_mm (the arc 2 gamma grows with it), a longer base_mm or a smaller workspace")


#: The last design laid out and its layout: the build's pre-CAD check and its layout stage ask
#: for the same design object (the direction search takes a second or two).
_LAST: list = [None, None]


def layout(design) -> dict:
    """``{"sides": (CapstanSide, CapstanSide), "rope_z_mm", "drum_z_mm": (bottom, top),
    "lift_mm"}`` of a 5-bar with capstans (module docstring); ``{}`` for direct drive. A 5-bar
    needs a capstan on both motors or on neither (DesignError naming ``transmission``)."""
    if not is_capstan(design):
        return {}
    if _LAST[0] is design:
        return _LAST[1]
    out = _layout(design)
    _LAST[:] = [design, out]
    return out


def _layout(design) -> dict:
    if not all(t.is_capstan for t in _transmissions(design)):
        raise DesignError("transmission", "a 5-bar with one motor through a capstan and one direct is not "
                          "built (the motors sit at different heights): give both motors a capstan")
    g = design.parts.layer_gap_mm
    return {"sides": motor_directions_deg(design), "rope_z_mm": rope_plane_z_mm(design),
            "drum_z_mm": (g, g + DRUM_THICKNESS_MM), "lift_mm": lift_mm(design)}


def capstan_joints(design) -> tuple:
    """Each capstan-driven motor of the 5-bar as a :class:`cad.datasheet.capstan_rows.CapstanJoint`
    (its link's range over the workspace, :func:`joint_ranges_deg`; rows, BOM lines and
    assembly steps suffixed ``_1`` left, ``_2`` right); empty for direct drive. The twin
    pantograph's four: :func:`cad.families.pantograph.twin_capstan.capstan_joints`; the pen's
    six: :func:`cad.families.pen.capstan.capstan_joints`."""
    if design.family == "twin-pantograph":
        return twin_capstan.capstan_joints(design)
    if design.family == "haptic-pen":
        return pen_capstan.capstan_joints(design)
    if not is_capstan(design):
        return ()
    dev = resolve_device(design)
    rng = joint_ranges_deg(design)
    return tuple(cr.capstan_joint(dev, j, float(rng[i, 1] - rng[i, 0]), f"{j.split('_')[1]} proximal link",
                                  f"_{i + 1}", inertia_in="the effective mass, the MJCF armature and the "
                                  "firmware's mass matrix")
                 for i, j in enumerate(("q_left", "q_right")) if dev.transmission(j).is_capstan)


def rope_compliance_m_per_N(design, k_q: dict) -> np.ndarray:
    """The handle's compliance from the ropes alone over the workspace grid, largest
    eigenvalue of J^-1 diag(1 / k_q) J^-T (m/N, (N,)); J = dq/dx (rad/m): the links rigid, the
    motors held, each rope a torsional spring ``k_q[joint]`` (N m/rad) at its joint. The twin
    pantograph's: :func:`cad.families.pantograph.twin_capstan.rope_compliance_m_per_N`; the
    pen's: :func:`cad.families.pen.capstan.rope_compliance_m_per_N`."""
    if design.family == "twin-pantograph":
        return twin_capstan.rope_compliance_m_per_N(design, k_q)
    if design.family == "haptic-pen":
        return pen_capstan.rope_compliance_m_per_N(design, k_q)
    J, st = fb5.jacobian_rad_per_m(design.mechanism, design.workspace_points())
    ok = np.asarray(st) == fb5.STATUS_OK
    kinv = np.array([1.0 / k_q[j] if k_q.get(j) else 0.0 for j in ("q_left", "q_right")])
    Jinv = np.linalg.inv(np.asarray(J)[ok])
    C = np.einsum("nij,j,nkj->nik", Jinv, kinv, Jinv)
    return np.linalg.eigvalsh(C)[:, -1]


def capstan_rows(design, k_max_N_per_m: float | None) -> tuple[list[dict], dict]:
    """(rows, limits) of the 5-bar's capstans: each motor's rows at the peak load and its rope's
    stiffness (:mod:`cad.datasheet.capstan_rows`, suffixed ``_1`` / ``_2``), the ropes'
    stiffness at the handle (weakest direction and pose, :func:`rope_compliance_m_per_N`) and
    ``k_max_N_per_m`` (the datasheet's eq (25) K_max) in series with it; ``([], {})`` for direct drive."""
    rows, limits, k_q = cr.joints_rows(capstan_joints(design))
    if not k_q:
        return rows, limits
    c = rope_compliance_m_per_N(design, k_q)
    if not c.size or c.max() <= 0:  # direct motors hold the handle (a twin with three): no rope compliance there
        return rows, limits
    k_h = float(1.0 / c.max())
    src = ("1 / lambda_max(J^-1 diag(1 / k_q) J^-T), J = dq/dx, weakest direction and pose over the workspace "
           "grid (links rigid, motors held)")
    if design.family == "twin-pantograph":  # four ropes on three task coordinates
        src = twin_capstan.HANDLE_STIFFNESS_SOURCE
    elif design.family == "haptic-pen":  # six ropes on five task coordinates
        src = pen_capstan.HANDLE_STIFFNESS_SOURCE
    rows.append(row("cable_handle_stiffness_N_per_m", "rope stiffness at the handle", k_h, "N/m", src,
                    lo=k_h, hi=float(1.0 / c.min())))
    if k_max_N_per_m is not None:
        rows.append(row("K_max_with_cable_N_per_m", "renderable stiffness, ropes in series",
                        float(cap.series_stiffness(k_max_N_per_m, k_h)), "N/m",
                        f"1 / (1 / K_max + 1 / k_handle): the eq (25) K_max {k_max_N_per_m:.4g} N/m in series "
                        f"with the ropes' {k_h:.4g} N/m at the handle ({src})"))
    return rows, limits


def bom_lines(design) -> list[dict]:
    """The ropes (one per capstan motor, with its cut length), as bom.csv rows
    (:func:`cad.datasheet.capstan_rows.cable_bom_line`); empty for direct drive."""
    return [cr.cable_bom_line(j) for j in capstan_joints(design)]


def winding_steps(design) -> tuple[str, ...]:
    """``assembly.md``'s winding and tensioning steps of each capstan
    (:func:`cad.datasheet.capstan_rows.winding_steps`)."""
    return tuple(s for j in capstan_joints(design) for s in cr.winding_steps(j))
