"""Numbers typed in docs/fabrication.md, recomputed from the code and catalogs they describe at
the printed rounding (issue 34 §4): the printed-part and sheet material tables against
cad/printing.py and cad/data/materials.py (where each value's source is named), the shop
allowances and nesting constants against cad/data/fits.py and cad/tolerances.py, and the
swap refusal against the command's own output. No CAD build; a few seconds in all."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGE = "docs/fabrication.md"
RAW = (ROOT / PAGE).read_text(encoding="utf-8")
TEXT = " ".join(RAW.split())


def row(first_cell: str) -> str:
    """The one table line of the page whose first cell is ``first_cell``."""
    found = [ln for ln in RAW.splitlines() if ln.startswith(f"| {first_cell} |")]
    assert len(found) == 1, f"{len(found)} rows start with {first_cell!r}"
    return found[0]


def test_printed_materials_row_is_the_filament_table():
    """The printed moduli and the sources they are cited from (cad/printing.py FILAMENTS)."""
    from cad.printing import FILAMENTS
    r = row("materials")
    for name, label, source in (("pla", "PLA (E = ", "Pro3D"), ("petg", "PETG (", "CR-3D"), ("abs", "ABS (", "Stratasys")):
        f = FILAMENTS[name]
        shown = re.search(re.escape(label) + r"([\d.]+) GPa", r).group(1)
        assert float(shown) == pytest.approx(f.E_xy_GPa, abs=0.5 * 10 ** -len(shown.split(".")[1])), name
        assert source in f.source and source in r


def test_printed_holes_row_is_the_print_settings_and_insert_chart():
    """Hole compensation, press fit, heat-set pilots and the FDM tolerance (cad/printing.py,
    cad/tolerances.py FDM_TOL_*)."""
    from cad import tolerances as tol
    from cad.printing import HEAT_SET_PILOT_MM, PrintSettings
    r = row("holes and seats")
    s = PrintSettings()
    assert f"holes modelled +{s.hole_compensation_mm:g} mm" in r
    assert f"bearing seats D + {s.hole_compensation_mm:g} − {s.press_fit_mm:g} mm" in r
    pilots = dict(re.findall(r"(M\d) ([\d.]+)", r.split("pilot ")[1].split(" mm")[0]))
    assert pilots and all(float(v) == HEAT_SET_PILOT_MM[k] for k, v in pilots.items())
    assert f"FDM tolerance ±{tol.FDM_TOL_MM:g} mm or ±{100 * tol.FDM_TOL_REL:g} %" in r


def test_sheet_materials_table_is_the_sheet_catalog():
    """Every number of the sheet table: density (MATERIALS), E and strength, stock thicknesses,
    tolerance bands, sizes, kerf (SHEETS), each where its source states it."""
    from cad.data.materials import MATERIALS, SHEETS
    for name in SHEETS:
        s, m = SHEETS[name], MATERIALS[name]
        r = row(f"`{name}`" + (" (PMMA)" if name == "acrylic-cast" else ""))
        cells = [c.strip() for c in r.strip("|").split("|")]
        rho = m.density_kg_m3 / 1000
        assert cells[1].startswith(f"{rho:.2f}"), name
        assert f"{s.E_GPa:g} GPa" in cells[2] or f"{s.E_GPa:.2f} GPa" in cells[2], name
        assert f"{s.strength_MPa:g} MPa" in cells[2], name
        assert f"{s.kerf_mm:g} mm" in cells[5], name
        if cells[3].startswith("as "):
            assert SHEETS[f"aluminium-{cells[3].split()[1]}"].thickness_range_mm == s.thickness_range_mm
            continue
        listed = [float(t) for t in cells[3].split(" mm")[0].split(", ")]
        assert listed == sorted(s.thickness_range_mm), name
        for t, lo, hi in re.findall(r"([\d.]+) mm(?: is|:) ([\d.]+)–([\d.]+) mm", cells[3]):
            assert s.thickness_range_mm[float(t)] == (float(lo), float(hi)), (name, t)
        for t, pm in re.findall(r"([\d.]+) mm ±([\d.]+)", cells[3]):
            lo, hi = s.thickness_range_mm[float(t)]
            assert hi - float(t) == pytest.approx(float(pm)) and float(t) - lo == pytest.approx(float(pm))
        sizes = re.findall(r"(\d+) × (\d+)", cells[4])
        assert {tuple(sorted(map(float, z))) for z in sizes} == {tuple(sorted(z)) for z in s.sizes_mm}, name
    r5083 = row("`aluminium-5083`")
    assert "0.2 % proof" in r5083 and "0.2 % proof" in SHEETS["aluminium-5083"].source["strength_MPa"]
    assert "0.1–0.2 mm" in r5083 and "0.1-0.2 mm" in SHEETS["aluminium-5083"].source["kerf_mm"]
    assert "1000–1250 mm wide" in r5083 and "over 1000 up to 1250 mm" in SHEETS["aluminium-5083"].source["thickness_range_mm"]
    ply = row("`birch-plywood`")
    assert "0.66–0.71 by thickness" in ply and "660-710 kg/m^3" in MATERIALS["birch-plywood"].source
    assert "**unverified**" in ply and "unverified" in SHEETS["birch-plywood"].source["E_GPa"]


def test_laser_cut_sizes_are_the_catalog_ones():
    from cad.data.materials import LASER_CUT_SIZES_MM
    shown = re.findall(r"([\d.]+) × ([\d.]+) mm \(\d+ × \d+ in", TEXT)
    assert [tuple(map(float, z)) for z in shown] == [tuple(z) for z in LASER_CUT_SIZES_MM]


def test_reaming_allowance_sentence_is_the_fits_table():
    from cad.data.fits import REAM_ALLOWANCE_MM
    rows = re.findall(r"(\d+)–(\d+) mm: ([\d.]+)", TEXT.split("undersize of reaming")[1][:200])
    over = re.search(r"over (\d+) mm: ([\d.]+) mm on the diameter", TEXT)
    ends = [float(b) for _, b, _ in rows] + [float("inf")]
    allow = [float(a) for *_, a in rows] + [float(over.group(2))]
    assert list(zip(ends, allow, strict=True)) == list(REAM_ALLOWANCE_MM)
    assert float(over.group(1)) == REAM_ALLOWANCE_MM[-2][0]
    pin = re.search(r"pin bore x1: cut at ([\d.]+) \(([\d.]+) mm stock\); ream to (\d+) H7", TEXT)
    from cad.data.fits import ream_allowance_mm
    d = float(pin.group(3))
    assert float(pin.group(2)) == ream_allowance_mm(d) and float(pin.group(1)) == d - ream_allowance_mm(d)


def test_nesting_and_label_constants_are_the_tolerances():
    from cad import tolerances as tol
    assert f"grown by a {tol.NEST_GAP_MM:g} mm gap (`NEST_GAP_MM`" in TEXT
    assert f"less a {tol.NEST_EDGE_MARGIN_MM:g} mm edge margin (`NEST_EDGE_MARGIN_MM`" in TEXT
    assert (f"({tol.LABEL_CHAR_WIDTH:.1f} h per character × h, {tol.LABEL_CLEARANCE_MM:g} mm clear) lies in "
            f"material -- tried from {tol.LABEL_HEIGHTS_MM[0]:g} mm high down to {tol.LABEL_HEIGHTS_MM[-1]:g} mm") in TEXT


def test_swap_refusal_example_is_what_swap_prints(tmp_path):
    """The swap example's crank length and the stroke that clears it, from the command itself
    (refused before anything is written)."""
    m = re.search(r"`swap designs/(\w+)\.toml --to ([\w-]+)`: the ([\d.]+) mm crank puts the A2 washer and nut "
                  r"in the hub, `stroke_mm >= ([\d.]+) clears it`", TEXT)
    proc = subprocess.run([sys.executable, "-m", "cad", "swap", f"designs/{m.group(1)}.toml", "--to", m.group(2),
                           "--out", str(tmp_path / "swapped.toml")], cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 2 and proc.stdout == "" and not any(tmp_path.iterdir())
    crank = float(re.search(r"crank l1 ([\d.]+) ->", proc.stderr).group(1))
    assert f"{crank:.1f}" == m.group(3)
    assert f"stroke_mm >= {m.group(4)} clears it" in proc.stderr
    assert "A2 washer+nut (crank) and the hub (crank) overlap" in proc.stderr


def test_largest_laser_plate_is_the_datasheet_base_plate():
    """"The Hoeken's plates (largest: the W × L mm base plate)": the base plate's size as the
    committed datasheet run of designs/hoeken_laser.toml names it (its footprint row, the
    capture the page's generated table renders; a regression pin of our own run)."""
    import json
    rows = json.loads((ROOT / "docs/datasheets/hoeken_laser.json").read_text())["datasheet"]["rows"]
    fig, = (r["figure"] for r in rows if r["key"] == "footprint_mm2")
    width, length = re.search(r"base plate (\d+) x (\d+) mm", fig).groups()
    assert f"(largest: the {width} × {length} mm base plate)" in TEXT


def test_handle_screw_engagement_is_the_thinnest_coupler_sheet():
    """The laser Hoeken's handle screw row: the screw takes the whole thinnest coupler plate, so
    its engagement is t_min of the 6 mm 5083 sheet's EN 485-4 band (cad/data/materials.py)."""
    from cad.data.materials import SHEETS
    t_min = SHEETS["aluminium-5083"].thickness_range_mm[6.0][0]
    assert f"| handle screw M4 × 12 | thread in the 6 mm coupler | {t_min:.2f} mm | {t_min:.2f} mm |" in RAW
