"""Console-script entry point ``hapticad``: signal handlers first, then the CLI.

SIGINT/SIGTERM are routed to :mod:`cad.io.signals` before typer and the command
modules are imported, so an interrupt at any moment -- even while the CLI is still being
imported -- ends with ``hapticad: aborted`` and exit 128 + signal, never a traceback.
"""

import os
import sys

# One BLAS thread per process (before numpy loads OpenBLAS): hapticad's matrices are small
# (a 114 x 114 frame stiffness) and a build runs its stages in parallel processes; with
# OpenBLAS's own threads competing for the same cores one such solve took 0.2 s instead
# of 4 ms (measured on the 2-core machine). An explicit user setting wins.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

try:  # Python's own SIGINT handler until install(): a Ctrl-C in this import is the abort too
    from cad.io import signals  # noqa: E402 - after the BLAS setting

    signals.install()
    signals.start_watchdog()  # Ctrl-C acts within a second even inside a long OCCT call
except KeyboardInterrupt:
    print("hapticad: aborted", file=sys.stderr, flush=True)
    os._exit(130)


def main() -> None:
    try:
        from cad.cli.app import main as app_main
    except BaseException:
        if signals.received() is None:
            raise
        print("hapticad: aborted", file=sys.stderr, flush=True)
        signals.exit_now(signals.exit_code())
    app_main()


if __name__ == "__main__":
    main()
