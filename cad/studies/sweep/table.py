"""A sweep's folder on disk: the table, its manifest, and a protocol that survives any kill.

The folder (``--out``) holds the sweep's own files (:data:`OWNED`) and ``manifest.json``
(the ownership record of docs/reliability.md "Output folders": each file with its sha256). The sweep
rewrites its files in place while it runs, so every rewrite follows one protocol
(:func:`publish`), whose every intermediate state a rerun accepts:

1. each new file is written to a temporary file beside its target
   (``.<name>.tmp.<host tag>.<pid>.<random><suffix>``, the shape of
   :func:`cad.io.atomic.atomic_path`, removed by the next run once its pid is dead);
2. ``manifest.json`` is rewritten (temporary file + rename) listing the files as they
   are *and*, under ``"pending"``, the sha256 each file is about to get;
3. the temporary files are renamed onto their targets;
4. ``manifest.json`` is rewritten listing the new files only.

SIGINT/SIGTERM are only recorded during the four steps (:func:`cad.io.signals.deferred`)
and act when they are through; a SIGKILL can land anywhere, and then each file holds its
old or its new bytes, both named by the manifest. A rerun (:func:`check_folder`) first
removes the dead run's temporary files, then, when the manifest holds a ``"pending"``
record and every file of ours has either its listed or its pending sha256, completes
step 4 (roll forward); only then the owned-folder rule (:func:`cad.io.outdir.check_out_dir`)
runs, unchanged: a file edited by someone else, or one we never wrote, is still refused.

Rows are keyed by ``design_hash`` (:func:`cad.studies.sweep.spec.design_hash`): :func:`read_table`
keeps one row per hash (a finished one before a ``lost`` one), so a table can never
hold a variant twice, and refuses a damaged table in one line naming the file.
"""

from __future__ import annotations

import contextlib
import json
import os
import stat
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

from cad.errors import DesignError
from cad.export.manifest import sha256_file
from cad.io import signals
from cad.io.atomic import host_tag, remove_stale_temps, umask
from cad.io.guard import check_file, sha256_of_output
from cad.io.outdir import check_out_dir

MANIFEST = "manifest.json"
TABLE = "results.parquet"
OWNED = ("results.parquet", "results.csv", "sweep.json", "chart.png")
DONE = ("ok", "missed", "error")
#: a manifest larger than this is not one the sweep wrote (5 files of ~200 bytes each)
MAX_MANIFEST_BYTES = 1 << 20
#: column -> pyarrow type test of the columns a resume reads
REQUIRED = {"variant": "integer", "design_hash": "string", "status": "string"}


def _regular(path: Path) -> os.stat_result | None:
    """``lstat`` of ``path`` when it is a regular file (never a link, FIFO or device), else
    None when absent; anything else is refused naming the file."""
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return None
    if not stat.S_ISREG(st.st_mode):
        raise DesignError("--out", f"{path} is not a regular file; move it away to restart")
    return st


def _temp(out: Path, name: str) -> Path:
    """A new empty temporary file for ``out/name`` (module docstring, step 1)."""
    out.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(
        prefix=f".{name}.tmp.{host_tag()}.{os.getpid()}.", suffix=Path(name).suffix, dir=out
    )
    os.close(fd)
    os.chmod(tmp, 0o666 & ~umask())
    return Path(tmp)


def _entries(out: Path, names: tuple[str, ...]) -> list[dict[str, Any]]:
    return [
        {"path": n, "sha256": sha256_file(out / n), "bytes": (out / n).stat().st_size}
        for n in sorted(names)
        if (out / n).is_file()
    ]


def _write_manifest(out: Path, pending: dict[str, str] | None = None) -> None:
    """``manifest.json`` listing the sweep's own files present now (and ``pending``)."""
    doc: dict[str, Any] = {"files": _entries(out, OWNED)}
    if pending:
        doc["pending"] = pending
    tmp = _temp(out, MANIFEST)
    try:
        tmp.write_text(json.dumps(doc, indent=2, sort_keys=True) + "\n", encoding="utf-8")
        os.replace(tmp, out / MANIFEST)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()
        raise


def publish(out: Path, writers: dict[str, Callable[[Path], None]]) -> None:
    """Replace the files ``writers`` names (``name -> write(path)``) in ``out`` by the
    four steps of the module docstring, signals deferred until they are through.

    Raises whatever a writer raises (nothing is then replaced); ``KeyboardInterrupt``
    after the four steps when a signal arrived meanwhile.
    """
    with signals.deferred():
        tmps: dict[str, Path] = {}
        try:
            for name, write in writers.items():
                tmps[name] = _temp(out, name)
                write(tmps[name])
            _write_manifest(out, {n: sha256_file(t) for n, t in tmps.items()})
            for name in list(tmps):
                os.replace(tmps.pop(name), out / name)
            _write_manifest(out)
        finally:
            for t in tmps.values():
                with contextlib.suppress(FileNotFoundError):
                    t.unlink()


def _manifest(out: Path) -> dict[str, Any] | None:
    """The parsed ``manifest.json`` of ``out`` (None when absent or not a sweep's)."""
    p = out / MANIFEST
    try:
        st = _regular(p)
        if st is None or st.st_size > MAX_MANIFEST_BYTES:
            return None
        doc = json.loads(p.read_text(encoding="utf-8"))
    except (DesignError, OSError, ValueError):
        return None  # check_out_dir says what is wrong with it
    return doc if isinstance(doc, dict) else None


def roll_forward(out: Path) -> bool:
    """Complete step 4 of an interrupted :func:`publish` when every file of ours has its
    listed or its pending sha256; True when the manifest was rewritten."""
    doc = _manifest(out)
    pending = doc.get("pending") if doc else None
    if not isinstance(pending, dict) or not isinstance(doc.get("files"), list):
        return False
    listed = {r.get("path"): r.get("sha256") for r in doc["files"] if isinstance(r, dict)}
    for name in OWNED:
        p = out / name
        if os.path.lexists(p):
            if _regular(p) is None:
                return False
            digest = sha256_of_output(p)  # None: larger than any file we write
            if digest is None or digest not in (listed.get(name), pending.get(name)):
                return False  # changed by someone else: check_out_dir names it
    _write_manifest(out)
    return True


def check_folder(out: Path, design_source: str) -> None:
    """Refuse (exit 2) an ``--out`` the sweep may not write to; before the owned-folder
    rule, remove a dead run's temporary files and roll an interrupted publish forward."""
    if out.is_dir() and not out.is_symlink():
        remove_stale_temps(out)
        roll_forward(out)
    check_out_dir(out, design_source)


def _type_ok(kind: str, typ) -> bool:
    import pyarrow as pa

    test = {"integer": pa.types.is_integer, "string": pa.types.is_string}[kind]
    return test(typ) or pa.types.is_null(typ)


def read_table(out: Path, keys: list[str]) -> list[dict[str, Any]]:
    """Rows of ``out/results.parquet``, one per ``design_hash`` (empty when absent).

    Refuses (DesignError naming ``--out`` and the file) a table that is not a regular
    file, not Parquet, lacks a column a resume reads (:data:`REQUIRED`, the varied
    ``keys``) or has one of the wrong type, or has a row without its ``design_hash``.
    A hash found twice keeps its first finished row (else its first row).
    """
    import pyarrow.parquet as pq

    p = out / TABLE
    if _regular(p) is None:
        return []

    check_file(p, "parquet", "--out")  # the size limit of every file hapticad reads
    why = f"; move {p.name} away to restart the sweep there, or name another --out"
    try:
        table = pq.read_table(p)
    except Exception as exc:  # noqa: BLE001 - any reader failure is a damaged file
        raise DesignError(
            "--out", f"{p} cannot be read as Parquet ({' '.join(str(exc).split())[:200]}){why}"
        ) from None
    for col, kind in REQUIRED.items():
        if col not in table.column_names:
            raise DesignError("--out", f"{p} has no column {col!r}{why}")
        if not _type_ok(kind, table.schema.field(col).type):
            raise DesignError(
                "--out",
                f"{p}: column {col!r} is {table.schema.field(col).type}, expected {kind}{why}",
            )
    missing = [k for k in keys if k not in table.column_names]
    if missing:
        raise DesignError(
            "--out",
            f"{p} holds a sweep over other keys (no column {missing[0]!r}); use a new folder",
        )
    rows = table.to_pylist()
    for i, r in enumerate(rows):
        if not r.get("design_hash"):
            raise DesignError("--out", f"{p}: row {i} has no design_hash{why}")
    return unique_rows(rows)


def unique_rows(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """One row per ``design_hash``: its first finished row, else its first row, in order."""
    best: dict[str, dict[str, Any]] = {}
    for r in rows:
        h = r["design_hash"]
        if h not in best or (best[h].get("status") not in DONE and r.get("status") in DONE):
            best[h] = r
    return list(best.values())
