"""Run a sweep on Dask and keep its table: resume, atomic writes, progress, chart.

* Scheduling is Dask's (``distributed``): an embedded ``LocalCluster`` of worker
  processes (one thread each: the CAD kernel holds the GIL; OCCT's own thread pool cut to
  one thread, so N workers use N cores) or an existing cluster at ``--scheduler
  tcp://HOST:PORT``. Before the clock starts (``startup_s``) the workers import the CAD
  stack and make the first variant's parts into the shared disk cache, each part on one
  worker (:func:`warm_up`); variants then read the parts they share from the cache. Each variant is one task; its arguments are the
  variant's raw design mapping (~2 kB) and it returns one row (~1 kB). When a worker
  dies, Dask's scheduler reruns its tasks on the others (the nanny restarts it); a task
  that kills workers repeatedly ends as a ``lost`` row, rerun on the next resume.
* The table (``results.parquet`` and ``results.csv``) is rewritten atomically
  (temporary file + rename) as rows complete -- at most every :data:`WRITE_EVERY_S`
  seconds and :data:`WRITE_COST_FACTOR` times the last rewrite's duration -- and at the
  end, so a crash loses at most the variants completed since the last rewrite.
* Resume: variants whose ``design_hash`` (resolved design, fidelity and ``--target``
  texts) is in the table with status ok / missed / error are skipped; ``lost`` rows are
  rerun. Rows of other variants (an earlier, different sweep into the same folder) stay.
"""

from __future__ import annotations

import json
import logging
import math
import pickle
import signal
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from cad.errors import DesignError
from cad.io.atomic import atomic_path, write_text_atomic
from cad.report.figures import save_figure
from cad.sweep.spec import Vary, apply, assignments, design_hash
from cad.sweep.task import VALUE_KEYS, evaluate_variant

OWNED = ("results.parquet", "results.csv", "sweep.json", "chart.png", "manifest.json")
DONE = ("ok", "missed", "error")
WRITE_EVERY_S = 1.0
#: ...and never more often than this many times its own duration: the rewrite is O(rows)
#: (measured 2.7 s of CPU for 10^5 rows), so the client spends at most ~1/5 of its time on it
WRITE_COST_FACTOR = 5.0
META_COLUMNS = ("variant", "design_hash", "targets", "status", "error", "targets_missed")
TAIL_COLUMNS = ("wall_s", "cpu_s", "worker")


@dataclass
class SweepSpec:
    """Everything that defines a sweep (what ``sweep.json`` records)."""

    design: Path
    raw: dict[str, Any]
    varies: tuple[Vary, ...]
    samples: int | None
    seed: int
    fidelity: str
    cli_targets: tuple = ()
    chart: tuple[str, str] = ("torque_variation", "M11_max_g")
    targets_text: str = ""

    def variants(self) -> list[tuple[dict[str, Any], dict[str, Any], str]]:
        """(assignment, resolved raw design, design hash) of every distinct variant, in order."""
        out, seen = [], set()
        for a in assignments(self.varies, self.samples, self.seed):
            raw = apply(self.raw, a)
            h = design_hash(raw, self.fidelity, self.targets_text)
            if h not in seen:
                seen.add(h)
                out.append((a, raw, h))
        return out


@dataclass
class Progress:
    total: int
    skipped: int
    counts: dict[str, int] = field(default_factory=lambda: dict.fromkeys((*DONE, "lost"), 0))
    t0: float = field(default_factory=time.perf_counter)
    bar: Any = None
    task: Any = None
    printed: int = -1

    def start(self) -> None:
        if sys.stderr.isatty():
            from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeRemainingColumn

            self.bar = Progress("sweep", BarColumn(), MofNCompleteColumn(), TimeRemainingColumn(),
                                transient=True)
            self.bar.start()
            self.task = self.bar.add_task("sweep", total=self.total)

    def add(self, status: str) -> None:
        self.counts[status] += 1
        if self.bar is not None:
            self.bar.advance(self.task)

    @property
    def done(self) -> int:
        return sum(self.counts.values())

    def line(self) -> None:
        if self.bar is not None or self.done == self.printed:
            return
        self.printed = self.done
        dt = time.perf_counter() - self.t0
        c = self.counts
        print(f"sweep: {self.done}/{self.total} variants done ({c['ok']} ok, {c['missed']} missed, "
              f"{c['error']} error, {c['lost']} lost; {self.skipped} resumed) "
              f"{self.done / dt if dt > 0 else 0:.2f}/s", file=sys.stderr, flush=True)

    def stop(self) -> None:
        if self.bar is not None:
            self.bar.stop()


def read_table(out: Path) -> list[dict[str, Any]]:
    """Rows of an existing ``results.parquet`` (empty list when absent)."""
    p = out / "results.parquet"
    if not p.is_file():
        return []
    import pyarrow.parquet as pq

    try:
        return pq.read_table(p).to_pylist()
    except Exception as exc:  # a damaged table is not silently replaced: it is the user's data
        raise DesignError("--out", f"{p} cannot be read as Parquet ({exc}); move it away to restart") from None


def columns(varies: tuple[Vary, ...]) -> list[str]:
    return [v.key for v in varies] + list(META_COLUMNS) + list(VALUE_KEYS) + list(TAIL_COLUMNS)


def publish(out: Path, rows: list[dict[str, Any]], cols: list[str]) -> None:
    """:func:`write_table` then ``manifest.json`` (the folder's ownership record, README
    "Output folders"), with SIGINT/SIGTERM held back in between so that an interrupt
    cannot leave a table the manifest does not list (a kill -9 still can: then move the
    folder's manifest.json away to resume)."""
    from cad.export.manifest import write_manifest

    main = threading.current_thread() is threading.main_thread() and hasattr(signal, "pthread_sigmask")
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM}) if main else None
    try:
        write_table(out, rows, cols)
        write_manifest(out)
    finally:
        if old is not None:
            signal.pthread_sigmask(signal.SIG_SETMASK, old)


def write_table(out: Path, rows: list[dict[str, Any]], cols: list[str]) -> None:
    """``results.parquet`` and ``results.csv``, each written atomically, rows sorted by variant."""
    import pyarrow as pa
    import pyarrow.csv as pacsv
    import pyarrow.parquet as pq

    rows = sorted(rows, key=lambda r: (r.get("variant") is None, r.get("variant") or 0))
    data = {c: [r.get(c) for r in rows] for c in cols}
    for c in VALUE_KEYS + ("wall_s", "cpu_s"):
        data[c] = [math.nan if v is None else float(v) for v in data[c]]
    table = pa.table({c: pa.array(v) for c, v in data.items()})
    with atomic_path(out / "results.parquet") as tmp:
        pq.write_table(table, tmp)
    with atomic_path(out / "results.csv") as tmp:
        pacsv.write_csv(table, tmp)


#: no dashboard, and the scheduler's small HTTP server (metrics) on a free port: two sweeps
#: (or a sweep beside another Dask cluster) must not fight over port 8787
NO_HTTP_PORT = {"dashboard_address": ":0"}


def _client(workers: int, scheduler: str | None):
    from dask.distributed import Client, LocalCluster

    if scheduler:
        try:
            return Client(scheduler, timeout="10s"), None
        except OSError as exc:
            raise DesignError("--scheduler", f"cannot reach {scheduler}: {exc}") from None
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                           dashboard_address=None, silence_logs=logging.ERROR,
                           scheduler_kwargs=NO_HTTP_PORT)
    return Client(cluster), cluster


def run_sweep(spec: SweepSpec, out: Path, workers: int, scheduler: str | None) -> dict[str, Any]:
    """Evaluate every variant not yet in ``out``'s table; returns the summary (``sweep.json``)."""
    out.mkdir(parents=True, exist_ok=True)
    cols = columns(spec.varies)
    rows = read_table(out)
    if rows and not set(v.key for v in spec.varies) <= set(rows[0]):
        raise DesignError("--out", f"{out} holds a sweep over other keys; use a new folder")
    done = {r["design_hash"] for r in rows if r.get("status") in DONE}
    rows = [r for r in rows if r.get("status") in DONE]
    variants = spec.variants()
    todo = [(i, a, raw, h) for i, (a, raw, h) in enumerate(variants) if h not in done]
    resumed = len(variants) - len(todo)
    prog = Progress(total=len(todo), skipped=resumed)
    t0 = time.perf_counter()
    t_eval = startup = c_eval = client_cpu = None
    last_done = None
    if todo:
        from dask.distributed import as_completed

        client, cluster = _client(workers, scheduler)
        warm_up(client, todo[0][2], str(spec.design), spec.fidelity, one_core=cluster is not None)
        t_eval, c_eval = time.perf_counter(), time.process_time()
        startup = t_eval - t0
        prog.start()
        try:
            futs = {client.submit(evaluate_variant, raw, str(spec.design), spec.fidelity,
                                  spec.cli_targets, pure=False): (i, a, h) for i, a, raw, h in todo}
            last_write, write_cost = time.perf_counter(), 0.0
            for fut in as_completed(futs):
                i, a, h = futs[fut]
                try:
                    res = fut.result()
                except Exception as exc:  # KilledWorker after repeated worker deaths, lost connection
                    res = {"status": "lost", "error": f"{type(exc).__name__}: {exc}"}
                rows.append({**a, "variant": i, "design_hash": h, "targets": spec.targets_text, **res})
                prog.add(res["status"])
                last_done = time.perf_counter()
                client_cpu = time.process_time() - c_eval
                if last_done - last_write >= max(WRITE_EVERY_S, WRITE_COST_FACTOR * write_cost):
                    tw = time.perf_counter()
                    publish(out, rows, cols)
                    prog.line()
                    last_write = time.perf_counter()
                    write_cost = last_write - tw
        finally:
            prog.stop()
            publish(out, rows, cols)
            client.close()
            if cluster is not None:
                cluster.close()
    elif not (out / "results.parquet").exists():
        publish(out, rows, cols)
    prog.line()
    wall = time.perf_counter() - t0
    summary = {
        "design": str(spec.design), "fidelity": spec.fidelity, "samples": spec.samples, "seed": spec.seed,
        "vary": [{"key": v.key, "values": list(v.values)} if v.values else
                 {"key": v.key, "lo": v.lo, "hi": v.hi, "n": v.n} for v in spec.varies],
        "targets": spec.targets_text, "variants": len(variants), "resumed": resumed,
        "evaluated": len(todo), **{k: prog.counts[k] for k in (*DONE, "lost")},
        "workers": workers if not scheduler else None, "scheduler": scheduler or "LocalCluster",
        "wall_s": wall,
        "startup_s": startup,
        "evaluation_s": (last_done - t_eval) if todo and last_done else None,
        "variants_per_s": (len(todo) / (last_done - t_eval)) if todo and last_done else None,
        "client_cpu_s": client_cpu,
        "variant_wall_s_median": _median([r.get("wall_s") for r in rows[-len(todo):]] if todo else []),
        "variant_cpu_s_median": _median([r.get("cpu_s") for r in rows[-len(todo):]] if todo else []),
        "task_bytes_in_median": _median([float(len(pickle.dumps((raw, str(spec.design), spec.fidelity,
                                                                  spec.cli_targets))))
                                         for _, _, raw, _ in todo]),
        "task_bytes_out_median": _median([float(len(pickle.dumps(r))) for r in rows[-len(todo):]]
                                         if todo else []),
        "files": [str(out / n) for n in OWNED],
    }
    write_chart(out / "chart.png", rows, spec)
    write_text_atomic(out / "sweep.json", json.dumps(summary, indent=1))
    from cad.export.manifest import write_manifest

    write_manifest(out)
    return summary


def warm_up(client, raw: dict[str, Any], source: str, fidelity: str, one_core: bool) -> None:
    """Before the clock starts: on every worker the CAD import (and, for the embedded
    cluster, one OCCT thread: one worker per core); then the first variant's parts made and
    integrated into the shared disk cache, split over the workers (each part once, not once
    per worker: that duplicated cold start cost the 2-worker sweep ~1 s per worker). A
    failure here is not fatal: the variant fails later as a row."""
    from dask.distributed import wait

    try:
        client.run(_setup_worker, one_core)
        addrs = sorted(client.scheduler_info()["workers"])
        futs = [client.submit(_warm_share, raw, source, fidelity, (i, len(addrs)), workers=[a],
                              allow_other_workers=False, pure=False) for i, a in enumerate(addrs)]
        wait(futs)
    except Exception:  # noqa: S110 - a worker that cannot warm up fails its variants as rows
        pass


def _setup_worker(one_core: bool) -> None:
    """Import the CAD stack in a worker (what its first variant would otherwise pay); with
    ``one_core``, OCCT's thread pool (parallel booleans, build123d turns them on) is cut to
    one thread so that two workers on two cores do not oversubscribe them. BLAS threads are
    already 1 in Dask's worker processes (``distributed.nanny.pre-spawn-environ``)."""
    from cad.parts.lazy_import import import_build123d

    import_build123d()
    import cad.build.inertia  # noqa: F401

    if one_core:
        from OCP.OSD import OSD_ThreadPool

        OSD_ThreadPool.DefaultPool_s().Init(1)


def _warm_share(raw: dict[str, Any], source: str, fidelity: str, share: tuple[int, int]) -> int:
    """This worker's share of :func:`cad.build.inertia.warm_part_cache` for one variant."""
    from cad.build.inertia import warm_part_cache
    from cad.design import parse_design

    try:
        return warm_part_cache(parse_design(raw, source), fidelity, share)
    except Exception:  # noqa: BLE001 - the variant reports its own error as a row
        return 0


def _median(v: list[float]) -> float | None:
    v = sorted(x for x in v if x is not None and math.isfinite(x))
    return v[len(v) // 2] if v else None


def write_chart(path: Path, rows: list[dict[str, Any]], spec: SweepSpec) -> None:
    """Scatter of the chosen objectives (``--chart X,Y``), coloured by the first varied key."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    xk, yk = spec.chart
    ck = spec.varies[0].key
    good = [r for r in rows if r.get("status") in ("ok", "missed")
            and all(isinstance(r.get(k), float) and math.isfinite(r[k]) for k in (xk, yk))]
    fig, ax = plt.subplots(figsize=(7, 5))
    cvals = [r.get(ck) for r in good]
    numeric = all(isinstance(c, (int, float)) and not isinstance(c, bool) for c in cvals)
    if good and numeric:
        for status, marker in (("ok", "o"), ("missed", "x")):
            sel = [r for r in good if r["status"] == status]
            if sel:
                sc = ax.scatter([r[xk] for r in sel], [r[yk] for r in sel], c=[r[ck] for r in sel],
                                marker=marker, cmap="viridis", vmin=min(cvals), vmax=max(cvals),
                                label=f"targets {'met' if status == 'ok' else 'missed'}")
        fig.colorbar(sc, ax=ax, label=ck)
    elif good:
        for j, cat in enumerate(sorted({str(c) for c in cvals})):
            sel = [r for r in good if str(r.get(ck)) == cat]
            ax.scatter([r[xk] for r in sel], [r[yk] for r in sel], color=plt.cm.tab10(j % 10), label=f"{ck} = {cat}")
    if good:
        ax.legend(fontsize=8)
    n_err = sum(r.get("status") in ("error", "lost") for r in rows)
    ax.set_xlabel(xk)
    ax.set_ylabel(yk)
    ax.set_title(f"{spec.design.name}: {len(good)} variants ({spec.fidelity})"
                 + (f", {n_err} failed (see results table)" if n_err else ""), fontsize=10)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        save_figure(fig, tmp, "png", dpi=90)
    plt.close(fig)
