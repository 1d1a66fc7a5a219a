"""Disk cache of what a build derives from its part solids: meshes, boxes, booleans, files.

A cold ``hapticad build`` (``--no-cache``) of a design built before reads its solids back
from the shape cache (:mod:`cad.parts.shape_cache`) in milliseconds, and then spent most
of its time deriving the same things from the same solids again: STL meshes, tight
bounding boxes, exact common volumes of same-body parts, part STEP/DXF bytes. Each of
those is a deterministic function of the solid(s) and a few parameters, so it is cached
here, next to the shape cache, under a key made of:

* the **content digest of every solid** it depends on (:func:`shape_digest`: the sha256 of
  the solid's BREP -- taken from the shape cache file the solid was read from, else
  computed by writing the BREP to memory);
* every parameter in canonical form (floats by ``repr``: a tolerance of 0.05 and of
  0.0500001 are two entries);
* the versions of OCP, bd_warehouse, build123d and numpy, and a hash of the source of the
  modules that compute the value and of ``cad/tolerances.py`` (a code change is a miss).

Integrity as in the shape cache: each entry ``<key>.bin`` has its sha256 in
``<key>.bin.sha256``, checked before the value is decoded; a mismatch, a missing hash or a
value that does not decode is a miss (recomputed and rewritten); a failed write is a fault
of :mod:`cad.io.cache_faults` (said once, the command carries on without the cache). Values are raw bytes,
JSON, or numpy arrays (``np.savez``, read with ``allow_pickle=False``): nothing is
unpickled. ``HAPTICAD_CACHE_DIR=off`` disables this cache together with the shape cache.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.util
import io
import json
from collections import OrderedDict
from collections.abc import Callable
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

import numpy as np

from cad.errors import FileRefused
from cad.io import cache_faults, guard
from cad.io.atomic import write_bytes_atomic, write_text_atomic
from cad.io.cache_limit import cache_root, touch
from cad.occ.shape_io import brep_bytes

#: Folder beside the shape cache's ``shapes-v2`` (bump to drop every derived entry); entries
#: in 256 sub-folders by the first two hex digits of their name.
SCHEMA = "derived-v2"
#: Digests remembered per shape object (the shape is kept alive with it, so an ``id`` is
#: never reused while its entry exists).
DIGEST_MEMO_MAX = 4096

_DIGESTS: OrderedDict[int, tuple[Any, str]] = OrderedDict()
STATS = {"hits": 0, "misses": 0, "digests_computed": 0}


def cache_dir() -> Path | None:
    """This cache's folder under the caches' parent (:func:`cad.io.cache_limit.cache_root`),
    beside the shape cache's; None when ``HAPTICAD_CACHE_DIR=off``."""
    root = cache_root()
    return None if root is None else root / SCHEMA


def enabled() -> bool:
    return cache_dir() is not None


def register_digest(shape, digest: str) -> None:
    """Remember ``digest`` (sha256 hex of the BREP ``shape`` was read from) for ``shape``."""
    _DIGESTS[id(shape)] = (shape, digest)
    _DIGESTS.move_to_end(id(shape))
    while len(_DIGESTS) > DIGEST_MEMO_MAX:
        _DIGESTS.popitem(last=False)


def register_placed(moved, shape, T) -> None:
    """Give ``moved`` (``shape`` moved by the 4x4 ``T``, :func:`cad.export.shapes.placed`) the
    digest of (``shape``'s digest, ``T`` exactly) -- only when ``shape``'s digest is known
    already (nothing is computed here)."""
    hit = _DIGESTS.get(id(shape))
    if hit is None or hit[0] is not shape or cache_dir() is None:
        return
    text = json.dumps([hit[1], _canonical(np.asarray(T, float))], separators=(",", ":"))
    register_digest(moved, "placed:" + hashlib.sha256(text.encode()).hexdigest())


def shape_digest(shape) -> str:
    """sha256 (hex) identifying the geometry of an OCP ``TopoDS_Shape``.

    The digest of the shape-cache file it was read from when known (:func:`register_digest`),
    else the sha256 of its BREP text written to memory without triangulations (the full
    topology, geometry and location: two shapes with one digest are the same solid).
    """
    hit = _DIGESTS.get(id(shape))
    if hit is not None and hit[0] is shape:
        return hit[1]

    digest = "brep:" + hashlib.sha256(brep_bytes(shape)).hexdigest()
    STATS["digests_computed"] += 1
    register_digest(shape, digest)
    return digest


@functools.cache
def _versions() -> str:
    out = []
    for pkg in (
        "cadquery-ocp",
        "cadquery-ocp-novtk",
        "bd_warehouse",
        "build123d",
        "numpy",
        "ezdxf",
    ):
        try:
            out.append(f"{pkg}={version(pkg)}")
        except PackageNotFoundError:
            out.append(f"{pkg}=none")
    return ";".join(out)


@functools.cache
def _code_hash(modules: tuple[str, ...]) -> str:
    """Hash of the source of ``modules``, of this module, of :mod:`cad.occ.shape_io` (the
    BREP text the digests hash) and of :mod:`cad.tolerances` (the tolerances a derived value
    is computed to live there, not in the modules that use them)."""
    h = hashlib.sha256()
    for m in (__name__, "cad.occ.shape_io", "cad.tolerances", *modules):
        spec = importlib.util.find_spec(m)
        h.update(m.encode())
        h.update(Path(spec.origin).read_bytes())
    return h.hexdigest()[:16]


def _canonical(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {str(k): _canonical(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_canonical(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _canonical(obj.tolist())
    if isinstance(obj, (float, np.floating)):
        return repr(float(obj))
    if isinstance(obj, (np.integer, np.bool_)):
        return obj.item()
    if obj is None or isinstance(obj, (bool, int, str)):
        return obj
    raise TypeError(f"cannot key a derived-cache parameter of type {type(obj).__name__}")


def entry_path(kind: str, key: Any, code: tuple[str, ...] = ()) -> Path | None:
    """Cache file of ``kind`` for ``key`` (None when the cache is off)."""
    d = cache_dir()
    if d is None:
        return None
    text = json.dumps(
        [kind, _canonical(key), _versions(), _code_hash(tuple(code))],
        sort_keys=True,
        separators=(",", ":"),
    )
    name = hashlib.sha256(text.encode()).hexdigest()[:40]
    return d / name[:2] / (name + ".bin")  # 256 shards: an atomic write scans its folder


def _read(path: Path) -> bytes | None:
    try:  # a regular file of bounded size, or a miss (cad/io/guard.py)
        data = guard.read_bytes(path, "cache", "cache")
        want = guard.read_text(path.with_name(path.name + ".sha256"), "marker", "cache", "ascii").strip()
    except (FileRefused, OSError):
        return None
    if hashlib.sha256(data).hexdigest() != want:
        return None

    touch(path)  # recently used (cad.io.cache_limit prunes the oldest)
    return data


def _write(path: Path, data: bytes) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    write_bytes_atomic(path, data)
    write_text_atomic(
        path.with_name(path.name + ".sha256"), hashlib.sha256(data).hexdigest() + "\n"
    )


def cached(
    kind: str,
    key: Any,
    make: Callable[[], Any],
    *,
    encode: Callable[[Any], bytes],
    decode: Callable[[bytes], Any],
    code: tuple[str, ...] = (),
) -> Any:
    """``make()`` through the disk cache (module docstring); ``encode``/``decode`` turn the
    value into bytes and back (a decode error is a miss)."""
    path = entry_path(kind, key, code)
    if path is not None:
        data = _read(path)
        if data is not None:
            try:
                value = decode(data)
            except Exception:  # noqa: BLE001 - a damaged entry is a miss
                value = None
            if value is not None:
                STATS["hits"] += 1
                return value
    STATS["misses"] += 1
    value = make()

    if path is not None and cache_faults.writable():
        try:
            _write(path, encode(value))
        except Exception as exc:  # noqa: BLE001 - read-only or full disk: work without the cache
            cache_faults.write_failed("a derived entry", exc)
    return value


def cached_bytes(
    kind: str, key: Any, make: Callable[[], bytes], code: tuple[str, ...] = ()
) -> bytes:
    """Bytes (a file's content) through the cache."""
    return cached(kind, key, make, encode=bytes, decode=bytes, code=code)


def _enc_json(v) -> bytes:
    return json.dumps(v, sort_keys=True).encode()


def cached_json(kind: str, key: Any, make: Callable[[], Any], code: tuple[str, ...] = ()) -> Any:
    """A JSON value (floats round-trip exactly through ``json``) through the cache."""
    return cached(
        kind, key, make, encode=_enc_json, decode=lambda b: json.loads(b.decode()), code=code
    )


def _enc_arrays(arrays) -> bytes:
    buf = io.BytesIO()
    np.savez(buf, *arrays)
    return buf.getvalue()


def _dec_arrays(data: bytes):
    with np.load(io.BytesIO(data), allow_pickle=False) as z:
        return tuple(z[f"arr_{i}"] for i in range(len(z.files)))


def cached_arrays(
    kind: str, key: Any, make: Callable[[], tuple], code: tuple[str, ...] = ()
) -> tuple:
    """A tuple of numpy arrays through the cache (bit-exact round trip, no pickle)."""
    return cached(kind, key, make, encode=_enc_arrays, decode=_dec_arrays, code=code)
