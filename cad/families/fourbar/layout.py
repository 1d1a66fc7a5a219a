"""The four-bar laid out as part instances: the ONE place its assembly is made.

:func:`assemble` turns a validated four-bar design into a
:class:`cad.assembly.model.AssemblyModel`:

1. kinematics (no CAD): the crank angles of the sweep (:func:`sweep_angles`), the link
   transforms and the joint positions in each link's frame
   (:mod:`cad.kinematics.linkgeom`);
2. z-layers and joint stacks (:func:`cad.families.fourbar.layers.choose_layers`, through
   :func:`plan_layers` for the refusal with a hint);
3. parts placed on the bodies ground / crank / coupler / rocker
   (:func:`cad.families.fourbar.mechanism.build_assembly`), the handle from a user script when
   ``parts.handle_script`` is set;
4. the bodies at the exported crank angle (``tf_world_body``: mid-stroke, or ``phi1_deg``)
   and over the crank angles the interference sweep uses (``motion``, labelled
   ``"phi1 = 12.3 deg"``).

:func:`check_layout` is the part of it that runs before any CAD import (the dispatcher
calls it to refuse a design early). No CAD library is imported at module import.

Frames: mm; a body frame is the link frame of :mod:`cad.kinematics.linkgeom` (origin at
the link's first joint, x towards its second) with z normal to the mechanism plane, z = 0
on the base plate's top face; ``tf_world_body`` maps body coordinates into the world R0
(origin A1).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from cad.assembly.model import AssemblyModel
from cad.device import resolve_device
from cad.errors import DesignError
from cad.families.fourbar.capstan_solids import add_capstan
from cad.families.fourbar.layers import (
    JOINTS,
    NoLayout,
    choose_layers,
    clearing_stroke_mm,
    footprint_bbox_mm,
    hub_set_screw,
    made_crank_axle,
)
from cad.families.fourbar.mechanism import build_assembly, check_plate_screws
from cad.families.fourbar.pose import body_transforms, planar_transforms
from cad.families.fourbar.sheet_tolerance import handle_floor_mm
from cad.kinematics.linkgeom import link_joints_mm
from cad.parts.handle import handle_params, resolve_script, user_handle_shape
from cad.parts.part_cache import deferred_shapes

#: Crank angles of the layer planning and the interference sweep at ``preview`` fidelity
#: (at most; the design's ``parts.interference_poses`` otherwise).
PREVIEW_POSES = 24
#: The moving bodies, in the order of the Hoeken paper's links 1..3.
LINKS = ("crank", "coupler", "rocker")


@dataclasses.dataclass(frozen=True)
class FourBarLayout:
    """The four-bar's layout record (``AssemblyModel.extra``): the layer ``plan``, the joint
    centres ``joints_mm`` (mm, world), the base plate's rectangle ``base_rect_mm``, the swept
    crank angles ``phi1_rad`` and the exported one ``pose_phi1_rad`` (rad), the user's
    ``handle_script`` (None: the built-in knob)."""

    plan: Any
    joints_mm: Any
    base_rect_mm: Any
    phi1_rad: Any
    pose_phi1_rad: float
    handle_script: Any = None



def sweep_angles(design, n: int) -> np.ndarray:
    """``n`` crank angles (rad) evenly over ``[phi1_min, phi1_max]`` of ``design``."""
    return np.linspace(design.phi1_min_rad, design.phi1_max_rad, n)


def n_poses(parts, fidelity: str) -> int:
    """Crank angles of the layer planning and the interference sweep at ``fidelity``."""
    if fidelity == "preview":
        return min(parts.interference_poses, PREVIEW_POSES)
    return parts.interference_poses


def exported_phi1_rad(design, phi1_deg: float | None = None) -> float:
    """Crank angle (rad) of the exported pose: ``phi1_deg`` (deg) when given, else
    mid-stroke. DesignError naming ``--phi1-deg`` outside the crank range."""
    if phi1_deg is None:
        return 0.5 * (design.phi1_min_rad + design.phi1_max_rad)
    lo, hi = math.degrees(design.phi1_min_rad), math.degrees(design.phi1_max_rad)
    if not lo - 1e-9 <= phi1_deg <= hi + 1e-9:
        raise DesignError(
            "--phi1-deg", f"must lie in the crank range [{lo:g}, {hi:g}] deg, got {phi1_deg!r}"
        )
    return math.radians(phi1_deg)


def check_layout(design, fidelity: str, allow_interference: bool) -> None:
    """Refuse, before any CAD import, a hub wall no ISO 4026 set screw fits
    (:func:`cad.families.fourbar.layers.hub_set_screw`, DesignError naming ``parts.hub_diameter_mm``),
    plates no catalog cap screw fits (:func:`cad.families.fourbar.mechanism.check_plate_screws`,
    naming the plate's field), and a design whose joint hardware has no clear layer order
    (:func:`plan_layers`) or whose jointed bars sit closer than ``parts.clearance_min_mm``
    (:func:`check_joint_gaps`); the last two skipped with ``allow_interference``: the build
    then exports the clash and reports it)."""

    hub_set_screw(design.parts)
    check_plate_screws(design.parts)
    if allow_interference:
        return
    n = n_poses(design.parts, fidelity)
    planar = planar_transforms(design.linkage, sweep_angles(design, n))
    plan = plan_layers(design, link_joints_mm(design.linkage), planar, n, strict=True)
    check_joint_gaps(plan, design.parts)


def check_joint_gaps(plan, parts) -> None:
    """DesignError naming ``parts.layer_gap_mm`` when two bars jointed to each other lie on
    adjacent layers less than ``parts.clearance_min_mm`` apart.

    Both bars surround their common pin, so they overlap in plan at every pose and their
    layer gap is their distance all through the stroke: the interference sweep
    (:func:`cad.assembly.interference.raise_on_collision`) would refuse the build at every
    pose, after the CAD work (``layer_gap_mm = 0.002`` typed in metres).
    """

    level = {name: i for i, name in enumerate(plan.order)}
    for joint, (a, b) in JOINTS.items():
        if b not in level or abs(level[a] - level[b]) != 1:
            continue
        gap = plan.gaps_mm[min(level[a], level[b])]
        if gap < parts.clearance_min_mm - 1e-9:
            raise DesignError(
                "parts.layer_gap_mm",
                f"{parts.layer_gap_mm:g} mm leaves the {a} and the {b} (jointed at {joint}, "
                f"adjacent layers) {gap:g} mm apart at every pose, below parts.clearance_min_mm "
                f"= {parts.clearance_min_mm:g} mm; use layer_gap_mm >= "
                f"{parts.clearance_min_mm:g} (or --allow-interference)",
            )


def plan_layers(design, J, planar, n_poses: int, strict: bool):
    """:func:`cad.families.fourbar.layers.choose_layers`; when ``strict`` and no layer order is clear,
    the refusal (before any CAD import) names the joint and parts and, for a family scaled
    by ``stroke_mm``, the smallest stroke whose layout is clear (the crank length with it)."""

    try:
        return choose_layers(J, design.parts, planar, strict=strict, made_axle=made_crank_axle(design))
    except NoLayout as e:
        s = getattr(design, "stroke_mm_requested", None)
        if e.field != "mechanism":
            raise
        if s is None:
            raise DesignError(e.field, e.reason + "; lengthen the crank (l1_mm) or shrink "
                              "parts.hub_diameter_mm / the joint hardware") from None
        s_ok = clearing_stroke_mm(design.family, s, design.parts, n_poses)
        l1 = design.linkage.l1_mm
        hint = (
            f"; stroke_mm >= {s_ok:g} clears it (crank l1 {l1:.2f} -> {l1 * s_ok / s:.2f} mm)"
            if s_ok is not None else "; no stroke up to 3x clears it"
        )
        raise DesignError("mechanism.stroke_mm", f"{s:g} mm: {e.reason}{hint}, or shrink "
                          "parts.hub_diameter_mm / the joint hardware") from None


def _parts(design, J, plan, footprint, fidelity: str, deferred: bool, script):
    """:class:`cad.families.fourbar.mechanism.Assembly` of the design (``script``: the user handle
    script's path or None)."""
    import contextlib

    parts = design.parts
    user_handle = None
    if script is not None:

        floor = handle_floor_mm(plan, parts)
        user_handle = user_handle_shape(script, handle_params(parts, floor))
    # deferred: solids only where a part's mass properties are not cached
    with deferred_shapes() if deferred else contextlib.nullcontext():
        dev = resolve_device(design)
        asm = build_assembly(J, plan, parts, footprint, fidelity=fidelity,
                             handle_shape=user_handle, design_label=design.name,
                             motor_spec=dev.motor.spec)
    return add_capstan(asm, design, J, plan, dev.transmission("crank"))


def assemble(
    design,
    fidelity: str = "fabrication",
    *,
    phi1_deg: float | None = None,
    poses: int | None = None,
    strict: bool = False,
    deferred: bool = False,
):
    """The four-bar ``design`` as a :class:`cad.assembly.model.AssemblyModel` (module docstring).

    fidelity : ``"fabrication"`` (bd_warehouse bearings with balls, the knob's round),
        ``"inertia"`` or ``"preview"`` (plain bearing rings, no round).
    phi1_deg : crank angle of the exported pose (deg); None: mid-stroke.
    poses : crank angles of the layer planning and of ``motion`` (default
        :func:`n_poses` of the fidelity).
    strict : refuse a design with no clear layer order (:func:`plan_layers`, the build
        without ``allow_interference``); else the best order, its conflicts listed.
    deferred : part solids as :class:`cad.parts.part_cache.DeferredShape` where their mass
        properties are cached (:func:`cad.families.fourbar.inertia.inertia_model`).

    Returns the model: instances on bodies ground / crank / coupler / rocker (mm, body =
    link frame), ``tf_world_body`` ``{body: (4, 4)}`` at the exported crank angle,
    ``motion`` ``{body: (poses, 4, 4)}`` over :func:`sweep_angles`, ``pose_labels``
    ``"phi1 = <deg> deg"``, ``holes`` ``{name: TappedHole}`` and ``extra``: ``plan`` (the
    layer plan), ``joints_mm`` (joint positions per link frame), ``base_rect_mm``,
    ``phi1_rad`` (the sweep), ``pose_phi1_rad``, ``handle_script`` (Path or None).

    Raises DesignError: ``--phi1-deg`` outside the crank range, no layer order when
    ``strict`` (:func:`plan_layers`), a fastener that cannot be sized, a bad user handle.
    """
    fb = design.linkage
    pose_phi = exported_phi1_rad(design, phi1_deg)
    script = resolve_script(design.parts, design.source)
    n = n_poses(design.parts, fidelity) if poses is None else poses
    phi = sweep_angles(design, n)
    J = link_joints_mm(fb)
    planar = planar_transforms(fb, phi)
    plan = plan_layers(design, J, planar, n, strict=strict)
    asm = _parts(design, J, plan, footprint_bbox_mm(plan, planar), fidelity, deferred, script)
    return AssemblyModel(
        design=design,
        instances=asm.instances,
        tf_world_body={b: v[0] for b, v in body_transforms(fb, [pose_phi]).items()},
        motion=body_transforms(fb, phi),
        pose_labels=tuple(f"phi1 = {math.degrees(p):.1f} deg" for p in phi),
        holes={h.name: h for h in asm.holes},
        extra=FourBarLayout(plan, J, asm.base_rect_mm, phi, pose_phi, script),
    )
