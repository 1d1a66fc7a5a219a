"""Mass properties of part solids cached by the solid's cache key (in-process, then on disk).

A ``check`` / ``fit`` / ``sweep`` evaluation needs of each part only its unit-density
volume integrals (volume, COM, tensor about the COM, mm units; the density is applied
afterwards, so a material change integrates nothing). They are a function of the solid,
and a part solid is a function of its cache key (:mod:`cad.parts.part_cache`: generator,
arguments, source hash, library versions). So the integrals are kept by that key:

* in this process (a dict by key), then
* on disk, ``<cache dir>/props-v1/<2 hex>/<sha256 of the key>.json`` beside the BREP files
  of :mod:`cad.parts.shape_cache` (256 sub-folders: an atomic write scans its folder for
  stale temporary files, so a sweep's thousands of entries must not share one folder). An entry holds the full key and the three integrals (floats
  written by ``repr``, so they read back bit-identical) and the sha256 of that payload; a
  wrong hash, another key, unreadable JSON or a non-finite / non-positive value is a miss
  (the solid is then made or read, validated and integrated again, and the entry rewritten).

An entry is written only after the solid passed :func:`cad.massprops.occt.check_valid`. The
integrals are those of the solid the first process had: read back from its BREP when the
shape cache holds it (what ``build`` uses), else freshly built and not written (an
evaluation does not fill the shape cache with solids nobody exports;
:meth:`cad.parts.part_cache.DeferredShape.solid_for_props`). Either way a second process
gets exactly the first process's values, and ``check`` and a later ``build`` of the design
agree to the last bit. The key
also carries a hash of ``cad/massprops/occt.py`` and of this file: a change of the
integration is a miss. ``HAPTICAD_CACHE_DIR=off`` disables the disk part.

With a :class:`cad.parts.part_cache.DeferredShape` whose entry is on disk, no solid is
read or built and neither build123d nor OCP is imported.
"""

from __future__ import annotations

import functools
import hashlib
import json
import math
from pathlib import Path

import numpy as np

from cad.errors import FileRefused
from cad.io import cache_faults, guard
from cad.io.atomic import write_text_atomic
from cad.io.cache_limit import touch
from cad.massprops.occt import cached_unit_props, check_valid, to_si, volume_props_mm
from cad.parts.part_cache import DeferredShape, shape_key
from cad.parts.shape_cache import cache_dir, library_versions

#: Folder under the shape cache holding the entries; v1: payload + sha256 in one JSON file.
PROPS_DIR = "props-v1"
#: in-process entries kept (unit-density integrals are ~100 bytes each)
MEMO_MAX = 4096

_MEMO: dict[str, tuple[float, np.ndarray, np.ndarray]] = {}
STATS = {"memo_hits": 0, "disk_hits": 0, "integrated": 0}


@functools.cache
def _code_version() -> str:
    h = hashlib.sha256()
    for p in (Path(__file__).parents[1] / "massprops" / "occt.py", Path(__file__)):
        h.update(p.read_bytes())
    return h.hexdigest()[:16]


def _entry_path(key: str) -> Path | None:
    d = cache_dir()
    if d is None:
        return None
    name = hashlib.sha256(f"props:{_code_version()}|{key}|{library_versions()}".encode()).hexdigest()[:32]
    return d / PROPS_DIR / name[:2] / f"{name}.json"


def _payload_text(payload: dict) -> str:
    return json.dumps(payload, sort_keys=True, separators=(",", ":"))


def _read(path: Path, key: str):
    """The integrals stored for ``key`` in ``path``, or None (module docstring: a miss)."""
    try:  # a regular file of bounded size, or a miss (cad/io/guard.py)
        doc = guard.load_json(path, "cache", "cache")
        payload = doc["payload"]
        if hashlib.sha256(_payload_text(payload).encode()).hexdigest() != doc["sha256"]:
            return None
        if payload["key"] != key:
            return None
        vol = float(payload["volume_mm3"])
        com = np.array(payload["com_mm"], dtype=float).reshape(3)
        inertia = np.array(payload["inertia_com_mm5"], dtype=float).reshape(3, 3)
    except (FileRefused, OSError, ValueError, KeyError, TypeError, AttributeError):
        return None
    if not (math.isfinite(vol) and vol > 0 and np.all(np.isfinite(com)) and np.all(np.isfinite(inertia))):
        return None

    touch(path)  # recently used (cad.io.cache_limit prunes the oldest)
    return vol, com, inertia


def _write(path: Path, key: str, vol: float, com, inertia) -> None:
    payload = {"key": key, "volume_mm3": float(vol),
               "com_mm": [float(x) for x in np.asarray(com).reshape(3)],
               "inertia_com_mm5": [[float(x) for x in row] for row in np.asarray(inertia).reshape(3, 3)]}
    doc = {"payload": payload, "sha256": hashlib.sha256(_payload_text(payload).encode()).hexdigest()}

    if not cache_faults.writable():
        return
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        write_text_atomic(path, json.dumps(doc, sort_keys=True) + "\n")
    except Exception as exc:  # noqa: BLE001 - read-only home or full disk: work without the cache
        cache_faults.write_failed("a mass-property entry", exc)


def _integrate(shape):
    check_valid(shape)
    STATS["integrated"] += 1
    return volume_props_mm(shape)


def unit_volume_props(shape) -> tuple[float, np.ndarray, np.ndarray]:
    """``(volume_mm3, com_mm (3,), inertia_com_mm5 (3, 3))`` of a part solid at unit density,
    validated (module docstring). ``shape``: a :class:`~cad.parts.part_cache.DeferredShape`,
    a solid from :mod:`cad.parts.part_cache`, or any other solid (then integrated through
    :func:`cad.massprops.occt.cached_solid_mass_props`'s per-object memo). Raises
    :class:`cad.errors.GeometryError` for an invalid solid."""
    key = shape_key(shape)
    if key is None:

        return cached_unit_props(shape)
    hit = _MEMO.get(key)
    if hit is not None:
        STATS["memo_hits"] += 1
        return hit
    path = _entry_path(key)
    got = _read(path, key) if path is not None and path.is_file() else None
    if got is not None:
        STATS["disk_hits"] += 1
    else:
        solid = shape.solid_for_props() if isinstance(shape, DeferredShape) else shape
        got = _integrate(solid)
        if path is not None:
            _write(path, key, *got)
    if len(_MEMO) >= MEMO_MAX:
        _MEMO.pop(next(iter(_MEMO)))
    _MEMO[key] = got
    return got


def part_mass_props(shape, density_kg_m3: float):
    """:class:`cad.massprops.props.MassProps` (SI, part frame) of a part solid of uniform
    density: :func:`unit_volume_props` converted by :func:`cad.massprops.occt.to_si`."""
    vol, com, inertia = unit_volume_props(shape)
    return to_si(vol, com, inertia, density_kg_m3)


def clear_memo() -> None:
    """Forget the in-process integrals (tests, benchmarks of the cold path)."""
    _MEMO.clear()
