"""Every screw of every non-four-bar family has its fastener data, and the data holds
against the catalog and against the solids read back from assembly.step.

References, not the build's code path:
* the catalog numbers (ISO 4762 lengths of bd_warehouse, thread diameters, the motor
  face's thread depth) and the plate/wall thicknesses of the design;
* the written ``assembly.step`` re-read with OCCT's XCAF reader: each screw's thread
  engagement measured by point classification along its axis in the part whose hole it
  engages (``tests/step_pairs.thread_in_part_mm``), and every pair of solids intersected
  (``tests/families/test_family_builds.py``).
Builds: ``conftest.family_builds`` (one per family, shared).
"""

from __future__ import annotations

import csv
import re
from pathlib import Path

import pytest
from catalog_ref import iso4026_lengths_mm
from step_pairs import radial_screw_mm, read_parts, thread_in_part_mm

FAMILIES = ("pantograph", "twin-pantograph", "powermouse")


def _refused_before_cad(monkeypatch, tmp_path, design: str, table: str, also=None,
                        **changes) -> str:
    """Build ``designs/<design>`` with ``[table]`` fields replaced by ``changes`` while any
    CAD import fails the test; return the DesignError text (one line) and check that no
    output folder was created."""
    import dataclasses

    import cad.parts.lazy_import as li
    from cad.design import load_design
    from cad.errors import DesignError
    from cad.pipeline import build_design

    d = load_design(Path(__file__).resolve().parents[2] / "designs" / design)
    for t, ch in {table: changes, **(also or {})}.items():
        d = dataclasses.replace(d, **{t: dataclasses.replace(getattr(d, t), **ch)})
    monkeypatch.setattr(li, "import_build123d", lambda: pytest.fail("CAD imported"))
    with pytest.raises(DesignError) as e:
        build_design(d, tmp_path / "o", {"step"})
    assert "\n" not in str(e.value)
    assert not (tmp_path / "o").exists()
    return str(e.value)

def _expected_counts(fam: str, d) -> dict[str, int]:
    """Screws per group, counted from the catalog and the design (not from the build)."""
    from cad.data import catalog

    if fam == "powermouse":
        # one per side wall, housing and flotor; the post's set screw; two turned tips
        return {"lid_screw": 4, "flotor_lid_screw": 4, "set_screw": 1, "handle": 1, "post": 1,
                "leg_screw": 4}
    stations = 2 if fam == "twin-pantograph" else 1  # motors under the base, on the bridge
    m = catalog.get_motor(d.parts.motor)
    out = {
        "leg_screw": 4,
        "mount_screw": 2 * stations * 4,  # 2 motors x 4 corner screws
        "motor_screw": 2 * stations * m.bolt_count,
    }
    if fam == "twin-pantograph":
        out["post_screw"] = 4 * 2  # 4 posts, a screw at each end
    out["set_screw"] = 2 * stations  # one per hub clevis (motor)
    return out


def _group(name: str) -> str:
    for g in ("leg_screw", "mount_screw", "motor_screw", "post_screw", "flotor_lid_screw",
              "lid_screw", "set_screw"):
        if g in name:
            return g
    if name in ("handle", "post"):  # the PowerMouse's turned tips: test_powermouse_joints
        return name
    raise AssertionError(name)


def _clamp_mm(fam: str, d, group: str, rep: dict) -> float:
    p = d.parts if fam != "powermouse" else None
    return {
        # the flotor lid is a wall of the coil's thickness d_c = d - d_r
        "flotor_lid_screw": lambda: rep["actuator"]["gap_mm"] - d.actuator.rattle_mm,
        "leg_screw": lambda: d.stator.housing_wall_mm if p is None else p.plate_thickness_mm,
        "post_screw": lambda: p.plate_thickness_mm,
        "mount_screw": lambda: p.motor_mount_thickness_mm,
        "motor_screw": lambda: p.motor_mount_thickness_mm,
        "lid_screw": lambda: d.stator.housing_wall_mm,
    }[group]()


@pytest.mark.parametrize("fam", FAMILIES)
def test_every_screw_has_fastener_data_within_its_hole(family_builds, fam):
    from cad.data import catalog

    d, out, rep = family_builds[fam]
    f, holes = rep["fasteners"], rep["tapped_holes"]
    counts: dict[str, int] = {}
    for name, x in f.items():
        counts[_group(name)] = counts.get(_group(name), 0) + 1
        if _group(name) in ("set_screw", "handle", "post"):
            continue  # radial, no clamp / turned tips: test_clevis_set_screw_*, test_powermouse_joints
        cs = catalog.get_cap_screw(x["size"], "test")
        assert x["kind"] == "ISO 4762" and x["length_mm"] in cs.lengths_mm, (name, x)
        h = holes[x["hole"]]
        dia = catalog.thread_diameter_mm(x["size"])
        if h["part"].endswith(tuple(f"motor_{i}" for i in (1, 2))):  # the maxon face
            m = catalog.get_motor(d.parts.motor)
            assert h["depth_mm"] == m.bolt_thread_depth_mm  # the maker's 3.5 mm
            assert x["engagement_mm"] >= min(2.5, m.bolt_thread_depth_mm) - 1e-9
        elif h["part"] == "flotor_body":  # a plastic flotor (delrin): 2 d
            assert d.flotor.material == "delrin" and h["min_engagement_mm"] == 2 * dia
            assert x["engagement_mm"] >= 2 * dia - 1e-9, (name, x)
        else:
            assert x["engagement_mm"] >= 1.5 * dia - 1e-9, (name, x)  # aluminium: 1.5 d
        assert x["engagement_mm"] <= h["depth_mm"] + 1e-9, (name, x, h)
        # the length is the stack: clamped thickness + engagement, the shortest catalog one
        clamp = _clamp_mm(fam, d, _group(name), rep)
        assert x["length_mm"] == pytest.approx(clamp + x["engagement_mm"])
        shorter = [L for L in cs.lengths_mm if L < x["length_mm"]]
        assert not shorter or max(shorter) - clamp < h["min_engagement_mm"] - 1e-9
    assert counts == _expected_counts(fam, d)
    assert len({x["hole"] for x in f.values()}) == len(f)  # one screw per hole


@pytest.mark.parametrize("fam", FAMILIES)
def test_thread_engagement_measured_in_the_step_file(family_builds, fam):
    """Each screw read back from assembly.step sits in the part its record names, with the
    recorded engagement (to 0.01 mm: bisection to 0.005 mm) and a hole deeper than its tip."""
    from cad.data import catalog

    d, out, rep = family_builds[fam]
    parts = dict(read_parts(out / "assembly.step"))
    for name, x in rep["fasteners"].items():
        if x["kind"] != "ISO 4762":
            continue  # set screws and turned tips: test_clevis_set_screw_*, test_powermouse_joints
        h = rep["tapped_holes"][x["hole"]]
        cs = catalog.get_cap_screw(x["size"], "test")
        e, tip_free = thread_in_part_mm(parts[name], parts[h["part"]], cs.d_mm, cs.dk_mm)
        assert e == pytest.approx(x["engagement_mm"], abs=0.01), (name, h["part"], e)
        assert tip_free, name


@pytest.mark.parametrize("fam", ("pantograph", "twin-pantograph"))
def test_bom_states_tapped_holes(family_builds, fam):
    _, out, _ = family_builds[fam]
    with (out / "bom.csv").open() as fh:
        rows = {r["part"]: r for r in csv.DictReader(fh)}
    assert "tap M3 x" in rows["base_plate"]["process"]
    assert "face tapped M3 x3" in rows["motor"]["process"]
    assert "tap M6 both ends" in rows["leg"]["process"]
    assert "tap M2 x1 (radial)" in rows["clevis_hub"]["process"]
    ss = rows["set_screw"]
    assert ss["made_or_bought"] == "bought" and "ISO 4026 M2-0.4 x 3.5" in ss["description"]
    assert ss["quantity"] == rows["motor"]["quantity"] == rows["clevis_hub"]["quantity"]
    if fam == "twin-pantograph":
        assert "tap M3 x8" in rows["bridge_plate"]["process"]
        assert "tap M4 both ends" in rows["post"]["process"]


def test_powermouse_bom_states_the_lid_screw_holes(family_builds):
    from cad.families.powermouse import parts as pp

    _, out, rep = family_builds["powermouse"]
    with (out / "bom.csv").open() as fh:
        rows = {r["part"]: r for r in csv.DictReader(fh)}
    for prefix, part, size in (("lid_screw", "pm_housing_body", pp.LID_SCREW),
                               ("flotor_lid_screw", "pm_flotor_body", pp.FLOTOR_LID_SCREW)):
        f = {k: x for k, x in rep["fasteners"].items() if _group(k) == prefix}
        assert f"tap {size.split('-')[0]} x{len(f)}" in rows[part]["process"]
        (L,) = {x["length_mm"] for x in f.values()}
        screw = rows[f"cap_screw_{size}x{L:g}"]
        same = [x for x in rep["fasteners"].values()  # the legs' screws may share the kind
                if (x["kind"], x["size"], x["length_mm"]) == ("ISO 4762", size, L)]
        assert screw["made_or_bought"] == "bought" and int(screw["quantity"]) == len(same)
        assert f"ISO 4762 {size} x {L:g}" in screw["description"]


def test_powermouse_flotor_lid_screws_against_the_catalog(family_builds):
    """The flotor lid (a d_c = d - d_r wall) held by M2.5 screws into 7 mm of full thread
    (8 mm tap drill, 1 mm lead-out) in the delrin side walls: 2 d = 5 mm minimum, so
    L >= d_c + 5; the shortest ISO 4762 M2.5 length (bd_warehouse CSV: 4..25 from the
    nominal list) that is, and the engagement L - d_c within 5..7 mm."""
    d, _, rep = family_builds["powermouse"]
    dc = rep["actuator"]["gap_mm"] - d.actuator.rattle_mm
    nominal = [4, 5, 6, 8, 10, 12, 16, 20, 25]  # iso4762 M2.5: short 4, long 25
    L = min(x for x in nominal if x >= dc + 5.0)
    assert 5.0 <= L - dc <= 7.0
    f = {k: x for k, x in rep["fasteners"].items() if k.startswith("flotor_lid_screw")}
    assert len(f) == 4
    for k, x in f.items():
        assert x["size"] == "M2.5-0.45" and x["length_mm"] == L, (k, x)
        assert x["clamps"] == ["flotor_lid"] and x["engagement_mm"] == pytest.approx(L - dc)
        h = rep["tapped_holes"][x["hole"]]
        assert h["part"] == "flotor_body" and h["depth_mm"] == 7.0


def test_thin_housing_wall_is_refused_before_cad(tmp_path, monkeypatch):
    msg = _refused_before_cad(monkeypatch, tmp_path, "powermouse.toml", "stator",
                              housing_wall_mm=3.5)
    assert re.match(r"stator.housing_wall_mm: 3.5 mm walls cannot take", msg)


def test_pantograph_stack_no_catalog_screw_fits_is_refused_before_cad(tmp_path, monkeypatch):
    """A 4 mm motor mount plate: an M3 motor screw would need 4 + 2.5..3.5 mm, and ISO 4762
    M3 comes in 6 and 8 mm -- refused naming the joint and the window, before any CAD."""
    msg = _refused_before_cad(monkeypatch, tmp_path, "pantograph.toml", "parts",
                              motor_mount_thickness_mm=4.0)
    assert msg.startswith("parts.motor_mount_thickness_mm: motor face to mount plate")
    assert "need L in 6.5..7.5 mm" in msg


@pytest.mark.parametrize("fam", ("pantograph", "twin-pantograph"))
def test_clevis_set_screw_record_against_the_catalog(family_builds, fam):
    """14 mm clevis round end on the 6 mm RE 35 shaft: a 4 mm wall, whose full thread on the
    round outside ends at sqrt(7^2 - (d/2)^2): M2.5 -> 3.888 mm, so its longest length not
    proud of the clevis (3.5) is < 1.5 d = 3.75; M2 -> 3.928 mm, longest length 3.5 >= 3."""
    import math

    from cad.data import catalog

    d, _, rep = family_builds[fam]
    r_in = catalog.get_motor(d.parts.motor).shaft_diameter_mm / 2
    R = d.parts.clevis_width_mm / 2
    assert (r_in, R) == (3.0, 7.0)
    assert max(L for L in iso4026_lengths_mm("M2.5-0.45")
               if L <= math.sqrt(R**2 - 1.25**2) - r_in) < 3.75  # M2.5 does not fit
    depth = math.sqrt(R**2 - 1.0**2) - r_in
    L = max(x for x in iso4026_lengths_mm("M2-0.4") if x <= depth)
    assert L == 3.5
    sets = {n: x for n, x in rep["fasteners"].items() if x["kind"] == "ISO 4026"}
    assert len(sets) == (4 if fam == "twin-pantograph" else 2)
    for name, x in sets.items():
        body = name.removesuffix(".set_screw")
        assert x == {"kind": "ISO 4026", "size": "M2-0.4", "length_mm": L,
                     "clamps": [f"{body}.motor_shaft"], "hole": f"{body}.clevis_hub0:set_screw",
                     "engagement_mm": L}
        h = rep["tapped_holes"][x["hole"]]
        assert h["part"] == f"{body}.clevis_hub0"
        assert h["depth_mm"] == pytest.approx(depth) and h["min_engagement_mm"] == 3.0


@pytest.mark.parametrize("fam", ("pantograph", "twin-pantograph"))
def test_clevis_set_screw_measured_in_the_step_file(family_builds, fam):
    """Each set screw read back from assembly.step: its point touches the shaft (3 mm from the
    shaft axis, the point just beyond it in the shaft), its end and the end's rim at d/2 inside
    the clevis's 7 mm round end (nothing proud), full thread round it in the clevis over the
    recorded hole depth, so the whole recorded length is engaged."""
    d, out, rep = family_builds[fam]
    parts = dict(read_parts(out / "assembly.step"))
    R = d.parts.clevis_width_mm / 2
    for name, x in rep["fasteners"].items():
        if x["kind"] != "ISO 4026":
            continue
        body = name.removesuffix(".set_screw")
        m = radial_screw_mm(parts[name], parts[f"{body}.clevis_hub0"],
                            parts[f"{body}.motor_shaft"], 2.0)
        assert m["tip_to_axis_mm"] == pytest.approx(3.0, abs=1e-3) and m["tip_on_shaft"], m
        assert m["length_mm"] == pytest.approx(x["length_mm"], abs=1e-3)
        assert m["rim_to_axis_max_mm"] <= R, m
        depth = rep["tapped_holes"][x["hole"]]["depth_mm"]
        assert m["full_thread_mm"] == pytest.approx(depth, abs=0.01), m
        assert min(m["length_mm"], m["full_thread_mm"]) == pytest.approx(x["engagement_mm"],
                                                                        abs=0.01)


def test_clevis_too_thin_for_a_set_screw_is_refused_before_cad(tmp_path, monkeypatch):
    """A 12 mm clevis on the 6 mm shaft: 3 mm wall, 2.92 mm of full M2 thread < 1.5 d = 3."""
    msg = _refused_before_cad(monkeypatch, tmp_path, "pantograph.toml", "parts",
                              clevis_width_mm=12.0)
    assert msg.startswith("parts.clevis_width_mm: hub clevis set screw")
    assert "(2.92 mm of full M2 thread)" in msg


def test_thin_flotor_wall_is_refused_before_cad(tmp_path, monkeypatch):
    """gap 9 mm, rattle 6 mm: 3 mm flotor walls < M2.5 tap drill 2.05 + 2 x 0.75 = 3.55 mm."""
    msg = _refused_before_cad(monkeypatch, tmp_path, "powermouse.toml", "actuator", gap_mm=9.0)
    assert msg.startswith("actuator.rattle_mm: 3 mm walls cannot take the M2.5-0.45")
    assert "(need >= 3.55 mm)" in msg


def test_flotor_lid_tap_drill_into_a_coil_pocket_is_refused_before_cad(tmp_path, monkeypatch):
    """edge 62 mm (optimum gap ~10.8, d_c ~4.8; a 6 mm post so that its corner hole fits): the
    8 mm tap drills would end at
    z = 31 - 4.8 - 8 = 18.2 mm, within 0.75 mm of the +-x coil pockets (l_m/2 + w_m = 18)."""
    msg = _refused_before_cad(monkeypatch, tmp_path, "powermouse.toml", "flotor", edge_mm=62.0,
                              also={"stator": {"post_diameter_mm": 6.0}},  # a hole that fits
                              corner_hole_mm=24.0)
    assert msg.startswith("flotor.edge_mm: the flotor lid screws' 8 mm tap drills")
    assert "(z <= 18 mm)" in msg
