"""Mass properties cached by part key (cad.parts.part_props): a second process evaluates a
design from the disk cache alone -- no solid, no build123d, no OCP -- and gets exactly the
values of the first process; a damaged entry is a miss, recomputed to the same values."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from cad.design import parse_design
from cad.design.fields import load_toml
from cad.studies.sweep.spec import apply

ROOT = Path(__file__).resolve().parents[3]
HOEKEN = ROOT / "designs" / "hoeken.toml"

_SECOND = r"""
import json, sys
from cad.families.fourbar.inertia import target_values
from cad.design import parse_design
from cad.design.fields import load_toml
from cad.parts import part_cache, part_props
from cad.studies.sweep.spec import apply
raw = apply(load_toml(sys.argv[1]), json.loads(sys.argv[2]))
values, report = target_values(parse_design(raw, sys.argv[1]), "inertia", False)
print(json.dumps({"values": values, "links": report["links"],
                  "cad_modules": sorted(m for m in sys.modules if m.split(".")[0] in ("build123d", "OCP", "bd_warehouse")),
                  "built": part_cache.STATS["built"], "integrated": part_props.STATS["integrated"]}))
"""

CHANGE = {"parts.bar_thickness_mm": 5.55}


def _fresh(monkeypatch, cache: Path):
    from cad.massprops import occt
    from cad.parts import bars, part_cache, part_props

    monkeypatch.setenv("HAPTICAD_CACHE_DIR", str(cache))
    part_cache.clear_memo()
    part_props.clear_memo()
    bars._PROFILES.clear()
    occt._PROPS_MEMO.clear()


def _evaluate():
    from cad.families.fourbar.inertia import target_values

    return target_values(parse_design(apply(load_toml(HOEKEN), CHANGE), str(HOEKEN)), "inertia", False)


@pytest.fixture(scope="module")
def cold(tmp_path_factory):
    """(cache dir, values, report, {disk key: DeferredShape}) of a first evaluation into an
    empty cache."""
    from cad.parts import part_cache

    cache = tmp_path_factory.mktemp("parts-cache")
    with pytest.MonkeyPatch.context() as mp:
        _fresh(mp, cache)
        values, report = _evaluate()
        deferred = {d.key: d for d in part_cache._DEFERRED.values()}
    return cache, values, report, deferred


def _copy(cold, monkeypatch, tmp_path: Path) -> Path:
    import shutil

    shutil.copytree(cold[0], tmp_path / "c")
    _fresh(monkeypatch, tmp_path / "c")
    return tmp_path / "c"


def test_second_process_reads_exact_mass_properties_without_cad(cold, monkeypatch, tmp_path):
    _copy(cold, monkeypatch, tmp_path)
    values, report = cold[1], cold[2]
    r = subprocess.run([sys.executable, "-c", _SECOND, str(HOEKEN), json.dumps(CHANGE)],
                       capture_output=True, text=True, cwd=ROOT, env={**os.environ},
                       timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    second = json.loads(r.stdout.strip().splitlines()[-1])
    assert second["cad_modules"] == []  # no build123d, OCP or bd_warehouse imported
    assert second["built"] == 0 and second["integrated"] == 0
    assert second["values"] == values  # bit-identical (floats through repr)
    assert second["links"] == json.loads(json.dumps(report["links"]))


def test_a_damaged_entry_is_a_miss_and_gives_the_same_values(cold, monkeypatch, tmp_path):
    from cad.parts import part_props

    cache, values = _copy(cold, monkeypatch, tmp_path), cold[1]
    entries = sorted((cache / "shapes-v2" / part_props.PROPS_DIR).glob("*/*.json"))
    assert len(entries) >= 10  # one per integrated part kind
    doc = json.loads(entries[0].read_text())
    doc["payload"]["volume_mm3"] *= 1.5  # a wrong value with its old hash
    entries[0].write_text(json.dumps(doc))
    entries[1].write_text(entries[1].read_text()[:40])  # truncated
    doc2 = json.loads(entries[2].read_text())
    doc2["payload"]["key"] += "x"  # an entry of another key under this name
    doc2["sha256"] = __import__("hashlib").sha256(
        part_props._payload_text(doc2["payload"]).encode()).hexdigest()
    entries[2].write_text(json.dumps(doc2))
    before = part_props.STATS["integrated"]
    again, _ = _evaluate()
    assert part_props.STATS["integrated"] - before == 3  # exactly the three damaged entries
    assert again == values
    for p in entries[:3]:  # rewritten whole
        assert part_props._read(p, json.loads(p.read_text())["payload"]["key"]) is not None


def test_workers_warm_the_cache_together_each_part_once(cold, monkeypatch, tmp_path):
    """``hapticad sweep``'s warm-up: two shares split the design's parts (the cached ones
    cost a read); together they integrate each missing part once, and afterwards an
    evaluation makes and integrates nothing."""
    from cad.families.fourbar.inertia import warm_part_cache
    from cad.parts import part_cache, part_props

    _copy(cold, monkeypatch, tmp_path)  # catalog parts cached, the new thickness's parts not
    d = parse_design(apply(load_toml(HOEKEN), {"parts.bar_thickness_mm": 6.15}), str(HOEKEN))
    before = part_props.STATS["integrated"]
    n = [warm_part_cache(d, "inertia", (i, 2)) for i in (0, 1)]
    made = part_props.STATS["integrated"] - before
    assert sum(n) >= 20 and abs(n[0] - n[1]) <= 1  # every integrated part, split evenly
    assert 5 <= made < sum(n)  # only the parts this thickness changes
    part_cache.clear_memo()
    part_props.clear_memo()
    built, integrated = part_cache.STATS["built"], part_props.STATS["integrated"]
    from cad.families.fourbar.inertia import target_values

    target_values(d, "inertia", False)
    assert (part_cache.STATS["built"], part_props.STATS["integrated"]) == (built, integrated)


def test_cached_integrals_equal_a_fresh_build_and_integration(cold, monkeypatch):
    """Every entry equals OCCT's integration of the part built again from its generator (our
    parts: the evaluation wrote no BREP of them) or read back from the shape cache (catalog
    parts, kept there)."""
    from cad.massprops.occt import volume_props_mm
    from cad.parts import part_props
    from cad.parts.shape_cache import entry_path, read_cached_shape

    monkeypatch.setenv("HAPTICAD_CACHE_DIR", str(cold[0]))
    checked = 0
    for key, d in cold[3].items():
        path = part_props._entry_path(key)
        if not path.is_file():
            continue  # a collision envelope: never integrated
        vol, com, inertia = part_props._read(path, key)
        own = key.startswith("part:")
        # our own parts: a fresh build, not kept; catalog parts: the solid read back from the cache
        v2, c2, i2 = volume_props_mm(d._make() if own else read_cached_shape(key))
        assert vol == v2 and (com == c2).all() and (inertia == i2).all(), key
        assert entry_path(key).is_file() != own, key
        checked += 1
    assert checked >= 10


@pytest.mark.parametrize("args", [(4.0, 5.9, 3.2), (4.0, 6.0, 0.7)])
def test_revolved_spacer_matches_its_closed_form(args):
    """The spacer (one revolution of its section) against the closed form: tube minus the two
    45-degree chamfer rings (Pappus: area of the triangle c^2/2 at centroid radius r_in + c/3)."""
    import math

    from cad.massprops.occt import solid_mass_props
    from cad.parts.joints import SPACER_BORE_CHAMFER_MM, spacer_shape

    r_in, r_out, h = args
    c = min(SPACER_BORE_CHAMFER_MM, h / 3.0, (r_out - r_in) / 3.0)
    vol = math.pi * (r_out**2 - r_in**2) * h - 2 * (2 * math.pi * (r_in + c / 3) * c * c / 2)
    p = solid_mass_props(spacer_shape.uncached(*args), 1000.0)
    assert p.mass_kg == pytest.approx(1000.0 * vol * 1e-9, rel=1e-12)
    assert p.com_m[2] == pytest.approx(h / 2 * 1e-3, rel=1e-12)
