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
Catalog solids (bd_warehouse bearings and fasteners) pass ``disk_key``: their disk key is
the library call and the library versions, not our source (an edit here does not rebuild
them).

**Deferred shapes** (what ``check``, ``fit`` and ``sweep`` use): inside
:func:`deferred_shapes`, a generator whose solid is not in this process yet returns a
:class:`DeferredShape` -- its cache key and how to make it -- instead of building or
reading it. :mod:`cad.parts.part_props` then finds the part's mass properties on disk by
that key and the solid is never needed: an evaluation of a design whose parts are all on
disk imports neither build123d nor OCP. A deferred shape becomes the real solid (memo,
disk, else built) on :meth:`DeferredShape.resolve`. Deferred shapes never leave the
inertia model; ``build`` and every export get real solids.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import hashlib
import json
import math
import threading
from collections import OrderedDict
from collections.abc import Callable
from pathlib import Path
from typing import Any

from cad.parts.lazy_import import import_build123d
from cad.parts.shape_cache import cached_shape, read_cached_shape

#: shapes kept in the in-process LRU (a four-bar has ~25 distinct parts per design)
MEMO_MAX = 512
#: PartsSpec fields that never change a solid (mass and inertia inputs, mesh and sweep settings)
NON_GEOMETRIC = ("bearing_mass_g", "motor_rotor_inertia_g_cm2", "stl_tolerance_mm",
                 "stl_angular_tolerance_deg", "interference_poses", "clearance_min_mm", "fidelity",
                 "encoder", "encoder_counts_per_rev")

_MEMO: OrderedDict[str, Any] = OrderedDict()
#: id(shape) -> (shape, disk key) of the solids in :data:`_MEMO` (their mass-property key)
_KEY_OF: dict[int, tuple[Any, str]] = {}
#: memo key -> DeferredShape handed out (one object per part, so identity caches work)
_DEFERRED: OrderedDict[str, DeferredShape] = OrderedDict()
STATS = {"memo_hits": 0, "misses": 0, "deferred": 0, "built": 0}
_STATE = threading.local()


@functools.cache
def _code_version() -> str:
    """Hash of the part scripts' source (cad/parts/*.py) and of cad/tolerances.py, which holds
    the part clearances (OPENING_MARGIN_MM, SEAT_MARGIN_MM, HOLE_MARGIN_MM)."""
    h = hashlib.sha256()
    here = Path(__file__).parent
    for p in [*sorted(here.glob("*.py")), here.parent / "tolerances.py"]:
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


class DeferredShape:
    """A part solid not made yet (module docstring): ``key`` is its disk-cache key (which
    also keys its mass properties); :meth:`resolve` returns the ``TopoDS_Shape``."""

    __slots__ = ("key", "_memo_key", "_make", "_shape", "_keep")

    def __init__(self, key: str, memo_key: str, make: Callable[[], Any], keep: bool = False):
        self.key, self._memo_key, self._make, self._shape = key, memo_key, make, None
        self._keep = keep  # catalog solid: shared by every design, worth writing to disk

    def resolve(self):
        """The real solid: from the memo, else the disk cache, else built (never deferred)."""
        if self._shape is None:
            with deferred_shapes(False):
                self._shape = _materialize(self._memo_key, self.key, self._make)
        return self._shape

    def solid_for_props(self):
        """The solid to integrate when its mass properties are not cached: the real one if it
        is in memory or in the disk cache, else built here and NOT kept (no BREP written, not
        in the memo): an evaluation needs only its mass properties (cached by the caller), and
        a later build still makes, writes and reads back its own solid, so exports keep
        coming from read-back geometry. Builds are deterministic: the same key gives the same
        solid, so the integrals are those of a fresh build. Catalog solids (bd_warehouse,
        shared by every design and slow to make) are kept as :meth:`resolve` keeps them."""
        if self._shape is not None or self._keep:
            return self.resolve()
        if self._memo_key in _MEMO:
            return _MEMO[self._memo_key]

        got = read_cached_shape(self.key)
        if got is not None:
            return got
        with deferred_shapes(False):
            return _build(self._make)

    def __repr__(self) -> str:
        return f"DeferredShape({self._memo_key[:60]!r})"


@contextlib.contextmanager
def deferred_shapes(on: bool = True):
    """Inside this block (this thread), part generators return :class:`DeferredShape` for
    solids not in memory (module docstring)."""
    was = getattr(_STATE, "deferred", False)
    _STATE.deferred = on
    try:
        yield
    finally:
        _STATE.deferred = was


def shape_key(shape) -> str | None:
    """The disk-cache key of a part solid (a :class:`DeferredShape` or a solid this module
    handed out), else None (a solid made elsewhere: a user handle, another family's part)."""
    if isinstance(shape, DeferredShape):
        return shape.key
    hit = _KEY_OF.get(id(shape))
    return hit[1] if hit is not None and hit[0] is shape else None


def _build(make: Callable[[], Any]):
    import_build123d()  # the first build123d import of a process goes through the shim
    STATS["built"] += 1
    return make()


def _materialize(memo_key: str, key: str, make: Callable[[], Any]):
    if memo_key in _MEMO:
        return _MEMO[memo_key]
    shape = cached_shape(key, lambda: _build(make))
    _MEMO[memo_key] = shape
    _KEY_OF[id(shape)] = (shape, key)
    while len(_MEMO) > MEMO_MAX:
        old = _MEMO.popitem(last=False)[1]
        _KEY_OF.pop(id(old), None)
    return shape


def cached_part(name: str, args: tuple, kwargs: dict, make: Callable[[], Any],
                disk_key: str | None = None):
    """The shape for ``name(*args, **kwargs)``: memo, else (deferred mode) a
    :class:`DeferredShape`, else disk cache, else ``make()``. ``disk_key``: the disk key of
    a catalog solid (default: ``part:<code version>:<name and arguments>``)."""
    key = f"{name}:{json.dumps(canonical([args, kwargs]), sort_keys=True, separators=(',', ':'))}"
    if key in _MEMO:
        _MEMO.move_to_end(key)
        STATS["memo_hits"] += 1
        return _MEMO[key]
    full = disk_key if disk_key is not None else f"part:{_code_version()}:{key}"
    if getattr(_STATE, "deferred", False):
        d = _DEFERRED.get(key)
        if d is None or d.key != full:
            d = _DEFERRED[key] = DeferredShape(full, key, make, keep=disk_key is not None)
            STATS["deferred"] += 1
        _DEFERRED.move_to_end(key)
        while len(_DEFERRED) > MEMO_MAX:
            _DEFERRED.popitem(last=False)
        return d
    STATS["misses"] += 1
    return _materialize(key, full, make)


def part_cached(fn: Callable | None = None, *, disk_key: Callable[..., str] | None = None):
    """Decorator: cache a part generator returning a ``TopoDS_Shape`` (module docstring).
    ``disk_key(*args, **kwargs)``: the disk key of a catalog solid (see :func:`cached_part`)."""

    def deco(f: Callable) -> Callable:
        @functools.wraps(f)
        def wrapper(*args, **kwargs):
            return cached_part(f"{f.__module__}.{f.__qualname__}", args, kwargs,
                               lambda: f(*args, **kwargs),
                               None if disk_key is None else disk_key(*args, **kwargs))

        wrapper.uncached = f
        return wrapper

    return deco if fn is None else deco(fn)


def clear_memo() -> None:
    """Forget the in-process shapes (tests, benchmarks of the cold path)."""
    _MEMO.clear()
    _KEY_OF.clear()
    _DEFERRED.clear()
