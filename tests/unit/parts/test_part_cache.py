"""Part solids cached by their geometric parameters (cad.parts.part_cache): what a parameter
change rebuilds, and cached results equal to uncached ones."""

from __future__ import annotations

from pathlib import Path

import pytest

from cad.design import parse_design
from cad.design.fields import load_toml
from cad.studies.sweep.spec import apply

HOEKEN = Path(__file__).resolve().parents[3] / "designs" / "hoeken.toml"


def _kinds(raw):
    from cad.families.fourbar import assemble
    from cad.parts.lazy_import import import_build123d

    import_build123d()
    d = parse_design(raw, str(HOEKEN))
    return assemble(d, "inertia", poses=d.parts.interference_poses).kinds()


def test_a_thickness_change_rebuilds_only_what_depends_on_it():
    from cad.parts import part_cache

    raw = load_toml(HOEKEN)
    a = _kinds(raw)
    b = _kinds(apply(raw, {"parts.bar_thickness_mm": 6.3}))
    c = _kinds(apply(raw, {"parts.handle_material": "pla", "parts.bar_material": "aluminium-7075"}))
    for name in ("motor_mount", "motor_maxon-re35", "base_plate", "leg", "bearing_M8-16-4"):
        assert b[name].shape is a[name].shape, name  # same solid object: not rebuilt
    # the bars, the hub and post (screw depths) and the knob (screw floor) depend on it
    for name in ("crank", "coupler", "rocker", "crank_hub", "post_A4", "handle"):
        assert b[name].shape is not a[name].shape, name
    assert all(c[n].shape is a[n].shape for n in a)  # a material never changes a solid
    assert part_cache.canonical(1.0) != part_cache.canonical(1.0 + 2**-50)  # exact keys


def test_cached_values_equal_uncached(monkeypatch):
    from cad.families.fourbar.inertia import target_values
    from cad.massprops import occt
    from cad.parts import bars, part_cache

    raw = apply(load_toml(HOEKEN), {"parts.bar_thickness_mm": 5.7})
    d = parse_design(raw, str(HOEKEN))
    target_values(d, "inertia", False)
    warm, _ = target_values(d, "inertia", False)  # every solid and integral from the caches
    monkeypatch.setenv("HAPTICAD_CACHE_DIR", "off")
    part_cache.clear_memo()
    bars._PROFILES.clear()
    occt._PROPS_MEMO.clear()
    cold, _ = target_values(d, "inertia", False)
    assert set(warm) == set(cold)
    for k in cold:
        assert warm[k] == pytest.approx(cold[k], rel=1e-12), k
