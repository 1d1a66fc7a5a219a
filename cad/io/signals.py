"""SIGINT and SIGTERM: abort cleanly, publish nothing (docs/reliability.md "Signals").

:func:`install` (called first thing by the ``hapticad`` entry points, before any heavy
import) makes SIGINT and SIGTERM record the signal and raise :class:`KeyboardInterrupt`.
The CLI turns any exception that escapes while a signal is recorded (a library that
catches the interrupt during its import and re-raises it as ``ImportError``, say) into
``hapticad: aborted`` and exit ``128 + signal`` (130 for SIGINT, 143 for SIGTERM).

Publishing is the one commit point: :func:`commit` refuses to start when a signal was
already received (a library that swallowed the interrupt cannot make the command
publish), runs the rename(s) with signals only recorded, and if one arrived meanwhile the
caller's ``undo`` puts everything back. After a commit went through, later signals are
only recorded: the published output is complete and the command finishes (exit code as
usual). :func:`check` is a checkpoint between build stages (a forked stage's result).
:func:`finish` ends the command: signals are blocked until the process has exited.

Python runs the handler only between bytecodes: a long call into OCCT (a boolean, an offset)
holds the interpreter for seconds to minutes, and the interrupt waited for it (15-60 s seen).
:func:`start_watchdog` (the ``hapticad`` entry point) forks a small watchdog process at start-up
and registers a C-level handler (``faulthandler.register``, chained to Python's) that tells it
of each SIGINT/SIGTERM at once, whatever the main thread is doing. When the command has not
acted on the signal within :data:`WATCHDOG_GRACE_S` (outside the publish and after none), the
watchdog prints ``hapticad: aborted`` and kills it (SIGKILL: exit status 137; the forked
children die with it and the next build removes its temporary folder, as after any SIGKILL).
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
from collections.abc import Callable, Iterator

SIGNALS = (signal.SIGINT, signal.SIGTERM)
_state: dict = {"signal": None, "installed": False, "committed": False, "deferred": 0}


#: Seconds a command has to act on SIGINT/SIGTERM before the watchdog kills it: Python's
#: handler runs within microseconds when the interpreter is free; a second is "at once" to a
#: person and far longer than any publish step (which holds the watchdog off anyway).
WATCHDOG_GRACE_S = 1.0
#: ... and once the handler ran (the abort is under way: undo, cleanup), this much longer.
WATCHDOG_CLEANUP_S = 15.0
#: bytes the command sends the watchdog (a faulthandler dump, its signal notice, is text)
_HOLD, _FREE, _DONE, _ACTING = b"\x01", b"\x02", b"\x03", b"\x04"


def _tell(msg: bytes) -> None:
    fd = _state.get("watch_fd")
    if fd is not None and os.getpid() == _state.get("watch_pid"):
        with contextlib.suppress(OSError):
            os.write(fd, msg)


def _handler(signum, frame) -> None:  # noqa: ARG001 - signal handler signature
    _tell(_ACTING)
    if _state["signal"] is None:
        _state["signal"] = signum
    if not _state["committed"] and not _state["deferred"]:
        raise KeyboardInterrupt


def install() -> None:
    """Route SIGINT and SIGTERM to :func:`_handler` (idempotent; main thread only)."""
    if _state["installed"]:
        return
    for s in SIGNALS:
        signal.signal(s, _handler)
    _state["installed"] = True
    previous = sys.unraisablehook

    def hook(unraisable) -> None:
        # An interrupt raised where Python cannot propagate it (an at-fork hook, a
        # finalizer) is "ignored" with a traceback on stderr; the signal is recorded, and
        # check() / commit() turn it into the abort: say nothing here.
        if issubclass(unraisable.exc_type, KeyboardInterrupt) and _state["signal"] is not None:
            return
        previous(unraisable)

    sys.unraisablehook = hook


def check() -> None:
    """Raise :class:`KeyboardInterrupt` when a signal was received and not yet acted on
    (it may have been swallowed by a library); a checkpoint between stages."""
    if _state["signal"] is not None and not _state["committed"]:
        raise KeyboardInterrupt


@contextlib.contextmanager
def deferred() -> Iterator[None]:
    """In the block a signal is only recorded (e.g. around ``os.fork``, whose at-fork hooks
    would swallow the interrupt); on leaving, :func:`check` raises it. Python runs signal
    handlers in the main thread only, so this holds whatever thread the kernel picked."""
    _state["deferred"] += 1
    _tell(_HOLD)
    try:
        yield
    finally:
        _state["deferred"] -= 1
        _tell(_FREE)
    check()


def received() -> int | None:
    """The first signal received since :func:`install` (or None)."""
    return _state["signal"]


def committed() -> bool:
    """True once a final commit (the command's output) went through."""
    return bool(_state["committed"])


def exit_code() -> int:
    """``128 + signal`` of the received signal (130 when none was recorded)."""
    return 128 + int(_state["signal"] or signal.SIGINT)


def exit_now(code: int) -> None:
    """Leave the process with ``code`` after an interrupt: flush stdout/stderr, then
    ``os._exit`` -- the interpreter's shutdown (atexit hooks, threads of imported libraries)
    must not turn the handled interrupt into a death by signal (status -2 instead of 130)."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
    os._exit(code)


def finish() -> None:
    """The command is over (its exit code is known): from here SIGINT/SIGTERM are only
    recorded and then blocked -- held by the kernel and discarded when the process exits.
    Without this a signal during the interpreter's shutdown (which restores the default
    dispositions) killed a finished command by the signal, no ``aborted`` line."""
    _state["deferred"] += 1
    _tell(_DONE)
    with contextlib.suppress(AttributeError, OSError, ValueError):  # no pthread_sigmask
        signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS)


def reset() -> None:
    """Forget a received signal and any commit (tests running the CLI in-process)."""
    _state["signal"] = None
    _state["committed"] = False
    _state["deferred"] = 0


@contextlib.contextmanager
def commit(undo: Callable[[], None] | None = None, final: bool = False) -> Iterator[None]:
    """Run the publishing step with SIGINT/SIGTERM deferred (module docstring).

    Raises :class:`KeyboardInterrupt` before the step when a signal was already received,
    or after calling ``undo`` when one arrived during the step; ``undo`` also runs when the
    step itself raises. ``final``: this publishes the command's output (not a file inside
    a temporary folder); later signals are then only recorded.
    """
    if _state["signal"] is not None and not _state["committed"]:
        raise KeyboardInterrupt
    _state["deferred"] += 1
    _tell(_HOLD)
    try:
        try:
            yield
        finally:
            _state["deferred"] -= 1
            _tell(_FREE)
        if _state["signal"] is not None and not _state["committed"]:
            raise KeyboardInterrupt
    except BaseException:
        if undo is not None:
            undo()
        raise
    if final and _state["installed"]:
        _state["committed"] = True
        _tell(_DONE)


def child_dies_with_parent(parent_pid: int) -> None:
    """In a forked child: default signal dispositions and, on Linux, SIGKILL when the
    parent dies (``prctl(PR_SET_PDEATHSIG)``); exits at once if the parent is gone."""
    for s in SIGNALS:
        with contextlib.suppress(ValueError, OSError):
            signal.signal(s, signal.SIG_DFL)
    with contextlib.suppress(Exception):
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        PR_SET_PDEATHSIG = 1
        libc.prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
    if os.getppid() != parent_pid:
        os._exit(1)


def start_watchdog() -> None:
    """Fork the watchdog (module docstring) and register the C-level notice of SIGINT and
    SIGTERM; call after :func:`install`, before heavy imports (the fork copies a small
    process). Nothing on a platform without ``fork`` or with ``HAPTICAD_FORK=0``."""
    import faulthandler

    if not hasattr(os, "fork") or os.environ.get("HAPTICAD_FORK") == "0" or "watch_fd" in _state:
        return
    r, w = os.pipe()
    parent = os.getpid()
    pid = os.fork()
    if pid == 0:  # the watchdog
        os.close(w)
        _watch(r, parent)
    os.close(r)
    _state.update(watch_fd=w, watch_pid=parent, watch_file=os.fdopen(w, "wb", buffering=0, closefd=False))
    for s in SIGNALS:
        with contextlib.suppress(RuntimeError, ValueError, OSError):
            faulthandler.register(s, file=_state["watch_file"], all_threads=False, chain=True)


def _watch(r: int, parent: int) -> None:
    """The watchdog's loop: exits when the command does; kills it when a signal was not acted
    on in time (module docstring). Never returns."""
    import select
    import time

    for s in SIGNALS:
        signal.signal(s, signal.SIG_IGN)  # the terminal's Ctrl-C reaches the whole group
    with contextlib.suppress(OSError):
        os.close(0)
        os.chdir("/")  # holds no folder of the command's
    with contextlib.suppress(Exception):  # Linux: named (ps, tests), and gone with the command
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(15, b"hapticad-watch", 0, 0, 0)  # PR_SET_NAME
        libc.prctl(1, int(signal.SIGKILL), 0, 0, 0)  # PR_SET_PDEATHSIG
    hold, done, deadline = 0, False, None
    while os.getppid() == parent:
        if select.select([r], [], [], 0.1)[0]:
            data = os.read(r, 65536)
            if not data:
                break
            hold += data.count(_HOLD) - data.count(_FREE)
            done = done or _DONE in data
            now = time.monotonic()
            if _ACTING in data:
                deadline = now + WATCHDOG_CLEANUP_S
            elif data.strip(_HOLD + _FREE + _DONE) and deadline is None:
                deadline = now + WATCHDOG_GRACE_S
        if deadline is not None and not done and hold <= 0 and time.monotonic() > deadline:
            with contextlib.suppress(OSError):
                os.write(2, b"hapticad: aborted\n")
                os.kill(parent, signal.SIGKILL)
            break
    os._exit(0)
