"""Family-neutral pictures and viewer files of a build, all from the one assembly model.

Every builder calls these with its part instances (``name``, ``kind``, ``body``,
``tf_body_part``) and its body poses (mm, world R0):

* :func:`write_views` -- the ``.glb`` of the posed assembly with the stroke animation
  (``assembly.glb`` when ``"glb"`` is among the formats; always returned for
  ``report.html``), ``animation.gif`` (the stroke) and ``render.png`` (the still);
* :func:`write_parts_3mf` -- ``parts.3mf``, the made parts for a slicer (``"3mf"``);
* :func:`write_viewer_outputs` -- both of the above for one assembly;
* :func:`write_sim_model` -- the simulator files (``mjcf``, ``urdf``) of a family's
  :class:`cad.export.sim.SimModel` (:mod:`cad.export.sim`).

The viewer meshes are coarser than the STL exports (:data:`VIEW_TOLERANCE_MM`): they are
only looked at.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from cad.export import STL_ANGULAR_TOLERANCE_RAD, STL_TOLERANCE_MM
from cad.export.gltf import body_color_map, glb_bytes, instance_rgb, kind_meshes
from cad.export.sim import SIM_FORMATS, write_sim_files
from cad.export.stl import mesh_shape
from cad.export.threemf import print_orientations, printable_parts, threemf_bytes
from cad.io.atomic import write_bytes_atomic
from cad.report.render import write_stroke_pictures
from cad.tolerances import VIEW_ANGULAR_TOLERANCE_RAD, VIEW_TOLERANCE_MM

#: Poses of the stroke animation in the glb (the GIF uses at most GIF_POSES of them).
STROKE_POSES = 24
GLB_NAME = "assembly.glb"
THREEMF_NAME = "parts.3mf"


def instance_colors(instances) -> dict[str, tuple[float, float, float]]:
    """``{instance name: rgb}`` as in the glb (:func:`cad.export.gltf.instance_rgb`)."""
    body_rgb = body_color_map(list(dict.fromkeys(i.body for i in instances)))
    return {i.name: instance_rgb(i, body_rgb) for i in instances}


def write_views(
    instances,
    tf_pose: dict[str, np.ndarray],
    stroke: dict[str, np.ndarray],
    out_dir: Path,
    formats: set[str],
    *,
    name: str,
    title: str,
    cutaway=(),
) -> tuple[list[str], bytes]:
    """Write the viewer files (module docstring); return ``(files written, glb bytes)``.

    tf_pose : ``{body: (4, 4)}`` the static pose (the assembly STEP's pose), mm.
    stroke : ``{body: (N, 4, 4)}`` poses over the stroke, mm.
    cutaway : instance names drawn cut away in the still and the GIF (not in the glb):
        a housing hiding what moves inside (:mod:`cad.report.cutaway`).
    """
    meshes = kind_meshes(instances, VIEW_TOLERANCE_MM, VIEW_ANGULAR_TOLERANCE_RAD)
    glb = glb_bytes(instances, tf_pose, meshes, name=name, stroke=stroke)
    files = []
    if "glb" in formats:
        write_bytes_atomic(Path(out_dir) / GLB_NAME, glb)
        files.append(GLB_NAME)
    files += write_stroke_pictures(
        instances, tf_pose, stroke, meshes, instance_colors(instances), out_dir, title=title,
        cutaway=cutaway,
    )
    return files, glb


def write_parts_3mf(
    instances, out_dir: Path, *, title: str, tolerance_mm: float, angular_tolerance_rad: float
) -> str:
    """``parts.3mf`` of the made parts at the STL tolerances; returns its name."""
    meshes = {}
    for inst in instances:
        k = inst.kind
        if k.made and k.listed and k.name not in meshes:
            meshes[k.name] = mesh_shape(k.shape, tolerance_mm, angular_tolerance_rad)
    data = threemf_bytes(printable_parts(instances, meshes), title, print_orientations(instances))
    write_bytes_atomic(Path(out_dir) / THREEMF_NAME, data)
    return THREEMF_NAME


def write_viewer_outputs(
    instances,
    tf_world_body: dict[str, np.ndarray],
    out_dir: Path,
    formats: set[str],
    *,
    name: str,
    title: str,
    stroke: dict[str, np.ndarray] | None = None,
    stl_tolerance_mm: float | None = None,
    angular_tolerance_rad: float | None = None,
    cutaway=(),
) -> tuple[list[str], bytes]:
    """Everything of this module for one assembly: :func:`write_views` (``stroke`` None:
    the exported pose only; ``cutaway``: instance names drawn cut away) and, when ``"3mf"`` is asked, :func:`write_parts_3mf` at the
    STL deflections (default :data:`cad.export.STL_TOLERANCE_MM`,
    :data:`cad.export.STL_ANGULAR_TOLERANCE_RAD`).

    tf_world_body : ``{body: (4, 4)}`` the exported pose, mm. Returns ``(files, glb)``.
    """
    pose = {b: np.asarray(T, dtype=float).reshape(4, 4) for b, T in tf_world_body.items()}
    if stroke is None:
        stroke = {b: T[None] for b, T in pose.items()}
    files, glb = write_views(instances, pose, stroke, out_dir, formats, name=name, title=title,
                             cutaway=cutaway)
    if "3mf" in formats:
        files.append(
            write_parts_3mf(
                instances,
                out_dir,
                title=name,
                tolerance_mm=stl_tolerance_mm or STL_TOLERANCE_MM,
                angular_tolerance_rad=angular_tolerance_rad or STL_ANGULAR_TOLERANCE_RAD,
            )
        )
    return files, glb


def write_sim_model(make_model, out_dir: Path, formats: set[str], stem: str) -> list[str]:
    """``<stem>.xml`` (MJCF) and/or ``<stem>.urdf`` when ``formats`` asks for them, of the
    :class:`cad.export.sim.SimModel` that ``make_model()`` returns (called only then);
    returns the names written (relative to ``out_dir``)."""
    if not set(formats) & set(SIM_FORMATS):
        return []
    paths = write_sim_files(make_model(), out_dir, formats, stem)
    return [Path(p).relative_to(out_dir).as_posix() for p in paths]
