"""Cheap mass model of a four-bar's moving parts (numpy + catalog data, no CAD import).

Per link, in the link frame (mm in, SI out):

* bar: plate area (closed-form hull of the joint discs, :func:`cad.parts.bars.outline_area_mm2`,
  minus the pocket slots of :func:`cad.parts.bars.pocket_segments` and the joint holes)
  x thickness x density; COM at the joints' centroid; Izz = m (L^2 + w^2) / 12 about
  it (L the outline length along the hull);
* joint hardware as point masses at the joint, on the link that carries it in the
  layer plan (:func:`cad.families.fourbar.layers.choose_layers`, numpy only, for the design's
  ``layer_order`` or the planner's choice): the bearing on the UPPER link, the pin
  (cylinder d x its catalog length, or ISO 7379 head + shoulder + thread), the gap and
  head spacers, nut or ring and washer on the LOWER link (the ground at A4), each of
  the plan's height at that joint (:class:`cad.families.fourbar.layers.JointStack`); the bars
  have the bearing seat where they are the upper link and the pin hole elsewhere. A
  point mass at a joint has the same velocity whichever link carries it, so the layer
  order moves mass between H22, H12 and H33 but changes D (and M11) only through the
  stack heights (a joint spanning two layers has a longer spacer and pin), the crank
  hub's height and the seats. Without a plan (no layout exists) each joint's hardware
  is split half and half between its links, with a one-gap stack;
* crank hub (disc at A1, from the base clearance up to the crank, 10 mm without a
  plan), knob (cylinder at P) and its screw, hub screws;
* the rotor inertia Jm of the motor catalog.

Then H11..H33 (eqs 16-19, :func:`cad.dynamics.inertia.h_from_links`) and M11 over the
stroke (eq 22). The model's error against the exact solids is measured at every reported
optimum (:mod:`cad.studies.codesign.exact`).
"""

from __future__ import annotations

import math

import numpy as np

from cad.actuators import capstan as cap
from cad.actuators import capstan_geometry as cg
from cad.data import catalog as cat
from cad.data.materials import get_material
from cad.device import resolve_device
from cad.dynamics.inertia import (
    PlanarLinkInertia,
    apparent_mass_matrix,
    apparent_mass_summary,
    h_from_links,
)
from cad.errors import HapticadError
from cad.families.fourbar import capstan as fcap
from cad.families.fourbar.layers import choose_layers, made_crank_axle, spacer_od_mm
from cad.families.fourbar.pose import planar_transforms
from cad.kinematics.fourbar import solve
from cad.kinematics.linkgeom import link_joints_mm
from cad.kinematics.metrics import path_frame
from cad.parts import tubebars as tb
from cad.parts.bars import Feature, hull_points, outline_area_mm2, pocket_segments

STEEL = 7870.0


def _rho(material: str) -> float:
    return get_material(material).density_kg_m3


def _features(parts, J, link: str, plan=None) -> dict:
    """Joint features of a bar as :mod:`cad.parts.bars` wants them (sizes as the assembly):
    the bearing seat where ``link`` is the upper link of the joint in ``plan`` (without a
    plan: on the coupler), the pin hole elsewhere."""
    brg = cat.get_bearing(parts.bearing)
    pin = cat.get_shoulder_screw(parts.pin)
    seat = Feature("seat", d_mm=brg.Da_mm, cb_d_mm=brg.D_mm, cb_depth_mm=brg.B_mm)
    out = {}
    for j, xy in J[link].items():
        if j == "A1":
            m = cat.get_motor(parts.motor)
            f = Feature("hub", d_mm=m.shaft_diameter_mm + 1.0, bolt_circle_mm=parts.hub_diameter_mm * 0.65,
                        bolt_hole_mm=cat.clearance_hole_mm(parts.hub_screw), bolt_count=3)
        elif j == "P":
            f = Feature("tapped", d_mm=cat.tap_drill_mm(parts.handle_screw),
                        keep_r_mm=parts.handle_diameter_mm / 2)
        else:
            upper = plan.joints[j].upper == link if plan is not None else link == "coupler"
            f = seat if upper else Feature("pin", d_mm=pin.ds_mm)
        out[j] = (np.asarray(xy, float), f)
    return out


def tube_bar_props(parts, J, link: str, plan=None) -> tuple[float, np.ndarray, float]:
    """(mass kg, COM m (2,), Izz about COM kg m^2) of a tube bar (``bar_style = "tube"``):
    each tube a thick-walled cylinder (m (3 (R^2 + r^2) + L^2) / 12 about its middle), each
    clevis its primitives (half disc + block per socket arm, two opposite arms a 2 Lc x w
    block; minus sockets, bore, seat annulus) as a point mass at its COM."""
    feats = _features(parts, J, link, plan)
    pts = {n: p for n, (p, _) in feats.items()}
    segs = tb.segments(link, pts)
    t, r, Lc, sd = parts.bar_thickness_mm, parts.bar_end_radius_mm, parts.clevis_length_mm, parts.socket_depth_mm
    ds = parts.tube_od_mm + 2 * tb.BOND_GAP_MM
    items = []  # (kg, COM m, own Izz kg m^2)
    R, ri = parts.tube_od_mm / 2, parts.tube_id_mm / 2
    for a, b in segs:
        L = tb.tube_length_mm(float(np.linalg.norm(pts[b] - pts[a])), parts)
        m = math.pi * (R**2 - ri**2) * L * 1e-9 * _rho(parts.tube_material)
        items.append((m, 0.5 * (pts[a] + pts[b]) * 1e-3, m * (3 * (R**2 + ri**2) + L**2) * 1e-6 / 12))
    for n, (p, f) in feats.items():
        dirs = [np.deg2rad(d) for d in tb.directions_deg(n, pts, segs)]
        u = np.array([[math.cos(d), math.sin(d)] for d in dirs])
        if len(dirs) == 1:  # half disc behind the joint, block along the arm
            parts_v = [(math.pi * r**2 / 2 * t, -4 * r / (3 * math.pi) * u[0]), (Lc * 2 * r * t, Lc / 2 * u[0])]
        else:
            parts_v = [(Lc * 2 * r * t, Lc / 2 * ui) for ui in u]
        parts_v += [(-math.pi * ds**2 / 4 * sd, (Lc - sd / 2) * ui) for ui in u]
        parts_v.append((-math.pi * f.d_mm**2 / 4 * t, np.zeros(2)))
        if f.cb_depth_mm > 0:
            parts_v.append((-math.pi * (f.cb_d_mm**2 - f.d_mm**2) / 4 * f.cb_depth_mm, np.zeros(2)))
        v = sum(x for x, _ in parts_v)
        c = sum(x * y for x, y in parts_v) / v
        m = v * 1e-9 * _rho(parts.clevis_material)
        span = Lc + r if len(dirs) == 1 else 2 * Lc  # the clevis as a span x w rectangle
        items.append((m, (p + c) * 1e-3, m * (span**2 + 4 * r**2) * 1e-6 / 12))
    M = sum(i[0] for i in items)
    com = sum(i[0] * i[1] for i in items) / M
    izz = sum(i[2] + i[0] * float(np.sum((i[1] - com) ** 2)) for i in items)
    return M, com, izz


def tube_problem(design) -> str | None:
    """Why tube bars cannot be made for this design (socket into a joint feature, bare tube
    too short, non-collinear joints), or None; plate bars: None."""
    parts = design.parts
    if parts.bar_style != "tube":
        return None
    J = link_joints_mm(design.linkage)
    try:
        for link in ("crank", "coupler", "rocker"):
            tb.check_link(link, _features(parts, J, link), parts)
    except HapticadError as exc:
        return str(exc)
    return None


def bar_props(parts, J, link: str, plan=None) -> tuple[float, np.ndarray, float]:
    """(mass kg, COM m (2,), Izz about COM kg m^2) of a bar (module docstring)."""
    if parts.bar_style == "tube":
        return tube_bar_props(parts, J, link, plan)
    feats = _features(parts, J, link, plan)
    pts = np.array([p for p, _ in feats.values()])
    r = parts.bar_end_radius_mm
    area = outline_area_mm2(pts, r)
    if r > parts.bar_width_mm / 2:  # dog-bone: the ends are wider than the strip
        area = outline_area_mm2(pts, parts.bar_width_mm / 2) + len(pts) * math.pi * (
            r**2 - (parts.bar_width_mm / 2) ** 2) * 0.75
    for a, b, wp in pocket_segments(feats, parts):
        area -= float(np.linalg.norm(b - a)) * wp + math.pi * wp**2 / 4
    for _, f in feats.values():
        area -= math.pi * f.d_mm**2 / 4
    vol = area * parts.bar_thickness_mm
    m = vol * 1e-9 * _rho(parts.bar_material)
    h = hull_points(pts)
    L = float(np.max(np.linalg.norm(h[:, None] - h[None], axis=-1))) + 2 * r
    com = pts.mean(axis=0) * 1e-3
    return m, com, m * (L**2 + parts.bar_width_mm**2) * 1e-6 / 12


def joint_split_kg(parts, spacer_mm: float, pin_length_mm: float | None = None,
                   shim_mm: float | None = None, nut: bool = True) -> tuple[float, float]:
    """(upper kg, lower kg) of one joint's hardware: the bearing (and a pin sleeve's bore
    ring, with the bearing) on the upper link; the pin, the gap spacer (``spacer_mm``) and head
    spacer (``shim_mm``, default t - B + head clearance), nut or ring and washer (when ``nut``)
    on the lower link. ``pin_length_mm``: the pin's catalog length (default the clamp plus
    one bar thickness)."""
    brg = cat.get_bearing(parts.bearing)
    pin = cat.get_shoulder_screw(parts.pin)
    t = parts.bar_thickness_mm
    shim = t - brg.B_mm + parts.pin_head_clearance_mm if shim_mm is None else shim_mm
    L = shim + brg.B_mm + spacer_mm + t if pin_length_mm is None else pin_length_mm
    if cat.is_dowel(parts.pin):
        ring = cat.get_retaining_ring(pin.ds_mm)
        v_pin = math.pi / 4 * pin.ds_mm**2 * (pin.k_mm + L + pin.b_mm)
        v_nut = 2 * math.pi / 4 * (ring.d4_mm**2 - pin.ds_mm**2) * ring.s_mm
    else:
        n = cat.get_nut(parts.pin)
        v_pin = math.pi / 4 * (pin.dk_mm**2 * pin.k_mm * 0.85 + pin.ds_mm**2 * L
                               + pin.thread_mm**2 * pin.b_mm)
        v_nut = (math.sqrt(3) / 2 * n.s_mm**2 - math.pi / 4 * pin.thread_mm**2) * n.m_mm
    w = cat.get_washer(parts.pin)
    v_w = math.pi / 4 * (w.d2_mm**2 - w.d1_mm**2) * w.h_mm
    od = spacer_od_mm(parts)
    v_sp = math.pi / 4 * (od**2 - pin.ds_mm**2) * (shim + spacer_mm)
    upper = brg.mass_kg if parts.bearing_mass_g is None else parts.bearing_mass_g * 1e-3
    lower = v_pin * 1e-9 * _rho(parts.pin_material) + v_sp * 1e-9 * _rho(parts.spacer_material)
    if nut:
        lower += (v_nut + v_w) * 1e-9 * STEEL
    if parts.pin_sleeve_material is not None:
        lower += math.pi / 4 * (brg.d_mm**2 - pin.ds_mm**2) * brg.B_mm * 1e-9 * _rho(parts.pin_sleeve_material)
    return upper, lower


def joint_hardware_kg(parts) -> float:
    """Mass (kg) of one joint's hardware with a one-gap stack: bearing, pin, two spacers, nut
    or ring, washer (:func:`joint_split_kg`)."""
    return sum(joint_split_kg(parts, parts.layer_gap_mm))


def layer_plan(design, parts=None):
    """The layer plan of ``design`` (numpy only, the build's poses), or None when the planner
    finds no layout (the build refuses it)."""
    parts = parts or design.parts
    fb = design.linkage
    phi = np.linspace(design.phi1_min_rad, design.phi1_max_rad, parts.interference_poses)
    try:
        return choose_layers(link_joints_mm(fb), parts, planar_transforms(fb, phi),
                             made_axle=made_crank_axle(design))
    except HapticadError:
        return None


def hardware_items(parts, J, plan=None) -> dict[str, list[tuple[float, np.ndarray]]]:
    """{link: [(kg, point m (2,))]} of the joint hardware as point masses (module docstring)."""
    out: dict[str, list] = {"crank": [], "coupler": [], "rocker": []}
    if plan is None:
        hw = joint_hardware_kg(parts)
        for link in out:
            out[link] += [(hw / 2, np.asarray(J[link][j]) * 1e-3) for j in ("A2", "A3", "A4") if j in J[link]]
        return out
    for j, s in plan.joints.items():
        up, low = joint_split_kg(parts, s.spacer_mm, s.pin_length_mm, s.shim_mm, s.nut)
        out[s.upper].append((up, np.asarray(J[s.upper][j]) * 1e-3))
        if s.lower in out:
            out[s.lower].append((low, np.asarray(J[s.lower][j]) * 1e-3))
    return out


def handle_kg(parts) -> float:
    """Knob (solid cylinder less the screw bore) and its cap screw, kg."""
    cs = cat.get_cap_screw(parts.handle_screw, "parts.handle_screw")
    d, h = parts.handle_diameter_mm, parts.handle_height_mm
    knob = math.pi / 4 * (d**2 * h - (cs.dk_mm + 1) ** 2 * 5.0) * 1e-9 * _rho(parts.handle_material)
    L = parts.bar_thickness_mm + 5.0
    screw = math.pi / 4 * (cs.dk_mm**2 * cs.k_mm + cs.d_mm**2 * L) * 1e-9 * STEEL
    return knob + screw


def link_inertias(design, parts=None, plan=None) -> dict:
    """{link: PlanarLinkInertia} of the cheap model (module docstring); ``plan``: the layer
    plan (:func:`layer_plan`; None: the order-free split)."""
    parts = parts or design.parts
    J = link_joints_mm(design.linkage)
    hw = hardware_items(parts, J, plan)
    hub_h = 10.0 if plan is None else plan.hub_z_mm[1] - plan.hub_z_mm[0]
    out = {}
    for link in ("crank", "coupler", "rocker"):
        items = [bar_props(parts, J, link, plan)] + [(m, p, 0.0) for m, p in hw[link]]
        if "P" in J[link]:
            items.append((handle_kg(parts), np.asarray(J[link]["P"]) * 1e-3, 0.0))
        if "A1" in J[link]:
            hub_m = (math.pi / 4 * (parts.hub_diameter_mm**2 - 36) * hub_h * 1e-9 * _rho(parts.hub_material)
                     + 3 * 1.0e-3 * (cat.thread_diameter_mm(parts.hub_screw) / 3) ** 2)
            items.append((hub_m, np.asarray(J[link]["A1"]) * 1e-3, hub_m * (parts.hub_diameter_mm * 1e-3) ** 2 / 8))
        M = sum(i[0] for i in items)
        com = sum(i[0] * i[1] for i in items) / M
        izz = sum(i[2] + i[0] * float(np.sum((i[1] - com) ** 2)) for i in items)
        out[link] = PlanarLinkInertia.from_com(M, com, izz)
    return out


def rotor_inertia_kg_m2(parts) -> float:
    if parts.motor_rotor_inertia_g_cm2 is not None:
        return parts.motor_rotor_inertia_g_cm2 * 1e-7
    return cat.get_motor(parts.motor).rotor_inertia_kg_m2


def rotor_of(design, parts=None) -> float:
    """The motor side's inertia at the crank (kg m^2): the rotor (``parts`` overrides) for a
    direct drive; through a capstan the resolved device's n^2 (J_m + J_capstan)
    (:meth:`cad.device.ResolvedDevice.joint_rotor_inertia_kg_m2`)."""
    dev = resolve_device(design)
    if not dev.transmission("crank").is_capstan:
        return rotor_inertia_kg_m2(parts or design.parts)
    return dev.joint_rotor_inertia_kg_m2("crank")


def drum_izz_kg_m2(design, span_deg: float | None = None) -> float:
    """The capstan drum sector's inertia about A1 (kg m^2; 0 for a direct drive): an annular
    sector (hub bore to the rim's crests, :func:`cad.actuators.capstan_geometry.crest_radius_mm`,
    :data:`cad.families.fourbar.capstan.DRUM_THICKNESS_MM` thick, its anchors' holes left out) of
    the arc the rope needs with the tangent points' 2 gamma, m (r_o^2 + r_i^2) / 2
    (:func:`cad.actuators.capstan_geometry.sector_mass_kg`), less its rope groove taken round the
    whole arc at its section's centroid radius (:func:`cad.actuators.capstan_geometry.ring_groove_volume_mm3`;
    the solid stops it short of the anchors: a few 1e-10 kg m^2)."""
    t = resolve_device(design).transmission("crank")
    if not t.is_capstan:
        return 0.0
    C = cap.centre_distance_mm(t.capstan_diameter_mm, t.drum_diameter_mm, t.centre_distance_mm)
    g = math.degrees(cg.tangent_half_angle_rad(t.drum_diameter_mm, t.capstan_diameter_mm, C))
    rng = math.degrees(design.phi1_max_rad - design.phi1_min_rad)
    span = 2 * g + rng + 2 * math.degrees(2.0 * fcap.ANCHOR_LENGTH_MM / t.drum_diameter_mm)
    r_o, r_i = cg.crest_radius_mm(t.drum_diameter_mm, t.cable_diameter_mm), design.parts.hub_diameter_mm / 2
    rho = get_material(fcap.DRUM_MATERIAL).density_kg_m3
    m = cg.sector_mass_kg(min(span, 360.0), r_o, r_i, fcap.DRUM_THICKNESS_MM, rho)
    _, rbar = cg.groove_section_mm(t.drum_diameter_mm, t.cable_diameter_mm)
    groove = cg.ring_groove_volume_mm3(t.drum_diameter_mm, t.cable_diameter_mm, min(span, 360.0)) * 1e-9 * rho
    return 0.5 * m * (r_o ** 2 + r_i ** 2) * 1e-6 - groove * (rbar * 1e-3) ** 2


def apparent_mass(design, parts=None, samples: int = 201, plan=False) -> dict:
    """Cheap-model H11..H33 and M11 range (g) of ``design`` (optionally other ``parts``);
    ``plan``: the layer plan (:func:`layer_plan`), computed when not given (False), None for
    the order-free split."""
    parts = parts or design.parts
    if plan is False:
        plan = layer_plan(design, parts)
    li = link_inertias(design, parts, plan)
    H = h_from_links(design.linkage, li["crank"], li["coupler"], li["rocker"],
                     rotor_of(design, parts) + drum_izz_kg_m2(design))
    phi = np.linspace(design.phi1_min_rad, design.phi1_max_rad, samples)
    fr = path_frame(design.linkage, design.phi1_min_rad, design.phi1_max_rad)
    M = apparent_mass_matrix(design.linkage, solve(design.linkage, phi), H, fr)
    return {**H.as_dict(), **apparent_mass_summary(M),
            "moving_mass_g": sum(v.mass_kg for v in li.values()) * 1e3,
            "layer_order": None if plan is None else list(plan.order)}
