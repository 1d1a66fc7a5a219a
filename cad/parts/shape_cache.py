"""Disk cache of catalog solids (bd_warehouse bearings and fasteners) as OCCT BREP files.

Building a bd_warehouse bearing or screw costs 0.2-0.4 s each; reading its BREP back
costs a few ms and needs neither bd_warehouse nor build123d. The key is the part
generator's name and arguments plus the versions of bd_warehouse, build123d and OCP, so a new
library version rebuilds. Every caller gets the shape READ BACK from the file (also
right after building it), so a first and a later build use bit-identical geometry
and their exports are byte-identical.

Integrity: each entry ``<key>.brep`` has its sha256 in ``<key>.brep.sha256``; the hash is
checked before OCCT parses the file (a truncated BREP can make ``BRepTools::Read`` never
return), and any mismatch or read failure is a miss: the shape is rebuilt and rewritten.
A write that fails (read-only folder, full disk) is a fault of :mod:`cad.io.cache_faults`:
said once, and the command carries on without the cache.

Location: ``$HAPTICAD_CACHE_DIR`` or ``~/.cache/hapticad``; set
``HAPTICAD_CACHE_DIR=off`` to disable (then shapes are built every time).
"""

from __future__ import annotations

import functools
import hashlib
from collections.abc import Callable
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

from cad.errors import FileRefused
from cad.io import cache_faults, guard
from cad.io.atomic import atomic_path, write_text_atomic
from cad.io.cache_limit import cache_root, touch
from cad.io.derived_cache import register_digest
from cad.parts.lazy_import import import_build123d

#: v2: every ``<key>.brep`` has ``<key>.brep.sha256`` beside it, checked before reading.
CACHE_SCHEMA = "shapes-v2"


def cache_dir() -> Path | None:
    """The shape cache's folder under the caches' parent (:func:`cad.io.cache_limit.cache_root`);
    None when ``HAPTICAD_CACHE_DIR=off``."""
    root = cache_root()
    return None if root is None else root / CACHE_SCHEMA


@functools.cache
def library_versions() -> str:
    out = []
    for pkg in ("bd_warehouse", "build123d", "cadquery-ocp", "cadquery-ocp-novtk"):
        try:
            out.append(f"{pkg}={version(pkg)}")
        except PackageNotFoundError:
            out.append(f"{pkg}=none")
    return ";".join(out)


def _read(path: Path):
    """The shape in ``path`` -- only after its sha256 matches the ``.sha256`` file beside
    it (a truncated BREP can make ``BRepTools::Read`` hang, so it is never parsed
    unverified); None on any mismatch or read failure (a miss)."""
    from OCP.BRep import BRep_Builder
    from OCP.BRepTools import BRepTools
    from OCP.TopoDS import TopoDS_Shape

    try:  # a regular file of bounded size, or a miss (cad/io/guard.py)
        data = guard.read_bytes(path, "cache", "cache")
        want = guard.read_text(_hash_path(path), "marker", "cache", "ascii").strip()
    except (FileRefused, OSError):
        return None
    if hashlib.sha256(data).hexdigest() != want:
        return None
    shape = TopoDS_Shape()
    try:
        ok = BRepTools.Read_s(shape, str(path), BRep_Builder())
    except Exception:  # noqa: BLE001 - any OCCT failure is a miss
        return None
    if not ok or shape.IsNull():
        return None

    register_digest(shape, want)  # what is derived from it is cached by this digest

    touch(path)  # recently used (cad.io.cache_limit prunes the oldest)
    return shape


def _hash_path(path: Path) -> Path:
    return path.with_name(path.name + ".sha256")


def _write(shape, path: Path) -> None:
    """BREP then its sha256 beside it, each atomically (a reader never sees a partial file;
    a BREP without a matching hash is a miss)."""
    from OCP.BRepTools import BRepTools


    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(path) as tmp:
        if not BRepTools.Write_s(shape, str(tmp)):
            raise OSError(f"cannot write {tmp}")
        digest = hashlib.sha256(tmp.read_bytes()).hexdigest()
    write_text_atomic(_hash_path(path), digest + "\n")


def entry_path(key: str) -> Path | None:
    """The BREP file of ``key`` (None when the cache is off)."""
    d = cache_dir()
    if d is None:
        return None
    return d / (hashlib.sha256(f"{key}|{library_versions()}".encode()).hexdigest()[:32] + ".brep")


def read_cached_shape(key: str):
    """The cached shape of ``key`` (verified as in :func:`cached_shape`), or None: nothing
    is made or written."""
    path = entry_path(key)
    return _read(path) if path is not None and path.is_file() else None


def cached_shape(key: str, make: Callable[[], object]):
    """The ``TopoDS_Shape`` for ``key``: from the disk cache, else ``make()`` then cached.

    A damaged entry (truncated, a flipped bit, a missing or wrong ``.sha256``, unreadable)
    is a miss: the shape is made again and the entry rewritten.
    """
    path = entry_path(key)
    if path is None:
        import_build123d()  # before a part generator imports it (defers scikit-learn)
        return _round_trip(make())
    if path.is_file():
        shape = _read(path)
        if shape is not None:
            return shape
    import_build123d()  # a miss: the part generator needs build123d (defers scikit-learn)
    shape = make()

    if not cache_faults.writable():
        return _round_trip(shape)
    try:
        _write(shape, path)
    except Exception as exc:  # noqa: BLE001 - full disk: OCCT raises RuntimeError std::bad_cast
        cache_faults.write_failed("a shape entry", exc)  # read-only or full: work without it
        return _round_trip(shape)
    back = _read(path)
    return back if back is not None else _round_trip(shape)


def _round_trip(shape):
    """``shape`` written as BREP and read back (through a private temporary file), as a
    cache hit would give it: the exports (STEP direction signs, STL triangulation) are then
    byte-identical whether the cache is on, off or unwritable."""
    import tempfile

    from OCP.BRep import BRep_Builder
    from OCP.BRepTools import BRepTools
    from OCP.TopoDS import TopoDS_Shape

    try:
        with tempfile.TemporaryDirectory(prefix="hapticad-brep-") as tmp:
            f = str(Path(tmp) / "s.brep")
            back = TopoDS_Shape()
            if not (BRepTools.Write_s(shape, f) and BRepTools.Read_s(back, f, BRep_Builder())):
                return shape
    except Exception:  # noqa: BLE001 - a full temporary folder: the shape as made
        return shape
    return shape if back.IsNull() else back
