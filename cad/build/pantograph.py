"""Build a twin-pantograph haptic mouse: layout -> clearances -> solids -> mass properties -> exports.

Contract: see :mod:`cad.build` (``build(design, out_dir, formats, *, fidelity,
allow_interference, progress, phi1_deg) -> report dict``; ``phi1_deg`` is
ignored). Isotropy paper §4.1, Fig. 1, Table 1.

Arrangement (our reading of Fig. 1; world frame = the kinematic base frame,
z up, z = 0 on the base plate's top face):

* two identical 5-bars in stacked planes, both with their actuated joints at
  B1 = (-a/2, 0) and B2 = (+a/2, 0);
* the *crank* pantograph (drives the crank pin) is the lower group: proximal
  links in layer L0, left distal L1, right distal L2; its motors hang under
  the base plate on motor-mount plates, shafts up;
* the crankshaft web lies between the groups; the crank pin hangs down into
  L2 and L1, the main journal rises through the upper group to the knob;
* the *knob* pantograph (drives the main journal, the kinematic reference
  point) is the upper group, mirrored: right distal U2, left distal U1,
  proximal links U0 on top; its motors stand on a bridge plate above U0
  (shafts down), the bridge carried by four posts behind the base line;
* every passive joint: a steel pin pressed into the proximal clevis, two ball
  bearings in the distal clevis; the journals run in the distal clevises'
  bearings the same way.

Clearances are checked analytically (capsules per layer, numpy) over the
design's workspace samples x 16 crank angles, before any solid is built.

Report keys: ``gii`` (the design's GII), ``layout_mm``, ``clearances_mm``,
``bodies`` (mass properties of each moving body from the exact B-rep, in its
link frame), ``effective_mass_home`` (diag and apparent readings) beside
``paper_table1``, ``parts`` (files), ``bom``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from cad.errors import InterferenceError

#: Paper Table 1 (haptic mouse at its home position).
PAPER_TABLE1 = {
    "mass_x_g": 395.0,
    "mass_y_g": 370.0,
    "inertia_theta_g_cm2": 4781.0,
    "peak_force_x_N": 23.0,
    "peak_force_y_N": 22.0,
    "continuous_force_x_N": 2.4,
}
#: Smallest accepted gap between moving parts in the same layer (mm): the
#: clevises are machined parts, 0.5 mm covers their tolerance stack.
MIN_CLEARANCE_MM = 0.5
#: Crank angles sampled by the clearance check (full turn).
CLEARANCE_THETA_SAMPLES = 16
#: Posts: offset along x from each actuated joint (mm), and the M4 screws.
POST_DX_MM = 22.0
POST_SCREW_TAP_MM = 3.3
POST_SCREW_CLEAR_MM = 4.5
#: Depth of the main journal in the knob's bore (mm).
KNOB_BORE_DEPTH_MM = 15.0


def _step(progress, text: str, done: int, total: int) -> None:
    if progress is not None:
        progress(text, done, total)


# ----------------------------------------------------------------------------- layout
def layout(design) -> dict:
    """Heights and plate extents of the assembly (mm), from the design only (no CAD)."""
    from cad.parts.catalog import get_bearing, get_motor
    from cad.parts.motor import mount_side_mm

    p = design.parts
    tp = design.mechanism
    a = design.params["base_mm"]
    l2, l3, l6 = design.params["proximal_mm"], design.params["distal_mm"], tp.crank_mm
    b = get_bearing(p.bearing)
    m = get_motor(p.motor)
    h, g, t = p.clevis_height_mm, p.layer_gap_mm, p.crank_thickness_mm
    pitch = h + g
    L0 = g + h / 2
    L = [L0, L0 + pitch, L0 + 2 * pitch]
    zW = L[2] + h / 2 + g + t / 2
    U2 = zW + t / 2 + g + h / 2
    U = [U2 + 2 * pitch, U2 + pitch, U2]  # U0 (proximal, top), U1, U2
    z_bridge = U[0] + h / 2 + g
    ms = mount_side_mm(m)
    post_y = -(ms / 2 + p.post_diameter_mm / 2 + 8.0)
    posts = [(sx * a / 2 + dx, post_y) for sx in (-1, 1) for dx in (-POST_DX_MM, POST_DX_MM)]
    ws = design.workspace
    cx, cy = ws["center_mm"]
    half = ws["side_mm"] / 2
    reach_x = a / 2 + l2 + p.clevis_width_mm
    base_x = (min(-reach_x, cx - half - l6 - 20), max(reach_x, cx + half + l6 + 20))
    base_y = (post_y - p.post_diameter_mm / 2 - 12, cy + half + l6 + p.clevis_width_mm + 20)
    bridge_x = (
        min(x for x, _ in posts) - p.post_diameter_mm,
        max(x for x, _ in posts) + p.post_diameter_mm,
    )
    bridge_y = (post_y - p.post_diameter_mm, ms / 2 + 5)
    journal_up = (U[0] + h / 2 + g + KNOB_BORE_DEPTH_MM) - (zW + t / 2)
    pin_down = (zW - t / 2) - (L[1] - h / 2)
    shaft_tip = -p.plate_thickness_mm - p.motor_mount_thickness_mm + m.shaft_length_mm
    return {
        "layer_pitch_mm": pitch,
        "lower_layers_z_mm": L,
        "web_z_mm": zW,
        "upper_layers_z_mm": U,
        "bridge_bottom_z_mm": z_bridge,
        "knob_bottom_z_mm": U[0] + h / 2 + g,
        "posts_xy_mm": posts,
        "base_plate_x_mm": base_x,
        "base_plate_y_mm": base_y,
        "bridge_x_mm": bridge_x,
        "bridge_y_mm": bridge_y,
        "journal_up_mm": journal_up,
        "crank_pin_down_mm": pin_down,
        "journal_d_mm": b.d_mm,
        "web_width_mm": max(b.d_mm + 6.0, 10.0),
        "pin_short_mm": 2 * h + g,
        "pin_long_mm": 3 * h + 2 * g,
        "tube_proximal_mm": l2 - 2 * (p.clevis_length_mm - p.socket_depth_mm),
        "tube_distal_mm": l3 - 2 * (p.clevis_length_mm - p.socket_depth_mm),
        "lower_shaft_engagement_mm": shaft_tip - (L[0] - h / 2),
        "upper_shaft_engagement_mm": (U[0] + h / 2)
        - (z_bridge + p.plate_thickness_mm + p.motor_mount_thickness_mm - m.shaft_length_mm),
        "motor_mount_side_mm": ms,
    }


# ------------------------------------------------------------------------- clearances
def seg_seg_distance(p1, q1, p2, q2) -> np.ndarray:
    """Distance between 2-D segments p1q1 and p2q2, vectorized over leading axes (mm)."""
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a = np.einsum("...i,...i->...", d1, d1)
    e = np.einsum("...i,...i->...", d2, d2)
    f = np.einsum("...i,...i->...", d2, r)
    c = np.einsum("...i,...i->...", d1, r)
    b = np.einsum("...i,...i->...", d1, d2)
    den = a * e - b * b
    s = np.where(
        den > 1e-12 * a * e, np.clip((b * f - c * e) / np.where(den > 0, den, 1.0), 0, 1), 0.0
    )
    tt = (b * s + f) / np.where(e > 0, e, 1.0)
    t = np.clip(tt, 0, 1)
    s = np.where(
        tt < 0,
        np.clip(-c / np.where(a > 0, a, 1.0), 0, 1),
        np.where(tt > 1, np.clip((b - c) / np.where(a > 0, a, 1.0), 0, 1), s),
    )
    c1 = p1 + d1 * s[..., None]
    c2 = p2 + d2 * t[..., None]
    return np.linalg.norm(c1 - c2, axis=-1)


def _pt_seg(pt, p, q):
    return seg_seg_distance(pt, pt, p, q)


def clearances(design, lay: dict | None = None) -> dict:
    """Smallest gaps (mm) between parts sharing a layer over the workspace x full turn.

    Capsules (segment + radius) per layer: proximal and distal links (radius =
    clevis_width / 2), pins crossing a layer they are not part of, the main
    journal crossing U0, the posts crossing every layer. Returns
    {check: {"gap_mm", "at": [x_mm, y_mm, theta_deg]}} and the overall minimum.
    """
    from cad.kinematics import twin_pantograph as tw
    from cad.parts.catalog import get_bearing

    lay = lay or layout(design)
    p = design.parts
    tp = design.mechanism
    ws = design.workspace
    X = tw.workspace_grid(
        ws["center_mm"], ws["side_mm"], max(ws["grid"], 5), CLEARANCE_THETA_SAMPLES
    )
    pose = tw.ik(tp, X)
    if np.any(pose.status != 0):
        i = int(np.flatnonzero(pose.status != 0)[0])
        raise InterferenceError(
            f"workspace pose {X[i].round(3).tolist()} is {tw.STATUS_NAMES[int(pose.status[i])]}"
        )
    rc = p.clevis_width_mm / 2
    rpin = get_bearing(p.bearing).d_mm / 2
    rpost = p.post_diameter_mm / 2
    B1 = np.array(tp.knob.base_left_mm)
    B2 = np.array(tp.knob.base_right_mm)
    checks: dict[str, np.ndarray] = {}
    for grp, fp in (("crank", pose.crank), ("knob", pose.knob)):
        C1, C2, E = fp.C_left_mm, fp.C_right_mm, fp.E_mm
        checks[f"{grp}: proximal L vs proximal R"] = seg_seg_distance(B1, C1, B2, C2) - 2 * rc
        checks[f"{grp}: left distal vs right elbow pin"] = _pt_seg(C2, C1, E) - rc - rpin
        for x, y in lay["posts_xy_mm"]:
            post = np.array([x, y])
            for name, (s0, s1) in {
                "proximal L": (B1, C1),
                "proximal R": (B2, C2),
                "distal L": (C1, E),
                "distal R": (C2, E),
            }.items():
                key = f"{grp}: {name} vs posts"
                d = _pt_seg(post, s0, s1) - rc - rpost
                checks[key] = np.minimum(checks[key], d) if key in checks else d
    Ek = pose.knob.E_mm
    checks["knob: main journal vs proximal links (U0)"] = (
        np.minimum(_pt_seg(Ek, B1, pose.knob.C_left_mm), _pt_seg(Ek, B2, pose.knob.C_right_mm))
        - rc
        - rpin
    )
    # knob (above U0) against the bridge plate, in plan
    bx, by = lay["bridge_x_mm"], lay["bridge_y_mm"]
    dx = np.maximum(np.maximum(bx[0] - Ek[:, 0], Ek[:, 0] - bx[1]), 0)
    dy = np.maximum(np.maximum(by[0] - Ek[:, 1], Ek[:, 1] - by[1]), 0)
    checks["knob vs bridge plate (plan)"] = np.hypot(dx, dy) - design.mechanism.knob_diameter_mm / 2
    out = {}
    for k, v in checks.items():
        i = int(np.argmin(v))
        out[k] = {
            "gap_mm": float(v[i]),
            "at": [float(X[i, 0]), float(X[i, 1]), float(np.degrees(X[i, 2]))],
        }
    worst = min(out, key=lambda k: out[k]["gap_mm"])
    return {
        "checks": out,
        "min_gap_mm": out[worst]["gap_mm"],
        "worst": worst,
        "poses": int(X.shape[0]),
    }


# --------------------------------------------------------------------------- helpers
def _rz(angle: float, x: float = 0.0, y: float = 0.0, z: float = 0.0) -> np.ndarray:
    T = np.eye(4)
    c, s = math.cos(angle), math.sin(angle)
    T[:2, :2] = [[c, -s], [s, c]]
    T[:3, 3] = (x, y, z)
    return T


def _flip() -> np.ndarray:
    T = np.eye(4)
    T[1, 1] = T[2, 2] = -1.0
    return T


def _props(shape, density, tf=None):
    from cad.massprops.occt import solid_mass_props

    mp = solid_mass_props(shape, density)
    if tf is None:
        return mp
    return mp.transformed(tf[:3, :3], tf[:3, 3] * 1e-3)


def _planar(mp):
    """MassProps (3-D, link frame) -> LinkMass (mass, COM xy, Izz about the COM)."""
    from cad.kinematics.fivebar import LinkMass

    return LinkMass(
        float(mp.mass_kg),
        (float(mp.com_m[0]), float(mp.com_m[1])),
        float(mp.inertia_com_kg_m2[2, 2]),
    )


def _write_sim(design, out_dir, formats, bodies, bodies_parts, lay, home, ik, mot, made, color):
    """``<name>.xml`` (MJCF) / ``<name>.urdf`` when asked (:mod:`cad.build.sim_pantograph`)."""
    from cad.export.sim import SIM_FORMATS, write_sim_files

    if not set(formats) & set(SIM_FORMATS):
        return []
    from cad.build.sim_pantograph import sim_model

    p = design.parts
    a = design.params["base_mm"]
    pt, mt, zb = p.plate_thickness_mm, p.motor_mount_thickness_mm, lay["bridge_bottom_z_mm"]
    ground = [("base_plate", "base_plate", _rz(0.0, 0, 0, -pt)),
              ("bridge_plate", "bridge_plate", _rz(0.0, 0, 0, zb))]
    ground += [(f"post_{k}", "post", _rz(0.0, x, y, 0.0)) for k, (x, y) in enumerate(lay["posts_xy_mm"])]
    for i, bx in enumerate((-a / 2, a / 2)):
        ground += [(f"crank_motor_mount_{i}", "motor_mount", _rz(0.0, bx, 0.0, -pt - mt)),
                   (f"knob_motor_mount_{i}", "motor_mount", _rz(0.0, bx, 0.0, zb + pt))]
    model = sim_model(design, bodies, bodies_parts, ground, lay, home, ik, mot.rotor_inertia_kg_m2,
                      made, color)
    return [p.name for p in write_sim_files(model, out_dir, formats, design.name)]


# ------------------------------------------------------------------------------ build
#: This builder writes the simulator formats (mjcf, urdf; :mod:`cad.build.sim_pantograph`).
SIM_EXPORT = True


def build(
    design,
    out_dir: Path,
    formats: set[str],
    *,
    fidelity: str = "fabrication",
    allow_interference: bool = False,
    progress=None,
    phi1_deg: float | None = None,
) -> dict:
    """Build the twin-pantograph mouse into ``out_dir``; return the report dict (module docstring).

    fidelity: "fabrication" uses bd_warehouse ball bearings (races and balls);
    "inertia" and "preview" a plain ring of the catalogue mass (same mass, so the
    mass properties do not change). Raises InterferenceError when two parts
    in one layer come closer than :data:`MIN_CLEARANCE_MM` anywhere in the
    workspace x full turn, unless allow_interference.
    """
    from cad.errors import DesignError

    if design.family != "twin-pantograph":
        raise DesignError(
            "mechanism.family",
            f"parts are generated for the twin-pantograph only, not {design.family!r}",
        )
    from cad.export import export_assembly_step, export_part, write_bom
    from cad.export.shapes import placed
    from cad.kinematics import fivebar as fb5
    from cad.kinematics import twin_pantograph as tw
    from cad.massprops.props import MassProps, combine
    from cad.materials import get_material
    from cad.parts import joints
    from cad.parts import motor as pm
    from cad.parts import pantograph as pp
    from cad.parts.catalog import get_bearing, get_motor

    out_dir = Path(out_dir)
    total = 7
    p = design.parts
    tp = design.mechanism
    a = design.params["base_mm"]
    l2, l3, l6 = design.params["proximal_mm"], design.params["distal_mm"], tp.crank_mm
    h, w = p.clevis_height_mm, p.clevis_width_mm
    brg = get_bearing(p.bearing)
    mot = get_motor(p.motor)

    _step(progress, "layout and clearances", 0, total)
    lay = layout(design)
    for key in ("lower_shaft_engagement_mm", "upper_shaft_engagement_mm"):
        if lay[key] < h / 2:
            raise DesignError(
                "parts.motor",
                f"{p.motor} shaft engages only {lay[key]:.1f} mm of the {h} mm hub ({key}); "
                "use thinner plates or a longer shaft",
            )
    clr = clearances(design, lay)
    if clr["min_gap_mm"] < MIN_CLEARANCE_MM and not allow_interference:
        w_ = clr["checks"][clr["worst"]]
        raise InterferenceError(
            f"{clr['worst']}: gap {w_['gap_mm']:.2f} mm < {MIN_CLEARANCE_MM} mm at pose {w_['at']} "
            "(x_mm, y_mm, theta_deg); pass allow_interference to export anyway"
        )

    _step(progress, "solids", 1, total)
    mat = {
        k: get_material(getattr(p, k))
        for k in (
            "tube_material",
            "clevis_material",
            "pin_material",
            "crank_material",
            "knob_material",
            "plate_material",
        )
    }
    cl = dict(
        length_mm=p.clevis_length_mm,
        width_mm=w,
        height_mm=h,
        socket_depth_mm=p.socket_depth_mm,
        tube_od_mm=p.tube_od_mm,
    )
    S = {
        "clevis_hub": pp.clevis_shape("hub", bore_mm=mot.shaft_diameter_mm, **cl),
        "clevis_pin": pp.clevis_shape("pin", bore_mm=brg.d_mm, **cl),
        "clevis_bearing": pp.clevis_shape("bearing", bore_mm=brg.D_mm, **cl),
        "tube_proximal": pp.tube_shape(lay["tube_proximal_mm"], p.tube_od_mm, p.tube_id_mm),
        "tube_distal": pp.tube_shape(lay["tube_distal_mm"], p.tube_od_mm, p.tube_id_mm),
        "pin_short": pp.pin_shape(brg.d_mm, lay["pin_short_mm"]),
        "pin_long": pp.pin_shape(brg.d_mm, lay["pin_long_mm"]),
        "crankshaft": pp.crankshaft_shape(
            l6,
            brg.d_mm,
            lay["web_width_mm"],
            p.crank_thickness_mm,
            lay["journal_up_mm"],
            lay["crank_pin_down_mm"],
        ),
        "knob": pp.knob_shape(tp.knob_diameter_mm, p.knob_height_mm, brg.d_mm, KNOB_BORE_DEPTH_MM),
        "post": pp.post_shape(
            p.post_diameter_mm, lay["bridge_bottom_z_mm"], POST_SCREW_TAP_MM, 10.0
        ),
        "motor_mount": pm.motor_mount_shape(mot, p.motor_mount_thickness_mm),
    }
    B = [(-a / 2, 0.0), (a / 2, 0.0)]
    mount_holes = [(bx + x, by + y, 3.3) for bx, by in B for x, y in pm.mount_hole_xy_mm(mot)]
    openings = [(bx, by, mot.pilot_diameter_mm + 2 * pp.OPENING_MARGIN_MM) for bx, by in B]
    post_holes = [(x, y, POST_SCREW_CLEAR_MM) for x, y in lay["posts_xy_mm"]]
    S["base_plate"] = pp.plate_shape(
        lay["base_plate_x_mm"],
        lay["base_plate_y_mm"],
        p.plate_thickness_mm,
        openings + mount_holes + post_holes,
    )
    S["bridge_plate"] = pp.plate_shape(
        lay["bridge_x_mm"],
        lay["bridge_y_mm"],
        p.plate_thickness_mm,
        openings + mount_holes + post_holes,
    )
    detailed = fidelity == "fabrication"
    S["bearing"] = (
        joints.bearing_shape(p.bearing, detailed)
        if detailed
        else pp.ring_solid(brg.d_mm / 2, brg.D_mm / 2, brg.B_mm)
    )
    S["motor"] = pm.motor_housing_shape(mot)

    _step(progress, "bodies and mass properties", 2, total)
    # parts of each moving body in its link frame (origin first joint, x to the second, z layer centre)
    Lc, s = p.clevis_length_mm, p.socket_depth_mm

    def link_parts(kind0: str, kind1: str, length: float, tube: str, extra=()):
        items = [
            (kind0, np.eye(4)),
            (tube, _rz(0.0, Lc - s)),
            (kind1, _rz(math.pi, length)),
        ]
        return items + list(extra)

    bz = [(-h / 2), (h / 2 - brg.B_mm)]
    brg_at = lambda x: [("bearing", _rz(0.0, x, 0.0, z)) for z in bz]  # noqa: E731
    bodies_parts = {
        "proximal_left": link_parts(
            "clevis_hub",
            "clevis_pin",
            l2,
            "tube_proximal",
            [("pin_short", _rz(0.0, l2, 0.0, -h / 2))],
        ),
        "proximal_right": link_parts(
            "clevis_hub",
            "clevis_pin",
            l2,
            "tube_proximal",
            [("pin_long", _rz(0.0, l2, 0.0, -h / 2))],
        ),
        "distal": link_parts(
            "clevis_bearing", "clevis_bearing", l3, "tube_distal", brg_at(0.0) + brg_at(l3)
        ),
        "crankshaft": [
            ("crankshaft", np.eye(4)),
            ("knob", _rz(0.0, 0.0, 0.0, lay["knob_bottom_z_mm"] - lay["web_z_mm"])),
        ],
    }
    density = {
        "clevis_hub": mat["clevis_material"],
        "clevis_pin": mat["clevis_material"],
        "clevis_bearing": mat["clevis_material"],
        "tube_proximal": mat["tube_material"],
        "tube_distal": mat["tube_material"],
        "pin_short": mat["pin_material"],
        "pin_long": mat["pin_material"],
        "crankshaft": mat["crank_material"],
        "knob": mat["knob_material"],
        "post": mat["plate_material"],
        "motor_mount": mat["plate_material"],
        "base_plate": mat["plate_material"],
        "bridge_plate": mat["plate_material"],
    }
    unit = {}
    for name, shape in S.items():
        if name in density:
            unit[name] = _props(shape, density[name].density_kg_m3)
    # bearing: catalogue mass, spread as its (ring or detailed) solid
    ring = pp.ring_solid(brg.d_mm / 2, brg.D_mm / 2, brg.B_mm)
    rp = _props(ring, 1000.0)
    unit["bearing"] = rp.scaled(brg.mass_kg / rp.mass_kg)
    unit["motor"] = MassProps(mot.mass_kg, np.zeros(3), np.eye(3) * 1e-9)

    def body_props(name: str, upper: bool) -> MassProps:
        F = _flip() if upper else np.eye(4)
        parts = []
        for kind, tf in bodies_parts[name]:
            mp = unit[kind]
            T = F @ tf
            parts.append(mp.transformed(T[:3, :3], T[:3, 3] * 1e-3))
        return combine(parts)

    bodies = {}
    for grp, upper in (("crank", False), ("knob", True)):
        for name in ("proximal_left", "proximal_right", "distal"):
            bodies[f"{grp}_{name}"] = body_props(name, upper)
    bodies["crankshaft"] = body_props("crankshaft", False)
    rotor = mot.rotor_inertia_kg_m2

    def fbm(grp):
        d = _planar(bodies[f"{grp}_distal"])
        return fb5.FiveBarMass(
            _planar(bodies[f"{grp}_proximal_left"]),
            _planar(bodies[f"{grp}_proximal_right"]),
            d,
            d,
            rotor,
        )

    cs = bodies["crankshaft"]
    twin_mass = tw.TwinMass(
        fbm("knob"),
        fbm("crank"),
        fb5.LinkMass(
            float(cs.mass_kg),
            (float(cs.com_m[0]), float(cs.com_m[1])),
            float(cs.inertia_com_kg_m2[2, 2]),
        ),
    )
    home = np.array(
        [*design.workspace["home_mm"], math.radians(design.workspace["home_theta_deg"])]
    )
    eff = tw.effective_mass_home(tp, home, twin_mass)
    eff_no_rotor = tw.effective_mass_home(
        tp,
        home,
        tw.TwinMass(
            fb5.FiveBarMass(
                *[
                    getattr(twin_mass.knob, f)
                    for f in ("proximal_left", "proximal_right", "distal_left", "distal_right")
                ],
                0.0,
            ),
            fb5.FiveBarMass(
                *[
                    getattr(twin_mass.crank, f)
                    for f in ("proximal_left", "proximal_right", "distal_left", "distal_right")
                ],
                0.0,
            ),
            twin_mass.crankshaft,
        ),
    )

    _step(progress, "part files", 3, total)
    listed = [
        ("clevis_hub", True, False, "clevis at the motor shaft (set screw)", "CNC milled", 4),
        ("clevis_pin", True, False, "clevis at the elbow, pin pressed in", "CNC milled", 4),
        ("clevis_bearing", True, False, "clevis with two ball bearings", "CNC milled", 8),
        (
            "tube_proximal",
            True,
            False,
            f"tube {p.tube_od_mm:g}/{p.tube_id_mm:g} mm, proximal",
            "cut to length",
            4,
        ),
        (
            "tube_distal",
            True,
            False,
            f"tube {p.tube_od_mm:g}/{p.tube_id_mm:g} mm, distal",
            "cut to length",
            4,
        ),
        ("pin_short", True, False, "elbow pin, left arms", "ground dowel, cut", 2),
        ("pin_long", True, False, "elbow pin, right arms", "ground dowel, cut", 2),
        ("crankshaft", True, False, f"crankshaft, l6 = {l6:g} mm (eq 7)", "turned + milled", 1),
        ("knob", True, False, f"knob, diameter {tp.knob_diameter_mm:g} mm (l5)", "turned", 1),
        ("post", True, False, "bridge post", "turned", 4),
        ("motor_mount", True, True, "motor mount plate", "waterjet/laser plate", 4),
        ("base_plate", True, True, "base plate", "waterjet/laser plate", 1),
        ("bridge_plate", True, True, "bridge plate (upper motors)", "waterjet/laser plate", 1),
        ("bearing", False, False, f"ball bearing {brg.designation} ({p.bearing})", "bought", 16),
        ("motor", False, False, mot.description, "bought", 4),
    ]
    files = []
    bom = []
    for name, made, plate, desc, process, qty in listed:
        files += [
            str(x.name) for x in export_part(S[name], name, out_dir, formats, plate=plate, stl=made)
        ]
        material = {"bearing": "steel-1018", "motor": "catalogue"}.get(name) or density[name].name
        bom.append(
            {
                "part": name,
                "description": desc,
                "material": material,
                "quantity": qty,
                "made_or_bought": "made" if made else "bought",
                "process": process,
                "mass_g": unit[name].mass_kg * 1e3,
            }
        )
    write_bom(bom, out_dir)
    files.append("bom.csv")

    _step(progress, "assembly at home", 4, total)
    ik = tw.ik(tp, home[None, :])
    items = []

    def color(kind):
        m = {"bearing": (0.6, 0.6, 0.65), "motor": (0.2, 0.2, 0.25)}
        if kind in m:
            return m[kind]
        return density[kind].color_rgb

    for grp, fp, zs, upper in (
        ("crank", ik.crank, lay["lower_layers_z_mm"], False),
        ("knob", ik.knob, lay["upper_layers_z_mm"], True),
    ):
        F = _flip() if upper else np.eye(4)
        C = [fp.C_left_mm[0], fp.C_right_mm[0]]
        E = fp.E_mm[0]
        for i, side in enumerate(("left", "right")):
            q = float(fp.q_rad[0, i])
            Tp = _rz(q, B[i][0], B[i][1], zs[0]) @ F
            for kind, tf in bodies_parts[f"proximal_{side}"]:
                items.append(
                    (f"{grp}_proximal_{side}_{kind}", placed(S[kind], Tp @ tf), color(kind))
                )
            psi = math.atan2(E[1] - C[i][1], E[0] - C[i][0])
            Td = _rz(psi, C[i][0], C[i][1], zs[1 + i]) @ F
            for k, (kind, tf) in enumerate(bodies_parts["distal"]):
                items.append(
                    (f"{grp}_distal_{side}_{kind}_{k}", placed(S[kind], Td @ tf), color(kind))
                )
    th = float(home[2])
    Tc = _rz(th, home[0], home[1], lay["web_z_mm"])
    for kind, tf in bodies_parts["crankshaft"]:
        items.append((kind, placed(S[kind], Tc @ tf), color(kind)))
    pt = p.plate_thickness_mm
    zb = lay["bridge_bottom_z_mm"]
    items.append(("base_plate", placed(S["base_plate"], _rz(0.0, 0, 0, -pt)), color("base_plate")))
    items.append(
        ("bridge_plate", placed(S["bridge_plate"], _rz(0.0, 0, 0, zb)), color("bridge_plate"))
    )
    for k, (x, y) in enumerate(lay["posts_xy_mm"]):
        items.append((f"post_{k}", placed(S["post"], _rz(0.0, x, y, 0.0)), color("post")))
    mt = p.motor_mount_thickness_mm
    for i, (bx, by) in enumerate(B):
        items.append(
            (
                f"crank_motor_mount_{i}",
                placed(S["motor_mount"], _rz(0.0, bx, by, -pt - mt)),
                color("motor_mount"),
            )
        )
        items.append(
            (f"crank_motor_{i}", placed(S["motor"], _rz(0.0, bx, by, -pt - mt)), color("motor"))
        )
        items.append(
            (
                f"knob_motor_mount_{i}",
                placed(S["motor_mount"], _rz(0.0, bx, by, zb + pt)),
                color("motor_mount"),
            )
        )
        items.append(
            (
                f"knob_motor_{i}",
                placed(S["motor"], _rz(0.0, bx, by, zb + pt + mt) @ _flip()),
                color("motor"),
            )
        )
    if "step" in formats:
        export_assembly_step(items, out_dir / "twin_pantograph_assembly.step", "twin_pantograph")
        files.append("twin_pantograph_assembly.step")

    files += _write_sim(design, out_dir, formats, bodies, bodies_parts, lay, home, ik, mot,
                        {n for n, made, *_ in listed if made}, color)

    _step(progress, "report", 6, total)
    g = design.gii()
    moving_g = sum(bodies[k].mass_kg for k in bodies) * 1e3
    report = {
        "design": design.name,
        "family": design.family,
        "fidelity": fidelity,
        "gii": {
            "gii": g.gii,
            "sigma_min": g.sigma_min,
            "sigma_max": g.sigma_max,
            "sigma_min_at": g.sigma_min_at.tolist(),
            "sigma_max_at": g.sigma_max_at.tolist(),
        },
        "crank_mm": l6,
        "layout_mm": lay,
        "clearances_mm": clr,
        "bodies": {k: v.to_dict() for k, v in bodies.items()},
        "moving_mass_g": moving_g,
        "motor": {
            "key": mot.key,
            "rotor_inertia_g_cm2": mot.rotor_inertia_g_cm2,
            "source": mot.source,
        },
        "home": {
            "x_mm": float(home[0]),
            "y_mm": float(home[1]),
            "theta_deg": float(math.degrees(home[2])),
        },
        "effective_mass_home": eff,
        "effective_mass_home_without_rotors": eff_no_rotor,
        "paper_table1": PAPER_TABLE1,
        "effective_mass_note": (
            "diag = mass felt moving one task axis with the others held; apparent = 1/(M^-1)_ii, "
            "the others free. Ours differs from Table 1 because the paper's values are measured on "
            "the built device (closed-loop identification, includes the real motors, encoders, "
            "cabling, fasteners and friction) and its link lengths, tube sizes and motors are not "
            "published; here the moving parts are the solids above with catalogue bearing and rotor data."
        ),
        "files": sorted(files),
        "bom": bom,
    }
    _step(progress, "done", total, total)
    return report
