"""Posed assembly: where every part is at crank angle phi1 (world frame R0, z up, mm).

A body's pose is the planar link transform of :func:`cad.kinematics.linkgeom.tf_world_link`
lifted to 4x4 (z unchanged); a part's world placement is
``tf_world_part = tf_world_body @ tf_body_part``.
"""

from __future__ import annotations

import numpy as np

from cad.data.materials import get_material
from cad.export.shapes import placed
from cad.kinematics.fourbar import FourBar, solve
from cad.kinematics.linkgeom import tf_world_link
from cad.parts import BODIES, PartInstance, planar_to_4x4


def body_transforms(fb: FourBar, phi1_rad) -> dict[str, np.ndarray]:
    """``{body: (N, 4, 4)}`` world transforms of every body at the crank angles ``phi1_rad`` (N,)."""
    phi = np.atleast_1d(np.asarray(phi1_rad, dtype=float))
    pose = solve(fb, phi)
    return {b: planar_to_4x4(tf_world_link(fb, pose, b)) for b in BODIES}


def planar_transforms(fb: FourBar, phi1_rad) -> dict[str, np.ndarray]:
    """``{body: (N, 3, 3)}`` planar link transforms (for :mod:`cad.families.fourbar.layers`)."""
    phi = np.atleast_1d(np.asarray(phi1_rad, dtype=float))
    pose = solve(fb, phi)
    return {b: tf_world_link(fb, pose, b) for b in BODIES}


def part_world_tf(
    inst: PartInstance, tf_world_body: dict[str, np.ndarray], i: int = 0
) -> np.ndarray:
    """4x4 world placement of a part at pose ``i``."""
    return tf_world_body[inst.body][i] @ inst.tf_body_part


def posed_shapes(
    instances, tf_world_body: dict[str, np.ndarray], i: int = 0, listed_only: bool = True
):
    """``[(instance name, placed TopoDS_Shape, rgb)]`` of the assembly at pose ``i``."""
    out = []
    for inst in instances:
        if listed_only and not inst.kind.listed:
            continue
        rgb = get_material(inst.kind.material).color_rgb
        out.append((inst.name, placed(inst.kind.shape, part_world_tf(inst, tf_world_body, i)), rgb))
    return out
