"""Run independent build stages side by side in forked child processes (POSIX ``os.fork``).

Why a process and not a thread: the stages run inside OCCT (pybind11 calls that hold the
GIL), matplotlib and numpy; with threads the Hoeken build measured slower than serial
(3.1-3.5 s against 2.5-3.1 s in-process, GIL contention). After the parts
exist, the exports, the preview and the interference sweep only read them, so a child
forked at that point sees every solid (copy-on-write) without pickling any geometry.

Contract of :func:`start`:

* ``fn()`` runs in a forked child; it writes its files (atomically, through
  :mod:`cad.io.atomic`) into the build's temporary output directory and may return a
  small picklable value;
* :meth:`Forked.result` waits for the child and returns that value, or re-raises the
  child's exception in the parent with the same class and message (a
  :class:`cad.errors.HapticadError` keeps its attributes; anything that cannot be
  rebuilt becomes a :class:`cad.errors.GeometryError` quoting the child's message);
* :meth:`Forked.cancel` kills and reaps the child (the caller is failing anyway and the
  dispatcher discards the temporary directory, so nothing half-written is published);
* the child dies with its parent: default SIGINT/SIGTERM dispositions and, on Linux,
  ``prctl(PR_SET_PDEATHSIG, SIGKILL)`` (:func:`cad.io.signals.child_dies_with_parent`), so
  a parent killed by SIGKILL leaves no export child running;
* the child never returns into the caller's frames: it leaves with ``os._exit``, so no
  ``finally``/``atexit`` of the parent (e.g. the atomic publish of the output folder)
  runs twice.

Where forking is off (:func:`fork_enabled`: not Linux, or ``HAPTICAD_FORK=0``), ``fn``
runs in-process when :meth:`Forked.result` is called -- the serial order, with the same
results (tests/unit/pipeline/test_forked.py compares the bytes of both).

Measured on ``hapticad build designs/hoeken.toml`` (2 cores): the stages after the parts
take ~1.3 s side by side instead of ~3 s one after the other.
"""

from __future__ import annotations

import contextlib
import gc
import importlib
import os
import pickle
import signal
import sys
import traceback
import warnings
from collections.abc import Callable
from typing import Any

from cad.errors import GeometryError, HapticadError
from cad.io import signals
from cad.io.signals import child_dies_with_parent


def fork_enabled() -> bool:
    """True when stages may run in forked children: Linux by default; ``HAPTICAD_FORK=0``
    turns it off, ``HAPTICAD_FORK=1`` on where ``os.fork`` exists (macOS system frameworks
    are not fork-safe, which is why Python's multiprocessing spawns there by default)."""
    if not hasattr(os, "fork"):
        return False
    flag = os.environ.get("HAPTICAD_FORK", "").strip().lower()
    if flag in ("0", "off", "no"):
        return False
    return flag in ("1", "on", "yes") or sys.platform.startswith("linux")


def _pack_exception(exc: BaseException) -> bytes:
    tb = "".join(traceback.format_exception(type(exc), exc, exc.__traceback__))
    cls = type(exc)
    try:
        state = pickle.dumps((exc.args, dict(getattr(exc, "__dict__", {}))))
    except Exception:  # noqa: BLE001 - unpicklable arguments: keep the message only
        state = None
    return pickle.dumps(("err", cls.__module__, cls.__qualname__, state, str(exc), tb))


def _rebuild_exception(module: str, qualname: str, state, message: str) -> BaseException:
    """The child's exception as an instance of its own class (without calling ``__init__``,
    which may take other arguments than ``args``, e.g. DesignError(field, reason))."""
    try:
        cls: Any = importlib.import_module(module)
        for part in qualname.split("."):
            cls = getattr(cls, part)
        if not (isinstance(cls, type) and issubclass(cls, BaseException)) or state is None:
            raise TypeError(qualname)
        args, attrs = pickle.loads(state)
        exc = cls.__new__(cls, *args)
        exc.args = args
        exc.__dict__.update(attrs)
        return exc
    except Exception:  # noqa: BLE001 - class not importable or state not restorable
        return GeometryError(f"{qualname}: {message}")


class StageDied(GeometryError):
    """A forked stage ended without a result (killed by a signal, e.g. a segmentation fault in
    OCCT, or exited early); ``signal`` is the signal number or None."""

    def __init__(self, message: str, signal: int | None = None):
        self.signal = signal
        super().__init__(message)


class Forked:
    """Handle of one stage started by :func:`start` (module docstring)."""

    def __init__(self, fn: Callable[[], Any], label: str):
        self.label = label
        self._fn = fn
        self._pid: int | None = None
        self._fd: int | None = None
        self._done = False
        if fork_enabled():
            self._fork()

    def _fork(self) -> None:
        r, w = os.pipe()
        for stream in (sys.stdout, sys.stderr):
            with contextlib.suppress(Exception):
                stream.flush()
        with warnings.catch_warnings():
            # Python >= 3.12 warns when a process with threads forks; the child only runs
            # `fn` and exits, touching no lock another thread could hold (no console, no
            # logging).
            warnings.simplefilter("ignore", DeprecationWarning)
            parent = os.getpid()
            with signals.deferred():  # an interrupt during the at-fork hooks is raised after
                pid = os.fork()
        if pid == 0:  # child
            status = 1
            try:
                os.close(r)
                # SIGINT/SIGTERM default; SIGKILL when the parent dies (even by SIGKILL)
                child_dies_with_parent(parent)
                gc.disable()  # short-lived: no collections, and no copy-on-write of the parent's pages
                try:
                    payload = pickle.dumps(("ok", self._fn()))
                    status = 0
                except BaseException as exc:  # noqa: BLE001 - reported to the parent
                    payload = _pack_exception(exc)
                with open(w, "wb", closefd=True) as f:
                    f.write(payload)
            except BaseException:  # noqa: BLE001 - nothing left to report through
                status = 2
            finally:
                os._exit(status)
        os.close(w)
        self._pid, self._fd = pid, r
        _LIVE.add(self)

    def _read_all(self) -> bytes:
        chunks = []
        while True:
            b = os.read(self._fd, 1 << 16)
            if not b:
                break
            chunks.append(b)
        os.close(self._fd)
        self._fd = None
        return b"".join(chunks)

    def result(self) -> Any:
        """Wait for the stage; return its value or raise its exception (module docstring)."""
        if self._done:
            raise RuntimeError(f"{self.label}: result() called twice")
        self._done = True
        if self._pid is None:
            return self._fn()
        signals.check()  # an interrupt swallowed by a library stops the build here
        data = self._read_all()
        _, status = os.waitpid(self._pid, 0)
        self._pid = None
        _LIVE.discard(self)
        try:
            msg = pickle.loads(data) if data else None
        except Exception:  # noqa: BLE001 - truncated pipe (child killed)
            msg = None
        if (
            msg is not None
            and msg[0] == "ok"
            and os.WIFEXITED(status)
            and os.WEXITSTATUS(status) == 0
        ):
            return msg[1]
        if msg is not None and msg[0] == "err":
            _, module, qualname, state, text, tb = msg
            exc = _rebuild_exception(module, qualname, state, text)
            if not isinstance(exc, HapticadError):
                exc.add_note(f"raised in the forked '{self.label}' stage:\n{tb}")
            raise exc
        how = (
            f"was killed by signal {os.WTERMSIG(status)}"
            if os.WIFSIGNALED(status)
            else f"exited with status {os.WEXITSTATUS(status)}"
        )
        sig = os.WTERMSIG(status) if os.WIFSIGNALED(status) else None
        raise StageDied(f"{self.label}: the forked stage {how} without a result", sig)

    def cancel(self) -> None:
        """Kill and reap the child (no-op when it is done or never forked)."""
        self._done = True
        _LIVE.discard(self)
        if self._pid is not None:
            with contextlib.suppress(ProcessLookupError):
                os.kill(self._pid, signal.SIGKILL)
            with contextlib.suppress(ChildProcessError):
                os.waitpid(self._pid, 0)
            self._pid = None
        if self._fd is not None:
            with contextlib.suppress(OSError):
                os.close(self._fd)
            self._fd = None


#: Stages whose child may still run (a failure anywhere cancels them: :func:`cancel_all`).
_LIVE: set[Forked] = set()


def cancel_all() -> None:
    """Kill and reap every child still running (the build dispatcher calls this when a
    build fails or is interrupted, before its temporary folder is removed)."""
    for t in list(_LIVE):
        t.cancel()


def start(fn: Callable[[], Any], label: str) -> Forked:
    """Start ``fn`` in a forked child (or defer it, see module docstring); returns the handle."""
    return Forked(fn, label)


@contextlib.contextmanager
def cancel_on_error(*tasks: Forked):
    """Cancel every still-running task when the block raises."""
    try:
        yield
    except BaseException:
        for t in tasks:
            t.cancel()
        raise
