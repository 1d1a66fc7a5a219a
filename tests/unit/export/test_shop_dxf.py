"""Issue 25 section 2: profiles a shop can cut, read back with ezdxf.

A bore finished by reaming is cut undersize by the stock of the reaming-allowance table
(0-5 mm: 0.1, 5-20 mm: 0.2, 21-50 mm: 0.3, over 50 mm: 0.5 mm on the diameter, the low end
of each row; source in cad.data.fits.REAM_ALLOWANCE_SOURCE) with the note "ream to 8
H7"; a milled bearing seat carries its fit and depth; a tapped hole is cut at its tap drill
d - P (M4: 4 - 0.7 = 3.3 mm, ISO 2306) with its thread note; the NOTES layer states units,
material, thickness and quantity.
"""

from __future__ import annotations

import numpy as np
import pytest


@pytest.mark.parametrize(("d_mm", "stock_mm"), [(3.0, 0.1), (5.0, 0.1), (8.0, 0.2),
                                                (20.0, 0.2), (22.0, 0.3), (60.0, 0.5)])
def test_reaming_allowance_is_the_table_row(d_mm, stock_mm):
    from cad.data.fits import ream_allowance_mm

    assert ream_allowance_mm(d_mm) == stock_mm


def test_shop_holes_from_fits_and_threads():
    from cad.data.fits import shop_holes

    h = shop_holes(("bearing seat 16 J7", "pin bore 8 H7", "pin 8 m6", "pilot bore 22 H7"),
                   [("M4-0.7", 6.0), ("M4", 6.0)])
    assert [(x.finish, x.d_mm, x.cut_d_mm, x.note()) for x in h] == [
        ("mill", 16.0, 16.0, "mill bearing seat 16 J7"),
        ("ream", 8.0, pytest.approx(7.8, abs=1e-12), "ream to 8 H7"),
        ("bore", 22.0, pytest.approx(21.7, abs=1e-12), "bore to 22 H7"),
        ("tap", pytest.approx(3.3, abs=1e-12), pytest.approx(3.3, abs=1e-12), "tap M4"),
    ]  # the shaft (m6) is not a hole; one M4 thread of that depth


def test_dxf_cuts_the_reamed_bore_undersize_and_notes_the_seat_and_thread(tmp_path):
    """A plate (2 made) with an 8 H7 pin bore, a 16 J7 seat counterbored 2.5 mm from the top
    over a 14 mm through hole, and an M4 tapped hole, through the families' common writer."""
    import build123d as bd
    import ezdxf

    from cad.assembly.fasteners import TappedHole
    from cad.data.fits import fit
    from cad.parts import PartInstance, PartKind
    from cad.pipeline import family

    a = (bd.Align.CENTER, bd.Align.CENTER, bd.Align.MIN)
    plate = bd.Box(80, 30, 6, align=a)
    plate -= bd.Pos(-25, 0) * bd.Cylinder(4.0, 6, align=a)  # pin bore 8
    plate -= bd.Pos(0, 0) * bd.Cylinder(7.0, 6, align=a)  # seat shoulder 14
    plate -= bd.Pos(0, 0, 3.5) * bd.Cylinder(8.0, 2.5, align=a)  # seat 16, 2.5 deep
    plate -= bd.Pos(25, 0) * bd.Cylinder(3.3 / 2, 6, align=a)  # M4 tap drill
    kind = PartKind(name="shop_plate", shape=plate.wrapped, material="aluminium-6061",
                    made=True, plate=True,
                    fits=(fit("bearing seat", 16.0), fit("pin bore", 8.0)))
    inst = [PartInstance(f"shop_plate_{i}", kind, "ground", np.eye(4)) for i in (1, 2)]
    holes = (TappedHole("shop_plate_1:t", "shop_plate_1", "M4", 6.0, 4.0),)
    bom = family.bom_rows(inst, {"shop_plate": None})
    family.write_outputs(inst, {"ground": np.eye(4)}, tmp_path, {"dxf"}, name="t", title="t",
                         bom=bom, preview=False, holes=holes)
    msp = list(ezdxf.readfile(tmp_path / "parts" / "shop_plate.dxf").modelspace())
    cut = sorted((round(e.dxf.center.x, 9), e.dxf.radius) for e in msp
                 if e.dxftype() == "CIRCLE" and e.dxf.layer == "CUT")
    assert [c for c, _ in cut] == [-25.0, 0.0, 25.0]
    assert cut[0][1] == pytest.approx((8.0 - 0.2) / 2, abs=1e-12)  # reaming stock 0.2
    assert cut[1][1] == pytest.approx(7.0, abs=1e-12)  # plain through hole: as modelled
    assert cut[2][1] == pytest.approx((4.0 - 0.7) / 2, abs=1e-12)  # M4 tap drill d - P
    mill = [e for e in msp if e.dxf.layer.startswith("MILL")]
    assert [(e.dxf.layer, e.dxf.radius) for e in mill] == [("MILL_Z3.50_6.00", 8.0)]
    notes = [e.dxf.text for e in msp if e.dxf.layer == "NOTES"]
    assert notes[:5] == ["part: shop_plate", "units: mm", "material: aluminium-6061",
                         "thickness: 6.00 mm", "quantity: 2"]
    text = "\n".join(notes)
    assert "pin bore x1: cut at 7.8 (0.2 mm stock); ream to 8 H7" in text
    assert ("bearing seat x1: mill bearing seat 16 J7 (ISO 286), 2.50 deep from the top face, "
            "layer MILL_Z3.50_6.00") in text
    assert "M4 x1: cut at the tap drill 3.3; tap M4, full thread 6 deep" in text
    assert "ISO 2306" in text and "reaming" in text  # the sources of both allowances


def test_dowel_pin_designs_build_their_dxf_profiles(tmp_path):
    """designs/hoeken_light.toml (dowel-4 pins) with the default formats: a pressed dowel's
    hole is no thread (it was parsed as one: 'could not convert string to float: owel', so
    the bundled light and paper designs did not build). Its DXF profiles read back with ezdxf
    carry no tap note for the dowel and the reamed pin bores stay 0.1 mm undersize (4 mm row)."""
    import ezdxf
    from cli_helpers import hapticad

    from cad.data.fits import shop_holes

    assert [h.finish for h in shop_holes((), [("dowel-4", 8.0), ("M3-0.5", None)])] == ["tap"]
    root = __import__("pathlib").Path(__file__).resolve().parents[3]
    code, _, err = hapticad("build", root / "designs" / "hoeken_light.toml", "--fidelity", "preview",
                            "--formats", "dxf", "--out", tmp_path / "o")
    assert code == 0, err
    for name in ("crank", "coupler"):
        msp = ezdxf.readfile(tmp_path / "o" / "parts" / f"{name}.dxf").modelspace()
        notes = [e.dxf.text for e in msp.query("TEXT MTEXT")]
        assert "pin bore x1: cut at 3.9 (0.1 mm stock); ream to 4 H7" in notes
        assert not [t for t in notes if "tap" in t and "tap M" not in t and "tap drill" not in t]
        radii = {round(c.dxf.radius, 6) for c in msp.query("CIRCLE")}
        assert (4.0 - 0.1) / 2 in radii and 2.0 not in radii  # the 4 H7 bore cut 0.1 mm under
