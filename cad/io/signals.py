"""SIGINT and SIGTERM: abort cleanly, publish nothing (README "Signals").

:func:`install` (called first thing by the ``hapticad`` entry points, before any heavy
import) makes SIGINT and SIGTERM record the signal and raise :class:`KeyboardInterrupt`.
The CLI turns any exception that escapes while a signal is recorded (a library that
catches the interrupt during its import and re-raises it as ``ImportError``, say) into
``hapticad: aborted`` and exit ``128 + signal`` (130 for SIGINT, 143 for SIGTERM).

Publishing is the one commit point: :func:`commit` blocks both signals, refuses to
start when one was already received (a library that swallowed the interrupt cannot make
the command publish), runs the rename(s), and before unblocking looks at the pending
signals -- if one arrived meanwhile the caller's ``undo`` puts everything back. After a
commit went through, later signals are only recorded: the published output is complete
and the command finishes (exit code as usual).
"""

from __future__ import annotations

import contextlib
import os
import signal
from collections.abc import Callable, Iterator

SIGNALS = (signal.SIGINT, signal.SIGTERM)
_state: dict = {"signal": None, "installed": False, "committed": False}


def _handler(signum, frame) -> None:  # noqa: ARG001 - signal handler signature
    if _state["signal"] is None:
        _state["signal"] = signum
    if not _state["committed"]:
        raise KeyboardInterrupt


def install() -> None:
    """Route SIGINT and SIGTERM to :func:`_handler` (idempotent; main thread only)."""
    if _state["installed"]:
        return
    for s in SIGNALS:
        signal.signal(s, _handler)
    _state["installed"] = True


def received() -> int | None:
    """The first signal received since :func:`install` (or None)."""
    return _state["signal"]


def committed() -> bool:
    """True once a final commit (the command's output) went through."""
    return bool(_state["committed"])


def exit_code() -> int:
    """``128 + signal`` of the received signal (130 when none was recorded)."""
    return 128 + int(_state["signal"] or signal.SIGINT)


def reset() -> None:
    """Forget a received signal and any commit (tests running the CLI in-process)."""
    _state["signal"] = None
    _state["committed"] = False


def _pending() -> bool:
    if not hasattr(signal, "sigpending"):
        return False
    return bool(set(signal.sigpending()) & set(SIGNALS))


@contextlib.contextmanager
def commit(undo: Callable[[], None] | None = None, final: bool = False) -> Iterator[None]:
    """Run the publishing step with SIGINT/SIGTERM blocked (module docstring).

    Raises :class:`KeyboardInterrupt` before the step when a signal was already received,
    or after calling ``undo`` when one arrived during the step; ``undo`` also runs when the
    step itself raises. ``final``: this publishes the command's output (not a file inside
    a temporary folder); later signals are then only recorded.
    """
    masked = hasattr(signal, "pthread_sigmask") and _state["installed"]
    old = signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS) if masked else None
    try:
        if _state["signal"] is not None:
            raise KeyboardInterrupt
        try:
            yield
            if masked and _pending():
                raise KeyboardInterrupt
        except BaseException:
            if undo is not None:
                undo()
            raise
        if final and _state["installed"]:
            _state["committed"] = True
    finally:
        if masked:
            signal.pthread_sigmask(signal.SIG_SETMASK, old)


def child_dies_with_parent(parent_pid: int) -> None:
    """In a forked child: default signal dispositions and, on Linux, SIGKILL when the
    parent dies (``prctl(PR_SET_PDEATHSIG)``); exits at once if the parent is gone."""
    for s in SIGNALS:
        with contextlib.suppress(ValueError, OSError):
            signal.signal(s, signal.SIG_DFL)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, SIGNALS)
    with contextlib.suppress(Exception):
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        PR_SET_PDEATHSIG = 1
        libc.prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
    if os.getppid() != parent_pid:
        os._exit(1)
