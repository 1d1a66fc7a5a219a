"""`hapticad sweep` on Dask: rows equal `hapticad check`, failing variants, resume, bad input.

The integration tests share one in-process Dask cluster (``--scheduler inproc://...``), so
the CAD import is paid once; the worker-process path (LocalCluster) and a killed worker are
exercised by the slow test, and a worker process killed mid-variant (deterministically, by a
worker plugin) by the default-suite test at the end.
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import pyarrow.parquet as pq
import pytest

from cad.design.fields import load_toml
from cad.design.writer import write_design
from cad.studies.sweep.spec import apply, assignments, design_hash, parse_vary
from tests.cli_helpers import assert_one_line_error, hapticad

DESIGNS = Path(__file__).resolve().parents[3] / "designs"
HOEKEN = DESIGNS / "hoeken.toml"


def test_vary_specs_and_full_factorial():
    a = parse_vary("parts.bar_thickness_mm=5,6.5")
    b = parse_vary("mechanism.stroke_mm=40:60:3")
    c = parse_vary("parts.handle_material=delrin,pla")
    assert a.values == (5, 6.5) and b.grid() == (40.0, 50.0, 60.0)
    combos = assignments((a, b, c), None)
    assert len(combos) == 12 and len({json.dumps(x, sort_keys=True) for x in combos}) == 12
    assert combos[0] == {"parts.bar_thickness_mm": 5, "mechanism.stroke_mm": 40.0, "parts.handle_material": "delrin"}


def test_latin_hypercube_has_one_sample_per_stratum():
    b = parse_vary("mechanism.stroke_mm=40:60:3")
    c = parse_vary("parts.handle_material=delrin,pla")
    pts = assignments((b, c), 10, seed=1)
    strata = sorted(int((p["mechanism.stroke_mm"] - 40) / 20 * 10) for p in pts)
    assert strata == list(range(10))
    assert sorted(p["parts.handle_material"] for p in pts) == ["delrin"] * 5 + ["pla"] * 5


def test_design_hash_keys_the_resolved_design():
    raw = load_toml(HOEKEN)
    h1 = design_hash(apply(raw, {"parts.bar_thickness_mm": 6}), "inertia")
    assert h1 == design_hash(apply(raw, {"parts.bar_thickness_mm": 6}), "inertia")
    assert h1 != design_hash(apply(raw, {"parts.bar_thickness_mm": 6.5}), "inertia")
    assert h1 != design_hash(apply(raw, {"parts.bar_thickness_mm": 6}), "fabrication")
    assert h1 != design_hash(apply(raw, {"parts.bar_thickness_mm": 6}), "inertia", "dy_max_mm<=0.2")
    assert raw.get("parts", {}).get("bar_thickness_mm") is None  # apply copies


@pytest.fixture(scope="module")
def scheduler():
    from dask.distributed import LocalCluster

    from cad.studies.sweep.run import NO_HTTP_PORT

    cluster = LocalCluster(n_workers=1, processes=False, threads_per_worker=1, dashboard_address=None,
                           scheduler_kwargs=NO_HTTP_PORT)
    yield cluster.scheduler_address
    cluster.close()


def _rows(out: Path) -> list[dict]:
    return pq.read_table(out / "results.parquet").to_pylist()


def test_rows_equal_check_failures_are_rows_and_reruns_resume(tmp_path, scheduler):
    out = tmp_path / "sweep"
    args = ("sweep", HOEKEN, "--vary", "parts.bar_thickness_mm=3,5.5", "--scheduler", scheduler,
            "--out", out, "--json")
    code, stdout, err = hapticad(*args)
    assert code == 0, err
    s = json.loads(stdout)
    assert (s["variants"], s["evaluated"], s["resumed"], s["error"]) == (2, 2, 0, 1)
    rows = {r["parts.bar_thickness_mm"]: r for r in _rows(out)}
    bad, good = rows[3], rows[5.5]
    assert bad["status"] == "error" and bad["error"].startswith("parts.bar_thickness_mm:")
    assert math.isnan(bad["M11_max_g"])
    assert good["status"] == "missed" and good["error"] == ""
    # a separate `hapticad check` of the same variant gives the same numbers
    variant = tmp_path / "variant.toml"
    write_design(variant, apply(load_toml(HOEKEN), {"parts.bar_thickness_mm": 5.5}))
    code, cout, err = hapticad("check", variant, "--json")
    assert code == 1, err  # the Hoeken's targets are the paper's values: missed
    computed = json.loads(cout)["computed"]
    assert set(computed) >= {"H11_kg_m2", "M11_max_g", "coupler_mass_g", "dy_max_mm"}
    for k, v in computed.items():
        assert good[k] == pytest.approx(v, rel=1e-12, abs=0), k
    assert good["targets_missed"].split(",") == [r["key"] for r in json.loads(cout)["rows"] if not r["ok"]]
    # the CSV (read by the csv module) holds the same table
    with open(out / "results.csv", newline="") as f:
        csv_rows = list(csv.DictReader(f))
    assert [float(r["M11_max_g"]) for r in csv_rows if r["status"] == "missed"] == [good["M11_max_g"]]
    # re-running the same command evaluates nothing and leaves the table as it was
    before = (out / "results.parquet").read_bytes()
    code, stdout, err = hapticad(*args)
    assert code == 0, err
    s = json.loads(stdout)
    assert (s["resumed"], s["evaluated"]) == (2, 0)
    assert (out / "results.parquet").read_bytes() == before
    # widening the sweep evaluates only the new variant; the old rows stay as they were
    code, stdout, err = hapticad("sweep", HOEKEN, "--vary", "parts.bar_thickness_mm=3,5.5,7",
                                 "--scheduler", scheduler, "--out", out, "--json")
    assert code == 0, err
    s = json.loads(stdout)
    assert (s["variants"], s["resumed"], s["evaluated"]) == (3, 2, 1)
    final = {r["parts.bar_thickness_mm"]: r for r in _rows(out)}
    assert json.dumps(final[5.5], sort_keys=True) == json.dumps(good, sort_keys=True)
    assert final[7]["status"] == "missed" and final[7]["moving_mass_g"] > good["moving_mass_g"]
    assert (out / "chart.png").stat().st_size > 5000


def test_bad_input_is_one_line_and_nothing_written(tmp_path):
    cases = [
        (("--vary", "parts.bar_thicknes_mm=5,6"), "--vary parts.bar_thicknes_mm"),
        (("--vary", "parts.bar_thickness_mm"), "--vary"),
        (("--vary", "parts.bar_thickness_mm=6:5:3"), "LO <= HI"),
        (("--vary", "parts.bar_thickness_mm=5,6", "--workers", "0"), "--workers"),
        (("--vary", "parts.bar_thickness_mm=5,6", "--chart", "nope,M11_max_g"), "--chart"),
        (("--vary", "parts.bar_thickness_mm=5,6", "--fidelity", "preview"), "--fidelity"),
        ((), "--vary"),
    ]
    for args, needle in cases:
        out = tmp_path / "o"
        code, _, err = hapticad("sweep", HOEKEN, *args, "--out", out)
        assert_one_line_error(code, err, needle)
        assert not out.exists()
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "data.csv").write_text("x")
    code, _, err = hapticad("sweep", HOEKEN, "--vary", "parts.bar_thickness_mm=5", "--out", mine)
    assert_one_line_error(code, err, "--out", "data.csv")
    assert [p.name for p in mine.iterdir()] == ["data.csv"]


@pytest.mark.slow
def test_killed_worker_is_rerun_with_worker_processes(tmp_path):
    """kill -9 one LocalCluster worker process mid-sweep: Dask reruns its variants elsewhere.

    The kill lands at the first table write (before it, a kill can stop the cluster's start-up,
    which is refused in one line); 16 variants, polled every 0.2 s, keep the sweep running well
    past it (with 8 variants an idle machine finished them all first: nothing left to kill, seen
    in CI). The deterministic mid-variant kill is the default
    suite's test_worker_killed_mid_variant_is_restarted_and_its_variant_rerun."""
    import os
    import subprocess
    import sys
    import time

    import psutil

    out = tmp_path / "o"
    proc = subprocess.Popen([sys.executable, "-m", "cad", "sweep", str(HOEKEN), "--vary",
                             "parts.bar_thickness_mm=5:8:16", "--workers", "2", "--out", str(out), "--json"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            cwd=Path(__file__).resolve().parents[3],
                            env={**os.environ, "HAPTICAD_CACHE_DIR": str(tmp_path / "cache")})
    killed = None
    deadline = time.monotonic() + 600
    while killed is None and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.2)
        if not (out / "results.parquet").exists():  # the cluster is up and rows are coming
            continue
        workers = []
        for c in psutil.Process(proc.pid).children(recursive=True):
            try:  # a child may exit (or be a zombie) between the listing and its cmdline
                cmd = " ".join(c.cmdline())
            except psutil.Error:
                continue
            if "spawn" in cmd or "forkserver" in cmd:
                workers.append(c)
        if workers:
            try:
                workers[-1].kill()
                killed = workers[-1].pid
            except psutil.NoSuchProcess:  # it ended first: try the next one
                continue
    stdout, stderr = proc.communicate(timeout=600)
    assert proc.returncode == 0, stderr
    assert killed is not None, "no worker process was found to kill"
    s = json.loads(stdout)
    rows = _rows(out)
    assert (s["variants"], s["lost"], s["error"]) == (16, 0, 0)
    assert len(rows) == 16 and all(r["status"] in ("ok", "missed") for r in rows)


def test_worker_killed_mid_variant_is_restarted_and_its_variant_rerun(tmp_path):
    """Default-suite variant of the slow kill test, deterministic: a worker *process* of a
    LocalCluster (given by ``--scheduler``) SIGKILLs itself as its first variant starts (a
    worker plugin, once: a marker file); Dask's nanny restarts it and the scheduler reruns the
    variant, so every row is evaluated and none is ``lost``."""
    import os

    from dask.distributed import Client, LocalCluster, WorkerPlugin

    from cad.studies.sweep.run import NO_HTTP_PORT

    marker = tmp_path / "killed"

    class KillOnce(WorkerPlugin):  # local class: cloudpickle ships it by value to the worker
        def __init__(self, path):
            self.path = path

        def transition(self, key, start, finish, **kw):
            if finish == "executing" and "evaluate_variant" in str(key) and not os.path.exists(self.path):
                with open(self.path, "w") as f:
                    f.write(str(os.getpid()))
                os.kill(os.getpid(), 9)

    cluster = LocalCluster(n_workers=1, processes=True, threads_per_worker=1, dashboard_address=None,
                           scheduler_kwargs=NO_HTTP_PORT)
    try:
        with Client(cluster) as c:
            c.register_plugin(KillOnce(str(marker)))
            first_pid = next(iter(c.run(os.getpid).values()))
            out = tmp_path / "o"
            code, stdout, err = hapticad("sweep", HOEKEN, "--vary", "parts.bar_thickness_mm=5,6",
                                         "--scheduler", cluster.scheduler_address, "--out", out, "--json")
            assert code == 0, err
            assert marker.read_text() == str(first_pid)  # the worker did die, mid-variant
            assert next(iter(c.run(os.getpid).values())) != first_pid  # and was restarted
    finally:
        cluster.close()
    s = json.loads(stdout)
    assert (s["variants"], s["evaluated"], s["lost"], s["error"]) == (2, 2, 0, 0)
    rows = _rows(out)
    assert sorted(r["parts.bar_thickness_mm"] for r in rows) == [5, 6]
    assert all(r["status"] in ("ok", "missed") and math.isfinite(r["M11_max_g"]) for r in rows)
