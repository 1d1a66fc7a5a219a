"""The PowerMouse's motion and its one interference check: the flotor's stroke for the
animation, the excursions the check sweeps, the assembly model (:func:`assemble`) and the
check (:func:`interference`) with the clearance figures of the report."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from cad.actuators import powermouse as pm
from cad.actuators.powermouse import rot_about
from cad.assembly import interference as itf
from cad.assembly.model import AssemblyModel
from cad.families.powermouse import parts as pp
from cad.families.powermouse.actuator import actuator_optimum
from cad.families.powermouse.placement import assembly, lid_holes, tf
from cad.parts import voicecoil as pv


@dataclasses.dataclass(frozen=True)
class PowerMouseLayout:
    """The PowerMouse's layout record (``AssemblyModel.extra``): the actuator optimum
    (``actuator``, eqs 8-9), the flotor/stator ``geometry``, the actuator's
    ``actuator_geometry`` and ``actuator_solids``, the single-actuator test ``rig``'s
    instances (Fig. 7) and, in a build, their BOM rows."""

    actuator: dict
    geometry: Any
    actuator_geometry: Any
    actuator_solids: Any
    rig: Any
    #: the rig's BOM rows, once per build (:func:`cad.families.powermouse.build.assemble_built`:
    #: before the export child forks, so it and report.json read the same rows); empty here
    rig_bom: tuple = ()



def stroke_poses(design) -> dict[str, np.ndarray]:
    """The flotor over its motion range for the animation, ``{body: (N, 4, 4)}`` mm: out
    to +range and -range along x, y, z, then +-range_deg about x, y, z (the cube centre),
    through the centre pose between each (:func:`cad.actuators.powermouse.rot_about`)."""
    r_mm, r_rad = design.motion.range_mm, np.deg2rad(design.motion.range_deg)
    poses = [np.eye(4)]
    for kind in ("t", "r"):
        for axis in np.eye(3):
            for s in (1.0, 0.0, -1.0, 0.0):
                T = np.eye(4)
                if kind == "t":
                    T[:3, 3] = s * r_mm * axis
                else:
                    T[:3, :3] = rot_about(axis, s * r_rad)
                poses.append(T)
    flotor = np.stack(poses)
    return {"flotor": flotor, "ground": np.repeat(np.eye(4)[None], len(flotor), axis=0)}


def motion_poses(design, g, fidelity: str) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """The flotor poses the interference check sweeps, ``[(label, R (3, 3), t_mm (3,))]``:
    fabrication -- the extreme poses of the motion range
    (:func:`cad.actuators.powermouse.workspace_poses`: 26 translations, 26 rotations) and
    the combined poses that move the handle and post furthest
    (:func:`cad.families.powermouse.parts.combined_poses`); inertia / preview -- the 12 on-axis ones."""
    poses = pm.workspace_poses(design.motion.range_mm, design.motion.range_deg)
    poses += pp.combined_poses(g)  # translation + rotation: the handle's and post's worst
    if fidelity != "fabrication":
        poses = [
            p
            for p in pm.workspace_poses(design.motion.range_mm, design.motion.range_deg)
            if p[0].startswith("t")
            and sorted(map(abs, p[2])) == [0.0, 0.0, design.motion.range_mm]
            or p[0].startswith("r(")
            and p[0][1:10] in ("(1, 0, 0)", "(0, 1, 0)", "(0, 0, 1)")
        ]
    return poses


def assemble(design, fidelity: str = "fabrication"):
    """The PowerMouse as a :class:`cad.assembly.model.AssemblyModel`: the part instances
    (:func:`assembly`; bodies ``flotor`` and ``ground``, both at the identity at the centre
    pose), the flotor's motion (``{"flotor": (N, 4, 4)}`` mm: the centre, then
    :func:`motion_poses`; ``pose_labels``: ``"centre"`` and the poses' labels), the lid's
    tapped holes; ``extra``: ``actuator`` (:func:`actuator_optimum`), ``geometry``
    (:class:`cad.families.powermouse.parts.PowerMouseGeometry`), ``actuator_geometry``,
    ``actuator_solids`` and ``rig`` (the test rig's instances, not part of the device);
    ``rig_bom`` empty (a build fills it)."""
    act = actuator_optimum(design)
    gap = act["gap_mm"]
    g = pp.geometry(design, gap)
    a = design.actuator
    ag = pv.ActuatorGeometry(a.magnet_length_mm, a.magnet_width_mm, a.magnet_thickness_mm, gap,
                             a.rattle_mm, a.plate_thickness_mm)
    acts = pv.actuator_solids(ag)
    inst, rig = assembly(design, g, acts)
    poses = motion_poses(design, g, fidelity)
    flotor = np.stack([np.eye(4)] + [tf(R, t) for _, R, t in poses])
    return AssemblyModel(
        design, tuple(inst), {"flotor": np.eye(4), "ground": np.eye(4)},
        {"flotor": flotor}, ("centre", *(label for label, _, _ in poses)), lid_holes(design, g),
        extra=PowerMouseLayout(act, g, ag, acts, rig),
    )


def pose_group(label: str) -> str:
    """Pose group of a motion label: centre, t(ranslations), r(otations), c(ombined)."""
    return "centre" if label == "centre" else label[:1]


def interference(model, allow_interference: bool = False, same_body=None) -> dict:
    """The one interference check (:func:`cad.assembly.interference.check_model`) over the
    flotor's motion: the flotor against the stator at the centre and every excursion, every
    pair of parts on one body once; touching allowed (the flotor touches at its limits by
    design), a common volume above :data:`cad.assembly.interference.OVERLAP_MIN_MM3` is a
    clash; the closest pose of each group (centre, translations, rotations, combined) is
    measured exactly. Returns the interference dict, with ``poses``: ``{label: (clearance_mm,
    "flotor part/stator part", how)}`` (:func:`pose_clearances`); InterferenceError naming the pair, the pose and the volume
    of the first clash unless allow_interference. ``same_body``: the build's same-body result (:meth:`cad.pipeline.run.Build.same_body`;
    None: computed here)."""
    rep = itf.check_model(model, fail_fast=not allow_interference, same_body=same_body, groups=pose_group)
    if not allow_interference:
        itf.raise_on_collision(rep, 0.0)
    out = rep.as_dict()
    out["parts"] = len(model.instances)
    out["overlap_threshold_mm3"] = itf.OVERLAP_MIN_MM3
    out["poses"] = dict(rep.poses or {})
    return out


def pose_clearances(design, poses: dict) -> dict:
    """The report's ``clearances_mm``: the smallest flotor-stator distance at the centre and
    over each pose group (exact OCCT at each group's closest pose), mm, the worst pose of
    each, and every pose's value (``how``: exact, mesh or bound)."""
    def worst(g: str) -> tuple[float | None, str]:
        rows = {k: v[0] for k, v in poses.items() if pose_group(k) == g}
        if not rows:
            return None, ""
        k = min(rows, key=rows.get)
        return rows[k], k

    (tr, wt), (ro, wr), (co, wc) = worst("t"), worst("r"), worst("c")
    return {
        "nominal_mm": poses["centre"][0],
        "translation_mm": tr,
        "rotation_mm": ro,
        "worst_translation": wt,
        "worst_rotation": wr,
        "combined_mm": co,
        "worst_combined": wc,
        "poses_checked": len(poses) - 1,
        "range_mm": design.motion.range_mm,
        "range_deg": design.motion.range_deg,
        "poses": {k: {"clearance_mm": v[0], "closest": v[1], "how": v[2]}
                  for k, v in poses.items() if k != "centre"},
    }
