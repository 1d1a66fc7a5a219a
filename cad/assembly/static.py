"""Interference of one rigid body against another over arbitrary rigid poses (6-DOF). Fast
pass first, exact OCCT only near contact.

The builds no longer use this module: every family's check is
:func:`cad.assembly.interference.check_model` (the PowerMouse's flotor excursions
included). :func:`pose_clearances` stays for the PowerMouse's part-level study
:func:`cad.parts.powermouse.motion_clearances` and the bench that times it.

Built on the primitives of :mod:`cad.assembly.interference` (one mesh per shape at an
absolute tolerance, python-fcl BVH distances, the boolean common), for motion that is not
a planar crank sweep (the PowerMouse flotor over its motion range; every pair of solids at
one pose is :func:`cad.assembly.interference.same_body_check`):

* :func:`pose_clearances` -- the smallest distance between a moving part set and a fixed
  one at each pose: fcl mesh distance at every pose; OCCT ``BRepExtrema_DistShapeShape``
  (and the common volume at contact) only at poses whose mesh distance is within
  ``2 tol + margin`` of contact, and at the closest pose of each pose group (so the
  reported minimum is exact).
"""

from __future__ import annotations

import itertools

import numpy as np

from cad.assembly.interference import CONFIRM_MARGIN_MM, separated_boxes  # noqa: F401

#: Margin on top of 2 x mesh tolerance before a pair is handed to OCCT (mm): the one
#: interference check's (:data:`cad.assembly.interference.CONFIRM_MARGIN_MM`).
MARGIN_MM = CONFIRM_MARGIN_MM


def exact_box(shape) -> np.ndarray:
    """(2, 3) tight OCCT bounding box (min, max corner) of a shape, mm."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    b = Bnd_Box()
    BRepBndLib.AddOptimal_s(shape, b, False)
    lo, hi = b.CornerMin(), b.CornerMax()
    return np.array([[lo.X(), lo.Y(), lo.Z()], [hi.X(), hi.Y(), hi.Z()]])


def _world_box(box: np.ndarray, T: np.ndarray) -> np.ndarray:
    c = np.array(list(itertools.product(*box.T)))
    w = c @ T[:3, :3].T + T[:3, 3]
    return np.array([w.min(axis=0), w.max(axis=0)])


def _box_corners_world(box: np.ndarray, T: np.ndarray) -> np.ndarray:
    c = np.array(list(itertools.product(*box.T)))
    return c @ T[:3, :3].T + T[:3, 3]


def inside_void(box_b, Tb, voids_a, Ta, eps_mm: float = 1e-9) -> bool:
    """True when the box ``box_b`` placed by ``Tb`` lies inside one of the boxes ``voids_a``
    ((2, 3) each, in the frame of part a, placed by ``Ta``) that part a leaves empty (the
    cavity of a shell): then the two share no volume (touching allowed)."""
    if not voids_a:
        return False
    c = _box_corners_world(box_b, Tb)
    Ti = np.linalg.inv(Ta)
    local = c @ Ti[:3, :3].T + Ti[:3, 3]
    return any(
        bool(
            np.all(local >= np.asarray(v)[0] - eps_mm)
            and np.all(local <= np.asarray(v)[1] + eps_mm)
        )
        for v in voids_a
    )


def _contact_or_overlap(a, b, box_a, Ta, box_b, Tb, voids_a=(), voids_b=()) -> float:
    """0 for touching solids, minus the cube root of the common volume for overlapping ones."""
    if (
        separated_boxes(box_a, Ta, box_b, Tb)
        or inside_void(box_b, Tb, voids_a, Ta)
        or inside_void(box_a, Ta, voids_b, Tb)
    ):
        return 0.0
    from cad.assembly.interference import common_volume_mm3

    vol = common_volume_mm3(a, b)
    return -(vol ** (1 / 3)) if vol > 1e-6 else 0.0


def _merged_bvh(parts):
    import fcl

    from cad.assembly import interference as itf

    v, f = itf._body_arrays(parts)
    m = fcl.BVHModel()
    m.beginModel(len(v), len(f))
    m.addSubModel(v.astype(np.float64), f.astype(np.int32))
    m.endModel()
    return fcl.CollisionObject(m, fcl.Transform())


_BVH: dict[int, object] = {}


def _body_distance(pa, pb, T: np.ndarray) -> float:
    """fcl mesh distance between all parts of ``pa`` (placed by ``T``) and all of ``pb``."""
    import fcl

    for parts in (pa, pb):
        if id(parts) not in _BVH:
            _BVH[id(parts)] = _merged_bvh(parts)
    oa, ob = _BVH[id(pa)], _BVH[id(pb)]
    oa.setTransform(fcl.Transform(T[:3, :3], T[:3, 3]))
    ob.setTransform(fcl.Transform())
    return max(0.0, float(fcl.distance(oa, ob, fcl.DistanceRequest(), fcl.DistanceResult())))


def pose_clearances(
    moving, fixed, poses, *, mesh_tol_mm: float = 0.05, groups=None, near_mm: float | None = None
) -> dict[str, tuple[float, str, bool]]:
    """Smallest distance between the moving and the fixed solids at each rigid pose.

    moving, fixed : ``[(name, TopoDS_Shape in the part frame, tf_body_part 4x4[, voids])]``
        (the moving body's frame / the world frame); ``voids``: boxes ((2, 3), part frame)
        the part leaves empty, e.g. the cavity of a shell.
    poses : ``[(label, 4x4 tf_world_moving)]``.
    groups : ``label -> group key`` (default: first character); the closest pose of each
        group is measured exactly whatever its distance.
    near_mm : poses whose mesh distance is below this are measured exactly (default
        ``2 mesh_tol_mm + MARGIN_MM``; ``inf``: every pose, the reference of the bench).

    Method: fcl mesh distance of every part pair at every pose (pairs ordered by box gap);
    at a pose within ``2 tol + margin`` of contact (or the closest of its group), every
    part pair whose mesh distance is that close is measured exactly: OCCT distance where
    the meshes are apart; where they touch, contact is certified without a boolean when a
    face plane of either part's tight box separates the two boxes (flush faces), else the
    boolean common decides (overlap volume). Returns ``{label: (clearance_mm, "moving
    part/fixed part", exact)}``; negative = overlap (minus the cube root of the common
    volume, mm), 0 = contact.
    """
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape

    from cad.assembly import interference as itf
    from cad.export.shapes import placed

    pm = itf.prepare([(it[0], "m", it[1], it[2]) for it in moving], mesh_tol_mm)
    pf = itf.prepare([(it[0], "f", it[1], it[2]) for it in fixed], mesh_tol_mm)
    pa, pb = pm.bodies["m"], pf.bodies["f"]
    la = [
        (exact_box(it[1]), np.asarray(it[2], float), it[3] if len(it) > 3 else ()) for it in moving
    ]
    lb = [
        (exact_box(it[1]), np.asarray(it[2], float), it[3] if len(it) > 3 else ()) for it in fixed
    ]
    eye = np.eye(4)
    near_mm = 2 * mesh_tol_mm + MARGIN_MM if near_mm is None else near_mm
    _BVH.clear()
    fast = {label: _body_distance(pa, pb, np.asarray(T, float)) for label, T in poses}
    group = groups or (lambda s: s[:1])
    closest: dict[str, str] = {}
    for label, d in fast.items():
        g = group(label)
        if g not in closest or d < fast[closest[g]]:
            closest[g] = label
    out = {}
    _BVH.clear()
    for label, T in poses:
        T = np.asarray(T, float)
        d = fast[label]
        if d > near_mm and label not in closest.values():
            out[label] = (float(d), "", False)
            continue
        within = d + 2 * mesh_tol_mm + MARGIN_MM  # pairs that may hold the minimum
        best = (np.inf, "")
        for i, p in enumerate(pa):
            wa = _world_box(p.aabb_mm, T)
            for j, q in enumerate(pb):
                if itf._aabb_gap(wa, q.aabb_mm) > within:
                    continue
                dm = itf._part_mesh_distance(p, q, T, eye)
                if dm > within:
                    continue
                sa = placed(p.shape, T)
                de = 0.0
                if dm > 1e-6:
                    ext = BRepExtrema_DistShapeShape(sa, q.shape)
                    de = float(ext.Value()) if ext.IsDone() else np.inf
                if de <= itf.CONTACT_MM:
                    de = _contact_or_overlap(
                        sa, q.shape, la[i][0], T @ la[i][1], lb[j][0], lb[j][1], la[i][2], lb[j][2]
                    )
                if de < best[0]:
                    best = (de, f"{p.name}/{q.name}")
        out[label] = (float(best[0]), best[1], True)
    return out
