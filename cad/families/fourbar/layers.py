"""Z-layers of the three moving bars and the joint stacks, chosen so nothing collides.

Pure numpy (no CAD import): every element of the mechanism (bars, spacers, screw
heads, nuts, hub, post, handle) is modelled here as a *rounded convex hull* -- the
convex hull of 1 to 3 points in its body's frame, grown by a radius -- over a z
interval. For a candidate layer order (bottom to top, one of the 6 permutations of
crank, coupler, rocker) the stack heights follow from the hardware (below); two
elements of different bodies whose z intervals overlap must stay
``clearance_min_mm`` apart in the plane at every sampled crank angle. The first
order (lowest top, then the order of :data:`ORDERS`) without a conflict is taken;
the exact 3-D sweep in :mod:`cad.assembly.interference` then checks the real solids.

Joint stack (same hardware at A2, A3, A4; heights along z, upward):

* the UPPER link at a joint holds the ball bearing in a seat counterbored from its
  bottom face (depth = bearing width B), leaving a lip ``t - B`` on top with a hole of
  the housing abutment diameter Da;
* a turned gap spacer (height = gap between the bars) sits on the LOWER link and
  carries the bearing's inner ring; a head-side spacer (shim) passes through the lip
  and carries the screw head ``pin_head_clearance_mm`` above the upper bar;
* the ISO 7379 shoulder screw goes through shim, inner ring and gap spacer into a
  reamed hole in the lower link (shoulder length L from the catalog list) and is
  clamped by a washer and nut under the lower link; on the ground post (A4) it
  screws into the post instead.

With the clamp length c = shim + B + spacer, the shoulder must end inside the lower
link with the nut on full thread: L - c in [lo, hi], lo = max(1, t + h_w + m - b),
hi = min(t - 0.5, t + h_w - g2) (h_w washer, m nut, b thread, g2 relief). When no
catalog length falls in the window the shim is lengthened.
"""

from __future__ import annotations

import hashlib
import itertools
import math
from dataclasses import dataclass

import numpy as np

from cad.assembly.fasteners import MIN_ENGAGEMENT_ALU_D, alu_hole, size_set_screw
from cad.data import catalog
from cad.design.parts import LINK_NAMES, PartsSpec
from cad.device import resolve_device
from cad.errors import DesignError
from cad.families.fourbar.pins import pin_window
from cad.families.fourbar.pose import planar_transforms
from cad.families.fourbar.sheet_tolerance import sheet_bands, size_over_band, thinnest_mm
from cad.kinematics.families import family_linkage
from cad.kinematics.linkgeom import link_joints_mm
from cad.parts.base import STANDOFF_TAP_DEPTH_MM
from cad.parts.motor import SET_SCREW
from cad.tolerances import LAYER_SLACK_MM

#: Tap lead-out below a hole's full thread (mm); see :mod:`cad.assembly.fasteners`.
TAP_LEADOUT_MM = 1.0
#: Solid hub below the hub screws' tapped holes (mm).
HUB_FLOOR_MM = 1.0

ORDERS: tuple[tuple[str, str, str], ...] = tuple(itertools.permutations(LINK_NAMES))  # type: ignore[assignment]
#: Joints: name -> (link A, link B) it connects (ground joint A4: rocker on the post).
JOINTS = {"A2": ("crank", "coupler"), "A3": ("coupler", "rocker"), "A4": ("rocker", "ground")}
#: A4 post: the reamed bore ends where the shoulder screw's thread relief g2 ends, so the
#: top tapped hole starts at the screw's first full thread and holds all of it
#: (:func:`cad.assembly.fasteners.shoulder_screw_hole`); the tapped hole runs this far past
#: the screw's length below the shoulder b (mm; b includes g2, so it is drilled
#: g2 + 1.5 mm past the tip), and :data:`POST_WEB_MM` of solid separates it from the
#: bottom hole. The post's total height rule is unchanged from the former layout
#: (bore 0.5 mm past the relief, hole b + 1 mm).
POST_THREAD_EXTRA_MM = 1.5
POST_WEB_MM = 1.0
#: Knob floor under the handle screw head (mm): the screw goes down through it into the
#: tapped coupler, so nothing hangs under the coupler at P.
HANDLE_SCREW_FLOOR_MM = 5.0
#: Screws fixing the crank to the hub (on the hub bolt circle, first at 90 deg).
HUB_SCREWS = 3
#: ISO 4026 set screws that may lock the crank hub on the motor shaft: M3
#: (:data:`cad.parts.motor.SET_SCREW`) first, a smaller one when the hub wall cannot take it.
HUB_SET_SCREW_SIZES = (SET_SCREW, "M2.5-0.45", "M2-0.4")


@dataclass(frozen=True)
class JointStack:
    """Heights (z, mm) of the hardware at one joint; see the module docstring."""

    joint: str
    upper: str
    lower: str
    z_upper_mm: float
    z_lower_top_mm: float
    spacer_mm: float
    shim_mm: float
    pin_length_mm: float
    clamp_mm: float
    nut: bool
    head_face_mm: float
    head_top_mm: float
    thread_end_mm: float


@dataclass(frozen=True)
class Element:
    """A rounded convex hull of ``points_mm`` (k<=3, body frame) grown by ``radius_mm``,
    over ``z_mm`` = (lo, hi), carried by ``body``; ``anchor`` is the layer level it moves
    with when gaps change (None: it spans layers or is fixed to the ground). ``z_margin_mm``:
    hardware standing proud of its layer (screw heads, washer + nut, the handle) is checked
    in plan against another body's element also when their z intervals are less than this
    apart (``clearance_min_mm``: the 3-D sweep needs that much, touching is a contact)."""

    label: str
    body: str
    points_mm: np.ndarray
    radius_mm: float
    z_mm: tuple[float, float]
    anchor: int | None = None
    z_margin_mm: float = 0.0


@dataclass(frozen=True)
class LayerPlan:
    """The chosen stack: bar z (bottom faces), joint stacks, hub/post/handle heights (mm)."""

    order: tuple[str, ...]
    thickness_mm: float
    z_mm: dict[str, float]
    joints: dict[str, JointStack]
    hub_z_mm: tuple[float, float]
    hub_screw_length_mm: float
    shaft_top_mm: float
    flange_z_mm: float
    post_top_mm: float
    handle_z_mm: float
    handle_screw_length_mm: float
    top_mm: float
    elements: tuple[Element, ...]
    min_planar_clearance_mm: float
    conflicts: tuple[str, ...]
    gaps_mm: tuple[float, float] = (0.0, 0.0)
    same_body_conflicts: tuple[str, ...] = ()
    pairs: tuple = ()
    candidates: tuple[dict, ...] = ()
    hub_set_screw: HubSetScrew | None = None  # set by choose_layers (hub_set_screw)


# --------------------------------------------------------------------------- geometry
def _seg_point_dist(a, b, p):
    """Distance from points p to segments ab; arrays (..., 2)."""
    ab = b - a
    L2 = np.einsum("...i,...i->...", ab, ab)
    t = np.where(L2 > 0, np.einsum("...i,...i->...", p - a, ab) / np.where(L2 > 0, L2, 1.0), 0.0)
    t = np.clip(t, 0.0, 1.0)
    q = a + t[..., None] * ab
    return np.linalg.norm(p - q, axis=-1)


def _cross2(u, v):
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def _seg_seg_dist(a, b, c, d):
    """Distance between segments ab and cd (arrays (..., 2)); 0 where they cross."""
    dist = np.minimum.reduce(
        [
            _seg_point_dist(a, b, c),
            _seg_point_dist(a, b, d),
            _seg_point_dist(c, d, a),
            _seg_point_dist(c, d, b),
        ]
    )
    d1 = _cross2(b - a, c - a)
    d2 = _cross2(b - a, d - a)
    d3 = _cross2(d - c, a - c)
    d4 = _cross2(d - c, b - c)
    crossing = (d1 * d2 < 0) & (d3 * d4 < 0)
    return np.where(crossing, 0.0, dist)


def _edges(pts):
    k = pts.shape[-2]
    if k == 1:
        return [(pts[..., 0, :], pts[..., 0, :])]
    if k == 2:
        return [(pts[..., 0, :], pts[..., 1, :])]
    return [(pts[..., i, :], pts[..., (i + 1) % k, :]) for i in range(k)]


def _inside_triangle(tri, p):
    """Is p (…,2) inside triangle tri (…,3,2) (either orientation)?"""
    s = [_cross2(tri[..., (i + 1) % 3, :] - tri[..., i, :], p - tri[..., i, :]) for i in range(3)]
    return ((s[0] >= 0) & (s[1] >= 0) & (s[2] >= 0)) | ((s[0] <= 0) & (s[1] <= 0) & (s[2] <= 0))


def hull_distance(pa: np.ndarray, pb: np.ndarray) -> np.ndarray:
    """Distance between the convex hulls of point sets pa (N,ka,2) and pb (N,kb,2), k<=3; 0 if they overlap."""
    d = np.full(pa.shape[0], np.inf)
    for a, b in _edges(pa):
        for c, e in _edges(pb):
            d = np.minimum(d, _seg_seg_dist(a, b, c, e))
    if pa.shape[1] == 3:
        for j in range(pb.shape[1]):
            d = np.where(_inside_triangle(pa, pb[:, j, :]), 0.0, d)
    if pb.shape[1] == 3:
        for j in range(pa.shape[1]):
            d = np.where(_inside_triangle(pb, pa[:, j, :]), 0.0, d)
    return d


def world_points(el: Element, tf_world_body: dict[str, np.ndarray]) -> np.ndarray:
    """(N,k,2) points of an element at every pose (``tf_world_body[body]``: (N,3,3))."""
    T = tf_world_body[el.body]
    p = np.asarray(el.points_mm, dtype=float)
    return np.einsum("nij,kj->nki", T[:, :2, :2], p) + T[:, None, :2, 2]


def planar_clearances(elements, tf_world_body) -> list[tuple[float, Element, Element]]:
    """(min planar clearance over the poses, element a, element b) for every pair of elements
    whose z intervals overlap (or, for two bodies, lie less than the larger ``z_margin_mm``
    apart): elements of different bodies over the poses, elements of one
    body once (they keep their distance; they only must not overlap, see
    :func:`required_clearance_mm`)."""
    out = []
    digest = {k: hashlib.sha256(np.ascontiguousarray(T, dtype=float).tobytes()).hexdigest()
              for k, T in tf_world_body.items()}
    wp: dict[int, np.ndarray] = {}
    for i, j in itertools.combinations(range(len(elements)), 2):
        a, b = elements[i], elements[j]
        margin = max(a.z_margin_mm, b.z_margin_mm) if a.body != b.body else 0.0
        if min(a.z_mm[1], b.z_mm[1]) - max(a.z_mm[0], b.z_mm[0]) <= -margin + LAYER_SLACK_MM:
            continue
        key = (digest[a.body], np.asarray(a.points_mm, dtype=float).tobytes(),
               digest[b.body], np.asarray(b.points_mm, dtype=float).tobytes())
        h = _HULL_MEMO.get(key)
        if h is None:
            for k in (i, j):
                if k not in wp:
                    wp[k] = world_points(elements[k], tf_world_body)
            h = float(hull_distance(wp[i], wp[j]).min())
            if len(_HULL_MEMO) > 4096:
                _HULL_MEMO.clear()
            _HULL_MEMO[key] = h
        out.append((h - a.radius_mm - b.radius_mm, a, b))
    return out


def required_clearance_mm(a: Element, b: Element, parts: PartsSpec) -> float:
    """Planar clearance two z-overlapping elements need: ``clearance_min_mm`` between bodies
    that move relative to each other, 0 (touching allowed) within one body."""
    return 0.0 if a.body == b.body else parts.clearance_min_mm


#: min over the poses of the planar hull distance of two outlines, by (motion, outline):
#: it does not depend on the layer heights, so the layer orders tried by
#: :func:`choose_layers` and a re-evaluation with another bar thickness reuse it.
_HULL_MEMO: dict[tuple, float] = {}


# --------------------------------------------------------------------------- stack
def joint_stack(
    joint: str, upper: str, lower: str, z_upper: float, z_lower_top: float, parts: PartsSpec
) -> JointStack:
    """Heights of the hardware at one joint (module docstring)."""
    t = parts.bar_thickness_mm
    brg = catalog.get_bearing(parts.bearing)
    pin = catalog.get_shoulder_screw(parts.pin)
    on_post = lower == "ground"
    spacer = z_upper - z_lower_top
    shim = (t - brg.B_mm) + parts.pin_head_clearance_mm
    clamp = shim + brg.B_mm + spacer
    lo, hi = pin_window(parts, t, on_post)
    L = catalog.shortest_length(pin.lengths_mm, clamp + lo)
    if L is None:
        raise DesignError(
            "parts.layer_gap_mm",
            f"the {parts.pin} shoulder screws stop at {pin.lengths_mm[-1]:g} mm; the stack "
            f"at {joint} needs {clamp + lo:g} mm",
        )
    if L - clamp > hi:
        shim += (L - clamp) - hi
        clamp = shim + brg.B_mm + spacer
    head_face = z_upper + t + (shim - (t - brg.B_mm))
    return JointStack(
        joint=joint,
        upper=upper,
        lower=lower,
        z_upper_mm=z_upper,
        z_lower_top_mm=z_lower_top,
        spacer_mm=spacer,
        shim_mm=shim,
        pin_length_mm=L,
        clamp_mm=clamp,
        nut=not on_post,
        head_face_mm=head_face,
        head_top_mm=head_face + pin.k_mm,
        thread_end_mm=head_face - L - pin.b_mm,
    )


def hub_screw_length(parts: PartsSpec) -> tuple[float, float]:
    """(length, engagement) of the hub screws: through the crank into the hub's tapped holes
    (1.5 d minimum in aluminium, :mod:`cad.assembly.fasteners`); the hub is made tall
    enough for the hole (:func:`plan_for_order`). Engagement: at the thinnest crank sheet in a
    laser build (:func:`cad.families.fourbar.sheet_tolerance.thinnest_mm`), the nominal otherwise."""

    hole = alu_hole("crank_hub:screw", "crank_hub", parts.hub_screw, math.inf)
    bands = sheet_bands(parts)  # a laser-cut crank: long enough at its thickest, the hole
    t = parts.bar_thickness_mm  # deep enough at its thinnest (cad.families.fourbar.sheet_tolerance)
    L, _ = size_over_band(parts.hub_screw, t, hole, "A1 (crank to hub)", "parts.hub_screw",
                          ["crank"], bands, clamp_field="parts.bar_thickness_mm")
    return L, L - thinnest_mm(bands, "crank", t)


@dataclass(frozen=True)
class HubSetScrew:
    """The ISO 4026 set screw locking the crank hub on the motor shaft (mm): thread ``size``,
    catalog ``length_mm`` (= its engagement: the flat point on the shaft), ``depth_mm`` of full
    thread of its radial hole (shaft surface to where the round hub leaves the thread's major
    diameter), ``min_engagement_mm`` (1.5 d in aluminium) and ``shaft_radius_mm``."""

    size: str
    length_mm: float
    depth_mm: float
    min_engagement_mm: float
    shaft_radius_mm: float


def hub_set_screw(parts: PartsSpec) -> HubSetScrew:
    """Size the hub's set screw before any CAD (:func:`cad.assembly.fasteners.size_set_screw`):
    tapped radially through the hub (radius ``hub_diameter_mm / 2``) onto the shaft (radius r),
    full thread ending sqrt(R^2 - (d/2)^2) from the axis, the largest of
    :data:`HUB_SET_SCREW_SIZES` with a bd_warehouse ISO 4026 length 1.5 d <= L <= that depth
    (its end never proud of the hub), L the longest. DesignError naming
    ``parts.hub_diameter_mm`` when no size fits."""
    r_in = catalog.get_motor(parts.motor).shaft_diameter_mm / 2
    size, L, depth = size_set_screw(r_in, parts.hub_diameter_mm / 2, HUB_SET_SCREW_SIZES,
                                    "crank hub set screw onto the motor shaft",
                                    "parts.hub_diameter_mm")
    d = catalog.thread_diameter_mm(size)
    if parts.hub_shaft_engagement_min_mm < d + 1.0 - LAYER_SLACK_MM:  # axis at half the engagement
        raise DesignError(
            "parts.hub_shaft_engagement_min_mm",
            f"{parts.hub_shaft_engagement_min_mm:g} mm: the hub's {size.split('-')[0]} set screw "
            f"sits at half the shaft engagement, so its hole needs >= {d + 1.0:g} mm to stay "
            "0.5 mm above the hub's bottom face",
        )
    return HubSetScrew(size, L, depth, MIN_ENGAGEMENT_ALU_D * catalog.thread_diameter_mm(size),
                       r_in)


#: Fields that set how far the motor shaft reaches into the crank hub, in blame order.
_SHAFT_FIELDS = ("hub_shaft_engagement_min_mm", "base_clearance_mm", "base_thickness_mm",
                 "motor_mount_thickness_mm")


def _shaft_blame(parts: PartsSpec, shaft_length_mm: float) -> str:
    """The field to name when the shaft reaches too little into the hub: the first of
    :data:`_SHAFT_FIELDS` the design changed from its default whose default value alone would
    give the required reach (shaft length - base - mount - base clearance >= the minimum);
    ``base_thickness_mm`` when no single field does."""
    import dataclasses

    def ok(p: PartsSpec) -> bool:
        reach = shaft_length_mm - p.base_thickness_mm - p.motor_mount_thickness_mm
        return reach - p.base_clearance_mm >= p.hub_shaft_engagement_min_mm - LAYER_SLACK_MM

    for f in _SHAFT_FIELDS:
        default = getattr(PartsSpec, f)
        if getattr(parts, f) != default and ok(dataclasses.replace(parts, **{f: default})):
            return f
    return "base_thickness_mm"


def post_min_height_mm(stack: JointStack, parts: PartsSpec) -> float:
    """Shortest A4 post that holds both of its screws apart (mm): the reamed bore for the
    shoulder entry and thread relief (:func:`post_bore_depth_mm`), the tapped hole for the
    ISO 7379 thread (b plus :data:`POST_THREAD_EXTRA_MM`), :data:`POST_WEB_MM` of solid, then
    the bottom tapped hole for the post screw."""
    pin = catalog.get_shoulder_screw(parts.pin)
    bore = post_bore_depth_mm(stack, parts)
    return bore + pin.b_mm + POST_THREAD_EXTRA_MM + POST_WEB_MM + STANDOFF_TAP_DEPTH_MM


def post_bore_depth_mm(stack: JointStack, parts: PartsSpec) -> float:
    """Depth of the A4 post's reamed top bore (mm): the shoulder's entry L - c plus the
    thread relief g2 (0 for a plain pin), so the tapped hole below starts at the screw's
    first full thread."""
    pin = catalog.get_shoulder_screw(parts.pin)
    return stack.pin_length_mm - stack.clamp_mm + pin.g2_mm


def _handle_screw_length(parts: PartsSpec) -> float:
    cs = catalog.get_cap_screw(parts.handle_screw, "parts.handle_screw")
    L = catalog.shortest_length(cs.lengths_mm, parts.bar_thickness_mm + HANDLE_SCREW_FLOOR_MM)
    if L is None or L - parts.bar_thickness_mm > parts.handle_height_mm - 2.0:
        raise DesignError(
            "parts.handle_height_mm",
            f"a {parts.handle_height_mm:g} mm knob cannot take the {parts.handle_screw} screw",
        )
    return L


def plan_for_order(
    order,
    joints_link: dict[str, dict[str, np.ndarray]],
    parts: PartsSpec,
    tf_world_body: dict[str, np.ndarray],
    gaps_mm: tuple[float, float] | None = None,
    made_axle: bool = False,
) -> LayerPlan:
    """Stack heights and planar conflicts of one layer order (bottom to top).

    ``gaps_mm``: gap between layers 0-1 and 1-2 (default ``layer_gap_mm`` both). ``made_axle``:
    the crank turns on a made axle at A1 (a capstan on the crank moves the motor away,
    :func:`cad.families.fourbar.capstan_solids.a1_support`), cut to reach at least the hub's
    top: the motor's shaft length no longer limits the hub's engagement.
    """
    t = parts.bar_thickness_mm
    g = parts.layer_gap_mm
    gaps = tuple(gaps_mm) if gaps_mm is not None else (g, g)
    level = {name: i for i, name in enumerate(order)}
    offs = (0.0, t + gaps[0], 2 * t + gaps[0] + gaps[1])
    motor = catalog.get_motor(parts.motor)
    els = _Elements(parts, motor)  # the catalog hardware looked up first, as ever
    hub_L, hub_engaged = hub_screw_length(parts)
    handle_L = _handle_screw_length(parts)
    z0 = _lowest_layer_z(order, level, offs, parts, hub_engaged)
    js = _stacks_at(order, level, offs, z0, parts)
    z = {n: z0 + offs[level[n]] for n in order}

    flange_z = -(parts.base_thickness_mm + parts.motor_mount_thickness_mm)
    shaft_top = flange_z + motor.shaft_length_mm
    hub_lo = parts.base_clearance_mm
    hub_hi = z["crank"]
    if made_axle:
        shaft_top = max(shaft_top, hub_hi)
    _check_shaft_engagement(parts, motor, min(shaft_top, hub_hi) - hub_lo)

    els.links_and_joints(joints_link, level, z, js)
    els.crank_and_handle(joints_link, level, z, (hub_lo, hub_hi), shaft_top)
    pairs = planar_clearances(els.out, tf_world_body)
    conflicts, same, min_cl = _plan_conflicts(pairs, parts)
    return LayerPlan(
        order=tuple(order),
        thickness_mm=t,
        z_mm=z,
        joints=js,
        hub_z_mm=(hub_lo, hub_hi),
        hub_screw_length_mm=hub_L,
        shaft_top_mm=shaft_top,
        flange_z_mm=flange_z,
        post_top_mm=js["A4"].z_lower_top_mm,
        handle_z_mm=z["coupler"] + t,
        handle_screw_length_mm=handle_L,
        top_mm=max(e.z_mm[1] for e in els.out),
        elements=tuple(els.out),
        min_planar_clearance_mm=float(min_cl),
        conflicts=conflicts,
        same_body_conflicts=same,
        gaps_mm=gaps,
        pairs=tuple(pairs),
    )


def _stacks_at(order, level: dict[str, int], offs: tuple[float, float, float], z0: float,
               parts: PartsSpec) -> dict[str, JointStack]:
    """Joint stacks of every joint with the lowest layer's bottom face at ``z0`` (mm)."""
    t, g = parts.bar_thickness_mm, parts.layer_gap_mm
    z = {n: z0 + offs[level[n]] for n in order}
    out = {}
    for j, (a, b) in JOINTS.items():
        if b == "ground":
            out[j] = joint_stack(j, a, b, z[a], z[a] - g, parts)
            continue
        up, low = (a, b) if level[a] > level[b] else (b, a)
        out[j] = joint_stack(j, up, low, z[up], z[low] + t, parts)
    return out


def _lowest_layer_z(order, level: dict[str, int], offs: tuple[float, float, float],
                    parts: PartsSpec, hub_engaged: float) -> float:
    """Bottom face of the lowest layer (mm above the base plate): it clears the base plate
    and the nuts hanging under it, and leaves room in the hub for the hub screws' tapped
    holes and in the A4 post for both its screws."""
    # lowest layer: clear the base plate, the nuts hanging under it and the hub screws
    base_clear = parts.base_clearance_mm
    probe = _stacks_at(order, level, offs, 100.0, parts)
    lowest = order[0]
    hang = 0.0
    for s in probe.values():
        if s.lower == lowest and s.nut:
            hang = max(hang, 100.0 - s.thread_end_mm)
    z0 = base_clear + hang
    # the hub (base_clear .. crank bottom) holds the hub screws' tapped holes, the post
    # (0 .. A4 stack) both its screws: raise the whole stack where they would not fit
    z0 = max(z0, base_clear + hub_engaged + TAP_LEADOUT_MM + HUB_FLOOR_MM - offs[level["crank"]])
    post_need = post_min_height_mm(probe["A4"], parts) - (probe["A4"].z_lower_top_mm - 100.0)
    return max(z0, post_need)


def _check_shaft_engagement(parts: PartsSpec, motor, engaged: float) -> None:
    """DesignError naming the field to change when the motor shaft reaches less than
    ``hub_shaft_engagement_min_mm`` into the crank hub (``engaged``, mm)."""
    if engaged < parts.hub_shaft_engagement_min_mm - LAYER_SLACK_MM:
        f = _shaft_blame(parts, motor.shaft_length_mm)
        raise DesignError(
            f"parts.{f}",
            f"{getattr(parts, f):g} mm: the {motor.shaft_length_mm:g} mm {parts.motor} shaft "
            f"reaches only {engaged:.2f} mm into the crank hub (need "
            f"parts.hub_shaft_engagement_min_mm = {parts.hub_shaft_engagement_min_mm:g}; the hub "
            "starts parts.base_clearance_mm above the base plate, the shaft rises from under "
            "the base and motor mount plates)",
        )


class _Elements:
    """The planar elements of a layer plan (``out``), added part group by part group."""

    def __init__(self, parts: PartsSpec, motor) -> None:
        self.parts, self.motor = parts, motor
        self.pin = catalog.get_shoulder_screw(parts.pin)
        self.nut = catalog.get_nut(parts.pin)
        self.washer = catalog.get_washer(parts.pin)
        self.hub_cs = catalog.get_cap_screw(parts.hub_screw, "parts.hub_screw")
        self.out: list[Element] = []

    def add(self, label, body, pts, r, zlo, zhi, anchor) -> None:
        """One element; hardware standing proud of its layer gets the z margin clearance_min_mm."""
        proud = any(w in label for w in ("screw head", "washer+nut", "handle"))
        self.out.append(
            Element(
                label,
                body,
                np.atleast_2d(np.asarray(pts, dtype=float)),
                float(r),
                (float(zlo), float(zhi)),
                anchor,
                self.parts.clearance_min_mm if proud else 0.0,
            )
        )

    def links_and_joints(self, J, level: dict[str, int], z: dict[str, float],
                         js: dict[str, JointStack]) -> None:
        """The bars, and at each joint the screw head, gap spacer and washer + nut or post."""
        parts, add = self.parts, self.add
        t = parts.bar_thickness_mm
        pin, nut, washer = self.pin, self.nut, self.washer
        for link in LINK_NAMES:
            pts = np.array(list(J[link].values()))
            add(f"{link} bar", link, pts, parts.bar_end_radius_mm, z[link], z[link] + t, level[link])
        r_nut = max(washer.d2_mm, nut.s_mm * 2.0 / np.sqrt(3.0)) / 2.0
        spacer_r = spacer_od_mm(parts) / 2.0
        for j, s in js.items():
            carrier = s.lower  # the pin, spacers and nut move with the lower link (or ground)
            p_c = J[carrier][j]
            add(f"{j} screw head", carrier, p_c, pin.dk_mm / 2.0, s.head_face_mm, s.head_top_mm,
                level[s.upper])
            add(f"{j} gap spacer", carrier, p_c, spacer_r, s.z_lower_top_mm, s.z_upper_mm, None)
            if s.nut:
                add(f"{j} washer+nut", carrier, p_c, r_nut, s.thread_end_mm, s.z_lower_top_mm - t,
                    level[s.lower])
            else:
                add(f"{j} post", "ground", J["ground"][j], parts.post_diameter_mm / 2.0, 0.0,
                    s.z_lower_top_mm, None)

    def crank_and_handle(self, J, level: dict[str, int], z: dict[str, float],
                         hub_z: tuple[float, float], shaft_top: float) -> None:
        """The crank hub and its screw heads, the motor shaft end above the crank, the handle."""
        parts, add = self.parts, self.add
        t = parts.bar_thickness_mm
        motor, hub_cs = self.motor, self.hub_cs
        add("hub", "crank", J["crank"]["A1"], parts.hub_diameter_mm / 2.0, hub_z[0], hub_z[1], None)
        r_bc = hub_bolt_circle_mm(parts) / 2.0
        a1 = np.asarray(J["crank"]["A1"], dtype=float)
        for k, (hx, hy) in enumerate(catalog.polar_points_mm(r_bc, HUB_SCREWS)):
            add(f"hub screw head {k + 1}", "crank", a1 + (hx, hy), hub_cs.dk_mm / 2.0,
                z["crank"] + t, z["crank"] + t + hub_cs.k_mm, level["crank"])
        if shaft_top > z["crank"] + t:
            add("motor shaft end", "crank", J["crank"]["A1"], motor.shaft_diameter_mm / 2.0,
                z["crank"] + t, shaft_top, None)
        zc = z["coupler"]
        add("handle", "coupler", J["coupler"]["P"], parts.handle_diameter_mm / 2.0, zc + t,
            zc + t + parts.handle_height_mm, level["coupler"])


def _plan_conflicts(pairs, parts: PartsSpec) -> tuple[tuple[str, ...], tuple[str, ...], float]:
    """(pairs closer than their required clearance, same-body pairs that overlap, least
    clearance between different bodies (mm; inf when none)), closest first."""
    conflicts = tuple(
        f"{a.label} / {b.label}: {d:.2f} mm"
        for d, a, b in sorted(pairs, key=lambda x: x[0])
        if d < required_clearance_mm(a, b, parts) - LAYER_SLACK_MM
    )
    same = tuple(
        f"{a.label} / {b.label}: {d:.2f} mm"
        for d, a, b in sorted(pairs, key=lambda x: x[0])
        if a.body == b.body and d < -LAYER_SLACK_MM
    )
    min_cl = min((d for d, a, b in pairs if a.body != b.body), default=np.inf)
    return conflicts, same, min_cl


#: Most times the layer gaps are widened for one order before it is given up.
MAX_GAP_ROUNDS = 6


def _widen(plan: LayerPlan, parts: PartsSpec) -> tuple[float, float] | None:
    """Gaps that separate in z (by ``layer_gap_mm``) every conflicting pair anchored to
    different layers, or None
    when a conflict involves an element spanning layers (only another order can help)."""
    gaps = list(plan.gaps_mm)
    changed = False
    for d, a, b in plan.pairs:
        if d >= required_clearance_mm(a, b, parts) - LAYER_SLACK_MM:
            continue
        if a.anchor is None or b.anchor is None or a.anchor == b.anchor:
            return None
        lo_el, hi_el = (a, b) if a.anchor < b.anchor else (b, a)
        need = lo_el.z_mm[1] - hi_el.z_mm[0] + max(parts.layer_gap_mm, parts.clearance_min_mm)
        if need > 0:
            k = hi_el.anchor - 1
            gaps[k] += need
            changed = True
    return tuple(gaps) if changed else None


def plan_order(order, joints_link, parts: PartsSpec, tf_world_body, made_axle: bool = False) -> LayerPlan:
    """:func:`plan_for_order`, widening the layer gaps where hardware hanging from one layer
    meets the bars of another (up to :data:`MAX_GAP_ROUNDS` times)."""
    plan = plan_for_order(order, joints_link, parts, tf_world_body, made_axle=made_axle)
    for _ in range(MAX_GAP_ROUNDS):
        if not plan.conflicts:
            break
        gaps = _widen(plan, parts)
        if gaps is None:
            break
        plan = plan_for_order(order, joints_link, parts, tf_world_body, gaps, made_axle)
    return plan


def spacer_od_mm(parts: PartsSpec) -> float:
    """Outside diameter of the turned spacers: between the bearing's shaft abutment
    diameter da and its inner-ring shoulder d1 (touches the inner ring only)."""
    brg = catalog.get_bearing(parts.bearing)
    return round(0.5 * (brg.da_mm + brg.d1_mm), 1)


def hub_bolt_circle_mm(parts: PartsSpec) -> float:
    """Diameter of the circle of hub screws: half-way between shaft and hub rim."""
    motor = catalog.get_motor(parts.motor)
    return 0.5 * (motor.shaft_diameter_mm + parts.hub_diameter_mm)


def made_crank_axle(design) -> bool:
    """True when the crank turns on a made axle at A1 (a capstan on the crank: the motor moves
    away, :func:`cad.families.fourbar.capstan_solids.a1_support`), so the hub's engagement is
    the axle's, not the motor shaft's (:func:`plan_for_order`)."""
    return resolve_device(design).transmission("crank").is_capstan


def choose_layers(joints_link, parts: PartsSpec, tf_world_body, strict: bool = False,
                  made_axle: bool = False) -> LayerPlan:
    """The layer plan: ``parts.layer_order`` if given, else the conflict-free order with the
    lowest top (ties: :data:`ORDERS` order); gaps widened where needed (:func:`plan_order`).
    When every order conflicts, the one with the largest planar clearance between links
    (and no overlap within a link) is returned with its ``conflicts`` listed (the 3-D check
    decides) -- unless ``strict`` (the build): then :class:`NoLayout` (a DesignError naming
    the joint, both parts and the overlap, :func:`no_layout_error`) before any CAD import.
    DesignError when every order has parts of one link overlapping (a nut under
    the crank in the hub, say): no layout exists. The hub's set screw is sized first
    (:func:`hub_set_screw`, carried as ``hub_set_screw``; DesignError when none fits).
    ``made_axle``: as :func:`plan_for_order`."""
    set_screw = hub_set_screw(parts)  # a hub wall no set screw fits: refused first
    orders = [parts.layer_order] if parts.layer_order else list(ORDERS)
    plans = [plan_order(o, joints_link, parts, tf_world_body, made_axle) for o in orders]
    if strict and not any(not p.conflicts for p in plans):
        others = []
        if parts.layer_order:
            others = [plan_order(o, joints_link, parts, tf_world_body, made_axle) for o in ORDERS]
        raise no_layout_error(plans, parts, [p for p in others if not p.conflicts])
    cands = tuple(
        {
            "order": list(p.order),
            "conflicts": len(p.conflicts),
            "top_mm": p.top_mm,
            "gaps_mm": list(p.gaps_mm),
            "min_planar_clearance_mm": p.min_planar_clearance_mm,
        }
        for p in plans
    )
    ok = [p for p in plans if not p.conflicts]
    if all(p.same_body_conflicts for p in plans):
        worst = plans[0]
        if parts.layer_order:
            raise DesignError(
                "parts.layer_order",
                f"the order {', '.join(worst.order)} does not keep the hardware of one link apart "
                f"({worst.same_body_conflicts[0]}); try another order or leave it automatic",
            )
        raise DesignError(
            "mechanism",
            "no layer order keeps the hardware of one link apart (same-link parts overlap in "
            f"every order; order {', '.join(worst.order)}: {worst.same_body_conflicts[0]}); "
            "lengthen the short link or shrink parts.hub_diameter_mm / the hardware",
        )
    best = (
        min(ok, key=lambda p: p.top_mm)
        if ok
        else max(
            (p for p in plans if not p.same_body_conflicts),
            key=lambda p: p.min_planar_clearance_mm,
        )
    )
    return LayerPlan(**{**best.__dict__, "candidates": cands, "hub_set_screw": set_screw})


class NoLayout(DesignError):
    """No layer order keeps the joint hardware apart (raised before any CAD import)."""


def _joint_of(label: str) -> str | None:
    """Joint an element belongs to: ``A2 washer+nut`` -> A2, the hub and its screws -> A1,
    the handle -> P, a bar -> None."""
    head = label.split()[0]
    if head in JOINTS:
        return head
    if head in ("hub", "motor"):
        return "A1"
    return "P" if head == "handle" else None


def worst_conflict(plan: LayerPlan, parts: PartsSpec) -> tuple[float, Element, Element] | None:
    """(shortfall mm = clearance - required, a, b) of the plan's worst pair, or None."""
    out = None
    for d, a, b in plan.pairs:
        short = d - required_clearance_mm(a, b, parts)
        if out is None or short < out[0]:
            out = (short, a, b)
    return out


def no_layout_error(plans, parts: PartsSpec, clear=()) -> NoLayout:
    """The refusal when no tried order is clear: the order whose worst pair is least bad,
    naming the joint, both parts (and their bodies), the planar overlap and the clearance
    needed; ``clear``: conflict-free plans of other orders (when ``parts.layer_order`` was
    forced)."""
    best = max(plans, key=lambda p: worst_conflict(p, parts)[0])
    short, a, b = worst_conflict(best, parts)
    d = short + required_clearance_mm(a, b, parts)
    joint = _joint_of(a.label) or _joint_of(b.label) or "layers"
    what = f"overlap by {-d:.2f} mm" if d < 0 else f"are {d:.2f} mm apart"
    need = required_clearance_mm(a, b, parts)
    text = (
        f"{joint}: the {a.label} ({a.body}) and the {b.label} ({b.body}) {what} in plan "
        f"(need {need:g} mm) in the best layer order {', '.join(best.order)}"
    )
    if clear:
        return NoLayout(
            "parts.layer_order",
            text + f"; order {', '.join(min(clear, key=lambda p: p.top_mm).order)} is clear "
            "(remove parts.layer_order to let the planner choose)",
        )
    return NoLayout("mechanism", text + "; no layer order is clear")


#: Stroke scan of :func:`clearing_stroke_mm`: coarse factor per step, up to this factor.
STROKE_SCAN_STEP = 1.05
STROKE_SCAN_MAX = 3.0


def clearing_stroke_mm(family: str, stroke_mm: float, parts: PartsSpec, n_poses: int) -> float | None:
    """Smallest stroke (0.1 mm, scanning up from ``stroke_mm`` to :data:`STROKE_SCAN_MAX` x)
    at which the family scaled to it has a conflict-free layer order, or None. Longer links
    move the joint hardware away from the hub (the hardware does not scale)."""
    def clear(s: float) -> bool:
        fb, lo, hi = family_linkage(family, s)
        tf = planar_transforms(fb, np.linspace(lo, hi, n_poses))
        try:
            choose_layers(link_joints_mm(fb), parts, tf, strict=True)
        except DesignError:
            return False
        return True

    lo, hi = stroke_mm, None
    s = stroke_mm
    while s < STROKE_SCAN_MAX * stroke_mm:
        s *= STROKE_SCAN_STEP
        if clear(s):
            hi = s
            break
        lo = s
    if hi is None:
        return None
    while hi - lo > 0.1:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if clear(mid) else (mid, hi)
    return math.ceil(hi * 10.0) / 10.0 if clear(math.ceil(hi * 10.0) / 10.0) else hi


def footprint_bbox_mm(plan: LayerPlan, tf_world_body) -> tuple[float, float, float, float]:
    """(xmin, ymin, xmax, ymax) of everything above the base plate over the sampled poses."""
    lo = np.array([np.inf, np.inf])
    hi = -lo
    for e in plan.elements:
        w = world_points(e, tf_world_body).reshape(-1, 2)
        lo = np.minimum(lo, w.min(axis=0) - e.radius_mm)
        hi = np.maximum(hi, w.max(axis=0) + e.radius_mm)
    return float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1])
