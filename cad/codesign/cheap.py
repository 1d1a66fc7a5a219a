"""Cheap mass model of a four-bar's moving parts (numpy + catalog data, no CAD import).

Per link, in the link frame (mm in, SI out):

* bar: plate area (closed-form hull of the joint discs, :func:`cad.parts.bars.outline_area_mm2`,
  minus the pocket slots of :func:`cad.parts.bars.pocket_segments` and the joint holes)
  x thickness x density; COM at the joints' centroid; Izz = m (L^2 + w^2) / 12 about
  it (L the outline length along the hull);
* joint hardware as point masses at the joint: bearing (catalog mass), pin (cylinder
  d x stack length, or ISO 7379 head + shoulder + thread), spacers, nut or ring, washer
  -- the same stack rule as :mod:`cad.assembly.layers` (shim = t - B + head clearance,
  gap spacer = layer_gap). A point mass at a joint has the same velocity whichever link
  carries it, so the layer order does not enter (only the small spin inertias do);
* crank hub (disc at A1), knob (cylinder at P) and its screw, hub screws;
* the rotor inertia Jm of the motor catalog.

Then H11..H33 (eqs 16-19, :func:`cad.dynamics.inertia.h_from_links`) and M11 over the
stroke (eq 22). The model's error against the exact solids is measured at every reported
optimum (:mod:`cad.codesign.exact`).
"""

from __future__ import annotations

import math

import numpy as np

STEEL = 7870.0


def _rho(material: str) -> float:
    from cad.materials import get_material

    return get_material(material).density_kg_m3


def _features(parts, J, link: str) -> dict:
    """Joint features of a bar as :mod:`cad.parts.bars` wants them (sizes as the assembly)."""
    from cad.parts import catalog as cat
    from cad.parts.bars import Feature

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
            f = seat if link == "coupler" else Feature("pin", d_mm=pin.ds_mm)
        out[j] = (np.asarray(xy, float), f)
    return out


def tube_bar_props(parts, J, link: str) -> tuple[float, np.ndarray, float]:
    """(mass kg, COM m (2,), Izz about COM kg m^2) of a tube bar (``bar_style = "tube"``):
    each tube a thick-walled cylinder (m (3 (R^2 + r^2) + L^2) / 12 about its middle), each
    clevis its primitives (half disc + block per socket arm, two opposite arms a 2 Lc x w
    block; minus sockets, bore, seat annulus) as a point mass at its COM."""
    from cad.parts import tubebars as tb

    feats = _features(parts, J, link)
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
    from cad.errors import HapticadError
    from cad.kinematics.linkgeom import link_joints_mm
    from cad.parts import tubebars as tb

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


def bar_props(parts, J, link: str) -> tuple[float, np.ndarray, float]:
    """(mass kg, COM m (2,), Izz about COM kg m^2) of a bar (module docstring)."""
    from cad.parts.bars import hull_points, outline_area_mm2, pocket_segments

    if parts.bar_style == "tube":
        return tube_bar_props(parts, J, link)
    feats = _features(parts, J, link)
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


def joint_hardware_kg(parts) -> float:
    """Mass (kg) of one joint's hardware: bearing, pin, two spacers, nut or ring, washer."""
    from cad.assembly.layers import spacer_od_mm
    from cad.parts import catalog as cat

    brg = cat.get_bearing(parts.bearing)
    pin = cat.get_shoulder_screw(parts.pin)
    t = parts.bar_thickness_mm
    shim = t - brg.B_mm + parts.pin_head_clearance_mm
    stack = shim + brg.B_mm + parts.layer_gap_mm + t
    rho_pin = _rho(parts.pin_material)
    if cat.is_dowel(parts.pin):
        ring = cat.get_retaining_ring(pin.ds_mm)
        v_pin = math.pi / 4 * pin.ds_mm**2 * (pin.k_mm + stack + pin.b_mm)
        v_nut = 2 * math.pi / 4 * (ring.d4_mm**2 - pin.ds_mm**2) * ring.s_mm
    else:
        nut = cat.get_nut(parts.pin)
        v_pin = math.pi / 4 * (pin.dk_mm**2 * pin.k_mm * 0.85 + pin.ds_mm**2 * stack
                               + pin.thread_mm**2 * pin.b_mm)
        v_nut = (math.sqrt(3) / 2 * nut.s_mm**2 - math.pi / 4 * pin.thread_mm**2) * nut.m_mm
    w = cat.get_washer(parts.pin)
    v_w = math.pi / 4 * (w.d2_mm**2 - w.d1_mm**2) * w.h_mm
    od = spacer_od_mm(parts)
    v_sp = math.pi / 4 * (od**2 - pin.ds_mm**2) * (shim + parts.layer_gap_mm)
    m = brg.mass_kg if parts.bearing_mass_g is None else parts.bearing_mass_g * 1e-3
    if parts.pin_sleeve_material is not None:
        m += math.pi / 4 * (brg.d_mm**2 - pin.ds_mm**2) * brg.B_mm * 1e-9 * _rho(parts.pin_sleeve_material)
    return (m + v_pin * 1e-9 * rho_pin + (v_nut + v_w) * 1e-9 * STEEL
            + v_sp * 1e-9 * _rho(parts.spacer_material))


def handle_kg(parts) -> float:
    """Knob (solid cylinder less the screw bore) and its cap screw, kg."""
    from cad.parts import catalog as cat

    cs = cat.get_cap_screw(parts.handle_screw, "parts.handle_screw")
    d, h = parts.handle_diameter_mm, parts.handle_height_mm
    knob = math.pi / 4 * (d**2 * h - (cs.dk_mm + 1) ** 2 * 5.0) * 1e-9 * _rho(parts.handle_material)
    L = parts.bar_thickness_mm + 5.0
    screw = math.pi / 4 * (cs.dk_mm**2 * cs.k_mm + cs.d_mm**2 * L) * 1e-9 * STEEL
    return knob + screw


def link_inertias(design, parts=None) -> dict:
    """{link: PlanarLinkInertia} of the cheap model (module docstring)."""
    from cad.dynamics.inertia import PlanarLinkInertia
    from cad.kinematics.linkgeom import link_joints_mm
    from cad.parts import catalog as cat

    parts = parts or design.parts
    J = link_joints_mm(design.linkage)
    hw = joint_hardware_kg(parts)
    out = {}
    for link in ("crank", "coupler", "rocker"):
        m, c, izz = bar_props(parts, J, link)
        items = [(m, c, izz)]
        for j, xy in J[link].items():
            p = np.asarray(xy) * 1e-3
            if j in ("A2", "A3"):
                items.append((hw / 2, p, 0.0))  # each joint's hardware shared by its two links
            elif j == "A4":
                items.append((hw * 0.5, p, 0.0))
            elif j == "P":
                items.append((handle_kg(parts), p, 0.0))
            elif j == "A1":
                hub_m = (math.pi / 4 * (parts.hub_diameter_mm**2 - 36) * 10.0 * 1e-9 * _rho(parts.hub_material)
                         + 3 * 1.0e-3 * (cat.thread_diameter_mm(parts.hub_screw) / 3) ** 2)
                items.append((hub_m, p, hub_m * (parts.hub_diameter_mm * 1e-3) ** 2 / 8))
        M = sum(i[0] for i in items)
        com = sum(i[0] * i[1] for i in items) / M
        izz = sum(i[2] + i[0] * float(np.sum((i[1] - com) ** 2)) for i in items)
        out[link] = PlanarLinkInertia.from_com(M, com, izz)
    return out


def rotor_inertia_kg_m2(parts) -> float:
    from cad.parts import catalog as cat

    if parts.motor_rotor_inertia_g_cm2 is not None:
        return parts.motor_rotor_inertia_g_cm2 * 1e-7
    return cat.get_motor(parts.motor).rotor_inertia_kg_m2


def apparent_mass(design, parts=None, samples: int = 201) -> dict:
    """Cheap-model H11..H33 and M11 range (g) of ``design`` (optionally other ``parts``)."""
    from cad.dynamics.inertia import apparent_mass_matrix, apparent_mass_summary, h_from_links
    from cad.kinematics.fourbar import solve
    from cad.kinematics.metrics import path_frame

    parts = parts or design.parts
    li = link_inertias(design, parts)
    H = h_from_links(design.linkage, li["crank"], li["coupler"], li["rocker"], rotor_inertia_kg_m2(parts))
    phi = np.linspace(design.phi1_min_rad, design.phi1_max_rad, samples)
    fr = path_frame(design.linkage, design.phi1_min_rad, design.phi1_max_rad)
    M = apparent_mass_matrix(design.linkage, solve(design.linkage, phi), H, fr)
    return {**H.as_dict(), **apparent_mass_summary(M),
            "moving_mass_g": sum(v.mass_kg for v in li.values()) * 1e3}
