"""Any family's planar link graph as a beam frame (numpy, no CAD): one structure model for
every family.

A family describes its moving links once (:class:`LinkGraph`): each link's joints in its own
frame (mm; origin at its first joint, x towards its second, as every body frame of the
project), the beams between them with their sections (:class:`cad.structure.frame.Section`,
SI, density included), the revolute joints that tie two links (every DOF but the rotation
about z, :meth:`cad.structure.frame.Frame.dof_map`), the supports and the handle joint.
:func:`frame_at` poses it (``tf_world_link`` 3x3 or 4x4 planar transforms, mm) into a
:class:`~cad.structure.frame.Frame` with the point masses lumped at the nearest joint of
their link. The four-bar (:func:`cad.structure.device.build_frame`) and the pantographs
(:mod:`cad.structure.pantograph`) both go through it.

:func:`plane_modes` and :func:`worst_stress_Pa` read the figures every family reports off a
frame: the lowest in-plane and out-of-plane modes (a planar frame's two families of modes
decouple exactly: in plane ux, uy, rz; out of plane uz, rx, ry) and the peak von Mises stress
under a force of given size in the worst of a set of directions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from cad.structure.frame import Frame, Section

#: Sub-elements per beam (finer mass lumping; the four-bar's value since issue 11).
N_SUB = 4


@dataclass(frozen=True)
class Lumped:
    """A point mass on a link: link name, position in the link frame (mm), mass (kg)."""

    link: str
    xy_mm: tuple[float, float]
    mass_kg: float


@dataclass(frozen=True)
class Beam:
    """A prismatic beam of ``link`` from joint ``a`` to joint ``b`` with ``section`` (SI)."""

    link: str
    a: str
    b: str
    section: Section


@dataclass
class LinkGraph:
    """Planar link graph (module docstring).

    joints_mm: link -> joint name -> (2,) xy in the link frame (mm); beams: in build order
    (link by link); ties: ``((link, joint), (link, joint))`` revolute joints; fixed:
    ``(link, joint) -> DOFs held`` (0..5 = ux, uy, uz, rx, ry, rz); springs: ``(link, joint,
    dof) -> k`` grounded springs (N/m, N m/rad); handle: ``(link, joint)`` where the force is
    applied."""

    joints_mm: dict[str, dict[str, np.ndarray]]
    beams: list[Beam]
    ties: list[tuple[tuple[str, str], tuple[str, str]]] = field(default_factory=list)
    fixed: dict[tuple[str, str], tuple[int, ...]] = field(default_factory=dict)
    handle: tuple[str, str] = ("", "")
    springs: dict[tuple[str, str, int], float] = field(default_factory=dict)


def frame_at(graph: LinkGraph, tf_world_link: dict, lumped=()) -> tuple[Frame, dict]:
    """The frame of ``graph`` at one pose and ``{(link, joint): node}``.

    tf_world_link: link -> 3x3 (or 4x4) planar transform, mm. Nodes are numbered link by link
    (the links in the order of their first beam): the link's joints in sorted name order,
    then its beams' sub-nodes (reproducible digits). ``lumped``: :class:`Lumped` masses, each
    added to the nearest joint node of its link (a link not in the graph is skipped)."""
    fr = Frame()
    ids: dict[tuple[str, str], int] = {}

    def world(link, xy):
        T = np.asarray(tf_world_link[link], float)
        R, t = (T[:2, :2], T[:2, 2]) if T.shape == (3, 3) else (T[:2, :2], T[:2, 3])
        return (R @ np.asarray(xy, float) + t) * 1e-3

    order = list(dict.fromkeys(b.link for b in graph.beams))
    for link in order:
        beams = [b for b in graph.beams if b.link == link]
        for n in sorted({x for b in beams for x in (b.a, b.b)}):
            ids[(link, n)] = fr.node(world(link, graph.joints_mm[link][n]))
        for b in beams:
            fr.element(ids[(link, b.a)], ids[(link, b.b)], b.section, link, n_sub=N_SUB)
    fr.ties += [(ids[a], ids[b]) for a, b in graph.ties]
    for j, dofs in graph.fixed.items():
        fr.fixed[ids[j]] = tuple(dofs)
    for (link, joint, dof), k in graph.springs.items():
        fr.springs[(ids[(link, joint)], dof)] = k
    for lp in lumped:
        if lp.link not in order:
            continue
        p = world(lp.link, lp.xy_mm)
        cand = [i for (lk, _), i in ids.items() if lk == lp.link]
        nearest = min(cand, key=lambda i: float(np.linalg.norm(fr.nodes[i] - p)))
        fr.add_mass(nearest, lp.mass_kg)
    return fr, ids


def plane_modes(fr: Frame, k: int = 12) -> dict[str, float]:
    """Lowest in-plane and out-of-plane natural frequencies (Hz) of a planar frame:
    ``{"in_plane_Hz", "out_of_plane_Hz"}`` among its ``k`` lowest modes, each mode classed by
    where its kinetic energy is (sum m u_z^2 against sum m (u_x^2 + u_y^2)); inf when none of
    the ``k`` lowest is of that class."""
    freqs, shapes = fr.modes(k)
    m = fr.masses()
    out = {"in_plane_Hz": math.inf, "out_of_plane_Hz": math.inf}
    for f, s in zip(freqs, shapes, strict=True):
        u = s.reshape(-1, 6)
        ez = float(m @ u[:, 2] ** 2)
        exy = float(m @ (u[:, 0] ** 2 + u[:, 1] ** 2))
        key = "out_of_plane_Hz" if ez > exy else "in_plane_Hz"
        out[key] = min(out[key], float(f))
    return out


def directions(n_plane: int = 24) -> np.ndarray:
    """Unit force directions (M, 3): ``n_plane`` in the plane, +z, and the in-plane ones
    tilted 45 deg out of plane (z > 0; a stress is the same for -d)."""
    a = np.linspace(0.0, math.pi, n_plane, endpoint=False)  # -d gives the same stress
    flat = np.c_[np.cos(a), np.sin(a), np.zeros_like(a)]
    tilt = np.c_[np.cos(a) / math.sqrt(2), np.sin(a) / math.sqrt(2), np.full_like(a, 1 / math.sqrt(2))]
    return np.vstack([flat, [[0.0, 0.0, 1.0]], tilt])


def worst_stress_Pa(fr: Frame, node: int, force_N: float, dirs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Peak von Mises stress of every element (Pa, (n_elements,)) under ``force_N`` at
    ``node`` in the worst of ``dirs`` (M, 3) for that element, and the index of that
    direction per element. Superposition of three unit-load solutions (linear frame)."""
    F = np.stack([fr.element_end_forces(fr.solve({node: np.r_[e, 0, 0, 0]})) for e in np.eye(3)])
    d = np.asarray(dirs, float)
    s = force_N * fr.stress_of_end_forces(np.einsum("mk,kej->mej", d, F))  # (M, n_elements)
    arg = np.argmax(s, axis=0)
    return s[arg, np.arange(s.shape[1])], arg
