"""``hapticad cache [--clear] [--json]``.

Where hapticad's disk caches are, how big they are per folder, and the size cap
(``HAPTICAD_CACHE_MAX_MB``, :mod:`cad.io.cache_limit`); ``--clear`` removes every cache
entry hapticad wrote there (nothing else in the folder).
"""

from __future__ import annotations

import typer

from cad.cli.app import print_json


def _summary(root) -> dict:
    from collections import Counter

    from cad.io.cache_limit import entries, max_bytes

    es = entries(root) if root is not None and root.is_dir() else []
    n, size = Counter(), Counter()
    for e in es:
        n[e.folder] += 1
        size[e.folder] += e.size_bytes
    cap = max_bytes()
    return {
        "cache_dir": None if root is None else str(root),
        "enabled": root is not None,
        "max_MB": None if cap is None else cap / 1e6,
        "total_MB": sum(size.values()) / 1e6,
        "folders": {k: {"entries": n[k], "MB": size[k] / 1e6} for k in sorted(n)},
    }


def register(app: typer.Typer) -> None:
    @app.command("cache")
    def cache_cmd(
        clear: bool = typer.Option(False, "--clear", help="Remove every cache entry (only hapticad's files)."),
        json_out: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Show (or clear) the shape, derived, mass-property and simulator caches."""
        from cad.io.cache_limit import cache_root, max_bytes
        from cad.io.cache_limit import clear as clear_all

        max_bytes()  # a bad HAPTICAD_CACHE_MAX_MB is refused before anything is removed
        root = cache_root()
        removed = None
        if clear and root is not None and root.is_dir():
            n, b = clear_all(root)
            removed = {"entries": n, "MB": b / 1e6}
        doc = _summary(root)
        if removed is not None:
            doc["removed"] = removed
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
