"""Size cap of hapticad's disk caches: the least recently used entries go first.

The caches live under ``$HAPTICAD_CACHE_DIR`` or ``~/.cache/hapticad``
(:func:`cache_root`): ``shapes-v2/`` (solids, :mod:`cad.parts.shape_cache`),
``derived-v2/`` (meshes, boxes, exported bytes, :mod:`cad.io.derived_cache`),
``props-v1/`` (mass properties, :mod:`cad.parts.part_props`) and ``sim/`` (simulator
models, :mod:`cad.sim.device`); folders of older schemas (``shapes-v1``, ``derived-v1``)
are never read again. An **entry** is a file hapticad names (40 or 32 hex digits or a 64-hex
sha256, with its ``.sha256`` companion, or a ``sim/<name>/`` folder); nothing else in the
folder is counted or touched, so a cache folder shared with other files loses none of them.

Recency: a hit refreshes the entry's modification time (:func:`touch`), so the oldest
mtime is the least recently used. :func:`prune` removes whole entries, oldest first, until
the total is at most 80 % of the cap; it runs once per process after a build
(:func:`prune_after_build`). The cap is ``HAPTICAD_CACHE_MAX_MB`` (default
:data:`DEFAULT_MAX_MB`; ``off`` for none); a bad value is a :class:`cad.errors.DesignError`
naming the variable.
"""

from __future__ import annotations

import os
import re
import shutil
from dataclasses import dataclass
from pathlib import Path
from stat import S_ISREG

from cad.errors import DesignError

#: Default cap of all caches together (MB = 10^6 bytes).
DEFAULT_MAX_MB = 2000.0
#: After pruning, the caches hold at most this fraction of the cap (room for the next builds).
LOW_WATER = 0.8
#: Schema folders in use; ``OLD`` ones are only pruned (first) or cleared.
CURRENT = ("shapes-v2", "derived-v2", "props-v1", "sim")
OLD = ("shapes-v1", "derived-v1")
_ENTRY = re.compile(r"^([0-9a-f]{32}|[0-9a-f]{40}|[0-9a-f]{64})\.(brep|bin|json)$")


@dataclass(frozen=True)
class Entry:
    """One cache entry: its files (the value and its ``.sha256``) or a ``sim/<name>`` folder,
    total bytes, last use (mtime, s since the epoch) and the folder it is in."""

    paths: tuple[Path, ...]
    size_bytes: int
    used_s: float
    folder: str


def cache_root() -> Path | None:
    """The caches' parent folder, or None when ``HAPTICAD_CACHE_DIR=off``."""
    env = os.environ.get("HAPTICAD_CACHE_DIR")
    if env is not None and env.strip().lower() in ("off", "0", "none", ""):
        return None
    return Path(env) if env else Path.home() / ".cache" / "hapticad"


def max_bytes() -> int | None:
    """The cap from ``HAPTICAD_CACHE_MAX_MB`` (bytes; None = no cap). DesignError naming the
    variable when it is not a positive number of MB or ``off``."""
    raw = os.environ.get("HAPTICAD_CACHE_MAX_MB")
    if raw is None or not raw.strip():
        return int(DEFAULT_MAX_MB * 1e6)
    if raw.strip().lower() in ("off", "none"):
        return None  # 0 is not "no cap": refused below, as docs/reliability.md says
    try:
        mb = float(raw)
    except ValueError:
        mb = float("nan")
    if not mb > 0 or mb == float("inf"):
        raise DesignError(
            "HAPTICAD_CACHE_MAX_MB",
            f"must be a positive size in MB or 'off', got {raw!r} (e.g. 2000 for 2 GB)",
        )
    return int(mb * 1e6)


def touch(path: Path) -> None:
    """Mark a cache entry (and its ``.sha256``) as just used; errors are ignored (a
    read-only cache still serves hits)."""
    for p in (path, path.with_name(path.name + ".sha256")):
        try:
            os.utime(p)
        except OSError:
            pass


def _file_rows(folder: Path, name: str) -> list[tuple[str, tuple[str, ...], int, float, str]]:
    """The entries of one schema folder as ``(dir, file names, bytes, mtime, folder)`` rows,
    in :func:`os.walk` order: the value file and its ``.sha256`` when that is a file. Plain
    strings and one ``stat`` per file (a cache of ~10^5 entries is listed after every build;
    Path objects and an ``is_file`` before each ``stat`` tripled its cost)."""
    out = []
    match, stat_, join = _ENTRY.match, os.stat, os.path.join
    for dirpath, _dirs, files in os.walk(folder):
        for f in files:
            if not match(f):
                continue
            p = join(dirpath, f)
            try:
                st = stat_(p)
            except OSError:
                continue
            try:
                sq = stat_(p + ".sha256")
            except OSError:
                sq = None
            if sq is not None and S_ISREG(sq.st_mode):  # as Path.is_file(): follows links
                out.append((dirpath, (f, f + ".sha256"), st.st_size + sq.st_size, st.st_mtime, name))
            else:
                out.append((dirpath, (f,), st.st_size, st.st_mtime, name))
    return out


def _sim_entries(folder: Path) -> list[Entry]:
    out = []
    for d in sorted(folder.iterdir()) if folder.is_dir() else ():
        if not d.is_dir() or d.is_symlink():
            continue
        files = [Path(a) / f for a, _, fs in os.walk(d) for f in fs]
        try:
            size = sum(f.stat().st_size for f in files)
            used = max([f.stat().st_mtime for f in files] or [d.stat().st_mtime])
        except OSError:
            continue
        out.append(Entry((d,), size, used, "sim"))
    return out


def _rows(root: Path) -> list[tuple[str, tuple[str, ...], int, float, str]]:
    """Every entry under ``root`` as :func:`_file_rows` rows (a sim folder: its parent and
    name), schema folders in ``OLD + CURRENT`` order, unsorted."""
    out: list[tuple[str, tuple[str, ...], int, float, str]] = []
    for name in OLD + CURRENT:
        folder = root / name
        if not folder.is_dir() or folder.is_symlink():
            continue
        if name == "sim":
            out += [(str(folder), (e.paths[0].name,), e.size_bytes, e.used_s, "sim")
                    for e in _sim_entries(folder)]
        else:
            out += _file_rows(folder, name)
    return out


def _sorted_entries(rows) -> list[Entry]:
    dirs: dict[str, Path] = {}
    es = []
    for d, names, size, used, name in rows:
        base = dirs.get(d) or dirs.setdefault(d, Path(d))
        es.append(Entry(tuple(base / f for f in names), size, used, name))
    return sorted(es, key=lambda e: (e.folder not in OLD, e.used_s))


def entries(root: Path) -> list[Entry]:
    """Every entry under ``root``, oldest schema folders first, then by last use."""
    return _sorted_entries(_rows(root))


def _remove(e: Entry) -> None:
    for p in e.paths:
        try:
            shutil.rmtree(p) if p.is_dir() else p.unlink()
        except FileNotFoundError:
            pass


def prune(root: Path, cap_bytes: int) -> tuple[int, int]:
    """Remove the least recently used entries (old schemas first) until the caches hold at
    most :data:`LOW_WATER` x ``cap_bytes``, if they hold more than ``cap_bytes``. Returns
    (entries removed, bytes freed)."""
    rows = _rows(root)
    total = sum(r[2] for r in rows)
    if total <= cap_bytes:  # the usual case: no Entry made
        return 0, 0
    es = _sorted_entries(rows)
    n = freed = 0
    for e in es:
        if total - freed <= LOW_WATER * cap_bytes:
            break
        _remove(e)
        n, freed = n + 1, freed + e.size_bytes
    return n, freed


def clear(root: Path) -> tuple[int, int]:
    """Remove every entry (nothing else); returns (entries, bytes)."""
    es = entries(root)
    for e in es:
        _remove(e)
    return len(es), sum(e.size_bytes for e in es)


_pruned = False


def prune_after_build() -> None:
    """:func:`prune` with the configured cap, once per process; a cache that cannot be
    listed or written is left as it is."""
    global _pruned
    root, cap = cache_root(), max_bytes()
    if _pruned or root is None or cap is None or not root.is_dir():
        return
    _pruned = True
    try:
        prune(root, cap)
    except OSError:
        pass
