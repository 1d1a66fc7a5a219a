"""glb / 3mf exports, the stroke GIF and report.html, each read back by a second tool.

One Hoeken build (preview fidelity, formats glb + 3mf) feeds every test (the 3MF read-back
also reads the bundled delta's shared build, tests/conftest.py ``delta_build``):

* ``assembly.glb`` read by trimesh (node names = the assembly's part instances, units in
  metres against the base plate's size in report.json) and by pygltflib (the ``stroke``
  animation turns the crank through the design's crank range, Hoeken paper Table I);
* ``parts.3mf`` read by lib3mf, the 3MF Consortium's reference library (unit mm, one
  object per made part, one build item per made instance, closed and oriented meshes,
  volume x density = the BOM mass);
* ``animation.gif`` read by Pillow (frames forward and back, the picture moves);
* ``report.html`` loaded in headless Chromium (SwiftShader WebGL) over the DevTools
  protocol: no console error, no request leaves the page, the model and its animation
  are shown, and the 3D canvas is not blank (distinct colours in its screenshot).
"""

from __future__ import annotations

import io
import json
import os
import re
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]


@pytest.fixture(scope="module")
def hoeken(tmp_path_factory):
    from cad.design import load_design
    from cad.pipeline import build_design

    out = tmp_path_factory.mktemp("viz") / "hoeken"
    d = load_design(ROOT / "designs" / "hoeken.toml")
    rep = build_design(d, out, {"glb", "3mf"}, fidelity="preview", use_cache=False)
    return d, rep, out


def _listed_instances(d):
    """The assembly's listed part instances, laid out again (the four-bar's one layout,
    :func:`cad.families.fourbar.assemble`), independently of the build output."""
    from cad.families.fourbar import assemble

    return [i for i in assemble(d, "preview", poses=8).instances if i.kind.listed]


def test_formats_are_parsed_and_listed(hoeken):
    from cad.export import parse_formats

    assert parse_formats("glb,3MF") == {"glb", "3mf"}
    _, rep, out = hoeken
    assert {"assembly.glb", "parts.3mf", "animation.gif", "render.png"} <= set(rep["files"])
    names = {f["path"] for f in json.loads((out / "manifest.json").read_text())["files"]}
    assert {"assembly.glb", "parts.3mf", "report.html", "animation.gif"} <= names


def test_glb_nodes_and_units_read_back_with_trimesh(hoeken):
    import trimesh

    d, rep, out = hoeken
    scene = trimesh.load(out / "assembly.glb")
    inst = _listed_instances(d)
    mesh_nodes = set(scene.graph.nodes_geometry)
    assert mesh_nodes == {i.name for i in inst}
    assert {f"body:{b}" for b in ("ground", "crank", "coupler", "rocker")} <= set(scene.graph.nodes)
    # metres, y up: the glb's x extent is the base plate's x extent (report.json, mm)
    x0, y0, x1, y1 = rep["base_plate_mm"]
    lo, hi = scene.bounds
    assert lo[0] * 1e3 == pytest.approx(x0, abs=0.5)
    assert hi[0] * 1e3 == pytest.approx(x1, abs=0.5)
    assert -hi[2] * 1e3 == pytest.approx(y0, abs=0.5)  # glTF z = -R0 y
    assert -lo[2] * 1e3 == pytest.approx(y1, abs=0.5)


def test_glb_stroke_animation_turns_the_crank_over_its_range(hoeken):
    import pygltflib

    d, rep, out = hoeken
    gl = pygltflib.GLTF2().load(str(out / "assembly.glb"))
    assert gl.asset.extras["units"] == "m"
    (anim,) = gl.animations
    assert anim.name == "stroke"
    crank = next(i for i, n in enumerate(gl.nodes) if n.name == "body:crank")
    ground = next(i for i, n in enumerate(gl.nodes) if n.name == "body:ground")
    targets = {(c.target.node, c.target.path) for c in anim.channels}
    assert (crank, "rotation") in targets and all(n != ground for n, _ in targets)
    ch = next(c for c in anim.channels if c.target.node == crank and c.target.path == "rotation")
    acc = gl.accessors[anim.samplers[ch.sampler].output]
    view = gl.bufferViews[acc.bufferView]
    q = np.frombuffer(
        gl.binary_blob(),
        dtype="<f4",
        count=4 * acc.count,
        offset=view.byteOffset + (acc.byteOffset or 0),
    ).reshape(-1, 4)
    # crank frame x = A1 -> A2 at angle phi1 about R0's z: q = (0, 0, sin(phi1/2), cos(phi1/2))
    assert np.allclose(q[:, :2], 0.0, atol=1e-6)
    phi = np.degrees(2 * np.arctan2(q[:, 2], q[:, 3])) % 360.0
    assert phi[0] == pytest.approx(rep["phi1_min_deg"], abs=1e-3)
    assert phi.max() == pytest.approx(rep["phi1_max_deg"], abs=1e-3)
    assert phi[-1] == pytest.approx(rep["phi1_min_deg"], abs=1e-3)  # forward then back


@pytest.mark.parametrize("fam", ["hoeken", "delta"])
def test_3mf_reads_back_with_lib3mf(request, fam):
    """The Hoeken's build above and the bundled delta's shared build (tests/conftest.py
    ``delta_build``, its report read back from report.json)."""
    import lib3mf
    import trimesh

    from cad.data.materials import get_material

    if fam == "hoeken":
        _, rep, out = request.getfixturevalue("hoeken")
    else:
        _, out, rep = request.getfixturevalue("delta_build")
    model = lib3mf.get_wrapper().CreateModel()
    model.QueryReader("3mf").ReadFromFile(str(out / "parts.3mf"))
    assert model.GetUnit() == lib3mf.ModelUnit.MilliMeter
    made = {r["part"]: r for r in rep["bom"] if r["made_or_bought"] == "made"}
    objs = {}
    it = model.GetMeshObjects()
    while it.MoveNext():
        o = it.GetCurrentMeshObject()
        assert o.IsManifoldAndOriented(), o.GetName()
        v = np.array([p.Coordinates[0:3] for p in o.GetVertices()])
        f = np.array([t.Indices[0:3] for t in o.GetTriangleIndices()])
        objs[o.GetName()] = trimesh.Trimesh(v, f, process=False).volume  # mm^3
    assert set(objs) == set(made)
    for name, vol in objs.items():
        rho = get_material(made[name]["material"]).density_kg_m3
        assert vol * 1e-9 * rho * 1e3 == pytest.approx(made[name]["mass_g"], rel=0.01), name
    items = model.GetBuildItems()
    n = 0
    while items.MoveNext():
        n += 1
    assert n == sum(r["quantity"] for r in made.values())


def test_stroke_gif_moves(hoeken):
    from PIL import Image, ImageChops

    from cad.report.render import GIF_POSES

    _, _, out = hoeken
    with Image.open(out / "animation.gif") as im:
        assert im.n_frames == 2 * GIF_POSES - 2
        frames = []
        for k in (0, GIF_POSES - 1):
            im.seek(k)
            frames.append(im.convert("RGB"))
    diff = np.asarray(ImageChops.difference(*frames)).any(axis=2)
    assert 0.001 < diff.mean() < 0.5  # the links moved, the stand did not


def test_report_html_in_headless_chromium(hoeken):
    """One page load: no console error, nothing fetched, model shown, canvas not blank."""
    from browser_cdp import Browser, find_chromium
    from PIL import Image

    d, rep, out = hoeken
    if not find_chromium():
        why = "no Chromium on PATH (apt-get install chromium; .ci/run installs it)"
        if os.environ.get("HAPTICAD_REQUIRE_BROWSER") == "1":
            pytest.fail(f"HAPTICAD_REQUIRE_BROWSER=1 but {why}")
        pytest.skip(why)
    page = out / "report.html"
    with Browser() as b:
        b.load(page)
        state = b.wait_for(
            "window.hapticadViewer && (window.hapticadViewer.ready || window.hapticadViewer.error)"
            " && JSON.stringify(window.hapticadViewer)"
        )
        assert state, f"viewer never became ready; errors: {b.errors}"
        state = json.loads(state)
        b.evaluate(  # two more frames drawn
            "new Promise(r => requestAnimationFrame(() => requestAnimationFrame(() => r(true))))",
            await_promise=True,
        )
        b.evaluate(  # the datasheet comes first (issue 24): bring the viewer on screen
            "document.getElementById('viewer').scrollIntoView();"
            "new Promise(r => requestAnimationFrame(() => requestAnimationFrame(() => r(true))))",
            await_promise=True,
        )
        box = b.evaluate(
            "(() => { const r = document.getElementById('viewer').getBoundingClientRect();"
            " return {x: r.x + scrollX, y: r.y + scrollY, width: r.width, height: r.height}; })()"
        )
        png = b.screenshot(box)
        b.evaluate(
            "document.getElementById('xray').click(); document.getElementById('play').click()"
        )
        b.evaluate(  # the see-through frame and the pause drawn without an error
            "new Promise(r => requestAnimationFrame(() => requestAnimationFrame(() => r(true))))",
            await_promise=True,
        )
        text = b.evaluate("document.body.innerText")
        b.evaluate("1")  # drain pending events
        errors, requests = list(b.errors), list(b.requests)
    assert errors == []
    assert state["error"] is None
    assert state["meshes"] == len(_listed_instances(d))
    assert state["animations"] == 1
    assert state["ground_meshes"] == sum(i.body == "ground" for i in _listed_instances(d))
    outside = [u for u in requests if not (u.startswith("data:") or u == page.resolve().as_uri())]
    assert outside == []
    img = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"))
    colours = len(np.unique(img.reshape(-1, 3), axis=0))
    assert colours > 200, colours  # a blank canvas has 1; a shaded assembly has thousands
    # the page's tables come from report.json
    for r in rep["bom"]:
        assert r["part"] in text
    assert "no collision" in text
    assert f"{rep['H11_kg_m2']:.6g}" in text


def test_an_unknown_format_is_a_named_error(tmp_path):
    from cli_helpers import assert_one_line_error, hapticad

    code, _, err = hapticad(
        "build", ROOT / "designs" / "hoeken.toml", "--formats", "step,gltf", "--out", tmp_path / "o"
    )
    assert_one_line_error(code, err, "--formats", "gltf")
    assert not (tmp_path / "o").exists()


def test_render_command_writes_the_pictures_and_refuses_other_families(tmp_path):
    from cli_helpers import assert_one_line_error, hapticad
    from PIL import Image

    out = tmp_path / "devices"
    # every family renders (the haptic pen too): the design refused is one whose build is
    # refused -- a waist bracket plate so thick the shoulder motor shafts miss their hubs
    bad = tmp_path / "thick_plate_pen.toml"
    bad.write_text((ROOT / "designs" / "haptic_pen.toml").read_text().replace(
        "[parts]\n", "[parts]\nmotor_mount_thickness_mm = 15.0\n"))
    code, _, err = hapticad(
        "render",
        ROOT / "designs" / "hoeken.toml",
        bad,
        "--out",
        out,
    )
    assert_one_line_error(code, err, "thick_plate_pen.toml", "parts.motor")
    assert not out.exists()  # checked before anything is built
    code, stdout, err = hapticad(
        "render", ROOT / "designs" / "hoeken.toml", "--out", out, "--fidelity", "preview"
    )
    assert code == 0, err
    with Image.open(out / "hoeken.png") as im:
        assert im.size == (960, 720)
        px = np.asarray(im.convert("RGB"))
    assert len(np.unique(px.reshape(-1, 3), axis=0)) > 200
    with Image.open(out / "hoeken.gif") as im:
        assert im.n_frames > 1
    assert sorted(p.name for p in out.iterdir()) == ["hoeken.gif", "hoeken.png", "manifest.json"]


def test_render_replaces_only_pictures_it_wrote(tmp_path):
    """render --out DIR shares DIR with the user: a <name>.png it did not write, or one
    changed since, is refused (exit 2, untouched, nothing built); its own are replaced."""
    import hashlib
    import json

    from cli_helpers import assert_one_line_error, hapticad

    out = tmp_path / "pictures"
    out.mkdir()
    (out / "hoeken.png").write_bytes(b"my holiday photo")
    (out / "notes.txt").write_text("mine")
    design = ROOT / "designs" / "hoeken.toml"
    code, _, err = hapticad("render", design, "--out", out, "--fidelity", "preview")
    assert_one_line_error(code, err, "--out", "hoeken.png")
    assert (out / "hoeken.png").read_bytes() == b"my holiday photo"
    assert sorted(p.name for p in out.iterdir()) == ["hoeken.png", "notes.txt"]
    (out / "hoeken.png").unlink()
    code, _, err = hapticad("render", design, "--out", out, "--fidelity", "preview")
    assert code == 0, err
    rows = {r["path"]: r for r in json.loads((out / "manifest.json").read_text())["files"]}
    assert sorted(rows) == ["hoeken.gif", "hoeken.png"]  # notes.txt is not claimed
    for name, r in rows.items():
        assert r["sha256"] == hashlib.sha256((out / name).read_bytes()).hexdigest()
    assert (out / "notes.txt").read_text() == "mine"
    gif = out / "hoeken.gif"
    gif.write_bytes(gif.read_bytes() + b"edited")
    code, _, err = hapticad("render", design, "--out", out, "--fidelity", "preview")
    assert_one_line_error(code, err, "--out", "changed since")
    assert gif.read_bytes().endswith(b"edited")


def test_committed_device_pictures_are_listed_in_their_manifest():
    """docs/devices/manifest.json lists every committed picture with its sha256, so a later
    `hapticad render --out docs/devices` may replace them (and only them)."""
    import hashlib
    import json

    folder = ROOT / "docs" / "devices"
    rows = {r["path"]: r["sha256"] for r in json.loads((folder / "manifest.json").read_text())["files"]}
    pictures = sorted(p.name for p in folder.iterdir() if p.suffix in (".png", ".gif"))
    assert sorted(rows) == pictures
    for name in pictures:
        assert rows[name] == hashlib.sha256((folder / name).read_bytes()).hexdigest(), name


def test_render_of_several_designs_writes_nothing_when_one_build_fails(tmp_path):
    """Every design is built before any picture is written: the Hoeken builds, the
    stroke-24 case (no clear layer layout) fails in its build -> exit 2, no file at all."""
    from cli_helpers import assert_one_line_error, hapticad

    out = tmp_path / "pictures"
    code, _, err = hapticad(
        "render", ROOT / "designs" / "hoeken.toml",
        ROOT / "tests" / "cases" / "assembly-clashes" / "hoeken_stroke24.toml",
        "--out", out, "--fidelity", "preview",
    )
    assert_one_line_error(code, err, "stroke_mm", "A2")
    assert not out.exists() or list(out.iterdir()) == []


# --- issue 24 §3: the page of every family, read back with html.parser -------------------

PAGE_FAMILIES = {"hoeken": "hoeken.toml", "pantograph": "pantograph.toml",
                 "twin-pantograph": "haptic_mouse.toml", "powermouse": "powermouse.toml"}


class _Page(HTMLParser):
    """``h2`` headings in order, every table as rows of cell texts (after the ``h2`` it
    follows), the design file named in the ``<code>`` of the first muted paragraph."""

    def __init__(self):
        super().__init__()
        self.h2: list[str] = []
        self.tables: list[tuple[str, list[list[str]]]] = []
        self.source = None
        self._in, self._cell = None, None

    def handle_starttag(self, tag, attrs):
        if tag == "h2":
            self._in = "h2"
            self.h2.append("")
        elif tag == "table":
            self.tables.append((self.h2[-1] if self.h2 else "", []))
        elif tag == "tr" and self.tables:
            self.tables[-1][1].append([])
        elif tag in ("td", "th") and self.tables:
            self.tables[-1][1][-1].append("")
            self._cell = True
        elif tag == "code" and self.source is None:
            self._in = "code"
            self.source = ""

    def handle_endtag(self, tag):
        if tag in ("h2", "code"):
            self._in = None
        elif tag in ("td", "th"):
            self._cell = None

    def handle_data(self, data):
        if self._in == "h2":
            self.h2[-1] += data
        elif self._in == "code":
            self.source += data
        elif self._cell:
            self.tables[-1][1][-1][-1] += data


@pytest.fixture(scope="module")
def pages(family_builds, hoeken_sim_build):
    """``{family: (design file name, out_dir, parsed report.html)}`` of the shared builds."""
    outs = {"hoeken": hoeken_sim_build[1], **{f: o for f, (_, o, _) in family_builds.items()}}
    out = {}
    for fam, o in outs.items():
        p = _Page()
        p.feed((o / "report.html").read_text(encoding="utf-8"))
        out[fam] = (PAGE_FAMILIES[fam], o, p)
    return out


@pytest.mark.parametrize("fam", list(PAGE_FAMILIES))
def test_page_order_source_and_readable_tables(pages, fam):
    """Verdicts first, then the 3D view and the stroke, the charts, the BOM; the design
    file's name; the fastener records as a table equal to report.json's; no table cell
    holds JSON."""
    fname, out, p = pages[fam]
    order = ["Datasheet", "Assembly (3D)", "The stroke", "Charts", "Bill of materials"]
    assert [h for h in p.h2 if h in order] == order
    assert p.source == fname
    rep = json.loads((out / "report.json").read_text())
    fast = rep["fasteners"]
    assert fast, fam  # every family's build has screws
    (rows,) = [r for h, r in p.tables if h == "Fasteners"]
    assert rows[0] == ["screw", "standard", "size", "length (mm)", "clamps", "hole engaged",
                       "engagement (mm)"]
    body = {r[0]: r for r in rows[1:]}
    assert set(body) == set(fast)
    for name, f in fast.items():
        r = body[name]
        assert (r[1], r[2], r[5]) == (f["kind"], f["size"], f["hole"])
        assert float(r[3]) == pytest.approx(f["length_mm"], rel=1e-5)
        assert float(r[6]) == pytest.approx(f["engagement_mm"], rel=1e-5)
        assert r[4] == ", ".join(f["clamps"])
    cells = [c for _, rows in p.tables for r in rows for c in r]
    json_like = [c for c in cells if re.search(r"[{\[]\s*[\"']|[\"']\s*:\s", c)]
    assert not json_like, json_like[:3]


def test_split_by_plane_keeps_area_winding_and_sides():
    """Random triangles cut by a plane: the pieces cover the same area, keep their
    source's normal direction and lie on one side each (seeded)."""
    from cad.report.cutaway import split_by_plane

    rng = np.random.default_rng(7)
    tris = rng.uniform(-10, 10, (200, 3, 3))
    n, off = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8]), 0.7
    out, src = split_by_plane(tris, n, off)

    def cross(t):
        return np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])

    area = np.zeros(len(tris))
    np.add.at(area, src, 0.5 * np.linalg.norm(cross(out), axis=1))
    assert np.allclose(area, 0.5 * np.linalg.norm(cross(tris), axis=1), rtol=1e-9)
    c, c0 = cross(out), cross(tris)[src]
    big = np.linalg.norm(c, axis=1) > 1e-9
    assert (np.einsum("ij,ij->i", c[big], c0[big]) > 0).all()  # same winding
    s = out @ n - off
    assert ((s >= -1e-9).all(axis=1) | (s <= 1e-9).all(axis=1)).all()
    assert len(out) > len(tris)  # some were cut


def test_powermouse_pictures_show_the_flotor_and_coils(family_builds):
    """The still and the GIF are a quarter cut-away: with the build's cut-away
    (:data:`PICTURE_CUTAWAY`) the flotor, the core and coils own pixels (each drawn alone in
    red, the rest grey); in the closed box neither the core nor any coil does. render.png on
    disk has more than 3x the pixels of the flotor's colour of an uncut render."""
    import fnmatch

    from PIL import Image

    from cad.export.gltf import kind_meshes
    from cad.families.powermouse import assemble
    from cad.families.powermouse.build import PICTURE_CUTAWAY
    from cad.pipeline.views import instance_colors
    from cad.report.render import cutaway_of, render_images
    from cad.tolerances import VIEW_ANGULAR_TOLERANCE_RAD, VIEW_TOLERANCE_MM

    d, out, _ = family_builds["powermouse"]
    m = assemble(d, "inertia")
    insts = [i for i in m.instances if i.kind.listed]
    meshes = kind_meshes(insts, VIEW_TOLERANCE_MM, VIEW_ANGULAR_TOLERANCE_RAD)
    tf = {b: np.asarray(T, float).reshape(1, 4, 4) for b, T in m.tf_world_body.items()}
    names = [i.name for i in insts if any(fnmatch.fnmatchcase(i.name, p) for p in PICTURE_CUTAWAY)]
    cut = cutaway_of(names, insts, m.tf_world_body, meshes)

    def visible(name: str, cutaway) -> bool:
        """Whether ``name`` owns a pixel: it alone drawn pure red, the rest grey."""
        cols = {i.name: (1.0, 0.0, 0.0) if i.name == name else (0.6, 0.6, 0.6) for i in insts}
        (img,) = render_images(insts, tf, meshes, cols, [0], size_px=(320, 240), supersample=1,
                               cutaway=cutaway)
        a = np.asarray(img, dtype=int)
        return bool(((a[..., 0] > 60) & (a[..., 1] < 10) & (a[..., 2] < 10)).any())

    assert "flotor_body" in names and "housing_body" in names
    inside = ["core", *sorted(i.name for i in insts if i.name.startswith("coil_"))]
    seen_cut = {n for n in ["flotor_body", *inside] if visible(n, cut)}
    assert {"flotor_body", "core"} <= seen_cut and len(seen_cut) >= 5, seen_cut
    assert not any(visible(n, None) for n in inside)  # the closed box hides them all
    colors = instance_colors(insts)
    flotor = np.asarray(colors["flotor_body"]) * 255

    def flotor_px(img) -> int:
        a = np.asarray(img.convert("RGB"), dtype=float)
        norm = np.linalg.norm(a, axis=-1) * np.linalg.norm(flotor)
        cos = (a @ flotor) / np.where(norm > 0, norm, 1)
        return int((cos > 0.995).sum())

    with Image.open(out / "render.png") as im:
        on_disk = flotor_px(im)
        size = im.size
    (uncut,) = render_images(insts, tf, meshes, colors, [0], size_px=size)
    assert on_disk > 3 * flotor_px(uncut)
