"""First modes, pen-end compliance and peak stress of the haptic pen (numpy, no CAD): each of
its two arms' 5-bars as a planar beam frame of :mod:`cad.structure.graph`, the model of the
planar pantographs (:mod:`cad.structure.pantograph`) reused arm by arm.

Model (each arm in its own plane; in-plane coordinates (z, rho) of
:mod:`cad.kinematics.haptic_pen`: x of the frame = world z, y = rho along the arm's radial
direction, z of the frame = the normal of the arm's plane; SI inside, mm / g / um at the
edges):

* links: the arm's proximal (B -> C) and distal (C -> E) links, lower and upper, each one beam
  joint to joint with the carbon tube's annulus (:func:`cad.structure.device.tube_section`,
  ``parts.tube_material``, the tube's mass spread along the beam,
  :func:`cad.structure.pantograph.tube_mass_kg`; clevises not credited: conservative);
* joints: C of each side and E revolute ties (every DOF but the rotation about the plane's
  normal; pins, bearings and the gimbal's journal rigid; the four layers' offsets ignored);
* boundary conditions, every figure: **motors held** (each proximal link clamped at its
  shoulder axis B in all six DOFs: shoulder shafts locked by the servo, motor bearings,
  waist bracket and waist motor shaft rigid: the waist held), **pen end free** (load at E,
  no support there). Behind a capstan (issue 35) the motor is held and its rope yields: a
  shoulder link turns at B about the plane's normal on the rope's torsional spring
  k_q = EA (2 / L) r_d^2 (:func:`cad.structure.device.motor_rope_stiffness_Nm_per_rad`), and a
  waist rope lets the whole arm turn about its waist axis (the frame's x axis, through both B)
  on its k_q: both B nodes share that rotation (the waist bracket rigid, :func:`arm_supports`).
  The waist body's inertia about that axis (bracket and shoulder motors) is not in the frame
  (it carries the links' masses only): with a waist rope the out-of-plane mode is an upper
  bound;
* masses: each link body of the build report (``report["bodies"]``, link frames) as the
  pantographs' (:func:`cad.structure.pantograph.lumped_from_bodies`: tube along the beam,
  the rest split between the two joints by the lever rule); at E the arm's gimbal (yoke
  and ring bodies) and its **share of the pen rod** by the lever rule between the two gimbal
  points (the ``pen`` body's mass and COM along the pen: arm B carries ``m x_c / l6``, arm A
  the rest);
* poses: the poses of the build's interference check (:func:`cad.families.pen.layout.motion_task`:
  home, the box corners at the rotation extremes, the rotation corners at the centre).

Approximation: planar, per pantograph. The two arms are coupled through the pen (the rod
carries the force along it from one arm's end to the other's); each arm here carries only
its lever-rule share of the rod. With the rod, gimbals and waists rigid, the coupled
system's first mode lies at or above the lower of the two arms' (Rayleigh: a coupled
shape's quotient (U_A + U_B) / (T_A + T_B) is at least the smaller of the two arms'
quotients, each at least its arm's first eigenvalue; the two lever-rule point masses have
the rod's mass and first moment and, for the part of its mass lying along the rod between
the gimbals, at least its moment of inertia about its COM (Bhatia-Davis: variance <=
(l6 - x_c) x_c; the hubs' small extent across the rod is left out), so they over-count its
kinetic energy; its spin about its own axis is a free mechanism DOF), so the
device's first mode is reported as the lower of the two. Not modelled: the rod's bending,
the gimbals' and the waist brackets' compliance (the out-of-plane figures hold the waist
rigid).

Figures: ``first_mode_Hz`` = min over arms and poses of the lowest in-plane and
out-of-plane modes (:func:`cad.structure.graph.plane_modes`); ``compliance_um_per_N``
{vertical, radial, normal} at the pen end, worst over arms and poses, and ``home`` per arm;
``max_stress_MPa``: von Mises beam stress under :func:`end_force_N` at the pen end in the
worst of :func:`cad.structure.graph.directions`; ``per_arm``: each arm's figures.
"""

from __future__ import annotations

import math

import numpy as np

from cad.datasheet.limits import STRESS_SAFETY_FACTOR
from cad.families.pen.layout import motion_task
from cad.kinematics import fivebar as fb5
from cad.kinematics import haptic_pen as hp
from cad.structure.device import motor_rope_stiffness_Nm_per_rad, tube_section
from cad.structure.elastic import get_elastic
from cad.structure.graph import (
    Beam,
    LinkGraph,
    Lumped,
    directions,
    frame_at,
    plane_modes,
    worst_stress_Pa,
)
from cad.structure.pantograph import lumped_from_bodies, tube_mass_kg

ARMS = ("A", "B")
SIDES = ("lower", "upper")
#: Modes searched for the lowest in-plane and out-of-plane ones.
MODES = 12
#: Compliance axes of the frame: x = world z (vertical), y = rho (radial), z = plane normal.
AXES = ("vertical", "radial", "normal")


def end_force_N(force_N: float, moment_arm_mm: float, pen_mm: float) -> float:
    """Largest force (N) one pen end carries under the design wrench at the pen centre: a
    force ``force_N`` in any direction and a moment ``force_N moment_arm_mm`` about any axis
    normal to the pen. Statics of a rod between two ball joints: the transverse force splits
    in halves and the moment adds +-M / l6 at each end; the force along the rod may go all to
    one arm (statically indeterminate: upper bound). With s the transverse part and
    b = M / l6, |f|^2 = (s / 2 + b)^2 + F^2 - s^2, greatest at s = min(2 b / 3, F)."""
    F = float(force_N)
    b = F * float(moment_arm_mm) / float(pen_mm)
    s = min(2.0 * b / 3.0, F)
    return math.sqrt((s / 2 + b) ** 2 + F * F - s * s)


def arm_graph(design, arm: str) -> tuple[LinkGraph, dict[str, float]]:
    """One arm's links as a :class:`~cad.structure.graph.LinkGraph` (module docstring; link
    names those of the build's bodies, ``A_proximal_lower`` ...) and ``{link: length_mm}``."""
    p = design.parts
    et = get_elastic(p.tube_material, "parts.tube_material")
    A = tube_section(p, et.E_Pa, et.G_Pa, 0.0).A
    pen = design.mechanism
    joints, beams, ties, lengths = {}, [], [], {}
    for side in SIDES:
        for kind, a, b, L in (("proximal", "B", "C", pen.proximal_mm), ("distal", "C", "E", pen.distal_mm)):
            link = f"{arm}_{kind}_{side}"
            lengths[link] = float(L)
            joints[link] = {a: np.zeros(2), b: np.array([float(L), 0.0])}
            rho = tube_mass_kg(design, L) / (A * L * 1e-3)
            beams.append(Beam(link, a, b, tube_section(p, et.E_Pa, et.G_Pa, rho)))
        ties.append(((f"{arm}_proximal_{side}", "C"), (f"{arm}_distal_{side}", "C")))
    ties.append(((f"{arm}_distal_lower", "E"), (f"{arm}_distal_upper", "E")))
    fixed, springs, waist_tie = arm_supports(design, arm)
    return LinkGraph(joints, beams, ties + waist_tie, fixed, (f"{arm}_distal_lower", "E"), springs), lengths


def arm_supports(design, arm: str) -> tuple[dict, dict, list]:
    """(fixed, springs, ties) of one arm's shoulder supports B (module docstring): clamped in
    all six DOFs with direct drive; behind a capstan (:func:`cad.structure.device.motor_rope_stiffness_Nm_per_rad`,
    the motor held) a shoulder link turns about the plane's normal (DOF 5) on its rope's
    torsional spring k_q, and a waist rope lets the two B nodes (both on the waist axis, the
    frame's x axis) turn together about that axis (DOF 3, one tie: the rigid waist bracket) on
    the waist rope's k_q."""
    ropes = motor_rope_stiffness_Nm_per_rad(design)
    k_waist = ropes.get(f"{arm}_q_waist")
    fixed, springs = {}, {}
    for side in SIDES:
        node = (f"{arm}_proximal_{side}", "B")
        k = ropes.get(f"{arm}_q_{side}")
        fixed[node] = tuple(d for d in range(6) if not (d == 5 and k is not None) and not (d == 3 and k_waist is not None))
        if k is not None:
            springs[(*node, 5)] = k
    if k_waist is None:
        return fixed, springs, []
    springs[(f"{arm}_proximal_lower", "B", 3)] = k_waist
    return fixed, springs, [((f"{arm}_proximal_lower", "B"), (f"{arm}_proximal_upper", "B"))]


def pen_share_kg(design, bodies: dict) -> dict[str, float]:
    """``{"A": kg, "B": kg}``: the pen rod's mass split between the two gimbal points by the
    lever rule (``bodies["pen"]``: mass and COM in the pen frame, origin at arm A's end, x
    along the pen; the COM clamped to the rod)."""
    b = bodies.get("pen")
    if b is None:
        return {"A": 0.0, "B": 0.0}
    m, l6 = float(b["mass_kg"]), float(design.mechanism.pen_mm)
    xb = min(max(float(b["com_mm"][0]) / l6, 0.0), 1.0)
    return {"A": m * (1 - xb), "B": m * xb}


def arm_lumped(design, graph: LinkGraph, bodies: dict, lengths: dict, arm: str) -> tuple[list[Lumped], float]:
    """The arm's point masses (module docstring) and the mass at its pen end E (kg)."""
    out = lumped_from_bodies(graph, bodies, lengths)
    m_end = pen_share_kg(design, bodies)[arm]
    m_end += sum(float(bodies[k]["mass_kg"]) for k in (f"{arm}_yoke", f"{arm}_ring") if k in bodies)
    out.append(Lumped(f"{arm}_distal_lower", (lengths[f"{arm}_distal_lower"], 0.0), m_end))
    return out, m_end


def arm_poses(design, X: np.ndarray, arm: str) -> dict[str, np.ndarray]:
    """``{link: (N, 3, 3)}`` planar transforms (mm) of one arm's links in its plane (x = world
    z, y = rho) at the pen poses ``X`` (N, 5); ValueError when a pose cannot be reached."""
    pen = design.mechanism
    X = np.atleast_2d(np.asarray(X, float))
    if np.any(hp.ik(pen, X)[1] != 0):
        raise ValueError("a pen pose cannot be reached")
    sign = -1.0 if arm == "A" else 1.0
    u = hp.pen_directions(X[:, 3], X[:, 4])[0]
    P = X[:, :3] + sign * pen.pen_mm / 2 * u
    ez, rho = P[:, 2], np.hypot(P[:, 0] - sign * pen.l4_mm / 2, P[:, 1])
    l1, l2, l3 = pen.shoulder_base_mm, pen.proximal_mm, pen.distal_mm
    _, _, c1x, c1y, c2x, c2y, _ = fb5.ik_arrays(-l1 / 2, 0.0, l1 / 2, 0.0, l2, l2, l3, l3, 1.0, -1.0, ez, rho)

    def rz(ox, oy, tx, ty):
        a = np.arctan2(ty - oy, tx - ox)
        T = np.zeros((len(a), 3, 3))
        T[:, 0, 0], T[:, 0, 1], T[:, 1, 0], T[:, 1, 1] = np.cos(a), -np.sin(a), np.sin(a), np.cos(a)
        T[:, 0, 2], T[:, 1, 2], T[:, 2, 2] = ox, oy, 1.0
        return T

    out = {}
    for side, bx, cx, cy in (("lower", -l1 / 2, c1x, c1y), ("upper", l1 / 2, c2x, c2y)):
        out[f"{arm}_proximal_{side}"] = rz(np.full(len(X), bx), np.zeros(len(X)), cx, cy)
        out[f"{arm}_distal_{side}"] = rz(cx, cy, ez, rho)
    return out


def arm_at(graph: LinkGraph, lumped: list[Lumped], tf: dict, force_N: float, dirs: np.ndarray) -> dict:
    """One arm's figures at one pose: ``compliance_um_per_N`` {vertical, radial, normal},
    ``in_plane_Hz``, ``out_of_plane_Hz``, ``stress_MPa`` (per element, worst of ``dirs``
    under ``force_N`` at E) and ``links`` (the element's link per element)."""
    fr, ids = frame_at(graph, tf, lumped)
    P = ids[graph.handle]
    c = {}
    for i, ax in enumerate(AXES):
        u = fr.solve({P: np.r_[np.eye(3)[i], 0, 0, 0]})
        c[ax] = float(u[6 * P + i]) * 1e6
    sig, _ = worst_stress_Pa(fr, P, force_N, dirs)
    return {"compliance_um_per_N": c, **plane_modes(fr, MODES), "stress_MPa": sig * 1e-6,
            "links": [e[3] for e in fr.elements]}


def analyse(design, bodies: dict, force_N: float) -> dict:
    """The ``structure`` figures of a haptic pen (module docstring).

    bodies: ``report["bodies"]`` ({body: {"mass_kg", "com_mm"}}, body frames of
    :func:`cad.families.pen.layout.body_poses`); force_N: ``[actuators] force_max_N`` (N),
    with ``[actuators] moment_arm_mm`` giving the end load :func:`end_force_N`. Raises
    ValueError naming the first pose the arms cannot reach."""
    X, labels = motion_task(design)
    arm_mm = float(design.actuators.get("moment_arm_mm", design.mechanism.pen_mm / 2))
    f_end = end_force_N(force_N, arm_mm, design.mechanism.pen_mm)
    strength = get_elastic(design.parts.tube_material, "parts.tube_material").strength_MPa
    dirs = directions()
    per_arm, crit = {}, (0.0, "", "", "")
    worst = dict.fromkeys(AXES, 0.0)
    for arm in ARMS:
        g, lengths = arm_graph(design, arm)
        lumped, m_end = arm_lumped(design, g, bodies, lengths, arm)
        try:
            poses = arm_poses(design, X, arm)
        except ValueError:
            raise ValueError(f"structure: a pose of {', '.join(labels)} cannot be reached") from None
        mine = {"in_plane_Hz": math.inf, "out_of_plane_Hz": math.inf, "end_mass_g": m_end * 1e3}
        for k, lab in enumerate(labels):
            r = arm_at(g, lumped, {n: v[k] for n, v in poses.items()}, f_end, dirs)
            if k == 0:
                mine["home_compliance_um_per_N"] = r["compliance_um_per_N"]
            for ax in AXES:
                worst[ax] = max(worst[ax], r["compliance_um_per_N"][ax])
            for key in ("in_plane_Hz", "out_of_plane_Hz"):
                if r[key] < mine[key]:
                    mine[key], mine[f"{key}_pose"] = r[key], lab
            i = int(np.argmax(r["stress_MPa"]))
            if r["stress_MPa"][i] > crit[0]:
                crit = (float(r["stress_MPa"][i]), r["links"][i], lab, arm)
        mine["first_mode_Hz"] = min(mine["in_plane_Hz"], mine["out_of_plane_Hz"])
        per_arm[arm] = mine
    low = min(ARMS, key=lambda a: per_arm[a]["first_mode_Hz"])
    return {
        "first_mode_Hz": per_arm[low]["first_mode_Hz"], "first_mode_arm": low,
        "first_mode_in_plane_Hz": min(per_arm[a]["in_plane_Hz"] for a in ARMS),
        "first_mode_out_of_plane_Hz": min(per_arm[a]["out_of_plane_Hz"] for a in ARMS),
        "compliance_um_per_N": worst, "max_stress_MPa": crit[0], "critical_link": crit[1],
        "critical_pose": crit[2], "strength_MPa": strength,
        "stress_limit_MPa": strength / STRESS_SAFETY_FACTOR, "force_N": float(force_N),
        "end_force_N": f_end, "moment_arm_mm": arm_mm, "pen_share_kg": pen_share_kg(design, bodies),
        "poses": list(labels), "per_arm": per_arm, "method": "beam",
        "rope_stiffness_Nm_per_rad": motor_rope_stiffness_Nm_per_rad(design),
    }
