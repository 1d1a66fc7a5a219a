"""Where the capstans of a twin-pantograph haptic mouse could sit (issue 35 §1), and what stops
them: the 5-bar's direction search (:func:`cad.families.pantograph.capstan.search_directions`)
applied to each of the twin's two 5-bars, the reach of a motor shaft into a stack of drum bands,
and the bridge posts against the swept drums. Pure numpy (no CAD import); the solids are not
built (:func:`cad.families.pantograph.twin_capstan.refuse_solids`).

Frames and units as :mod:`cad.families.pantograph.capstan` (mm, deg, world = the kinematic base
frame, z = 0 on the base plate's top). The knob pantograph hangs under the bridge, its motors on
the bridge, shafts down; the crank pantograph stands on the base plate, its motors under it,
shafts up: a drum band ``k`` (1 next to the plate its motor hangs on) has its rope's plane
:func:`band_rope_offset_mm` from that plate's face, the same measure up from the base plate or
down from the bridge.
"""

from __future__ import annotations

import numpy as np

from cad.actuators import capstan_geometry as cg
from cad.data.catalog import get_motor
from cad.device import resolve_device
from cad.families.pantograph import capstan as pcap
from cad.families.pantograph import twin_capstan as tc
from cad.families.pantograph.layout import layout
from cad.kinematics import twin_pantograph as ktwin
from cad.parts.motor import mount_side_mm
from cad.tolerances import CAPSTAN_RANGE_MARGIN_DEG

#: Each 5-bar of the twin: its columns in :data:`cad.families.pantograph.twin_capstan.JOINTS`.
GROUPS = {"knob": (0, 1), "crank": (2, 3)}


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
    """For each bridge post of the twin's layout (``posts_xy_mm``, :func:`cad.families.pantograph.layout.layout`):
    True when a drum of ``sides`` (the ``group``'s, :func:`group_directions`) sweeps over any
    point of the post's circle (its diameter plus the clearance) at a workspace sample, its arc
    widened by :data:`cad.tolerances.CAPSTAN_RANGE_MARGIN_DEG` at both ends."""
    return [post_in_swept_drums(design, xy, {group: sides}) for xy in layout(design)["posts_xy_mm"]]


def post_in_swept_drums(design, xy_mm, sides_by_group: dict) -> bool:
    """True when a drum of ``sides_by_group`` (group -> its two :class:`CapstanSide`, in any
    band) sweeps over the circle of a bridge post at ``xy_mm`` (its diameter plus
    :data:`cad.families.pantograph.capstan.CLEARANCE_MM`) at a workspace sample, each drum's arc
    widened by :data:`cad.tolerances.CAPSTAN_RANGE_MARGIN_DEG` at both ends."""
    q_all = np.degrees(np.unwrap(ktwin.ik(design.mechanism, design.workspace_points()).q_rad, axis=0))
    dev = resolve_device(design)
    r_post = design.parts.post_diameter_mm / 2 + pcap.CLEARANCE_MM
    ring = np.linspace(0.0, 2 * np.pi, 73)[:-1]
    pts = np.vstack([np.asarray(xy_mm, float) + r_post * np.column_stack([np.cos(ring), np.sin(ring)]), xy_mm])
    for group, sides in sides_by_group.items():
        for col, s in zip(GROUPS[group], sides, strict=True):
            d = pts - np.asarray(s.b_mm, float)
            inside = np.hypot(d[:, 0], d[:, 1]) <= pcap.swept_radius_mm(dev.transmission(tc.JOINTS[col]))
            ang = np.degrees(np.arctan2(d[:, 1], d[:, 0]))
            start = s.arc_start_deg + q_all[:, col] - CAPSTAN_RANGE_MARGIN_DEG
            on_arc = ((ang[None, :] - start[:, None]) % 360.0) <= s.arc_span_deg + 2 * CAPSTAN_RANGE_MARGIN_DEG
            if np.any(inside[None, :] & on_arc):
                return True
    return False


def clear_post_y_mm(design, x_mm: float, sides_by_group: dict, step_mm: float = 0.05) -> float:
    """The first y (mm, world), stepping back by ``step_mm`` from the layout's post line
    (``posts_xy_mm``), where a bridge post at ``x_mm`` stands clear of every drum of
    ``sides_by_group`` (:func:`post_in_swept_drums`); drums only: the rope runs, capstans and
    the bridge's own extent are not in it."""
    y = layout(design)["posts_xy_mm"][0][1]
    while post_in_swept_drums(design, (x_mm, y), sides_by_group):
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
