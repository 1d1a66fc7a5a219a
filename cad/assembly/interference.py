"""Interference over a motion: N poses x all pairs of bodies, fast mesh pass then exact OCCT.

The one check of every family is :func:`check_model`: it takes an assembly model
(:class:`cad.assembly.model.AssemblyModel`: part instances on bodies, the bodies over the
poses of ``motion`` -- a four-bar's crank angles, a pantograph's workspace grid, the
PowerMouse flotor's 6-DOF excursions) and sweeps every moving solid against every other
solid, moving or ground, with the method below (:func:`sweep`), plus every pair of parts
on one body once (:func:`same_body_check`). A clash names the pair of parts, the pose
(crank angle or label) and the overlap volume (:func:`raise_on_collision`). Planar motion
(every body turning about z at z = 0) is culled by z; other motion is swept unculled.

Method (SPEC "Measured pitfalls": meshes at 0.1 mm miss a 0.05 mm overlap; exact answers
need OCCT):

1. every part is meshed once at ``mesh_tol_mm`` (absolute, OCCT) and placed in the
   frame of its rigid body (ground, crank, coupler, rocker);
2. fast pass: the distance between every pair of bodies by python-fcl BVHs of the parts
   (the closest part pairs first, by bounding box gap, until a box gap exceeds the best
   distance) -- or by manifold3d ``min_gap`` (``method="manifold3d"``). Every
   :data:`COARSE_STEP`-th pose is measured; a pose in between only when its lower bound
   -- the larger of a Lipschitz bound from its coarse neighbours and the gap of the part
   bounding boxes at that pose (:func:`box_lower_bounds`; exact for parts stacked in z,
   which planar motion keeps apart) -- could make it a near contact or a new minimum.
   Parts that are solids of revolution about a joint shared with the other body keep
   their distance at every pose and are measured once. The pose of the smallest distance
   of each pair is refined between its neighbouring samples (bounded scalar search);
3. exact pass: every (pair, pose) whose mesh distance is below
   ``clearance_min_mm + 2 mesh_tol_mm + CONFIRM_MARGIN_MM`` -- a chordal mesh is off
   the true surface by at most the tolerance, on either side (convex faces lie inside
   the mesh, holes outside) -- and the closest pose of every pair are checked with OCCT
   on the solids: ``BRepExtrema_DistShapeShape`` between the parts of the two bodies
   whose bounding boxes come that close, and ``BRepAlgoAPI_Common`` volume where the
   distance is zero.

``min_clearance_mm`` is the exact smallest distance found between two different parts on
two different bodies (0 with ``overlap_volume_mm3 > 0`` for a collision); a bought part whose
collision envelopes ride on two bodies (a bearing's outer ring in its seat, its inner ring on
the journal; a motor's shaft on the link, the motor on the ground) keeps its own gap out of it -- that gap is the maker's, inside one part -- and is
checked for overlap on its own (:func:`own_part_gaps`, ``own_part_gaps`` in the report).

Parts of ONE body do not move apart, so every such pair is checked once
(:func:`same_body_check`, on the real solids written to ``assembly.step``): tight OCCT
bounding boxes first, ``BRepAlgoAPI_Common`` only where they overlap by more than a
touch; a common volume above :data:`OVERLAP_MIN_MM3` is a collision named with both parts
(a screw in its tapped hole or a bearing in its seat only touch). :func:`merge_same_body`
adds the result to the sweep's report; the API is generic (name, body, shape,
placement), so every family can call it.
"""

from __future__ import annotations

import contextlib
import itertools
import threading
import time
from dataclasses import dataclass, field

import numpy as np

from cad.errors import InterferenceError
from cad.export.shapes import placed
from cad.export.stl import mesh_shape
from cad.io import derived_cache
from cad.occ.bbox import tight_box
from cad.occ.distance import common_volume_mm3, min_distance_mm
from cad.tolerances import (  # noqa: F401 (names of this module's API)
    BOX_TOUCH_MM,
    CONFIRM_MARGIN_MM,
    CONTACT_MM,
    CULL_MARGIN_MM,
    LB_SLACK_MM,
    OVERLAP_MIN_MM3,
    SWEEP_MESH_TOL_MM,
)

#: What the check covers (copied into report.json ``interference.checked``).
CHECKED = (
    "every pair of solids: pairs on different bodies over the stroke (mesh pass, exact OCCT "
    "distance and common volume near contact), pairs on one body once (bounding boxes, then "
    "the exact OCCT common volume); touching is allowed, a common volume is a collision"
)
#: Modules whose source the cached exact values (distances, volumes, boxes) depend on.
_CODE = ("cad.assembly.interference", "cad.export.shapes", "cad.occ.bbox", "cad.occ.distance")


@dataclass
class PartMesh:
    name: str
    body: str
    shape: object  # TopoDS_Shape placed in the body frame
    vertices_mm: np.ndarray
    faces: np.ndarray
    aabb_mm: np.ndarray  # (2, 3) in the body frame
    axis_xy: np.ndarray | None = None  # solid of revolution about this vertical axis (body frame)
    bvh: object = None  # fcl CollisionObject of this part alone (exact-pass pre-filter)
    tight_box: np.ndarray | None = None  # (2, 3) tight OCCT box in the body frame (lazy)
    #: the bought item this envelope is part of (a motor's shaft: the motor's instance name);
    #: None: its own instance (the name before ``[``): :func:`same_part`
    owner: str | None = None


@dataclass
class Prepared:
    bodies: dict[str, list[PartMesh]]
    mesh_tol_mm: float
    mesh_time_s: float


@dataclass
class InterferenceReport:
    """Result of a sweep (distances mm, volumes mm^3, angles deg)."""

    min_clearance_mm: float
    overlap_volume_mm3: float
    closest: dict
    pairs: list[dict]
    collisions: list[dict]
    method: str
    mesh_tol_mm: float
    n_poses: int
    n_exact_checks: int
    time_s: dict = field(default_factory=dict)
    same_body: dict | None = None
    #: labelled sweeps: ``{label: (distance_mm, "part a/part b", how)}`` -- the smallest
    #: distance between two bodies at each pose; ``how`` is "exact" (OCCT), "mesh" (fcl, off
    #: by at most 2 mesh tolerances) or "bound" (a lower bound: the pose was pruned)
    poses: dict | None = None
    #: the gaps inside one bought part whose envelopes ride on two bodies (a bearing's rings),
    #: not counted in ``min_clearance_mm`` (:func:`own_part_gaps`)
    own_part_gaps: dict | None = None

    def as_dict(self) -> dict:
        return {
            "checked": CHECKED,
            "same_body": self.same_body,
            "min_clearance_mm": self.min_clearance_mm,
            "own_part_gaps": self.own_part_gaps,
            "overlap_volume_mm3": self.overlap_volume_mm3,
            "closest": self.closest,
            "pairs": self.pairs,
            "collisions": self.collisions,
            "method": self.method,
            "mesh_tol_mm": self.mesh_tol_mm,
            "n_poses": self.n_poses,
            "n_exact_checks": self.n_exact_checks,
        }


def collision_items(instances) -> list[tuple[str, str, object, np.ndarray, bool, str | None]]:
    """``(part name, body, TopoDS shape in the part frame, tf_body_part, revolution, owner)`` for
    every collision envelope of the assembly (bearings split into their two rings; ``owner``:
    the bought item a solid is part of, ``PartInstance.part_of``, else None)."""
    out = []
    for inst in instances:
        rev = bool(getattr(inst.kind, "revolution", False))
        own = getattr(inst, "part_of", None)
        if inst.kind.collision is None:
            out.append((inst.name, inst.body, inst.kind.shape, inst.tf_body_part, rev, own))
            continue
        single = len(inst.kind.collision) == 1
        for role, shp in inst.kind.collision:
            if role == "self":
                body, tf = inst.body, inst.tf_body_part
            else:
                body, tf = inst.other_body, inst.tf_other_part
            if body is None or tf is None:
                raise InterferenceError(
                    f"{inst.name}: collision role {role!r} without the joint's other body"
                )
            label = (
                inst.name if single else f"{inst.name}[{'inner' if role == 'other' else 'outer'}]"
            )
            out.append((label, body, shp, tf, rev, own))
    return out


def _owner(p: PartMesh) -> str:
    return p.owner or p.name.split("[", 1)[0]


def same_part(p: PartMesh, q: PartMesh) -> bool:
    """Two collision envelopes of one bought part: of one part instance (a bearing's rings
    ``x[outer]`` and ``x[inner]``, :func:`collision_items`), or one of them a solid of the other
    (a motor's shaft and its motor: ``PartInstance.part_of``). Their gap is inside the part (the
    maker's), not a clearance between two parts."""
    return _owner(p) == _owner(q)


def prepare(items, mesh_tol_mm: float = SWEEP_MESH_TOL_MM) -> Prepared:
    """Mesh every collision item once (cached per shape) and place it in its body frame."""
    t0 = time.perf_counter()
    cache: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    bodies: dict[str, list[PartMesh]] = {}
    for item in items:
        name, body, shape, tf = item[:4]
        rev = bool(item[4]) if len(item) > 4 else False
        owner = item[5] if len(item) > 5 else None
        key = id(shape)
        if key not in cache:
            cache[key] = mesh_shape(shape, mesh_tol_mm, 0.5)
        v, f = cache[key]
        T = np.asarray(tf, dtype=float)
        vb = v @ T[:3, :3].T + T[:3, 3]
        axis = T[:2, 3].copy() if rev and abs(abs(T[2, 2]) - 1.0) < 1e-12 else None
        bodies.setdefault(body, []).append(
            PartMesh(
                name,
                body,
                placed(shape, T),
                vb,
                f,
                np.array([vb.min(axis=0), vb.max(axis=0)]),
                axis,
                owner=owner,
            )
        )
    return Prepared(bodies, mesh_tol_mm, time.perf_counter() - t0)


def _corners(parts: list[PartMesh]) -> np.ndarray:
    """(8, 3) corners of the bounding box of some parts (body frame); empty if none."""
    if not parts:
        return np.zeros((0, 3))
    lo = np.min([p.aabb_mm[0] for p in parts], axis=0)
    hi = np.max([p.aabb_mm[1] for p in parts], axis=0)
    return np.array(list(itertools.product(*zip(lo, hi, strict=True))))


#: The fast pass first measures every COARSE_STEP-th pose, then only the poses in
#: between whose lower bound (Lipschitz: a distance changes by at most the largest
#: displacement of either body's bounding box corners) could be a near contact or a
#: new minimum; the result over the sampled poses is the same as measuring all of them.
COARSE_STEP = 8




def _box_corners(parts: list[PartMesh]) -> np.ndarray:
    """(P, 8, 3) corners of each part's bounding box (body frame)."""
    return np.array(
        [list(itertools.product(*zip(p.aabb_mm[0], p.aabb_mm[1], strict=True))) for p in parts]
    ).reshape(len(parts), 8, 3)


def world_boxes(parts: list[PartMesh], T: np.ndarray) -> np.ndarray:
    """(N, P, 2, 3) world bounding boxes (min, max corner) of each part at each pose.

    ``T`` : (N, 4, 4) world transforms of the body carrying the parts.
    """
    T = np.asarray(T, dtype=float)
    c = _box_corners(parts)
    w = (c.reshape(1, -1, 3) @ T[:, :3, :3].transpose(0, 2, 1)).reshape(
        len(T), len(parts), 8, 3
    ) + T[:, None, None, :3, 3]
    return np.stack([w.min(axis=2), w.max(axis=2)], axis=2)


def _box_gaps(ca: np.ndarray, cb: np.ndarray, Ta: np.ndarray, Tb: np.ndarray) -> np.ndarray:
    """(Pa, Pb) gaps between the world boxes of two part sets at one pose; ``ca``, ``cb``: (P, 8,
    3) box corners in the body frames (:func:`_box_corners`), ``Ta``, ``Tb``: 4x4."""
    wa = ca @ Ta[:3, :3].T + Ta[:3, 3]
    wb = cb @ Tb[:3, :3].T + Tb[:3, 3]
    la, ha = wa.min(axis=1), wa.max(axis=1)
    lb, hb = wb.min(axis=1), wb.max(axis=1)
    g = np.maximum(0.0, np.maximum(la[:, None] - hb[None], lb[None] - ha[:, None]))
    return np.sqrt((g * g).sum(axis=-1))


def box_lower_bounds(
    pa: list[PartMesh], pb: list[PartMesh], Ta: np.ndarray, Tb: np.ndarray
) -> np.ndarray:
    """(N,) at each pose, the smallest gap between the world bounding boxes of a part of
    ``pa`` (body a at ``Ta`` (N, 4, 4)) and a part of ``pb``: a lower bound of the mesh
    distance between the two part sets (each mesh lies inside its box); inf if a set is
    empty."""
    n = len(Ta)
    if not pa or not pb:
        return np.full(n, np.inf)
    A, B = world_boxes(pa, Ta), world_boxes(pb, Tb)
    gap = np.maximum(
        0.0,
        np.maximum(
            A[:, :, None, 0, :] - B[:, None, :, 1, :], B[:, None, :, 0, :] - A[:, :, None, 1, :]
        ),
    )
    return np.sqrt((gap * gap).sum(axis=-1)).min(axis=(1, 2))


def _disp(T: np.ndarray, corners: np.ndarray, i: np.ndarray, j: np.ndarray) -> np.ndarray:
    """(len(j),) largest displacement of the ``corners`` (K, 3) between poses ``i`` and ``j``
    of the transforms ``T`` (N, 4, 4) (0 without corners): every point of the box moves at
    most that much (the displacement is affine in the point, its norm convex)."""
    if len(corners) == 0:
        return np.zeros(len(j))
    dR = T[j, :3, :3] - T[i, :3, :3]
    dt = T[j, :3, 3] - T[i, :3, 3]
    dv = corners[None] @ dR.transpose(0, 2, 1) + dt[:, None, :]
    return np.sqrt((dv * dv).sum(axis=-1)).max(axis=1)


def bounded_pair_distances(
    scene, a: str, b: str, Ta: np.ndarray, Tb: np.ndarray, keep, pre: dict | None = None
) -> tuple:
    """Mesh distances of a body pair over the poses, skipping provably uninteresting ones.

    ``keep(m) -> float``: poses whose lower bound is below ``keep(current pair minimum)`` are
    measured. The lower bound of a pose is the larger of (1) the Lipschitz bound from the
    measured neighbouring coarse poses (a distance changes by at most the displacement of
    either body's bounding box corners) and (2) ``scene.pose_lower_bounds`` (the part
    bounding boxes at that pose, and the pose-invariant part pairs). ``pre``: ``{pose:
    distance}`` already measured with this scene. Returns ``(d, measured)``: ``d[i]`` is
    the distance where ``measured[i]``, else a lower bound of it.
    """
    n = len(Ta)
    d = np.full(n, np.nan)
    measured = np.zeros(n, dtype=bool)
    coarse = sorted(set(range(0, n, COARSE_STEP)) | {n - 1})
    pre = pre or {}
    for i in coarse:
        d[i] = pre[i] if i in pre else scene.distance(a, b, Ta[i], Tb[i])
        measured[i] = True
    ca, cb = scene.corners.get((a, b), (np.zeros((0, 3)), np.zeros((0, 3))))
    c = np.asarray(coarse)
    j = np.arange(n)
    i0 = c[np.searchsorted(c, j, side="right") - 1]  # coarse pose at or below j
    i1 = c[np.minimum(np.searchsorted(c, j, side="left"), len(c) - 1)]  # at or above j
    lb = np.maximum.reduce(
        [
            d[i0] - _disp(Ta, ca, i0, j) - _disp(Tb, cb, i0, j),
            d[i1] - _disp(Ta, ca, i1, j) - _disp(Tb, cb, i1, j),
            scene.pose_lower_bounds(a, b, Ta, Tb),
        ]
    )
    m = float(np.nanmin(d))
    for k in np.flatnonzero(~measured):
        if lb[k] < keep(m) - LB_SLACK_MM:
            d[k] = scene.distance(a, b, Ta[k], Tb[k])
            measured[k] = True
            m = min(m, float(d[k]))
        else:
            d[k] = lb[k]
    return d, measured


def _body_arrays(parts: list[PartMesh]):
    vs, fs, off = [], [], 0
    for p in parts:
        vs.append(p.vertices_mm)
        fs.append(p.faces + off)
        off += len(p.vertices_mm)
    return np.concatenate(vs), np.concatenate(fs)


def _z_range(parts: list[PartMesh]) -> tuple[float, float]:
    return min(p.aabb_mm[0, 2] for p in parts), max(p.aabb_mm[1, 2] for p in parts)




def _z_gap(p: PartMesh, z: tuple[float, float]) -> float:
    return max(0.0, z[0] - p.aabb_mm[1, 2], p.aabb_mm[0, 2] - z[1])


def cull_pair(
    pa: list[PartMesh], pb: list[PartMesh], margin_mm: float
) -> tuple[list[PartMesh], list[PartMesh], float]:
    """Parts of each body within ``margin_mm`` in z of the other body, and the smallest z gap
    of the parts left out (a lower bound of their distance; inf if none)."""
    za, zb = _z_range(pa), _z_range(pb)
    ka = [p for p in pa if _z_gap(p, zb) <= margin_mm]
    kb = [p for p in pb if _z_gap(p, za) <= margin_mm]
    gaps = [_z_gap(p, zb) for p in pa if _z_gap(p, zb) > margin_mm]
    gaps += [_z_gap(p, za) for p in pb if _z_gap(p, za) > margin_mm]
    return ka, kb, min(gaps, default=np.inf)


def _planar_body(T) -> bool:
    T = np.asarray(T)
    return bool(np.allclose(T[..., 2, :], [0.0, 0.0, 1.0, 0.0]) and np.allclose(T[..., :2, 2], 0.0))


def _is_planar(tf_world_body: dict[str, np.ndarray]) -> bool:
    """True when every body turns about z only, at z = 0 (row 2 of each transform is
    (0, 0, 1, 0)): parts keep their z, so the fast pass may cull by z."""
    return all(_planar_body(T) for T in tf_world_body.values())


def _check_planar(tf_world_body: dict[str, np.ndarray]) -> None:
    for body, T in tf_world_body.items():
        if not _planar_body(T):
            raise InterferenceError(f"body {body!r}: the sweep assumes planar motion (z kept)")


def _axial(parts: list[PartMesh], axes_xy: list[np.ndarray]) -> list[bool]:
    return [
        p.axis_xy is not None and any(np.allclose(p.axis_xy, a, atol=1e-9) for a in axes_xy)
        for p in parts
    ]


def split_invariant(pa: list[PartMesh], pb: list[PartMesh], joint_axes) -> tuple[list, list, list]:
    """For two bodies turning about common joint axes, the parts whose distance changes with the
    pose (non-axial parts of each) and the part pairs whose distance does not (an axial part
    -- solid of revolution about the joint axis -- against anything of the other body)."""
    if not joint_axes:
        return pa, pb, []
    ax_a = _axial(pa, [xa for xa, _ in joint_axes])
    ax_b = _axial(pb, [xb for _, xb in joint_axes])
    inv = [(p, q) for i, p in enumerate(pa) for j, q in enumerate(pb) if ax_a[i] or ax_b[j]]
    return (
        [p for i, p in enumerate(pa) if not ax_a[i]],
        [q for j, q in enumerate(pb) if not ax_b[j]],
        inv,
    )


class _FclScene:
    def __init__(self, prepared: Prepared, margin_mm: float, joints=None):
        import fcl

        self.fcl = fcl
        self.prepared = prepared
        self.margin = margin_mm
        self.joints = joints or {}
        self.objs: dict[tuple[str, str], tuple] = {}
        self.lower_bound: dict[tuple[str, str], float] = {}
        self.invariant_min: dict[tuple[str, str], float] = {}
        self.corners: dict[tuple[str, str], tuple] = {}
        self.parts: dict[tuple[str, str], tuple] = {}
        self.skip: dict[tuple[str, str], np.ndarray] = {}  # same-part pairs (:func:`same_part`)

    def pose_lower_bounds(self, a: str, b: str, Ta: np.ndarray, Tb: np.ndarray) -> np.ndarray:
        """(N,) lower bounds of :meth:`distance` at the poses ``Ta``, ``Tb`` (N, 4, 4): the
        pose-invariant pairs' distance, or the part boxes of the swept parts if farther."""
        self.pair(a, b, Ta[0], Tb[0])
        va, vb = self.parts[(a, b)]
        return np.minimum(self.invariant_min[(a, b)], box_lower_bounds(va, vb, Ta, Tb))

    def pair(self, a: str, b: str, Ta=None, Tb=None):
        if (a, b) not in self.objs:
            ka, kb, lb = cull_pair(self.prepared.bodies[a], self.prepared.bodies[b], self.margin)
            va, vb, inv = split_invariant(ka, kb, self.joints.get((a, b)))
            inv = [(p, q) for p, q in inv if not same_part(p, q)]  # own_part_gaps checks them
            self.skip[(a, b)] = np.array([[same_part(p, q) for q in vb] for p in va], bool)
            self.objs[(a, b)] = (_box_corners(va), _box_corners(vb)) if va and vb else None
            self.lower_bound[(a, b)] = lb
            self.corners[(a, b)] = (_corners(va), _corners(vb))
            self.parts[(a, b)] = (va, vb)
            # pose-invariant pairs: measured once, at the first pose asked for
            self.invariant_min[(a, b)] = (
                _closest_of_pairs(inv, Ta, Tb) if Ta is not None else np.inf
            )
        return self.objs[(a, b)]

    def distance(self, a: str, b: str, Ta: np.ndarray, Tb: np.ndarray) -> float:
        """Mesh distance of the two bodies at one pose: the pose-invariant pairs' distance, or
        the closest swept part pair (part BVHs, measured in increasing order of their box gap
        while a box gap is below the smallest distance found); two envelopes of one part
        (:func:`same_part`) are not a pair here (:func:`own_part_gaps`)."""
        boxes = self.pair(a, b, Ta, Tb)
        best = self.invariant_min[(a, b)]
        if boxes is None:
            return best
        va, vb = self.parts[(a, b)]
        gaps = np.where(self.skip[(a, b)], np.inf, _box_gaps(boxes[0], boxes[1], Ta, Tb))
        order = np.argsort(gaps, axis=None, kind="stable")
        flat = gaps.ravel()
        nb = len(vb)
        for k in order:
            if flat[k] >= best:
                break
            best = min(best, _part_mesh_distance(va[k // nb], vb[k % nb], Ta, Tb))
        return float(best)


class _ManifoldScene:
    def __init__(self, prepared: Prepared, margin_mm: float, search_mm: float):
        import manifold3d

        self.m3 = manifold3d
        self.prepared = prepared
        self.margin = margin_mm
        self.search = search_mm
        self.man: dict[tuple[str, str], tuple] = {}
        self.lower_bound: dict[tuple[str, str], float] = {}
        self.corners: dict[tuple[str, str], tuple] = {}
        self.parts: dict[tuple[str, str], tuple] = {}

    def _union(self, parts: list[PartMesh]):
        m3 = self.m3
        pieces = []
        for p in parts:
            mesh = m3.Mesh64(
                vert_properties=np.ascontiguousarray(p.vertices_mm, dtype=np.float64),
                tri_verts=np.ascontiguousarray(p.faces, dtype=np.uint64),
            )
            pieces.append(m3.Manifold(mesh))
        return m3.Manifold.batch_boolean(pieces, m3.OpType.Add)

    def pair(self, a, b, Ta=None, Tb=None):
        if (a, b) not in self.man:
            ka, kb, lb = cull_pair(self.prepared.bodies[a], self.prepared.bodies[b], self.margin)
            # a part with envelopes on both bodies: its own gap is not one (own_part_gaps)
            ka, kb = ([p for p in ka if not any(same_part(p, q) for q in kb)],
                      [q for q in kb if not any(same_part(p, q) for p in ka)])
            self.man[(a, b)] = (self._union(ka), self._union(kb)) if ka and kb else None
            self.lower_bound[(a, b)] = lb
            self.corners[(a, b)] = (_corners(ka), _corners(kb))
            self.parts[(a, b)] = (ka, kb)
        return self.man[(a, b)]

    def pose_lower_bounds(self, a: str, b: str, Ta: np.ndarray, Tb: np.ndarray) -> np.ndarray:
        """(N,) lower bounds of :meth:`distance` at the poses (the part bounding boxes)."""
        self.pair(a, b)
        ka, kb = self.parts[(a, b)]
        return box_lower_bounds(ka, kb, Ta, Tb)

    def distance(self, a, b, Ta, Tb) -> float:
        objs = self.pair(a, b)
        if objs is None:
            return np.inf
        ma = objs[0].transform(np.ascontiguousarray(Ta[:3, :], dtype=np.float64))
        mb = objs[1].transform(np.ascontiguousarray(Tb[:3, :], dtype=np.float64))
        if not (ma ^ mb).is_empty():
            return 0.0
        return float(ma.min_gap(mb, self.search))


def _world_aabb(aabb: np.ndarray, T: np.ndarray) -> np.ndarray:
    corners = np.array(list(itertools.product(*aabb.T)))
    w = corners @ T[:3, :3].T + T[:3, 3]
    return np.array([w.min(axis=0), w.max(axis=0)])


def _aabb_gap(a: np.ndarray, b: np.ndarray) -> float:
    d = np.maximum(0.0, np.maximum(a[0] - b[1], b[0] - a[1]))
    return float(np.linalg.norm(d))


def have_fcl() -> bool:
    try:
        import fcl  # noqa: F401
    except ImportError:
        return False
    return True


def _part_bvh(p: PartMesh):
    if p.bvh is None:
        import fcl

        g = fcl.BVHModel()
        g.beginModel(len(p.vertices_mm), len(p.faces))
        g.addSubModel(p.vertices_mm.astype(np.float64), p.faces.astype(np.int32))
        g.endModel()
        p.bvh = fcl.CollisionObject(g, fcl.Transform())
    return p.bvh


#: The mesh distances measured by the :func:`sweep` running in this thread (None outside one):
#: its exact pass asks again for part pairs at poses its fast pass measured (7143 of the 26195
#: fcl calls of designs/delta_capstan.toml's build); the same parts at the same placements give
#: the same float, so a repeat is read back. Each entry holds its two parts (no id reused).
_SWEEP_MEMO = threading.local()


@contextlib.contextmanager
def _distance_memo():
    """Keep the sweep's part mesh distances for its duration (:data:`_SWEEP_MEMO`)."""
    before = getattr(_SWEEP_MEMO, "d", None)
    _SWEEP_MEMO.d = {}
    try:
        yield
    finally:
        _SWEEP_MEMO.d = before


def _part_mesh_distance(p: PartMesh, q: PartMesh, Ta: np.ndarray, Tb: np.ndarray) -> float:
    import fcl

    memo = getattr(_SWEEP_MEMO, "d", None)
    if memo is not None:
        key = (id(p), id(q), Ta.dtype.str, Ta.shape, Ta.tobytes(), Tb.dtype.str, Tb.shape, Tb.tobytes())
        hit = memo.get(key)
        if hit is not None and hit[0] is p and hit[1] is q:
            return hit[2]
    oa, ob = _part_bvh(p), _part_bvh(q)
    oa.setTransform(fcl.Transform(Ta[:3, :3], Ta[:3, 3]))
    ob.setTransform(fcl.Transform(Tb[:3, :3], Tb[:3, 3]))
    d = float(fcl.distance(oa, ob, fcl.DistanceRequest(), fcl.DistanceResult()))
    if memo is not None:
        memo[key] = (p, q, d)
    return d


def _closest_of_pairs(
    pairs: list[tuple[PartMesh, PartMesh]], Ta: np.ndarray, Tb: np.ndarray
) -> float:
    """Smallest mesh distance over part pairs ``(p of body a, q of body b)`` at one pose; pairs
    are measured in increasing order of their bounding box gap and the scan stops once a box
    gap reaches the smallest distance found (a box gap is a lower bound of the distance)."""
    if not pairs:
        return np.inf
    gaps = [_aabb_gap(_world_aabb(p.aabb_mm, Ta), _world_aabb(q.aabb_mm, Tb)) for p, q in pairs]
    best = np.inf
    for k in np.argsort(gaps, kind="stable"):
        if gaps[k] >= best:
            break
        p, q = pairs[k]
        best = min(best, _part_mesh_distance(p, q, Ta, Tb))
    return best


def separated_boxes(box_a, Ta, box_b, Tb, eps_mm: float = 1e-9) -> bool:
    """True when the oriented boxes ``box_a`` placed by ``Ta`` and ``box_b`` by ``Tb`` (each
    (2, 3) in its own frame, 4x4 mm) are separated by a plane normal to one of their six
    face directions, touching allowed: then the solids inside share no volume."""
    ca = np.array(list(itertools.product(*np.asarray(box_a).T))) @ Ta[:3, :3].T + Ta[:3, 3]
    cb = np.array(list(itertools.product(*np.asarray(box_b).T))) @ Tb[:3, :3].T + Tb[:3, 3]
    for n in np.concatenate([Ta[:3, :3].T, Tb[:3, :3].T]):
        pa, pb = ca @ n, cb @ n
        if pb.min() - pa.max() >= -eps_mm or pa.min() - pb.max() >= -eps_mm:
            return True
    return False


def _tight_body_box(p: PartMesh) -> np.ndarray:
    """(2, 3) tight OCCT box of a part in its body frame (computed once per part)."""
    if p.tight_box is None:

        p.tight_box = tight_box(p.shape)
    return p.tight_box


def exact_distance_volume(sa, sb) -> tuple[float, float]:
    """OCCT distance (mm, inf when it fails) of two placed solids, and their common volume
    (mm^3) when they touch or overlap (distance <= :data:`CONTACT_MM`), else 0."""
    d = min_distance_mm(sa, sb)
    vol = common_volume_mm3(sa, sb) if d <= CONTACT_MM else 0.0
    return d, vol


def exact_pair(sa, sb) -> tuple[float, float]:
    """:func:`exact_distance_volume` through the derived cache, keyed by the digests of
    both placed solids (their geometry and world placement, exactly)."""
    if not derived_cache.enabled():
        return exact_distance_volume(sa, sb)
    key = [derived_cache.shape_digest(sa), derived_cache.shape_digest(sb)]
    d, vol = derived_cache.cached_json(
        "exact-distance", key,
        lambda: [repr(x) for x in exact_distance_volume(sa, sb)], code=_CODE)
    return float(d), float(vol)


def exact_check(
    pa: list[PartMesh], pb: list[PartMesh], Ta: np.ndarray, Tb: np.ndarray, within_mm: float
) -> tuple[float, float, str, str]:
    """Exact (OCCT) smallest distance and overlap volume between two bodies at one pose.

    Only part pairs whose world bounding boxes -- and, when python-fcl is installed,
    whose meshes -- come within ``within_mm`` are measured exactly.
    Returns (distance mm, overlap volume mm^3 of all the pairs, part a, part b) of the
    closest pair (:func:`exact_check_pair` also returns that pair's own volume).
    """
    return exact_check_pair(pa, pb, Ta, Tb, within_mm)[:4]


def exact_check_pair(
    pa: list[PartMesh], pb: list[PartMesh], Ta: np.ndarray, Tb: np.ndarray, within_mm: float,
    certify_touch: bool = False,
) -> tuple[float, float, str, str, float]:
    """:func:`exact_check` and, last, the common volume (mm^3) of the closest pair alone; two
    envelopes of one part (:func:`same_part`) are not a pair (:func:`own_part_gaps`).
    ``certify_touch`` (where touching is allowed): a pair whose meshes touch is taken as
    touching (distance 0; the true gap is under two mesh tolerances) and given volume 0
    without a boolean where a face plane separates their tight boxes
    (:func:`separated_boxes`, flush faces); else the OCCT distance and boolean decide."""
    best = (np.inf, 0.0, "", "")
    overlap = 0.0
    use_fcl = have_fcl()
    boxes_a = [_world_aabb(p.aabb_mm, Ta) for p in pa]
    boxes_b = [_world_aabb(p.aabb_mm, Tb) for p in pb]
    for i, p in enumerate(pa):
        for j, q in enumerate(pb):
            if same_part(p, q) or _aabb_gap(boxes_a[i], boxes_b[j]) > within_mm:
                continue
            dm = _part_mesh_distance(p, q, Ta, Tb) if use_fcl else np.inf
            if dm > within_mm:
                continue
            if certify_touch and dm <= CONTACT_MM:
                # meshes in contact: taken as touching (the true gap is under 2 mesh
                # tolerances); no volume where a face plane separates the tight boxes
                if separated_boxes(_tight_body_box(p), Ta, _tight_body_box(q), Tb):
                    d, vol = 0.0, 0.0
                else:
                    d, vol = exact_pair(placed(p.shape, Ta), placed(q.shape, Tb))
            else:
                d, vol = exact_pair(placed(p.shape, Ta), placed(q.shape, Tb))
            overlap += vol
            if d < best[0] or (d <= CONTACT_MM and vol > best[1]):
                best = (d, vol, p.name, q.name)
    return best[0], overlap, best[2], best[3], best[1]


class _PoseNames:
    """How a sweep names its poses: by crank angle (``phi1_rad``, a four-bar stroke: the
    closest pose may be refined between samples) or by label (any motion: a workspace grid,
    the 6-DOF excursions of a flotor). ``value(i)`` is the pose's position (phi1 in rad, or
    the index), ``entry(v)`` its name in the report (degrees, or the label)."""

    def __init__(self, phi1_rad, labels):
        self.phi = None if labels is not None else np.asarray(phi1_rad, dtype=float)
        self.labels = None if labels is None else tuple(labels)
        self.key = "phi1_deg" if labels is None else "pose"
        self.n = len(self.phi) if labels is None else len(self.labels)

    def value(self, i: int):
        return float(self.phi[i]) if self.phi is not None else int(i)

    def entry(self, v):
        return float(np.degrees(v)) if self.phi is not None else self.labels[int(v)]


def _scenes(prepared: Prepared, method: str, margin: float, clearance_min_mm: float, joints):
    """(culled scene, unculled scene) of the fast pass for ``method`` ("fcl", "manifold3d")."""
    if method == "fcl":
        jx = {}
        for (a, b), axes in (joints or {}).items():
            jx[(a, b)] = [(np.asarray(xa, float), np.asarray(xb, float)) for xa, xb in axes]
            jx[(b, a)] = [(np.asarray(xb, float), np.asarray(xa, float)) for xa, xb in axes]
        return _FclScene(prepared, margin, jx), _FclScene(prepared, np.inf, jx)
    if method == "manifold3d":
        return (_ManifoldScene(prepared, margin, clearance_min_mm + 10.0),
                _ManifoldScene(prepared, np.inf, clearance_min_mm + 10.0))
    raise InterferenceError(f"unknown sweep method {method!r} (fcl, manifold3d, auto)")


def _fast_pass(scene, full, tfs: dict, pairs: list, threshold: float, slack: float,
               names: _PoseNames, tf_at) -> tuple[dict, float]:
    """Mesh distances of every body pair over the poses (z-culled where the scene culls,
    unculled where a left-out part could be closer), the closest pose of each pair refined
    between its neighbours when ``tf_at`` is given. Returns ``({(a, b): (d (N,), i_min,
    pose_min, d_min, Ta_min, Tb_min)}, smallest distance found, {(a, b): (distances or
    lower bounds (N,), measured (N,))})``."""
    n = names.n
    for a, b in pairs:  # coarse poses of every pair first: a global minimum to prune with
        scene.pair(a, b, tfs[a][0], tfs[b][0])
    coarse = sorted(set(range(0, n, COARSE_STEP)) | {n - 1})
    coarse_d = {(a, b): {i: scene.distance(a, b, tfs[a][i], tfs[b][i]) for i in coarse}
                for a, b in pairs}
    g_min = min((min(v.values()) for v in coarse_d.values()), default=np.inf)
    dist, measured, scenes = {}, {}, {}
    for a, b in pairs:
        sc = scene
        if scene.lower_bound[(a, b)] < g_min:  # a culled part may be closer: measure without culling
            sc = full
        dist[(a, b)], measured[(a, b)] = bounded_pair_distances(
            sc, a, b, tfs[a], tfs[b],
            lambda m, g=lambda: g_min: max(threshold, min(m, g())),
            pre=coarse_d[(a, b)] if sc is scene else None,
        )
        scenes[(a, b)] = sc
        g_min = min(g_min, float(dist[(a, b)][measured[(a, b)]].min()))
    fast = {}
    for (a, b), d in dist.items():
        d = np.where(measured[(a, b)], d, np.inf)
        i_min = int(np.argmin(d))
        v_min, d_min = names.value(i_min), float(d[i_min])
        Ta_min, Tb_min = tfs[a][i_min], tfs[b][i_min]
        if d_min <= max(threshold, g_min + 2 * slack) and tf_at is not None and n > 2:
            v_min, d_min, Ta_min, Tb_min = _refine(scenes[(a, b)], a, b, names, i_min,
                                                   (v_min, d_min, Ta_min, Tb_min), tf_at)
        fast[(a, b)] = (d, i_min, v_min, d_min, Ta_min, Tb_min)
    return fast, g_min, {k: (dist[k], measured[k]) for k in dist}


def _refine(sc, a: str, b: str, names: _PoseNames, i_min: int, best: tuple, tf_at) -> tuple:
    """The closest pose of a pair refined between its neighbouring crank angles (bounded
    scalar search); ``best`` = (phi, d, Ta, Tb) kept when the search finds nothing closer."""
    from scipy.optimize import minimize_scalar

    n = names.n
    lo = float(names.phi[max(i_min - 1, 0)])
    hi = float(names.phi[min(i_min + 1, n - 1)])

    def f(p):
        T = tf_at(p)
        return sc.distance(a, b, T[a], T[b])

    r = minimize_scalar(f, bounds=(lo, hi), method="bounded", options={"xatol": 1e-4})
    if r.fun < best[1]:
        T = tf_at(float(r.x))
        return float(r.x), float(r.fun), T[a], T[b]
    return best


def _is_clash(de: float, vol: float, clearance_min_mm: float, contact_ok: bool) -> bool:
    """A collision: a common volume above :data:`OVERLAP_MIN_MM3` when contact is allowed;
    else contact or a distance under ``clearance_min_mm``."""
    if contact_ok:
        return de <= CONTACT_MM and vol > OVERLAP_MIN_MM3
    return de <= CONTACT_MM or de < clearance_min_mm - CONTACT_MM


# long-function: one loop over the body pairs carrying the exact pass's running minimum,
# overlap and collision list (split further it would pass all of them back and forth)
def _exact_pass(prepared: Prepared, fast: dict, tfs: dict, names: _PoseNames, *, threshold: float,
                slack: float, clearance_min_mm: float, exact: bool, contact_ok: bool,
                fail_fast: bool = False, groups=None, raw=None, joints=None) -> dict:
    """Exact pass: near contacts, and the closest pose of every pair that may hold the
    minimum (OCCT distance; common volume at contact). Returns the report fields.
    ``joints`` (:func:`sweep`): the part pairs whose distance does not change with the pose
    (:func:`split_invariant`) are checked at a body pair's first checked pose only.
    ``fail_fast``: stop at the first collision (the build is refused anyway). ``groups``
    (labelled poses): ``label -> group``; the closest pose of each group is checked too.
    ``raw``: ``{pair: (distances or lower bounds (N,), measured (N,))}`` of the fast pass."""
    key = names.key
    table = _PoseTable(names, raw or {})
    pairs_out, collisions = [], []
    n_exact, t_exact = 0, 0.0
    best_clear, best_info, total_overlap = np.inf, {}, 0.0
    global_mesh_min = min((v[3] for v in fast.values()), default=np.inf)
    for (a, b), (d, i_min, v_min, d_min, Ta_min, Tb_min) in fast.items():
        row = {"bodies": [a, b], "mesh_min_mm": d_min, f"{key}_at_min": names.entry(v_min)}
        clear = d_min
        if exact:
            t1 = time.perf_counter()
            checks = []
            if d_min <= max(threshold, global_mesh_min + 2 * slack):
                checks.append((v_min, Ta_min, Tb_min, max(threshold, d_min + slack)))
            near = set(np.flatnonzero(d < threshold).tolist())
            more = near | _group_minima(d, names, groups)
            checks += [  # a group's closest pose: every part pair that may hold its minimum
                (names.value(i), tfs[a][i], tfs[b][i],
                 threshold if i in near else max(threshold, float(d[i]) + slack))
                for i in sorted(more)
                if i != i_min
            ]
            ex_min, ex_parts, ex_v = np.inf, ("", ""), v_min
            moving = split_invariant(prepared.bodies[a], prepared.bodies[b], (joints or {}).get((a, b)))[:2]
            for k, (v, Ta, Tb, within) in enumerate(checks):
                pa_, pb_ = (prepared.bodies[a], prepared.bodies[b]) if k == 0 else moving
                de, vol, pa, pb, vp = exact_check_pair(pa_, pb_, Ta, Tb, within, certify_touch=contact_ok)
                n_exact += 1
                table.exact((a, b), v, de, pa, pb)
                if de < ex_min:
                    ex_min, ex_parts, ex_v = de, (pa, pb), v
                if _is_clash(de, vol, clearance_min_mm, contact_ok):
                    c = {"bodies": [a, b], "parts": [pa, pb], key: names.entry(v),
                         "distance_mm": max(de, 0.0), "overlap_volume_mm3": vol}
                    if names.phi is None:  # the named pair's own share of the bodies' overlap
                        c["parts_overlap_volume_mm3"] = vp
                    collisions.append(c)
                    total_overlap = max(total_overlap, vol)
                    if fail_fast:
                        break
            t_exact += time.perf_counter() - t1
            if np.isfinite(ex_min):
                row.update({"exact_min_mm": ex_min, "parts": list(ex_parts),
                            f"{key}_exact": names.entry(ex_v)})
                clear = ex_min
        elif not contact_ok and (d_min <= CONTACT_MM or d_min < clearance_min_mm - CONTACT_MM):
            collisions.append({"bodies": [a, b], "parts": [], key: names.entry(v_min),
                               "distance_mm": d_min, "overlap_volume_mm3": None})
        pairs_out.append(row)
        if fail_fast and collisions:
            break
        if clear < best_clear:
            best_clear = clear
            best_info = {"bodies": [a, b], "parts": row.get("parts", []),
                         key: row.get(f"{key}_exact", row[f"{key}_at_min"]),
                         "exact": "exact_min_mm" in row}
    return {"min_clearance_mm": float(max(best_clear, 0.0)),
            "overlap_volume_mm3": float(total_overlap), "closest": best_info,
            "pairs": pairs_out, "collisions": collisions, "n_exact_checks": n_exact,
            "t_exact": t_exact, "poses": table.result()}


def _group_minima(d: np.ndarray, names: _PoseNames, groups) -> set[int]:
    """Indices of the closest pose of each group (``groups(label) -> key``; labelled poses)."""
    if groups is None or names.labels is None:
        return set()
    best: dict = {}
    for i, label in enumerate(names.labels):
        g = groups(label)
        if np.isfinite(d[i]) and (g not in best or d[i] < d[best[g]]):
            best[g] = i
    return set(best.values())


class _PoseTable:
    """The smallest distance between two bodies at each labelled pose: per body pair the
    fast pass's value (mesh distance where measured, else its lower bound), replaced by the
    exact value where the pair was checked exactly there; then the smallest over the pairs
    (:attr:`InterferenceReport.poses`)."""

    def __init__(self, names: _PoseNames, raw: dict):
        self.names = names
        self.cells: dict = {}
        if names.labels is None:
            return
        for pair, (d, measured) in raw.items():
            for i, label in enumerate(names.labels):
                self.cells[(pair, label)] = (float(d[i]), "", "mesh" if measured[i] else "bound")

    def exact(self, pair, v, de: float, pa: str, pb: str) -> None:
        if self.names.labels is None:
            return
        k = (pair, self.names.entry(v))
        if self.cells.get(k, ("", "", ""))[2] != "exact" or de < self.cells[k][0]:
            self.cells[k] = (float(de), f"{pa}/{pb}", "exact")

    def result(self) -> dict | None:
        if self.names.labels is None:
            return None
        out: dict = {}
        for (_, label), cell in self.cells.items():
            if label not in out or cell[0] < out[label][0]:
                out[label] = cell
        return out


def sweep(
    prepared: Prepared,
    tf_world_body: dict[str, np.ndarray],
    phi1_rad: np.ndarray | None,
    clearance_min_mm: float,
    *,
    method: str = "auto",
    exact: bool = True,
    tf_at=None,
    joints=None,
    labels=None,
    contact_ok: bool = False,
    fail_fast: bool = False,
    groups=None,
) -> InterferenceReport:
    """Sweep all body pairs over the poses (module docstring).

    ``tf_world_body``: ``{body: (N, 4, 4)}`` at ``phi1_rad`` (N,). ``tf_at(phi) -> {body: 4x4}``
    (optional) evaluates a single pose for the refinement step.
    ``labels``: N pose names for any other motion (``phi1_rad`` None): poses are reported by
    label (``"pose"`` keys instead of ``"phi1_deg"``), no refinement, and where the motion is
    not planar (a flotor's 6-DOF excursions) nothing is culled by z.
    ``joints``: ``{(body a, body b): [(axis xy in a's frame, axis xy in b's frame), ...]}`` for
    bodies turning about a common joint: parts that are solids of revolution about such an
    axis keep their distance to the other body at every pose, so the fcl pass measures them
    once (pose-invariant pairs) and sweeps only the rest.
    ``contact_ok``: touching is allowed (a bearing on its journal, a flotor at its stop): a
    collision is a common volume above :data:`OVERLAP_MIN_MM3`; else (four-bar) contact or
    a distance under ``clearance_min_mm`` is one. ``fail_fast``: the exact pass stops at the
    first collision (the report is then incomplete: for a build about to be refused).
    ``groups`` (labelled poses): ``label -> group key``; the closest pose of each group is
    checked exactly too (so each group's minimum in ``poses`` is exact).
    ``method``: "fcl", "manifold3d" or "auto" (fcl when installed) for the fast pass; ``exact=False`` reports the mesh
    distances only (preview fidelity).
    """
    t0 = time.perf_counter()
    names = _PoseNames(phi1_rad, labels)
    planar = _is_planar(tf_world_body)
    if labels is None and not planar:
        _check_planar(tf_world_body)
    if method == "auto":
        method = "fcl" if have_fcl() else "manifold3d"
    threshold = clearance_min_mm + 2 * prepared.mesh_tol_mm + CONFIRM_MARGIN_MM
    margin = max(threshold, CULL_MARGIN_MM) if planar else np.inf
    scene, full = _scenes(prepared, method, margin, clearance_min_mm, joints)
    t_build = time.perf_counter() - t0
    # fast pass over all pairs (z-culled), then uncull where a left-out part could be closer
    slack = 2 * prepared.mesh_tol_mm + CONFIRM_MARGIN_MM
    t1 = time.perf_counter()
    pairs = list(itertools.combinations(sorted(prepared.bodies), 2))
    with _distance_memo():
        fast, _, raw = _fast_pass(scene, full, tf_world_body, pairs, threshold, slack, names,
                                  tf_at if names.phi is not None else None)
        t_fast = time.perf_counter() - t1
        r = _exact_pass(prepared, fast, tf_world_body, names, threshold=threshold, slack=slack,
                        clearance_min_mm=clearance_min_mm, exact=exact, contact_ok=contact_ok,
                        fail_fast=fail_fast, groups=groups, raw=raw, joints=joints)
        own, own_clashes = own_part_gaps(prepared, tf_world_body, names, joints)
    return InterferenceReport(
        min_clearance_mm=r["min_clearance_mm"],
        overlap_volume_mm3=max([r["overlap_volume_mm3"], *(c["overlap_volume_mm3"] for c in own_clashes)]),
        closest=r["closest"],
        pairs=r["pairs"],
        collisions=r["collisions"] + own_clashes,
        own_part_gaps=own,
        method=f"{method}{'+occt' if exact else ' (mesh only)'}",
        mesh_tol_mm=prepared.mesh_tol_mm,
        n_poses=names.n,
        n_exact_checks=r["n_exact_checks"],
        time_s={"mesh": prepared.mesh_time_s, "bvh": t_build, "fast": t_fast,
                "exact": r["t_exact"]},
        poses=r["poses"],
    )


def own_part_gaps(prepared: Prepared, tf_world_body: dict, names, joints=None) -> tuple[dict, list[dict]]:
    """The gaps inside a bought part whose envelopes ride on two bodies (a bearing's outer ring
    in its seat's body, its inner ring on the journal's: :func:`same_part`): not a clearance
    between two parts, so outside ``min_clearance_mm``, but still checked over the motion --
    the fcl mesh distance at every pose (once where either ring turns about the joint the two
    bodies share, :func:`split_invariant`'s rule), then the exact OCCT distance and, at contact,
    the common volume at the closest pose; a common volume above :data:`OVERLAP_MIN_MM3` is a
    collision (the part's envelopes not where they belong over the motion). Returns
    (``{"pairs", "min_gap_mm", "parts", "bodies"}``, collisions)."""
    out: dict = {"pairs": 0, "min_gap_mm": None, "parts": [], "bodies": []}
    clashes = []
    for a, b in itertools.combinations(sorted(prepared.bodies), 2):
        axes = (joints or {}).get((a, b)) or []
        for p in prepared.bodies[a]:
            for q in (q for q in prepared.bodies[b] if same_part(p, q)):
                Ta, Tb = tf_world_body[a], tf_world_body[b]
                fixed = _axial([p], [xa for xa, _ in axes])[0] or _axial([q], [xb for _, xb in axes])[0]
                i = 0
                if have_fcl() and not fixed:
                    i = int(np.argmin([_part_mesh_distance(p, q, Ta[k], Tb[k]) for k in range(names.n)]))
                de, vol = exact_pair(placed(p.shape, Ta[i]), placed(q.shape, Tb[i]))
                out["pairs"] += 1
                if out["min_gap_mm"] is None or de < out["min_gap_mm"]:
                    out.update(min_gap_mm=float(max(de, 0.0)), parts=[p.name, q.name], bodies=[a, b])
                if _is_clash(de, vol, 0.0, True):
                    clashes.append({"bodies": [a, b], "parts": [p.name, q.name],
                                    names.key: names.entry(names.value(i)), "distance_mm": max(de, 0.0),
                                    "overlap_volume_mm3": vol})
    return out, clashes


def _at(c: dict) -> str:
    """Where a sweep collision happened: ``phi1 = 12.00 deg`` or ``pose <label>``."""
    if "pose" in c:
        return f"pose {c['pose']}"
    return f"phi1 = {c['phi1_deg']:.2f} deg"


def raise_on_collision(rep: InterferenceReport, clearance_min_mm: float) -> None:
    """InterferenceError naming the first collision (or a clearance under the minimum): the
    part pair, the pose (crank angle or label) and the overlap volume."""
    if not rep.collisions:
        return
    c = min(rep.collisions, key=lambda r: (r["distance_mm"], -(r["overlap_volume_mm3"] or 0.0)))
    parts = " / ".join(p for p in c["parts"] if p) or " / ".join(c["bodies"])
    if c.get("kind") == "same body":
        msg = (
            f"{parts} (both on {c['bodies'][0]}) share {c['overlap_volume_mm3']:.3f} mm^3 "
            "at every pose"
        )
    elif c["distance_mm"] <= CONTACT_MM:
        vol = c["overlap_volume_mm3"]
        what = f"overlap {vol:.3f} mm^3" if vol else "contact"
        vp = c.get("parts_overlap_volume_mm3")
        if vp is not None and vol and abs(vol - vp) > 1e-9 * vol:
            what = (f"overlap {vp:.3f} mm^3; {vol:.3f} mm^3 between "
                    f"{c['bodies'][0]} and {c['bodies'][1]}")
        msg = f"{parts} collide at {_at(c)} ({what})"
    else:
        msg = (
            f"{parts} are {c['distance_mm']:.3f} mm apart at {_at(c)} "
            f"(< clearance_min_mm = {clearance_min_mm:g})"
        )
    where = "motion" if any("pose_at_min" in r for r in rep.pairs) else "stroke"
    raise InterferenceError(
        f"{msg}; {len(rep.collisions)} near contact(s) in the {where} "
        "(use --allow-interference to export anyway)"
    )


# --------------------------------------------------------------------------- same-body pairs


@dataclass
class SameBodyResult:
    """Every pair of parts carried by one body, checked once (they do not move apart);
    ``n_box_overlaps``: OCCT booleans run (pairs whose boxes overlap, repeats of the same two
    solids in the same relative placement counted once)."""

    collisions: list[dict]
    n_pairs: int
    n_box_overlaps: int
    time_s: float

    def as_dict(self) -> dict:
        return {
            "pairs": self.n_pairs,
            "exact_checks": self.n_box_overlaps,
            "collisions": self.collisions,
        }


def static_items(instances) -> list[tuple]:
    """``(part name, body, real TopoDS shape in the part frame, tf_body_part, hull)`` of every
    part instance -- the solid written to ``assembly.step`` (not the sweep's envelopes); a
    bought part made of several solids (a bearing's rings and balls) is one item, its
    ``kind.hull`` (or None) a solid enclosing it that is intersected first."""
    return [
        (i.name, i.body, i.kind.shape, np.asarray(i.tf_body_part, float), i.kind.hull)
        for i in instances
    ]


def _signed_permutation(R: np.ndarray) -> bool:
    """True when ``R`` maps each axis onto +-one axis exactly (90-degree turns, flips)."""
    a = np.abs(R)
    return bool(np.all((a == 0.0) | (a == 1.0)) and np.all(a.sum(axis=0) == 1.0)
                and np.all(a.sum(axis=1) == 1.0))


def placed_tight_box(shape, T: np.ndarray) -> np.ndarray:
    """(2, 3) tight box (mm) of ``shape`` placed by the 4x4 rigid ``T``, through the derived
    cache (:mod:`cad.io.derived_cache`). When ``T``'s rotation is a signed permutation the
    box is the part-frame box moved (exact: every world axis is one part axis), so one
    cached box serves every such placement; otherwise the placed shape's own box, keyed by
    ``T`` exactly."""
    T = np.asarray(T, float)
    if not derived_cache.enabled():
        return tight_box(placed(shape, T))
    digest = derived_cache.shape_digest(shape)
    if _signed_permutation(T[:3, :3]):
        lo, hi = (np.array(c) for c in derived_cache.cached_json(
            "tight-box", [digest], lambda: tight_box(shape).tolist(), code=_CODE))
        c = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                      for z in (lo[2], hi[2])]) @ T[:3, :3].T + T[:3, 3]
        return np.array([c.min(axis=0), c.max(axis=0)])
    return np.array(derived_cache.cached_json(
        "tight-box-placed", [digest, T], lambda: tight_box(placed(shape, T)).tolist(), code=_CODE))


def _pair_volume(p, q, min_volume_mm3: float) -> float:
    """Common volume of two same-body parts ``(name, shape, box, hull, ...)``: their hulls
    first (a hull encloses its part, so no hull overlap means no part overlap), then the
    parts."""
    if p[3] is not None or q[3] is not None:
        hp = p[3] if p[3] is not None else p[1]
        hq = q[3] if q[3] is not None else q[1]
        if common_volume_mm3(hp, hq) <= min_volume_mm3:
            return 0.0
    return common_volume_mm3(p[1], q[1])


def _rigid_inverse(T: np.ndarray) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3] = T[:3, :3].T
    out[:3, 3] = -T[:3, :3].T @ T[:3, 3]
    return out


def _cached_pair_volume(p, q, shapes, rel: np.ndarray, min_volume_mm3: float) -> float:
    """:func:`_pair_volume` through the derived cache, keyed by the digests of both solids
    (and hulls), their relative placement ``rel`` (rounded to 1e-9) and the threshold."""
    if not derived_cache.enabled():
        return _pair_volume(p, q, min_volume_mm3)
    dg = derived_cache.shape_digest
    (sa, ha), (sb, hb) = shapes
    key = [dg(sa), dg(ha) if ha is not None else None, dg(sb), dg(hb) if hb is not None else None,
           np.round(rel, 9) + 0.0, float(min_volume_mm3)]
    return float(derived_cache.cached_json(
        "common-volume", key, lambda: _pair_volume(p, q, min_volume_mm3), code=_CODE))


def same_body_check(items, min_volume_mm3: float = OVERLAP_MIN_MM3) -> SameBodyResult:
    """Every pair of parts of one body: bounding-box culling, then the exact OCCT common volume.

    ``items``: ``(name, body, TopoDS shape in the part frame, 4x4 tf_body_part[, hull])``
    (generic: any family; :func:`static_items` makes them from part instances; a hull, when
    given, encloses the shape and is intersected first). Boxes (tight, OCCT) that
    are apart or only touch (overlap <= :data:`BOX_TOUCH_MM` on some axis) cannot share a
    volume; every other pair is intersected with ``BRepAlgoAPI_Common``. Touching is allowed
    (a screw in its clearance or tapped hole, a bearing in its seat); a common volume above
    ``min_volume_mm3`` is a collision ``{"kind": "same body", "bodies", "parts",
    "overlap_volume_mm3", "distance_mm": 0, "phi1_deg": None}`` (the pose does not matter).
    """
    t0 = time.perf_counter()
    by_body: dict[str, list[tuple]] = {}
    for name, body, shape, tf, *rest in items:
        T = np.asarray(tf, float)
        s = placed(shape, T)
        h0 = rest[0] if rest else None
        hull = placed(h0, T) if h0 is not None else None
        by_body.setdefault(body, []).append(
            (name, s, placed_tight_box(shape, T), hull, (id(shape), T), (shape, h0))
        )
    memo: dict[tuple, float] = {}
    collisions, n_pairs, n_exact = [], 0, 0
    for body, parts in sorted(by_body.items()):
        lo = np.array([p[2][0] for p in parts])
        hi = np.array([p[2][1] for p in parts])
        ov = np.minimum(hi[:, None], hi[None]) - np.maximum(lo[:, None], lo[None])
        near = (ov > BOX_TOUCH_MM).all(axis=-1)
        n_pairs += len(parts) * (len(parts) - 1) // 2
        for i, j in zip(*np.nonzero(np.triu(near, 1)), strict=True):
            (ka, Ta), (kb, Tb) = parts[i][4], parts[j][4]
            # the same two solids in the same relative placement (the same hardware at
            # another joint): the same common volume, computed once
            rel = _rigid_inverse(Ta) @ Tb
            key = (ka, kb, np.round(rel, 9).tobytes())
            if key not in memo:
                n_exact += 1
                memo[key] = _cached_pair_volume(
                    parts[i], parts[j], (parts[i][5], parts[j][5]), rel, min_volume_mm3
                )
            vol = memo[key]
            if vol > min_volume_mm3:
                collisions.append(
                    {
                        "kind": "same body",
                        "bodies": [body, body],
                        "parts": [parts[i][0], parts[j][0]],
                        "phi1_deg": None,
                        "distance_mm": 0.0,
                        "overlap_volume_mm3": vol,
                    }
                )
    return SameBodyResult(collisions, n_pairs, n_exact, time.perf_counter() - t0)


def merge_same_body(rep: InterferenceReport, same: SameBodyResult) -> InterferenceReport:
    """``rep`` with the same-body collisions added (``overlap_volume_mm3``: the largest overlap
    of any pair) and ``same_body`` filled in."""
    rep.collisions = list(rep.collisions) + list(same.collisions)
    rep.overlap_volume_mm3 = max(
        [rep.overlap_volume_mm3] + [c["overlap_volume_mm3"] for c in same.collisions]
    )
    rep.same_body = same.as_dict()
    rep.time_s = {**rep.time_s, "same_body": same.time_s}
    return rep


# --------------------------------------------------------------------- one assembly model
def joint_axes(model) -> dict:
    """``{(body, other body): [(axis xy in body, axis xy in other body), ...]}`` of every
    joint the model's instances carry across two bodies (a part with ``other_body`` whose
    kind is a solid of revolution about its vertical z axis: a bearing's inner ring moving
    with its journal). Input of :func:`sweep`'s revolution shortcut."""
    out: dict = {}
    for inst in model.instances:
        if inst.other_body is None or not getattr(inst.kind, "revolution", False):
            continue
        Ta, Tb = np.asarray(inst.tf_body_part, float), np.asarray(inst.tf_other_part, float)
        if abs(abs(Ta[2, 2]) - 1.0) > 1e-12 or abs(abs(Tb[2, 2]) - 1.0) > 1e-12:
            continue
        a, b, ax = inst.body, inst.other_body, (Ta[:2, 3].copy(), Tb[:2, 3].copy())
        if b < a:
            a, b, ax = b, a, (ax[1], ax[0])
        axes = out.setdefault((a, b), [])
        if not any(np.allclose(ax[0], x[0]) and np.allclose(ax[1], x[1]) for x in axes):
            axes.append(ax)
    return out


def model_motion(model, bodies) -> tuple[dict[str, np.ndarray], tuple[str, ...]]:
    """``({body: (N, 4, 4)}, N labels)``: each of ``bodies`` over the model's motion (a body
    the motion leaves out is fixed at its ``tf_world_body``); one pose, the exported one,
    when the model has no motion."""
    if not model.motion:
        labels = ("exported pose",)
    else:
        labels = tuple(model.pose_labels)
    n = len(labels)
    out = {}
    for b in bodies:
        if model.motion and b in model.motion:
            T = np.asarray(model.motion[b], float)
            if T.shape != (n, 4, 4):
                raise InterferenceError(
                    f"motion of body {b!r} has shape {T.shape}, expected ({n}, 4, 4) for the "
                    f"{n} pose labels")
            out[b] = T
        else:
            out[b] = np.repeat(np.asarray(model.tf_world_body[b], float)[None], n, axis=0)
    return out, labels


def check_model(
    model,
    clearance_min_mm: float = 0.0,
    *,
    mesh_tol_mm: float = SWEEP_MESH_TOL_MM,
    exact: bool = True,
    contact_ok: bool = True,
    joints=None,
    method: str = "auto",
    fail_fast: bool = False,
    groups=None,
    phi1_rad=None,
    tf_at=None,
    same_body: SameBodyResult | None = None,
) -> InterferenceReport:
    """The one interference check of an assembly model (:class:`cad.assembly.model.AssemblyModel`)
    of any family: every moving solid against every other solid over the model's motion.

    * every pair of bodies (moving or ground) at each of the N poses of ``model.motion``
      (:func:`sweep`: the collision envelopes meshed at ``mesh_tol_mm``, fcl BVH distances
      with box and Lipschitz pruning, parts turning about a shared joint measured once,
      z culling where the motion is planar; then the exact OCCT distance, and the common
      volume at contact, near contact and at each pair's closest pose);
    * every pair of parts on one body once (:func:`same_body_check` on the real solids).

    ``contact_ok`` (default): touching is allowed, a common volume above
    :data:`OVERLAP_MIN_MM3` is a collision; False: contact or a distance under
    ``clearance_min_mm`` is one (the four-bar's rule). Collisions name the bodies, the parts,
    the pose label (``"pose"``) and ``overlap_volume_mm3``; :func:`raise_on_collision`
    turns the first into an :class:`cad.errors.InterferenceError`. ``joints``: as
    :func:`sweep`, added to :func:`joint_axes` of the model (joints no part carries across,
    a motor shaft in its housing). Distances mm, volumes mm^3.
    Only the sampled poses are checked: a clash between two neighbouring samples is found
    only where it reaches a sample. ``fail_fast`` (a build that refuses any clash): the
    same-body pairs first, and on a collision there the sweep is not run; the sweep's exact
    pass stops at its first collision (the report lists the clashes found until then).
    ``groups``: ``label -> group key``, the closest pose of each group checked exactly
    (:func:`sweep`); the report's ``poses`` gives the smallest distance at every pose.
    ``phi1_rad`` (N,) and ``tf_at`` (a four-bar stroke): the poses are crank angles (named
    ``phi1_deg``, the closest pose refined between samples by ``tf_at(phi) -> {body: 4x4}``)
    instead of ``model.pose_labels``. ``same_body``: the same-body result when already
    computed (a build runs it beside other work), else it is computed here.
    """
    same = same_body if same_body is not None else same_body_check(static_items(model.instances))
    if fail_fast and same.collisions:
        rep = InterferenceReport(0.0, 0.0, {}, [], [], "same-body check only (fail fast)",
                                 mesh_tol_mm, len(model_motion(model, [])[1]), 0)
        return merge_same_body(rep, same)
    prepared = prepare(collision_items(model.instances), mesh_tol_mm)
    tfs, labels = model_motion(model, sorted(prepared.bodies))
    jx = joint_axes(model)
    for (a, b), axes in (joints or {}).items():
        if b < a:
            a, b, axes = b, a, [(xb, xa) for xa, xb in axes]
        jx.setdefault((a, b), []).extend(axes)
    if phi1_rad is not None:
        labels = None
    rep = sweep(prepared, tfs, phi1_rad, clearance_min_mm, method=method, exact=exact, joints=jx,
                labels=labels, contact_ok=contact_ok, fail_fast=fail_fast, groups=groups,
                tf_at=tf_at)
    return merge_same_body(rep, same)


# ------------------------------------------------------------- poses of a free body (6-DOF)
# (was cad/assembly/static.py) The smallest distance between a moving part set and a fixed
# one at arbitrary rigid poses, for motion that is not a planar crank sweep: the PowerMouse's
# part-level study :func:`cad.families.powermouse.parts.motion_clearances` (the builds' check is
# :func:`check_model`). fcl mesh distance at every pose; OCCT ``BRepExtrema_DistShapeShape``
# (and the common volume at contact) only at poses whose mesh distance is within
# ``2 tol + CONFIRM_MARGIN_MM`` of contact, and at the closest pose of each pose group (so
# the reported minimum is exact).
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

    vol = common_volume_mm3(a, b)
    return -(vol ** (1 / 3)) if vol > 1e-6 else 0.0


def _merged_bvh(parts):
    import fcl

    v, f = _body_arrays(parts)
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
        ``2 mesh_tol_mm + CONFIRM_MARGIN_MM``; ``inf``: every pose, the reference of the bench).

    Method: fcl mesh distance of every part pair at every pose (pairs ordered by box gap);
    at a pose within ``2 tol + margin`` of contact (or the closest of its group), every
    part pair whose mesh distance is that close is measured exactly: OCCT distance where
    the meshes are apart; where they touch, contact is certified without a boolean when a
    face plane of either part's tight box separates the two boxes (flush faces), else the
    boolean common decides (overlap volume). Returns ``{label: (clearance_mm, "moving
    part/fixed part", exact)}``; negative = overlap (minus the cube root of the common
    volume, mm), 0 = contact.
    """
    pm = prepare([(it[0], "m", it[1], it[2]) for it in moving], mesh_tol_mm)
    pf = prepare([(it[0], "f", it[1], it[2]) for it in fixed], mesh_tol_mm)
    pa, pb = pm.bodies["m"], pf.bodies["f"]
    la = [
        (tight_box(it[1]), np.asarray(it[2], float), it[3] if len(it) > 3 else ()) for it in moving
    ]
    lb = [
        (tight_box(it[1]), np.asarray(it[2], float), it[3] if len(it) > 3 else ()) for it in fixed
    ]
    eye = np.eye(4)
    near_mm = 2 * mesh_tol_mm + CONFIRM_MARGIN_MM if near_mm is None else near_mm
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
        within = d + 2 * mesh_tol_mm + CONFIRM_MARGIN_MM  # pairs that may hold the minimum
        best = (np.inf, "")
        for i, p in enumerate(pa):
            wa = _world_aabb(p.aabb_mm, T)
            for j, q in enumerate(pb):
                if _aabb_gap(wa, q.aabb_mm) > within:
                    continue
                dm = _part_mesh_distance(p, q, T, eye)
                if dm > within:
                    continue
                sa = placed(p.shape, T)
                de = 0.0
                if dm > 1e-6:
                    de = min_distance_mm(sa, q.shape)
                if de <= CONTACT_MM:
                    de = _contact_or_overlap(
                        sa, q.shape, la[i][0], T @ la[i][1], lb[j][0], lb[j][1], la[i][2], lb[j][2]
                    )
                if de < best[0]:
                    best = (de, f"{p.name}/{q.name}")
        out[label] = (float(best[0]), best[1], True)
    return out
