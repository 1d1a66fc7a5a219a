"""``hapticad cache [--clear] [--json]``.

Where hapticad's disk caches are, how big they are per folder, and the size cap
(``HAPTICAD_CACHE_MAX_MB``, :mod:`cad.io.cache_limit`); ``--clear`` removes every cache
entry hapticad wrote there (nothing else in the folder).
"""

from __future__ import annotations

import typer

from cad.cli.app import print_json


def register(app: typer.Typer) -> None:
    @app.command("cache")
    def cache_cmd(
        clear: bool = typer.Option(False, "--clear", help="Remove every cache entry (only hapticad's files)."),
        json_out: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Show (or clear) the shape, derived, mass-property and simulator caches."""
        from cad.api import cache

        doc = cache(clear)
        root, removed = doc["cache_dir"], doc.get("removed")
        if json_out:
            print_json(doc, indent=2)
            return
        if root is None:
            print("caches are off (HAPTICAD_CACHE_DIR=off)")
            return
        cap = "no cap" if doc["max_MB"] is None else f"cap {doc['max_MB']:g} MB"
        print(f"{root}: {doc['total_MB']:.1f} MB ({cap}, HAPTICAD_CACHE_MAX_MB)")
        for k, v in doc["folders"].items():
            print(f"  {k:<11} {v['entries']:6d} entries {v['MB']:9.1f} MB")
        if removed is not None:
            print(f"removed {removed['entries']} entries, {removed['MB']:.1f} MB")
