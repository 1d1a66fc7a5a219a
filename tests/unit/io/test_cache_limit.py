"""The disk caches are capped: least recently used entries go first, nothing else is touched.

References: file sizes and modification times read with ``os`` in the test (not through
:mod:`cad.io.cache_limit`); the entries are written by the caches' own writers or laid out
by hand with the caches' naming (hex digest + ``.sha256``).
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

import pytest
from cli_helpers import assert_one_line_error, hapticad, hapticad_json

from cad.io import cache_limit


def _entry(folder: Path, n: int, size: int, mtime: float) -> list[Path]:
    """A derived-cache style entry ``<40 hex>.bin`` of ``size`` bytes + its ``.sha256``."""
    name = hashlib.sha1(f"{folder}{n}".encode()).hexdigest()
    p = folder / name[:2] / f"{name}.bin"
    p.parent.mkdir(parents=True, exist_ok=True)
    data = bytes(size)
    p.write_bytes(data)
    h = p.with_name(p.name + ".sha256")
    h.write_text(hashlib.sha256(data).hexdigest() + "\n")
    for q in (p, h):
        os.utime(q, (mtime, mtime))
    return [p, h]


def _on_disk(root: Path) -> int:
    return sum((Path(a) / f).stat().st_size for a, _, fs in os.walk(root) for f in fs)


@pytest.fixture
def cache(tmp_path, monkeypatch):
    root = tmp_path / "cache"
    monkeypatch.setenv("HAPTICAD_CACHE_DIR", str(root))
    old = [_entry(root / "derived-v1", i, 1000, 5_000.0 + i) for i in range(3)]
    new = [_entry(root / "derived-v2", i, 1000, 10_000.0 + i) for i in range(10)]
    mine = root / "derived-v2" / "my-notes.txt"  # a user's file in the cache folder
    mine.write_text("keep me")
    return root, old, new, mine


def test_prune_removes_old_schemas_then_least_recently_used(cache):
    root, old, new, mine = cache
    entry = 1000 + 65  # value + its sha256 line (64 hex + newline)
    n, freed = cache_limit.prune(root, cap_bytes=10 * entry)  # 13 entries > 10: down to 8
    assert (n, freed) == (5, 5 * entry)
    assert not any(p.exists() for e in old for p in e)  # older schema first
    assert not any(p.exists() for e in new[:2] for p in e)  # then the two least recently used
    assert all(p.exists() for e in new[2:] for p in e) and mine.read_text() == "keep me"
    assert _on_disk(root) - len("keep me") == 8 * entry <= 0.8 * 10 * entry
    assert cache_limit.prune(root, cap_bytes=10 * entry) == (0, 0)  # under the cap: nothing


def test_a_hit_makes_an_entry_recent(cache, monkeypatch):
    """Reading an entry through the derived cache refreshes its mtime, so pruning keeps it."""
    from cad.io import derived_cache

    root = cache[0]
    derived_cache.cached_bytes("t", "k", lambda: b"x" * 2000)
    (p,) = [Path(a) / f for a, _, fs in os.walk(root / "derived-v2") for f in fs
            if f.endswith(".bin") and os.path.getsize(Path(a) / f) == 2000]
    os.utime(p, (1.0, 1.0))
    assert derived_cache.cached_bytes("t", "k", lambda: pytest.fail("a miss")) == b"x" * 2000
    assert p.stat().st_mtime > 1e9  # touched now
    cache_limit.prune(root, cap_bytes=4000)
    assert p.exists()  # the most recently used entry survives


def test_cache_command_reports_and_clears_only_hapticad_entries(cache):
    root, old, new, mine = cache
    doc = hapticad_json("cache")
    assert doc["cache_dir"] == str(root) and doc["max_MB"] == cache_limit.DEFAULT_MAX_MB
    assert doc["total_MB"] == pytest.approx((_on_disk(root) - len("keep me")) / 1e6)
    assert doc["folders"]["derived-v1"]["entries"] == 3 and doc["folders"]["derived-v2"]["entries"] == 10
    doc = hapticad_json("cache", "--clear")
    assert doc["removed"]["entries"] == 13 and doc["total_MB"] == 0.0
    assert mine.read_text() == "keep me" and _on_disk(root) == len("keep me")


@pytest.mark.parametrize("bad", ["abc", "-5", "inf", "nan"])
def test_bad_cap_is_one_line_and_builds_nothing(tmp_path, monkeypatch, bad):
    monkeypatch.setenv("HAPTICAD_CACHE_MAX_MB", bad)
    design = Path(__file__).resolve().parents[3] / "designs" / "hoeken.toml"
    code, _, err = hapticad("build", str(design), "--out", str(tmp_path / "o"))
    assert_one_line_error(code, err, "HAPTICAD_CACHE_MAX_MB", repr(bad))
    assert not (tmp_path / "o").exists()


def test_prune_after_build_uses_the_cap_once(cache, monkeypatch):
    root = cache[0]
    monkeypatch.setattr(cache_limit, "_pruned", False)
    monkeypatch.setenv("HAPTICAD_CACHE_MAX_MB", "0.005")  # 5000 bytes: 13 kB of entries
    cache_limit.prune_after_build()
    assert _on_disk(root) - len("keep me") <= 4000
    _entry(root / "derived-v2", 99, 9000, 20_000.0)
    cache_limit.prune_after_build()  # once per process: left for the next command
    assert _on_disk(root) - len("keep me") > 9000
