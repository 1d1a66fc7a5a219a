"""Command-line interface ``hapticad`` (typer).

Each command lives in its own module ``cad/cli/cmd_<name>.py`` exposing
``register(app)``; :mod:`cad.cli.app` discovers them. Command modules import
CAD libraries only inside the command body so ``hapticad analyze`` stays light.
"""
