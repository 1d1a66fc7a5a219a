"""Build a pantograph-family device: the plain 5-bar or the twin-pantograph haptic mouse.

Contract: see :mod:`cad.pipeline` (``build(design, out_dir, formats, *, fidelity,
allow_interference, progress, phi1_deg) -> report dict``; ``phi1_deg`` must be None, the
family has no crank: refused at load time by :func:`check_options`). Isotropy paper §3
(Fig. 2, the plain 5-bar) and §4.1 (Fig. 1, Table 1, the twin pantograph).

Pipeline: layout (heights, plates; numpy) -> analytic clearances over the workspace ->
one list of part instances (:func:`assembly`; body, kind, placement) -> mass properties
per body from the solids -> effective mass -> every-pair solid check at the home pose ->
the common outputs of :mod:`cad.pipeline.family` (``parts/``, ``assembly.step``,
``bom.csv``, ``preview.png``, ``report.md``).

Arrangement (our reading of Fig. 1; world frame = the kinematic base frame, z up,
z = 0 on the base plate's top face, the bench plane at ``bench_z_mm`` below it):

* the base plate stands on four leg standoffs (cap screws from above) tall enough that
  the motors under it clear the bench by :data:`cad.parts.base.LEG_GROUND_CLEARANCE_MM`;
* the lower 5-bar (the *crank* pantograph of the mouse, the only one of the plain
  5-bar) has its actuated joints at B1 = (-a/2, 0), B2 = (+a/2, 0): proximal links in
  layer L0, left distal L1, right distal L2; its motors hang under the base plate on
  motor-mount plates (cap screws into the base plate), shafts up into the hub clevises;
* plain 5-bar: the end effector E is a handle pin running in both distal clevises'
  bearings, with a knob above L2;
* twin pantograph: the crankshaft web lies above L2; the crank pin hangs down into L2
  and L1, the main journal rises through the upper group to the knob. The *knob*
  pantograph (drives the main journal) is the upper group, mirrored: right distal U2,
  left distal U1, proximal links U0 on top; its motors stand on a bridge plate above
  U0 (shafts down), the bridge carried by four posts behind the base line (cap screws
  into both ends of each post);
* every passive joint: a steel pin pressed into the proximal clevis, two ball bearings
  in the distal clevis; the journals run in the distal clevises' bearings the same way.

Body frames are planar (rotation about z, z = 0 on the base plate's top): a moving link's
origin at its first joint, x towards its second; the upper group's parts are turned over
inside their body (``tf_body_part`` carries the flip and the layer height).

Clearances between moving parts are checked analytically (capsules per layer, numpy)
over the design's workspace samples (x 16 crank angles for the mouse), before any solid
is built; the solids are then checked pair by pair at the home pose.

Report keys: ``gii``, ``layout_mm``, ``clearances_mm``, ``bodies`` (mass properties of
each moving body from the exact B-rep, in its link frame), ``effective_mass_home``
(mouse: diag and apparent readings beside ``paper_table1``; 5-bar: the 2x2 mass matrix
at the workspace centre), ``interference`` (every pair of solids at home),
``bench_z_mm`` / ``lowest_z_mm``, ``bom``, ``fits`` (ISO 286 fits per part,
:mod:`cad.data.fits`), ``files``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from cad.errors import DesignError, InterferenceError

#: Source the output depends on (build cache key).
CODE_DEPS = (
    "pipeline",
    "families",
    "datasheet",
    "firmware",  # --formats firmware (cad/firmware)
    "report",  # report.html, the stroke GIF and render (cad/report)
    "parts",
    "assembly",
    "export",
    "massprops",
    "kinematics",
    "isotropy",
    "design",
    "io",
    "data",
    "errors.py",
    "dynamics",  # eq (25) of the firmware's wall
    "tolerances.py",
)
#: Families this module builds (others of cad.design.pantograph are refused at load).
FAMILIES = ("pantograph", "twin-pantograph")

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
#: Posts: offset along x from each actuated joint (mm), and their screws.
POST_DX_MM = 22.0
POST_SCREW = "M4-0.7"
POST_TAP_DEPTH_MM = 10.0
#: Depth of the journal / handle pin in the knob's bore (mm).
KNOB_BORE_DEPTH_MM = 15.0
#: Knob diameter of the plain 5-bar's handle (mm); the mouse's is mechanism.knob_diameter_mm.
PLAIN_KNOB_DIAMETER_MM = 20.0
#: Smallest thread engagement of a cap screw in a tapped hole (x thread diameter):
#: 1.5 d in aluminium.
MIN_ENGAGEMENT_D = 1.5



#: Final checks of assembly.md (cad.assembly.steps).
ASSEMBLY_CHECKS = (
    "each motor shaft turned by hand moves the linkage over the whole workspace square "
    "(report.md) with no binding and no contact between links",
    "the clevis set screws are tight (no slip of a hub clevis on its shaft flat)",
)

def check_options(design, fidelity: str, phi1_deg, formats=frozenset()) -> None:
    """Refuse what this builder cannot do, before any CAD import (DesignError)."""
    if set(formats) & {"mjcf", "urdf"} and design.family != "twin-pantograph":
        raise DesignError(
            "--formats",
            f"mjcf/urdf export is available for four-bar and twin-pantograph designs, "
            f"not {design.family!r}",
        )
    if design.family not in FAMILIES:
        from cad.cli.families import refusal

        raise DesignError("mechanism.family", refusal("build", design.family)
                          + " (the haptic pen has kinematics and GII only, no parts)")
    if phi1_deg is not None:
        raise DesignError(
            "--phi1-deg",
            f"a {design.family} has no crank angle, got {phi1_deg!r}; the assembly is "
            "exported at workspace.home_mm",
        )
    screw_plan(design)  # a stack no catalog screw fastens: named before any CAD
    set_screw_plan(design)  # a clevis wall no set screw fits: named before any CAD


def _step(progress, text: str, done: int, total: int) -> None:
    if progress is not None:
        progress(text, done, total)


def _twin(design) -> bool:
    return design.family == "twin-pantograph"


def _lower_five_bar(design):
    return design.mechanism.crank if _twin(design) else design.mechanism


def home_xy_mm(design) -> np.ndarray:
    """End-effector (mouse: main journal) position of the exported pose (mm)."""
    ws = design.workspace
    return np.asarray(ws.get("home_mm", ws["center_mm"]), dtype=float)


# ----------------------------------------------------------------------------- layout
def screw_plan(design) -> dict[str, dict]:
    """Every screw group of the device sized from its stack, before any CAD
    (:func:`cad.assembly.fasteners.size_cap_screw`: catalog ISO 4762 length, engagement
    between 1.5 d in aluminium -- the maker's minimum in the motor face -- and the hole's
    full-thread depth). Group -> size, clamp_mm, length_mm, engagement_mm, depth_mm,
    min_engagement_mm, joint, clamps (parts clamped, head side first). DesignError naming
    the joint when no catalog length fits."""
    from cad.assembly import fasteners as fs
    from cad.data.catalog import get_motor
    from cad.parts import base
    from cad.parts import motor as pm

    p = design.parts
    m = get_motor(p.motor)
    pt, mt = p.plate_thickness_mm, p.motor_mount_thickness_mm
    face = min(m.bolt_thread_depth_mm, fs.MIN_ENGAGEMENT_BOUGHT_MM)
    groups = {
        "leg": (base.LEG_SCREW, pt, base.STANDOFF_TAP_DEPTH_MM - fs.TAP_LEADOUT_MM, None,
                "leg to base plate", "parts.plate_thickness_mm", ("base_plate",)),
        "mount": (pm.MOUNT_SCREW, mt, pt, None, "motor mount plate to base/bridge plate",
                  "parts.motor_mount_thickness_mm", ("motor_mount",)),
        "motor": (m.bolt_size, mt, m.bolt_thread_depth_mm, face, "motor face to mount plate",
                  "parts.motor_mount_thickness_mm", ("motor_mount",)),
    }
    if _twin(design):
        groups["post"] = (POST_SCREW, pt, POST_TAP_DEPTH_MM - fs.TAP_LEADOUT_MM, None,
                          "bridge post to base/bridge plate", "parts.plate_thickness_mm",
                          ("plate",))
    out = {}
    for g, (size, clamp, depth, need, joint, field, clamps) in groups.items():
        hole = fs.alu_hole(g, g, size, depth)
        if need is not None:
            hole = fs.TappedHole(g, g, size, depth, need)
        L, e = fs.size_cap_screw(size, clamp, hole, joint, field)
        out[g] = {"size": size, "clamp_mm": clamp, "length_mm": L, "engagement_mm": e,
                  "depth_mm": depth, "min_engagement_mm": hole.min_engagement_mm,
                  "joint": joint, "clamps": clamps}
    return out


#: ISO 4026 set screws that may lock a hub clevis on its motor shaft, largest first tried.
SET_SCREW_SIZES = ("M3-0.5", "M2.5-0.45", "M2-0.4")


def set_screw_plan(design) -> dict:
    """The set screw locking each hub clevis on its motor shaft, before any CAD: radial, at
    the clevis mid-plane, tapped through the round end's wall (``clevis_width_mm / 2`` minus
    the shaft radius) with its flat point touching the shaft and its end inside the clevis
    outer surface (:func:`cad.assembly.fasteners.size_set_screw`: the largest of
    :data:`SET_SCREW_SIZES` with a bd_warehouse ISO 4026 length 1.5 d <= L <= full-thread
    depth). Returns size, length_mm, engagement_mm (= L), depth_mm, wall_mm, shaft_radius_mm,
    min_engagement_mm. DesignError naming ``parts.clevis_width_mm`` when no size fits,
    ``parts.clevis_height_mm`` when the shaft ends short of the screw."""
    from cad.assembly import fasteners as fs
    from cad.data.catalog import get_motor, thread_diameter_mm

    p = design.parts
    m = get_motor(p.motor)
    r_in, r_out = m.shaft_diameter_mm / 2, p.clevis_width_mm / 2
    size, L, depth = fs.size_set_screw(r_in, r_out, SET_SCREW_SIZES,
                                       "hub clevis set screw onto the motor shaft",
                                       "parts.clevis_width_mm")
    d = thread_diameter_mm(size)
    # shaft length inside a hub clevis (the same for the crank and knob pantographs)
    engaged = m.shaft_length_mm - p.plate_thickness_mm - p.motor_mount_thickness_mm - p.layer_gap_mm
    if engaged - p.clevis_height_mm / 2 < d / 2:
        raise DesignError(
            "parts.clevis_height_mm",
            f"the {p.motor} shaft ends {engaged:g} mm into the {p.clevis_height_mm:g} mm hub "
            f"clevis, short of its {size.split('-')[0]} set screw at mid-height",
        )
    return {"size": size, "length_mm": L, "engagement_mm": L, "depth_mm": depth,
            "wall_mm": r_out - r_in, "shaft_radius_mm": r_in,
            "min_engagement_mm": fs.MIN_ENGAGEMENT_ALU_D * d}


def layout(design) -> dict:
    """Heights and plate extents of the assembly (mm), from the design only (no CAD)."""
    from cad.data.catalog import get_bearing, get_motor
    from cad.parts import base
    from cad.parts.motor import mount_side_mm

    twin = _twin(design)
    p = design.parts
    a = design.params["base_mm"]
    l2 = design.params["proximal_mm"]
    l6 = design.mechanism.crank_mm if twin else 0.0
    b = get_bearing(p.bearing)
    m = get_motor(p.motor)
    h, g, t = p.clevis_height_mm, p.layer_gap_mm, p.crank_thickness_mm
    pitch = h + g
    L0 = g + h / 2
    L = [L0, L0 + pitch, L0 + 2 * pitch]
    ms = mount_side_mm(m)
    ws = design.workspace
    cx, cy = ws["center_mm"]
    half = ws["side_mm"] / 2
    reach_x = a / 2 + l2 + p.clevis_width_mm
    margin = base.LEG_INSET_MM + base.LEG_DIAMETER_MM / 2 + 4.0
    post_y = -(ms / 2 + p.post_diameter_mm / 2 + 8.0)
    y_back = (post_y - p.post_diameter_mm / 2) if twin else -ms / 2
    base_x = (
        min(-reach_x, cx - half - l6 - 20, -a / 2 - ms / 2) - margin,
        max(reach_x, cx + half + l6 + 20, a / 2 + ms / 2) + margin,
    )
    base_y = (y_back - margin, cy + half + l6 + p.clevis_width_mm + 20 + margin)
    leg_h = p.motor_mount_thickness_mm + m.body_length_mm + base.LEG_GROUND_CLEARANCE_MM
    pt, mt = p.plate_thickness_mm, p.motor_mount_thickness_mm
    shaft_tip = -pt - mt + m.shaft_length_mm
    out = {
        "layer_pitch_mm": pitch,
        "lower_layers_z_mm": L,
        "base_plate_x_mm": base_x,
        "base_plate_y_mm": base_y,
        "leg_height_mm": leg_h,
        "bench_z_mm": -pt - leg_h,
        "journal_d_mm": b.d_mm,
        "pin_short_mm": 2 * h + g,
        "pin_long_mm": 3 * h + 2 * g,
        "tube_proximal_mm": l2 - 2 * (p.clevis_length_mm - p.socket_depth_mm),
        "tube_distal_mm": design.params["distal_mm"] - 2 * (p.clevis_length_mm - p.socket_depth_mm),
        "lower_shaft_engagement_mm": shaft_tip - (L[0] - h / 2),
        "motor_mount_side_mm": ms,
        "screws": screw_plan(design),
        "set_screw": set_screw_plan(design),
    }
    if not twin:
        knob_z = L[2] + h / 2 + g
        out.update(
            knob_bottom_z_mm=knob_z,
            handle_pin_z_mm=L[1] - h / 2,
            handle_pin_mm=knob_z + KNOB_BORE_DEPTH_MM - (L[1] - h / 2),
        )
        return out
    zW = L[2] + h / 2 + g + t / 2
    U2 = zW + t / 2 + g + h / 2
    U = [U2 + 2 * pitch, U2 + pitch, U2]  # U0 (proximal, top), U1, U2
    z_bridge = U[0] + h / 2 + g
    posts = [(sx * a / 2 + dx, post_y) for sx in (-1, 1) for dx in (-POST_DX_MM, POST_DX_MM)]
    out.update(
        web_z_mm=zW,
        upper_layers_z_mm=U,
        bridge_bottom_z_mm=z_bridge,
        knob_bottom_z_mm=U[0] + h / 2 + g,
        posts_xy_mm=posts,
        bridge_x_mm=(
            min(x for x, _ in posts) - p.post_diameter_mm,
            max(x for x, _ in posts) + p.post_diameter_mm,
        ),
        bridge_y_mm=(post_y - p.post_diameter_mm, ms / 2 + 5),
        journal_up_mm=(U[0] + h / 2 + g + KNOB_BORE_DEPTH_MM) - (zW + t / 2),
        crank_pin_down_mm=(zW - t / 2) - (L[1] - h / 2),
        web_width_mm=max(b.d_mm + 6.0, 10.0),
        upper_shaft_engagement_mm=(U[0] + h / 2) - (z_bridge + pt + mt - m.shaft_length_mm),
    )
    return out


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


def _poses(design):
    """Workspace samples (N, 2 or 3) and the five-bar poses of each group there."""
    from cad.kinematics import fivebar as fb5
    from cad.kinematics import twin_pantograph as tw

    ws = design.workspace
    if _twin(design):
        X = tw.workspace_grid(
            ws["center_mm"], ws["side_mm"], max(ws["grid"], 5), CLEARANCE_THETA_SAMPLES
        )
        pose = tw.ik(design.mechanism, X)
        names = tw.STATUS_NAMES
        groups = {"crank": pose.crank, "knob": pose.knob}
    else:
        X = design.workspace_points()
        pose = fb5.ik(design.mechanism, X)
        names = fb5.STATUS_NAMES
        groups = {"lower": pose}
    if np.any(pose.status != 0):
        i = int(np.flatnonzero(pose.status != 0)[0])
        raise InterferenceError(
            f"workspace pose {X[i].round(3).tolist()} is {names[int(pose.status[i])]}"
        )
    return X, groups


def clearances(design, lay: dict | None = None) -> dict:
    """Smallest gaps (mm) between parts sharing a layer over the workspace (x full turn).

    Capsules (segment + radius) per layer: proximal and distal links (radius =
    clevis_width / 2), pins crossing a layer they are not part of, the main journal
    crossing U0, the posts crossing every layer, the leg screw heads standing in L0.
    Returns {check: {"gap_mm", "at": [x_mm, y_mm(, theta_deg)]}} and the overall minimum.
    """
    from cad.data.catalog import get_bearing, get_cap_screw
    from cad.parts import base

    lay = lay or layout(design)
    p = design.parts
    fb = _lower_five_bar(design)
    X, groups = _poses(design)
    rc = p.clevis_width_mm / 2
    rpin = get_bearing(p.bearing).d_mm / 2
    rpost = p.post_diameter_mm / 2
    B1 = np.array(fb.base_left_mm)
    B2 = np.array(fb.base_right_mm)
    checks: dict[str, np.ndarray] = {}

    def worst(key: str, d: np.ndarray) -> None:
        checks[key] = np.minimum(checks[key], d) if key in checks else d

    head = get_cap_screw(base.LEG_SCREW, "parts").dk_mm / 2
    for x, y in _leg_xy(lay):
        leg = np.array([x, y])
        fp = groups["crank" if _twin(design) else "lower"]
        for C, B in ((fp.C_left_mm, B1), (fp.C_right_mm, B2)):
            worst("L0 proximal links vs leg screw heads", _pt_seg(leg, B, C) - rc - head)
    for grp, fp in groups.items():
        C1, C2, E = fp.C_left_mm, fp.C_right_mm, fp.E_mm
        checks[f"{grp}: proximal L vs proximal R"] = seg_seg_distance(B1, C1, B2, C2) - 2 * rc
        checks[f"{grp}: left distal vs right elbow pin"] = _pt_seg(C2, C1, E) - rc - rpin
        for x, y in lay.get("posts_xy_mm", ()):
            post = np.array([x, y])
            for name, (s0, s1) in {
                "proximal L": (B1, C1),
                "proximal R": (B2, C2),
                "distal L": (C1, E),
                "distal R": (C2, E),
            }.items():
                worst(f"{grp}: {name} vs posts", _pt_seg(post, s0, s1) - rc - rpost)
    if _twin(design):
        kn = groups["knob"]
        Ek = kn.E_mm
        checks["knob: main journal vs proximal links (U0)"] = (
            np.minimum(_pt_seg(Ek, B1, kn.C_left_mm), _pt_seg(Ek, B2, kn.C_right_mm)) - rc - rpin
        )
        # knob (above U0) against the bridge plate, in plan
        bx, by = lay["bridge_x_mm"], lay["bridge_y_mm"]
        dx = np.maximum(np.maximum(bx[0] - Ek[:, 0], Ek[:, 0] - bx[1]), 0)
        dy = np.maximum(np.maximum(by[0] - Ek[:, 1], Ek[:, 1] - by[1]), 0)
        checks["knob vs bridge plate (plan)"] = (
            np.hypot(dx, dy) - design.mechanism.knob_diameter_mm / 2
        )
    out = {}
    for k, v in checks.items():
        i = int(np.argmin(v))
        at = [float(X[i, 0]), float(X[i, 1])]
        if X.shape[1] > 2:
            at.append(float(np.degrees(X[i, 2])))
        out[k] = {"gap_mm": float(v[i]), "at": at}
    worst_key = min(out, key=lambda k: out[k]["gap_mm"])
    return {
        "checks": out,
        "min_gap_mm": out[worst_key]["gap_mm"],
        "worst": worst_key,
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


def _leg_xy(lay: dict) -> list[tuple[float, float]]:
    from cad.parts import base

    (x0, x1), (y0, y1) = lay["base_plate_x_mm"], lay["base_plate_y_mm"]
    return base.leg_xy_mm((x0, y0, x1, y1))


def _planar(mp):
    """MassProps (3-D, link frame) -> LinkMass (mass, COM xy, Izz about the COM)."""
    from cad.kinematics.fivebar import LinkMass

    return LinkMass(
        float(mp.mass_kg),
        (float(mp.com_m[0]), float(mp.com_m[1])),
        float(mp.inertia_com_kg_m2[2, 2]),
    )


# -------------------------------------------------------------------------- assembly
def _kinds(design, lay: dict, fidelity: str) -> dict:
    """Every distinct part (:class:`cad.parts.PartKind`) of the design, by name."""
    from cad.data.catalog import (
        FASTENER_MATERIAL,
        clearance_hole_mm,
        get_bearing,
        get_cap_screw,
        get_motor,
        tap_drill_mm,
    )
    from cad.data.fits import fit
    from cad.parts import PartKind, base, joints
    from cad.parts import motor as pm
    from cad.parts import pantograph as pp

    p = design.parts
    twin = _twin(design)
    brg = get_bearing(p.bearing)
    mot = get_motor(p.motor)
    fb = _lower_five_bar(design)
    B = [fb.base_left_mm, fb.base_right_mm]
    K: dict[str, PartKind] = {}

    def add(name, shape, material, made, description, process, **kw):
        K[name] = PartKind(
            name=name,
            shape=shape,
            material=material,
            made=made,
            description=description,
            process=process,
            **kw,
        )

    cl = dict(
        length_mm=p.clevis_length_mm,
        width_mm=p.clevis_width_mm,
        height_mm=p.clevis_height_mm,
        socket_depth_mm=p.socket_depth_mm,
        tube_od_mm=p.tube_od_mm,
    )
    cm, tm = p.clevis_material, p.tube_material
    ss = lay["set_screw"]
    sz = ss["size"].split("-")[0]
    add(
        "clevis_hub",
        pp.clevis_shape("hub", bore_mm=mot.shaft_diameter_mm,
                        set_screw_drill_mm=tap_drill_mm(ss["size"]), **cl),
        cm,
        True,
        f"clevis on the motor shaft ({sz} set screw)",
        f"CNC milled; ream shaft bore; tap {sz} x1 (radial)",
        fits=(fit("hub shaft bore", mot.shaft_diameter_mm, "shaft bore"),),
    )
    add(
        "set_screw",
        pm.set_screw_shape(ss["length_mm"], ss["size"]),
        FASTENER_MATERIAL,
        False,
        f"set screw ISO 4026 {ss['size']} x {ss['length_mm']:g} (locks the clevis on the "
        "motor shaft)",
        "bought",
    )
    add(
        "clevis_pin",
        pp.clevis_shape("pin", bore_mm=brg.d_mm, **cl),
        cm,
        True,
        "clevis at the elbow, pin pressed in",
        "CNC milled; ream pin bore",
        fits=(fit("pin bore", brg.d_mm),),
    )
    add(
        "clevis_bearing",
        pp.clevis_shape("bearing", bore_mm=brg.D_mm, **cl),
        cm,
        True,
        "clevis with two ball bearings",
        "CNC milled; bore bearing seat (both bearings)",
        fits=(fit("bearing seat", brg.D_mm),),
    )
    for which in ("proximal", "distal"):
        L = lay[f"tube_{which}_mm"]
        add(
            f"tube_{which}",
            pp.tube_shape(L, p.tube_od_mm, p.tube_id_mm),
            tm,
            True,
            f"tube {p.tube_od_mm:g}/{p.tube_id_mm:g} x {L:g} mm, {which} links",
            "cut to length, bonded",
        )
    add(
        "pin_short",
        pp.pin_shape(brg.d_mm, lay["pin_short_mm"]),
        p.pin_material,
        True,
        f"elbow pin d{brg.d_mm:g} x {lay['pin_short_mm']:g}, left arm",
        "ground dowel, cut",
        fits=(fit("pin", brg.d_mm),),
    )
    add(
        "pin_long",
        pp.pin_shape(brg.d_mm, lay["pin_long_mm"]),
        p.pin_material,
        True,
        f"elbow pin d{brg.d_mm:g} x {lay['pin_long_mm']:g}, right arm",
        "ground dowel, cut",
        fits=(fit("pin", brg.d_mm),),
    )
    detailed = fidelity == "fabrication"
    add(
        "bearing",
        joints.bearing_shape(p.bearing, detailed),
        "steel-1018",
        False,
        f"ball bearing {brg.designation} ({p.bearing})",
        "bought",
        mass_kg=brg.mass_kg,
        inertia_model="ring",
        ring_mm=(brg.d_mm / 2, brg.D_mm / 2, brg.B_mm),
    )
    add(
        "motor",
        pm.motor_housing_shape(mot),
        "steel-1018",
        False,
        mot.description,
        f"bought; face tapped {mot.bolt_size.split('-')[0]} x{mot.bolt_count}; with its "
        "shaft (solid motor_shaft in assembly.step)",
        mass_kg=mot.mass_kg,
    )
    add(
        "motor_shaft",
        pm.motor_shaft_shape(mot),
        "steel-1018",
        False,
        "motor shaft",
        "part of the motor",
        inertia_model="none",
        listed=False,
    )
    add(
        "motor_mount",
        pm.motor_mount_shape(mot, p.motor_mount_thickness_mm),
        p.plate_material,
        True,
        "motor mount plate",
        "waterjet/laser plate; bore the pilot seat",
        plate=True,
        fits=(fit("pilot bore", mot.pilot_diameter_mm),),
    )
    pt = p.plate_thickness_mm
    mount_holes = [
        (bx + x, by + y, tap_drill_mm(pm.MOUNT_SCREW))
        for bx, by in B
        for x, y in pm.mount_hole_xy_mm(mot)
    ]
    # the motor face screws' heads sit in the plate's opening (four-bars do the same)
    head_d = get_cap_screw(mot.bolt_size, "parts.motor").dk_mm
    opening = max(mot.pilot_diameter_mm + 2 * pp.OPENING_MARGIN_MM,
                  mot.bolt_circle_mm + head_d + 2 * pp.OPENING_MARGIN_MM)
    openings = [(bx, by, opening) for bx, by in B]
    ms = pm.MOUNT_SCREW.split("-")[0]
    leg_holes = [(x, y, clearance_hole_mm(base.LEG_SCREW)) for x, y in _leg_xy(lay)]
    post_holes = [(x, y, clearance_hole_mm(POST_SCREW)) for x, y in lay.get("posts_xy_mm", ())]
    add(
        "base_plate",
        pp.plate_shape(
            lay["base_plate_x_mm"],
            lay["base_plate_y_mm"],
            pt,
            openings + mount_holes + post_holes + leg_holes,
        ),
        p.plate_material,
        True,
        "base plate (motors under, legs at the corners)",
        f"waterjet/laser plate; tap {ms} x{len(mount_holes)}",
        plate=True,
    )
    lh = lay["leg_height_mm"]
    add(
        "leg",
        base.leg_shape(lh),
        p.plate_material,
        True,
        f"leg standoff d{base.LEG_DIAMETER_MM:g} x {lh:g}, tapped {base.LEG_SCREW} both ends",
        f"turned; tap {base.LEG_SCREW.split('-')[0]} both ends",
    )
    steel = FASTENER_MATERIAL

    def screw(size, L):
        name = f"cap_screw_{size}x{L:g}"
        if name not in K:
            cs = get_cap_screw(size, "parts")
            add(
                name,
                joints.cap_screw_shape(size, L),
                steel,
                False,
                f"socket head cap screw ISO 4762 {size} x {L:g}",
                "bought",
                collision=(("self", joints.screw_envelope(cs.dk_mm, cs.k_mm, cs.d_mm, L)),),
            )
        return name

    for g, sp in lay["screws"].items():
        K[f"_{g}_screw"] = K[screw(sp["size"], sp["length_mm"])]
    kd = design.mechanism.knob_diameter_mm if twin else PLAIN_KNOB_DIAMETER_MM
    add(
        "knob",
        pp.knob_shape(kd, p.knob_height_mm, brg.d_mm, KNOB_BORE_DEPTH_MM),
        p.knob_material,
        True,
        f"knob, diameter {kd:g} mm",
        "turned; ream pin bore",
        fits=(fit("pin bore", brg.d_mm),),
    )
    if not twin:
        add(
            "handle_pin",
            pp.pin_shape(brg.d_mm, lay["handle_pin_mm"]),
            p.pin_material,
            True,
            f"handle pin d{brg.d_mm:g} x {lay['handle_pin_mm']:g} (end effector E)",
            "ground dowel, cut",
            fits=(fit("pin", brg.d_mm),),
        )
        return K
    l6 = design.mechanism.crank_mm
    add(
        "crankshaft",
        pp.crankshaft_shape(
            l6,
            brg.d_mm,
            lay["web_width_mm"],
            p.crank_thickness_mm,
            lay["journal_up_mm"],
            lay["crank_pin_down_mm"],
        ),
        p.crank_material,
        True,
        f"crankshaft, l6 = {l6:g} mm (eq 7)",
        "turned + milled; grind both journals",
        fits=(fit("journal", brg.d_mm),),
    )
    add(
        "post",
        pp.post_shape(
            p.post_diameter_mm,
            lay["bridge_bottom_z_mm"],
            tap_drill_mm(POST_SCREW),
            POST_TAP_DEPTH_MM,
        ),
        p.plate_material,
        True,
        f"bridge post d{p.post_diameter_mm:g}, tapped {POST_SCREW} both ends",
        f"turned; tap {POST_SCREW.split('-')[0]} both ends",
    )
    add(
        "bridge_plate",
        pp.plate_shape(
            lay["bridge_x_mm"], lay["bridge_y_mm"], pt, openings + mount_holes + post_holes
        ),
        p.plate_material,
        True,
        "bridge plate (upper motors)",
        f"waterjet/laser plate; tap {ms} x{len(mount_holes)}",
        plate=True,
    )
    return K


def _link_parts(which: str, side: str, K: dict, lay: dict, p, elbow_pin: str) -> list:
    """``[(kind, tf in the link's layer frame)]`` of one link (x along the link, z centred)."""
    Lc, s, h = p.clevis_length_mm, p.socket_depth_mm, p.clevis_height_mm
    if which == "proximal":
        length = lay["proximal_mm"]
        return [
            (K["clevis_hub"], np.eye(4)),
            (K["tube_proximal"], _rz(0.0, Lc - s)),
            (K["clevis_pin"], _rz(math.pi, length)),
            (K[elbow_pin], _rz(0.0, length, 0.0, -h / 2)),
        ]
    length = lay["distal_mm"]
    B = K["bearing"].ring_mm[2]
    out = [
        (K["clevis_bearing"], np.eye(4)),
        (K["tube_distal"], _rz(0.0, Lc - s)),
        (K["clevis_bearing"], _rz(math.pi, length)),
    ]
    return out + [
        (K["bearing"], _rz(0.0, x, 0.0, z)) for x in (0.0, length) for z in (-h / 2, h / 2 - B)
    ]


def assembly(design, lay: dict, fidelity: str):
    """The part instances and the world transform of each body at the home pose.

    Returns ``(instances, tf_world_body, home_pose, tapped_holes)``: instances is a list of
    :class:`cad.parts.PartInstance` (screws carry their
    :class:`cad.assembly.fasteners.Fastener` record); tf_world_body maps body -> 4x4 (mm);
    tapped_holes maps hole name -> :class:`cad.assembly.fasteners.TappedHole`.
    """
    from cad.kinematics import fivebar as fb5
    from cad.kinematics import twin_pantograph as tw
    from cad.parts import PartInstance, translation

    p = design.parts
    twin = _twin(design)
    K = _kinds(design, lay, fidelity)
    lay = {
        **lay,
        "proximal_mm": design.params["proximal_mm"],
        "distal_mm": design.params["distal_mm"],
    }
    fb = _lower_five_bar(design)
    B = [fb.base_left_mm, fb.base_right_mm]
    inst: list = []
    tfs: dict[str, np.ndarray] = {"ground": np.eye(4)}
    set_holes: dict = {}

    def place(name, kind, body, tf, fastener=None):
        inst.append(PartInstance(name, kind, body, np.asarray(tf, dtype=float), fastener=fastener))

    home = home_xy_mm(design)
    if twin:
        th = math.radians(design.workspace["home_theta_deg"])
        X = np.array([[home[0], home[1], th]])
        ik = tw.ik(design.mechanism, X)
        groups = [
            ("crank", ik.crank, lay["lower_layers_z_mm"], False),
            ("knob", ik.knob, lay["upper_layers_z_mm"], True),
        ]
    else:
        groups = [("", fb5.ik(fb, home[None, :]), lay["lower_layers_z_mm"], False)]
    pt, mt = p.plate_thickness_mm, p.motor_mount_thickness_mm
    zb = lay.get("bridge_bottom_z_mm", 0.0)
    for grp, fp, zs, upper in groups:
        F = _flip() if upper else np.eye(4)
        pre = f"{grp}_" if grp else ""
        C = [fp.C_left_mm[0], fp.C_right_mm[0]]
        E = fp.E_mm[0]
        shaft_tf = (
            translation(0, 0, zb + pt + mt) @ _flip() if upper else translation(0, 0, -pt - mt)
        )
        for i, side in enumerate(("left", "right")):
            body = f"{pre}proximal_{side}"
            tfs[body] = _rz(float(fp.q_rad[0, i]), B[i][0], B[i][1])
            pin = "pin_short" if side == "left" else "pin_long"
            for k, (kind, tf) in enumerate(_link_parts("proximal", side, K, lay, p, pin)):
                place(f"{body}.{kind.name}{k}", kind, body, translation(0, 0, zs[0]) @ F @ tf)
            place(f"{body}.motor_shaft", K["motor_shaft"], body, shaft_tf)
            _set_screw(place, set_holes, K, lay, body, translation(0, 0, zs[0]) @ F)
            body = f"{pre}distal_{side}"
            tfs[body] = _rz(math.atan2(E[1] - C[i][1], E[0] - C[i][0]), C[i][0], C[i][1])
            for k, (kind, tf) in enumerate(_link_parts("distal", side, K, lay, p, pin)):
                place(f"{body}.{kind.name}{k}", kind, body, translation(0, 0, zs[1 + i]) @ F @ tf)
    if twin:
        tfs["crankshaft"] = _rz(th, home[0], home[1])
        place("crankshaft", K["crankshaft"], "crankshaft", translation(0, 0, lay["web_z_mm"]))
        place("knob", K["knob"], "crankshaft", translation(0, 0, lay["knob_bottom_z_mm"]))
    else:
        tfs["handle"] = translation(home[0], home[1])
        place("handle_pin", K["handle_pin"], "handle", translation(0, 0, lay["handle_pin_z_mm"]))
        place("knob", K["knob"], "handle", translation(0, 0, lay["knob_bottom_z_mm"]))
    holes = _ground(place, K, lay, p, B, twin)
    return inst, tfs, home, {**holes, **set_holes}


#: This builder writes glb and 3mf (:mod:`cad.pipeline.views`).
VIEW_EXPORT = True
#: Poses of the stroke animation: the handle once round the workspace square.
STROKE_POSES = 32


def body_poses(design, X) -> dict[str, np.ndarray]:
    """``{body: (N, 4, 4)}`` world poses (mm) with the handle at the workspace points ``X``
    ((N, 2) x, y mm; the twin pantograph (N, 3) x, y mm, theta rad), placed as
    :func:`assembly` places the bodies at home (tests compare the two)."""
    from cad.kinematics import fivebar as fb5
    from cad.kinematics import twin_pantograph as tw
    from cad.parts import translation

    X = np.atleast_2d(np.asarray(X, dtype=float))
    n = len(X)
    fb = _lower_five_bar(design)
    B = [fb.base_left_mm, fb.base_right_mm]
    if _twin(design):
        ik = tw.ik(design.mechanism, X)
        groups = [("crank_", ik.crank), ("knob_", ik.knob)]
    else:
        ik = fb5.ik(fb, X[:, :2])
        groups = [("", ik)]
    if np.any(ik.status != 0):
        raise ValueError(f"{int(np.sum(ik.status != 0))} of the {n} points cannot be reached")
    out = {"ground": np.repeat(np.eye(4)[None], n, axis=0)}
    for pre, fp in groups:
        E = fp.E_mm
        for i, (side, C) in enumerate((("left", fp.C_left_mm), ("right", fp.C_right_mm))):
            out[f"{pre}proximal_{side}"] = np.stack(
                [_rz(float(fp.q_rad[k, i]), B[i][0], B[i][1]) for k in range(n)]
            )
            out[f"{pre}distal_{side}"] = np.stack(
                [
                    _rz(math.atan2(E[k, 1] - C[k, 1], E[k, 0] - C[k, 0]), C[k, 0], C[k, 1])
                    for k in range(n)
                ]
            )
    if _twin(design):
        out["crankshaft"] = np.stack([_rz(X[k, 2], X[k, 0], X[k, 1]) for k in range(n)])
    else:
        out["handle"] = np.stack([translation(X[k, 0], X[k, 1]) for k in range(n)])
    return out


def stroke_points(design, n: int = STROKE_POSES) -> np.ndarray:
    """The handle once round the workspace square (from its centre's left, counter-clockwise),
    ``n`` points, (n, 2) mm; the twin pantograph adds theta = the home angle (rad)."""
    sq = _square(design.workspace)
    seg = np.linalg.norm(np.diff(sq, axis=0), axis=1)
    s = np.linspace(0.0, seg.sum(), n)
    xy = np.column_stack([np.interp(s, np.r_[0, np.cumsum(seg)], sq[:, j]) for j in (0, 1)])
    if not _twin(design):
        return xy
    th = math.radians(design.workspace["home_theta_deg"])
    return np.column_stack([xy, np.full(n, th)])


def stroke_poses(design) -> dict[str, np.ndarray] | None:
    """:func:`body_poses` over :func:`stroke_points`, or None where the square leaves the
    reachable set (the animation then shows the home pose only)."""
    try:
        poses = body_poses(design, stroke_points(design))
    except ValueError:
        return None
    return poses


def _screw(place, holes, K, lay, group: str, name: str, hole: str, part: str, tf, clamps=None):
    """Place one screw of ``group`` (:func:`screw_plan`) with its fastener record, and the
    tapped hole ``hole`` (in the instance ``part``) it engages."""
    from cad.assembly.fasteners import Fastener, TappedHole

    sp = lay["screws"][group]
    holes[hole] = TappedHole(hole, part, sp["size"], sp["depth_mm"], sp["min_engagement_mm"])
    f = Fastener("ISO 4762", sp["size"], sp["length_mm"], tuple(clamps or sp["clamps"]), hole,
                 sp["engagement_mm"])
    place(name, K[f"_{group}_screw"], "ground", tf, fastener=f)


def _set_screw(place, holes, K, lay, body: str, tf_clevis) -> None:
    """The set screw of the hub clevis of ``body`` (clevis frame ``tf_clevis``): axis along
    -x at z = 0, flat point on the shaft surface (x = -shaft radius), its other end at or
    inside the clevis outer surface; the wall's tapped hole is its record's hole."""
    from cad.assembly.fasteners import Fastener, TappedHole

    ss = lay["set_screw"]
    clevis = f"{body}.clevis_hub0"
    hole = f"{clevis}:set_screw"
    holes[hole] = TappedHole(hole, clevis, ss["size"], ss["depth_mm"], ss["min_engagement_mm"])
    T = np.eye(4)
    T[:3, :3] = [[0, 0, -1], [0, 1, 0], [1, 0, 0]]  # part z (point -> end) -> clevis -x
    T[0, 3] = -ss["shaft_radius_mm"]
    f = Fastener("ISO 4026", ss["size"], ss["length_mm"], (f"{body}.motor_shaft",), hole,
                 ss["engagement_mm"])
    place(f"{body}.set_screw", K["set_screw"], body, tf_clevis @ T, fastener=f)


def _motor_station(place, holes, K, lay, p, tag: str, i: int, bxy, z_mount: float, upper: bool):
    """One motor on its mount plate: the plate, the motor, the plate's screws into the
    base/bridge plate and the motor face screws (through the plate into the face's tapped
    holes; heads in the base/bridge plate's opening)."""
    from cad.data.catalog import get_motor
    from cad.parts import motor as pm
    from cad.parts import translation

    mot = get_motor(p.motor)
    mt = p.motor_mount_thickness_mm
    bx, by = bxy
    plate = "bridge_plate" if upper else "base_plate"
    place(f"{tag}_motor_mount_{i}", K["motor_mount"], "ground", translation(bx, by, z_mount))
    # upper: plate on the bridge, motor standing on it (face up at z_mount + mt, turned over),
    # its screws from above into the bridge, the face screws from below; lower: mirrored
    z_face = z_mount + mt if upper else z_mount
    # turned over about y: the face's bolt circle (symmetric in x) stays on the plate's holes
    turn = np.diag([-1.0, 1.0, -1.0, 1.0])
    tf_motor = translation(bx, by, z_face) @ (turn if upper else np.eye(4))
    motor = f"{tag}_motor_{i}"
    place(motor, K["motor"], "ground", tf_motor)
    z_mount_head, f_mount = (z_mount + mt, np.eye(4)) if upper else (z_mount, _flip())
    for k, (x, y) in enumerate(pm.mount_hole_xy_mm(mot)):
        _screw(place, holes, K, lay, "mount", f"{tag}_mount_screw_{i}_{k + 1}",
               f"{plate}:{tag}_mount_{i}_{k + 1}", plate,
               translation(bx + x, by + y, z_mount_head) @ f_mount)
    z_head, f_face = (z_mount, _flip()) if upper else (z_mount + mt, np.eye(4))
    for k, (x, y) in enumerate(pm.motor_bolt_xy_mm(mot)):
        _screw(place, holes, K, lay, "motor", f"{tag}_motor_screw_{i}_{k + 1}",
               f"{motor}:face_{k + 1}", motor, translation(bx + x, by + y, z_head) @ f_face)


def _ground(place, K, lay, p, B, twin) -> dict:
    """The fixed parts: base plate, legs, motors with their mounts, (mouse) posts and bridge.
    Returns the tapped holes the screws engage ({name: TappedHole})."""
    from cad.parts import translation

    holes: dict = {}
    pt, mt = p.plate_thickness_mm, p.motor_mount_thickness_mm
    place("base_plate", K["base_plate"], "ground", translation(0, 0, -pt))
    for i, (x, y) in enumerate(_leg_xy(lay)):
        place(f"leg_{i + 1}", K["leg"], "ground", translation(x, y, lay["bench_z_mm"]))
        _screw(place, holes, K, lay, "leg", f"leg_screw_{i + 1}", f"leg_{i + 1}:top",
               f"leg_{i + 1}", translation(x, y, 0.0))
    zb = lay.get("bridge_bottom_z_mm", 0.0)
    stations = [("lower", -pt - mt, False)] + ([("upper", zb + pt, True)] if twin else [])
    for tag, z_mount, upper in stations:
        for i, bxy in enumerate(B):
            _motor_station(place, holes, K, lay, p, tag, i + 1, bxy, z_mount, upper)
    if not twin:
        return holes
    place("bridge_plate", K["bridge_plate"], "ground", translation(0, 0, zb))
    for k, (x, y) in enumerate(lay["posts_xy_mm"]):
        post = f"post_{k + 1}"
        place(post, K["post"], "ground", translation(x, y, 0.0))
        _screw(place, holes, K, lay, "post", f"post_screw_{k + 1}_bottom", f"{post}:bottom",
               post, translation(x, y, -pt) @ _flip(), ["base_plate"])
        _screw(place, holes, K, lay, "post", f"post_screw_{k + 1}_top", f"{post}:top", post,
               translation(x, y, zb + pt), ["bridge_plate"])
    return holes


# ------------------------------------------------------------------------------ build
#: This builder writes the simulator formats for the twin pantograph (mjcf, urdf;
#: :mod:`cad.families.pantograph.sim`).
SIM_EXPORT = True


def _write_sim(design, out_dir, formats, instances, bodies, lay, home) -> list[str]:
    """``<name>.xml`` (MJCF) / ``<name>.urdf`` of the mouse when asked, from the instance list
    (:mod:`cad.families.pantograph.sim`; meshes are ``parts/<kind>.stl``)."""
    from cad.export.sim import SIM_FORMATS, write_sim_files

    if not set(formats) & set(SIM_FORMATS):
        return []
    import dataclasses

    from cad.data.catalog import get_motor
    from cad.data.materials import get_material
    from cad.families.pantograph.sim import sim_model
    from cad.kinematics import twin_pantograph as tw

    th = math.radians(design.workspace["home_theta_deg"])
    ik = tw.ik(design.mechanism, np.array([[home[0], home[1], th]]))
    K = {i.kind.name: i.kind for i in instances}
    p = design.parts
    L, U = lay["lower_layers_z_mm"], lay["upper_layers_z_mm"]
    layer_z = {
        "crank_proximal": L[0],
        "knob_proximal": U[0],
        "crank_distal_left": L[1],
        "crank_distal_right": L[2],
        "knob_distal_left": U[1],
        "knob_distal_right": U[2],
        "crankshaft": lay["web_z_mm"],
    }
    shifted = {}
    for b, mp in bodies.items():  # body frames of the sim sit at the layer height
        z = layer_z.get(b, layer_z.get(b.rsplit("_", 1)[0], 0.0))
        shifted[b] = mp.transformed(np.eye(3), np.array([0.0, 0.0, -z * 1e-3]))
    for grp in ("crank", "knob"):
        shifted[f"{grp}_distal"] = shifted[f"{grp}_distal_left"]
    lay2 = {
        **lay,
        "proximal_mm": design.params["proximal_mm"],
        "distal_mm": design.params["distal_mm"],
    }
    parts = {
        f"proximal_{s}": [(k.name, tf) for k, tf in _link_parts("proximal", s, K, lay2, p, pin)]
        for s, pin in (("left", "pin_short"), ("right", "pin_long"))
    }
    parts["distal"] = [(k.name, tf) for k, tf in _link_parts("distal", "left", K, lay2, p, "")]
    parts["crankshaft"] = [
        ("crankshaft", np.eye(4)),
        ("knob", _rz(0.0, 0.0, 0.0, lay["knob_bottom_z_mm"] - lay["web_z_mm"])),
    ]
    ground = [(i.name, i.kind.name, i.tf_body_part) for i in instances if i.body == "ground"]
    made = {k.name for k in K.values() if k.made and k.listed}
    model = sim_model(
        design,
        shifted,
        parts,
        ground,
        lay,
        [*home, th],
        ik,
        get_motor(p.motor).rotor_inertia_kg_m2,
        made,
        lambda kind: get_material(K[kind].material).color_rgb,
    )
    model = dataclasses.replace(model, meshdir="parts")
    return [q.name for q in write_sim_files(model, out_dir, formats, design.name)]


def _effective_mass(design, bodies: dict, home: np.ndarray) -> tuple[dict, dict | None]:
    """Effective mass at home (with and, for the mouse, without rotor inertia)."""
    from cad.data.catalog import get_motor
    from cad.kinematics import fivebar as fb5
    from cad.kinematics import twin_pantograph as tw

    rotor = get_motor(design.parts.motor).rotor_inertia_kg_m2

    def fbm(pre: str, jm: float):
        d = [_planar(bodies[f"{pre}distal_{s}"]) for s in ("left", "right")]
        pr = [_planar(bodies[f"{pre}proximal_{s}"]) for s in ("left", "right")]
        return fb5.FiveBarMass(pr[0], pr[1], d[0], d[1], jm)

    if not _twin(design):
        M = fb5.mass_matrix_kg(design.mechanism, home[None, :], fbm("", rotor))[0]
        M = M + bodies["handle"].mass_kg * np.eye(2)  # the handle translates with E
        return {
            "at_mm": home.tolist(),
            "mass_matrix_g": (M * 1e3).tolist(),
            "mass_x_g_diag": float(M[0, 0] * 1e3),
            "mass_y_g_diag": float(M[1, 1] * 1e3),
        }, None
    th = math.radians(design.workspace["home_theta_deg"])
    X = np.array([home[0], home[1], th])
    cs = bodies["crankshaft"]
    crank = fb5.LinkMass(
        float(cs.mass_kg),
        (float(cs.com_m[0]), float(cs.com_m[1])),
        float(cs.inertia_com_kg_m2[2, 2]),
    )
    tm = design.mechanism
    eff = tw.effective_mass_home(
        tm, X, tw.TwinMass(fbm("knob_", rotor), fbm("crank_", rotor), crank)
    )
    bare = tw.effective_mass_home(tm, X, tw.TwinMass(fbm("knob_", 0.0), fbm("crank_", 0.0), crank))
    return eff, bare


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
    """Build a plain 5-bar or a twin-pantograph mouse into ``out_dir``; return the report dict.

    fidelity: "fabrication" uses bd_warehouse ball bearings (races and balls); "inertia"
    and "preview" a plain ring (same catalogue mass: the mass properties do not change).
    Raises InterferenceError when two moving parts in one layer come closer than
    :data:`MIN_CLEARANCE_MM` anywhere in the workspace, or two solids share volume at the
    home pose, unless allow_interference; GeometryError if a solid reaches below the bench.
    """
    from cad.errors import GeometryError
    from cad.pipeline import family, forked

    check_options(design, fidelity, phi1_deg, formats)
    out_dir = Path(out_dir)
    total = 6
    p = design.parts
    h = p.clevis_height_mm

    _step(progress, "layout and clearances", 0, total)
    lay = layout(design)
    for key in ("lower_shaft_engagement_mm", "upper_shaft_engagement_mm"):
        if key in lay and lay[key] < h / 2:
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
            "(x_mm, y_mm[, theta_deg]); pass allow_interference to export anyway"
        )

    _step(progress, "solids", 1, total)
    instances, tfs, home, holes = assembly(design, lay, fidelity)
    fasteners = family.fastener_report(instances, holes)  # DesignError: two in a hole, ...

    _step(progress, "mass properties", 2, total)
    props = family.kind_props(instances)
    bodies = family.body_props(instances, props, [b for b in tfs if b != "ground"])
    eff, eff_bare = _effective_mass(design, bodies, home)

    # the files are written by a forked child while this process checks the solids
    # (cad.pipeline.forked; serial where forking is off)
    bom = family.bom_rows(instances, props)
    title = f"{design.name}: {design.family} at home {home.round(2).tolist()} mm"

    def exports() -> list[str]:
        return family.write_outputs(
            instances,
            tfs,
            out_dir,
            formats,
            name=design.name,
            title=title,
            bom=bom,
            marks=[("workspace", _square(design.workspace))],
            holes=tuple(holes.values()),
        )

    task = forked.start(exports, "exports")
    with forked.cancel_on_error(task):
        _step(progress, "every pair of solids at home", 3, total)
        itf = family.check_assembly(instances, tfs)
        if itf["collisions"] and not allow_interference:
            c = itf["collisions"][0]
            raise InterferenceError(
                f"{c['parts'][0]} / {c['parts'][1]} overlap {c['overlap_volume_mm3']:.3f} mm^3 "
                f"at the home pose; {len(itf['collisions'])} overlapping pair(s) "
                "(use --allow-interference)"
            )
        low, low_part = family.lowest_z_mm(instances, tfs)
        if low < lay["bench_z_mm"] - 1e-6:
            raise GeometryError(
                f"{low_part} reaches z = {low:.2f} mm, below the bench plane at "
                f"{lay['bench_z_mm']:.2f} mm"
            )
        _step(progress, "exports", 4, total)
        files = task.result()
    if _twin(design):
        files += _write_sim(design, out_dir, formats, instances, bodies, lay, home)
    from cad.pipeline.views import write_viewer_outputs

    view_files, viewer_glb = write_viewer_outputs(
        instances,
        tfs,
        out_dir,
        formats,
        name=design.name,
        title=f"{design.name} ({design.family})",
        stroke=stroke_poses(design),
    )
    files += view_files

    _step(progress, "report", 5, total)
    report = _report(design, lay, clr, bodies, eff, eff_bare, itf, bom, home, fidelity, low)
    report.update(fasteners)
    report["part_materials"] = family.part_materials(instances)
    report["fits"] = family.fits_report(instances)
    report["placement"] = family.placement_report(instances, tfs, props)
    report["files"] = sorted(files + ["report.md"])
    family.write_report_md(
        out_dir, f"{design.name} ({design.family})", _md_rows(report), bom, report["notes"]
    )
    family.write_assembly_md(out_dir, f"{design.name} ({design.family})", instances,
                             checks=ASSEMBLY_CHECKS)
    report["_viewer_glb"] = viewer_glb  # popped by the dispatcher: embedded in report.html
    _step(progress, "done", total, total)
    return report


def _square(ws: dict) -> np.ndarray:
    (cx, cy), h = ws["center_mm"], ws["side_mm"] / 2
    return np.array(
        [[cx - h, cy - h], [cx + h, cy - h], [cx + h, cy + h], [cx - h, cy + h], [cx - h, cy - h]]
    )


def _report(design, lay, clr, bodies, eff, eff_bare, itf, bom, home, fidelity, low) -> dict:
    from cad.data.catalog import get_motor

    g = design.gii()
    mot = get_motor(design.parts.motor)
    report = {
        "name": design.name,
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
        "layout_mm": lay,
        "clearances_mm": clr,
        "interference": itf,
        "overlap_volume_mm3": itf["overlap_volume_mm3"],
        "bench_z_mm": lay["bench_z_mm"],
        "lowest_z_mm": low,
        "bodies": {k: v.to_dict() for k, v in bodies.items()},
        "moving_mass_g": sum(v.mass_kg for v in bodies.values()) * 1e3,
        "total_mass_g": sum(r["mass_g"] * r["quantity"] for r in bom),
        "motor": {
            "key": mot.key,
            "rotor_inertia_g_cm2": mot.rotor_inertia_g_cm2,
            "source": mot.source,
        },
        "home": {"x_mm": float(home[0]), "y_mm": float(home[1])},
        "effective_mass_home": eff,
        "bom": bom,
        "notes": [
            "The base plate stands on four leg standoffs: no solid lies below the bench plane "
            f"z = {lay['bench_z_mm']:.1f} mm (lowest solid at {low:.1f} mm).",
            "Every pair of solids is checked at the home pose (common volume > "
            f"{itf['overlap_threshold_mm3']:g} mm^3 is a collision); moving links are checked "
            "over the workspace by capsules per layer (clearances_mm).",
            "Every screw is sized from its stack (fasteners, tapped_holes): catalog ISO 4762 "
            "length, engagement between 1.5 d (aluminium; the maker's minimum in the motor "
            "face) and the tapped hole's depth, one screw per hole. Each hub clevis is locked on "
            f"its motor shaft by an ISO 4026 {lay['set_screw']['size']} x "
            f"{lay['set_screw']['length_mm']:g} set screw tapped radially through its wall "
            "(the longest catalog length not proud of the round end, >= 1.5 d).",
        ],
    }
    if _twin(design):
        report["crank_mm"] = design.mechanism.crank_mm
        report["home"]["theta_deg"] = float(design.workspace["home_theta_deg"])
        report["effective_mass_home_without_rotors"] = eff_bare
        report["paper_table1"] = PAPER_TABLE1
        report["effective_mass_note"] = (
            "diag = mass felt moving one task axis with the others held; apparent = 1/(M^-1)_ii, "
            "the others free. Ours differs from Table 1 because the paper's values are measured on "
            "the built device (closed-loop identification, includes the real motors, encoders, "
            "cabling, fasteners and friction) and its link lengths, tube sizes and motors are not "
            "published; here the moving parts are the solids above with catalogue bearing and rotor data."
        )
    return report


def _md_rows(r: dict) -> list[tuple[str, str]]:
    rows = [
        ("GII (workspace)", f"{r['gii']['gii']:.4f}"),
        ("moving mass (g)", f"{r['moving_mass_g']:.1f}"),
        ("total mass (g)", f"{r['total_mass_g']:.1f}"),
        (
            "min layer clearance over the workspace (mm)",
            f"{r['clearances_mm']['min_gap_mm']:.2f} ({r['clearances_mm']['worst']})",
        ),
        (
            "solids / pairs checked exactly at home",
            f"{r['interference']['parts']} / {r['interference']['exact_pairs']}",
        ),
        ("overlap volume at home (mm^3)", f"{r['overlap_volume_mm3']:.4g}"),
        ("bench plane / lowest solid z (mm)", f"{r['bench_z_mm']:.1f} / {r['lowest_z_mm']:.1f}"),
    ]
    for k, v in r["effective_mass_home"].items():
        if isinstance(v, float):
            rows.append((f"effective mass at home: {k}", f"{v:.4g}"))
    return rows
