"""Issue 10 proof: four-bar assemblies have no two solids in one place, checked independently.

Reference: ``tests/step_pairs.py`` -- the written ``assembly.step`` read back from disk with
OCCT's XCAF reader and every pair of parts intersected with ``BRepAlgoAPI_Common`` (a pair
sharing more than 1e-3 mm^3 is a clash); not the build's in-memory list nor its code path.

Builds are made once per module (``_build``) at ``preview`` fidelity, STEP only: the solids
of the hardware, bars, base, motor and hub are the same at every fidelity (preview drops
the bearing balls -- inside one bought part -- and the knob's top round, which only removes
material), and the same-body check is exact at every fidelity; the preview's mesh-only
sweep of moving pairs is what differs, and ``test_every_pair_check_*`` covers the exact one.
"""

from __future__ import annotations

import copy
import itertools
from pathlib import Path

import pytest
from step_pairs import clashes

ROOT = Path(__file__).resolve().parents[3]
CASES = ROOT / "tests" / "cases" / "assembly-clashes"  # copied from ../shared (CI has none)
FOURBAR_DESIGNS = (
    "hoeken",
    "roberts",
    "chebyshev",
    "chebyshev_v",
    "custom_example",
    "hoeken_cq_handle",
    "hoeken_light",
    "hoeken_light_brief",
    "hoeken_paper",
)
SWAP_TO = ("roberts", "chebyshev", "chebyshev-v")

_BUILT: dict[str, tuple[dict, Path]] = {}
#: The bundled Hoeken's STEP and DXF: the run's shared preview build with these formats and its
#: drawings (tests/regressions/test_stock_agrees.py, tests/conftest.py ``shared_build``), read-only.
HOEKEN_SHARED = ("hoeken.toml", ("step", "dxf", "drawings"), "preview")
_SHARED = {}


@pytest.fixture(scope="module", autouse=True)
def _shared(shared_build):
    _SHARED["build"] = shared_build  # called by _build("hoeken") only: nothing built here
    yield
    _SHARED.clear()


def _build(key: str, design, tmp_root: Path, fidelity: str = "preview", allow=False):
    from cad.pipeline import build_design

    if key == "hoeken" and key not in _BUILT and (fidelity, allow) == ("preview", False):
        _, out, rep = _SHARED["build"](*HOEKEN_SHARED)
        _BUILT[key] = (rep, out)
    if key not in _BUILT:
        out = tmp_root / key
        formats = {"step", "dxf"} if key == "hoeken" else {"step"}
        rep = build_design(
            design, out, formats, fidelity=fidelity, allow_interference=allow, use_cache=False
        )
        _BUILT[key] = (rep, out)
    return _BUILT[key]


@pytest.fixture(scope="module")
def tmp_root(tmp_path_factory):
    return tmp_path_factory.mktemp("clashes")


def _swapped(family: str):
    from cad.cli.cmd_swap import swap_raw
    from cad.design import load_design, parse_design

    src = load_design(ROOT / "designs" / "hoeken.toml")
    raw = swap_raw(src, family, ROOT / "designs" / "swapped.toml")
    return parse_design(raw, source=str(ROOT / "designs" / "swapped.toml"))


@pytest.mark.parametrize("name", FOURBAR_DESIGNS)
def test_bundled_four_bar_step_has_no_overlapping_solids(name, tmp_root, monkeypatch):
    from cad.design import load_design

    monkeypatch.setenv("HAPTICAD_ALLOW_SCRIPTS", "1")  # hoeken_cq_handle's bundled script

    rep, out = _build(name, load_design(ROOT / "designs" / f"{name}.toml"), tmp_root)
    assert clashes(out / "assembly.step") == []
    assert rep["overlap_volume_mm3"] == 0.0
    assert rep["interference"]["same_body"]["collisions"] == []


@pytest.mark.parametrize("family", SWAP_TO)
def test_swapped_hoeken_step_has_no_overlapping_solids(family, tmp_root):
    rep, out = _build(f"swap_{family}", _swapped(family), tmp_root)
    assert clashes(out / "assembly.step") == []
    assert rep["overlap_volume_mm3"] == 0.0


def test_step_holds_the_motor_shaft_and_the_hub_sits_on_it(tmp_root):
    """The shaft is in assembly.step (issue 10: the hub floated above the motor): the shaft
    solid reaches from the motor's pilot into the hub's bore."""
    from step_pairs import _box, read_parts

    from cad.design import load_design

    _, out = _build("hoeken", load_design(ROOT / "designs" / "hoeken.toml"), tmp_root)
    parts = dict(read_parts(out / "assembly.step"))
    shaft, hub, motor = (_box(parts[k], tight=True).Get() for k in ("motor_shaft", "crank_hub", "motor"))
    assert shaft[2] < motor[5] + 1.5  # starts within 1.5 mm of the pilot face
    assert shaft[5] > hub[2] + 5.9  # 6 mm engagement at least (parts.hub_shaft_engagement_min_mm)
    assert abs(shaft[0] + shaft[3] - hub[0] - hub[3]) < 1e-6  # coaxial in x


def test_roberts_post_is_tall_enough_for_both_screws(tmp_root):
    """Case roberts.toml: the A4 shoulder screw and the post screw had one hole of a 7 mm post."""
    from cad.design import load_design

    d = load_design(ROOT / "designs" / "roberts.toml")
    rep, _ = _build("roberts", d, tmp_root)
    f = rep["fasteners"]
    assert f["pin_A4"]["hole"] == "post_A4:top" and f["post_screw"]["hole"] == "post_A4:bottom"
    holes = rep["tapped_holes"]
    for name in ("pin_A4", "post_screw"):
        h = holes[f[name]["hole"]]
        assert h["min_engagement_mm"] - 1e-9 <= f[name]["engagement_mm"] <= h["depth_mm"] + 1e-9
    assert len({x["hole"] for x in f.values()}) == len(f)  # one fastener per hole


def _no_cad_import(monkeypatch):
    """Make the build's first CAD import fail: a refusal raised with this in place came
    from the layer planning, before any CAD."""
    import cad.parts.lazy_import as li

    def boom():
        raise AssertionError("the CAD import was reached")

    monkeypatch.setattr(li, "import_build123d", boom)


def test_stroke24_case_is_refused_before_cad_naming_joint_parts_and_fix(tmp_root, monkeypatch):
    """Case hoeken_stroke24.toml: the 12.3 mm crank leaves no layer order where the A2 joint
    clears the hub (the A2 washer and nut under the crank sit in the hub: 3.72 mm in plan = hub
    radius 10 + washer radius 6 - l1 12.28; the coupler's end under the crank meets it otherwise).
    The build refuses in the layer planning, before the CAD import, naming the joint, both
    parts, the overlap and the smallest stroke that clears; nothing is exported. The stroke
    it names is then built and read back: zero overlap."""
    from cad.data import catalog
    from cad.design import load_design, parse_design
    from cad.errors import DesignError

    d = load_design(CASES / "hoeken_stroke24.toml")
    with monkeypatch.context() as m:
        _no_cad_import(m)
        with pytest.raises(DesignError) as e:
            _build("stroke24", d, tmp_root)
    msg = str(e.value)
    assert msg.startswith("mechanism.stroke_mm: 24 mm: A2: the A2 washer+nut (crank) and the hub")
    # same-body pair: the nut hangs from the crank at A2, l1 from the hub's axis
    w, nut = catalog.get_washer(d.parts.pin), catalog.get_nut(d.parts.pin)
    r_nut = max(w.d2_mm, nut.s_mm * 2.0 / 3.0**0.5) / 2.0
    overlap = d.parts.hub_diameter_mm / 2 + r_nut - d.linkage.l1_mm
    assert f"overlap by {overlap:.2f} mm" in msg
    assert "stroke_mm >= 31.4 clears it" in msg
    assert "\n" not in msg
    assert not (tmp_root / "stroke24").exists()
    raw = {"name": "stroke31", "mechanism": {"family": "hoeken", "stroke_mm": 31.4}}
    rep, out = _build("stroke31", parse_design(raw, source=str(CASES / "s.toml")), tmp_root)
    assert clashes(out / "assembly.step") == []
    assert rep["overlap_volume_mm3"] == 0.0


def test_same_body_check_finds_what_the_independent_check_finds():
    """A deliberately bad layout (the pre-fix motor: no tapped holes) is caught by the
    build's same-body check with the same volume as an independent boolean of the pair."""
    from build123d import Align, Cylinder

    from cad.assembly.interference import same_body_check
    from cad.parts import translation

    a = (Align.CENTER, Align.CENTER, Align.MIN)
    block = Cylinder(10, 10, align=a).wrapped
    pin = Cylinder(1.25, 5, align=a).wrapped
    items = [
        ("block", "ground", block, translation()),
        ("pin", "ground", pin, translation(3.0, 0.0, 7.0)),  # 3 mm inside the block
        ("far", "ground", pin, translation(30.0, 0.0, 0.0)),
        ("touching", "ground", pin, translation(0.0, 0.0, 10.0)),  # on the top face
        ("other body", "crank", pin, translation(3.0, 0.0, 7.0)),  # not the same body
    ]
    r = same_body_check(items)
    import math

    want = math.pi * 1.25**2 * 3.0
    assert [c["parts"] for c in r.collisions] == [["block", "pin"]]
    assert r.collisions[0]["overlap_volume_mm3"] == pytest.approx(want, rel=1e-6)
    assert r.n_pairs == 6 + 0  # C(4, 2) ground pairs, the crank part alone
    assert r.n_box_overlaps == 1  # "touching" only touches: culled by its box


def test_fasteners_are_sized_from_their_stack():
    from cad.assembly.fasteners import (
        Fastener,
        TappedHole,
        alu_hole,
        check_fasteners,
        size_cap_screw,
    )
    from cad.errors import DesignError

    hole = alu_hole("post:bottom", "post", "M6-1", 11.0)
    assert hole.min_engagement_mm == 9.0  # 1.5 d
    L, e = size_cap_screw("M6-1", 6.0, hole, "A4", "parts.pin")
    assert (L, e) == (16.0, 10.0)  # ISO 4762 M6: ... 12, 16 -> 16 is the first >= 6 + 9
    with pytest.raises(DesignError, match="A4: no M6-1 x L screw"):
        size_cap_screw("M6-1", 6.0, TappedHole("h", "p", "M6-1", 9.5, 9.0), "A4", "parts.pin")
    f = Fastener("ISO 4762", "M6-1", 16.0, ("base_plate",), "post:bottom", 10.0)
    check_fasteners({"a": f}, {"post:bottom": hole})
    with pytest.raises(DesignError, match="both engage post:bottom"):
        check_fasteners({"a": f, "b": f}, {"post:bottom": hole})
    with pytest.raises(DesignError, match="window"):
        check_fasteners(
            {"a": Fastener("ISO 4762", "M6-1", 12.0, (), "post:bottom", 6.0)}, {"post:bottom": hole}
        )


def test_bom_and_report_state_fits_tapped_holes_and_the_set_screw(tmp_root):
    import csv

    from cad.design import load_design

    rep, out = _build("hoeken", load_design(ROOT / "designs" / "hoeken.toml"), tmp_root)
    with (out / "bom.csv").open() as fh:
        rows = {r["part"]: r for r in csv.DictReader(fh)}
    assert any(r["part"].startswith("set_screw_M3") for r in rows.values())
    assert "tap M3 x3" in rows["crank_hub"]["process"]
    assert "tap M3 x4" in rows["base_plate"]["process"]
    seat_bars = [k for k, v in rep["fits"].items() if any("bearing seat" in f for f in v)]
    assert seat_bars and all("J7" in rows[k]["fits"] for k in seat_bars)
    assert "H7" in rows["crank_hub"]["fits"] and "H7" in rows["post_A4"]["fits"]


def test_dxf_mill_layer_holds_only_the_seat_and_notes_state_the_fits(tmp_root):
    import ezdxf

    from cad.data import catalog
    from cad.design import load_design

    d = load_design(ROOT / "designs" / "hoeken.toml")
    rep, out = _build("hoeken", d, tmp_root)
    D = catalog.get_bearing(d.parts.bearing).D_mm
    seats = {j: s["upper"] for j, s in rep["layers"]["joints"].items()}
    for bar in ("crank", "coupler", "rocker"):
        doc = ezdxf.readfile(out / "parts" / f"{bar}.dxf")
        mill = [e for e in doc.modelspace() if e.dxf.layer.startswith("MILL")]
        n_seats = sum(up == bar for up in seats.values())
        assert len(mill) == n_seats  # the seat circles only, not the outline repeated
        assert all(e.dxftype() == "CIRCLE" and e.dxf.radius == pytest.approx(D / 2) for e in mill)
        notes = " ".join(e.dxf.text for e in doc.modelspace() if e.dxf.layer == "NOTES")
        assert ("J7" in notes) == (n_seats > 0)


def test_every_pair_check_property_over_random_four_bars(tmp_path, monkeypatch):
    """Random valid four-bars (family, stroke 20-120 mm, layer order or the planner's choice,
    hardware): each is either refused by the layer planning before the CAD import (the same
    one-line error from :func:`cad.families.fourbar.build.check_layout` and from the build), or
    builds and its assembly.step, read back from disk, has no two solids sharing volume.
    Seeded, few examples: a build costs seconds."""
    from hypothesis import HealthCheck, given, seed, settings
    from hypothesis import strategies as st

    import cad.parts.lazy_import as li
    from cad.design import parse_design
    from cad.errors import DesignError
    from cad.families.fourbar.build import check_layout
    from cad.pipeline import build_design

    hardware = st.sampled_from(
        [
            {},
            {"pin": "M8-1.25", "bearing": "M10-22-6", "bar_thickness_mm": 8.0},
            {"hub_screw": "M4-0.7", "handle_screw": "M3-0.5"},
            {"layer_gap_mm": 3.0, "post_diameter_mm": 16.0},
        ]
    )
    count = itertools.count()
    outcome: list[str] = []
    real_import = li.import_build123d

    @seed(10)
    @settings(
        max_examples=4,
        deadline=None,
        database=None,
        suppress_health_check=list(HealthCheck),
    )
    @given(
        family=st.sampled_from(["hoeken", "roberts", "chebyshev", "chebyshev-v"]),
        stroke=st.floats(20.0, 120.0),
        order=st.none() | st.permutations(["crank", "coupler", "rocker"]),
        hw=hardware,
    )
    def check(family, stroke, order, hw):
        parts = {**copy.deepcopy(hw), **({"layer_order": list(order)} if order else {})}
        raw = {
            "name": f"prop{next(count)}",
            "mechanism": {"family": family, "stroke_mm": stroke},
            "parts": parts,
        }
        try:
            d = parse_design(raw, source=str(tmp_path / "prop.toml"))
            d.check_buildable()
        except DesignError:
            outcome.append("invalid")
            return
        out = tmp_path / raw["name"]
        try:
            check_layout(d, "preview", False)
        except DesignError as early:
            monkeypatch.setattr(li, "import_build123d", lambda: pytest.fail("CAD imported"))
            with pytest.raises(DesignError) as e:
                build_design(d, out, {"step"}, fidelity="preview", use_cache=False)
            monkeypatch.setattr(li, "import_build123d", real_import)
            assert str(e.value) == str(early) and not out.exists()
            outcome.append("refused")
            return
        rep = build_design(d, out, {"step"}, fidelity="preview", use_cache=False)
        assert rep["overlap_volume_mm3"] == 0.0
        assert clashes(out / "assembly.step") == []
        outcome.append("built")

    check()
    assert "built" in outcome  # at least one valid layout was built (not only refusals)


@pytest.mark.parametrize("name", ("hoeken", "roberts"))
def test_four_bar_cap_screws_engage_their_holes_in_the_step_file(name, tmp_root, monkeypatch):
    """Every ISO 4762 screw of a four-bar read back from assembly.step sits in the part its
    record names with the recorded engagement (point classification along its axis,
    ``step_pairs.thread_in_part_mm``), its length a catalog one, its engagement between the
    minimum (1.5 d in aluminium, 2.5 mm in the maxon face, 1 d for the hand-loaded knob screw
    in the coupler) and the hole depth, the hole deeper than its tip."""
    from step_pairs import read_parts, thread_in_part_mm

    from cad.data import catalog
    from cad.design import load_design

    rep, out = _build(name, load_design(ROOT / "designs" / f"{name}.toml"), tmp_root)
    parts = dict(read_parts(out / "assembly.step"))
    n = 0
    for inst, x in rep["fasteners"].items():
        if x["kind"] != "ISO 4762":
            continue
        h = rep["tapped_holes"][x["hole"]]
        cs = catalog.get_cap_screw(x["size"], "test")
        assert x["length_mm"] in cs.lengths_mm
        need = {"motor": 2.5, "coupler": 1.0 * cs.d_mm}.get(h["part"], 1.5 * cs.d_mm)
        assert need - 1e-9 <= x["engagement_mm"] <= h["depth_mm"] + 1e-9, (inst, x, h)
        e, tip_free = thread_in_part_mm(parts[inst], parts[h["part"]], cs.d_mm, cs.dk_mm)
        assert e == pytest.approx(x["engagement_mm"], abs=0.01), (inst, e)
        assert tip_free, inst
        n += 1
    assert n >= 3 + 3 + 4 + 4 + 1  # hub, motor face, mount, leg screws and the post screw


@pytest.mark.parametrize("name", ("hoeken", "roberts", "hoeken_light", "hoeken_paper"))
def test_a4_pin_record_is_what_the_post_holds_in_the_step_file(name, tmp_root):
    """The A4 pin read back from assembly.step: an ISO 7379 screw engages the post over the
    length where both the post's wall surrounds it (``thread_in_part_mm``: a ring at d/2 +
    0.3 mm inside the post, from the tip up) and the screw has thread (``thread_length_mm``:
    from the tip, the screw's radius before the thinner relief); the record is that length
    (to 0.01 mm), equal to the whole thread (the reamed bore ends where the relief ends) and
    to the hole's stated minimum. A plain pin (dowel) is pressed its whole length in the post
    hole. The hole is deeper than the tip."""
    from step_pairs import _box, read_parts, thread_in_part_mm, thread_length_mm

    from cad.data import catalog
    from cad.design import load_design

    d = load_design(ROOT / "designs" / f"{name}.toml")
    rep, out = _build(name, d, tmp_root)
    parts = dict(read_parts(out / "assembly.step"))
    x, h = rep["fasteners"]["pin_A4"], rep["tapped_holes"]["post_A4:top"]
    pin = catalog.get_shoulder_screw(d.parts.pin)
    dowel = catalog.is_dowel(d.parts.pin)
    wall, tip_free = thread_in_part_mm(parts["pin_A4"], parts["post_A4"], pin.thread_mm,
                                       0.0 if dowel else pin.dk_mm)
    assert tip_free
    if dowel:
        assert x["engagement_mm"] == pytest.approx(wall, abs=0.01)
        return
    x0, y0, z0, x1, y1, _ = _box(parts["pin_A4"], tight=True).Get()
    thread = thread_length_mm(parts["pin_A4"], (0.5 * (x0 + x1), 0.5 * (y0 + y1), z0), (0, 0, 1))
    assert x["engagement_mm"] == pytest.approx(min(wall, thread), abs=0.01), (wall, thread)
    assert wall == pytest.approx(thread, abs=0.02)  # the bore starts where the thread ends
    assert h["min_engagement_mm"] == pytest.approx(thread, abs=0.02)
    assert x["engagement_mm"] <= h["depth_mm"]


def test_a4_pin_record_claiming_more_thread_than_the_screw_has_is_refused():
    """The former record (b - 0.5 = 10.5 mm for M6, which counted the 2.5 mm relief as
    thread) lies within the hole's depth window but not within the screw: refused."""
    from cad.assembly.fasteners import Fastener, check_fasteners, shoulder_screw_hole
    from cad.errors import DesignError

    hole = shoulder_screw_hole("post_A4:top", "post_A4", "M6-1", 12.5)
    ok = Fastener("ISO 7379", "M6-1", 12.0, ("rocker",), "post_A4:top", 8.5)
    check_fasteners({"pin_A4": ok}, {hole.name: hole})
    for bad in (10.5, 8.0):  # more thread than the screw has / less than all of it
        f = Fastener("ISO 7379", "M6-1", 12.0, ("rocker",), "post_A4:top", bad)
        with pytest.raises(DesignError, match="pin_A4"):
            check_fasteners({"pin_A4": f}, {hole.name: hole})


@pytest.mark.parametrize("name", ("hoeken", "roberts", "hoeken_light"))
def test_a2_a3_nut_records_are_the_thread_inside_the_nut_in_the_step_file(name, tmp_root):
    """The A2/A3 pins read back from assembly.step: the recorded engagement (the nut height;
    a plain pin's lower DIN 471 ring: its thickness) is the length along the axis where the
    nut (its z extent, material at d/2 + 0.3 mm) and the screw's thread (from the tip, before
    the thinner relief: ``thread_length_mm``; a plain pin: all of it) overlap, to 0.01 mm."""
    from step_pairs import _box, _classifier, read_parts, thread_length_mm

    from cad.data import catalog
    from cad.design import load_design

    d = load_design(ROOT / "designs" / f"{name}.toml")
    rep, out = _build(name, d, tmp_root)
    parts = dict(read_parts(out / "assembly.step"))
    pin = catalog.get_shoulder_screw(d.parts.pin)
    for j in ("A2", "A3"):
        x = rep["fasteners"][f"pin_{j}"]
        assert x["hole"] == f"nut_{j}"
        x0, y0, z0, x1, y1, z1 = _box(parts[f"pin_{j}"], tight=True).Get()
        cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
        thread_top = z0 + (z1 - z0 if catalog.is_dowel(d.parts.pin)
                           else thread_length_mm(parts[f"pin_{j}"], (cx, cy, z0), (0, 0, 1)))
        n0, n1 = _box(parts[f"nut_{j}"], tight=True).Get()[2::3]
        in_nut = _classifier(parts[f"nut_{j}"])
        assert in_nut(cx + pin.thread_mm / 2 + 0.3, cy, 0.5 * (n0 + n1))  # the nut holds it
        engaged = min(n1, thread_top) - max(n0, z0)
        assert x["engagement_mm"] == pytest.approx(engaged, abs=0.01), (j, engaged)
        assert n0 > z0  # the tip stands out below the nut
