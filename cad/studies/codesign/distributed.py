"""The co-design search on a Dask cluster (``hapticad optimize --workers N | --scheduler ADDRESS``).

* The study lives in an optuna journal file, ``DIR/journal.log`` of the folder ``--study DIR``
  (:class:`optuna.storages.JournalStorage` over a
  :class:`optuna.storages.journal.JournalFileBackend`: append-only, locked by a symbolic link,
  so it works on the shared file systems of a SLURM cluster), beside ``DIR/study.json`` naming
  the design and the search options it belongs to (:func:`check_study_dir` refuses a folder
  holding another study). The study's name is ``<design name>-<study key>``: the key hashes
  the design mapping, the seed and the search options (``--trials`` excluded).
* The Dask cluster is the sweep's (:mod:`cad.studies.cluster`: an embedded LocalCluster of
  worker processes with one thread each, or an existing scheduler). The trials still to run
  are split into one batch per worker; a batch is one Dask task that loads the study from
  the journal with its own seeded TPE sampler and runs ``study.optimize`` for its share
  (:func:`run_batch`). Each trial's record and candidate tables go into the storage as a
  user attribute, so the client rebuilds every trial -- of this run and of earlier ones --
  from the journal (:func:`trials_from`).
* Seeds: batch ``i`` of a run that finds ``done`` completed trials samples with the seed
  :func:`batch_seed` ``(seed, done, i)``, which is ``seed`` itself for the first batch of a
  new study: one worker then evaluates exactly the trials of the in-process search. With
  more workers, TPE's proposals depend on which trials finished first (scheduling order):
  the set of trials is reproducible only up to that order.
* Resume: rerun the same command. The completed trials are kept; only ``--trials`` minus
  their count is run. A trial killed mid-evaluation stays RUNNING in the journal and is
  ignored (TPE does not see it and it is not counted).
"""

from __future__ import annotations

import hashlib
import json
import math
import time
from pathlib import Path

from cad.design import bounds
from cad.errors import DesignError, HapticadError
from cad.io import signals
from cad.io.atomic import write_text_atomic
from cad.studies import cluster
from cad.studies.codesign import search
from cad.studies.codesign.search import Candidate, Problem

JOURNAL = "journal.log"
META = "study.json"
#: the trial user attribute holding its record and candidate tables (:func:`trial_attr`)
ATTR = "hapticad"
#: seconds after which a journal lock nobody wrote under is broken (optuna's default: 30)
LOCK_GRACE_S = 10


def placement(workers: int | None, scheduler: str | None, study, out=None) -> dict | None:
    """Where a four-bar search runs (:func:`run`'s ``where``): None without ``workers`` and
    ``scheduler`` (in this process); else ``{"workers", "scheduler", "study"}`` with the study
    folder ``study`` or, without it, ``<out stem>_study`` beside ``out``. Raises DesignError
    naming the flag: both given, ``--workers`` out of range, ``--scheduler`` not an address,
    ``--study`` without either, or missing with no ``out``."""
    if workers is not None and scheduler is not None:
        raise DesignError("--workers", f"give --workers {workers} or --scheduler {scheduler}, not both "
                                       "(the scheduler's workers run the trials)")
    cluster.check_flags(workers, scheduler)
    if workers is None and scheduler is None:
        if study is not None:
            raise DesignError("--study", f"{study}: only with --workers N or --scheduler ADDRESS "
                                         "(the in-process search keeps its trials in memory)")
        return None
    if study is None and out is None:
        raise DesignError("--study", "missing: the Dask search keeps its trials in a folder every "
                                     "worker reaches; give --study DIR (or --out, then <out>_study)")
    study = Path(study) if study is not None else Path(out).parent / f"{Path(out).stem}_study"
    return {"workers": workers, "scheduler": scheduler, "study": str(study)}


def study_key(design, seed: int, options: dict) -> str:
    """SHA-256 (hex, 16 chars) of the design mapping, ``seed`` and the search ``options``
    (what makes two searches the same study; ``--trials`` is not among them)."""
    text = json.dumps({"design": design.raw, "seed": seed, "options": options}, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def check_study_dir(folder: Path, design, seed: int, options: dict) -> dict:
    """The ``study.json`` of ``folder`` for this search (written by :func:`run` only once the
    cluster is reached: a refusal creates nothing). Raises DesignError (``--study``) when
    the folder is a file, holds files but no ``study.json``, or holds the study of another
    design, seed or search options."""
    key = study_key(design, seed, options)
    meta = {"study_name": f"{design.name}-{key}", "study_key": key, "design": design.name,
            "design_source": str(design.source), "seed": seed, "options": options}
    if folder.exists() and not folder.is_dir():
        raise DesignError("--study", f"{folder} is a file, not a folder")
    mp = folder / META
    if mp.is_file():
        try:
            old = json.loads(mp.read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise DesignError("--study", f"{mp} is not readable: {exc}") from None
        if old.get("study_key") != key:
            raise DesignError("--study", f"{folder} holds the study of {old.get('design')!r} (seed "
                              f"{old.get('seed')}, options {old.get('options')}), not this one of "
                              f"{design.name!r} (seed {seed}, options {options}); name another folder")
    elif folder.is_dir() and any(folder.iterdir()):
        raise DesignError("--study", f"{folder} is not a study folder (files but no {META}); "
                          "name a new or empty folder")
    return meta


def journal_storage(path: Path):
    """The optuna storage of the journal file ``path`` (created on first write), locked by a
    symbolic link (NFS-safe) that a waiting process breaks after :data:`LOCK_GRACE_S` seconds
    without a write (a worker killed while holding it); appends without fsync
    (:func:`unsynced_backend`)."""
    from optuna.storages import JournalStorage
    from optuna.storages.journal import JournalFileSymlinkLock

    lock = JournalFileSymlinkLock(str(path), grace_period=LOCK_GRACE_S)
    return JournalStorage(unsynced_backend(str(path), lock))


def unsynced_backend(path: str, lock):
    """optuna's :class:`~optuna.storages.journal.JournalFileBackend` of ``path`` whose appends
    write and flush each batch of log lines under ``lock`` and close the file, without
    optuna's ``os.fsync`` per append (issue 35 §4: one fsync per suggested parameter, ~17 per
    trial, took 63 % of a trial of the cheap model in one worker -- 3.47 of 5.51 s for 60
    trials, in memory 1.42 s -- and serialized the workers on the disk under the lock). A
    killed worker loses nothing written (the kernel holds it; a half line is cut on resume,
    :func:`repair_journal`); a power cut may lose the last trials, which a resume runs again.
    NFS clients flush on close, so other hosts read each append after it."""
    from optuna.storages.journal import JournalFileBackend

    class UnsyncedJournalFileBackend(JournalFileBackend):
        def append_logs(self, logs: list[dict]) -> None:
            text = "\n".join(json.dumps(log, separators=(",", ":")) for log in logs) + "\n"
            lock.acquire()
            try:
                with open(path, "ab") as f:
                    f.write(text.encode("utf-8"))
            finally:
                lock.release()

    return UnsyncedJournalFileBackend(path, lock_obj=lock)


def repair_journal(path: Path) -> list[str]:
    """Before a resume: remove the journal's lock when older than :data:`LOCK_GRACE_S` (its
    holder was killed: a write holds it for milliseconds) and cut a last line left half-written
    by a killed worker (optuna refuses the journal once a line follows it). Returns what was
    done, in words."""
    done = []
    lock = Path(str(path) + ".lock")
    try:
        if time.time() - lock.lstat().st_mtime > LOCK_GRACE_S:
            lock.unlink()
            done.append(f"removed the stale lock {lock}")
    except FileNotFoundError:
        pass
    if path.is_file():
        from optuna.storages.journal import JournalFileSymlinkLock

        held = JournalFileSymlinkLock(str(path), grace_period=LOCK_GRACE_S)
        held.acquire()  # no append under way while the tail is read and cut
        try:
            data = path.read_bytes()
            if data and not data.endswith(b"\n"):
                with path.open("r+b") as f:
                    f.truncate(data.rfind(b"\n") + 1)
                done.append(f"cut a half-written last line of {path}")
        finally:
            held.release()
    return done


def batch_seed(seed: int, done: int, batch: int) -> int:
    """The TPE seed of batch ``batch`` of a run finding ``done`` completed trials: ``seed``
    for the first batch of a new study, else drawn from numpy's SeedSequence of the three."""
    import numpy as np

    if done == 0 and batch == 0:
        return seed
    return int(np.random.SeedSequence([seed, done, batch]).generate_state(1)[0])


def quotas(todo: int, batches: int) -> list[int]:
    """``todo`` trials split over ``batches`` (the first ``todo % batches`` one more), no zeros."""
    q, r = divmod(todo, batches)
    return [q + (i < r) for i in range(batches) if q + (i < r) > 0]


def _jsonable(x):
    """``x`` through JSON (numpy scalars as Python numbers): what the journal stores."""
    return json.loads(json.dumps(x, default=lambda v: v.item() if hasattr(v, "item") else str(v)))


def trial_attr(pb: Problem, number: int, val: float, info: dict, parts: dict, tr) -> dict:
    """The user attribute of one trial: its record (:func:`search.trial_record`) and, when it
    is a candidate (feasible, or judged on every limit with ``pb.all_limits``), its tables."""
    out = {"record": search.trial_record(number, val, info)}
    if math.isfinite(val) or (pb.all_limits and "misses" in info):
        out["candidate"] = {"mechanism": info["mechanism"], "parts": parts, "transmission": tr}
    return _jsonable(out)


def best_feasible(study) -> float | None:
    """The lowest M11 (g) of the study's completed feasible trials (the structure check is
    skipped for trials that cannot beat it, as in the in-process search), or None."""
    from optuna.trial import TrialState

    vals = [t.user_attrs[ATTR]["record"]["value"] for t in
            study.get_trials(deepcopy=False, states=(TrialState.COMPLETE,)) if ATTR in t.user_attrs]
    return min((v for v in vals if v is not None), default=None)


def run_batch(pb: Problem, journal: str, name: str, n_trials: int, total: int, seed: int) -> int:
    """One Dask task: ``n_trials`` trials of the study ``name`` in ``journal`` with a TPE
    sampler seeded ``seed``, stopping early once the study holds ``total`` completed trials
    (a batch rerun after a worker died). Returns the trials this batch completed."""
    import warnings

    import optuna
    from optuna.study import MaxTrialsCallback

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    study = optuna.load_study(study_name=name, storage=journal_storage(Path(journal)),
                              sampler=search.tpe_sampler(seed))
    ran: list[int] = []

    def objective(trial):
        val, info, parts, tr = search.suggest_and_evaluate(trial, pb, best_feasible(trial.study))
        trial.set_user_attr(ATTR, trial_attr(pb, trial.number, val, info, parts, tr))
        ran.append(trial.number)
        return search.study_value(pb, val, info)

    with warnings.catch_warnings(), bounds.muted():
        warnings.simplefilter("ignore")  # optuna's experimental-feature warnings (multivariate TPE)
        study.optimize(objective, n_trials=n_trials, callbacks=[MaxTrialsCallback(total)])
    return len(ran)


def completed(study) -> int:
    """The study's completed trials that hold their record (every trial :func:`run_batch` ran)."""
    from optuna.trial import TrialState

    return sum(ATTR in t.user_attrs for t in study.get_trials(deepcopy=False, states=(TrialState.COMPLETE,)))


def trials_from(study, pb: Problem) -> tuple[list[Candidate], list[dict]]:
    """(feasible candidates best first, records in trial order) of the study's completed
    trials, rebuilt from their user attributes; ``pb.evaluated`` filled as the in-process
    search fills it (``pb.all_limits``)."""
    from optuna.trial import TrialState

    records, cands = [], []
    for t in sorted(study.get_trials(deepcopy=False, states=(TrialState.COMPLETE,)), key=lambda t: t.number):
        a = t.user_attrs.get(ATTR)
        if a is None:
            continue
        rec = a["record"]
        records.append(rec)
        c = a.get("candidate")
        if c is None:
            continue
        cheap = {k: v for k, v in rec.items() if k not in ("trial", "value")}
        cand = Candidate(t.number, c["mechanism"], c["parts"], {**cheap, "mechanism": c["mechanism"]},
                         c["transmission"])
        if pb.all_limits and "misses" in cheap:
            pb.evaluated[t.number] = cand
        if rec["value"] is not None:
            cands.append(cand)
    cands.sort(key=lambda c: c.cheap["M11_max_g"])
    return cands, records


def run(pb: Problem, trials: int, seed: int, starts: bool, where: dict,
        progress=None) -> tuple[list[Candidate], list[dict], dict]:
    """The search of :func:`search.run` on Dask (module docstring). ``where``: ``study`` (the
    folder), ``workers`` (embedded LocalCluster, None with ``scheduler``), ``scheduler``
    (address or None), ``options`` (the search options of :func:`study_key`). Returns
    (candidates, records, the report's ``study`` entry). Raises DesignError (``--study``,
    ``--scheduler``) or HapticadError (a batch failed: the completed trials are kept)."""
    import optuna

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    folder = Path(where["study"])
    meta = check_study_dir(folder, pb.design, seed, where["options"])
    name, journal = meta["study_name"], folder / JOURNAL
    if pb.capstan is not None:
        pb.capstan_stock = tuple(search.capstan_stock_mm(pb))
    for said in repair_journal(journal):
        if progress:
            progress(said)
    study = (optuna.load_study(study_name=name, storage=journal_storage(journal))
             if journal.is_file() else None)
    done = 0 if study is None else completed(study)
    todo = max(0, trials - done)
    info = {"storage": str(journal), "study_name": name, "workers": where.get("workers"),
            "scheduler": where.get("scheduler") or "LocalCluster", "resumed_trials": done,
            "new_trials": 0, "startup_s": None, "evaluation_s": None, "trials_per_s": None}
    if todo:
        info.update(_evaluate(pb, (folder, meta, starts), todo, trials, (seed, done), where, progress))
        study = optuna.load_study(study_name=name, storage=journal_storage(journal))
    cands, records = trials_from(study, pb) if study is not None else ([], [])
    info["completed_trials"] = len(records)
    return cands, records, info


def create_study(folder: Path, meta: dict, pb: Problem, starts: bool):
    """The study of ``meta`` in ``folder`` (``study.json`` written first), its starting trials
    enqueued when it is new (:func:`search.enqueue_starts`)."""
    import optuna

    write_text_atomic(folder / META, json.dumps(meta, indent=1))
    study = optuna.create_study(study_name=meta["study_name"], storage=journal_storage(folder / JOURNAL),
                                direction="minimize", load_if_exists=True)
    if not study.get_trials(deepcopy=False):
        search.enqueue_starts(study, pb, starts)
    return study


def _evaluate(pb: Problem, made: tuple, todo: int, total: int, seeds: tuple[int, int],
              where: dict, progress=None) -> dict:
    """Reach the cluster, create the study (``made``: folder, ``study.json`` mapping, starts),
    run ``todo`` trials as one batch per worker (:func:`run_batch`); the timings."""
    from dask.distributed import as_completed

    folder, meta, starts = made
    name, journal = meta["study_name"], folder / JOURNAL
    t0 = time.perf_counter()
    client = dask_cluster = None
    try:
        with signals.deferred():
            client, dask_cluster = cluster.connect(where.get("workers") or 1, where.get("scheduler"), "optimize")
        create_study(folder, meta, pb, starts)
        n = max(1, len(cluster.worker_addresses(client)))  # a scheduler's workers at the start
        if progress:
            progress(f"{todo} trials on Dask, {n} batches ({seeds[1]} in {journal} already)")
        client.run(warm_up)
        t1 = time.perf_counter()
        futs = [client.submit(run_batch, pb, str(journal), name, q, total, batch_seed(*seeds, i), pure=False)
                for i, q in enumerate(quotas(todo, n))]
        try:  # as they complete (an interrupt while waiting leaves no pending gather behind)
            ran = sum(f.result() for f in as_completed(futs))
        except Exception as exc:  # KilledWorker after repeated deaths, a lost connection
            raise HapticadError(f"optimize: a trial batch failed on Dask ({type(exc).__name__}: "
                                f"{' '.join(str(exc).split())[:200]}); the completed trials are kept in "
                                f"{journal}: rerun the command to resume") from None
        t2 = time.perf_counter()
    finally:
        cluster.shutdown(client, dask_cluster)
    return {"new_trials": ran, "batches": len(futs), "startup_s": t1 - t0, "evaluation_s": t2 - t1,
            "trials_per_s": ran / (t2 - t1) if t2 > t1 else None}


def warm_up() -> None:
    """On a worker, before the clock: import optuna and the search with its cheap model (what
    the first batch would otherwise pay: this module imports them)."""
    import optuna  # noqa: F401
