"""Printed made parts (``parts.process = "printed"``, issue 25 §3).

* the wall/infill layer model against hand computations: a box, a box with a through hole,
  and a bar with a counterbored seat (closed form of walls, skins and core, layer by layer);
* the printed bar modulus against the rule of mixtures computed by hand;
* parts.3mf read back (zip + XML, and lib3mf): the flipped item rotated 180 deg about x,
  resting on z = 0, with its orientation metadata; no metadata without printed parts;
* the BOM wording of the printed Hoeken, the warning for tests/cases hoeken_pla, and the
  machined default unchanged (process texts, fits, 3MF bytes, parts_spec keys).
"""

from __future__ import annotations

import io
import math
import zipfile
from pathlib import Path
from xml.etree import ElementTree

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]
PLA_CASE = ROOT / "tests" / "cases" / "silent-limits" / "hoeken_pla.toml"
NS = {"m": "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"}


def _settings(**kw):
    from cad.printing import PrintSettings

    return PrintSettings(**kw)


@pytest.mark.parametrize("L,W,T", [(100.0, 20.0, 8.0), (40.0, 12.0, 5.0)])
def test_box_core_and_mass_closed_form(L, W, T):
    """Box L x W x T printed flat: core (L - 2w)(W - 2w)(T - 2 n h), w = 2 x 0.45 mm,
    n = 4 layers of h = 0.2 mm; mass = rho (V - 0.8 core) at 20 % infill."""
    from build123d import Box

    from cad.parts.printed import printed_core_mm3, printed_mass_kg

    s = _settings()
    core = (L - 1.8) * (W - 1.8) * (T - 1.6)
    assert printed_core_mm3(Box(L, W, T), s) == pytest.approx(core, rel=1e-9)
    m = 1240.0 * (L * W * T - 0.8 * core) * 1e-9
    assert printed_mass_kg(Box(L, W, T), 1240.0, s) == pytest.approx(m, rel=1e-9)


def test_box_with_hole_core():
    """A 4 mm radius through hole grows by the wall: core area (L-2w)(W-2w) - pi (r + w)^2."""
    from build123d import Box, Cylinder

    from cad.parts.printed import printed_core_mm3

    s = _settings(walls=3, line_width_mm=0.4)  # w = 1.2 mm
    w = 1.2
    core = ((60 - 2 * w) * (20 - 2 * w) - math.pi * (4 + w) ** 2) * (8 - 1.6)
    got = printed_core_mm3(Box(60, 20, 8) - Cylinder(4, 8), s)
    assert got == pytest.approx(core, rel=1e-6)  # 1e-6: the hole is a true circle in OCCT


def test_counterbored_bar_core_layer_by_layer():
    """A bar with a through hole of radius r and, from the top, a counterbore of radius R and
    depth d (a bearing seat): layer k has core where layers k-n..k+n all have material,
    shrunk by w; the hole of that window is R if any of its layers is in the counterbore."""
    from build123d import Box, Cylinder, Pos

    from cad.parts.printed import printed_core_mm3

    L, W, T, r, R, d = 60.0, 24.0, 8.0, 4.0, 8.0, 4.0
    part = Box(L, W, T) - Cylinder(r, T) - Pos(0, 0, T / 2 - d / 2) * Cylinder(R, d)
    s = _settings()
    w, h, n, N = 0.9, 0.2, 4, 40
    z = (np.arange(N) + 0.5) * h
    in_cb = z > T - d
    core = 0.0
    for k in range(n, N - n):
        hole = R if in_cb[k - n : k + n + 1].any() else r
        core += ((L - 2 * w) * (W - 2 * w) - math.pi * (hole + w) ** 2) * h
    assert printed_core_mm3(part, s) == pytest.approx(core, rel=1e-6)


def test_printed_bar_modulus_rule_of_mixtures():
    """20 x 8 mm bar, E_s 2.539 GPa: shell 160 - 18.2 x 6.4 mm^2 solid, core at f^2 = 0.04."""
    from cad.printing import printed_bar_modulus_GPa

    s = _settings()
    a_core = (20 - 1.8) * (8 - 1.6)
    want = 2.539 * ((160 - a_core) + 0.04 * a_core) / 160
    assert printed_bar_modulus_GPa(2.539, 20.0, 8.0, s) == pytest.approx(want, rel=1e-12)
    assert printed_bar_modulus_GPa(2.539, 20.0, 8.0, _settings(infill_percent=100)) == pytest.approx(2.539)


def _box_mesh(L, W, T, z0):
    import trimesh

    b = trimesh.creation.box((L, W, T))
    return np.asarray(b.vertices) + [0, 0, z0 + T / 2], np.asarray(b.faces)


def _model(data: bytes):
    with zipfile.ZipFile(io.BytesIO(data)) as z:
        return ElementTree.fromstring(z.read("3D/3dmodel.model"))


def test_3mf_orientation_read_back():
    """A flipped printed part: its item rotates 180 deg about x and rests on z = 0 (its top
    face on the bed); the object carries the orientation and settings; lib3mf reads it."""
    import lib3mf

    from cad.export.threemf import threemf_bytes

    v, f = _box_mesh(30, 10, 6, z0=2.0)  # part frame z 2..8
    data = threemf_bytes([("bar", v, f, 1), ("post", v, f, 1)], "t",
                         {"bar": (True, "FDM print PLA: 0.2 mm layers")})
    root = _model(data)
    items = root.findall("m:build/m:item", NS)
    m = np.array([float(x) for x in items[0].get("transform").split()])
    rot, t = m[:9].reshape(3, 3), m[9:]
    np.testing.assert_array_equal(rot, np.diag([1.0, -1.0, -1.0]))
    placed = v @ rot + t  # 3MF: row vector times the matrix
    assert placed[:, 2].min() == pytest.approx(0.0, abs=1e-9)
    top = v[:, 2] == v[:, 2].max()
    assert np.allclose(placed[top, 2], 0.0)  # the part's top face is on the bed
    np.testing.assert_array_equal(np.array(items[1].get("transform").split()[:9], float),
                                  np.eye(3).ravel())  # not printed: as modelled
    meta = {e.get("name"): e.text for e in root.iter(f"{{{NS['m']}}}metadata")}
    assert meta["hapticad:print_orientation"].startswith("flipped")
    assert meta["hapticad:print_settings"] == "FDM print PLA: 0.2 mm layers"
    model = lib3mf.get_wrapper().CreateModel()
    model.QueryReader("3mf").ReadFromBuffer(bytearray(data))
    it = model.GetBuildItems()
    assert it.MoveNext()
    tf = it.GetCurrent().GetObjectTransform()
    assert [tf.Fields[i][i] for i in range(3)] == pytest.approx([1.0, -1.0, -1.0])


def test_3mf_without_printed_parts_has_no_print_metadata():
    from cad.export.threemf import model_xml

    v, f = _box_mesh(30, 10, 6, z0=0.0)
    xml = model_xml([("bar", v, f, 1)], "t")
    assert xml == model_xml([("bar", v, f, 1)], "t", {})
    assert "metadatagroup" not in xml and "hapticad:" not in xml
    assert 'transform="1 0 0 0 1 0 0 0 1 ' in xml


@pytest.fixture(scope="module")
def printed_kinds(tmp_path_factory):
    """designs/hoeken_printed.toml with an aluminium hub (its radial set-screw hole makes every
    layer across it its own section: ~10 s of the layer model, left to the build)."""
    from cad.design import load_design
    from cad.families.fourbar.inertia import inertia_assembly

    text = (ROOT / "designs" / "hoeken_printed.toml").read_text()
    p = tmp_path_factory.mktemp("printed") / "hoeken_printed.toml"
    p.write_text(text.replace('hub_material = "pla"', 'hub_material = "aluminium-6061"'))
    return inertia_assembly(load_design(p), "preview").kinds()


def test_bom_process_says_what_to_print(printed_kinds):
    """Every made PLA part: the print settings and orientation, no plate cutting or tapping."""
    made = {n: k for n, k in printed_kinds.items() if k.made}
    assert {"crank", "coupler", "rocker", "base_plate", "post_A4", "handle"} <= set(made)
    assert made.pop("crank_hub").process.startswith("turned")  # aluminium: machined as before
    for n, k in made.items():
        assert k.process.startswith("FDM print PLA: 0.2 mm layers, 2 walls x 0.45 mm, 4 top/bottom "
                                    "layers, 20 % infill, oriented "), n
        assert "waterjet" not in k.process and "tap M" not in k.process, n
        assert k.print_flip is not None, n
    c = made["coupler"]
    assert "bearing seat x1 printed 16.1 mm (press fit" in c.process  # 16 + 0.2 - 0.1
    assert "pin bore x1 printed 8.2 mm" in c.process
    assert "M4 heat-set insert x1 in the 5.6 mm hole" in c.process
    assert "pin bore 8 printed 8.2 (slip fit, not H7)" in c.fits
    assert "M3 heat-set insert x4: drill the printed tap hole to the 4 mm pilot" in made["base_plate"].process


def test_printed_bar_mass_is_the_layer_model(printed_kinds):
    """The crank's mass is the layer model's, below the solid block's (pockets make it mostly
    walls, so the gain is the core's 80 % only)."""
    from cad.parts.part_props import part_mass_props
    from cad.parts.printed import printed_mass_kg

    k = printed_kinds["crank"]
    solid = part_mass_props(k.shape.solid_for_props() if hasattr(k.shape, "solid_for_props")
                            else k.shape, 1240.0).mass_kg
    assert k.mass_kg == pytest.approx(printed_mass_kg(k.shape, 1240.0, _settings()), rel=1e-12)
    assert 0.2 * solid < k.mass_kg < solid


def test_hoeken_pla_case_warns_and_prints():
    """shared/cases/silent-limits/hoeken_pla.toml (every made part PLA, process unset): one
    warning per material naming the parts and the features changed; the bars are printed."""
    from cad.design import bounds, load_design

    bounds.reset()
    d = load_design(PLA_CASE)
    w = bounds.collected()
    bar = [x for x in w if x.startswith("parts.bar_material = 'pla' is a printing filament")]
    assert len(bar) == 1
    assert "crank, coupler, rocker are FDM printed instead" in bar[0]
    assert "reamed H7 pin bores printed 0.2 mm over" in bar[0]
    assert any(x.startswith("parts.hub_material = 'pla'") and "heat-set inserts" in x for x in w)
    assert d.parts.printed("pla") and d.parts.process == "machined"
    bounds.reset()


def test_machined_default_unchanged():
    """The bundled aluminium Hoeken: the machined texts and ISO 286 fits of before, nothing
    printed, no print keys in parts_spec, and parts.3mf without print metadata."""
    from cad.data.fits import fit
    from cad.design import load_design
    from cad.export.threemf import print_orientations
    from cad.families.fourbar.inertia import inertia_assembly

    d = load_design(ROOT / "designs" / "hoeken.toml")
    asm = inertia_assembly(d, "preview")
    k = asm.kinds()
    assert k["crank"].process == "waterjet/laser 6 mm plate; ream pin bore x1"
    assert k["coupler"].process == ("waterjet/laser 6 mm plate; mill bearing seat x1; "
                                    "ream pin bore x1; tap M4 x1")
    assert k["coupler"].fits == (fit("bearing seat", 16.0), fit("pin bore", 8.0))
    assert k["base_plate"].process == "waterjet/laser 6 mm plate; tap M3 x4"
    assert all(x.print_flip is None and x.mass_kg is None for x in k.values() if x.made)
    assert print_orientations(asm.instances) == {}
    assert not {"process", "print_walls"} & set(d.parts.as_dict(report=True))  # report.json


@pytest.mark.parametrize("table,field", [
    ({"process": "laser", "bar_thickness_mm": 7.0}, "parts.bar_thickness_mm"),  # not stock
    ({"process": "milled"}, "parts.process"),
    ({"print_infill_percent": 120}, "parts.print_infill_percent"),
    ({"print_walls": 0}, "parts.print_walls"),
])
def test_bad_process_keys_name_the_field(table, field):
    from cad.design.parts import parse_parts
    from cad.errors import DesignError

    with pytest.raises(DesignError) as e:
        parse_parts(table)
    assert e.value.field == field
