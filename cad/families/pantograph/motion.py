"""The motion of a pantograph-family device and its one interference check: the bodies at
any workspace points (:func:`body_poses`), the stroke the animation shows, the poses the
check sweeps (:func:`motion_points`), the assembly model (:func:`assemble`) and the check
itself (:func:`interference`)."""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from cad.assembly import interference as itf
from cad.assembly.model import AssemblyModel
from cad.errors import DesignError
from cad.families.pantograph.layout import (
    home_xy_mm,
    is_twin,
    layout,
    lower_five_bar,
    rz,
    workspace_square,
)
from cad.families.pantograph.placement import assembly
from cad.isotropy.gii import square_grid_mm
from cad.kinematics import fivebar as fb5
from cad.kinematics import twin_pantograph as tw
from cad.parts import translation

#: Poses of the stroke animation: the handle once round the workspace square.
STROKE_POSES = 32


@dataclasses.dataclass(frozen=True)
class PantographLayout:
    """The pantographs' layout record (``AssemblyModel.extra``): the numbers of the layout
    (``layout``: lengths, heights, clearances in mm) and the home point ``home_mm``."""

    layout: dict
    home_mm: Any



def body_poses(design, X) -> dict[str, np.ndarray]:
    """``{body: (N, 4, 4)}`` world poses (mm) with the handle at the workspace points ``X``
    ((N, 2) x, y mm; the twin pantograph (N, 3) x, y mm, theta rad), placed as
    :func:`assembly` places the bodies at home (tests compare the two)."""
    X = np.atleast_2d(np.asarray(X, dtype=float))
    n = len(X)
    fb = lower_five_bar(design)
    B = [fb.base_left_mm, fb.base_right_mm]
    if is_twin(design):
        ik = tw.ik(design.mechanism, X)
        groups = [("crank_", ik.crank), ("knob_", ik.knob)]
    else:
        ik = fb5.ik(fb, X[:, :2])
        groups = [("", ik)]
    if np.any(ik.status != 0):
        x = X[int(np.argmax(ik.status != 0))]
        raise ValueError(f"{int(np.sum(ik.status != 0))} of the {n} points cannot be reached "
                         f"(first: {', '.join(f'{v:g}' for v in x)})")
    out = {"ground": np.repeat(np.eye(4)[None], n, axis=0)}
    for pre, fp in groups:
        E = fp.E_mm
        for i, (side, C) in enumerate((("left", fp.C_left_mm), ("right", fp.C_right_mm))):
            out[f"{pre}proximal_{side}"] = np.stack(
                [rz(float(fp.q_rad[k, i]), B[i][0], B[i][1]) for k in range(n)]
            )
            out[f"{pre}distal_{side}"] = np.stack(
                [
                    rz(math.atan2(E[k, 1] - C[k, 1], E[k, 0] - C[k, 0]), C[k, 0], C[k, 1])
                    for k in range(n)
                ]
            )
    if is_twin(design):
        out["crankshaft"] = np.stack([rz(X[k, 2], X[k, 0], X[k, 1]) for k in range(n)])
    else:
        out["handle"] = np.stack([translation(X[k, 0], X[k, 1]) for k in range(n)])
    return out


def stroke_points(design, n: int = STROKE_POSES) -> np.ndarray:
    """The handle once round the workspace square (from its centre's left, counter-clockwise),
    ``n`` points, (n, 2) mm; the twin pantograph adds theta = the home angle (rad)."""
    sq = workspace_square(design.workspace)
    seg = np.linalg.norm(np.diff(sq, axis=0), axis=1)
    s = np.linspace(0.0, seg.sum(), n)
    xy = np.column_stack([np.interp(s, np.r_[0, np.cumsum(seg)], sq[:, j]) for j in (0, 1)])
    if not is_twin(design):
        return xy
    th = math.radians(design.workspace["home_theta_deg"])
    return np.column_stack([xy, np.full(n, th)])


def stroke_poses(design) -> dict[str, np.ndarray] | None:
    """:func:`body_poses` over :func:`stroke_points`, or None where the square leaves the
    reachable set (the animation then shows the home pose only)."""
    try:
        poses = body_poses(design, stroke_points(design))
    except ValueError:
        return None
    return poses


#: Samples per side of the workspace square the interference check sweeps (boundary
#: included: the corners, edge midpoints and centre are poses). Coarser than the GII grid
#: (``workspace.grid``) to keep the build fast: a clash that reaches no sample is missed
#: (the 2-D layer clearances, ``clearances_mm``, still cover the finer grid).
MOTION_GRID = 5


#: Crank angles of the twin pantograph's motion at each grid point (full turn).
MOTION_THETA_SAMPLES = 8


def motion_points(design) -> tuple[np.ndarray, tuple[str, ...]]:
    """The poses the interference check sweeps: the home pose first, then the workspace
    square on a :data:`MOTION_GRID` x :data:`MOTION_GRID` grid (the twin pantograph: x
    :data:`MOTION_THETA_SAMPLES` crank angles over the full turn). Returns ``(X, labels)``:
    X (N, 2) x, y mm (twin: (N, 3) x, y mm, theta rad), N labels (``"x=-50 y=150 mm"``,
    twin ``"x=-50 y=150 mm theta=45 deg"``)."""
    ws = design.workspace
    home = home_xy_mm(design)
    if is_twin(design):
        th = math.radians(design.workspace["home_theta_deg"])
        grid = tw.workspace_grid(ws["center_mm"], ws["size_mm"], MOTION_GRID, MOTION_THETA_SAMPLES)
        X = np.vstack([[home[0], home[1], th], grid])
    else:
        X = np.vstack([home, square_grid_mm(ws["center_mm"], ws["size_mm"], MOTION_GRID)])
    labels = [f"x={x[0]:g} y={x[1]:g} mm" + (f" theta={math.degrees(x[2]):g} deg"
                                              if len(x) > 2 else "") for x in X]
    labels[0] = f"home ({labels[0]})"
    return X, tuple(labels)


def motor_joints(design) -> dict:
    """``{(proximal body, "ground"): [(axis xy in the link, axis xy in the world)]}``: each
    proximal link turns about its motor's axis (the motor shaft, a solid of revolution on
    the link, keeps its distance to the motor housing): input of the interference check's
    revolution shortcut (:func:`cad.assembly.interference.check_model`)."""
    fb = lower_five_bar(design)
    B = [np.asarray(fb.base_left_mm, float), np.asarray(fb.base_right_mm, float)]
    pres = ("crank_", "knob_") if is_twin(design) else ("",)
    out = {}
    for pre in pres:
        for side, b in zip(("left", "right"), B, strict=True):
            out[("ground", f"{pre}proximal_{side}")] = [(b, np.zeros(2))]
    return out


def assemble(design, fidelity: str = "fabrication"):
    """The device as a :class:`cad.assembly.model.AssemblyModel`: the part instances
    (:func:`assembly`), every body at home (``tf_world_body``, mm) and over the motion the
    interference check sweeps (``motion``: ``{body: (N, 4, 4)}`` at the poses of
    :func:`motion_points`, ``pose_labels``), the tapped holes; ``extra``: ``layout`` (the
    :func:`layout` dict) and ``home_mm`` ((2,) mm). DesignError (``workspace``) when a motion
    pose cannot be reached."""
    lay = layout(design)
    inst, tfs, home, holes = assembly(design, lay, fidelity)
    X, labels = motion_points(design)
    try:
        motion = body_poses(design, X)
    except ValueError as e:  # the design's workspace is the fault, not a collision
        raise DesignError("workspace", f"{e}; move workspace.center_mm or shrink "
                          "workspace.side_mm / size_mm") from None
    return AssemblyModel(design, tuple(inst), tfs, motion, labels, holes,
                         extra=PantographLayout(lay, home))


def interference(model, allow_interference: bool = False, same_body=None) -> dict:
    """The one interference check (:func:`cad.assembly.interference.check_model`) of the
    model over its workspace motion: every pair of bodies at every pose, every pair of parts
    on one body once; touching allowed, a common volume above
    :data:`cad.assembly.interference.OVERLAP_MIN_MM3` is a clash. Returns the report's
    ``interference`` dict (``min_clearance_mm``, ``overlap_volume_mm3``, ``pairs``,
    ``collisions`` with parts, pose label and volume, ``n_poses`` ...). InterferenceError
    naming the pair, the pose and the volume of the first clash unless allow_interference. ``same_body``: the build's same-body result (:meth:`cad.pipeline.run.Build.same_body`;
    None: computed here)."""
    rep = itf.check_model(model, joints=motor_joints(model.design),
                          fail_fast=not allow_interference, same_body=same_body)
    if not allow_interference:
        itf.raise_on_collision(rep, 0.0)
    out = rep.as_dict()
    out["parts"] = len(model.instances)
    out["overlap_threshold_mm3"] = itf.OVERLAP_MIN_MM3
    return out
