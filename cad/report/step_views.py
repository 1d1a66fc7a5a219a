"""Exploded views of the assembly steps (issue 25 §4): ``steps/step_NN.png`` per step.

Input: the steps of :func:`cad.assembly.steps.assembly_steps` (``Step.new``: the instance
names each step places), the part instances, their bodies' poses ``{body: (4, 4)}`` (mm,
world R0, the exported pose) and the view meshes ``{kind: (V, F)}``
(:func:`cad.export.gltf.kind_meshes`). Each picture is drawn by the one renderer of the
build's still (:func:`cad.report.render.render_images`, same view direction):

* the instances placed by earlier steps at their assembled place, in grey
  (:data:`ASSEMBLED_RGB` blended into their colour by :data:`ASSEMBLED_GREY`);
* the instances this step places in their own colour (the glb's,
  :func:`cad.pipeline.views.instance_colors`), moved out along the step's insertion axis
  (:func:`explode`), each with a thin line from its assembled centre to where it is drawn;
* instances of later steps are not drawn.

Insertion axis: the first fastener of the step that is not a set screw (screws and pins are
modelled head up along their local +z, :mod:`cad.parts.joints`) -- its local +z in the world;
a step with no such fastener: world z. Each fastener moves towards its own head (its own +z:
the screws of one step driven from above and from below part on their sides); another instance moves away
from a reference point along the axis -- the middle of the step's parts in a step with a
fastener (a joint's stack opens about its middle: spacers above it up, the nut below it
down), else the centre of the assembled parts -- by :data:`EXPLODE_FRACTION` of the scene's
size plus its own distance from that point (so a stack opens up in order). With nothing
assembled yet, everything moves along +axis.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from cad.assembly.steps import SET_SCREW
from cad.io.atomic import write_bytes_atomic
from cad.report.render import png_bytes, render_images

#: Grey of the parts already assembled, and how much of it replaces their own colour.
ASSEMBLED_RGB = (0.90, 0.90, 0.92)
ASSEMBLED_GREY = 0.85
#: Displacement of a step's parts: this fraction of the scene's bounding-box diagonal, plus
#: each part's own offset along the axis from the assembled parts' centre.
EXPLODE_FRACTION = 0.25
#: Size of a step picture (px) and its supersampling: small and cheap (a build writes one
#: per step, typically 10-30).
STEP_SIZE_PX = (480, 360)
STEP_SUPERSAMPLE = 1
STEP_DIR = "steps"
#: Build formats that ask for the step pictures: the fabrication files (an evaluation
#: build of check/fit/render asks for none of them and gets none).
STEP_VIEW_FORMATS = ("step", "stl", "dxf", "drawings")


@dataclasses.dataclass
class StepScene:
    """What the renderer is given for one step: ``instances`` to draw (assembled ones at
    their place, new ones on their own displaced body ``explode:<name>``), ``tf_world_body``
    ``{body: (1, 4, 4)}`` mm, ``colors`` ``{name: rgb}``, ``lines`` (L, 2, 3) world mm,
    ``displaced`` ``{name: offset (3,) mm}`` and the unit ``axis`` (3,)."""

    instances: list
    tf_world_body: dict
    colors: dict
    lines: np.ndarray
    displaced: dict
    axis: np.ndarray


def _centre_mm(inst, tf_world_body, meshes) -> np.ndarray:
    """World centre (3,) mm of an instance's mesh bounding box."""
    v = np.asarray(meshes[inst.kind.name][0])
    c = 0.5 * (v.min(axis=0) + v.max(axis=0))
    T = np.asarray(tf_world_body[inst.body]).reshape(4, 4) @ inst.tf_body_part
    return T[:3, :3] @ c + T[:3, 3]


def _head_axis(inst, tf_world_body) -> np.ndarray:
    """A fastener's local +z in the world (unit (3,)): the way to its head."""
    T = np.asarray(tf_world_body[inst.body]).reshape(4, 4) @ inst.tf_body_part
    return T[:3, 2] / np.linalg.norm(T[:3, 2])


def _axis(new, tf_world_body) -> np.ndarray:
    """The step's insertion axis (unit (3,), world): local +z of its first fastener that is
    not a set screw (:data:`cad.assembly.steps.SET_SCREW`, radial in a part the step puts on a
    shaft), else world z."""
    for inst in new:
        if inst.fastener is not None and inst.fastener.kind != SET_SCREW:
            return _head_axis(inst, tf_world_body)
    return np.array([0.0, 0.0, 1.0])


def explode(new, placed, tf_world_body, meshes, scene_mm: float):
    """``(axis (3,), {name: offset (3,) mm})`` of the instances ``new`` of one step
    (module doc); ``placed``: instances assembled before; ``scene_mm``: the scene's size. A
    fastener moves towards its own head (:func:`_head_axis`: screws of one step driven from
    above and from below each come out on their own side), by the same distance as along the
    step's axis."""
    axis = _axis(new, tf_world_body)
    c_new = {i.name: _centre_mm(i, tf_world_body, meshes) @ axis for i in new}
    if any(i.fastener is not None for i in new):  # a joint's stack opens about its middle
        ref = float(np.mean(list(c_new.values())))
    elif placed:
        ref = float(np.mean([_centre_mm(i, tf_world_body, meshes) @ axis for i in placed]))
    else:
        ref = min(c_new.values())
    out = {}
    for i in new:
        rel = c_new[i.name] - ref
        if i.fastener is not None:
            out[i.name] = (EXPLODE_FRACTION * scene_mm + abs(rel)) * _head_axis(i, tf_world_body)
        else:
            out[i.name] = (1.0 if rel >= 0 else -1.0) * (EXPLODE_FRACTION * scene_mm + abs(rel)) * axis
    return axis, out


def step_scene(new_names, placed_names, instances, tf_world_body, meshes, colors) -> StepScene:
    """The :class:`StepScene` of one step: ``new_names`` placed by it, ``placed_names``
    before it; only listed instances with a mesh are drawn."""
    shown = {i.name: i for i in instances if i.kind.listed and i.kind.name in meshes}
    new = [shown[n] for n in new_names if n in shown]
    placed = [shown[n] for n in placed_names if n in shown]
    tf = {b: np.asarray(T, float).reshape(1, 4, 4) for b, T in tf_world_body.items()}
    lo, hi = _bbox(list(shown.values()), tf, meshes)
    axis, offsets = explode(new, placed, tf, meshes, float(np.linalg.norm(hi - lo)))
    grey = np.asarray(ASSEMBLED_RGB)
    cols = {i.name: tuple((1 - ASSEMBLED_GREY) * np.asarray(colors[i.name]) + ASSEMBLED_GREY * grey)
            for i in placed}
    drawn, lines = list(placed), []
    for i in new:
        body = f"explode:{i.name}"
        T = tf[i.body].copy()
        T[0, :3, 3] += offsets[i.name]
        tf[body] = T
        drawn.append(dataclasses.replace(i, body=body))
        cols[i.name] = tuple(colors[i.name])
        c = _centre_mm(i, tf, meshes)
        lines.append([c, c + offsets[i.name]])
    return StepScene(drawn, tf, cols, np.asarray(lines, float).reshape(-1, 2, 3), offsets, axis)


def _bbox(insts, tf, meshes) -> tuple[np.ndarray, np.ndarray]:
    """World box (lo (3,), hi (3,)) mm of the instances' meshes."""
    pts = []
    for i in insts:
        v = np.asarray(meshes[i.kind.name][0])
        T = tf[i.body][0] @ i.tf_body_part
        pts.append(v @ T[:3, :3].T + T[:3, 3])
    p = np.concatenate(pts) if pts else np.zeros((1, 3))
    return p.min(axis=0), p.max(axis=0)


def step_scenes(steps, instances, tf_world_body, meshes, colors) -> list[tuple[int, StepScene]]:
    """``[(step number from 1, its StepScene)]`` of every step that places a drawn
    instance, in order (``steps``: :class:`cad.assembly.steps.Step` list)."""
    placed: list[str] = []
    out = []
    for k, s in enumerate(steps, 1):
        scene = step_scene(s.new, placed, instances, tf_world_body, meshes, colors)
        if scene.displaced:
            out.append((k, scene))
        placed += s.new
    return out


def step_image_name(k: int) -> str:
    """``steps/step_NN.png`` of step ``k`` (from 1)."""
    return f"{STEP_DIR}/step_{k:02d}.png"


def write_step_pictures(steps, instances, tf_world_body, meshes, colors, out_dir: Path) -> dict:
    """Write ``steps/step_NN.png`` for every step that places a drawn part; returns
    ``{step index from 1: relative path}``."""
    done = {}
    for k, sc in step_scenes(steps, instances, tf_world_body, meshes, colors):
        (img,) = render_images(sc.instances, sc.tf_world_body, meshes, sc.colors, [0],
                               size_px=STEP_SIZE_PX, supersample=STEP_SUPERSAMPLE, lines=sc.lines)
        name = step_image_name(k)
        write_bytes_atomic(Path(out_dir) / name, png_bytes(img))
        done[k] = name
    return done
