"""Parametric part scripts (build123d, imported lazily): parameters in, solids out.

Modules:

* :mod:`cad.data.catalog` -- bought-part data (bearings, fasteners, motors), pure data;
* :mod:`cad.parts.bars` -- crank, coupler (binary or ternary plate), rocker;
* :mod:`cad.parts.joints` -- bearings, ISO 7379 shoulder screws, nuts, washers, cap
  screws (bd_warehouse) and turned spacers;
* :mod:`cad.parts.motor` -- motor envelope, motor mount plate, direct-drive crank hub;
* :mod:`cad.parts.base` -- base plate holding A1 and A4, the A4 post, legs;
* :mod:`cad.parts.handle` -- the knob at P or a user script (build123d or cadquery).

Every part script returns an OCP ``TopoDS_Shape`` in the part's own frame (mm). Where
a part sits is a :class:`PartInstance` (4x4 ``tf_body_part``: part frame -> the frame
of the rigid body that carries it; a body is "ground" or one of the moving links, whose
frame is the link frame of :mod:`cad.kinematics.linkgeom` with z normal to the
mechanism plane, z = 0 on the base plate's top face).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

BODIES = ("ground", "crank", "coupler", "rocker")


@dataclass(frozen=True)
class PartKind:
    """One distinct part (one file set, one BOM line).

    name : file stem and BOM key (``crank``, ``bearing_M8-16-4`` ...).
    shape : ``TopoDS_Shape`` in the part frame, mm.
    material : key of :data:`cad.data.materials.MATERIALS`.
    made : True for parts to fabricate, False for bought parts.
    plate : 2.5-D plate cut from sheet (a DXF profile is exported).
    description, process : for the BOM (``"waterjet/laser 6 mm plate"``, ``"turned"``, ``"bought"``).
    mass_kg : catalog mass of a bought part (None: solid volume x density).
    inertia_model : ``"solid"`` (integrate the solid), ``"ring"`` (catalog mass as a uniform
        annulus, bearings) or ``"none"`` (counted elsewhere, e.g. the motor shaft is inside Jm).
    ring_mm : (r_in, r_out, width) for the ``"ring"`` model, axis z, COM at z = width / 2.
    collision : ``[(role, TopoDS_Shape)]`` envelopes used by the interference sweep instead
        of ``shape`` (a bearing: inner ring moves with the pin's link, outer ring with the
        seat's link); roles ``"self"`` or ``"other"`` (the joint's other link).
    listed : False for solids that are part of another bought item (the motor shaft): no
        files, no BOM line.
    hull : a solid enclosing ``shape`` (a bearing's d..D x B ring around its rings and balls),
        intersected first by the same-body check: only where it shares volume with another
        part is the detailed ``shape`` intersected too. None: ``shape`` itself.
    fits : ISO 286 tolerance classes of its seats and bores (``"bearing seat 16 J7"``), for
        the BOM, report.json and the DXF notes.
    print_flip : None for a part that is not printed; else its print orientation: False as
        modelled (part z up), True flipped (part z down), written into parts.3mf.
    revolution : the collision solid(s) are solids of revolution about the part's z axis
        (rings, spacers, pin envelopes): their distance to a link turning about that axis
        is the same at every pose (used to speed up the interference sweep).
    sheet_mm : None for a part that is not laser-cut; else ``(width, length)`` mm of the
        sheets it is nested on, ``(0.0, 0.0)`` for the stock size of its material that orders the
        least sheet area (:mod:`cad.export.nesting`).
    """

    name: str
    shape: Any
    material: str
    made: bool
    plate: bool = False
    description: str = ""
    process: str = ""
    mass_kg: float | None = None
    inertia_model: str = "solid"
    ring_mm: tuple[float, float, float] | None = None
    collision: tuple[tuple[str, Any], ...] | None = None
    listed: bool = True
    revolution: bool = False
    fits: tuple[str, ...] = ()
    hull: Any = None
    print_flip: bool | None = None
    sheet_mm: tuple[float, float] | None = None


@dataclass(frozen=True)
class PartInstance:
    """A placed part: ``kind`` carried by ``body`` at ``tf_body_part`` (4x4, mm).

    ``other_body`` is the joint's other link for parts whose collision envelope has an
    ``"other"`` role (a bearing's inner ring), placed there by ``tf_other_part``.
    ``fastener``: for screws, a :class:`cad.assembly.fasteners.Fastener` record (thread size,
    length, what it clamps, which hole it engages); None otherwise.
    ``part_of``: the instance name of the bought item this solid is part of (a motor's shaft:
    its motor), None otherwise; the gap between them is the maker's, not a clearance between
    parts (:func:`cad.assembly.interference.same_part`).
    """

    name: str
    kind: PartKind
    body: str
    tf_body_part: np.ndarray = field(default_factory=lambda: np.eye(4))
    other_body: str | None = None
    tf_other_part: np.ndarray | None = None
    fastener: Any = None
    part_of: str | None = None


def translation(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> np.ndarray:
    """4x4 homogeneous translation (mm)."""
    T = np.eye(4)
    T[:3, 3] = (x, y, z)
    return T


def flip_x() -> np.ndarray:
    """4x4 rotation by 180 deg about x (turns a part upside down: z -> -z)."""
    T = np.eye(4)
    T[1, 1] = T[2, 2] = -1.0
    return T


def planar_to_4x4(tf_2d: np.ndarray) -> np.ndarray:
    """(..., 3, 3) planar transforms -> (..., 4, 4) spatial ones (z unchanged)."""
    tf_2d = np.asarray(tf_2d, dtype=float)
    out = np.zeros((*tf_2d.shape[:-2], 4, 4))
    out[..., :2, :2] = tf_2d[..., :2, :2]
    out[..., :2, 3] = tf_2d[..., :2, 2]
    out[..., 2, 2] = 1.0
    out[..., 3, 3] = 1.0
    return out
