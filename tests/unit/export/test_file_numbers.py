"""The numbers written in the files, read as text (issue 21 §4), not through OCCT.

A round trip through OCCT hides a colour-space slip (its STEP writer and reader convert
the same way), so these tests parse the written bytes:

* ``assembly.step``: every ``COLOUR_RGB`` entity against the material table. STEP colours
  are display (sRGB-encoded) values: OCCT's writer encodes its linear ``Quantity_Color`` to
  sRGB (CadQuery issue #794: a colour given as 0.5 through ``Quantity_TOC_RGB`` is written
  0.735356983052), so a table value must enter through ``Quantity_TOC_sRGB``.
* ``assembly.glb`` and the copy inside ``report.html``: ``baseColorFactor`` is LINEAR RGB
  (glTF 2.0 spec, 3.9.2 "The base color ... linear"), so it must be the table colour
  decoded with the sRGB transfer function of IEC 61966-2-1 (:func:`_srgb_to_linear`,
  written out here independently of the code).
* ``parts.3mf`` vertices, parsed from the zip's XML, against the mesh given, to 1e-3 mm
  on a 1 m part.
"""

from __future__ import annotations

import base64
import io
import json
import re
import zipfile
from pathlib import Path
from xml.etree import ElementTree

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]

#: OCCT keeps a Quantity_Color as three float32: a value comes back within ~1e-8; 1e-6
#: is far below the 0.02-0.12 an sRGB encoding slip moves a channel by.
STEP_COLOUR_ATOL = 1e-6


def _srgb_to_linear(c):
    """IEC 61966-2-1:1999 sRGB decoding: c / 12.92 for c <= 0.04045, else
    ((c + 0.055) / 1.055) ** 2.4."""
    c = np.asarray(c, dtype=float)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def _linear_to_srgb(c):
    """Its inverse (IEC 61966-2-1): 12.92 c for c <= 0.0031308, else 1.055 c^(1/2.4) - 0.055."""
    c = np.asarray(c, dtype=float)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)


def _hex(h):
    return np.array([int(h[i:i + 2], 16) / 255 for i in (1, 3, 5)])


def test_reference_transfer_function_matches_published_values():
    """The reference above against numbers printed elsewhere: CadQuery #794 (OCCT wrote
    linear 0.5 as 0.735356983052) and issue 21 (#d9534f taken as linear shows as #ee9b97)."""
    assert _srgb_to_linear(0.735356983052) == pytest.approx(0.5, abs=1e-9)
    shown = np.round(_linear_to_srgb(_hex("#d9534f")) * 255).astype(int)
    assert "#" + "".join(f"{c:02x}" for c in shown) == "#ee9b97"


@pytest.fixture(scope="module")
def hoeken(tmp_path_factory):
    """The bundled Hoeken, preview fidelity, with STEP and the glb (and report.html)."""
    from cad.design import load_design
    from cad.pipeline import build_design

    out = tmp_path_factory.mktemp("numbers") / "hoeken"
    d = load_design(ROOT / "designs" / "hoeken.toml")
    build_design(d, out, {"step", "glb"}, fidelity="preview", use_cache=False)
    return out, json.loads((out / "report.json").read_text())


def _step_colours(path: Path) -> list[tuple[float, float, float]]:
    """The distinct ``COLOUR_RGB('', r, g, b)`` triples of a STEP file, sorted."""
    num = r"([-+0-9.Ee]+)"
    return sorted({tuple(float(x) for x in m) for m in
                   re.findall(rf"COLOUR_RGB\('[^']*',{num},{num},{num}\)", path.read_text())})


def test_assembly_step_colours_are_the_table(hoeken):
    """Every COLOUR_RGB of assembly.step is a table colour of a material the assembly uses,
    and every such colour is written (aluminium 0.78, not its sRGB encoding 0.896); each
    part's STEP carries its material's colour."""
    from cad.data.materials import MATERIALS

    out, rep = hoeken
    got = _step_colours(out / "assembly.step")
    want = sorted({MATERIALS[m].color_rgb for m in set(rep["part_materials"].values())})
    assert len(got) == len(want) >= 3
    np.testing.assert_allclose(got, want, rtol=0, atol=STEP_COLOUR_ATOL)
    rows = [r for r in rep["bom"] if (out / "parts" / f"{r['part']}.step").is_file()]
    assert {"crank", "coupler", "rocker"} <= {r["part"] for r in rows}
    for row in rows:  # each part's own STEP (written through build123d's Color)
        np.testing.assert_allclose(_step_colours(out / "parts" / f"{row['part']}.step"),
                                   [MATERIALS[row["material"]].color_rgb], rtol=0,
                                   atol=STEP_COLOUR_ATOL, err_msg=row["part"])
    alu = MATERIALS["aluminium-6061"].color_rgb[0]
    assert abs(float(_linear_to_srgb(alu)) - alu) > 100 * STEP_COLOUR_ATOL  # the slip shows


def _glb_colours(gl):
    """``{node name: (body, mesh name, baseColorFactor)}`` of every part node of the glb."""
    parent = {c: i for i, n in enumerate(gl.nodes) for c in (n.children or [])}
    out = {}
    for i, n in enumerate(gl.nodes):
        if n.mesh is None:
            continue
        body = gl.nodes[parent[i]].name.removeprefix("body:")
        mesh = gl.meshes[n.mesh]
        factor = gl.materials[mesh.primitives[0].material].pbrMetallicRoughness.baseColorFactor
        out[n.name] = (body, mesh.name, factor)
    return out


def _check_linear_factors(gl, rep):
    from cad.data.materials import MATERIALS
    from cad.export.gltf import BODY_COLORS

    made = {r["part"] for r in rep["bom"] if r["made_or_bought"] == "made"}
    parts = _glb_colours(gl)
    assert parts["crank"][0] == "crank" and len(parts) > 20
    for node, (body, mesh, factor) in parts.items():
        display = (_hex(BODY_COLORS[body]) if mesh in made
                   else MATERIALS[rep["part_materials"][node]].color_rgb)
        np.testing.assert_allclose(factor, [*_srgb_to_linear(display), 1.0], rtol=1e-12,
                                   atol=1e-15, err_msg=node)
    # the crank's #d9534f: linear (0.694, 0.0865, 0.0782), no longer the 0.851 of hex/255
    assert parts["crank"][2][0] == pytest.approx(0.6938717612919899, rel=1e-12)


def test_glb_base_colour_is_linear(hoeken):
    """assembly.glb: each part's baseColorFactor is its display colour (body colour for made
    parts, material colour for bought ones) decoded to linear RGB."""
    import pygltflib

    out, rep = hoeken
    _check_linear_factors(pygltflib.GLTF2().load(str(out / "assembly.glb")), rep)


def test_report_html_viewer_gets_the_same_linear_colours(hoeken):
    """report.html embeds the glb (base64) for three.js, whose GLTFLoader reads
    baseColorFactor as LinearSRGBColorSpace and renders to sRGB (r179, vendored): the same
    linear factors reach the viewer, so the crank shows #d9534f."""
    import pygltflib

    out, rep = hoeken
    page = (out / "report.html").read_text()
    blob = re.search(r"<script[^>]*id=['\"]glb['\"][^>]*>([^<]*)</script>", page).group(1)
    gl = pygltflib.GLTF2.load_from_bytes(base64.b64decode(blob.strip()))
    _check_linear_factors(gl, rep)
    static = ROOT / "cad" / "report" / "vendor"
    loader = (static / "GLTFLoader.js").read_text()
    assert "setRGB( array[ 0 ], array[ 1 ], array[ 2 ], LinearSRGBColorSpace )" in loader
    three = (static / "three.module.min.js").read_text()  # the renderer's default output
    assert "SRGBColorSpace as Tn" in three and "this._outputColorSpace=Tn" in three
    from cad.report.html import VIEWER_JS

    assert "ColorSpace" not in VIEWER_JS and "ColorManagement" not in VIEWER_JS  # not overridden


def _read_3mf_vertices(data: bytes) -> dict[str, np.ndarray]:
    ns = {"m": "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"}
    with zipfile.ZipFile(io.BytesIO(data)) as z:
        root = ElementTree.fromstring(z.read("3D/3dmodel.model"))
    return {o.get("name"): np.array([[float(v.get(a)) for a in "xyz"]
                                     for v in o.iterfind("m:mesh/m:vertices/m:vertex", ns)])
            for o in root.iterfind("m:resources/m:object", ns)}


@pytest.mark.parametrize("length_mm", [10.0, 1000.0, 5000.0])
def test_3mf_vertices_within_1um_at_any_part_size(length_mm):
    """A closed bar ``length_mm`` long with seeded non-round corners, written and parsed back
    from the zip's XML: every vertex within 1e-3 mm of the mesh (6 significant digits were
    0.01 mm off on a 1 m part), and lib3mf reads the same vertices."""
    import lib3mf
    import trimesh

    from cad.export.threemf import threemf_bytes

    rng = np.random.default_rng(7)
    box = trimesh.creation.box((length_mm, 7.3, 3.1))
    v = np.asarray(box.vertices) + rng.uniform(0.5, 1.0, (1, 3)) * length_mm  # off-origin
    v = v + rng.uniform(-0.1, 0.1, v.shape) * np.array([1, 0, 0])  # irregular x, still closed
    data = threemf_bytes([("bar", v, np.asarray(box.faces), 1)], "t")
    got = _read_3mf_vertices(data)["bar"]
    assert got.shape == v.shape
    assert np.abs(got - v).max() <= 1e-3
    model = lib3mf.get_wrapper().CreateModel()
    reader = model.QueryReader("3mf")
    reader.ReadFromBuffer(bytearray(data))
    it = model.GetMeshObjects()
    assert it.MoveNext()
    lib_v = np.array([p.Coordinates[0:3] for p in it.GetCurrentMeshObject().GetVertices()])
    # lib3mf keeps float32: its own rounding is 2^-24 relative
    np.testing.assert_allclose(lib_v, v, rtol=0, atol=1e-3 + 2.0**-23 * np.abs(v).max())
