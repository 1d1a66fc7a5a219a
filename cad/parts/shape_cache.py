"""Disk cache of catalog solids (bd_warehouse bearings and fasteners) as OCCT BREP files.

Building a bd_warehouse bearing or screw costs 0.2-0.4 s each; reading its BREP back
costs a few ms and needs neither bd_warehouse nor build123d. The key is the part
generator's name and arguments plus the versions of bd_warehouse and OCP, so a new
library version rebuilds. Every caller gets the shape READ BACK from the file (also
right after building it), so a first and a later build use bit-identical geometry
and their exports are byte-identical.

Location: ``$HAPTICAD_CACHE_DIR`` or ``~/.cache/hapticad``; set
``HAPTICAD_CACHE_DIR=off`` to disable (then shapes are built every time).
"""

from __future__ import annotations

import functools
import hashlib
import os
from collections.abc import Callable
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

CACHE_SCHEMA = "shapes-v1"


def cache_dir() -> Path | None:
    env = os.environ.get("HAPTICAD_CACHE_DIR")
    if env is not None and env.strip().lower() in ("off", "0", "none", ""):
        return None
    base = Path(env) if env else Path.home() / ".cache" / "hapticad"
    return base / CACHE_SCHEMA


@functools.cache
def _versions() -> str:
    out = []
    for pkg in ("bd_warehouse", "cadquery-ocp", "cadquery-ocp-novtk"):
        try:
            out.append(f"{pkg}={version(pkg)}")
        except PackageNotFoundError:
            out.append(f"{pkg}=none")
    return ";".join(out)


def _read(path: Path):
    from OCP.BRep import BRep_Builder
    from OCP.BRepTools import BRepTools
    from OCP.TopoDS import TopoDS_Shape

    shape = TopoDS_Shape()
    ok = BRepTools.Read_s(shape, str(path), BRep_Builder())
    return shape if ok and not shape.IsNull() else None


def cached_shape(key: str, make: Callable[[], object]):
    """The ``TopoDS_Shape`` for ``key``: from the disk cache, else ``make()`` then cached."""
    d = cache_dir()
    if d is None:
        return make()
    name = hashlib.sha256(f"{key}|{_versions()}".encode()).hexdigest()[:32] + ".brep"
    path = d / name
    if path.is_file():
        shape = _read(path)
        if shape is not None:
            return shape
    shape = make()
    try:
        from OCP.BRepTools import BRepTools

        from cad.io.atomic import atomic_path

        d.mkdir(parents=True, exist_ok=True)
        with atomic_path(path) as tmp:
            if not BRepTools.Write_s(shape, str(tmp)):
                raise OSError(f"cannot write {tmp}")
    except OSError:
        return shape  # read-only home or full disk: work without the cache
    back = _read(path)
    return back if back is not None else shape
