"""OCCT's thread pool (parallel booleans; build123d turns them on)."""

from __future__ import annotations


def limit_occt_threads(n_threads: int) -> None:
    """Cut OCCT's default thread pool (``OSD_ThreadPool::DefaultPool``) to ``n_threads``
    threads, e.g. 1 in each of two sweep workers on two cores."""
    from OCP.OSD import OSD_ThreadPool

    OSD_ThreadPool.DefaultPool_s().Init(int(n_threads))
