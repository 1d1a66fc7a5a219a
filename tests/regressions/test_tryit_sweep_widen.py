"""Widening a sweep keeps one variant number per variant (found by trying, t1tester).

``--vary parts.bar_thickness_mm=5,6`` then, in the same folder, ``=4,5,6``: docs/sweeps.md's
"widening a sweep evaluates only the new variants" held, but the resumed rows kept the
numbers of the first sweep (5 -> 0, 6 -> 1) and the new one took its number in the
widened sweep (4 -> 0): two rows ``variant = 0``. The table must be the one an
uninterrupted run of the widened sweep writes (the reference: a run into a new folder).
"""

from __future__ import annotations

from pathlib import Path

import pyarrow.parquet as pq
import pytest

from tests.cli_helpers import hapticad

ROOT = Path(__file__).resolve().parents[2]
HOEKEN = ROOT / "designs" / "hoeken.toml"
RUN_COLUMNS = ("wall_s", "cpu_s", "worker")


@pytest.fixture(scope="module")
def scheduler():
    """A TCP scheduler with one worker thread (as tests/unit/studies/test_sweep_resume.py)."""
    from dask.distributed import LocalCluster

    from cad.studies.sweep.run import NO_HTTP_PORT

    cluster = LocalCluster(n_workers=1, processes=False, threads_per_worker=1,
                           dashboard_address=None, scheduler_kwargs=NO_HTTP_PORT,
                           protocol="tcp", host="127.0.0.1")
    yield cluster.scheduler_address
    cluster.close()


def _sweep(out: Path, values: str, scheduler: str) -> list[dict]:
    code, _, err = hapticad("sweep", HOEKEN, "--vary", f"parts.bar_thickness_mm={values}",
                            "--scheduler", scheduler, "--out", out)
    assert code == 0, err
    return [{k: v for k, v in r.items() if k not in RUN_COLUMNS}
            for r in pq.read_table(out / "results.parquet").to_pylist()]


def test_a_widened_sweep_numbers_its_variants_as_a_fresh_run(tmp_path, scheduler):
    first = _sweep(tmp_path / "sw", "5.5,6", scheduler)
    assert [(r["parts.bar_thickness_mm"], r["variant"]) for r in first] == [(5.5, 0), (6.0, 1)]
    widened = _sweep(tmp_path / "sw", "5,5.5,6", scheduler)
    fresh = _sweep(tmp_path / "fresh", "5,5.5,6", scheduler)
    assert [r["variant"] for r in widened] == [0, 1, 2]
    assert repr(widened) == repr(fresh)  # repr: NaN (a target not computed) equals itself


def test_kept_rows_numbered_by_this_sweep_and_other_sweeps_after():
    """cad.studies.sweep.run.numbered_rows: a row whose ``variant`` was lost (null in a damaged
    table, kept as-is before) or stale gets its number in this sweep; a row of another
    sweep (hash not among the variants) is numbered after them; ``changed`` says so."""
    from cad.studies.sweep.run import numbered_rows

    variants = [({}, {}, "h0"), ({}, {}, "h1"), ({}, {}, "h2")]
    rows = [{"design_hash": "h2", "variant": None}, {"design_hash": "old", "variant": 0},
            {"design_hash": "h0", "variant": 0}]
    got, changed = numbered_rows(rows, variants)
    assert [r["variant"] for r in got] == [2, 3, 0] and changed
    same, changed = numbered_rows(got, variants)
    assert same == got and not changed
