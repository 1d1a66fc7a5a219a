"""cad.pipeline.forked: stages in forked children -- values and exceptions come back intact,
failures and cancellations leave no process or half-published output behind, the serial
fallback runs in the same order, and a forked build writes the same bytes as a serial one."""

from __future__ import annotations

import hashlib
import json
import os
import signal
import time
from pathlib import Path

import pytest

from cad.errors import DesignError, GeometryError, InterferenceError, MeshError
from cad.pipeline import forked

ROOT = Path(__file__).resolve().parents[3]


def _no_children_left() -> bool:
    try:
        os.waitpid(-1, os.WNOHANG)
    except ChildProcessError:
        return True
    return False


def test_value_comes_from_a_child_process():
    parent = os.getpid()
    task = forked.start(lambda: {"pid": os.getpid(), "x": [1.5, "a"]}, "t")
    out = task.result()
    assert out["x"] == [1.5, "a"]
    assert out["pid"] != parent
    assert _no_children_left()


@pytest.mark.parametrize(
    "exc",
    [
        DesignError("parts.bar_width_mm", "must exceed the bore, got 3"),
        MeshError("crank: mesh is not watertight (4 open or non-manifold edges)"),
        OSError("disk full (simulated)"),
        InterferenceError("pin_A2 / base_plate collide at phi1 = 10.00 deg"),
    ],
)
def test_child_exception_is_raised_in_the_parent_with_class_message_and_fields(exc):
    def boom():
        raise exc

    with pytest.raises(type(exc)) as info:
        forked.start(boom, "t").result()
    assert type(info.value) is type(exc)
    assert str(info.value) == str(exc)
    if isinstance(exc, DesignError):
        assert (info.value.field, info.value.reason) == (exc.field, exc.reason)
    assert _no_children_left()


def test_exception_class_that_cannot_be_imported_becomes_a_geometry_error():
    class LocalError(Exception):
        pass

    def boom():
        raise LocalError("local detail")

    with pytest.raises(GeometryError, match="LocalError: local detail"):
        forked.start(boom, "t").result()


def test_killed_child_is_reported():
    def die():
        os.kill(os.getpid(), signal.SIGKILL)

    with pytest.raises(GeometryError, match="killed by signal 9"):
        forked.start(die, "exports").result()
    assert _no_children_left()


def test_child_never_runs_the_callers_finally_blocks(tmp_path):
    """The child leaves with os._exit: a finally of the caller (the dispatcher's atomic
    publish, for instance) runs once, in the parent."""
    log = tmp_path / "log"
    try:
        task = forked.start(lambda: os.getpid(), "t")
        child = task.result()
    finally:
        with open(log, "a") as f:
            f.write(f"{os.getpid()}\n")
    assert log.read_text().split() == [str(os.getpid())]
    assert child != os.getpid()


def test_cancel_kills_a_running_child_promptly():
    t0 = time.perf_counter()
    task = forked.start(lambda: time.sleep(30), "slow")
    task.cancel()
    assert time.perf_counter() - t0 < 5.0
    assert _no_children_left()


def test_cancel_on_error_cancels_every_task():
    tasks = [forked.start(lambda: time.sleep(30), f"t{i}") for i in range(2)]
    with pytest.raises(InterferenceError), forked.cancel_on_error(*tasks):
        raise InterferenceError("parent failed")
    assert _no_children_left()


def test_serial_fallback_runs_at_result_in_process(monkeypatch):
    monkeypatch.setenv("HAPTICAD_FORK", "0")
    calls = []
    task = forked.start(lambda: calls.append(os.getpid()) or "done", "t")
    assert calls == []  # deferred: the serial order of the stages is kept
    assert task.result() == "done"
    assert calls == [os.getpid()]


def _hashes(out: Path) -> dict:
    return {
        p.relative_to(out).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(out.rglob("*"))
        if p.is_file() and p.name != "report.json" and p.name != "manifest.json"
    }


def test_forked_build_writes_the_same_bytes_as_a_serial_one(tmp_path, monkeypatch):
    from cad.design import load_design
    from cad.pipeline import build_design

    d = load_design(ROOT / "designs" / "hoeken.toml")
    fmts = {"step", "stl", "dxf"}
    a = build_design(d, tmp_path / "forked", fmts, fidelity="inertia", use_cache=False)
    monkeypatch.setenv("HAPTICAD_FORK", "0")
    b = build_design(d, tmp_path / "serial", fmts, fidelity="inertia", use_cache=False)
    assert _hashes(tmp_path / "forked") == _hashes(tmp_path / "serial")
    assert sorted(_hashes(tmp_path / "forked")) == sorted(a["files"])
    for r in (a, b):
        r.pop("timings_s", None)
    assert json.dumps(a, sort_keys=True, default=str) == json.dumps(b, sort_keys=True, default=str)


def test_parent_failure_cancels_the_children_and_publishes_nothing(tmp_path, monkeypatch):
    """An interference found while the export and preview children run: the error is the
    parent's, no child is left, the output folder is untouched and no temp dir remains."""
    import cad.assembly.interference as itf
    from cad.design import load_design
    from cad.pipeline import build_design

    def collide(rep, clearance_min_mm):
        raise InterferenceError("simulated collision")

    monkeypatch.setattr(itf, "raise_on_collision", collide)
    out = tmp_path / "exports" / "hoeken"
    out.mkdir(parents=True)
    (out / "old.txt").write_text("previous build")
    from cad.export.manifest import write_manifest

    write_manifest(out)  # a previous build's folder: everything in it listed
    d = load_design(ROOT / "designs" / "hoeken.toml")
    with pytest.raises(InterferenceError, match="simulated collision"):
        build_design(d, out, {"step", "stl"}, fidelity="inertia", use_cache=False)
    assert _no_children_left()
    assert sorted(p.name for p in out.iterdir()) == ["manifest.json", "old.txt"]
    assert sorted(p.name for p in out.parent.iterdir()) == ["hoeken"]
