"""Handle compliance, first modes and peak stress of a 5-bar pantograph or a twin-pantograph
mouse (numpy, no CAD): their link graph on the one frame of :mod:`cad.structure.graph`.

Model (world = the kinematic base frame, SI inside, mm / g / um at the edges):

* links: every proximal (B -> C) and distal (C -> E) link one beam joint to joint with the
  carbon tube's annulus (:func:`cad.structure.device.tube_section`, ``parts.tube_material``;
  the aluminium clevises, stiffer than the tube, are not credited: conservative), the
  mouse's crankshaft one beam from the main journal to the crank pin with the web's
  rectangle (``web_width_mm`` x ``parts.crank_thickness_mm``, ``parts.crank_material``);
* joints: C of each arm and E a revolute tie (every DOF but the rotation about z; rigid pins
  and bearings in the frame, the stacked layers' z offsets ignored: one plane); the mouse's
  two E points tie to the crankshaft's journal (knob pantograph) and pin (crank pantograph);
* boundary conditions, every figure: **motors held** (each proximal link clamped at its
  motor's axis B in all six DOFs: shaft locked by the servo, motor bearings rigid; a 5-bar
  link driven through a capstan turns on its own axle at B, held in the five other DOFs,
  its turn about z held by the rope's two free runs, a torsional spring k_q =
  EA (2 / L) r_d^2 (:func:`cad.structure.device.motor_rope_stiffness_Nm_per_rad`) in
  series with the held motor),
  **handle free** (loads at E / the main journal, no support there);
* masses: from the build's bodies (``report["bodies"]``: mass and COM of every moving body
  in its link frame): the tube's (the crankshaft's web's) own mass spread along its beam,
  the rest of the body (the clevises, pins, bearings, knob, screws) split between the link's
  two joints by the lever rule so that the body's mass and first moment are kept; the plain
  5-bar's handle body a point mass at E;
* poses: home and the four corners of the workspace square (the mouse at its home crank
  angle ``home_theta_deg``); a pose the mechanism cannot reach is skipped and named.

Figures (worst over the poses): ``first_mode_in_plane_Hz`` and ``first_mode_out_of_plane_Hz``
(:func:`cad.structure.graph.plane_modes`), ``first_mode_Hz`` the lower of the two;
``compliance_um_per_N`` {x, y, z} at the handle along the world axes; ``max_stress_MPa``:
von Mises beam stress under ``force_N`` at the handle in the worst of
:func:`cad.structure.graph.directions`, at the element with the highest stress / strength
(``critical_link``, ``strength_MPa`` of its material); ``per_pose``: the same figures at each
pose (and ``max_stress_in_plane_MPa``, in-plane directions only); ``bearing_compliance_estimate``: the
radial compliance of the ball bearings at C and E the rigid ties leave out (Palmgren,
:func:`cad.structure.bearings.radial_deflection_mm`; distal links two-force members, each
clevis two bearings sharing the load), not added to the frame's compliance.
"""

from __future__ import annotations

import math

import numpy as np

from cad.data.materials import get_material
from cad.datasheet.limits import STRESS_SAFETY_FACTOR
from cad.isotropy.gii import workspace_half_mm
from cad.kinematics import fivebar as fb5
from cad.kinematics import twin_pantograph as tw
from cad.structure.bearings import ball_set, radial_deflection_mm
from cad.structure.device import motor_rope_stiffness_Nm_per_rad, tube_section
from cad.structure.elastic import get_elastic
from cad.structure.frame import Section, rect_torsion_J
from cad.structure.graph import (
    Beam,
    LinkGraph,
    Lumped,
    directions,
    frame_at,
    plane_modes,
    worst_stress_Pa,
)

#: The crankshaft web's width floor (mm) where a report gives no ``web_width_mm``
#: (:func:`cad.families.pantograph.layout.layout`: max(bearing bore + 6, 10)).
WEB_WIDTH_MIN_MM = 10.0
#: Modes searched for the lowest in-plane and out-of-plane ones.
MODES = 12
SIDES = ("left", "right")


def groups(design) -> list[tuple[str, object]]:
    """``[(body prefix, FiveBar)]``: the plain 5-bar's one group, the mouse's knob and crank."""
    if design.family == "twin-pantograph":
        return [("knob_", design.mechanism.knob), ("crank_", design.mechanism.crank)]
    return [("", design.mechanism)]


def poses(design) -> tuple[np.ndarray, tuple[str, ...]]:
    """Task points of the structure poses (N, 2) mm or, for the mouse, (N, 3) mm, mm, rad:
    home and the four corners of the workspace square; and their labels."""
    ws = design.workspace
    home = np.asarray(ws.get("home_mm", ws["center_mm"]), float)
    (cx, cy), (hx, hy) = ws["center_mm"], workspace_half_mm(ws)
    pts = [home, *[np.array([cx + sx * hx, cy + sy * hy]) for sy in (-1, 1) for sx in (-1, 1)]]
    labels = ("home", "corner -x -y", "corner +x -y", "corner -x +y", "corner +x +y")
    if design.family == "twin-pantograph":
        th = math.radians(ws["home_theta_deg"])
        pts = [np.r_[p, th] for p in pts]
    return np.array(pts), labels


def tube_and_crank_sections(design, web_width_mm: float, rho_tube: float) -> tuple[Section, Section]:
    """(tube section with density ``rho_tube``, crankshaft web section), SI."""
    p = design.parts
    et = get_elastic(p.tube_material, "parts.tube_material")
    tube = tube_section(p, et.E_Pa, et.G_Pa, rho_tube)
    ec = get_elastic(p.crank_material, "parts.crank_material")
    w, t = web_width_mm * 1e-3, p.crank_thickness_mm * 1e-3
    web = Section(A=w * t, Iz=t * w**3 / 12, Iy=w * t**3 / 12, J=rect_torsion_J(w, t), cy=w / 2,
                  cz=t / 2, t_torsion=min(w, t), E=ec.E_Pa, G=ec.G_Pa,
                  rho=get_material(p.crank_material).density_kg_m3)
    return tube, web


def tube_mass_kg(design, length_mm: float) -> float:
    """Mass (kg) of the tube of a link ``length_mm`` joint to joint: the tube runs from
    ``clevis_length_mm - socket_depth_mm`` after the first joint to as far before the second
    (:mod:`cad.families.pantograph.placement`)."""
    p = design.parts
    L = length_mm - 2 * (p.clevis_length_mm - p.socket_depth_mm)
    A = math.pi * (p.tube_od_mm**2 - p.tube_id_mm**2) / 4
    return get_material(p.tube_material).density_kg_m3 * A * L * 1e-9


def link_graph(design, web_width_mm: float) -> tuple[LinkGraph, dict[str, float]]:
    """The moving links as a :class:`~cad.structure.graph.LinkGraph` (module docstring) with
    the tube's mass in the tube beams' density, and ``{link: length_mm}``."""
    et = get_elastic(design.parts.tube_material, "parts.tube_material")
    A = tube_section(design.parts, et.E_Pa, et.G_Pa, 0.0).A
    joints, beams, ties, fixed, lengths, springs = {}, [], [], {}, {}, {}
    ropes = motor_rope_stiffness_Nm_per_rad(design)
    web = tube_and_crank_sections(design, web_width_mm, 0.0)[1]
    for pre, fb in groups(design):
        for side in SIDES:
            for kind, a, b in (("proximal", "B", "C"), ("distal", "C", "E")):
                link = f"{pre}{kind}_{side}"
                L = float(getattr(fb, f"{kind}_{side}_mm"))
                lengths[link] = L
                joints[link] = {a: np.zeros(2), b: np.array([L, 0.0])}
                tube = tube_and_crank_sections(design, web_width_mm,
                                               tube_mass_kg(design, L) / (A * L * 1e-3))[0]
                beams.append(Beam(link, a, b, tube))
            k_rope = ropes.get(f"{pre}q_{side}")
            fixed[(f"{pre}proximal_{side}", "B")] = (0, 1, 2, 3, 4, 5) if k_rope is None else (0, 1, 2, 3, 4)
            if k_rope is not None:  # the link on its own axle, turned through its capstan's rope
                springs[(f"{pre}proximal_{side}", "B", 5)] = k_rope
            ties.append(((f"{pre}proximal_{side}", "C"), (f"{pre}distal_{side}", "C")))
        ties.append(((f"{pre}distal_left", "E"), (f"{pre}distal_right", "E")))
    handle = ("distal_left", "E")
    if design.family == "twin-pantograph":
        l6 = float(design.mechanism.crank_mm)
        joints["crankshaft"] = {"J": np.zeros(2), "K": np.array([l6, 0.0])}
        beams.append(Beam("crankshaft", "J", "K", web))
        lengths["crankshaft"] = l6
        ties += [(("knob_distal_left", "E"), ("crankshaft", "J")),
                 (("crank_distal_left", "E"), ("crankshaft", "K"))]
        handle = ("crankshaft", "J")
    return LinkGraph(joints, beams, ties, fixed, handle, springs), lengths


def lumped_from_bodies(graph: LinkGraph, bodies: dict, lengths: dict[str, float]) -> list[Lumped]:
    """Point masses (module docstring: lever rule of each body less its beam's own mass, the
    tube or the crankshaft's web, already spread along the beam) from ``report["bodies"]``
    (``{body: {"mass_kg", "com_mm"}}``, link frames)."""
    own = {b.link: b.section.rho * b.section.A * lengths[b.link] * 1e-3 for b in graph.beams}
    out = []
    for link, L in lengths.items():
        b = bodies.get(link)
        if b is None:
            continue
        m, xc = float(b["mass_kg"]), float(b["com_mm"][0])
        mt = own[link]
        rest = m - mt
        if rest <= 0:
            continue
        x = min(max((m * xc - mt * L / 2) / rest, 0.0), L)
        out += [Lumped(link, (0.0, 0.0), rest * (1 - x / L)), Lumped(link, (L, 0.0), rest * x / L)]
    if "handle" in bodies and "distal_left" in lengths:  # plain 5-bar: handle pin and knob translate with E
        out.append(Lumped("distal_left", (lengths["distal_left"], 0.0), float(bodies["handle"]["mass_kg"])))
    return out  # the mouse's crankshaft (with the knob) is a link of the graph: lever rule above


def link_poses(design, X: np.ndarray) -> dict[str, np.ndarray]:
    """``{link: (N, 3, 3)}`` planar world transforms (mm) at the task points ``X``; raises
    ValueError naming a point the mechanism cannot reach (non-zero IK status)."""
    X = np.atleast_2d(np.asarray(X, float))
    if design.family == "twin-pantograph":
        ik = tw.ik(design.mechanism, X)
        grp = [("knob_", ik.knob), ("crank_", ik.crank)]
    else:
        ik = fb5.ik(design.mechanism, X[:, :2])
        grp = [("", ik)]
    if np.any(np.asarray(ik.status) != 0):
        raise ValueError(f"{int(np.sum(np.asarray(ik.status) != 0))} of {len(X)} points cannot be reached")

    def rz(a, x, y):
        c, s = np.cos(a), np.sin(a)
        T = np.zeros((len(a), 3, 3))
        T[:, 0, 0], T[:, 0, 1], T[:, 1, 0], T[:, 1, 1] = c, -s, s, c
        T[:, 0, 2], T[:, 1, 2], T[:, 2, 2] = x, y, 1.0
        return T

    out = {}
    for (pre, fp), (_, fb) in zip(grp, groups(design), strict=True):
        E = fp.E_mm
        for i, (side, C) in enumerate((("left", fp.C_left_mm), ("right", fp.C_right_mm))):
            B = getattr(fb, f"base_{side}_mm")
            out[f"{pre}proximal_{side}"] = rz(fp.q_rad[:, i], np.full(len(X), B[0]), np.full(len(X), B[1]))
            out[f"{pre}distal_{side}"] = rz(np.arctan2(E[:, 1] - C[:, 1], E[:, 0] - C[:, 0]), C[:, 0], C[:, 1])
    if design.family == "twin-pantograph":
        out["crankshaft"] = rz(X[:, 2], X[:, 0], X[:, 1])
    return out


def bearing_compliance(design, X: np.ndarray, force_N: float) -> dict:
    """Handle compliance (um/N, secant at ``force_N``) the rigid ties leave out: Palmgren's
    radial deflection of the distal clevises' ball bearings at C and E (two per clevis sharing
    the load), the distal links two-force members (rigid-link statics, motors held:
    F = s_L u_L + s_R u_R, u_i the unit vector C_i -> E), handle displacement by virtual work
    u = sum_i 2 |s_i| delta_r(F |s_i| / 2); worst of x and y over the poses. The mouse: the
    knob pantograph alone carries the force (the crank pantograph's parallel path through
    the crankshaft neglected: an upper bound)."""
    Z, dw = ball_set(design.parts.bearing)
    fb = groups(design)[0][1]
    ik = fb5.ik(fb, np.atleast_2d(X)[:, :2])
    worst = {"x": 0.0, "y": 0.0}
    for k in range(len(ik.E_mm)):
        U = np.array([ik.E_mm[k] - ik.C_left_mm[k], ik.E_mm[k] - ik.C_right_mm[k]])
        U /= np.linalg.norm(U, axis=1)[:, None]
        for ax, f in (("x", np.array([1.0, 0.0])), ("y", np.array([0.0, 1.0]))):
            s = np.linalg.solve(U.T, f)  # per newton
            u_mm = float(sum(2 * abs(si) * radial_deflection_mm(force_N * abs(si) / 2, Z, dw) for si in s))
            worst[ax] = max(worst[ax], u_mm / force_N * 1e3)
    return {"x_um_per_N": worst["x"], "y_um_per_N": worst["y"], "force_N": force_N,
            "bearing": design.parts.bearing, "balls": Z, "ball_diameter_mm": dw,
            "included_in_compliance_um_per_N": False}


def pose_frames(design) -> list[tuple[str, dict]]:
    """``[(pose label, {link: 4x4 world transform})]`` of the reachable structure poses
    (:func:`poses`; an unreachable one left out)."""
    X, labels = poses(design)
    out = []
    for k, lab in enumerate(labels):
        try:
            out.append((lab, {n: v[0] for n, v in link_poses(design, X[k:k + 1]).items()}))
        except ValueError:
            continue
    return out


def first_modes(design, bodies: dict, web_width_mm: float, frames=None) -> dict:
    """Lowest in-plane and out-of-plane modes (Hz) over the poses, and where: the modes of
    :func:`analyse` alone (no compliance, no stress), for searches over link sections.
    ``frames``: :func:`pose_frames` of a design with the same link lengths (computed when
    None). Returns ``{"in_plane_Hz", "out_of_plane_Hz", "first_mode_Hz", "pose", "plane"}``."""
    g, lengths = link_graph(design, web_width_mm)
    lumped = lumped_from_bodies(g, bodies, lengths)
    best = {"in_plane_Hz": (math.inf, ""), "out_of_plane_Hz": (math.inf, "")}
    for lab, tf in frames if frames is not None else pose_frames(design):
        fr, _ = frame_at(g, tf, lumped)
        for key, f in plane_modes(fr, MODES).items():
            if key in best and f < best[key][0]:
                best[key] = (f, lab)
    plane = min(best, key=lambda k: best[k][0])
    return {"in_plane_Hz": best["in_plane_Hz"][0], "out_of_plane_Hz": best["out_of_plane_Hz"][0],
            "first_mode_Hz": best[plane][0], "pose": best[plane][1],
            "plane": "in plane" if plane == "in_plane_Hz" else "out of plane"}


def analyse(design, bodies: dict, force_N: float, web_width_mm: float) -> dict:
    """The ``structure`` figures of a pantograph-family design (module docstring).

    bodies: ``report["bodies"]`` ({body: {"mass_kg", "com_mm"}}, link frames); force_N: the
    handle force of the stress figure (N); web_width_mm: the mouse's crankshaft web width
    (``report["layout_mm"]["web_width_mm"]``; unused for the plain 5-bar)."""
    g, lengths = link_graph(design, web_width_mm)
    lumped = lumped_from_bodies(g, bodies, lengths)
    X, labels = poses(design)
    strength = {"tube": get_elastic(design.parts.tube_material, "parts.tube_material").strength_MPa,
                "crankshaft": get_elastic(design.parts.crank_material, "parts.crank_material").strength_MPa}
    dirs = directions()
    used, skipped, per_pose = [], [], {}
    c = {"x": 0.0, "y": 0.0, "z": 0.0}
    modes = {"in_plane_Hz": math.inf, "out_of_plane_Hz": math.inf}
    crit = (-1.0, 0.0, "", 0.0, "")  # (utilisation, stress MPa, link, strength, pose)
    for k, lab in enumerate(labels):
        try:
            tf = {n: v[0] for n, v in link_poses(design, X[k:k + 1]).items()}
        except ValueError:
            skipped.append(lab)
            continue
        used.append(lab)
        fr, ids = frame_at(g, tf, lumped)
        P = ids[g.handle]
        here = {"compliance_um_per_N": {}}
        for i, ax in enumerate("xyz"):
            u = fr.solve({P: np.r_[np.eye(3)[i], 0, 0, 0]})
            here["compliance_um_per_N"][ax] = float(u[6 * P + i]) * 1e6
            c[ax] = max(c[ax], here["compliance_um_per_N"][ax])
        here.update(plane_modes(fr, MODES))
        for key in modes:
            modes[key] = min(modes[key], here[key])
        sig, _ = worst_stress_Pa(fr, P, force_N, dirs)
        here["max_stress_MPa"] = float(sig.max()) * 1e-6
        here["max_stress_in_plane_MPa"] = float(worst_stress_Pa(fr, P, force_N, dirs[dirs[:, 2] == 0])[0].max()) * 1e-6
        per_pose[lab] = here
        for e, sv in zip(fr.elements, sig * 1e-6, strict=True):
            st = strength["crankshaft" if e[3] == "crankshaft" else "tube"]
            if sv / st > crit[0]:
                crit = (sv / st, float(sv), e[3], st, lab)
    _, smax, link, st, at = crit
    return {
        "compliance_um_per_N": c,
        "first_mode_in_plane_Hz": modes["in_plane_Hz"],
        "first_mode_out_of_plane_Hz": modes["out_of_plane_Hz"],
        "first_mode_Hz": min(modes.values()),
        "max_stress_MPa": smax, "critical_link": link, "critical_pose": at, "strength_MPa": st,
        "stress_limit_MPa": st / STRESS_SAFETY_FACTOR, "force_N": float(force_N),
        "poses": used, "poses_skipped": skipped, "per_pose": per_pose, "method": "beam",
        "tube_material": design.parts.tube_material,
        "rope_stiffness_Nm_per_rad": motor_rope_stiffness_Nm_per_rad(design),
        "bearing_compliance_estimate": bearing_compliance(design, X[[labels.index(x) for x in used]], force_N),
    }
