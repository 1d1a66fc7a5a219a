"""Signals with real processes (issue 11 items 6, 7): a build interrupted at any moment.

SIGINT or SIGTERM during the imports or while the forked export children run: exit
128 + signal, ``hapticad: aborted`` as the last stderr line, no traceback, the previous
build untouched, no temporary folder, no process left. SIGKILL while the children run:
the children die with the parent; the next build removes the dead build's temp folder.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from cad.export.manifest import write_manifest

ROOT = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="uses /proc")


def _procs_in(cwd: Path) -> list[int]:
    """Pids of the processes whose working folder is ``cwd`` (the build and its forks)."""
    found = []
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                if os.readlink(d / "cwd") == str(cwd):
                    found.append(int(d.name))
            except OSError:
                continue
    return found


def _children(pid: int) -> list[int]:
    kids = []
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                stat = (d / "stat").read_text()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                kids.append(int(d.name))
    return kids


def _tree(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file()}


def _start(tmp_path: Path) -> tuple[subprocess.Popen, Path]:
    cwd = (tmp_path / "w").resolve()
    (cwd / "exports" / "hoeken").mkdir(parents=True)
    shutil.copy(ROOT / "designs" / "hoeken.toml", cwd / "h.toml")
    (cwd / "exports" / "hoeken" / "old.txt").write_text("the previous build")
    write_manifest(cwd / "exports" / "hoeken")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    p = subprocess.Popen(
        [sys.executable, "-m", "cad", "build", "h.toml", "--fidelity", "preview", "--no-cache",
         "--json"],
        cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )
    return p, cwd


def _wait_for_children(p: subprocess.Popen, timeout_s: float = 240.0) -> None:
    t0 = time.monotonic()
    while not _children(p.pid):
        assert p.poll() is None, p.communicate()
        assert time.monotonic() - t0 < timeout_s, "no export child appeared"
        time.sleep(0.02)


def _gone(cwd: Path, timeout_s: float = 10.0) -> bool:
    t0 = time.monotonic()
    while _procs_in(cwd):
        if time.monotonic() - t0 > timeout_s:
            return False
        time.sleep(0.05)
    return True


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
@pytest.mark.parametrize("moment", ["imports", "export-children"])
def test_interrupted_build_aborts_cleanly(tmp_path, sig, moment):
    p, cwd = _start(tmp_path)
    before = _tree(cwd / "exports")
    if moment == "imports":
        time.sleep(0.3)
    else:
        _wait_for_children(p)
    p.send_signal(sig)
    out, err = p.communicate(timeout=120)
    assert p.returncode == 128 + sig, err
    assert err.strip().splitlines()[-1] == "hapticad: aborted", err
    assert "Traceback" not in err and out == ""
    assert _tree(cwd / "exports") == before  # nothing published, the old build untouched
    assert sorted(p.name for p in (cwd / "exports").iterdir()) == ["hoeken"]  # no temp folder
    assert _gone(cwd), "a forked child outlived the build"


def test_sigkill_children_die_and_the_next_build_cleans_up(tmp_path):
    from cad.io.atomic import atomic_dir

    p, cwd = _start(tmp_path)
    before = _tree(cwd / "exports" / "hoeken")
    _wait_for_children(p)
    p.kill()
    p.communicate(timeout=60)
    assert _gone(cwd), "a forked child outlived its SIGKILLed parent"
    stale = [e for e in (cwd / "exports").iterdir() if e.name.startswith(".hoeken.tmp.")]
    assert len(stale) == 1 and f".tmp.{p.pid}." in stale[0].name
    # a folder of the same shape whose owner is alive (this process) is not touched
    alive = cwd / "exports" / f".hoeken.tmp.{os.getpid()}.abcdefgh"
    alive.mkdir()
    (alive / ".hapticad-owner").write_text(f"{os.uname().nodename}\n{os.getpid()}\n")
    with pytest.raises(RuntimeError), atomic_dir(cwd / "exports" / "hoeken"):  # the next build
        raise RuntimeError("fails after its start: publishes nothing")
    assert sorted(e.name for e in (cwd / "exports").iterdir()) == [alive.name, "hoeken"]
    assert _tree(cwd / "exports" / "hoeken") == before


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_a_signal_during_the_publish_puts_the_old_folder_back(tmp_path, monkeypatch, sig):
    """The rename is deferred-signal: a signal between moving the old folder away and moving
    the new one in is acted on after both, by undoing them (handler called as the OS would)."""
    from cad.io import atomic, signals

    target = tmp_path / "out"
    target.mkdir()
    (target / "old.txt").write_text("old")
    monkeypatch.setitem(signals._state, "installed", True)
    real = os.replace
    fired = []

    def replace(a, b):
        real(a, b)
        if Path(b) == target and not fired:
            fired.append(True)
            signals._handler(sig, None)  # arrives right after the new folder moved in

    monkeypatch.setattr(atomic.os, "replace", replace)
    try:
        with pytest.raises(KeyboardInterrupt), atomic.atomic_dir(target) as tmp:
            (tmp / "new.txt").write_text("new")
        assert signals.received() == sig and signals.exit_code() == 128 + sig
    finally:
        signals.reset()
    assert fired and sorted(p.name for p in tmp_path.iterdir()) == ["out"]
    assert [p.name for p in target.iterdir()] == ["old.txt"]
    assert (target / "old.txt").read_text() == "old"


def test_a_signal_before_the_publish_publishes_nothing(tmp_path, monkeypatch):
    """A library swallowed the interrupt (recorded, no exception): the publish refuses."""
    from cad.io import atomic, signals

    monkeypatch.setitem(signals._state, "installed", True)
    try:
        with pytest.raises(KeyboardInterrupt), atomic.atomic_dir(tmp_path / "e" / "out") as tmp:
            (tmp / "new.txt").write_text("new")
            with pytest.raises(KeyboardInterrupt):
                signals._handler(signal.SIGINT, None)  # raised ... and swallowed
        with pytest.raises(KeyboardInterrupt):
            atomic.write_text_atomic(tmp_path / "f.toml", "x", final=True)
    finally:
        signals.reset()
    assert list(tmp_path.iterdir()) == []  # not even the parent folder "e"
