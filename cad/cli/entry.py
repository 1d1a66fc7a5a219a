"""Console-script entry point ``hapticad``: signal handlers first, then the CLI.

SIGINT/SIGTERM are routed to :mod:`cad.io.signals` before typer and the command
modules are imported, so an interrupt at any moment -- even while the CLI is still being
imported -- ends with ``hapticad: aborted`` and exit 128 + signal, never a traceback.
"""

import sys

from cad.io import signals

signals.install()


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
