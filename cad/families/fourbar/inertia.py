"""Inertia model of a four-bar design from its solids, without exports or interference.

What ``hapticad check`` and ``hapticad fit`` evaluate: the parts of every link
(the same assembly ``hapticad build`` makes, at ``fidelity="inertia"`` by default),
their exact mass properties, the link sums in the link frames, H11..H33
(Hoeken paper eqs 16-19 with the coupler COM angle) and the apparent mass (eq 22).

**Inertia budget.** Kinetic energy is additive over parts, so eq (14) splits
exactly into one term per part p (mass m, COM r at angle beta in its link frame,
Izz about its COM):

- crank part:   D_p = Izz + m |r|^2                       (rotation about A1)
- coupler part: D_p = m l1^2 + 2 m l1 |r| cos(phi1 - phi2 - beta) alpha1
                      + (Izz + m |r|^2) alpha1^2
- rocker part:  D_p = (Izz + m |r|^2) alpha3^2            (rotation about A4)
- motor rotor:  D_p = Jm

and M11_p = D_p * Jx^2 / |J|^4 (path frame), so the parts' M11 shares sum to M11
exactly (a test checks the sums). The budget lists each part's share of H11, H22,
H33, of H12 (component along the coupler's total COM direction) and of M11 at
mid-stroke and at the worst point (where M11 is largest).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from cad.checks import values_from_report
from cad.device import resolve_device
from cad.dynamics.inertia import apparent_mass_matrix, apparent_mass_summary, equivalent_inertia
from cad.families.fourbar import assemble
from cad.families.fourbar.build import inertia_from_links
from cad.kinematics.fourbar import jacobian_mm_per_rad, solve, velocity_ratios
from cad.kinematics.metrics import compute_metrics, path_frame
from cad.parts.part_cache import DeferredShape
from cad.parts.part_props import unit_volume_props
from cad.pipeline import build_design, family

LINKS = ("crank", "coupler", "rocker")


@dataclass(frozen=True)
class PartShare:
    """One part's mass properties in its link frame (SI)."""

    name: str
    kind: str
    link: str
    mass_kg: float
    com_link_m: np.ndarray
    Izz_com_kg_m2: float


def _planar(mass, com, izz):
    r2 = float(com[0] ** 2 + com[1] ** 2)
    return izz + mass * r2


def part_D(design, share: PartShare, pose, a2, a3) -> np.ndarray:
    """This part's term of D(phi1) (kg m^2), see the module docstring."""
    m, c, izz = share.mass_kg, share.com_link_m, share.Izz_com_kg_m2
    if share.link == "crank":
        return np.full(len(pose), _planar(m, c, izz))
    if share.link == "rocker":
        return _planar(m, c, izz) * a3**2
    l1 = design.linkage.l1_mm * 1e-3
    r = math.hypot(c[0], c[1])
    beta = math.atan2(c[1], c[0])
    return (m * l1**2 + 2.0 * m * l1 * r * np.cos(pose.phi1_rad - pose.phi2_rad - beta) * a2
            + _planar(m, c, izz) * a2**2)


def inertia_assembly(design, fidelity: str = "inertia"):
    """The four-bar's assembly as :func:`inertia_model` sees it
    (:func:`cad.families.fourbar.assemble` over the design's ``parts.interference_poses``
    crank angles, layers not strict): every part kind whose solid is not in memory yet is a
    :class:`cad.parts.part_cache.DeferredShape` (built or read only where its mass
    properties are not cached, :mod:`cad.parts.part_props`). Returns the
    :class:`cad.assembly.model.AssemblyModel`."""
    return assemble(design, fidelity, poses=design.parts.interference_poses, deferred=True)


def warm_part_cache(design, fidelity: str = "inertia", share: tuple[int, int] = (0, 1)) -> int:
    """Mass properties of the parts of ``design`` that integrate a solid -- of those (sorted
    by cache key, the same list in every process) every ``share[1]``-th from ``share[0]`` --
    made, validated and integrated unless cached, so that ``share[1]`` processes warm the
    shape and mass-property caches together, each part once (``hapticad sweep`` at worker
    start). Returns the number of parts of this share."""
    kinds = inertia_assembly(design, fidelity).kinds().values()
    todo = sorted({k.shape.key: k.shape for k in kinds
                   if k.inertia_model == "solid" and isinstance(k.shape, DeferredShape)}.items())
    mine = todo[share[0]::share[1]]
    for _, shape in mine:
        unit_volume_props(shape)
    return len(mine)


def inertia_model(design, fidelity: str = "inertia", samples: int = 401) -> dict[str, Any]:
    """Parts -> link mass properties -> H, apparent mass, per-part budget (module docstring).

    Returns a JSON-able dict: ``H11_kg_m2`` .. ``H33_kg_m2``, ``beta2_deg``, ``Jm_kg_m2``,
    ``apparent_mass`` (M11/M12/M22 ranges, g), ``links`` (``mass_g``, ``com_link_mm``,
    ``Izz_com_kg_m2`` per link), ``budget`` (rows per part), ``wall_s``.
    """
    t0 = time.perf_counter()
    parts = design.parts
    fb = design.linkage
    asm = inertia_assembly(design, fidelity)
    props = family.kind_props(asm.instances)
    link_props = family.body_props(asm.instances, props)
    # [motor] / parts overrides applied; through a capstan the crank feels n^2 Jm (cad.device)
    Jm = resolve_device(design).joint_rotor_inertia_kg_m2("crank")
    H, planar_links = inertia_from_links(design, link_props, Jm)

    shares: list[PartShare] = []
    for inst in asm.instances:
        mp = props[inst.kind.name]
        if mp is None or inst.body not in LINKS:
            continue
        T = inst.tf_body_part
        p = mp.transformed(T[:3, :3], T[:3, 3] * 1e-3)
        shares.append(PartShare(inst.name, inst.kind.name, inst.body, p.mass_kg, p.com_m,
                                float(p.inertia_com_kg_m2[2, 2])))

    phi = np.linspace(design.phi1_min_rad, design.phi1_max_rad, samples)
    pose = solve(fb, phi)
    a2, a3 = velocity_ratios(fb, pose)
    fr = path_frame(fb, design.phi1_min_rad, design.phi1_max_rad)
    Jp = fr.rotate(jacobian_mm_per_rad(fb, pose)) * 1e-3
    w11 = Jp[:, 0] ** 2 / np.einsum("ni,ni->n", Jp, Jp) ** 2  # M11 = D * w11
    M = apparent_mass_matrix(fb, pose, H, fr)
    D = equivalent_inertia(fb, pose, H)
    i_mid, i_worst = samples // 2, int(np.argmax(M[:, 0, 0]))
    l1 = fb.l1_mm * 1e-3
    budget = []
    for s in shares:
        d = part_D(design, s, pose, a2, a3)
        ip = _planar(s.mass_kg, s.com_link_m, s.Izz_com_kg_m2)
        beta = math.atan2(s.com_link_m[1], s.com_link_m[0])
        row = {"part": s.name, "kind": s.kind, "link": s.link, "mass_g": s.mass_kg * 1e3,
               "H11_kg_m2": ip if s.link == "crank" else (s.mass_kg * l1**2 if s.link == "coupler" else 0.0),
               "H12_kg_m2": (s.mass_kg * l1 * math.hypot(*s.com_link_m[:2]) * math.cos(beta - H.beta2_rad)
                             if s.link == "coupler" else 0.0),
               "H22_kg_m2": ip if s.link == "coupler" else 0.0,
               "H33_kg_m2": ip if s.link == "rocker" else 0.0,
               "M11_mid_g": float(d[i_mid] * w11[i_mid] * 1e3),
               "M11_worst_g": float(d[i_worst] * w11[i_worst] * 1e3)}
        budget.append(row)
    budget.append({"part": "motor rotor (Jm)", "kind": parts.motor, "link": "crank", "mass_g": 0.0,
                   "H11_kg_m2": Jm, "H12_kg_m2": 0.0, "H22_kg_m2": 0.0, "H33_kg_m2": 0.0,
                   "M11_mid_g": float(Jm * w11[i_mid] * 1e3), "M11_worst_g": float(Jm * w11[i_worst] * 1e3)})
    budget.sort(key=lambda r: -r["M11_worst_g"])
    return {
        "name": design.name, "fidelity": fidelity,
        **{k: v for k, v in H.as_dict().items()}, "Jm_kg_m2": Jm,
        "apparent_mass": apparent_mass_summary(M),
        "M11_mid_g": float(M[i_mid, 0, 0] * 1e3), "M11_worst_g": float(M[i_worst, 0, 0] * 1e3),
        "worst_phi1_deg": float(np.degrees(phi[i_worst])),
        "D_check_kg_m2": float(D[i_worst]),
        "D_min_kg_m2": float(D.min()), "D_max_kg_m2": float(D.max()),
        "links": {k: {"mass_g": link_props[k].mass_kg * 1e3,
                      "com_link_mm": (link_props[k].com_m * 1e3).tolist(),
                      "Izz_com_kg_m2": float(link_props[k].inertia_com_kg_m2[2, 2]),
                      "lG_mm": planar_links[k].lG_m * 1e3,
                      "beta_deg": math.degrees(planar_links[k].beta_rad)} for k in LINKS},
        "budget": budget,
        "wall_s": time.perf_counter() - t0,
    }


def target_values(design, fidelity: str, need_clearance: bool) -> tuple[dict, dict]:
    """(flat values for targets, inertia model report) of a four-bar design. ``need_clearance``:
    also build (no exports) for the interference sweep and the ``structure`` entry."""
    import tempfile
    from pathlib import Path

    model = inertia_model(design, fidelity=fidelity)
    m = compute_metrics(design.linkage, design.phi1_min_rad, design.phi1_max_rad,
                        force_N=design.force_N)
    report = {**model, **m.as_dict()}
    if need_clearance:

        with tempfile.TemporaryDirectory() as tmp:
            rep = build_design(design, Path(tmp) / "b", set(), fidelity=fidelity, simulate_wall=False,
                               allow_interference=True, use_cache=False)
        report["min_clearance_mm"] = rep["min_clearance_mm"]
        report["overlap_volume_mm3"] = rep["overlap_volume_mm3"]
        report["structure"] = rep.get("structure")
    return values_from_report(report), report
