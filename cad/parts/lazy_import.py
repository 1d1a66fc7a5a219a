"""``import build123d`` without paying for scikit-learn: one deliberate, documented shim.

Why: build123d 0.12's ``build123d/__init__.py`` imports ``build123d.brep_from_stl`` (STL
to B-rep conversion), whose top line ``from sklearn.cluster import DBSCAN`` imports
scikit-learn and, through it, ``scipy.stats``: ~0.9 s of a cold ``hapticad build``
(measured, ``python -X importtime``). hapticad never converts an STL into a B-rep, so
that import buys nothing on our paths.

What :func:`import_build123d` does: it imports build123d with a meta-path finder in
place that answers ``import sklearn`` / ``import sklearn.cluster`` ONLY when all of these
hold: the finder is active (only inside this function), the importing code is the body
of the module ``build123d.brep_from_stl``, and the real scikit-learn is not imported yet.
It then hands out placeholder modules whose ``DBSCAN`` is :func:`deferred_dbscan`; right
after the import the finder is removed and the placeholders are dropped from
``sys.modules``. Afterwards:

* ``import sklearn.cluster`` anywhere imports the real package (nothing of ours is left
  in ``sys.modules`` or on ``sys.meta_path``);
* ``build123d.brep_from_stl.DBSCAN(...)`` imports the real ``sklearn.cluster.DBSCAN`` on
  its first call, rebinds the module attribute to it, and returns a real estimator, so
  build123d's STL conversion still works.

When scikit-learn is already imported, or build123d is, nothing is shimmed (plain
import). Set ``HAPTICAD_LAZY_SKLEARN=0`` to disable the shim.

Garbage collector: importing build123d creates ~300k objects tracked by Python's cyclic
GC (modules, classes, functions, pybind11 types) that live until the process exits. The
import runs with the collector paused (it otherwise runs ~4 full collections in the
middle of the import, ~0.4 s measured) and is followed by :func:`gc.freeze`, which moves
those objects to the permanent generation (Python docs, ``gc.freeze``): every later full
collection skips them, and so does the interpreter's shutdown (0.74 s -> 0.06 s after
``import build123d``, measured). Reference counting still frees everything as usual;
only garbage *cycles* that already exist at that moment stay in memory (a few dozen
objects of the import itself).

Route every first ``import build123d`` of a build through :func:`import_build123d`, or
run the code that may import it inside :func:`routed_first_import`: a build whose solids
all come from the shape cache then never imports build123d (nor scipy.optimize, which it
pulls in), ~1 s of CPU less; the first part generator that does need it gets it through
:func:`import_build123d` (scikit-learn deferred) whichever module it imports it from.
"""

from __future__ import annotations

import contextlib
import gc
import importlib.abc
import importlib.machinery
import os
import sys
import threading

#: Marker attribute of the placeholder modules.
_PLACEHOLDER = "__hapticad_placeholder__"
#: Module whose top-level import is deferred.
_IMPORTER = "build123d.brep_from_stl"
_NAMES = ("sklearn", "sklearn.cluster")
_lock = threading.Lock()


def deferred_dbscan(*args, **kwargs):
    """Stand-in for ``sklearn.cluster.DBSCAN`` inside ``build123d.brep_from_stl``.

    Imports the real class on first use, rebinds ``build123d.brep_from_stl.DBSCAN`` to it,
    and returns ``DBSCAN(*args, **kwargs)`` (a real scikit-learn estimator).
    """
    from sklearn.cluster import DBSCAN

    mod = sys.modules.get(_IMPORTER)
    if mod is not None and getattr(mod, "DBSCAN", None) is deferred_dbscan:
        mod.DBSCAN = DBSCAN
    return DBSCAN(*args, **kwargs)


def _imported_by_brep_from_stl() -> bool:
    """True when the import being resolved runs inside the body of ``build123d.brep_from_stl``."""
    f = sys._getframe(1)
    while f is not None:
        if f.f_code.co_name == "<module>" and f.f_globals.get("__name__") == _IMPORTER:
            return True
        f = f.f_back
    return False


def _is_placeholder(mod) -> bool:
    return mod is not None and getattr(mod, _PLACEHOLDER, False) is True


class _PlaceholderLoader(importlib.abc.Loader):
    def create_module(self, spec):
        return None  # default module creation

    def exec_module(self, module) -> None:
        setattr(module, _PLACEHOLDER, True)
        module.__doc__ = "hapticad placeholder (cad.parts.lazy_import); not scikit-learn"
        if module.__name__ == "sklearn.cluster":
            module.DBSCAN = deferred_dbscan


class _SklearnDeferrer(importlib.abc.MetaPathFinder):
    """Serves placeholder ``sklearn`` / ``sklearn.cluster`` to ``build123d.brep_from_stl`` only."""

    def find_spec(self, fullname, path=None, target=None):
        if fullname not in _NAMES or not _imported_by_brep_from_stl():
            return None
        if fullname == "sklearn.cluster" and not _is_placeholder(sys.modules.get("sklearn")):
            return None  # the real package is there: import the real subpackage
        return importlib.machinery.ModuleSpec(fullname, _PlaceholderLoader(), is_package=True)


def _enabled() -> bool:
    return os.environ.get("HAPTICAD_LAZY_SKLEARN", "1").strip().lower() not in ("0", "off", "no")


def import_build123d():
    """Import and return the ``build123d`` module, deferring scikit-learn (module docstring)."""
    mod = sys.modules.get("build123d")
    if mod is not None:
        return mod
    for f in list(sys.meta_path):  # this call is the first import: no router must answer it
        if isinstance(f, _Build123dRouter):
            with contextlib.suppress(ValueError):
                sys.meta_path.remove(f)
    gc_was_enabled = gc.isenabled()
    gc.disable()
    try:
        if not _enabled() or "sklearn" in sys.modules or _IMPORTER in sys.modules:
            import build123d
        else:
            with _lock:
                finder = _SklearnDeferrer()
                sys.meta_path.insert(0, finder)
                try:
                    import build123d
                finally:
                    with contextlib.suppress(ValueError):
                        sys.meta_path.remove(finder)
                    for name in reversed(_NAMES):
                        if _is_placeholder(sys.modules.get(name)):
                            del sys.modules[name]
    finally:
        if gc_was_enabled:
            gc.enable()
    gc.freeze()
    return build123d


class _ExistingModule(importlib.abc.Loader):
    """Loader handing the import system a module that is already imported."""

    def __init__(self, module):
        self._module = module

    def create_module(self, spec):
        return self._module

    def exec_module(self, module) -> None:
        return None


class _Build123dRouter(importlib.abc.MetaPathFinder):
    """Answers the first ``import build123d`` by :func:`import_build123d`, then steps aside."""

    def find_spec(self, fullname, path=None, target=None):
        if fullname != "build123d":
            return None
        with contextlib.suppress(ValueError):
            sys.meta_path.remove(self)
        mod = import_build123d()
        return importlib.machinery.ModuleSpec(fullname, _ExistingModule(mod), origin=mod.__file__)


@contextlib.contextmanager
def routed_first_import():
    """Inside this block a first ``import build123d`` from anywhere (``from build123d import
    Cylinder`` in a part generator) goes through :func:`import_build123d`; nothing is
    imported if nothing asks for build123d. The finder is removed on leaving."""
    if "build123d" in sys.modules or not _enabled():
        if not _enabled():
            import_build123d()  # the shim is off: import up front as before
        yield
        return
    router = _Build123dRouter()
    sys.meta_path.insert(0, router)
    try:
        yield
    finally:
        with contextlib.suppress(ValueError):
            sys.meta_path.remove(router)
