"""What ``hapticad cache`` reports (and :func:`cad.api.cache` returns): where the disk caches
are, their size per folder, the size cap (:mod:`cad.io.cache_limit`); optionally clearing
every entry hapticad wrote first. No CAD import."""

from __future__ import annotations

from cad.io.cache_limit import cache_root, entries, max_bytes
from cad.io.cache_limit import clear as clear_all


def _summary(root) -> dict:
    from collections import Counter


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


def cache_summary(clear: bool = False) -> dict:
    """``{"cache_dir", "enabled", "max_MB", "total_MB", "folders": {folder: {"entries",
    "MB"}}}`` (MB = 1e6 bytes), plus ``removed`` (entries, MB) when ``clear`` removed them.
    A bad ``HAPTICAD_CACHE_MAX_MB`` raises DesignError before anything is removed."""
    max_bytes()
    root = cache_root()
    removed = None
    if clear and root is not None and root.is_dir():
        n, b = clear_all(root)
        removed = {"entries": n, "MB": b / 1e6}
    doc = _summary(root)
    if removed is not None:
        doc["removed"] = removed
    return doc
