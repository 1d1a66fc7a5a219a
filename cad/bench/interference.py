"""Benchmark: interference over a stroke -- exact OCCT vs manifold3d vs a BVH (python-fcl).

Scene with a closed-form answer: K pairs of cylinders (radius 5 mm, 5 mm tall), one fixed,
one sweeping past it along x(phi) = 10 + g_k + phi^2 (and turning about its axis, so mesh
facets do not line up); the smallest gap of pair k is exactly ``g_k`` (negative: an
overlap of depth |g_k|), reached at phi = 0, which is one of the N samples. A pair is a
*contact* when g_k < ``CONTACT_CLEARANCE_MM``.

Methods (time = meshing + the whole sweep, median of repeats):

* ``occt-exact`` -- BRepExtrema_DistShapeShape on the solids at every pose and pair (the
  brute-force exact sweep);
* ``fcl`` / ``manifold3d`` -- mesh-only sweeps at several absolute mesh tolerances;
* ``fcl+occt`` -- the tool's method (:func:`cad.assembly.interference.sweep`): mesh pass,
  then every near contact confirmed exactly.

Error = max over the pairs with g_k <= ``ERROR_RANGE_MM`` of |reported gap - g_k| (gaps of
overlapping pairs count as 0);
``missed`` / ``false_alarms`` count contacts a method gets wrong. A second part times the
tool's sweep on the real Hoeken assembly (all body pairs, :data:`SWEEP_POSES` crank
angles, meshing timed apart) and checks it against exact OCCT distances at sampled poses
(:func:`_real_assembly`). Top-level keys for the issue-7 goals: ``sweep_200_s`` (median
sweep time) and ``missed`` (contacts missed by the tool's method at its default mesh
tolerance on the closed-form scene, plus misses against the exact Hoeken samples).
Issue 10 adds ``same_body_s``: the median time of the same-body check (every pair of
parts of one body, box culling then OCCT common volume) on the Hoeken assembly at
fabrication fidelity, and, in a full run, the brute-force count (every same-body pair
intersected, no culling) it must equal (``same_body.missed`` = 0).
"""

from __future__ import annotations

import statistics
import time
from pathlib import Path

import numpy as np

from cad.assembly import interference as itf
from cad.bench.common import median_time as _median_time
from cad.bench.common import save_chart
from cad.design import load_design
from cad.export.shapes import placed
from cad.families.fourbar import assemble
from cad.families.fourbar.build import joint_axes
from cad.families.fourbar.pose import body_transforms
from cad.occ.distance import common_volume_mm3, min_distance_mm
from cad.parts import translation
from cad.parts.reference_solids import cylinder_on_xy
from cad.tolerances import BENCH_INTERFERENCE_MESH_TOLERANCES_MM as MESH_TOLERANCES_MM

#: Prescribed smallest gaps of the cylinder pairs (mm); negative = overlap depth.
GAPS_MM = (-0.2, -0.05, -0.01, 0.01, 0.03, 0.08, 0.2, 0.5)
#: A pair closer than this is a contact (mm).
CONTACT_CLEARANCE_MM = 0.1
#: The gap error is scored on pairs up to this gap (mm): the contacts and the near misses
#: a clearance check must get right; farther pairs only need to be known to be far.
ERROR_RANGE_MM = 0.1
RADIUS_MM = 5.0
HEIGHT_MM = 5.0
REFERENCE = "closed form: cylinder pair k has smallest gap g_k at phi = 0 (a sample)"


def interference_scene(n_poses: int):
    cyl = cylinder_on_xy(RADIUS_MM, HEIGHT_MM)
    items, tfs = [], {}
    phi = np.linspace(-1.0, 1.0, n_poses if n_poses % 2 else n_poses + 1)
    for k, g in enumerate(GAPS_MM):
        y = 30.0 * k
        items.append((f"fixed{k}", f"f{k}", cyl, translation(0.0, y)))
        items.append((f"moving{k}", f"m{k}", cyl, np.eye(4)))
        T = np.repeat(np.eye(4)[None], len(phi), axis=0)
        T[:, 1, 3] = 0.0
        tfs[f"f{k}"] = T
        ang = 0.37 * phi + 0.11 * k
        M = np.repeat(np.eye(4)[None], len(phi), axis=0)
        M[:, 0, 0], M[:, 0, 1], M[:, 1, 0], M[:, 1, 1] = (
            np.cos(ang),
            -np.sin(ang),
            np.sin(ang),
            np.cos(ang),
        )
        M[:, 0, 3] = 2 * RADIUS_MM + g + phi**2
        M[:, 1, 3] = y
        tfs[f"m{k}"] = M
    return items, tfs, phi


def _score(gaps: dict[int, float]) -> dict:
    err = max(
        abs(max(gaps[k], 0.0) - max(g, 0.0)) for k, g in enumerate(GAPS_MM) if g <= ERROR_RANGE_MM
    )
    missed = sum(1 for k, g in enumerate(GAPS_MM) if g < CONTACT_CLEARANCE_MM <= gaps[k])
    false = sum(1 for k, g in enumerate(GAPS_MM) if gaps[k] < CONTACT_CLEARANCE_MM <= g)
    return {"error": err, "missed": missed, "false_alarms": false}


def _pair_gaps(rep) -> dict[int, float]:
    out = {}
    for row in rep.pairs:
        a, b = row["bodies"]
        if a[1:] != b[1:]:
            continue
        k = int(a[1:])
        out[k] = row.get("exact_min_mm", row["mesh_min_mm"])
    return out


def _occt_brute(items, tfs, phi) -> dict[int, float]:
    out = {}
    for k in range(len(GAPS_MM)):
        (_, fb, fs, ft), (_, mb, ms, mt) = items[2 * k], items[2 * k + 1]
        best = np.inf
        for i in range(len(phi)):
            d = min_distance_mm(placed(fs, tfs[fb][i] @ ft), placed(ms, tfs[mb][i] @ mt))
            best = min(best, d)
        out[k] = best
    return out


def run(quick: bool, out_dir: Path) -> dict:
    """Run the benchmark, write the chart (PNG + SVG) into ``out_dir``, return the points."""
    repeats = 1 if quick else 3
    n_poses = 21 if quick else 201
    items, tfs, phi = interference_scene(n_poses)
    points: list[dict] = []

    t, gaps = _median_time(lambda: _occt_brute(items, tfs, phi), repeats)
    points.append({"method": "occt-exact", "knob": "B-rep", "time_s": t, **_score(gaps)})
    tols = MESH_TOLERANCES_MM[1:4] if quick else MESH_TOLERANCES_MM
    for tol in tols:
        for method in ("fcl", "manifold3d"):

            def mesh_only(tol=tol, method=method):
                prep = itf.prepare(items, tol)
                return itf.sweep(prep, tfs, phi, CONTACT_CLEARANCE_MM, method=method, exact=False)

            t, rep = _median_time(mesh_only, repeats)
            points.append(
                {"method": method, "knob": f"tol={tol:g}mm", "time_s": t, **_score(_pair_gaps(rep))}
            )

        def tool(tol=tol):
            prep = itf.prepare(items, tol)
            return itf.sweep(prep, tfs, phi, CONTACT_CLEARANCE_MM, method="fcl", exact=True)

        t, rep = _median_time(tool, repeats)
        points.append(
            {
                "method": "fcl+occt",
                "knob": f"tol={tol:g}mm",
                "time_s": t,
                "exact_checks": rep.n_exact_checks,
                **_score(_pair_gaps(rep)),
            }
        )
    real = _real_assembly(n_poses=SWEEP_POSES, repeats=repeats, n_ref=2 if quick else 12)
    tool_tol = [
        p
        for p in points
        if p["method"] == "fcl+occt" and p["knob"] == f"tol={itf.SWEEP_MESH_TOL_MM:g}mm"
    ]
    missed_scene = tool_tol[0]["missed"] if tool_tol else None
    same = _same_body(repeats, brute_force=not quick)
    charts = _chart(points, Path(out_dir))
    return {
        "topic": "interference",
        "reference": REFERENCE,
        "gaps_mm": list(GAPS_MM),
        "contact_clearance_mm": CONTACT_CLEARANCE_MM,
        "poses": len(phi),
        "repeats": repeats,
        # goals of issue 7 section 4 (read by `hapticad bench`)
        "sweep_200_s": real["sweep_time_s"],
        "missed": (missed_scene or 0) + real["missed"],
        "missed_closed_form_scene": missed_scene,
        "missed_hoeken_vs_exact": real["missed"],
        "points": points,
        "hoeken_assembly": real,
        # issue 10: every same-body pair once (boxes, then OCCT common volume)
        "same_body_s": same["time_s"],
        "same_body": same,
        "charts": charts,
    }


#: Poses of the timed Hoeken sweep (issue 7 section 4: 200 poses x all pairs <= 1 s).
SWEEP_POSES = 200
#: The exact reference on the Hoeken assembly measures every part pair whose bounding
#: boxes come within this distance (mm) of each other (plus the mesh tolerance, by which
#: a solid may stick out of its mesh's box).
REF_RADIUS_MM = 2.0


def _hoeken(fidelity: str = "inertia"):
    d = load_design(Path(__file__).resolve().parents[2] / "designs" / "hoeken.toml")
    model = assemble(d, fidelity, poses=SWEEP_POSES)  # layers planned over the timed sweep
    return d, model.extra.joints_mm, model


def _exact_reference(prep, tfs, poses, radius_mm: float) -> dict:
    """Exact OCCT distance of every body pair at the given poses, over every part pair whose
    boxes come within ``radius_mm`` (no mesh involved): ``{(a, b): {pose: distance}}``."""
    import itertools

    out: dict = {}
    within = radius_mm + prep.mesh_tol_mm
    for a, b in itertools.combinations(sorted(prep.bodies), 2):
        for i in poses:
            Ta, Tb = tfs[a][i], tfs[b][i]
            best = np.inf
            for p in prep.bodies[a]:
                ba = itf._world_aabb(p.aabb_mm, Ta)
                for q in prep.bodies[b]:
                    if itf._aabb_gap(ba, itf._world_aabb(q.aabb_mm, Tb)) > within:
                        continue
                    best = min(best, min_distance_mm(placed(p.shape, Ta), placed(q.shape, Tb)))
            out[(a, b)] = {**out.get((a, b), {}), int(i): best}
    return out


def _same_body(repeats: int, brute_force: bool) -> dict:
    """The same-body check (issue 10) on the Hoeken assembly at fabrication fidelity (bearings
    with balls): median time of ``repeats``; with ``brute_force``, every same-body pair
    intersected without box culling (the reference: culling must lose no collision)."""
    _, _, asm = _hoeken("fabrication")
    items = itf.static_items(asm.instances)
    times, r = [], None
    for _ in range(repeats):
        r = itf.same_body_check(items)
        times.append(r.time_s)
    out = {
        "time_s": statistics.median(times),
        "times_s": times,
        "pairs": r.n_pairs,
        "exact_checks": r.n_box_overlaps,
        "collisions": len(r.collisions),
    }
    if brute_force:
        t0 = time.perf_counter()
        ps = [(n, b, placed(s, T)) for n, b, s, T, _ in items]
        found = sum(
            common_volume_mm3(p[2], q[2]) > itf.OVERLAP_MIN_MM3
            for i, p in enumerate(ps)
            for q in ps[i + 1 :]
            if p[1] == q[1]
        )
        out.update(
            {"brute_force_collisions": int(found), "brute_force_s": time.perf_counter() - t0}
        )
        out["missed"] = int(found) - len(r.collisions)
    return out


def _real_assembly(n_poses: int, repeats: int, n_ref: int) -> dict:
    """The tool's sweep on the Hoeken assembly (all body pairs, ``n_poses`` crank angles):
    median time of ``repeats`` (meshing timed apart: done once per build), and a check
    against exact OCCT distances at ``n_ref`` poses (evenly spread, plus the pose of each
    pair's reported minimum): a *miss* is an exact sample below the reported
    ``min_clearance_mm`` (the sweep claims a minimum over the stroke) or an exact
    clearance violation the sweep did not report."""
    d, J, asm = _hoeken()
    clearance = d.parts.clearance_min_mm
    phi = np.linspace(d.phi1_min_rad, d.phi1_max_rad, n_poses)
    tfs = body_transforms(d.linkage, phi)
    items = itf.collision_items(asm.instances)
    times, mesh_times, rep, prep = [], [], None, None
    for _ in range(repeats):
        t0 = time.perf_counter()
        prep = itf.prepare(items, itf.SWEEP_MESH_TOL_MM)  # fresh meshes and BVHs every time
        mesh_times.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        rep = itf.sweep(prep, tfs, phi, clearance, joints=joint_axes(J))
        times.append(time.perf_counter() - t0)
    poses = set(np.linspace(0, n_poses - 1, n_ref).round().astype(int).tolist())
    at_min = {int(np.argmin(np.abs(phi - np.radians(r["phi1_deg_at_min"])))) for r in rep.pairs}
    t0 = time.perf_counter()
    ref = _exact_reference(prep, tfs, sorted(poses | at_min), REF_RADIUS_MM)
    t_ref = time.perf_counter() - t0
    reported = {tuple(c["bodies"]) for c in rep.collisions}
    missed, worst = 0, np.inf
    for pair, by_pose in ref.items():
        for dist in by_pose.values():
            worst = min(worst, dist)
            if dist < rep.min_clearance_mm - 1e-6:
                missed += 1
            elif dist < clearance - itf.CONTACT_MM and pair not in reported:
                missed += 1
    return {
        "poses": n_poses,
        "sweep_time_s": statistics.median(times),
        "sweep_times_s": times,
        "mesh_time_s": statistics.median(mesh_times),
        "goal_s": 1.0,
        "min_clearance_mm": rep.min_clearance_mm,
        "exact_reference_min_mm": worst,
        "exact_reference_poses": len(poses | at_min),
        "exact_reference_time_s": t_ref,
        "missed": missed,
        "exact_checks": rep.n_exact_checks,
        "collisions": len(rep.collisions),
        "phase_times_s": rep.time_s,
    }


def _chart(points: list[dict], out_dir: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    floor = 1e-6
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for meth, mk in (("occt-exact", "*"), ("fcl", "o"), ("manifold3d", "s"), ("fcl+occt", "D")):
        sel = [p for p in points if p["method"] == meth]
        if not sel:
            continue
        xs = [p["time_s"] for p in sel]
        ys = [max(p["error"], floor) for p in sel]
        ax.loglog(xs, ys, marker=mk, linestyle="-" if len(sel) > 1 else "", label=meth)
        for p, x, y in zip(sel, xs, ys, strict=True):
            ax.annotate(
                f"{p['knob'].replace('tol=', '')} miss={p['missed']}",
                (x, y),
                fontsize=6,
                textcoords="offset points",
                xytext=(4, 3),
            )
    ax.set_xlabel("time per sweep [s] (meshing included, median)")
    ax.set_ylabel(f"max |gap error| [mm] (floored at {floor:g})")
    ax.set_title("interference sweep: error vs time; miss = missed contacts")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.suptitle("reference: " + REFERENCE, fontsize=8)
    fig.tight_layout(rect=(0, 0, 1, 0.95))

    paths = save_chart(fig, out_dir, "interference_error_vs_time")
    plt.close(fig)
    return paths


if __name__ == "__main__":  # pragma: no cover - manual run
    import json
    import sys

    print(
        json.dumps(
            run(quick="--full" not in sys.argv, out_dir=Path("bench_out")), indent=1, default=str
        )
    )
