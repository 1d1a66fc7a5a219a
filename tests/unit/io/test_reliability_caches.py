"""Every cache is an optimization: a fault in it is a miss, said once, the work redone (issue 22 §3).

Reproducers of ``shared/cases/reliability/``: ``cache-on-full-disk-bad-cast`` (a real full
disk: a 1 MB tmpfs mounted in a user namespace; plus an in-process fault, OCCT's
``RuntimeError: std::bad_cast`` as the full disk gives it), ``wall-damaged-sim-cache-refused``
and ``cached-build-serves-incomplete-folder``; and ``cache-cap-zero-means-no-cap`` (§5).
References: the cache-off build's bytes, the box's closed-form volume, the files as first
written (read with ``pathlib``, not through the caches).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from cli_helpers import assert_one_line_error, hapticad, hapticad_json

from cad.design import bounds
from cad.io import cache_faults

ROOT = Path(__file__).resolve().parents[3]
HOEKEN = ROOT / "designs" / "hoeken.toml"
HC = [sys.executable, "-m", "cad"]


def _tree(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file()}


def _can_mount_tmpfs(tmp: Path) -> bool:
    if shutil.which("unshare") is None:
        return False
    (tmp / "probe").mkdir()
    r = subprocess.run(["unshare", "-rm", "sh", "-c", f"mount -t tmpfs -o size=64k tmpfs {tmp / 'probe'}"],
                       capture_output=True, timeout=30, check=False)
    return r.returncode == 0


BUILD = ["build", str(HOEKEN), "--fidelity", "preview", "--formats", "step"]


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """One cold build with the cache on (its own cache folder): the bytes every build here
    must give (``tests/unit/parts/test_shape_cache.py`` holds cache on == cache off)."""
    root = tmp_path_factory.mktemp("reference")
    env = {**os.environ, "PYTHONPATH": str(ROOT), "HAPTICAD_CACHE_DIR": str(root / "cache")}
    r = subprocess.run([*HC, *BUILD, "--out", str(root / "o")], env=env, capture_output=True,
                       text=True, timeout=600, check=False)
    assert r.returncode == 0, r.stderr
    return root / "o", root / "cache"


def test_build_on_a_full_disk_carries_on_without_the_cache_said_once(tmp_path, reference):
    """A real full disk: the cache folder on a 1 MB tmpfs (``unshare -rm``: a private mount
    namespace, no root needed where user namespaces are allowed). The build exits 0, says
    once that it works without the cache, and its files are the reference bytes."""
    if not _can_mount_tmpfs(tmp_path):
        pytest.skip("no unprivileged tmpfs mount here (unshare -rm refused); the in-process "
                    "fault tests below still run")
    full = tmp_path / "full"
    full.mkdir()
    env = {**os.environ, "PYTHONPATH": str(ROOT), "HAPTICAD_CACHE_DIR": str(full / "c")}
    cmd = " ".join([f"mount -t tmpfs -o size=1m tmpfs {full} &&", "exec",
                    *(f"'{a}'" for a in [*HC, *BUILD, "--out", str(tmp_path / "o")])])
    r = subprocess.run(["unshare", "-rm", "sh", "-c", cmd], env=env, capture_output=True,
                       text=True, timeout=600, check=False)
    assert r.returncode == 0, r.stderr
    assert "Traceback" not in r.stderr
    said = [ln for ln in r.stderr.splitlines() if "works without the cache" in ln]
    assert len(said) == 1 and said[0].startswith("hapticad: warning: cache "), r.stderr
    got, want = _tree(tmp_path / "o"), _tree(reference[0])
    assert "assembly.step" in got and got.keys() == want.keys()
    assert [k for k in want if got[k] != want[k]] == []


@pytest.fixture
def fresh(tmp_path, monkeypatch):
    monkeypatch.setenv("HAPTICAD_CACHE_DIR", str(tmp_path / "cache"))
    bounds.reset()
    cache_faults.reset()
    yield tmp_path / "cache"
    cache_faults.reset()
    bounds.reset()


def test_a_failed_shape_write_is_a_miss_said_once_and_stops_cache_writes(fresh, monkeypatch):
    """OCCT's BREP writer on a full disk raises ``RuntimeError: std::bad_cast`` (seen in the
    reproducer): the shape is still handed out, one warning names the cache, and no later
    entry (derived value) is attempted."""
    from OCP.BRepGProp import BRepGProp
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox
    from OCP.GProp import GProp_GProps

    from cad.io import derived_cache
    from cad.parts import shape_cache

    def full_disk(shape, path):
        raise RuntimeError("std::bad_cast")

    monkeypatch.setattr(shape_cache, "_write", full_disk)
    shape = shape_cache.cached_shape("full-disk-box", lambda: BRepPrimAPI_MakeBox(10.0, 20.0, 30.0).Shape())
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, props)
    assert abs(props.Mass() - 6000.0) < 1e-9  # 10 x 20 x 30 mm, closed form
    assert not cache_faults.writable()
    assert bounds.collected() == [w for w in bounds.collected() if "works without the cache" in w]
    assert len(bounds.collected()) == 1 and "std::bad_cast" in bounds.collected()[0]
    assert str(fresh) in bounds.collected()[0]
    made = []
    value = derived_cache.cached_bytes("test-kind", ["k"], lambda: made.append(1) or b"abc")
    assert value == b"abc" and made == [1]
    assert not (fresh / derived_cache.SCHEMA).exists()  # no write attempted after the fault
    shape_cache.cached_shape("full-disk-box-2", lambda: BRepPrimAPI_MakeBox(1.0, 2.0, 3.0).Shape())
    assert len(bounds.collected()) == 1  # said once


def test_a_fault_in_a_forked_build_stage_stops_the_parent_writing_too(fresh, capfd):
    """The build stages run in forked children: the fault flag is shared with them (and back);
    the child says it on stderr itself (its warnings list dies with it)."""
    from cad.pipeline import forked

    def stage():
        cache_faults.write_failed("a derived entry", OSError(28, "No space left on device"))
        return cache_faults.writable()

    assert forked.start(stage, "fault").result() is False
    assert not cache_faults.writable()  # the parent sees the child's fault
    if forked.fork_enabled():
        err = capfd.readouterr().err
        assert err.count("works without the cache") == 1 and "No space left on device" in err
    before = bounds.collected()
    cache_faults.write_failed("a shape entry", OSError(28, "No space left on device"))
    assert bounds.collected() == before  # said once (by the child when forked)


def test_damaged_saved_simulator_model_is_rebuilt(fresh):
    """``wall``'s device model in ``<cache>/sim/<name>/``, truncated to 200 bytes (the
    reproducer): a miss -- removed, rebuilt to the bytes first written, said once."""
    from cad.design import load_design
    from cad.sim.device import device_build

    d = load_design(HOEKEN)
    folder = device_build(d)
    xml = folder / f"{d.name}.xml"
    good = xml.read_bytes()
    assert folder == fresh / "sim" / d.name and len(good) > 200
    xml.write_bytes(good[:200])
    bounds.reset()
    assert device_build(d) == folder
    assert xml.read_bytes() == good
    assert len(bounds.collected()) == 1 and "was damaged" in bounds.collected()[0]


def test_a_part_file_deleted_with_its_manifest_row_is_rebuilt(tmp_path, monkeypatch, reference):
    """The reproducer: a part STEP and its ``manifest.json`` row removed; the next build is not
    "cached", and the file comes back with its first bytes."""
    out = tmp_path / "o"
    shutil.copytree(reference[0], out)
    monkeypatch.setenv("HAPTICAD_CACHE_DIR", str(reference[1]))  # warm: the rebuild is cheap
    args = (*BUILD, "--out", str(out))
    assert hapticad_json(*args)["cached"] is True  # untouched: up to date
    name = sorted(p.relative_to(out).as_posix() for p in (out / "parts").glob("*.step"))[0]
    good = (out / name).read_bytes()
    (out / name).unlink()
    man = json.loads((out / "manifest.json").read_text())
    man["files"] = [f for f in man["files"] if f["path"] != name]
    (out / "manifest.json").write_text(json.dumps(man))
    assert hapticad_json(*args)["cached"] is False
    assert (out / name).read_bytes() == good


@pytest.mark.parametrize("args", [("cache",), ("cache", "--clear")])
def test_cache_cap_zero_is_refused_as_the_readme_says(fresh, monkeypatch, args):
    """docs/reliability.md "Size cap": anything that is not a positive number (or ``off``) is refused;
    ``0`` used to mean "no cap". Nothing is removed by a refused ``--clear``."""
    entry = fresh / "derived-v2" / "ab" / ("ab" + "0" * 38 + ".bin")
    entry.parent.mkdir(parents=True)
    entry.write_bytes(b"x")
    monkeypatch.setenv("HAPTICAD_CACHE_MAX_MB", "0")
    code, _, err = hapticad(*args)
    assert_one_line_error(code, err, "HAPTICAD_CACHE_MAX_MB", "'0'", "positive")
    assert entry.read_bytes() == b"x"
