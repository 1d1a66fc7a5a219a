"""Handle compliance, first resonance and peak stress of a four-bar from its parts.

Model (R0, SI inside, mm / g / um at the edges). Each moving link is a chain of beams
between its joints (crank A1-A2; coupler A2-A3 and the hull edges to P; rocker A4-A3),
its section the bar's plate (tube bars, ``bar_style = "tube"``: the tube's annulus,
:func:`tube_section`, the clevises point masses at their joints): width w, thickness t, and where the bar is pocketed
(``bar_pockets`` and a pocket wider than 2 mm) the two webs either side of the slot:
A = (w - wp) t, Iz (in plane) = t (w^3 - wp^3) / 12, Iy (out of plane) = (w - wp) t^3 / 12,
J = 2 J_rect(web, t). Joints A2, A3 tie the links in every DOF but the rotation about z
(rigid pins; bd_warehouse's SKT table carries no bearing stiffness, so bearing radial
compliance is not included). Supports: the crank is clamped at A1 (motor shaft held by
the servo, its compliance not modelled; through a capstan with the rope's ``cable_EA_N`` the
crank's rotation at A1 is held by the rope's torsional spring k_q instead,
:func:`crank_rope_stiffness_Nm_per_rad`, ``crank_rope_stiffness_Nm_per_rad`` in the report)
and the rocker pinned at A4 (rigid post).

Two methods, same frame (:mod:`cad.structure.frame`):

* ``beam`` -- Euler-Bernoulli with the pocket section over every beam's whole length
  (closed form, ~ms);
* ``fem`` -- each beam's in-plane and out-of-plane bending stiffness taken from a
  plane-stress finite-element cantilever of the real bar segment (scikit-fem,
  :mod:`cad.structure.fem`: solid ends around the joints, the slot, shear), i.e.
  E I_eff = L^3 / (3 c_fem).

Loads: ``force_N`` at P along the path direction x (path frame) and out of plane z, at
three crank angles (range ends and middle); the report gives the worst.
Masses: each link's bar mass spread evenly along its beams, every other part (bearings,
pins, spacers, handle, screws) as a point mass at the nearest node of its link.

``structure`` (report.json): ``compliance_um_per_N`` {x, z}, ``first_mode_Hz`` (lowest
natural frequency of the frame with its masses), ``handle_mode_x_Hz`` (the frame mode that
contributes most to the handle's static compliance along x, largest phi_Px^2 / w^2 over the
lowest :data:`HANDLE_MODES` mass-normalized modes; lowest over the poses): every figure with
the same boundary conditions, crank held at A1 (it used to put the crank-free apparent mass
M11 on the crank-held path stiffness),
``max_stress_MPa`` (von Mises, beam stresses at ``force_N``), ``strength_MPa``,
``method``, ``limits`` and ``ok``; and, separate from those (not added to them),
``bearing_compliance_estimate``: the handle compliance along x the rigid joints leave out,
Palmgren's closed form for the deep-groove bearings at A2/A3/A4
(:mod:`cad.structure.bearings`).
"""

from __future__ import annotations

import functools
import math

import numpy as np

# Default structural limits: defined with their reasons in cad.datasheet.limits, the one
# place of every default limit (overridable in [targets]: first_mode_Hz = { min = ... },
# max_stress_MPa = { max = ... }).
from cad.actuators.capstan import rope_stiffness_Nm_per_rad
from cad.data import catalog
from cad.data.materials import get_material
from cad.datasheet.limits import FIRST_MODE_MIN_HZ, STRESS_SAFETY_FACTOR
from cad.device import resolve_device
from cad.families.fourbar.pose import planar_transforms
from cad.kinematics.linkgeom import link_joints_mm
from cad.kinematics.metrics import path_frame
from cad.structure import fem
from cad.structure.bearings import bearing_compliance
from cad.structure.elastic import bar_elastic, get_elastic
from cad.structure.frame import Section, rect_torsion_J
from cad.structure.graph import Beam, LinkGraph, Lumped, frame_at  # noqa: F401 (Lumped: public here)

POSES = 3
METHODS = ("beam", "fem")
#: Modes searched for the handle's path mode.
HANDLE_MODES = 12


def bar_section(parts, E: float, G: float, rho: float) -> Section:
    """Section of a bar (module docstring), SI."""
    w, t = parts.bar_width_mm * 1e-3, parts.bar_thickness_mm * 1e-3
    wp = pocket_width_mm(parts) * 1e-3
    web = (w - wp) / 2 if wp > 0 else w
    J = rect_torsion_J(w, t) if wp == 0 else 2 * rect_torsion_J(web, t)
    return Section(
        A=(w - wp) * t, Iz=t * (w**3 - wp**3) / 12, Iy=(w - wp) * t**3 / 12, J=J,
        cy=w / 2, cz=t / 2, t_torsion=min(web, t), E=E, G=G, rho=rho,
    )


def tube_section(parts, E: float, G: float, rho: float) -> Section:
    """Section of a tube bar (``bar_style = "tube"``), SI: A = pi (D^2 - d^2) / 4,
    Iz = Iy = pi (D^4 - d^4) / 64, J = pi (D^4 - d^4) / 32 (thin or thick wall, exact)."""
    D, d = parts.tube_od_mm * 1e-3, parts.tube_id_mm * 1e-3
    i = math.pi * (D**4 - d**4) / 64
    return Section(A=math.pi * (D**2 - d**2) / 4, Iz=i, Iy=i, J=2 * i, cy=D / 2, cz=D / 2,
                   t_torsion=D / 2, E=E, G=G, rho=rho)


def link_material(parts) -> str:
    """Material of the beams between joints: the tube's for tube bars, else the plate's."""
    return parts.tube_material if parts.bar_style == "tube" else parts.bar_material


def link_section(parts, E: float, G: float, rho: float) -> Section:
    """The beam section of the bars' style (:func:`bar_section` or :func:`tube_section`)."""
    return (tube_section if parts.bar_style == "tube" else bar_section)(parts, E, G, rho)


def pocket_width_mm(parts) -> float:
    """Pocket width (mm) the bars get (0 without pockets), as :mod:`cad.parts.bars`."""
    wp = parts.bar_width_mm - 2 * parts.bar_pocket_web_mm
    return wp if parts.bar_pockets and wp >= 2.0 else 0.0


def link_edges(J: dict) -> dict[str, list[tuple[str, str]]]:
    """Beams of every moving link between its joint names (coupler: hull edges to P)."""
    c = J["coupler"]
    p, a2, a3 = c["P"], c["A2"], c["A3"]
    area2 = abs((a3[0] - a2[0]) * (p[1] - a2[1]) - (a3[1] - a2[1]) * (p[0] - a2[0]))
    if area2 > 1e-6 * max(1.0, float(np.linalg.norm(a3 - a2))) ** 2:
        cp = [("A2", "A3"), ("A3", "P"), ("A2", "P")]
    else:  # collinear: consecutive points along the line
        u = (a3 - a2) / np.linalg.norm(a3 - a2)
        names = sorted(("A2", "A3", "P"), key=lambda n: float((c[n] - a2) @ u))
        cp = [(names[0], names[1]), (names[1], names[2])]
    return {"crank": [("A1", "A2")], "coupler": cp, "rocker": [("A4", "A3")]}


def end_radius_mm(parts, joint: str) -> float:
    """Radius of the solid region around a joint before a pocket may start (mm)."""
    if joint == "P":
        return parts.handle_diameter_mm / 2 + parts.bar_pocket_web_mm
    if joint == "A1":
        return parts.hub_diameter_mm / 2 + parts.bar_pocket_web_mm
    return catalog.get_bearing(parts.bearing).D_mm / 2 + parts.bar_pocket_web_mm


def fem_section(parts, s: Section, L_mm: float, ends: tuple[str, str], nu: float) -> Section:
    """The beam section with E I_eff from plane-stress FE cantilevers of the real segment."""
    from dataclasses import replace

    cy, cz = _fem_compliances(parts, round(L_mm, 9), ends, s.E, nu)
    L = L_mm * 1e-3
    return replace(s, Iz=L**3 / (3 * s.E * cy), Iy=L**3 / (3 * s.E * cz))


@functools.lru_cache(maxsize=256)
def _fem_compliances(parts, L_mm: float, ends: tuple[str, str], E: float, nu: float):
    wp = pocket_width_mm(parts)
    a = max(end_radius_mm(parts, ends[0]), end_radius_mm(parts, ends[1]))
    slot = wp if (wp > 0 and L_mm - 2 * a > wp) else 0.0
    g = fem.BarGeometry(L_mm, parts.bar_width_mm, parts.bar_thickness_mm, slot, a if slot else 0.0)
    return fem.cached_cantilever(g, E, nu, "y"), fem.cached_cantilever(g, E, nu, "z")


def link_graph(design, bar_mass_kg: dict, method: str) -> LinkGraph:
    """The four-bar's moving links as a :class:`~cad.structure.graph.LinkGraph` (module
    docstring): crank clamped at A1, rocker pinned at A4, revolute joints A2 and A3, handle P.

    ``bar_mass_kg``: link -> bar mass spread along its beams; a link not in it gets the
    section area times the bar material's density."""
    parts = design.parts
    el = bar_elastic(parts)
    J = link_joints_mm(design.linkage)
    k_rope = crank_rope_stiffness_Nm_per_rad(design)
    beams = []
    edges = link_edges(J)
    for link, ed in edges.items():
        total_L = sum(float(np.linalg.norm(J[link][b] - J[link][a])) for a, b in ed) * 1e-3
        base = link_section(parts, el.E_Pa, el.G_Pa, 0.0)
        rho = (bar_mass_kg[link] / (base.A * total_L) if link in bar_mass_kg
               else get_material(link_material(parts)).density_kg_m3)
        for a, b in ed:
            s = link_section(parts, el.E_Pa, el.G_Pa, rho)
            if method == "fem" and parts.bar_style != "tube":  # a tube's beam is exact
                L_mm = float(np.linalg.norm(J[link][b] - J[link][a]))
                s = fem_section(parts, s, L_mm, (a, b), el.nu)
            beams.append(Beam(link, a, b, s))
    return LinkGraph(
        joints_mm={k: dict(v) for k, v in J.items()}, beams=beams,
        ties=[(("crank", "A2"), ("coupler", "A2")), (("coupler", "A3"), ("rocker", "A3"))],
        fixed={("crank", "A1"): (0, 1, 2, 3, 4, 5) if k_rope is None else (0, 1, 2, 3, 4),
               ("rocker", "A4"): (0, 1, 2, 3, 4)},
        handle=("coupler", "P"),
        springs={} if k_rope is None else {("crank", "A1", 5): k_rope})


def crank_rope_stiffness_Nm_per_rad(design) -> float | None:
    """The rope of a capstan on the crank as a torsional spring holding the crank's rotation at
    A1 (N m/rad, :func:`cad.actuators.capstan.rope_stiffness_Nm_per_rad`), the motor held by
    the servo, the rope's E A the resolved device's (the design's ``transmission.cable_EA_N``,
    else the rope catalog's); None for direct drive or a rope with no E A at all (the frame then
    holds the crank rigidly, as the datasheet says)."""
    t = resolve_device(design).transmission("crank")
    if not t.is_capstan or t.cable_EA_N is None:
        return None
    return rope_stiffness_Nm_per_rad(t.capstan_diameter_mm, t.drum_diameter_mm, t.cable_EA_N,
                                     t.centre_distance_mm)


def motor_rope_stiffness_Nm_per_rad(design) -> dict[str, float]:
    """``{motor joint: k_q}`` (N m/rad) of every motor of ``design`` driving its joint through a
    capstan whose rope has an E A: the two free runs as a torsional spring at the joint
    (:func:`cad.actuators.capstan.rope_stiffness_Nm_per_rad`, the resolved device's diameters,
    E A and centre distance), the motor held by its servo. Direct-drive joints (and ropes with
    no E A) are left out: the frame holds them rigidly. Any family's motors (the 5-bar's
    ``q_left`` / ``q_right``)."""
    out = {}
    for t in resolve_device(design).transmissions:
        if t.is_capstan and t.cable_EA_N is not None:
            out[t.motor_joint] = rope_stiffness_Nm_per_rad(
                t.capstan_diameter_mm, t.drum_diameter_mm, t.cable_EA_N, t.centre_distance_mm)
    return out


def build_frame(design, pose_tf: dict, lumped: list[Lumped], bar_mass_kg: dict, method: str):
    """The frame at one pose (``pose_tf``: link -> 3x3 planar transform, mm) and its P node
    (:func:`link_graph` posed by :func:`cad.structure.graph.frame_at`)."""
    g = link_graph(design, bar_mass_kg, method)
    fr, ids = frame_at(g, pose_tf, lumped)
    return fr, ids[g.handle]


def analyse(design, lumped: list[Lumped], bar_mass_kg: dict, method: str = "beam",
            M11_max_kg: float | None = None, targets=None, poses: int = POSES) -> dict:
    """The ``structure`` report (module docstring). ``targets``: the design's Target tuple
    (``first_mode_Hz`` min, ``max_stress_MPa`` max override the defaults, :func:`limits`)."""
    if method not in METHODS:
        raise ValueError(f"method: must be one of {METHODS}, got {method!r}")
    fb = design.linkage
    ex = path_frame(fb, design.phi1_min_rad, design.phi1_max_rad).x_hat
    phis = (np.linspace(design.phi1_min_rad, design.phi1_max_rad, poses) if poses > 1
            else np.array([0.5 * (design.phi1_min_rad + design.phi1_max_rad)]))
    tfs = planar_transforms(fb, phis)
    F = design.force_N
    cx = cz = smax = 0.0
    f1 = fx = math.inf
    for i in range(len(phis)):
        fr, P = build_frame(design, {k: v[i] for k, v in tfs.items()}, lumped, bar_mass_kg, method)
        ux = fr.solve({P: np.r_[ex[0], ex[1], 0, 0, 0, 0]})
        uz = fr.solve({P: np.r_[0, 0, 1.0, 0, 0, 0]})
        cx = max(cx, float(ux[6 * P:6 * P + 2] @ ex))
        cz = max(cz, float(uz[6 * P + 2]))
        smax = max(smax, F * float(max(fr.element_stress_Pa(ux).max(), fr.element_stress_Pa(uz).max())))
        freqs, shapes = fr.modes(HANDLE_MODES)
        f1 = min(f1, float(freqs[0]))
        px = shapes[:, 6 * P:6 * P + 2] @ ex  # handle displacement along x per mode
        fx = min(fx, float(freqs[int(np.argmax(px**2 / np.maximum(freqs, 1e-9) ** 2))]))
    strength = get_elastic(link_material(design.parts)).strength_MPa
    lim = limits(link_material(design.parts), targets)
    out = {
        "compliance_um_per_N": {"x": cx * 1e6, "z": cz * 1e6},
        "first_mode_Hz": f1,
        "max_stress_MPa": smax * 1e-6,
        "method": method,
        "strength_MPa": strength,
        "limits": lim,
        "bearing_radial_stiffness": ("not in the frame (joints rigid): bd_warehouse's bearing tables give "
                                     "no stiffness; see bearing_compliance_estimate"),
        "bearing_compliance_estimate": bearing_compliance(design, phis),
        "poses": len(phis),
    }
    k_rope = crank_rope_stiffness_Nm_per_rad(design)
    if k_rope is not None:  # the crank held at A1 through its capstan's rope
        out["crank_rope_stiffness_Nm_per_rad"] = k_rope
    el = bar_elastic(design.parts)
    if el.E_GPa != get_elastic(link_material(design.parts)).E_GPa:  # printed bars
        out["printed_bar_modulus"] = {"E_GPa": el.E_GPa, "source": el.source}
    out["handle_mode_x_Hz"] = fx
    out["ok"] = bool(f1 >= lim["first_mode_min_Hz"] and smax * 1e-6 <= lim["max_stress_max_MPa"])
    return out


def limits(material: str, targets=None) -> dict:
    """Structural limits: the defaults (module constants) unless the design's [targets]
    bound them: ``first_mode_Hz = { min = ... }``, ``max_stress_MPa = { max = ... }``."""
    lim = {"first_mode_min_Hz": FIRST_MODE_MIN_HZ,
           "max_stress_max_MPa": get_elastic(material).strength_MPa / STRESS_SAFETY_FACTOR}
    for t in targets or ():
        if t.key == "first_mode_Hz" and t.min is not None:
            lim["first_mode_min_Hz"] = float(t.min)
        if t.key == "max_stress_MPa" and t.max is not None:
            lim["max_stress_max_MPa"] = float(t.max)
    return lim


def lumped_from_assembly(asm, props: dict) -> tuple[list[Lumped], dict]:
    """Point masses (every moving part but the bars) and bar masses per link from the
    assembly's instances and their mass properties (:mod:`cad.families.fourbar.build`)."""
    lumped: list[Lumped] = []
    bars: dict[str, float] = {}
    for inst in asm.instances:
        mp = props.get(inst.kind.name)
        if mp is None or inst.body not in ("crank", "coupler", "rocker"):
            continue
        if (inst.kind.plate and inst.name == inst.body) or inst.name.startswith(f"{inst.body}_tube_"):
            bars[inst.body] = bars.get(inst.body, 0.0) + mp.mass_kg
            continue
        T = inst.tf_body_part
        c = T[:3, :3] @ np.asarray(mp.com_m) + T[:3, 3] * 1e-3
        lumped.append(Lumped(inst.body, (float(c[0]) * 1e3, float(c[1]) * 1e3), mp.mass_kg))
    return lumped, bars


def structure_of_build(design, asm, props: dict, M11_max_g: float, method: str = "fem") -> dict:
    """The ``structure`` entry of a build report (module docstring)."""
    lumped, bars = lumped_from_assembly(asm, props)
    return analyse(design, lumped, bars, method, M11_max_g * 1e-3, design.targets)
