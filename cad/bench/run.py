"""``hapticad bench`` (and :func:`cad.api.bench`): run the speed-against-accuracy topics of
:mod:`cad.bench`, write ``bench.json`` and the charts, and rate the performance goals."""

from __future__ import annotations

import json
import os
from pathlib import Path

#: topic -> module in cad.bench exposing run(quick, out_dir) -> dict
TOPICS = {
    "kinematics": "cad.bench.kinematics",
    "massprops": "cad.bench.massprops",
    "interference": "cad.bench.interference",
    "gii": "cad.bench.gii",
    "voicecoil": "cad.bench.voicecoil",
    "build": "cad.bench.build",
    "fidelity": "cad.bench.fidelity",
    "wall": "cad.bench.wall",
    "structure": "cad.bench.structure",
    "families": "cad.bench.families",
    "evaluations": "cad.bench.evaluations",
    "sweep": "cad.bench.sweep",
    "capstan": "cad.bench.capstan",
    "optimize": "cad.bench.optimize",
    "motor_choice": "cad.bench.motor_choice",
}
#: topics run only when named in --only (minutes of worker processes each)
OPT_IN = ("sweep", "optimize", "motor_choice")


def _cpu_s() -> float:
    """CPU seconds (user + system) of this process and of its finished children."""
    import resource

    me, ch = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + ch.ru_utime + ch.ru_stime


def goal_rows(results: dict) -> list[tuple[str, str, str, bool | None]]:
    """(goal, measured, target, met) rows for the issue's performance goals."""
    rows = []
    k = results.get("kinematics", {})
    if "poses" in k and "ratio" in k["poses"]:
        r = k["poses"]["ratio"]
        rows.append(("4-bar poses+J vs pylinkage step_fast (100k)", f"{r:.2f}x", ">= 100x", r >= 100))
        rv = k["poses"].get("ratio_vs_python_step")
        if rv:
            rows.append(("4-bar poses+J vs pylinkage step() (pure Python)", f"{rv:.0f}x", "(reference)", None))
    if "analyze_wall" in k:
        t = k["analyze_wall"]["median_s"]
        rows.append(("hapticad analyze wall (median)", f"{t:.3f} s", "<= 0.6 s", t <= 0.6))
    b = results.get("build", {})
    for key, goal, lim in (("cold_s", "hapticad build hoeken cold (--no-cache)", 4.5),
                           ("cold_empty_shape_cache_s", "hapticad build hoeken, empty shape cache", 8.0),
                           ("cached_s", "hapticad build hoeken unchanged", 1.5)):
        if key in b:
            rows.append((goal, f"{b[key]:.2f} s", f"<= {lim} s", b[key] <= lim))
    if "same_body_share" in b:
        rows.append(("every-pair same-body check, share of the cold Hoeken build",
                     f"{100 * b['same_body_share']:.1f} % wall ({100 * b['same_body_share_cpu']:.1f} % CPU)",
                     "<= 10 %", b["same_body_share"] <= b["same_body_share_goal"]))
    c = results.get("capstan", {})
    if "ratio" in c:
        rows.append(("capstan Hoeken cold build / direct Hoeken's (medians, one run)",
                     f"{c['ratio']:.2f}x ({c['capstan_cold_s']:.2f} / {c['direct_cold_s']:.2f} s)",
                     f"<= {c['ratio_goal']:g}x", c["meets_goal"]))
    f = results.get("families", {})
    if "powermouse_cold_s" in f:
        t = f["powermouse_cold_s"]
        rows.append(("hapticad build powermouse cold", f"{t:.2f} s", "<= 8 s", t <= 8.0))
    e = results.get("evaluations", {})
    for key, goal in (("same_s", "check/fit evaluation, same design (after import)"),
                      ("material_s", "check/fit evaluation, new material"),
                      ("thickness_s", "check/fit evaluation, new bar thickness"),
                      ("fresh_process_s", "check evaluation in a fresh process (disk cache)")):
        if key in e:
            rows.append((goal, f"{e[key]:.3f} s (CPU {e[key.replace('_s', '_cpu_s')]:.3f} s)",
                         f"<= {e['goal_s']} s", e[key] <= e["goal_s"]))
    sw = results.get("sweep", {})
    if "speedup_2_workers" in sw:
        rows.append(("sweep throughput, 2 workers / 1 worker",
                     f"{sw['speedup_2_workers']:.2f}x ({sw['variants_per_s_1']:.2f} -> {sw['variants_per_s_2']:.2f} variants/s)",
                     ">= 1.7x", sw["speedup_2_workers"] >= 1.7))
    o = results.get("optimize", {})
    if "ratio_2_workers" in o:
        rows.append(("optimize trials per second on Dask, 2 workers / 1 worker (medians, one run)",
                     f"{o['ratio_2_workers']:.2f}x ({o['trials_per_s_1']:.1f} -> {o['trials_per_s_2']:.1f} "
                     f"trials/s; in-process {o['trials_per_s_in_process']:.1f})", "(measured)", None))
    i = results.get("interference", {})
    if "sweep_200_s" in i:
        rows.append(("interference sweep 200 poses x all pairs", f"{i['sweep_200_s']:.2f} s, {i.get('missed', '?')} missed",
                     "<= 1 s, 0 missed", i["sweep_200_s"] <= 1.0 and i.get("missed", 1) == 0))
    if "same_body_s" in i:
        sb = i.get("same_body", {})
        missed = sb.get("missed")
        rows.append(("same-body pairs, Hoeken fabrication (box cull + OCCT common)",
                     f"{i['same_body_s']:.2f} s, {sb.get('exact_checks', '?')}/{sb.get('pairs', '?')} exact, "
                     f"{'?' if missed is None else missed} missed", "0 missed vs brute force",
                     None if missed is None else missed == 0))
    g = results.get("gii", {})
    if "culling_ratio" in g:
        rows.append(("GII culling: fewer Jacobian evaluations than brute", f"{g['culling_ratio']:.1f}x",
                     ">= 10x", g["culling_ratio"] >= 10))
    return rows


def run_bench(out: Path, quick: bool = False, only: str | None = None, echo=None) -> dict:
    """Run the topics (``only``: a comma list of :data:`TOPICS`; default every topic not in
    :data:`OPT_IN`) into ``out`` (only a folder bench or build wrote); ``echo(topic)`` before
    each. Returns what ``bench.json`` holds: per topic its results with ``bench_wall_s`` and
    ``bench_cpu_s``, ``total``, ``goals`` (goal, measured, target, met), ``measured``,
    ``command``. Raises DesignError for an unknown topic. The folder is published whole at the
    end (:func:`cad.io.atomic.atomic_dir_update`, the files of topics not run kept): an
    interrupt leaves it as it was, never charts without their manifest."""
    from cad.errors import DesignError
    from cad.export.manifest import write_manifest
    from cad.io.atomic import atomic_dir_update, write_text_atomic
    from cad.io.outdir import check_out_dir

    out = Path(out)
    topics = [t for t in TOPICS if t not in OPT_IN]
    if only:
        topics = [t.strip() for t in only.split(",") if t.strip()]
        for t in topics:
            if t not in TOPICS:
                raise DesignError("--only", f"unknown topic {t!r} (known: {', '.join(TOPICS)})")
    check_out_dir(out)  # only a folder bench (or build) wrote: docs/reliability.md "Output folders"
    with atomic_dir_update(out, check_out_dir) as tmp:  # all at once: an interrupt leaves `out` as it was
        results = _run_topics(topics, quick, tmp, echo)
        results["command"] = "hapticad bench" + (" --quick" if quick else "") + (f" --only {only}" if only else "")
        write_text_atomic(tmp / "bench.json", json.dumps(results, indent=1, default=float))
        write_manifest(tmp)
    return results


def _run_topics(topics: list[str], quick: bool, out: Path, echo) -> dict:
    """Each topic's results (charts written into ``out``), then ``total``, ``goals`` and
    ``measured``: what ``bench.json`` holds but its ``command`` (:func:`run_bench`)."""
    import importlib
    import time

    results: dict = {}
    for t in topics:
        try:
            mod = importlib.import_module(TOPICS[t])
        except ImportError as exc:
            results[t] = {"skipped": f"module not available: {exc}"}
            continue
        t0, c0 = time.perf_counter(), _cpu_s()
        if echo is not None:
            echo(t)
        results[t] = mod.run(quick, out)
        results[t]["bench_wall_s"] = time.perf_counter() - t0
        results[t]["bench_cpu_s"] = _cpu_s() - c0
    rows = goal_rows(results)
    total_wall = sum(r.get("bench_wall_s", 0.0) for r in results.values() if isinstance(r, dict))
    total_cpu = sum(r.get("bench_cpu_s", 0.0) for r in results.values() if isinstance(r, dict))
    results["total"] = {"wall_s": total_wall, "cpu_s": total_cpu, "quick": quick, "topics": topics,
                        "load_avg_1min": os.getloadavg()[0] if hasattr(os, "getloadavg") else None}
    results["goals"] = [{"goal": g, "measured": m, "target": tg, "met": ok} for g, m, tg, ok in rows]
    results["measured"] = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())  # the docs' generated tables
    return results
