"""``preview.png``: top (x-y) and side (x-z) projections of the posed assembly, every family.

Each part kind is meshed once, coarsely (:data:`PREVIEW_MESH_TOL_MM`: it is only drawn),
and every instance placed in the world frame R0 (mm, z up). A plate is drawn by its
upward-facing triangles, so its holes and pockets show; any other part by the convex hull
of its projected mesh (scipy). One translucent colour per body, the colours of the glb and
of ``render.png`` (:func:`cad.export.gltf.body_color_map`), the fixed body first
(underneath); optional marks (a path, a workspace outline) on the top view.

Drawn with a matplotlib ``Figure`` (no pyplot) and written by
:func:`cad.report.figures.save_figure` (same bytes every run).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from cad.export.gltf import body_color_map
from cad.export.stl import mesh_shape
from cad.io.atomic import write_bytes_atomic
from cad.io.escape import mathtext
from cad.report.figures import TITLE_Y, save_figure
from cad.tolerances import PREVIEW_ANGULAR_TOL_RAD, PREVIEW_MESH_TOL_MM

#: Opacity of the part outlines (overlapping parts stay visible).
ALPHA = 0.35


def _hull(pts2: np.ndarray) -> np.ndarray | None:
    """Convex hull polygon (K, 2) of 2-D points, None when they span no area."""
    from scipy.spatial import ConvexHull, QhullError

    try:
        return pts2[ConvexHull(pts2).vertices]
    except (QhullError, ValueError):
        return None


def _kind_outline(kind) -> tuple[np.ndarray, np.ndarray | None]:
    """``(vertices_mm (V, 3), upward faces (F, 3) of a plate, else None)`` in the part frame."""
    v, f = mesh_shape(kind.shape, PREVIEW_MESH_TOL_MM, PREVIEW_ANGULAR_TOL_RAD)
    if not kind.plate:
        return v, None
    tri = v[f]
    nz = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])[:, 2]
    return v, f[nz > 0]


def projection_polygons(instances, tf_world_body: dict, hide_ground_below_mm=None):
    """Polygons of each body in the top (x, y) and side (x, z) views, mm in R0.

    tf_world_body : ``{body: (4, 4)}`` world placement of each body (mm).
    hide_ground_below_mm : parts of the body "ground" lying wholly below this world z are
        left out of the top view (legs and motors under a base plate), None: none.
    Returns ``[{body: [polygon (K, 2)]} top, {...} side]``, bodies in order of appearance.
    """
    outlines: dict = {}
    polys: list[dict[str, list]] = [{}, {}]
    for inst in instances:
        k = inst.kind
        if k.name not in outlines:
            outlines[k.name] = _kind_outline(k)
        v, f_top = outlines[k.name]
        T = np.asarray(tf_world_body[inst.body], dtype=float) @ inst.tf_body_part
        w = v @ T[:3, :3].T + T[:3, 3]
        hidden = (
            hide_ground_below_mm is not None
            and inst.body == "ground"
            and w[:, 2].max() < hide_ground_below_mm
        )
        top = polys[0].setdefault(inst.body, [])
        if f_top is not None and not hidden:
            top.extend(list(w[f_top][:, :, :2]))
        elif not hidden and (h := _hull(w[:, :2])) is not None:
            top.append(h)
        if (h := _hull(w[:, [0, 2]])) is not None:
            polys[1].setdefault(inst.body, []).append(h)
    return polys


def write_preview(
    instances, tf_world_body: dict, out: Path, title: str, *, marks=(), hide_ground_below_mm=None
) -> Path:
    """Write ``preview.png`` (module docstring) and return its path.

    tf_world_body : ``{body: (4, 4)}`` the pose drawn (mm, R0).
    marks : ``(label, (N, 2) x-y points mm)`` drawn as black lines on the top view.
    hide_ground_below_mm : see :func:`projection_polygons`.
    """
    import io

    from matplotlib.collections import PolyCollection
    from matplotlib.figure import Figure

    polys = projection_polygons(instances, tf_world_body, hide_ground_below_mm)
    bodies = list(dict.fromkeys(["ground"] + [i.body for i in instances]))
    rgb = body_color_map(bodies)
    fig = Figure(figsize=(11, 5))
    axes = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.3, 1]})
    for view, ax in enumerate(axes):
        for body in bodies:
            if polys[view].get(body):
                ax.add_collection(
                    PolyCollection(
                        polys[view][body],
                        facecolors=rgb[body],
                        edgecolors="none",
                        alpha=ALPHA,
                        label=body,
                    )
                )
    for label, pts in marks:
        pts = np.asarray(pts)
        axes[0].plot(pts[:, 0], pts[:, 1], "k-", lw=1.0, label=label)
    axes[0].set_title("top view (R0, mm)", y=TITLE_Y)
    axes[1].set_title("side view x-z (mm)", y=TITLE_Y)
    for ax in axes:
        ax.set_aspect("equal")
        ax.autoscale_view()
        ax.grid(True, lw=0.3)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), fontsize=8, frameon=False)
    fig.suptitle(mathtext(title))
    buf = io.BytesIO()
    save_figure(fig, buf, "png", dpi=100)
    return write_bytes_atomic(out, buf.getvalue())
