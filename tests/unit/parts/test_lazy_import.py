"""cad.parts.lazy_import: build123d imported without scikit-learn, and nothing of the shim
left behind (the real sklearn imports normally; build123d's STL-to-B-rep clustering, the
only user of DBSCAN, still works and gives the same clusters as scikit-learn itself).

Each check runs in a fresh interpreter: the shim only acts on a first import.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap

import pytest


def _run(code: str, **env) -> dict:
    r = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)],
        capture_output=True,
        text=True,
        env={**os.environ, **env},
        timeout=120,
    )
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout.strip().splitlines()[-1])


def test_build123d_imports_without_sklearn_and_leaves_nothing_behind():
    out = _run(
        """
        import gc, json, sys
        from cad.parts.lazy_import import import_build123d, _SklearnDeferrer
        bd = import_build123d()
        import build123d.brep_from_stl as bfs
        res = {
            "same_module": bd is sys.modules["build123d"],
            "has_box": hasattr(bd, "Box"),
            "sklearn_loaded": sorted(m for m in sys.modules if m.split(".")[0] == "sklearn"),
            "finder_left": any(isinstance(f, _SklearnDeferrer) for f in sys.meta_path),
            "deferred": bfs.DBSCAN.__name__,
            "gc_enabled": gc.isenabled(),
        }
        import sklearn.cluster
        res["real_after"] = sklearn.cluster.DBSCAN.__module__
        res["real_file"] = sklearn.cluster.__file__
        print(json.dumps(res))
        """
    )
    assert out["same_module"] and out["has_box"]
    assert out["sklearn_loaded"] == []
    assert not out["finder_left"]
    assert out["deferred"] == "deferred_dbscan"
    assert out["gc_enabled"]
    assert out["real_after"] == "sklearn.cluster._dbscan"
    assert out["real_file"].endswith(os.path.join("sklearn", "cluster", "__init__.py"))


def test_deferred_dbscan_clusters_like_sklearn_in_build123d():
    """build123d's two DBSCAN users (points, cosine on unit vectors), first called through the
    stand-in, against scikit-learn's DBSCAN called directly and the obvious clusters."""
    out = _run(
        """
        import json
        import numpy as np
        from cad.parts.lazy_import import import_build123d
        import_build123d()
        import build123d.brep_from_stl as bfs
        from build123d import Vector
        rng = np.random.default_rng(7)
        a = rng.normal(0.0, 0.05, (20, 3))
        b = rng.normal(5.0, 0.05, (15, 3))
        pts = np.vstack([a, b]).tolist()
        masks = bfs._cluster_points(pts, eps=0.5, min_samples=3)
        rebound = bfs.DBSCAN.__module__
        from sklearn.cluster import DBSCAN
        ref = DBSCAN(eps=0.5, min_samples=3).fit(np.array(pts)).labels_
        dirs = [Vector(1, 0, 0)] * 4 + [Vector(0, 1, 0)] * 5 + [Vector(0.999, 0.01, 0)]
        vmasks = bfs._cluster_unit_vectors(dirs, eps=0.01, min_samples=2)
        print(json.dumps({
            "sizes": sorted(int(m.sum()) for m in masks),
            "ref_sizes": sorted(int((ref == k).sum()) for k in set(ref) if k != -1),
            "first_is_a": bool(masks[0][:20].all() and not masks[0][20:].any()),
            "rebound": rebound,
            "same_class": bfs.DBSCAN is DBSCAN,
            "vsizes": sorted(int(m.sum()) for m in vmasks),
        }))
        """
    )
    assert out["sizes"] == [15, 20] == out["ref_sizes"]
    assert out["first_is_a"]
    assert out["rebound"] == "sklearn.cluster._dbscan" and out["same_class"]
    assert out["vsizes"] == [4 + 1, 5]  # the near-x direction joins the x cluster


@pytest.mark.parametrize("env", [{"HAPTICAD_LAZY_SKLEARN": "0"}, {"PRELOAD": "1"}])
def test_no_shim_when_disabled_or_sklearn_already_loaded(env):
    out = _run(
        """
        import json, os, sys
        if os.environ.get("PRELOAD"):
            import sklearn.cluster
        from cad.parts.lazy_import import import_build123d
        import_build123d()
        import build123d.brep_from_stl as bfs
        import sklearn.cluster
        print(json.dumps({"real": bfs.DBSCAN is sklearn.cluster.DBSCAN}))
        """,
        **env,
    )
    assert out["real"]


def test_gc_state_is_restored_when_it_was_off():
    out = _run(
        """
        import gc, json
        gc.disable()
        from cad.parts.lazy_import import import_build123d
        import_build123d()
        print(json.dumps({"enabled": gc.isenabled(), "frozen": gc.get_freeze_count() > 0}))
        """
    )
    assert out == {"enabled": False, "frozen": True}


def test_routed_first_import_goes_through_the_shim_from_anywhere():
    """Inside ``routed_first_import`` a plain ``from build123d import ...`` (a part generator)
    and an explicit ``import_build123d()`` (the shape cache's miss path) both import build123d
    once, without scikit-learn, and leave no finder behind; nothing asks -> nothing imported."""
    out = _run(
        """
        import json, sys
        from cad.parts import lazy_import as li
        with li.routed_first_import():
            quiet = "build123d" in sys.modules
        with li.routed_first_import():
            from build123d import Box
            bd = li.import_build123d()
            import build123d
        print(json.dumps({
            "quiet": quiet,
            "same": bd is build123d is sys.modules["build123d"],
            "volume": Box(1, 2, 3).volume,
            "sklearn": sorted(m for m in sys.modules if m.split(".")[0] == "sklearn"),
            "left": [type(f).__name__ for f in sys.meta_path
                     if isinstance(f, (li._Build123dRouter, li._SklearnDeferrer))],
        }))
        """
    )
    assert out == {"quiet": False, "same": True, "volume": 6.0, "sklearn": [], "left": []}


def test_routed_first_import_when_the_shape_cache_misses(tmp_path):
    """The shape cache's miss path calls import_build123d() while the router is installed
    (it once deadlocked on the shim's lock)."""
    out = _run(
        """
        import json, sys
        from cad.parts import lazy_import as li
        from cad.parts.shape_cache import cached_shape
        def make():
            from build123d import Box
            return Box(1, 2, 3).wrapped
        with li.routed_first_import():
            s = cached_shape("test-routed", make)
        print(json.dumps({"null": s.IsNull(),
                          "sklearn": sorted(m for m in sys.modules if m.split(".")[0] == "sklearn")}))
        """,
        HAPTICAD_CACHE_DIR=str(tmp_path),
    )
    assert out == {"null": False, "sklearn": []}
