"""Layout of the haptic pen (numbers and body poses; numpy only, no CAD import).

World frame = the kinematic frame of :mod:`cad.kinematics.haptic_pen` (mm, z up): arm A's
waist axis is vertical through (-l4/2, 0), arm B's through (+l4/2, 0); each arm is a
symmetric 5-bar whose base line lies on its waist axis (shoulders at z = -l1/2 "lower" and
z = +l1/2 "upper"), in the plane through the waist axis at waist angle psi (in-plane
coordinates (z, rho), rho along e_r = (cos psi, sin psi, 0)).

Arrangement (our reading of Fig. 4 and §4.2):

* each arm's links lie in four layers on the *outer* side of its plane (outward normal
  ``n_out``: -x for arm A at home, +x for arm B), from the plane outwards: lower distal (L4),
  upper distal (L3), upper proximal (L2), lower proximal (L1) -- every link in its own layer,
  since the upper proximal swings below the lower shoulder (q up to ~188 deg); the shoulder
  motors stand on the waist bracket's motor plate outside L1, shafts inwards; the upper hub
  reaches L2 through a spigot;
* each waist bracket (motor plate, a foot strip under the links, a boss on the waist motor
  shaft) turns about its waist axis on a waist motor hanging under the base plate;
* at each pen end E a gimbal: the yoke turns on a journal in the two distal clevises'
  bearings (axis ``n_out``), the ring turns in the yoke about the vertical axis ``a``, the pen
  hub turns on the ring's pins about ``b`` = the horizontal normal of the pen (e_yaw). The
  three axes meet at E: a spherical joint. The pen's roll is passive; the pose keeps ``b``
  horizontal (pen orientation Rz(yaw) Ry(-pitch)).

Body frames (``tf_world_body``, every joint a rotation about the child body's z axis through
its origin, so the same frames serve the MJCF): waist -- origin on the waist axis at z = 0,
z up, y = n_out; a link -- origin at its first joint on the plane, x towards its second
joint, z = n_out; yoke -- origin at E, z = n_out, x up; ring -- origin at E, z up, x = the
pen's horizontal direction; pen -- origin at arm A's end, x along the pen, z = e_yaw.
"""

from __future__ import annotations

import math

import numpy as np

from cad.data.catalog import get_bearing, get_motor
from cad.device import resolve_device
from cad.errors import DesignError
from cad.families.pantograph.capstan import DRUM_THICKNESS_MM
from cad.kinematics import fivebar as fb5
from cad.kinematics import haptic_pen as hp
from cad.parts import base
from cad.parts.motor import mount_side_mm
from cad.tolerances import PEN_FOOT_MARGIN_MM as FOOT_MARGIN_MM
from cad.tolerances import PEN_GIMBAL_GAP_MM as GIMBAL_GAP_MM

ARMS = ("A", "B")
#: Radial wall of the gimbal ring and its axial thickness (mm).
RING_WALL_MM = 4.0
RING_THICKNESS_MM = 6.0
#: Yoke arm and base thickness (mm).
YOKE_ARM_MM = 5.0
YOKE_BASE_MM = 6.0
#: Waist hub: height, diameter, gap above the base plate (mm).
WAIST_HUB_MM = (15.0, 26.0, 1.0)
#: Samples per rotation axis of the motion the interference check sweeps (corners and centre).
MOTION_ROT = (-1.0, 0.0, 1.0)


def _motor(key: str):
    return get_motor(key)


def shoulder_band_mm(design) -> float:
    """How far the waist bracket's motor plate moves out for shoulder capstans (mm): two layer
    gaps and two drums (:data:`cad.families.pantograph.capstan.DRUM_THICKNESS_MM`), a band for
    each shoulder drum (:mod:`cad.families.pen.shoulder_capstan`); 0 with direct shoulders."""
    dev = resolve_device(design)
    if not any(dev.transmission(f"{a}_q_{s}").is_capstan for a in ARMS for s in ("lower", "upper")):
        return 0.0
    return 2 * (design.parts.layer_gap_mm + DRUM_THICKNESS_MM)


def layout(design) -> dict:
    """Offsets and sizes of the pen's assembly (mm), from the design only; with shoulder
    capstans the motor plate :func:`shoulder_band_mm` further out (the proximal links on their
    own axles: no shaft in a hub to check)."""
    p = design.parts
    b = get_bearing(p.bearing)
    h, g = p.clevis_height_mm, p.layer_gap_mm
    pitch = h + g
    ri = p.gimbal_ring_mm / 2
    ro = ri + RING_WALL_MM
    yoke_x = ro + GIMBAL_GAP_MM  # inner faces of the yoke arms (along a)
    base0 = math.hypot(ro, RING_THICKNESS_MM / 2) + GIMBAL_GAP_MM  # yoke base inner face
    base1 = base0 + YOKE_BASE_MM
    z4 = base1 + g + h / 2
    layers = {"distal_lower": z4, "distal_upper": z4 + pitch, "proximal_upper": z4 + 2 * pitch,
              "proximal_lower": z4 + 3 * pitch}
    band = shoulder_band_mm(design)
    plate0 = layers["proximal_lower"] + h / 2 + g + band
    m = _motor(p.motor)
    plate1 = plate0 + p.motor_mount_thickness_mm
    shaft_tip = plate1 - m.shaft_length_mm
    low_eng = layers["proximal_lower"] + h / 2 - shaft_tip
    if not band and low_eng < h / 2:
        raise DesignError("parts.motor", f"{p.motor} shaft engages only {low_eng:.1f} mm of the "
                          f"{h:g} mm hub; use a thinner motor_mount_thickness_mm")
    r_hub = b.D_mm / 2 + 1.5
    # pen hub half length along b: its end corners stay GIMBAL_GAP_MM inside the ring
    hub_half = math.sqrt((ri - GIMBAL_GAP_MM) ** 2 - r_hub**2)
    return {
        "layer_pitch_mm": pitch,
        "layers_mm": layers,
        "ring_inner_mm": ri,
        "ring_outer_mm": ro,
        "yoke_arm_x_mm": yoke_x,
        "yoke_base_mm": (base0, base1),
        "journal_mm": (base1, layers["distal_upper"] + h / 2),
        "pen_hub_half_mm": hub_half,
        "pen_hub_radius_mm": r_hub,
        "motor_plate_mm": (plate0, plate1),
        "motor_plate_side_mm": mount_side_mm(m),
        "shoulder_shaft_tip_mm": shaft_tip,
        "spigot_mm": (layers["proximal_upper"] + h / 2, plate0 - 1.0),
        "pin_lower_mm": (layers["distal_lower"] - h / 2, layers["proximal_lower"] + h / 2),
        "pin_upper_mm": (layers["distal_upper"] - h / 2, layers["proximal_upper"] + h / 2),
        "tube_proximal_mm": design.params["proximal_mm"] - 2 * (p.clevis_length_mm - p.socket_depth_mm),
        "tube_distal_mm": design.params["distal_mm"] - 2 * (p.clevis_length_mm - p.socket_depth_mm),
        "bearing": b,
    }


def ground_layout(design, lay: dict, z_low_mm: float, band_mm: float = 0.0, stations_xy=()) -> dict:
    """Heights of the waist bracket's foot, the base plate and the bench (mm, world z), from
    the lowest link point over the motion ``z_low_mm``. With waist capstans
    (:mod:`cad.families.pen.capstan_solids`): ``band_mm`` the drums' band between the base plate
    and the waist hub (the plate that much lower; the hub on its own axle, no shaft engagement:
    ``waist_shaft_engagement_mm`` 0), ``stations_xy`` the moved waist motors' axes ((x, y) mm,
    world) the base plate also covers with its margin."""
    p = design.parts
    wm = _motor(p.waist_motor)
    foot_top = z_low_mm - FOOT_MARGIN_MM
    foot_bottom = foot_top - p.plate_thickness_mm
    hub_h, hub_d, hub_gap = WAIST_HUB_MM
    z_base = foot_bottom - hub_h - hub_gap - band_mm
    z_hub = z_base + band_mm + hub_gap
    pt, mt = p.plate_thickness_mm, p.motor_mount_thickness_mm
    shaft_top = z_base - pt - mt + wm.shaft_length_mm
    if not band_mm and shaft_top - z_hub < hub_h / 2:
        raise DesignError("parts.waist_motor", f"{p.waist_motor} shaft engages only "
                          f"{shaft_top - z_base - hub_gap:.1f} mm of the waist hub")
    l4 = design.mechanism.l4_mm
    ms = mount_side_mm(wm)
    if ms > l4:
        raise DesignError("parts.waist_motor", f"{p.waist_motor} mount plates ({ms:g} mm) do not "
                          f"fit between the waist axes {l4:g} mm apart")
    margin = base.LEG_INSET_MM + base.LEG_DIAMETER_MM / 2 + 4.0
    leg_h = mt + wm.body_length_mm + base.LEG_GROUND_CLEARANCE_MM
    xy = np.array([(-l4 / 2, 0.0), (l4 / 2, 0.0), *stations_xy], float)
    lo, hi = xy.min(axis=0) - ms / 2 - margin, xy.max(axis=0) + ms / 2 + margin
    return {
        "foot_mm": (foot_bottom, foot_top),
        "base_top_z_mm": z_base,
        "base_plate_x_mm": (float(lo[0]), float(hi[0])),
        "base_plate_y_mm": (float(lo[1]), float(hi[1])),
        "leg_height_mm": leg_h,
        "bench_z_mm": z_base - pt - leg_h,
        "waist_hub_mm": (z_hub, z_hub + hub_h),
        "waist_hub_d_mm": hub_d,
        "waist_shaft_engagement_mm": 0.0 if band_mm else shaft_top - z_hub,
    }


def home_task(design) -> np.ndarray:
    """(5,) task pose of the exported assembly: the workspace centre, pen along +x."""
    return np.array([*design.workspace["center_mm"], 0.0, 0.0])


def motion_task(design) -> tuple[np.ndarray, tuple[str, ...]]:
    """The poses the interference check sweeps ((n, 5) x, y, z mm, yaw, pitch rad) and their
    labels: home, each corner of the workspace box at each corner of the rotation square
    alternately, and the four rotation corners at the centre."""
    ws = design.workspace
    c = np.asarray(ws["center_mm"], float)
    s = np.asarray(ws["size_mm"], float) / 2
    r = math.radians(ws["rotation_deg"])
    rows = [home_task(design)]
    rot = [(-r, -r), (r, r), (-r, r), (r, -r)]
    k = 0
    for sx in (-1, 1):
        for sy in (-1, 1):
            for sz in (-1, 1):
                for yw, pt in (rot[k % 4], rot[(k + 1) % 4]):
                    rows.append(np.array([*(c + s * (sx, sy, sz)), yw, pt]))
                k += 1
    for yw, pt in rot:
        rows.append(np.array([*c, yw, pt]))
    X = np.array(rows)
    labels = tuple(
        f"x {x[0]:.1f}, y {x[1]:.1f}, z {x[2]:.1f} mm, yaw {math.degrees(x[3]):.0f}, "
        f"pitch {math.degrees(x[4]):.0f} deg" for x in X)
    return X, labels


def stroke_task(design, n: int = 24) -> np.ndarray:
    """(n, 5) task poses of the animation: the pen once round an ellipse through 0.4 of the
    workspace box in x and y at the centre height, yawing and pitching by half the rotation
    range (a closed loop, first pose = last)."""
    ws = design.workspace
    c = np.asarray(ws["center_mm"], float)
    s = np.asarray(ws["size_mm"], float)
    r = math.radians(ws["rotation_deg"]) / 2
    t = np.linspace(0.0, 2 * math.pi, n)
    return np.column_stack([c[0] + 0.4 * s[0] * np.cos(t), c[1] + 0.4 * s[1] * np.sin(t),
                            np.full(n, c[2]), r * np.sin(t), r * np.cos(t)])


def _frame(x, z, origin) -> np.ndarray:
    """(..., 4, 4) frames with axes x, y = z cross x, z and ``origin`` (world, mm)."""
    x, z, origin = np.broadcast_arrays(x, z, origin)
    T = np.zeros(x.shape[:-1] + (4, 4))
    T[..., :3, 0] = x
    T[..., :3, 1] = np.cross(z, x)
    T[..., :3, 2] = z
    T[..., :3, 3] = origin
    T[..., 3, 3] = 1.0
    return T


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def body_poses(design, X) -> dict[str, np.ndarray]:
    """``{body: (N, 4, 4)}`` world poses (mm) at task poses ``X`` (N, 5) = (x, y, z mm, yaw,
    pitch rad) (module docstring); DesignError (``workspace``) naming how many poses cannot be
    reached and the first."""
    pen = design.mechanism
    X = np.atleast_2d(np.asarray(X, float))
    n = len(X)
    q, st = hp.ik(pen, X)
    if np.any(st != 0):  # a DesignError (a ValueError): the design's workspace is the fault

        x = X[int(np.argmax(st != 0))]
        raise DesignError("workspace", f"{int(np.sum(st != 0))} of the {n} pen poses cannot be "
                          f"reached (first: x {x[0]:g}, y {x[1]:g}, z {x[2]:g} mm, yaw "
                          f"{np.degrees(x[3]):g}, pitch {np.degrees(x[4]):g} deg); move "
                          "workspace.center_mm or shrink workspace.size_mm / rotation_deg")
    u, e_yaw, _ = hp.pen_directions(X[:, 3], X[:, 4])
    l1, l2, l3, l6, l4 = (pen.shoulder_base_mm, pen.proximal_mm, pen.distal_mm, pen.pen_mm,
                          pen.l4_mm)
    zhat = np.broadcast_to([0.0, 0.0, 1.0], (n, 3))
    out = {"ground": np.repeat(np.eye(4)[None], n, axis=0)}
    for arm, sign, col in (("A", -1.0, 0), ("B", 1.0, 3)):
        x0 = sign * l4 / 2
        P = X[:, :3] + sign * l6 / 2 * u
        psi = q[:, col]
        er = np.stack([np.cos(psi), np.sin(psi), np.zeros(n)], axis=-1)
        n5 = np.stack([-np.sin(psi), np.cos(psi), np.zeros(n)], axis=-1)
        n_out = -sign * n5  # A: +n5 (-x at home), B: -n5
        base = np.array([x0, 0.0, 0.0])
        rho = np.hypot(P[:, 0] - x0, P[:, 1])
        _, _, c1x, c1y, c2x, c2y, _ = fb5.ik_arrays(-l1 / 2, 0.0, l1 / 2, 0.0, l2, l2, l3, l3,
                                                     1.0, -1.0, P[:, 2], rho)

        def world(x5, y5, er=er, base=base):
            return base + np.asarray(x5)[..., None] * zhat + np.asarray(y5)[..., None] * er

        B_lo, B_up = world(np.full(n, -l1 / 2), np.zeros(n)), world(np.full(n, l1 / 2), np.zeros(n))
        C_lo, C_up, E = world(c1x, c1y), world(c2x, c2y), P
        out[f"{arm}_waist"] = _frame(-sign * er, zhat, base)
        for side, B, C in (("lower", B_lo, C_lo), ("upper", B_up, C_up)):
            out[f"{arm}_proximal_{side}"] = _frame(_unit(C - B), n_out, B)
            out[f"{arm}_distal_{side}"] = _frame(_unit(E - C), n_out, C)
        out[f"{arm}_yoke"] = _frame(zhat, n_out, E)
        h = _unit(np.stack([u[:, 0], u[:, 1], np.zeros(n)], axis=-1))
        out[f"{arm}_ring"] = _frame(h, zhat, E)
    out["pen"] = _frame(u, e_yaw, X[:, :3] - l6 / 2 * u)
    return out


def ik_elbows_ok(design, X) -> np.ndarray:
    """(N,) bool: every arm of the pen reaches ``X`` (status ok of the pen kinematics)."""
    return hp.ik(design.mechanism, np.atleast_2d(X))[1] == 0


def lowest_link_z_mm(design, lay: dict, X) -> float:
    """Lowest world z of any link clevis over the task poses ``X`` (mm): the elbows, shoulders
    and pen ends lowered by half a clevis width."""
    T = body_poses(design, X)
    w = design.parts.clevis_width_mm / 2
    zs = [T[f"{a}_{k}"][:, 2, 3] for a in ARMS for k in ("proximal_lower", "proximal_upper",
                                                         "distal_lower", "distal_upper",
                                                         "yoke")]
    ends = [T[f"{a}_distal_{s}"] @ np.array([design.params["distal_mm"], 0, 0, 1.0])
            for a in ARMS for s in ("lower", "upper")]
    low = min(float(np.min(z)) for z in zs)
    low = min(low, min(float(np.min(e[:, 2])) for e in ends))
    return low - max(w, lay["ring_outer_mm"])
