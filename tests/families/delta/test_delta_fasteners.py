"""The direct-drive delta's fasteners (cad/families/delta/fastening.py), read back from the
written build of designs/delta.toml (the shared preview build of tests/conftest.py):

* each screw group's thread and catalog length against the catalog, worked out here: the
  shortest ISO 4762 length of bd_warehouse's list at least the clamped plate's thickness plus
  the hole's minimum engagement (1.5 d in aluminium, min(face depth, 2.5 mm) in the maxon
  face), the engagement L - clamp within the hole's thread; the hub's ISO 4026 set screw by
  its 16 mm boss's geometry (full thread sqrt(R^2 - (d/2)^2) - r_shaft, 1.5 d <= L <= it);
* report.json ``fasteners`` / ``tapped_holes``, bom.csv and order.csv counts in closed form
  (3 arms x the motor's 3 bolts, 3 brackets x 2, 3 hubs, 1 handle, 3 effector cross bars);
* assembly.md fastens each screw in the step that mounts its part;
* (slow) OCCT on assembly.step read back (tests/step_readback.py): every screw shares no
  volume with any other solid -- its hole is cut in the part it enters -- and touches the
  part it clamps; it stands off the tapped hole's wall by the tap drill's radius less the
  thread's minor radius (ISO 724), the simplified thread's envelope.
"""

from __future__ import annotations

import csv
import math
import re

import pytest

from cad.data import catalog as cat
from cad.families.delta import hardware as hw
from tests.conftest import DELTA_FORMATS

# the RE 40 of designs/delta.toml: M3 face holes 3.5 mm deep, 3 on the bolt circle, 6 mm shaft
RE40 = cat.get_motor("maxon-re40")


def _shortest(size: str, at_least: float) -> float:
    return min(L for L in cat.get_cap_screw(size, "t").lengths_mm if L >= at_least)


def expected() -> dict:
    """{group: (size, length, engagement, thread depth, minimum engagement, clamp)} worked out
    from the catalog (module docstring)."""
    face_min = min(RE40.bolt_thread_depth_mm, 2.5)
    out = {"motor": ("M3-0.5", _shortest("M3-0.5", 5.0 + face_min), None, 3.5, face_min, hw.BRACKET_THICKNESS_MM),
           "bracket": ("M2.5-0.45", _shortest("M2.5-0.45", 6.0 + 1.5 * 2.5), None, 8.0, 3.75, hw.PLATE_THICKNESS_MM),
           "handle": ("M3-0.5", _shortest("M3-0.5", 5.0 + 1.5 * 3.0), None, 10.0, 4.5, hw.EFFECTOR_THICKNESS_MM)}
    # the effector cross bar (8 mm round) tapped through from its bottom: the full M3 thread
    # within sqrt(4^2 - 1.5^2) = 3.708 of its axis, so 4 - 3.708 = 0.292 mm of partial thread
    # first, the minimum 4.5 + 0.292, the full thread ending 4 + 3.708 from the bottom
    c = math.sqrt(16.0 - 2.25)
    lo = 4.5 + 4.0 - c
    out["effector_bar"] = ("M3-0.5", _shortest("M3-0.5", 5.0 + lo), None, 4.0 + c, lo, hw.EFFECTOR_THICKNESS_MM)
    out = {g: (s, L, L - c, dep, mn, c) for g, (s, L, _, dep, mn, c) in out.items()}
    # the hub's boss: R = 8, shaft radius 3; M3's window 4.5 .. sqrt(64 - 2.25) - 3 = 4.86 holds no
    # catalog length (4, 5), M2.5's 3.75 .. 4.90 holds 4
    depth = math.sqrt(8.0**2 - 1.25**2) - 3.0
    assert not [L for L in cat.get_set_screw("M3-0.5", "t").lengths_mm if 4.5 <= L <= math.sqrt(61.75) - 3.0]
    out["hub"] = ("M2.5-0.45", 4.0, 4.0, depth, 3.75, 0.0)
    return out


def test_the_plan_matches_the_catalog():
    from cad.design import load_design
    from cad.families.delta.fastening import HUB_BOSS_D_MM, screw_plan

    assert (RE40.bolt_size, RE40.bolt_count, RE40.bolt_thread_depth_mm, RE40.shaft_diameter_mm) == ("M3-0.5", 3, 3.5, 6.0)
    assert HUB_BOSS_D_MM == 16.0 and (hw.PLATE_THICKNESS_MM, hw.BRACKET_THICKNESS_MM) == (6.0, 5.0)
    plan = screw_plan(load_design("designs/delta.toml"))
    for g, (size, L, e, depth, lo, clamp) in expected().items():
        p = plan[g]
        assert (p["size"], p["length_mm"], p["engagement_mm"]) == (size, L, pytest.approx(e)), g
        assert p["depth_mm"] == pytest.approx(depth) and p["min_engagement_mm"] == pytest.approx(lo), g
        assert lo <= e <= depth + 1e-9 and p["clamp_mm"] == clamp, g
    assert [plan[g]["length_mm"] for g in ("motor", "bracket", "handle", "hub", "effector_bar")] == [
        8.0, 10.0, 10.0, 4.0, 10.0]


def _group(name: str) -> str:
    if name.endswith("bar_screw"):
        return "effector_bar"
    return {"motor": "motor", "bracket": "bracket", "effector": "handle", "upper": "hub"}[re.split(r"[_.]", name)[0]]


@pytest.fixture(scope="module")
def built(shared_build):
    return shared_build("delta.toml", DELTA_FORMATS, "preview")


def test_report_bom_and_order_read_back(built):
    _, out, rep = built
    fast, holes = rep["fasteners"], rep["tapped_holes"]
    exp = expected()
    counts = {"motor": 3 * 3, "bracket": 3 * 2, "hub": 3, "handle": 1, "effector_bar": 3}
    assert {g: sum(_group(n) == g for n in fast) for g in counts} == counts and len(holes) == 22
    for name, f in fast.items():
        size, L, e, depth, lo, clamp = exp[_group(name)]
        h = holes[f["hole"]]
        assert (f["size"], f["length_mm"], f["engagement_mm"], h["size"]) == (size, L, pytest.approx(e), size)
        assert h["depth_mm"] == pytest.approx(depth) and h["min_engagement_mm"] == pytest.approx(lo)
        if f["kind"] == "ISO 4762":  # length = the clamped plate + the engagement
            assert f["length_mm"] == pytest.approx(clamp + f["engagement_mm"])
    with (out / "bom.csv").open(encoding="utf-8", newline="") as fh:
        bom = {r["designation"]: r["quantity"] for r in csv.DictReader(fh)}
    with (out / "order.csv").open(encoding="utf-8", newline="") as fh:
        order = {r["designation"]: r["quantity"] for r in csv.DictReader(fh)}
    lines = {"ISO 4762 M3-0.5 x 8": 9, "ISO 4762 M2.5-0.45 x 10": 6, "ISO 4762 M3-0.5 x 10": 1 + 3,
             "ISO 4026 M2.5-0.45 x 4": 3}
    for des, n in lines.items():
        assert int(bom[des]) == n and int(order[des]) == n, des


def _steps(md: str) -> list[tuple[str, str]]:
    parts = re.split(r"^## Step \d+: (.*)$", md, flags=re.M)
    return list(zip(parts[1::2], parts[2::2], strict=True))


def test_assembly_md_fastens_each_screw_where_its_part_is_mounted(built):
    _, out, rep = built
    steps = _steps((out / "assembly.md").read_text())
    where = {}
    for k, (title, body) in enumerate(steps):
        for name in rep["fasteners"]:
            if f"fastener `{name}`" in body:
                where[name] = (k, title)
    assert set(where) == set(rep["fasteners"])
    first = {}  # the step that places each part
    for k, (_, body) in enumerate(steps):
        for n in re.findall(r"^- `([^`]+)` \(", body, flags=re.M):
            first.setdefault(n, k)
    for name, (k, title) in where.items():
        g = _group(name)
        if g == "hub":  # in its arm's own step, with the hub it locks
            i = name.split(".")[0]
            assert title == f"{i}: its parts" and first[f"{i}.hub"] == k
        else:
            f = rep["fasteners"][name]
            part = f["hole"].split(":")[0]
            assert title.startswith(f"fasten {f['clamps'][0]} with ") and first[part] < k
            assert first[f["clamps"][0]] < k
    final = dict(steps)["final checks"]
    assert "each held by its set screw" in final and "fastening, a clamp or a bond" not in final


def _box(solid):
    b = solid.bounding_box()
    return (b.min.X, b.min.Y, b.min.Z), (b.max.X, b.max.Y, b.max.Z)


@pytest.mark.slow  # OCCT Booleans of 22 screws against the solids near them (~1 min)
def test_every_screw_is_clear_of_every_other_solid_in_the_step(built):
    from cad.assembly.interference import OVERLAP_MIN_MM3
    from tests.step_readback import common_mm3, dist_mm, step_solids

    _, out, rep = built
    solids = step_solids(out / "assembly.step")
    key = {n: n.replace(".", "_") for n in rep["fasteners"]}
    for name, f in rep["fasteners"].items():
        s = solids[key[name]]
        lo, hi = _box(s)
        for other, o in solids.items():
            if other == key[name]:
                continue
            olo, ohi = _box(o)
            if any(hi[a] < olo[a] or ohi[a] < lo[a] for a in range(3)):
                continue
            assert common_mm3(s, o) <= OVERLAP_MIN_MM3, (name, other)
        part = f["hole"].split(":")[0].replace(".", "_")
        # in its hole: the screw solid is the thread's minor diameter d1 = d - 1.082532 P (ISO 724),
        # the hole the tap drill (the set screw's solid is the tap drill itself)
        d, pitch = (float(x) for x in f["size"].removeprefix("M").split("-"))
        gap = (cat.tap_drill_mm(f["size"]) - (d - 1.082532 * pitch)) / 2 if f["kind"] == "ISO 4762" else 0.0
        assert dist_mm(s, solids[part]) == pytest.approx(gap, abs=1e-4), (name, part)
        for c in f["clamps"]:
            if c.replace(".", "_") in solids:  # the motor shaft is part of the motor's solid
                assert dist_mm(s, solids[c.replace(".", "_")]) < 1e-6, (name, c)


def test_the_capstan_delta_fastens_every_bracket_to_the_plate():
    """designs/delta_capstan.toml's model (no build): the arm brackets and the capstans' moved
    motor brackets each held by 2 bracket screws (3 x 2 + 3 x 2 = 12), the handle's screw, no
    face screw or hub set screw on a capstan arm (its capstan sits where the face screws' heads
    would), the capstans' own set screws kept; every record engages a hole of the model
    (:func:`cad.assembly.fasteners.check_fasteners`)."""
    from cad.assembly.fasteners import check_fasteners
    from cad.design import load_design
    from cad.families.delta.assembly import assemble
    from cad.families.delta.fastening import screw_counts

    d = load_design("designs/delta_capstan.toml")
    m = assemble(d, "preview")
    fast = {i.name: i.fastener for i in m.instances if i.fastener is not None}
    check_fasteners(fast, m.holes)
    assert screw_counts(d) == {"motor": 0, "hub": 0, "bracket": 12, "handle": 1, "effector_bar": 3}
    brackets = [n for n, f in fast.items() if f.clamps == ("base_plate",)]
    assert len(brackets) == 12 and {fast[n].hole.split(":")[0] for n in brackets} == {
        *(f"motor_bracket_{i}" for i in range(3)), *(f"capstan_motor_bracket_{i}" for i in range(3))}
    assert not [n for n in fast if n.startswith("motor_screw") or n.endswith("hub_set_screw")]
    assert sorted(n for n in fast if n.startswith("capstan_set_screw")) == [f"capstan_set_screw_{i}" for i in range(3)]
    assert len(fast) == 12 + 1 + 3 + 3


def test_the_drawings_thread_key_has_the_screws_tap_drill():
    """The drawings name a hole's thread by its short key (``"M2.5"``, :func:`cad.data.fits.
    metric_thread`) and match it to the solid's hole by that key's tap drill: with the ISO 261
    coarse pitches (M2 0.4, M2.5 0.45) the short key's drill is the screw's, d - P (M2.5:
    2.05 mm, the bracket's and the hub's holes; it was 2.125 with 0.15 d for a pitch)."""
    from cad.data.fits import metric_thread

    for size, d, p in (("M2-0.4", 2.0, 0.4), ("M2.5-0.45", 2.5, 0.45), ("M3-0.5", 3.0, 0.5)):
        assert cat.tap_drill_mm(metric_thread(size)) == pytest.approx(d - p, abs=1e-12)
        assert cat.tap_drill_mm(size) == pytest.approx(d - p, abs=1e-12)
