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

ROOT = Path(__file__).resolve().parents[2]
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
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid and "(hapticad-watch)" not in stat:
                kids.append(int(d.name))  # the forks, not the signal watchdog (cad.io.signals)
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


def _building(cwd: Path) -> bool:
    """The build's temporary output folder exists (cad.io.atomic.atomic_dir): its export
    children are forked inside it. Waiting for it too keeps the signal watchdog, forked at
    start and named only a moment later (cad.io.signals), from passing for an export child."""
    return any(e.name.startswith(".hoeken.tmp.") for e in (cwd / "exports").iterdir())


def _wait_for_children(p: subprocess.Popen, cwd: Path, timeout_s: float = 240.0) -> None:
    t0 = time.monotonic()
    while not (_building(cwd) and _children(p.pid)):
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
        _wait_for_children(p, cwd)
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
    _wait_for_children(p, cwd)
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


def _dead_pid() -> int:
    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    return p.pid


def test_a_killed_writers_temp_file_is_removed_by_the_next_write(tmp_path):
    """A file command (swap/synth/fit --out) killed by SIGKILL leaves its hidden temporary
    file; the next atomic write into that folder removes it -- and only such files: a live
    owner's, another host's, a user's look-alike and a folder stay."""
    from cad.io.atomic import host_tag, write_text_atomic

    tag, dead = host_tag(), _dead_pid()
    other_tag = "000000" if tag != "000000" else "111111"
    stale = tmp_path / f".r.toml.tmp.{tag}.{dead}.abcd_123.toml"
    stale_bak = tmp_path / f".r.toml.tmp.{tag}.{dead}.abcd_123.toml.bak"
    keep = [
        tmp_path / f".r.toml.tmp.{tag}.{os.getppid()}.abcd_123.toml",  # owner alive
        tmp_path / f".r.toml.tmp.{other_tag}.{dead}.abcd_123.toml",  # another host's
        tmp_path / ".r.toml.tmp",  # the user's
        tmp_path / f"r.toml.tmp.{tag}.{dead}.abcd_123.toml",  # not hidden: not ours
    ]
    for p in [stale, stale_bak, *keep]:
        p.write_text("x")
    (tmp_path / f".d.tmp.{tag}.{dead}.abcd_123").mkdir()  # a folder without owner file
    write_text_atomic(tmp_path / "s.toml", "a = 1\n")
    assert not stale.exists() and not stale_bak.exists()
    assert all(p.exists() for p in keep)
    assert (tmp_path / f".d.tmp.{tag}.{dead}.abcd_123").is_dir()
    assert (tmp_path / "s.toml").read_text() == "a = 1\n"


def test_sigkilled_swap_leaves_nothing_after_the_next_swap(tmp_path):
    """A real SIGKILL of `hapticad swap` while it writes (the child stops itself with
    SIGSTOP at its first rename, when its temporary file exists), then the next swap into
    the same folder: no hidden file remains."""
    out = tmp_path / "o"
    out.mkdir()
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    code = (
        "import os, signal, cad.io.atomic as a\n"
        "real = os.replace\n"
        "def stop(src, dst):\n"
        "    os.kill(os.getpid(), signal.SIGSTOP)\n"
        "    real(src, dst)\n"
        "a.os.replace = stop\n"
        "from cad.cli.entry import main\n"
        "main()\n"
    )
    args = ["swap", str(ROOT / "designs" / "hoeken.toml"), "--to", "roberts",
            "--out", str(out / "r.toml")]
    p = subprocess.Popen([sys.executable, "-c", code, *args], env=env, cwd=tmp_path,
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        st = Path(f"/proc/{p.pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
        if st == "T" or p.poll() is not None:
            break
        time.sleep(0.05)
    p.kill()
    p.wait()
    hidden = [e.name for e in out.iterdir() if e.name.startswith(".")]
    assert hidden, "the killed swap left no temporary file (the test did not catch it writing)"
    r = subprocess.run([sys.executable, "-m", "cad", *args], env=env, cwd=tmp_path,
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert sorted(e.name for e in out.iterdir()) == ["r.toml"]
