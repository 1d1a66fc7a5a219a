"""A damaged shape-cache entry is a miss, never a hang or an error (issue 11 item 5).

Each damage of the trial (truncated to 95 % and 99.9 %, one changed digit) plus a flipped
bit, a missing or wrong ``.sha256`` and an empty file: the next call makes the shape again
(its volume is the box's closed form), rewrites the entry (hash matches the bytes again) and
the call after that is a hit. Run in a child process with a time limit, so a regression
(OCCT parsing a truncated file) fails instead of hanging the suite.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]

CHILD = r"""
import hashlib, json, sys
from pathlib import Path
from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox
from OCP.GProp import GProp_GProps
from OCP.BRepGProp import BRepGProp
from cad.parts import shape_cache

made = {"n": 0}
def make():
    made["n"] += 1
    # a box with a rounded-off digit in its size: the BREP text holds many digits to damage
    return BRepPrimAPI_MakeBox(10.123456789, 20.0, 30.0).Shape()

def volume(s):
    p = GProp_GProps(); BRepGProp.VolumeProperties_s(s, p); return p.Mass()

def entry():
    files = sorted(shape_cache.cache_dir().glob("*.brep"))
    assert len(files) == 1, files
    return files[0]

def damage(kind, p):
    data = p.read_bytes(); h = Path(str(p) + ".sha256")
    if kind == "truncate95": p.write_bytes(data[: int(len(data) * 0.95)])
    elif kind == "truncate999": p.write_bytes(data[: int(len(data) * 0.999)])
    elif kind == "digit":
        i = data.index(b"10.123456789"); p.write_bytes(data[:i] + b"19" + data[i + 2:])
    elif kind == "bitflip":
        b = bytearray(data); b[len(b) // 2] ^= 0x04; p.write_bytes(bytes(b))
    elif kind == "no-hash": h.unlink()
    elif kind == "wrong-hash": h.write_text("0" * 64 + "\n")
    elif kind == "empty": p.write_bytes(b"")

out = {}
shape_cache.cached_shape("test-box", make)
good = entry().read_bytes()
for kind in sys.argv[1:]:
    made["n"] = 0
    damage(kind, entry())
    v1 = volume(shape_cache.cached_shape("test-box", make))
    n_after_miss = made["n"]
    v2 = volume(shape_cache.cached_shape("test-box", make))
    p = entry()
    out[kind] = {
        "volumes": [v1, v2], "made": [n_after_miss, made["n"]],
        "rewritten": p.read_bytes() == good,
        "hash_ok": hashlib.sha256(p.read_bytes()).hexdigest()
        == Path(str(p) + ".sha256").read_text().strip(),
    }
print(json.dumps(out))
"""

KINDS = ["truncate95", "truncate999", "digit", "bitflip", "no-hash", "wrong-hash", "empty"]


def test_every_damaged_entry_is_a_miss_and_rewritten(tmp_path):
    env = {**os.environ, "HAPTICAD_CACHE_DIR": str(tmp_path / "cache"), "PYTHONPATH": str(ROOT)}
    r = subprocess.run([sys.executable, "-c", CHILD, *KINDS], env=env, capture_output=True,
                       text=True, timeout=120, check=False)
    assert r.returncode == 0, r.stderr
    res = json.loads(r.stdout)
    box = 10.123456789 * 20.0 * 30.0  # closed form, mm^3
    for kind in KINDS:
        got = res[kind]
        assert abs(got["volumes"][0] - box) < 1e-9 * box, (kind, got)
        assert abs(got["volumes"][1] - box) < 1e-9 * box, (kind, got)
        assert got["made"] == [1, 1], (kind, got)  # made again once, then a hit
        assert got["rewritten"] and got["hash_ok"], (kind, got)


def test_exports_are_the_same_bytes_with_the_cache_on_and_off(tmp_path):
    """The shape cache hands out solids read back from BREP; with the cache off (or
    unwritable) the solids are round-tripped the same way, so STEP (direction signs) and
    STL (triangulation) bytes do not depend on the cache (found by a new-user test: with
    HAPTICAD_CACHE_DIR=off, DIRECTION('',(1.,0.,-0.)) and a 1.7 % larger base-plate STL)."""
    design = ROOT / "designs" / "hoeken.toml"
    runs = {}
    for name, cache in (("off", "off"), ("on", str(tmp_path / "cache"))):
        out = tmp_path / name
        env = {**os.environ, "HAPTICAD_CACHE_DIR": cache, "PYTHONPATH": str(ROOT)}
        r = subprocess.run(
            [sys.executable, "-m", "cad", "build", str(design), "--out", str(out),
             "--fidelity", "preview", "--formats", "step,stl"],
            capture_output=True, text=True, env=env, timeout=600,
        )
        assert r.returncode == 0, r.stderr
        runs[name] = {p.relative_to(out).as_posix(): p.read_bytes()
                      for p in sorted(out.rglob("*")) if p.suffix in (".step", ".stl")}
    assert len(runs["off"]) > 10 and "assembly.step" in runs["off"]
    assert runs["off"].keys() == runs["on"].keys()
    differ = [k for k in runs["off"] if runs["off"][k] != runs["on"][k]]
    assert differ == []
