"""Shared benchmark helpers: median timing and atomic chart files."""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable
from pathlib import Path

from cad.io.atomic import atomic_path
from cad.report.figures import save_figure


def median_time(fn: Callable[[], object], repeats: int) -> tuple[float, object]:
    """Median wall time (s) of ``repeats`` calls of ``fn`` and the last call's result."""
    times, out = [], None
    for _ in range(max(1, repeats)):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def save_chart(fig, out_dir: Path, stem: str, dpi: int = 120) -> list[str]:
    """Write ``fig`` as ``<stem>.png`` and ``<stem>.svg`` in ``out_dir`` atomically; return the paths."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    paths = []
    for ext in ("png", "svg"):
        target = out_dir / f"{stem}.{ext}"
        with atomic_path(target) as tmp:
            save_figure(fig, tmp, ext, dpi=dpi)
        paths.append(str(target))
    return paths
