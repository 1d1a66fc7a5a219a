"""Console-script entry point ``hapticad``: signal handlers first, then the CLI.

SIGINT/SIGTERM are routed to :mod:`cad.io.signals` before typer and the command
modules are imported, so an interrupt at any moment ends with ``hapticad: aborted``.
"""

from cad.io import signals

signals.install()

from cad.cli.app import main  # noqa: E402 - after the handlers on purpose

if __name__ == "__main__":
    main()
