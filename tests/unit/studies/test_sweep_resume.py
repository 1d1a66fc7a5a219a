"""`hapticad sweep` survives any kill and refuses bad folders and designs (issue 22).

Cases of ``shared/cases/reliability/sweep-*`` (cheap variants): a signal or SIGKILL at
the first table write and at seeded random moments resumes with exactly the rows of an
uninterrupted run (read back with pyarrow); SIGKILL at every step of the table protocol
(:mod:`cad.studies.sweep.table`) leaves a folder the rerun accepts, holding the old or the new
table; a damaged table is refused in one line; duplicated rows are removed on resume;
an invalid base design and other refusals create nothing; an interrupt during the
cluster's start-up ends with `hapticad: aborted` as the last line and no folder.

The kill tests run the sweep's client as a real process against a Dask scheduler in this
test process (worker threads, the CAD stack imported once); the interrupt during start-up
uses the embedded LocalCluster of one worker process.
"""

from __future__ import annotations

import hashlib
import json
import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from tests.cli_helpers import assert_one_line_error, hapticad

ROOT = Path(__file__).resolve().parents[3]
HOEKEN = ROOT / "designs" / "hoeken.toml"
VARY = ("--vary", "parts.bar_thickness_mm=5:7.5:6")
#: columns that differ between two runs of the same variant (timing, worker pid)
RUN_COLUMNS = ("wall_s", "cpu_s", "worker")


@pytest.fixture(scope="module")
def scheduler():
    """A TCP scheduler with one worker thread, reachable from the sweep processes."""
    from dask.distributed import LocalCluster

    from cad.studies.sweep.run import NO_HTTP_PORT

    cluster = LocalCluster(
        n_workers=1,
        processes=False,
        threads_per_worker=1,
        dashboard_address=None,
        scheduler_kwargs=NO_HTTP_PORT,
        protocol="tcp",
        host="127.0.0.1",
    )
    yield cluster.scheduler_address
    cluster.close()


def _rows(out: Path) -> dict[str, dict]:
    """design_hash -> row without the run columns; asserts one row per hash."""
    rows = pq.read_table(out / "results.parquet").to_pylist()
    hashes = [r["design_hash"] for r in rows]
    assert len(hashes) == len(set(hashes)), "a variant is in the table twice"
    return {r["design_hash"]: {k: v for k, v in r.items() if k not in RUN_COLUMNS} for r in rows}


def _same(a: dict, b: dict) -> bool:
    return json.dumps(a, sort_keys=True, default=str) == json.dumps(b, sort_keys=True, default=str)


@pytest.fixture(scope="module")
def reference(scheduler, tmp_path_factory):
    """The rows of an uninterrupted run."""
    out = tmp_path_factory.mktemp("ref") / "sw"
    code, _, err = hapticad("sweep", HOEKEN, *VARY, "--scheduler", scheduler, "--out", out)
    assert code == 0, err
    rows = _rows(out)
    assert len(rows) == 6 and {r["status"] for r in rows.values()} <= {"ok", "missed"}
    return rows


def _start(out: Path, scheduler: str) -> subprocess.Popen:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.Popen(
        [
            sys.executable,
            "-m",
            "cad",
            "sweep",
            str(HOEKEN),
            *VARY,
            "--scheduler",
            scheduler,
            "--out",
            str(out),
        ],
        cwd=out.parent,
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )


def _resume_equals_reference(out: Path, scheduler: str, reference: dict) -> None:
    code, _, err = hapticad(
        "sweep", HOEKEN, *VARY, "--scheduler", scheduler, "--out", out, "--json"
    )
    assert code == 0, err
    assert [p.name for p in out.iterdir() if p.name.startswith(".")] == []
    rows = _rows(out)
    assert rows.keys() == reference.keys()
    for h, r in reference.items():
        assert _same(rows[h], r), h


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGINT], ids=["SIGKILL", "SIGINT"])
def test_a_kill_at_the_first_table_write_resumes_with_every_row(
    tmp_path, scheduler, reference, sig
):
    """The reproducer: the signal lands the moment results.parquet first appears."""
    out = tmp_path / "sw"
    p = _start(out, scheduler)
    while p.poll() is None and not (out / "results.parquet").exists():
        time.sleep(0.001)
    p.send_signal(sig)
    _, err = p.communicate(timeout=120)
    if sig == signal.SIGINT and p.returncode != 0:  # 0 when the sweep had already finished
        assert (p.returncode, err.strip().splitlines()[-1]) == (130, "hapticad: aborted"), err
        assert "Traceback" not in err
    _resume_equals_reference(out, scheduler, reference)


@pytest.mark.parametrize("trial", range(3))
def test_a_kill_at_a_random_moment_resumes_with_every_row(tmp_path, scheduler, reference, trial):
    """Seeded moments in the 2 s after the first table write (later rewrites, the final
    publish with chart and sweep.json, the shut-down), SIGKILL or SIGTERM."""
    rng = random.Random(2208 + trial)
    sig = (signal.SIGKILL, signal.SIGTERM)[trial % 2]
    out = tmp_path / "sw"
    p = _start(out, scheduler)
    while p.poll() is None and not (out / "results.parquet").exists():
        time.sleep(0.002)
    time.sleep(rng.uniform(0.0, 2.0))
    p.send_signal(sig)
    p.communicate(timeout=120)
    _resume_equals_reference(out, scheduler, reference)


# --- the table protocol, SIGKILL at each of its steps ------------------------------------

_KILLER = r"""
import os, signal, sys
from pathlib import Path
import pyarrow as pa, pyarrow.parquet as pq
from cad.studies.sweep import table

out, kill_at = Path(sys.argv[1]), int(sys.argv[2])
def writers(n):
    t = pa.table({"variant": list(range(n)), "design_hash": [f"h{i}" for i in range(n)],
                  "status": ["ok"] * n})
    return {"results.parquet": lambda p: pq.write_table(t, p),
            "results.csv": lambda p: p.write_text(f"{n} rows\n")}
table.publish(out, writers(2))                       # the previous table: 2 rows
calls = [0]
real = os.replace
def replace(a, b):
    calls[0] += 1
    if calls[0] == kill_at:
        os.kill(os.getpid(), signal.SIGKILL)
    real(a, b)
os.replace = replace
def half_written(p):                                  # SIGKILL while a temp file is written
    p.write_text("half")
    if kill_at == 0:
        os.kill(os.getpid(), signal.SIGKILL)
w = writers(3)
w["results.csv"] = half_written
table.publish(out, w)
os.kill(os.getpid(), signal.SIGKILL)                  # after the whole publish
"""


def test_sigkill_at_every_step_of_a_table_write_leaves_a_folder_the_rerun_resumes(tmp_path):
    """Steps (cad.studies.sweep.table): 0 inside a writer, before rename 1 (pending manifest),
    2 (parquet), 3 (csv), 4 (final manifest), 5 after everything: each leaves the old
    rows (2) or the new (3), and the rerun's folder check accepts it and cleans up."""
    from cad.studies.sweep.table import check_folder, read_table

    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    steps = range(6)
    procs = {
        k: subprocess.Popen(
            [sys.executable, "-c", _KILLER, str(tmp_path / f"o{k}"), str(k)],
            env=env,
            stderr=subprocess.PIPE,
        )
        for k in steps
    }
    n_rows = {}
    for k, p in procs.items():
        _, err = p.communicate(timeout=120)
        assert p.returncode == -signal.SIGKILL, err
        out = tmp_path / f"o{k}"
        assert any(f.name.startswith(".") for f in out.iterdir()) == (k < 5)  # temp files
        check_folder(out, str(HOEKEN))  # no refusal
        assert [f.name for f in out.iterdir() if f.name.startswith(".")] == []
        n_rows[k] = len(read_table(out, []))
        doc = json.loads((out / "manifest.json").read_text())
        assert "pending" not in doc
        for f in doc["files"]:
            assert hashlib.sha256((out / f["path"]).read_bytes()).hexdigest() == f["sha256"]
    assert n_rows == {0: 2, 1: 2, 2: 2, 3: 3, 4: 3, 5: 3}


def test_a_file_edited_after_an_interrupted_write_is_still_refused(tmp_path):
    """Rolling forward accepts only the listed or the pending bytes: an edit is the user's."""
    from cad.errors import DesignError
    from cad.studies.sweep.table import check_folder, publish

    out = tmp_path / "o"
    publish(out, {"results.csv": lambda p: p.write_text("a\n")})
    doc = json.loads((out / "manifest.json").read_text())
    doc["pending"] = {"results.csv": "0" * 64}
    (out / "manifest.json").write_text(json.dumps(doc))
    (out / "results.csv").write_text("edited by hand\n")
    with pytest.raises(DesignError, match="results.csv .changed since hapticad wrote it"):
        check_folder(out, str(HOEKEN))


# --- damaged tables, duplicated rows ------------------------------------------------------


def _rehash(out: Path) -> None:
    """Make manifest.json list the files as they are now (the reproducer's step)."""
    m = json.loads((out / "manifest.json").read_text())
    for f in m["files"]:
        b = (out / f["path"]).read_bytes()
        f["sha256"], f["bytes"] = hashlib.sha256(b).hexdigest(), len(b)
    (out / "manifest.json").write_text(json.dumps(m))


def test_a_damaged_table_is_refused_in_one_line_and_duplicates_are_removed(tmp_path, scheduler):
    out = tmp_path / "sw"
    args = (
        "sweep",
        HOEKEN,
        "--vary",
        "parts.bar_thickness_mm=5,6",
        "--scheduler",
        scheduler,
        "--out",
        out,
    )
    code, _, err = hapticad(*args)
    assert code == 0, err
    good = pq.read_table(out / "results.parquet")
    damages = {
        "no column 'design_hash'": lambda t: t.drop_columns(["design_hash"]),
        "column 'status' is int64, expected string": lambda t: t.set_column(
            t.column_names.index("status"), "status", pa.array([1] * t.num_rows)
        ),
        "row 1 has no design_hash": lambda t: t.set_column(
            t.column_names.index("design_hash"),
            "design_hash",
            pa.array([t["design_hash"][0].as_py(), None]),
        ),
    }
    for needle, damage in damages.items():
        pq.write_table(damage(good), out / "results.parquet")
        _rehash(out)
        code, _, err = hapticad(*args)
        assert_one_line_error(code, err, "--out", "results.parquet", needle)
    for needle, data in (
        ("cannot be read as Parquet", (out / "results.parquet").read_bytes()[:300]),
        ("cannot be read as Parquet", b"PAR1" + b"\x00" * 64 + b"PAR1"),
    ):
        (out / "results.parquet").write_bytes(data)
        _rehash(out)
        code, _, err = hapticad(*args)
        assert_one_line_error(code, err, "--out", "results.parquet", needle)
    # a row written twice (both finished): the resume keeps one, evaluates nothing
    pq.write_table(pa.concat_tables([good, good.slice(0, 1)]), out / "results.parquet")
    _rehash(out)
    code, out_json, err = hapticad(*args, "--json")
    assert code == 0, err
    assert (json.loads(out_json)["evaluated"], json.loads(out_json)["resumed"]) == (0, 2)
    back = pq.read_table(out / "results.parquet")
    assert back.num_rows == 2 and _same(back.to_pylist(), good.to_pylist())  # NaN == NaN in JSON


# --- refusals create nothing; the base design as every command loads it ------------------


@pytest.mark.parametrize(
    "edit, field",
    [
        (("force_N = 5.0", "force_N = nan"), "mechanism.force_N"),
        (("[parts]", "[parts]\nbar_thicknes_mm = 6.0"), "parts.bar_thicknes_mm"),
        (('name = "hoeken"', 'name = "../../x"'), "name"),
    ],
)
def test_sweep_refuses_at_load_a_base_design_other_commands_refuse(tmp_path, edit, field):
    src = HOEKEN.read_text()
    assert edit[0] in src
    design = tmp_path / "d.toml"
    design.write_text(src.replace(edit[0], edit[1], 1))
    code, _, err_check = hapticad("analyze", design)
    assert_one_line_error(code, err_check, field)
    out = tmp_path / "sw"
    code, _, err = hapticad(
        "sweep", design, "--vary", "parts.bar_thickness_mm=5,6", "--workers", "1", "--out", out
    )
    assert_one_line_error(code, err, field)
    assert err == err_check  # the same loader, the same line
    assert not out.exists()


def test_refusals_after_the_out_check_create_nothing(tmp_path, monkeypatch):
    from cad.studies.sweep import run

    monkeypatch.setattr(run, "CONNECT_TIMEOUT_S", 1.0)
    cases = [
        (
            (
                "--vary",
                "parts.bar_thickness_mm=5:8:10000",
                "--vary",
                "parts.bar_width_mm=10:20:10000",
            ),
            "100000000 combinations",
        ),
        (
            ("--vary", "parts.bar_thickness_mm=5,6", "--scheduler", "tcp://127.0.0.1:9"),
            "--scheduler",
        ),
    ]
    for args, needle in cases:
        out = tmp_path / "a" / "sw"
        code, _, err = hapticad("sweep", HOEKEN, *args, "--out", out)
        assert_one_line_error(code, err, needle)
        assert not (tmp_path / "a").exists()


# --- an interrupt during the cluster's start-up -------------------------------------------


def _descendants(pid: int) -> list:
    import psutil

    try:
        return psutil.Process(pid).children(recursive=True)
    except psutil.NoSuchProcess:
        return []


def _spawning(pid: int) -> bool:
    """A worker process of the embedded cluster exists (multiprocessing's spawn)."""
    import psutil

    for c in _descendants(pid):
        try:
            if "spawn_main" in " ".join(c.cmdline()):
                return True
        except psutil.Error:  # gone meanwhile
            continue
    return False


def test_ctrl_c_during_the_cluster_start_up_ends_with_aborted_and_no_folder(tmp_path):
    """Ctrl-C reaches the whole process group (the reproducer signals the main process
    only; both are sent): no multiprocessing warning or worker traceback after
    `hapticad: aborted`, no --out folder, no process left."""
    import psutil

    out = tmp_path / "sw"
    env = {**os.environ, "PYTHONPATH": str(ROOT), "HAPTICAD_CACHE_DIR": str(tmp_path / "cache")}
    p = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "cad",
            "sweep",
            str(HOEKEN),
            "--vary",
            "parts.bar_thickness_mm=5,6",
            "--workers",
            "1",
            "--out",
            str(out),
        ],
        cwd=tmp_path,
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    deadline = time.monotonic() + 120
    while p.poll() is None and time.monotonic() < deadline:  # a worker process is being spawned
        if _spawning(p.pid):
            break
        time.sleep(0.01)
    kids = _descendants(p.pid)
    assert p.poll() is None, "the sweep ended before its cluster started"
    os.kill(p.pid, signal.SIGINT)
    os.killpg(p.pid, signal.SIGINT)
    _, err = p.communicate(timeout=120)  # stderr closes when the resource tracker is gone too
    lines = err.strip().splitlines()
    assert (p.returncode, lines[-1]) == (130, "hapticad: aborted"), err
    assert "Traceback" not in err and "leaked" not in err, err
    assert not out.exists()
    gone, alive = psutil.wait_procs(kids, timeout=10)
    assert alive == []
