"""cad.io.derived_cache: what a build derives from its solids (meshes, tight boxes, common
volumes, FE compliances, part files) read back from disk equals what is computed afresh;
every input of the key matters; a damaged entry is a miss, never a wrong value."""

from __future__ import annotations

import numpy as np
import pytest

from cad.io import derived_cache


@pytest.fixture()
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("HAPTICAD_CACHE_DIR", str(tmp_path))
    return tmp_path / derived_cache.SCHEMA


def _plate():
    from build123d import Box, Cylinder, Pos

    return (Box(40, 20, 6) - Pos(-10, 0, 0) * Cylinder(4, 10)).solids()[0].wrapped


def _counts():
    return derived_cache.STATS["hits"], derived_cache.STATS["misses"]


def test_mesh_hit_is_the_fresh_mesh_and_a_damaged_entry_is_rebuilt(cache, monkeypatch):
    from cad.export.stl import mesh_shape

    shape = _plate()
    monkeypatch.setattr(derived_cache, "cache_dir", lambda: None)
    v0, f0 = mesh_shape(shape, 0.05, 0.5)  # computed, no cache
    monkeypatch.undo()
    monkeypatch.setenv("HAPTICAD_CACHE_DIR", str(cache.parent))
    h, m = _counts()
    v1, f1 = mesh_shape(shape, 0.05, 0.5)
    v2, f2 = mesh_shape(shape, 0.05, 0.5)
    assert _counts() == (h + 1, m + 1)
    for v, f in ((v1, f1), (v2, f2)):
        assert v.dtype == v0.dtype and f.dtype == f0.dtype
        assert np.array_equal(v, v0) and np.array_equal(f, f0)
    # another tolerance is another entry (a finer mesh has more triangles)
    v3, f3 = mesh_shape(shape, 0.01, 0.5)
    assert len(f3) > len(f0)
    # flip one byte of every entry: each is a miss and the value is recomputed
    for p in cache.glob("*/*.bin"):
        b = bytearray(p.read_bytes())
        b[len(b) // 2] ^= 0x01
        p.write_bytes(bytes(b))
    h, m = _counts()
    v4, f4 = mesh_shape(shape, 0.05, 0.5)
    assert _counts() == (h, m + 1)
    assert np.array_equal(v4, v0) and np.array_equal(f4, f0)


def test_digest_follows_geometry_and_placement(cache):
    from cad.export.shapes import placed

    a, b = _plate(), _plate()
    assert derived_cache.shape_digest(a) == derived_cache.shape_digest(b)  # same BREP
    T = np.eye(4)
    T[0, 3] = 1.0
    assert derived_cache.shape_digest(placed(a, T)) != derived_cache.shape_digest(a)
    # a placed shape's digest (registered from its source's) is the same for the same move
    assert derived_cache.shape_digest(placed(a, T)) == derived_cache.shape_digest(
        placed(a, T.copy())
    )
    T2 = T.copy()
    T2[0, 3] = 1.0 + 1e-12
    assert derived_cache.shape_digest(placed(a, T2)) != derived_cache.shape_digest(placed(a, T))


def test_shape_cache_reads_register_the_file_digest(cache, tmp_path):
    import hashlib

    from cad.parts.shape_cache import cached_shape

    s = cached_shape("test-derived-plate", _plate)
    (brep,) = (tmp_path / "shapes-v2").glob("*.brep")
    assert derived_cache.shape_digest(s) == hashlib.sha256(brep.read_bytes()).hexdigest()


@pytest.mark.parametrize("rot_deg", [0.0, 90.0, 180.0, 33.0])
def test_placed_tight_box_is_occt_box_of_the_placed_shape(cache, rot_deg):
    from cad.assembly.interference import placed_tight_box
    from cad.export.shapes import placed
    from cad.occ.bbox import tight_box

    shape = _plate()
    c, s = np.cos(np.radians(rot_deg)), np.sin(np.radians(rot_deg))
    if rot_deg in (90.0, 180.0):
        c, s = round(c), round(s)  # exact signed permutation
    T = np.array([[c, -s, 0, 5.0], [s, c, 0, -2.0], [0, 0, 1, 1.5], [0, 0, 0, 1]])
    want = tight_box(placed(shape, T))
    for _ in range(2):  # computed, then read back
        assert np.allclose(placed_tight_box(shape, T), want, rtol=0, atol=1e-9)


def test_same_body_check_same_result_with_and_without_cache(cache, monkeypatch):
    """A screw through a plate's hole only touches it; a pin in solid plate overlaps:
    the cached check finds exactly what the uncached one finds, twice."""
    from build123d import Box, Cylinder, Pos

    from cad.assembly.interference import same_body_check

    plate = (Box(40, 20, 6) - Pos(-10, 0, 0) * Cylinder(2, 10)).solids()[0].wrapped
    pin = Cylinder(2, 12).solids()[0].wrapped
    T_hole, T_solid = np.eye(4), np.eye(4)
    T_hole[0, 3], T_solid[0, 3] = -10.0, 10.0
    items = [
        ("plate", "ground", plate, np.eye(4)),
        ("pin_hole", "ground", pin, T_hole),
        ("pin_solid", "ground", pin, T_solid),
    ]
    runs = [same_body_check(items), same_body_check(items)]
    monkeypatch.setattr(derived_cache, "cache_dir", lambda: None)
    runs.append(same_body_check(items))
    for r in runs:
        assert [c["parts"] for c in r.collisions] == [["plate", "pin_solid"]]
        # pi r^2 times the plate thickness
        assert r.collisions[0]["overlap_volume_mm3"] == pytest.approx(np.pi * 4 * 6, rel=1e-6)
        assert r.n_box_overlaps == runs[2].n_box_overlaps


def test_fem_cantilever_cached_equals_computed(cache):
    from cad.structure import fem

    g = fem.BarGeometry(62.5, 20.0, 6.0, 14.0, 11.0)
    want = fem.cantilever(g, 70e9, 0.33, "y")
    h, m = _counts()
    assert fem.cached_cantilever(g, 70e9, 0.33, "y") == want
    assert fem.cached_cantilever(g, 70e9, 0.33, "y") == want
    assert _counts() == (h + 1, m + 1)
    assert fem.cached_cantilever(g, 70e9, 0.33, "z") != want  # direction is in the key


@pytest.mark.parametrize("dx", [50.0, 40.0, 35.0])  # 10 mm apart, touching, overlapping
def test_exact_pair_cached_equals_computed(cache, dx):
    from cad.assembly.interference import exact_distance_volume, exact_pair
    from cad.export.shapes import placed

    a, b = _plate(), _plate()
    derived_cache.shape_digest(a)  # known digests: placed copies get theirs cheaply
    derived_cache.shape_digest(b)
    T = np.eye(4)
    T[0, 3] = dx  # the plates are 40 mm long, centred
    sa, sb = placed(a, np.eye(4)), placed(b, T)
    want = exact_distance_volume(sa, sb)
    assert exact_pair(sa, sb) == want
    assert exact_pair(placed(a, np.eye(4)), placed(b, T.copy())) == want  # read back
    assert (want[0] > 9.9) == (dx == 50.0) and (want[1] > 1.0) == (dx == 35.0)
