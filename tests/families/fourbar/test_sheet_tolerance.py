"""Fasteners of a laser build over the sheets' thickness tolerance (issue 25,
:mod:`cad.families.fourbar.sheet_tolerance`), at design load (no CAD).

References typed here, not read from our tables: EN 485-4:1993 Table 1 (alloy group II, width
1000..1250 mm) +-0.22 mm at 5 mm and +-0.24 mm at 6 mm; the birch plywood data sheet (EN 315
limits) 6.5 mm -> 6.1..6.9 mm; ISO 4762 M3 lengths 5, 6, 8, 10, 12, 16 mm, M4 6..16 mm with no
14; engagement windows of :mod:`cad.assembly.fasteners` (1.5 d in aluminium, the maxon face
hole 3.5 mm deep with a 2.5 mm minimum, the leg's 12 mm tapped end less 1 mm lead-out).
"""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
DESIGN = ROOT / "designs" / "hoeken_laser.toml"
MACHINED = ROOT / "designs" / "hoeken.toml"

AL5, AL6 = 0.22, 0.24  # EN 485-4 Table 1, group II: +-mm at 5 and 6 mm


def _load(tmp_path, *edits: tuple[str, str]):
    from cad.design import bounds, load_design

    text = DESIGN.read_text()
    for old, new in edits:
        assert old in text
        text = text.replace(old, new)
    p = tmp_path / "d.toml"
    p.write_text(text)
    bounds.reset()
    return load_design(p)


def _rows(parts):
    """{joint: report row} of the plate screws (motor face, mount, leg) at design load."""
    from cad.families.fourbar.mechanism import check_plate_screws
    from cad.families.fourbar.sheet_tolerance import screw_row, sheet_bands

    out = {}
    for a, clamps, (L, e) in check_plate_screws(parts):
        out[a["joint"]] = (L, e, screw_row("x", a["size"], L, a["clamp"], clamps, a["hole"],
                                          sheet_bands(parts)))
    return out


def test_hoeken_laser_plate_screws_by_hand(tmp_path):
    """6 mm 5083 base plate, 5 mm 5083 motor mount: the leg, mount and motor face screws
    engage nominal +- the clamped sheet's tolerance and hold over it."""
    from cad.design import bounds

    rows = _rows(_load(tmp_path).parts)
    assert not [w for w in bounds.collected() if "holds over that band" in w]
    L, e, r = rows["leg 1 to base plate"]  # M6 x 16 through 6 mm into a 12 - 1 = 11 mm thread
    assert (L, e) == (16.0, 10.0)
    assert r["engagement_worst_mm"] == pytest.approx([16 - (6 + AL6), 16 - (6 - AL6)])
    assert r["window_mm"] == pytest.approx([1.5 * 6, 11.0]) and r["verdict"] == "holds"
    assert r["sheets"] == ["6 mm aluminium-5083 measures 5.76..6.24 mm (EN 485-4)"]
    L, e, r = rows["motor mount to base plate"]  # M3 x 10 through 5 mm into the 6 mm base
    assert (L, e) == (10.0, 5.0)
    assert r["engagement_worst_mm"] == pytest.approx([10 - (5 + AL5), 10 - (5 - AL5)])
    # the thread is the base plate: at most its thinnest sheet deep
    assert r["window_mm"] == pytest.approx([1.5 * 3, 6 - AL6]) and r["verdict"] == "holds"
    assert r["keys"] == ["parts.motor_mount_thickness_mm", "parts.base_thickness_mm"]
    L, e, r = rows["A1 (motor to mount plate)"]  # M3 x 8 into the maxon's 3.5 mm face hole
    assert (L, e) == (8.0, 3.0)
    assert r["engagement_worst_mm"] == pytest.approx([8 - (5 + AL5), 8 - (5 - AL5)])
    assert r["window_mm"] == pytest.approx([2.5, 3.5]) and r["verdict"] == "holds"


def test_plywood_motor_mount_warns(tmp_path):
    """A 6.5 mm birch plywood motor mount (no tapped hole in it: allowed): 6.1..6.9 mm puts
    the motor face screw's L window at 6.9 + 2.5 .. 6.1 + 3.5 = 9.4..9.6 mm and the mount
    screws' at 6.9 + 4.5 .. 6.1 + 5.76 = 11.4..11.86 mm: no M3 catalog length in either, so
    each warns naming the joint, the sheet, its band and the key; the nominal screw stays."""
    from cad.design import bounds

    d = _load(tmp_path, ('motor_mount_material = "aluminium-5083"',
                         'motor_mount_material = "birch-plywood"'),
              ("motor_mount_thickness_mm = 5.0", "motor_mount_thickness_mm = 6.5"))
    m3 = (5.0, 6.0, 8.0, 10.0, 12.0, 16.0)
    assert not [x for x in m3 if 9.4 <= x <= 9.6 or 11.4 <= x <= 11.86]
    rows = _rows(d.parts)
    warns = [w for w in bounds.collected() if "holds over that band" in w]
    bounds.reset()
    band = "6.5 mm birch-plywood measures 6.1..6.9 mm (EN 315)"
    for joint, L, lo, hi, e in (("A1 (motor to mount plate)", 10.0, 9.4, 9.6, (3.1, 3.9)),
                                ("motor mount to base plate", 12.0, 11.4, 11.86, (5.1, 5.9))):
        w = [x for x in warns if x.startswith(joint + ":")]
        assert len(w) == 1, warns
        assert band in w[0] and "parts.motor_mount_thickness_mm" in w[0]
        assert f"needs L in {lo:g}..{hi:g} mm" in w[0]
        got_L, _, r = rows[joint]
        assert got_L == L and r["verdict"] == "misses"
        assert r["engagement_worst_mm"] == pytest.approx(e)
    assert "6 mm aluminium-5083 measures 5.76..6.24 mm" in \
        [x for x in warns if x.startswith("motor mount to base plate")][0]
    assert rows["leg 1 to base plate"][2]["verdict"] == "holds"


def test_hub_screw_lengthened_over_band(tmp_path):
    """An M4 hub screw through the 6 mm crank sheet: nominal 6 + 1.5 x 4 = 12 -> M4 x 12, but
    at 6.24 mm it needs 12.24 -> the next catalog length, 16; the hub's thread is cut for the
    thinnest crank, 16 - 5.76 = 10.24 mm. Machined, the same screw stays M4 x 12 (6 mm)."""
    from cad.families.fourbar.layers import hub_screw_length
    from cad.design import load_design

    d = _load(tmp_path, ("[parts]\n", '[parts]\nhub_screw = "M4-0.7"\n'))
    assert hub_screw_length(d.parts) == pytest.approx((16.0, 16 - (6 - AL6)))
    m = MACHINED.read_text().replace("[parts]\n", '[parts]\nhub_screw = "M4-0.7"\n')
    p = tmp_path / "m.toml"
    p.write_text(m)
    assert hub_screw_length(load_design(p).parts) == (12.0, 6.0)


def test_pin_stacks_over_band(tmp_path):
    """ISO 7379 M6 pin with washer (h 1.8) and nut (m 5.2), b 11, g2 2.5 (ISO 7379 / ISO 7089 /
    ISO 4032 via bd_warehouse): the shoulder's entry into a 5.76..6.24 mm lower bar must lie in
    max(1, 6.24 + 1.8 + 5.2 - 11) .. min(5.76 - 0.5, 5.76 + 1.8 - 2.5) = 2.24..5.06 mm; the
    head's 1 mm clearance over the upper bar drops by 0.24 mm at its thickest."""
    from cad.families.fourbar.pose import planar_transforms
    from cad.families.fourbar.sheet_tolerance import pin_rows, sheet_bands
    from cad.families.fourbar.layout import n_poses, plan_layers, sweep_angles
    from cad.kinematics.linkgeom import link_joints_mm

    d = _load(tmp_path)
    n = n_poses(d.parts, "preview")
    plan = plan_layers(d, link_joints_mm(d.linkage), planar_transforms(d.linkage, sweep_angles(d, n)),
                       n, strict=True)
    rows = {r["fastener"]: r for r in pin_rows(plan, d.parts, sheet_bands(d.parts))}
    assert set(rows) == {"pin_A2", "pin_A3", "pin_A4"}
    for j in ("pin_A2", "pin_A3"):
        assert rows[j]["entry_window_mm"] == pytest.approx([2.24, 5.06])
        assert 2.24 <= rows[j]["shoulder_entry_mm"] <= 5.06 and rows[j]["verdict"] == "holds"
        s = plan.joints[j[4:]]
        assert rows[j]["stack_height_mm"][2] - rows[j]["stack_height_mm"][0] == pytest.approx(2 * AL6)
        assert rows[j]["entry_window_mm"][1] - s.pin_length_mm + s.clamp_mm >= 0
    for r in rows.values():
        assert r["head_clearance_mm"] == pytest.approx([1.0 - AL6, 1.0])
    assert rows["pin_A4"]["entry_window_mm"] == [1.0, None]  # on the post: no bar below


def test_machined_unchanged():
    """process = "machined": no sheet, and every screw as before this change (regression pins:
    the hoeken.toml values at commit afbd453, before it)."""
    from cad.families.fourbar.layers import hub_screw_length
    from cad.families.fourbar.mechanism import check_plate_screws
    from cad.families.fourbar.sheet_tolerance import handle_min_engagement_mm, sheet_bands
    from cad.design import load_design

    parts = load_design(MACHINED).parts
    assert sheet_bands(parts) == {}
    assert [got for _, _, got in check_plate_screws(parts)] == [(8.0, 3.0), (10.0, 5.0), (16.0, 10.0)]
    assert hub_screw_length(parts) == (12.0, 6.0)
    assert handle_min_engagement_mm(parts, 1.5, 1.0) == 6.0  # min(1.5 x 4, max(6, 4))
