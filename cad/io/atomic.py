"""Atomic writes: write to a temporary path beside the target, then rename.

A failure at any point leaves the target untouched and no partial file behind.

* Modes follow the umask (``mkstemp``/``mkdtemp`` create 0600/0700; the result is set
  to 0666/0777 minus the umask before it is published, like a plain ``open``/``mkdir``).
* Folders this module creates on the way to a target (``exports/`` ...) are removed
  again when the write fails (only if still empty).
* A temporary folder carries its owner's pid in its name and an owner file
  (:data:`OWNER_FILE`); a temporary file carries a tag of its host and its owner's pid
  in its name (``.<name>.tmp.<host tag>.<pid>.<8 chars><suffix>``).
  :func:`remove_stale_temps` (run by every :func:`atomic_dir`, and by :func:`atomic_path`
  the first time a process writes into a folder) deletes the ones whose owner is dead
  on this host (a command killed by SIGKILL), and nothing else.
* The rename is the commit point of :mod:`cad.io.signals`: a SIGINT/SIGTERM received
  before it publishes nothing.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import re
import shutil
import socket
import stat
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path

from cad.errors import FileRefused
from cad.io import guard, signals

#: Owner file inside a temporary folder: ``<host>\n<pid>\n``.
OWNER_FILE = ".hapticad-owner"
_TEMP_RE = re.compile(r"^\..*\.(tmp|old)\.(\d+)\.[A-Za-z0-9_]{8}$")
_TEMP_FILE_RE = re.compile(r"^\..+\.tmp\.([0-9a-f]{6})\.(\d+)\.[A-Za-z0-9_]{8}[^/]*$")


def host_tag() -> str:
    """Six hex digits of this host's name (temporary file names; a pid means nothing on
    another host sharing the folder)."""
    return hashlib.sha256(socket.gethostname().encode("utf-8")).hexdigest()[:6]


def umask() -> int:
    """The process umask (read from /proc where possible: no set-and-restore race)."""
    with contextlib.suppress(OSError, ValueError):
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("Umask:"):
                return int(line.split()[1], 8)
    m = os.umask(0o022)
    os.umask(m)
    return m


def _honour_umask(path: Path) -> None:
    """chmod a file to 0666 & ~umask, a folder tree to 0777/0666 & ~umask."""
    m = umask()
    if path.is_dir() and not path.is_symlink():
        os.chmod(path, 0o777 & ~m)
        for root, dirs, files in os.walk(path):
            for d in dirs:
                os.chmod(os.path.join(root, d), 0o777 & ~m)
            for f in files:
                p = os.path.join(root, f)
                if not os.path.islink(p) and stat.S_IMODE(os.lstat(p).st_mode) == 0o600:
                    os.chmod(p, 0o666 & ~m)
    elif path.is_file():
        os.chmod(path, 0o666 & ~m)


def _mkdirs(folder: Path) -> list[Path]:
    """``mkdir -p folder``; returns the folders it created, outermost first."""
    created: list[Path] = []
    p = folder
    while not p.exists() and p != p.parent:
        created.append(p)
        p = p.parent
    created.reverse()
    for c in created:
        try:
            c.mkdir()
        except FileExistsError:
            pass
    return created


def _rmdirs(created: list[Path]) -> None:
    for c in reversed(created):
        with contextlib.suppress(OSError):
            c.rmdir()


@contextlib.contextmanager
def atomic_path(
    target: str | os.PathLike, suffix: str | None = None, final: bool = False
) -> Iterator[Path]:
    """Yield a temporary path; on success rename it onto ``target``.

    ``suffix`` defaults to the target's suffix so that exporters that pick a
    format from the extension still work. ``final``: the file is the command's output
    (:func:`cad.io.signals.commit`); a signal during the rename restores the old file.
    """
    target = Path(target)
    created = _mkdirs(target.parent)
    _remove_stale_temps_once(target.parent)
    fd, tmp = tempfile.mkstemp(
        prefix=f".{target.name}.tmp.{host_tag()}.{os.getpid()}.",
        suffix=suffix if suffix is not None else target.suffix,
        dir=target.parent,
    )
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        _honour_umask(tmp_path)
        backup = None
        if final and target.is_file():
            backup = Path(str(tmp_path) + ".bak")
            try:
                os.link(target, backup)  # kept until the rename is through (signal -> undo)
            except OSError:  # no hard links on this file system: no undo of a replacement
                backup = None

        done: list[bool] = []

        def undo() -> None:
            if done and backup is not None:
                os.replace(backup, target)
            elif done:
                target.unlink()

        try:
            with signals.commit(undo if final else None, final=final):
                os.replace(tmp_path, target)
                done.append(True)
        finally:
            if backup is not None:
                with contextlib.suppress(FileNotFoundError):
                    backup.unlink()
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            tmp_path.unlink()
        _rmdirs(created)
        raise


def write_text_atomic(target: str | os.PathLike, text: str, final: bool = False) -> Path:
    """Write ``text`` (UTF-8) to ``target`` atomically and return the path."""
    with atomic_path(target, final=final) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(target)


def write_bytes_atomic(target: str | os.PathLike, data: bytes) -> Path:
    """Write ``data`` to ``target`` atomically and return the path."""
    with atomic_path(target) as tmp:
        tmp.write_bytes(data)
    return Path(target)


def _owner_text() -> str:
    return f"{socket.gethostname()}\n{os.getpid()}\n"


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # EPERM: alive, someone else's
        return True
    return True


def _stale_file(name: str) -> bool:
    """``name`` is a temporary file of :func:`atomic_path` (or its ``.bak`` link) whose
    owner, on this host, is dead."""
    m = _TEMP_FILE_RE.match(name)
    if m is None or m.group(1) != host_tag():
        return False
    pid = int(m.group(2))
    return pid != os.getpid() and not _pid_alive(pid)


def _stale_dir(path: str, name: str) -> bool:
    """``name`` is a temporary folder of :func:`atomic_dir` whose owner (its
    :data:`OWNER_FILE`: this host and the pid in the name) is dead."""
    m = _TEMP_RE.match(name)
    if m is None:
        return False
    pid = int(m.group(2))
    try:  # never a FIFO or a device planted as the owner file (cad/io/guard.py)
        lines = guard.read_text(Path(path, OWNER_FILE), "marker", "owner").splitlines()
    except FileRefused:
        return False
    host = socket.gethostname()
    return lines[:2] == [host, str(pid)] and pid != os.getpid() and not _pid_alive(pid)


def remove_stale_temps(folder: Path) -> list[Path]:
    """Delete the temporary folders and files in ``folder`` left by dead commands on this
    host (module docstring): a folder named ``.<name>.tmp|old.<pid>.<8 chars>`` whose
    :data:`OWNER_FILE` names this host and that pid, or a plain file named
    ``.<name>.tmp.<host tag>.<pid>.<8 chars>…``, whose pid is not running. Nothing else
    is touched. Returns the removed paths.
    """
    removed = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed
    for e in entries:
        if e.is_dir(follow_symlinks=False):
            if _stale_dir(e.path, e.name):
                shutil.rmtree(e.path, ignore_errors=True)
                removed.append(Path(e.path))
        elif e.is_file(follow_symlinks=False) and _stale_file(e.name):
            with contextlib.suppress(FileNotFoundError):
                os.unlink(e.path)
            removed.append(Path(e.path))
    return removed


_SCANNED: set[str] = set()


def _remove_stale_temps_once(folder: Path) -> None:
    """:func:`remove_stale_temps` the first time this process writes into ``folder``
    (a cache folder of thousands of entries is not scanned at every write)."""
    key = os.path.abspath(folder)
    if key not in _SCANNED:
        _SCANNED.add(key)
        remove_stale_temps(folder)


def _mkdtemp_owned(parent: Path, name: str, kind: str) -> Path:
    d = Path(tempfile.mkdtemp(prefix=f".{name}.{kind}.{os.getpid()}.", dir=parent))
    (d / OWNER_FILE).write_text(_owner_text(), encoding="utf-8")
    return d


@contextlib.contextmanager
def atomic_dir(
    target: str | os.PathLike, check: Callable[[Path], None] | None = None
) -> Iterator[Path]:
    """Yield a fresh temporary directory; on success it replaces ``target``.

    Everything a command exports goes into the temporary directory; only when
    all of it is written does it appear at ``target`` (an older ``target`` is
    removed at that moment). ``check(target)``, when given, runs again just before
    that (e.g. :func:`cad.io.outdir.check_owned`: the old folder holds nothing foreign)
    and may raise to stop the publish. On failure or a signal nothing changes at
    ``target`` and the folders created on the way are removed.
    """
    target = Path(target)
    created = _mkdirs(target.parent)
    remove_stale_temps(target.parent)
    tmp = _mkdtemp_owned(target.parent, target.name, "tmp")
    old: Path | None = None
    try:
        yield tmp
        if check is not None:
            check(target)
        (tmp / OWNER_FILE).unlink()
        _honour_umask(tmp)
        if os.path.lexists(target):
            old = _mkdtemp_owned(target.parent, target.name, "old")
        moved = []

        def undo() -> None:
            if "new" in moved:
                os.replace(target, tmp)
            if "old" in moved:
                os.replace(old / "x", target)

        with signals.commit(undo, final=True):
            if old is not None:
                os.replace(target, old / "x")
                moved.append("old")
            os.replace(tmp, target)
            moved.append("new")
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)
        _rmdirs(created)
        raise
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)


@contextlib.contextmanager
def atomic_dir_update(
    target: str | os.PathLike, check: Callable[[Path], None] | None = None
) -> Iterator[Path]:
    """:func:`atomic_dir` for a command that adds its files to an output folder: the
    temporary directory starts with a copy of every regular file ``target`` holds but its
    ``manifest.json`` (a folder :func:`cad.io.outdir.check_out_dir` accepted: hapticad's own
    files), so the files the command does not write again are kept (``bench --only``,
    ``tolerance --out`` into a build's folder); its sub-folders (empty ones too) and symbolic
    links are kept as they are (a shared folder, ``render --out``, holds the user's files).
    Everything appears at once, with the manifest the command writes; an interrupted or
    failed command leaves ``target`` as it was.
    """
    target = Path(target)
    with atomic_dir(target, check) as tmp:
        if target.is_dir():
            for src in sorted(target.rglob("*")):
                rel = src.relative_to(target)
                mode = os.lstat(src).st_mode
                if rel.as_posix() == "manifest.json" or not (stat.S_ISREG(mode) or stat.S_ISDIR(mode)
                                                              or stat.S_ISLNK(mode)):
                    continue
                (tmp / rel).parent.mkdir(parents=True, exist_ok=True)
                if stat.S_ISLNK(mode):
                    os.symlink(os.readlink(src), tmp / rel)
                elif stat.S_ISDIR(mode):
                    (tmp / rel).mkdir(exist_ok=True)
                else:
                    shutil.copy2(src, tmp / rel)
        yield tmp
