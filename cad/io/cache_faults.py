"""A fault of a disk cache is a miss: the work is redone, and the command says so once.

Every disk cache of hapticad (shapes, derived values, mass properties, simulator models under
``$HAPTICAD_CACHE_DIR``) is an optimization, never a requirement. Reading a damaged entry is a
miss at the reader (each cache checks its sha256 before decoding). Writing an entry can fail
in ways that are not an :class:`OSError`: on a full disk OCCT's BREP writer raises
``RuntimeError: std::bad_cast``. Every cache writer therefore catches any ``Exception`` of
its write and calls :func:`write_failed`; from then on no cache entry is written by this
command -- also not by the build stages it forks (the flag lives in a shared anonymous
mapping) -- and one warning line says why (``hapticad: warning: cache /path: cannot write
...; this command works without the cache``). Results are the same: each value is computed
as on a cold cache. Signals (``KeyboardInterrupt``) are never caught here.
"""

from __future__ import annotations

import mmap
import os
import shutil
import sys
from pathlib import Path

from cad.design import bounds
from cad.io.cache_limit import cache_root

#: one byte shared with forked children (MAP_SHARED | MAP_ANONYMOUS): 1 once a write failed
_SHARED = mmap.mmap(-1, 1)
_OWNER_PID = os.getpid()


def writable() -> bool:
    """False once a cache write of this command failed (:func:`write_failed`)."""
    return _SHARED[0] == 0


def _reason(exc: BaseException, root: Path | None) -> str:
    text = exc.strerror if isinstance(exc, OSError) and exc.strerror else f"{type(exc).__name__}: {exc}"
    try:
        free = shutil.disk_usage(root).free if root is not None else None
    except OSError:
        free = None
    return text if free is None else f"{text}; {free / 1e6:.1f} MB free there"


def write_failed(what: str, exc: BaseException) -> None:
    """Record that writing ``what`` (e.g. "a shape entry") into the cache raised ``exc``:
    no further cache writes by this command; the first such fault is said once (a warning of
    :mod:`cad.design.bounds` in the command's process, printed and in ``--json``; a direct
    stderr line from a forked build stage)."""
    if _SHARED[0]:
        return
    _SHARED[0] = 1

    root = cache_root()
    text = (f"cache {root}: cannot write {what} ({_reason(exc, root)}); this command works "
            "without the cache (every value computed afresh, same results)")
    if os.getpid() == _OWNER_PID:

        bounds.warn(text)
    else:
        print(f"hapticad: warning: {text}", file=sys.stderr, flush=True)


def reset() -> None:
    """Writable again (the CLI calls this at the start of every command; tests)."""
    _SHARED[0] = 0
