"""The Dask cluster of ``hapticad sweep`` and ``hapticad optimize --workers/--scheduler``.

One place for what both commands share: the ``--workers`` / ``--scheduler`` checks, the
embedded ``LocalCluster`` (worker processes, one thread each: the CAD kernel and the cheap
model hold the GIL) or a client of an existing scheduler, and its shutdown after a normal
end or an interrupt (docs/sweeps.md, docs/codesign.md).
"""

from __future__ import annotations

import logging
import signal

from cad.errors import DesignError, HapticadError
from cad.io import signals

#: how long ``--scheduler ADDRESS`` is tried before the command is refused (Dask retries
#: within it: a scheduler still starting is reached)
CONNECT_TIMEOUT_S = 10.0
#: no dashboard, and the scheduler's small HTTP server (metrics) on a free port: two commands
#: (or one beside another Dask cluster) must not fight over port 8787
NO_HTTP_PORT = {"dashboard_address": ":0"}
#: the embedded LocalCluster's largest ``--workers``
MAX_WORKERS = 256
#: the address schemes Dask's client accepts for ``--scheduler``
SCHEMES = ("tcp://", "tls://", "inproc://", "ucx://")


def check_flags(workers: int | None, scheduler: str | None) -> None:
    """Raise DesignError naming ``--workers`` (outside [1, :data:`MAX_WORKERS`] when no
    scheduler is given) or ``--scheduler`` (not a Dask address); None is "not given"."""
    if scheduler is None and workers is not None and not 1 <= workers <= MAX_WORKERS:
        raise DesignError("--workers", f"must be in [1, {MAX_WORKERS}], got {workers}")
    if scheduler is not None and not scheduler.startswith(SCHEMES):
        raise DesignError("--scheduler", f"expected tcp://HOST:PORT, got {scheduler!r}")


def connect(workers: int, scheduler: str | None, command: str, timeout_s: float | None = None):
    """(client, embedded cluster or None). Call it with SIGINT/SIGTERM deferred and assign
    its result inside that block: an interrupt during the cluster's start-up then acts once
    both exist and :func:`shutdown` can close them. Raises DesignError (``--scheduler``:
    not reached within ``timeout_s`` seconds, default :data:`CONNECT_TIMEOUT_S`) or HapticadError (the LocalCluster did not
    start; ``command`` names the command in the message)."""
    from dask.distributed import Client, LocalCluster

    if scheduler:
        probe_scheduler(scheduler, timeout_s or CONNECT_TIMEOUT_S)
        try:
            return Client(scheduler, timeout=f"{timeout_s or CONNECT_TIMEOUT_S}s"), None
        except OSError as exc:
            raise DesignError("--scheduler", f"cannot reach {scheduler}: {exc}") from None
    # SIGINT/SIGTERM blocked in the threads the cluster starts (its event loop, the
    # threads that spawn the workers) and so in every worker process: a Ctrl-C reaches
    # the whole process group, and workers that handled it would print tracebacks after
    # `hapticad: aborted`. The client closes them (Dask stops a worker by a message,
    # then SIGKILL), and they exit by themselves when this process dies.
    from multiprocessing import resource_tracker

    resource_tracker.ensure_running()  # started here: its start unblocks both in the caller
    old = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
    try:
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.CRITICAL,
                               scheduler_kwargs=NO_HTTP_PORT)
    except Exception as exc:  # e.g. a console script without its __main__ guard: spawn fails
        raise HapticadError(f"{command}: the local Dask cluster did not start ({type(exc).__name__}: "
                            f"{' '.join(str(exc).split())[:200]})") from None
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)
    return Client(cluster), cluster


def probe_scheduler(scheduler: str, timeout_s: float) -> None:
    """Refuse (DesignError naming ``--scheduler``) a ``tcp://`` address where nothing
    listens or where a server answers that is not a Dask scheduler, within ``timeout_s``
    seconds: a Dask scheduler sends its handshake (a msgpack frame with the keys
    ``compression`` and ``pickle-protocol``, distributed.comm.core) as soon as a connection
    opens, and Dask's own client would wait for it without end on an HTTP or silent server.
    Other schemes (tls, ucx, inproc) go straight to Dask's client."""
    import time

    from distributed.comm.addressing import parse_address, parse_host_port

    scheme, loc = parse_address(scheduler)
    if scheme != "tcp":
        return
    host, port = parse_host_port(loc)
    end = time.monotonic() + timeout_s
    while True:  # a scheduler still starting refuses connections for a moment: retry
        try:
            got = _first_bytes(host, port, end)
            break
        except OSError as exc:
            if time.monotonic() >= end:
                raise DesignError("--scheduler", f"cannot reach {scheduler} within "
                                  f"{timeout_s:g} s: {exc}") from None
            time.sleep(0.2)
    if b"compression" not in got or b"pickle-protocol" not in got:
        raise DesignError("--scheduler", f"{scheduler} is not a Dask scheduler: no Dask handshake "
                          f"within {timeout_s:g} s (another server on that port?)")


def _first_bytes(host: str, port: int, end: float) -> bytes:
    """What a server at ``host:port`` sends first, read until monotonic time ``end`` (or
    until a Dask handshake is in, or the server closes); OSError if no connection opens."""
    import socket
    import time

    got = b""
    with socket.create_connection((host, port), timeout=max(end - time.monotonic(), 0.01)) as s:
        while b"pickle-protocol" not in got and len(got) < 4096:
            s.settimeout(max(end - time.monotonic(), 0.01))
            try:
                chunk = s.recv(4096)
            except TimeoutError:
                break
            if not chunk:
                break
            got += chunk
    return got


def shutdown(client, cluster) -> None:
    """Close the client and the embedded cluster (signals deferred), then release the
    multiprocessing semaphores the cluster made: an aborted command leaves through
    ``os._exit`` (:func:`cad.io.signals.exit_now`), which skips multiprocessing's exit
    hook, and its resource tracker would print a "leaked semaphore" warning after
    ``hapticad: aborted``."""
    import gc
    import multiprocessing.util as mpu

    with signals.deferred():
        try:
            if client is not None:
                client.close()
            if cluster is not None:
                cluster.close()
        finally:
            gc.collect()
            if cluster is not None or signals.received() is not None:
                mpu._run_finalizers(0)  # noqa: SLF001 - the exit hook's own step (unlinks + unregisters)


def worker_addresses(client) -> list[str]:
    """The addresses of the workers the scheduler knows now, sorted."""
    return sorted(client.scheduler_info()["workers"])
