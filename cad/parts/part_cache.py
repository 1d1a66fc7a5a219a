"""Cache of our own part solids by their geometric parameters (in-process, then on disk).

``check``, ``fit`` and ``sweep`` rebuild a design's parts at every evaluation, and most
parts do not change between two evaluations: a bar thickness change does not touch the
bearings, the motor or its mount, and a material change touches no shape at all. Every
part generator decorated with :func:`part_cached` is therefore looked up by a key made
of its arguments:

* in this process first (a bounded LRU of :data:`MEMO_MAX` shapes; the same object is
  returned, and OCCT shapes are never modified in place by hapticad), then
* on disk through :func:`cad.parts.shape_cache.cached_shape` (the BREP read back, so a
  fresh process reuses the solids of earlier runs; ``HAPTICAD_CACHE_DIR=off`` disables it).

The key is the generator's name, its arguments in canonical form and a hash of the source
of ``cad/parts`` (a code change is a cache miss). Of a :class:`cad.design.parts.PartsSpec`
argument only the fields that can change a shape are used: materials and catalog
masses/inertias (:data:`NON_GEOMETRIC`) never do, so a material change reuses every solid.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import math
from collections import OrderedDict
from collections.abc import Callable
from pathlib import Path
from typing import Any

#: shapes kept in the in-process LRU (a four-bar has ~25 distinct parts per design)
MEMO_MAX = 512
#: PartsSpec fields that never change a solid (mass and inertia inputs, mesh and sweep settings)
NON_GEOMETRIC = ("bearing_mass_g", "motor_rotor_inertia_g_cm2", "stl_tolerance_mm",
                 "stl_angular_tolerance_deg", "interference_poses", "clearance_min_mm", "fidelity")

_MEMO: OrderedDict[str, Any] = OrderedDict()
STATS = {"memo_hits": 0, "misses": 0}


@functools.cache
def _code_version() -> str:
    h = hashlib.sha256()
    for p in sorted(Path(__file__).parent.glob("*.py")):
        h.update(p.name.encode())
        h.update(p.read_bytes())
    return h.hexdigest()[:16]


def canonical(obj: Any) -> Any:
    """A JSON-able, exact form of a generator argument (floats by repr, arrays as lists)."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        parts = type(obj).__name__ == "PartsSpec"
        return {"__type__": type(obj).__name__,
                **{f.name: canonical(getattr(obj, f.name)) for f in dataclasses.fields(obj)
                   if not (parts and (f.name in NON_GEOMETRIC or f.name.endswith("_material")))}}
    if isinstance(obj, dict):
        return {str(k): canonical(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [canonical(v) for v in obj]
    if hasattr(obj, "tolist"):  # numpy arrays and scalars
        return canonical(obj.tolist())
    if isinstance(obj, float):
        return repr(obj) if math.isfinite(obj) else str(obj)
    if obj is None or isinstance(obj, (bool, int, str)):
        return obj
    raise TypeError(f"cannot key a part argument of type {type(obj).__name__}")


def cached_part(name: str, args: tuple, kwargs: dict, make: Callable[[], Any]):
    """The shape for ``name(*args, **kwargs)``: memo, else disk cache, else ``make()``."""
    from cad.parts.shape_cache import cached_shape

    key = f"{name}:{json.dumps(canonical([args, kwargs]), sort_keys=True, separators=(',', ':'))}"
    if key in _MEMO:
        _MEMO.move_to_end(key)
        STATS["memo_hits"] += 1
        return _MEMO[key]
    STATS["misses"] += 1
    shape = cached_shape(f"part:{_code_version()}:{key}", make)
    _MEMO[key] = shape
    while len(_MEMO) > MEMO_MAX:
        _MEMO.popitem(last=False)
    return shape


def part_cached(fn: Callable) -> Callable:
    """Decorator: cache a part generator returning a ``TopoDS_Shape`` (module docstring)."""

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        return cached_part(f"{fn.__module__}.{fn.__qualname__}", args, kwargs,
                           lambda: fn(*args, **kwargs))

    wrapper.uncached = fn
    return wrapper


def clear_memo() -> None:
    """Forget the in-process shapes (tests, benchmarks of the cold path)."""
    _MEMO.clear()
