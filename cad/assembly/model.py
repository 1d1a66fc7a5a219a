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

from cad.data.materials import get_material
from cad.errors import DesignError
from cad.export.shapes import placed
from cad.export.step import labelled_shape  # a labelled, coloured Solid, as part files are
from cad.occ.compound import deep_copy, labelled_compound


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
    extra : the family's layout record, a frozen dataclass of its package
        (``FourBarLayout``, ``PantographLayout``, ``PenLayout``, ``PowerMouseLayout``) that
        its own dynamics and report rows read (never read by the pipeline); None: none.
    """

    design: Any
    instances: tuple
    tf_world_body: dict[str, np.ndarray]
    motion: dict[str, np.ndarray] | None = None
    pose_labels: tuple[str, ...] = ()
    holes: dict = field(default_factory=dict)
    extra: Any = None

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

    def tf_world_part(self, inst, pose: int | None = None) -> np.ndarray:
        """(4, 4) world transform of one instance (mm): ``tf_world_body @ tf_body_part`` at
        the exported pose, or at pose ``pose`` of :attr:`motion` (a body the motion does not
        move stays at its ``tf_world_body``). Raises DesignError for a pose the motion lacks."""
        return self._tf_world_body(inst.body, pose) @ np.asarray(inst.tf_body_part, dtype=float)

    def _tf_world_body(self, body: str, pose: int | None) -> np.ndarray:
        if pose is None:
            return np.asarray(self.tf_world_body[body], dtype=float)
        n = len(self.pose_labels) if self.motion is None else \
            max((len(m) for m in self.motion.values()), default=0)
        if isinstance(pose, bool) or not isinstance(pose, (int, np.integer)) or not 0 <= pose < n:

            raise DesignError("pose", f"must be an index of the motion's {n} poses, got {pose!r}")
        if self.motion is not None and body in self.motion:
            return np.asarray(self.motion[body][pose], dtype=float)
        return np.asarray(self.tf_world_body[body], dtype=float)

    def compound(self, pose: int | None = None):
        """The device as a build123d ``Compound``: one child per part instance, in instance
        order, each a ``Solid`` (or a ``Compound`` for a part of several solids) placed at its
        world transform (:meth:`tf_world_part`, mm), labelled with the instance's name (the
        names of ``assembly.step``'s solids and of report.json's ``part_materials``) and
        coloured with its material's colour (:data:`cad.data.materials.MATERIALS`
        ``color_rgb``). The compound's label is the design's name.

        ``pose``: None for the exported pose, else an index of :attr:`motion` (its label is
        ``pose_labels[pose]``). ``show(model.compound())`` displays it in ocp_vscode (not a
        hapticad dependency); build123d's ``export_step(model.compound(), path)`` writes it
        with those names and colours. Imports build123d (on first use).
        """
        children, seen = [], set()
        for inst in self.instances:
            shape = inst.kind.shape
            if inst.kind.name in seen:  # its own geometry: a STEP writer merges instances that
                shape = deep_copy(shape)  # share it (one name)
            seen.add(inst.kind.name)
            children.append(labelled_shape(placed(shape, self.tf_world_part(inst, pose)), inst.name,
                                      get_material(inst.kind.material).color_rgb))
        return labelled_compound(children, str(getattr(self.design, "name", "assembly")))
