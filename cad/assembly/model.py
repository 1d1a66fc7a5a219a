"""The one assembly model every family lays out and everything downstream reads.

A family's layout code (``cad/families/<package>/``) returns an :class:`AssemblyModel`
from ``assemble(design, fidelity="fabrication")``: the part instances (each a
:class:`cad.parts.PartKind` carried by a body at ``tf_body_part``), where every body is at
the exported pose (``tf_world_body``) and over the motion the interference check sweeps
(``motion``). Mass properties, the BOM, the interference check, fasteners, every file
format and the reports read this one object (:mod:`cad.pipeline`).

Frames and units: millimetres; ``tf_A_B`` is a 4x4 homogeneous transform mapping
coordinates in frame B into frame A, so ``tf_world_part = tf_world_body @ tf_body_part``
(the rule of scipy's ``RigidTransform`` naming). Body ``"ground"`` is the world frame at
every pose.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np


@dataclass(frozen=True)
class AssemblyModel:
    """A device as part instances on bodies, and the bodies' motion.

    design : the validated design object it was laid out from.
    instances : tuple of :class:`cad.parts.PartInstance` (order = BOM / file order).
    tf_world_body : ``{body: (4, 4) array}``, mm, at the exported pose.
    motion : ``{body: (n, 4, 4) array}``, mm, tf_world_body at the ``n`` poses the
        interference check sweeps (the same ``n`` for every body; a body absent is fixed
        at its ``tf_world_body``); None for a device with no motion to sweep.
    pose_labels : ``n`` human-readable names of those poses (``"phi1 = 12.0 deg"``), used
        in clash messages.
    holes : ``{hole name: record}`` of tapped and clearance holes that fasteners engage
        (:func:`cad.pipeline.family.fastener_report`).
    extra : family-specific layout data the family's own dynamics and report rows read
        (never read by the pipeline).
    """

    design: Any
    instances: tuple
    tf_world_body: dict[str, np.ndarray]
    motion: dict[str, np.ndarray] | None = None
    pose_labels: tuple[str, ...] = ()
    holes: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict)

    @property
    def bodies(self) -> tuple[str, ...]:
        """Bodies carrying at least one instance, in order of first appearance."""
        return tuple(dict.fromkeys(i.body for i in self.instances))

    def kinds(self) -> dict:
        """``{kind name: PartKind}`` in order of first appearance."""
        out: dict = {}
        for inst in self.instances:
            out.setdefault(inst.kind.name, inst.kind)
        return out

    def tf_world_part(self, inst) -> np.ndarray:
        """(4, 4) world transform of one instance at the exported pose (mm)."""
        return np.asarray(self.tf_world_body[inst.body]) @ np.asarray(inst.tf_body_part)
