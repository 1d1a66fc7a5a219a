"""The four-bar crank hub's ISO 4026 set screw: sized like the pantograph clevis set screw
(:func:`cad.assembly.fasteners.size_set_screw`), checked against independent references.

References, not the build's code path:
* bd_warehouse's ISO 4026 catalog read straight from its CSVs (``setscrew_parameters.csv``
  short..long of the size within the ``iso4026`` row of ``nominal_screw_lengths.csv``);
* the closed form of a radial hole through a round hub of radius R onto a shaft of radius
  r: the full thread (major diameter d all round) ends sqrt(R^2 - (d/2)^2) from the shaft
  axis, so the hole depth is that minus r, and the longest catalog length L with
  1.5 d <= L <= depth is used (its end never proud of the hub);
* the written ``assembly.step`` of the bundled Hoeken re-read with OCCT's XCAF reader
  (``tests/step_pairs.radial_screw_mm``: point classification round the screw's axis).
Build: ``conftest.hoeken_sim_build`` (shared, preview fidelity, with STEP).
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import pytest
from catalog_ref import iso4026_lengths_mm
from cli_helpers import assert_one_line_error, hapticad
from step_pairs import radial_screw_mm, read_parts

ROOT = Path(__file__).resolve().parents[3]
#: Thread diameters of the sizes the four-bar hub may take, M3 first (ISO 261 coarse).
SIZES_D_MM = {"M3-0.5": 3.0, "M2.5-0.45": 2.5, "M2-0.4": 2.0}


def _closed_form(r_mm: float, R_mm: float):
    """(size, L, depth) of the largest size with a catalog length in [1.5 d, depth], or None."""
    for size, d in SIZES_D_MM.items():
        depth = math.sqrt(R_mm**2 - (d / 2) ** 2) - r_mm
        fit = [L for L in iso4026_lengths_mm(size) if 1.5 * d <= L <= depth]
        if fit:
            return size, max(fit), depth
    return None


def _hoeken(**parts):
    from cad.design import load_design

    d = load_design(ROOT / "designs" / "hoeken.toml")
    return dataclasses.replace(d, parts=dataclasses.replace(d.parts, **parts))


@pytest.mark.parametrize(
    ("hub_mm", "size", "length_mm"),
    # 20: M3 depth 6.887 -> 6; 17: 5.367 -> 5; 16: M3 4.858 (no M3 length in 4.5..4.858),
    # M2.5 4.902 -> 4; 14: M2.5 3.888 (3.5 < 1.5 d = 3.75 < 4), M2 3.928 -> 3.5; 13: M2 -> 3
    [(20.0, "M3-0.5", 6.0), (17.0, "M3-0.5", 5.0), (16.0, "M2.5-0.45", 4.0),
     (14.0, "M2-0.4", 3.5), (13.0, "M2-0.4", 3.0)],
)
def test_hub_set_screw_sizing_against_the_closed_form(hub_mm, size, length_mm):
    from cad.families.fourbar.layers import hub_set_screw

    ss = hub_set_screw(_hoeken(hub_diameter_mm=hub_mm).parts)
    size_ref, L_ref, depth_ref = _closed_form(3.0, hub_mm / 2)  # RE 35: 6 mm shaft
    assert (ss.size, ss.length_mm) == (size_ref, L_ref) == (size, length_mm)
    assert ss.depth_mm == pytest.approx(depth_ref, abs=1e-12)
    assert ss.min_engagement_mm == 1.5 * SIZES_D_MM[size] and ss.shaft_radius_mm == 3.0
    assert 3.0 + ss.length_mm <= math.sqrt((hub_mm / 2) ** 2 - (SIZES_D_MM[size] / 2) ** 2)


def test_hub_set_screw_record_bom_and_hole_of_the_hoeken_build(hoeken_sim_build):
    """The bundled Hoeken (20 mm hub, 6 mm RE 35 shaft): M3 full thread ends at
    sqrt(10^2 - 1.5^2) = 9.887 mm from the axis, a 6.887 mm hole; ISO 4026 M3 lengths
    ... 6, 8: L = 6 (>= 1.5 d = 4.5)."""
    d, _, rep, _ = hoeken_sim_build
    assert (d.parts.hub_diameter_mm, d.parts.motor) == (20.0, "maxon-re35")
    depth = math.sqrt(10.0**2 - 1.5**2) - 3.0
    L = max(x for x in iso4026_lengths_mm("M3-0.5") if 4.5 <= x <= depth)
    assert L == 6.0
    sets = {n: x for n, x in rep["fasteners"].items() if x["kind"] == "ISO 4026"}
    assert sets == {"hub_set_screw": {"kind": "ISO 4026", "size": "M3-0.5", "length_mm": L,
                                      "clamps": ["motor_shaft"], "hole": "crank_hub:set_screw",
                                      "engagement_mm": L}}
    h = rep["tapped_holes"]["crank_hub:set_screw"]
    assert h["part"] == "crank_hub" and h["size"] == "M3-0.5"
    assert h["depth_mm"] == pytest.approx(depth, abs=1e-9) and h["min_engagement_mm"] == 4.5
    bom = {r["part"]: r for r in rep["bom"]}
    assert bom["set_screw_M3-0.5x6"]["description"].startswith("set screw ISO 4026 M3-0.5 x 6 ")
    assert bom["set_screw_M3-0.5x6"]["made_or_bought"] == "bought"
    assert "tap M3 x1 (radial)" in bom["crank_hub"]["process"]


def test_hub_set_screw_measured_in_the_step_file(hoeken_sim_build):
    """The set screw read back from the Hoeken's assembly.step: its point 3 mm from the shaft
    axis (the point just beyond it inside the shaft), 6 mm long, its end's rim at d/2 inside
    the 10 mm hub (nothing proud), full M3 thread round it in the hub over the recorded hole
    depth (6.887 mm, to 0.01 mm), so the whole recorded length is engaged."""
    d, out, rep, _ = hoeken_sim_build
    parts = dict(read_parts(out / "assembly.step"))
    x = rep["fasteners"]["hub_set_screw"]
    m = radial_screw_mm(parts["hub_set_screw"], parts["crank_hub"], parts["motor_shaft"], 3.0)
    assert m["tip_to_axis_mm"] == pytest.approx(3.0, abs=1e-3) and m["tip_on_shaft"], m
    assert m["length_mm"] == pytest.approx(x["length_mm"], abs=1e-3)
    assert m["rim_to_axis_max_mm"] <= d.parts.hub_diameter_mm / 2, m
    depth = rep["tapped_holes"][x["hole"]]["depth_mm"]
    assert m["full_thread_mm"] == pytest.approx(depth, abs=0.01), m
    assert min(m["length_mm"], m["full_thread_mm"]) == pytest.approx(x["engagement_mm"], abs=0.01)


@pytest.mark.parametrize("allow_interference", [False, True])
def test_hub_too_thin_for_a_set_screw_is_refused_before_cad(tmp_path, monkeypatch,
                                                            allow_interference):
    """A 12 mm hub on the 6 mm shaft: 3 mm wall, 2.92 mm of full M2 thread < 1.5 d = 3 mm.
    (The design file's own check refuses such a hub already for its hub screws; a spec made
    in code reaches the build.) Refused before any CAD import, nothing written."""
    import cad.parts.lazy_import as li
    from cad.errors import DesignError
    from cad.pipeline import build_design

    monkeypatch.setattr(li, "import_build123d", lambda: pytest.fail("CAD imported"))
    with pytest.raises(DesignError) as e:
        build_design(_hoeken(hub_diameter_mm=12.0), tmp_path / "o", {"step"},
                     allow_interference=allow_interference, use_cache=False)
    msg = str(e.value)
    assert "\n" not in msg and not (tmp_path / "o").exists()
    assert msg.startswith("parts.hub_diameter_mm: crank hub set screw onto the motor shaft")
    assert "(2.92 mm of full M2 thread)" in msg
    assert _closed_form(3.0, 6.0) is None


def test_hub_no_allowed_set_screw_fits_exits_2_from_the_cli(tmp_path, monkeypatch):
    """Through the CLI: M2 hub screws let the design file take a 15 mm hub; with the hub
    limited to M3 set screws (4.35 mm of full M3 thread < 1.5 d = 4.5) the build exits 2,
    one line naming parts.hub_diameter_mm, no CAD import, nothing written."""
    import cad.families.fourbar.layers as layers
    import cad.parts.lazy_import as li

    monkeypatch.setattr(layers, "HUB_SET_SCREW_SIZES", ("M3-0.5",))
    monkeypatch.setattr(li, "import_build123d", lambda: pytest.fail("CAD imported"))
    toml = (ROOT / "designs" / "hoeken.toml").read_text()
    src = tmp_path / "thin_hub.toml"
    src.write_text(toml.replace("[parts]\n", '[parts]\nhub_screw = "M2-0.4"\n'
                                             "hub_diameter_mm = 15.0\n", 1))
    code, _, err = hapticad("build", src, "--out", tmp_path / "out", "--no-cache")
    assert_one_line_error(code, err, "parts.hub_diameter_mm", "crank hub set screw",
                          "(4.35 mm of full M3 thread)")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["thin_hub.toml"]


def test_shaft_engagement_too_short_for_the_set_screw_hole_exits_2(tmp_path, monkeypatch):
    """The hub's M3 set screw sits at half the shaft engagement: a 3.5 mm engagement puts
    its 3 mm hole within 0.25 mm of the hub's bottom face (< 0.5 mm): d + 1 = 4 mm is the
    least, refused before any CAD naming the key, nothing written."""
    import cad.parts.lazy_import as li

    monkeypatch.setattr(li, "import_build123d", lambda: pytest.fail("CAD imported"))
    toml = (ROOT / "designs" / "hoeken.toml").read_text()
    src = tmp_path / "short.toml"
    src.write_text(toml.replace("[parts]\n", "[parts]\nhub_shaft_engagement_min_mm = 3.5\n", 1))
    code, _, err = hapticad("build", src, "--out", tmp_path / "out", "--no-cache")
    assert_one_line_error(code, err, "parts.hub_shaft_engagement_min_mm: 3.5 mm", ">= 4 mm")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["short.toml"]
    from cad.families.fourbar.layers import hub_set_screw

    assert hub_set_screw(_hoeken(hub_shaft_engagement_min_mm=4.0).parts).size == "M3-0.5"
