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
* The table (``results.parquet`` and ``results.csv``) is rewritten as rows complete -- at
  most every :data:`WRITE_EVERY_S` seconds and :data:`WRITE_COST_FACTOR` times the last
  rewrite's duration -- and at the end, by the protocol of :mod:`cad.studies.sweep.table` (the
  manifest names each file's next sha256 before it is renamed into place), so a crash or a
  signal at any moment loses at most the variants completed since the last rewrite and
  never blocks the rerun.
* Resume: variants whose ``design_hash`` (resolved design, fidelity and ``--target``
  texts) is in the table with status ok / missed / error are skipped; ``lost`` rows are
  rerun; a hash is in the table once. Rows of other variants (an earlier, different sweep
  into the same folder) stay.
"""

from __future__ import annotations

import json
import math
import pickle
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import cad.families.fourbar.inertia  # noqa: F401
from cad.design import parse_design
from cad.families.fourbar.inertia import warm_part_cache
from cad.io import signals
from cad.io.escape import mathtext
from cad.occ.threads import limit_occt_threads
from cad.parts.lazy_import import import_build123d
from cad.report.figures import save_figure
from cad.studies import cluster as cluster_mod
from cad.studies.sweep.spec import Vary, apply, assignments, design_hash
from cad.studies.sweep.table import DONE, MANIFEST, OWNED, TABLE, publish, read_table
from cad.studies.sweep.task import VALUE_KEYS, evaluate_variant

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


def columns(varies: tuple[Vary, ...]) -> list[str]:
    return [v.key for v in varies] + list(META_COLUMNS) + list(VALUE_KEYS) + list(TAIL_COLUMNS)


def table_writers(rows: list[dict[str, Any]], cols: list[str]) -> dict[str, Any]:
    """``results.parquet`` and ``results.csv`` writers (:func:`cad.studies.sweep.table.publish`),
    rows sorted by variant."""
    import pyarrow as pa
    import pyarrow.csv as pacsv
    import pyarrow.parquet as pq

    rows = sorted(rows, key=lambda r: (r.get("variant") is None, r.get("variant") or 0))
    data = {c: [r.get(c) for r in rows] for c in cols}
    for c in VALUE_KEYS + ("wall_s", "cpu_s"):
        data[c] = [math.nan if v is None else float(v) for v in data[c]]
    table = pa.table({c: pa.array(v) for c, v in data.items()})
    return {TABLE: lambda p: pq.write_table(table, p), "results.csv": lambda p: pacsv.write_csv(table, p)}


#: how long ``--scheduler ADDRESS`` is tried before the sweep is refused (read at each call)
CONNECT_TIMEOUT_S = cluster_mod.CONNECT_TIMEOUT_S
NO_HTTP_PORT = cluster_mod.NO_HTTP_PORT  # the embedded cluster's (tests start their own alike)


def _evaluate(spec: SweepSpec, out: Path, todo: list, rows: list, cols: list[str],
              prog: Progress, client, one_core: bool) -> dict[str, Any]:
    """Run ``todo`` on ``client``, appending each row to ``rows`` and rewriting the table
    as rows complete (module docstring); returns the timings of ``sweep.json``."""
    from dask.distributed import as_completed

    warm_up(client, todo[0][2], str(spec.design), spec.fidelity, one_core=one_core)
    t_eval, c_eval = time.perf_counter(), time.process_time()
    timing: dict[str, Any] = {"t_eval": t_eval, "last_done": None, "client_cpu_s": None}
    prog.start()
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
        timing["last_done"] = time.perf_counter()
        timing["client_cpu_s"] = time.process_time() - c_eval
        if timing["last_done"] - last_write >= max(WRITE_EVERY_S, WRITE_COST_FACTOR * write_cost):
            tw = time.perf_counter()
            publish(out, table_writers(rows, cols))
            prog.line()
            last_write = time.perf_counter()
            write_cost = last_write - tw
    return timing


def run_sweep(spec: SweepSpec, out: Path, workers: int, scheduler: str | None) -> dict[str, Any]:
    """Evaluate every variant not yet in ``out``'s table; returns the summary (``sweep.json``).

    ``out`` is created by the first write only (a refusal or an interrupt before it
    leaves nothing); every write follows :func:`cad.studies.sweep.table.publish`.
    """
    cols = columns(spec.varies)
    kept = read_table(out, [v.key for v in spec.varies])
    variants = spec.variants()
    rows, renumbered = numbered_rows([r for r in kept if r.get("status") in DONE], variants)
    done = {r["design_hash"] for r in rows}
    todo = [(i, a, raw, h) for i, (a, raw, h) in enumerate(variants) if h not in done]
    resumed = len(variants) - len(todo)
    prog = Progress(total=len(todo), skipped=resumed)
    t0 = time.perf_counter()
    timing: dict[str, Any] = {}
    client = cluster = None
    try:
        if todo:
            with signals.deferred():
                client, cluster = cluster_mod.connect(workers, scheduler, "sweep", CONNECT_TIMEOUT_S)
            timing = _evaluate(spec, out, todo, rows, cols, prog, client, cluster is not None)
            timing["startup_s"] = timing["t_eval"] - t0
        prog.stop()
        prog.line()
        summary = _summary(spec, out, variants, todo, rows, prog, workers, scheduler,
                           time.perf_counter() - t0, timing)
        same = not todo and not renumbered and len(rows) == table_rows(out)
        writers = {} if same else table_writers(rows, cols)
        writers["chart.png"] = lambda p: write_chart(p, rows, spec)
        writers["sweep.json"] = lambda p: p.write_text(json.dumps(summary, indent=1), encoding="utf-8")
        publish(out, writers)
    finally:
        prog.stop()
        cluster_mod.shutdown(client, cluster)
    return summary


def numbered_rows(rows: list[dict[str, Any]], variants: list) -> tuple[list[dict[str, Any]], bool]:
    """``(rows, changed)``: the kept rows with the variant numbers of THIS sweep (a widened
    or re-ordered sweep numbers its variants anew; the old numbers would repeat), rows of
    other sweeps numbered after them in their order; ``changed`` when a number moved."""
    index = {h: i for i, (_, _, h) in enumerate(variants)}
    extra = iter(range(len(variants), len(variants) + len(rows)))
    out = [{**r, "variant": index[r["design_hash"]] if r["design_hash"] in index else next(extra)}
           for r in rows]
    return out, any(a.get("variant") != b["variant"] for a, b in zip(rows, out, strict=True))


def table_rows(out: Path) -> int:
    """Rows of ``out/results.parquet`` as its footer states them (-1 when absent)."""
    import pyarrow.parquet as pq

    p = out / TABLE
    return pq.ParquetFile(p).metadata.num_rows if p.is_file() else -1


def _summary(spec: SweepSpec, out: Path, variants: list, todo: list, rows: list, prog: Progress,
             workers: int, scheduler: str | None, wall: float, timing: dict) -> dict[str, Any]:
    """``sweep.json``: the spec, counts, timings and data per task."""
    t_eval, last_done = timing.get("t_eval"), timing.get("last_done")
    new = rows[-len(todo):] if todo else []
    return {
        "design": str(spec.design), "fidelity": spec.fidelity, "samples": spec.samples, "seed": spec.seed,
        "vary": [{"key": v.key, "values": list(v.values)} if v.values else
                 {"key": v.key, "lo": v.lo, "hi": v.hi, "n": v.n} for v in spec.varies],
        "targets": spec.targets_text, "variants": len(variants), "resumed": len(variants) - len(todo),
        "evaluated": len(todo), **{k: prog.counts[k] for k in (*DONE, "lost")},
        "workers": workers if not scheduler else None, "scheduler": scheduler or "LocalCluster",
        "wall_s": wall,
        "startup_s": timing.get("startup_s"),
        "evaluation_s": (last_done - t_eval) if todo and last_done else None,
        "variants_per_s": (len(todo) / (last_done - t_eval)) if todo and last_done else None,
        "client_cpu_s": timing.get("client_cpu_s"),
        "variant_wall_s_median": _median([r.get("wall_s") for r in new]),
        "variant_cpu_s_median": _median([r.get("cpu_s") for r in new]),
        "task_bytes_in_median": _median([float(len(pickle.dumps((raw, str(spec.design), spec.fidelity,
                                                                  spec.cli_targets))))
                                         for _, _, raw, _ in todo]),
        "task_bytes_out_median": _median([float(len(pickle.dumps(r))) for r in new]),
        "files": [str(out / n) for n in (*OWNED, MANIFEST)],
    }


def warm_up(client, raw: dict[str, Any], source: str, fidelity: str, one_core: bool) -> None:
    """Before the clock starts: on every worker the CAD import (and, for the embedded
    cluster, one OCCT thread: one worker per core); then the first variant's parts made and
    integrated into the shared disk cache, split over the workers (each part once, not once
    per worker: that duplicated cold start cost the 2-worker sweep ~1 s per worker). A
    failure here is not fatal: the variant fails later as a row."""
    from dask.distributed import wait

    try:
        client.run(_setup_worker, one_core)
        addrs = cluster_mod.worker_addresses(client)
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
    import_build123d()

    if one_core:

        limit_occt_threads(1)


def _warm_share(raw: dict[str, Any], source: str, fidelity: str, share: tuple[int, int]) -> int:
    """This worker's share of :func:`cad.families.fourbar.inertia.warm_part_cache` for one variant."""
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
    ax.set_title(f"{mathtext(spec.design.name)}: {len(good)} variants ({spec.fidelity})"
                 + (f", {n_err} failed (see results table)" if n_err else ""), fontsize=10)
    fig.tight_layout()
    save_figure(fig, path, "png", dpi=90)
    plt.close(fig)
