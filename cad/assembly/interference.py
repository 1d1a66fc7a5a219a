"""Interference over the stroke: N poses x all pairs of bodies, fast mesh pass then exact OCCT.

Method (SPEC "Measured pitfalls": meshes at 0.1 mm miss a 0.05 mm overlap; exact answers
need OCCT):

1. every part is meshed once at ``mesh_tol_mm`` (absolute, OCCT) and its triangles
   gathered per rigid body (ground, crank, coupler, rocker) in the body frame;
2. fast pass: at every pose the distance between every pair of bodies by a BVH
   (python-fcl) -- or by manifold3d ``min_gap`` (``method="manifold3d"``); the
   pose of the smallest distance of each pair is refined between its neighbouring
   samples (bounded scalar search on the mesh distance);
3. exact pass: every (pair, pose) whose mesh distance is below
   ``clearance_min_mm + 2 mesh_tol_mm + CONFIRM_MARGIN_MM`` -- a chordal mesh is off
   the true surface by at most the tolerance, on either side (convex faces lie inside
   the mesh, holes outside) -- and the closest pose of every pair are checked with OCCT
   on the solids: ``BRepExtrema_DistShapeShape`` between the parts of the two bodies
   whose bounding boxes come that close, and ``BRepAlgoAPI_Common`` volume where the
   distance is zero.

``min_clearance_mm`` is the exact smallest distance found between two different bodies
(0 with ``overlap_volume_mm3 > 0`` for a collision). Parts of one body are never
checked against each other (they are fastened together by design).
"""

from __future__ import annotations

import itertools
import time
from dataclasses import dataclass, field

import numpy as np

from cad.errors import InterferenceError

#: Extra margin on top of 2 x mesh tolerance before a near contact is confirmed exactly (mm).
CONFIRM_MARGIN_MM = 0.05
#: Distances below this are contact (mm): OCCT's own confusion tolerance is 1e-7.
CONTACT_MM = 1e-6
#: Default absolute mesh tolerance of the fast pass (mm); see cad.bench.interference.
SWEEP_MESH_TOL_MM = 0.05


@dataclass
class PartMesh:
    name: str
    body: str
    shape: object  # TopoDS_Shape placed in the body frame
    vertices_mm: np.ndarray
    faces: np.ndarray
    aabb_mm: np.ndarray  # (2, 3) in the body frame


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

    def as_dict(self) -> dict:
        return {
            "min_clearance_mm": self.min_clearance_mm,
            "overlap_volume_mm3": self.overlap_volume_mm3,
            "closest": self.closest,
            "pairs": self.pairs,
            "collisions": self.collisions,
            "method": self.method,
            "mesh_tol_mm": self.mesh_tol_mm,
            "n_poses": self.n_poses,
            "n_exact_checks": self.n_exact_checks,
        }


def collision_items(instances) -> list[tuple[str, str, object, np.ndarray]]:
    """``(part name, body, TopoDS shape in the part frame, tf_body_part)`` for every collision
    envelope of the assembly (bearings split into their two rings)."""
    out = []
    for inst in instances:
        if inst.kind.collision is None:
            out.append((inst.name, inst.body, inst.kind.shape, inst.tf_body_part))
            continue
        for role, shp in inst.kind.collision:
            if role == "self":
                body, tf = inst.body, inst.tf_body_part
            else:
                body, tf = inst.other_body, inst.tf_other_part
            if body is None or tf is None:
                raise InterferenceError(f"{inst.name}: collision role {role!r} without the joint's other body")
            out.append((f"{inst.name}[{'inner' if role == 'other' else 'outer'}]", body, shp, tf))
    return out


def prepare(items, mesh_tol_mm: float = SWEEP_MESH_TOL_MM) -> Prepared:
    """Mesh every collision item once (cached per shape) and place it in its body frame."""
    from cad.export.shapes import placed
    from cad.export.stl import mesh_shape

    t0 = time.perf_counter()
    cache: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    bodies: dict[str, list[PartMesh]] = {}
    for name, body, shape, tf in items:
        key = id(shape)
        if key not in cache:
            cache[key] = mesh_shape(shape, mesh_tol_mm, 0.5)
        v, f = cache[key]
        T = np.asarray(tf, dtype=float)
        vb = v @ T[:3, :3].T + T[:3, 3]
        bodies.setdefault(body, []).append(
            PartMesh(name, body, placed(shape, T), vb, f, np.array([vb.min(axis=0), vb.max(axis=0)])))
    return Prepared(bodies, mesh_tol_mm, time.perf_counter() - t0)


def _body_arrays(parts: list[PartMesh]):
    vs, fs, off = [], [], 0
    for p in parts:
        vs.append(p.vertices_mm)
        fs.append(p.faces + off)
        off += len(p.vertices_mm)
    return np.concatenate(vs), np.concatenate(fs)


class _FclScene:
    def __init__(self, prepared: Prepared):
        import fcl

        self.fcl = fcl
        self.objs = {}
        for body, parts in prepared.bodies.items():
            v, f = _body_arrays(parts)
            g = fcl.BVHModel()
            g.beginModel(len(v), len(f))
            g.addSubModel(v.astype(np.float64), f.astype(np.int32))
            g.endModel()
            self.objs[body] = fcl.CollisionObject(g, fcl.Transform())

    def distance(self, a: str, b: str, Ta: np.ndarray, Tb: np.ndarray) -> float:
        fcl = self.fcl
        oa, ob = self.objs[a], self.objs[b]
        oa.setTransform(fcl.Transform(Ta[:3, :3], Ta[:3, 3]))
        ob.setTransform(fcl.Transform(Tb[:3, :3], Tb[:3, 3]))
        return float(fcl.distance(oa, ob, fcl.DistanceRequest(), fcl.DistanceResult()))


class _ManifoldScene:
    def __init__(self, prepared: Prepared, search_mm: float):
        import manifold3d

        self.m3 = manifold3d
        self.search = search_mm
        self.man = {}
        for body, parts in prepared.bodies.items():
            pieces = []
            for p in parts:
                mesh = manifold3d.Mesh64(vert_properties=np.ascontiguousarray(p.vertices_mm, dtype=np.float64),
                                         tri_verts=np.ascontiguousarray(p.faces, dtype=np.uint64))
                pieces.append(manifold3d.Manifold(mesh))
            self.man[body] = manifold3d.Manifold.batch_boolean(pieces, manifold3d.OpType.Add)

    def _placed(self, body, T):
        return self.man[body].transform(np.ascontiguousarray(T[:3, :], dtype=np.float64))

    def distance(self, a, b, Ta, Tb) -> float:
        ma, mb = self._placed(a, Ta), self._placed(b, Tb)
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


def exact_check(pa: list[PartMesh], pb: list[PartMesh], Ta: np.ndarray, Tb: np.ndarray,
                within_mm: float) -> tuple[float, float, str, str]:
    """Exact (OCCT) smallest distance and overlap volume between two bodies at one pose.

    Only part pairs whose world bounding boxes are within ``within_mm`` are measured.
    Returns (distance mm, overlap volume mm^3, part a, part b) of the closest pair.
    """
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Common
    from OCP.BRepExtrema import BRepExtrema_DistShapeShape
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    from cad.export.shapes import placed

    best = (np.inf, 0.0, "", "")
    overlap = 0.0
    boxes_a = [_world_aabb(p.aabb_mm, Ta) for p in pa]
    boxes_b = [_world_aabb(p.aabb_mm, Tb) for p in pb]
    for i, p in enumerate(pa):
        for j, q in enumerate(pb):
            if _aabb_gap(boxes_a[i], boxes_b[j]) > within_mm:
                continue
            sa, sb = placed(p.shape, Ta), placed(q.shape, Tb)
            ext = BRepExtrema_DistShapeShape(sa, sb)
            d = float(ext.Value()) if ext.IsDone() else np.inf
            vol = 0.0
            if d <= CONTACT_MM:
                common = BRepAlgoAPI_Common(sa, sb)
                props = GProp_GProps()
                BRepGProp.VolumeProperties_s(common.Shape(), props)
                vol = max(0.0, float(props.Mass()))
                overlap += vol
            if d < best[0] or (d <= CONTACT_MM and vol > best[1]):
                best = (d, vol, p.name, q.name)
    return best[0], overlap, best[2], best[3]


def sweep(prepared: Prepared, tf_world_body: dict[str, np.ndarray], phi1_rad: np.ndarray,
          clearance_min_mm: float, *, method: str = "fcl", exact: bool = True,
          tf_at=None) -> InterferenceReport:
    """Sweep all body pairs over the poses (module docstring).

    ``tf_world_body``: ``{body: (N, 4, 4)}`` at ``phi1_rad`` (N,). ``tf_at(phi) -> {body: 4x4}``
    (optional) evaluates a single pose for the refinement step.
    ``method``: "fcl" or "manifold3d" for the fast pass; ``exact=False`` reports the mesh
    distances only (preview fidelity).
    """
    t0 = time.perf_counter()
    scene = _FclScene(prepared) if method == "fcl" else _ManifoldScene(prepared, clearance_min_mm + 10.0)
    t_build = time.perf_counter() - t0
    bodies = sorted(prepared.bodies)
    n = len(phi1_rad)
    threshold = clearance_min_mm + 2 * prepared.mesh_tol_mm + CONFIRM_MARGIN_MM
    pairs_out, collisions = [], []
    n_exact = 0
    best_clear, best_info, total_overlap = np.inf, {}, 0.0
    t_fast = t_exact = 0.0
    for a, b in itertools.combinations(bodies, 2):
        t1 = time.perf_counter()
        d = np.array([scene.distance(a, b, tf_world_body[a][i], tf_world_body[b][i]) for i in range(n)])
        i_min = int(np.argmin(d))
        phi_min, d_min = float(phi1_rad[i_min]), float(d[i_min])
        Ta_min, Tb_min = tf_world_body[a][i_min], tf_world_body[b][i_min]
        if tf_at is not None and n > 2:
            lo = float(phi1_rad[max(i_min - 1, 0)])
            hi = float(phi1_rad[min(i_min + 1, n - 1)])
            from scipy.optimize import minimize_scalar

            def f(p, a=a, b=b):
                T = tf_at(p)
                return scene.distance(a, b, T[a], T[b])

            r = minimize_scalar(f, bounds=(lo, hi), method="bounded", options={"xatol": 1e-4})
            if r.fun < d_min:
                phi_min, d_min = float(r.x), float(r.fun)
                T = tf_at(phi_min)
                Ta_min, Tb_min = T[a], T[b]
        t_fast += time.perf_counter() - t1
        row = {"bodies": [a, b], "mesh_min_mm": d_min, "phi1_deg_at_min": float(np.degrees(phi_min))}
        if exact:
            t1 = time.perf_counter()
            slack = 2 * prepared.mesh_tol_mm + CONFIRM_MARGIN_MM
            checks = [(phi_min, Ta_min, Tb_min, max(threshold, d_min + slack))] + [
                (float(phi1_rad[i]), tf_world_body[a][i], tf_world_body[b][i], threshold)
                for i in np.flatnonzero(d < threshold) if i != i_min
            ]
            ex_min, ex_parts, ex_phi = np.inf, ("", ""), phi_min
            for phi, Ta, Tb, within in checks:
                de, vol, pa, pb = exact_check(prepared.bodies[a], prepared.bodies[b], Ta, Tb, within)
                n_exact += 1
                if de < ex_min:
                    ex_min, ex_parts, ex_phi = de, (pa, pb), phi
                if de <= CONTACT_MM or de < clearance_min_mm:
                    collisions.append({"bodies": [a, b], "parts": [pa, pb], "phi1_deg": float(np.degrees(phi)),
                                       "distance_mm": max(de, 0.0), "overlap_volume_mm3": vol})
                    total_overlap = max(total_overlap, vol)
            t_exact += time.perf_counter() - t1
            if not np.isfinite(ex_min):  # nothing came within the threshold: the mesh value stands
                ex_min = d_min
            row.update({"exact_min_mm": ex_min, "parts": list(ex_parts), "phi1_deg_exact": float(np.degrees(ex_phi))})
            clear = ex_min
        else:
            clear = d_min
            if d_min <= CONTACT_MM or d_min < clearance_min_mm:
                collisions.append({"bodies": [a, b], "parts": [], "phi1_deg": float(np.degrees(phi_min)),
                                   "distance_mm": d_min, "overlap_volume_mm3": None})
        pairs_out.append(row)
        if clear < best_clear:
            best_clear = clear
            best_info = {"bodies": [a, b], "parts": row.get("parts", []),
                         "phi1_deg": row.get("phi1_deg_exact", row["phi1_deg_at_min"])}
    return InterferenceReport(
        min_clearance_mm=float(max(best_clear, 0.0)), overlap_volume_mm3=float(total_overlap), closest=best_info,
        pairs=pairs_out, collisions=collisions,
        method=f"{method}{'+occt' if exact else ' (mesh only)'}", mesh_tol_mm=prepared.mesh_tol_mm,
        n_poses=n, n_exact_checks=n_exact,
        time_s={"mesh": prepared.mesh_time_s, "bvh": t_build, "fast": t_fast, "exact": t_exact},
    )


def raise_on_collision(rep: InterferenceReport, clearance_min_mm: float) -> None:
    """InterferenceError naming the first collision (or a clearance under the minimum)."""
    if not rep.collisions:
        return
    c = min(rep.collisions, key=lambda r: r["distance_mm"])
    parts = " / ".join(p for p in c["parts"] if p) or " / ".join(c["bodies"])
    if c["distance_mm"] <= CONTACT_MM:
        vol = c["overlap_volume_mm3"]
        what = f"overlap {vol:.3f} mm^3" if vol else "contact"
        msg = f"{parts} collide at phi1 = {c['phi1_deg']:.2f} deg ({what})"
    else:
        msg = (f"{parts} are {c['distance_mm']:.3f} mm apart at phi1 = {c['phi1_deg']:.2f} deg "
               f"(< clearance_min_mm = {clearance_min_mm:g})")
    raise InterferenceError(f"{msg}; {len(rep.collisions)} near contact(s) in the stroke "
                            "(use --allow-interference to export anyway)")
