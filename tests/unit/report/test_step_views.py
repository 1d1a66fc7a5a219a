"""Exploded view per assembly step (issue 25 §4): ``steps/step_NN.png`` of every family.

Read back from the shared builds (tests/conftest.py: ``family_builds``, ``hoeken_sim_build``,
``delta_build``; all ask for fabrication formats): ``assembly.md`` links one picture under every step that
places a part with a solid, each picture is read back with Pillow (non-blank: parts drawn
in several colours), listed in report.json and the manifest and embedded in report.html's
"Assembly steps" section (parsed with html.parser). The scenes the renderer is given
(:func:`cad.report.step_views.step_scenes`, from the family's own assembly model laid out
again) displace exactly the parts of their step, every listed part instance in exactly one
step. A picture of a known two-box scene shows the added box in its colour where it was
moved to, and not where it sits assembled.
"""

from __future__ import annotations

import json
import re
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]
FAMILIES = ["hoeken", "pantograph", "twin-pantograph", "powermouse", "delta"]
_STEP = re.compile(r"^## Step (\d+): (.*)$")
_BULLET = re.compile(r"^- `([^`]+)` \(([^)]+)\): ")
_IMAGE = re.compile(r"^!\[[^\]]*\]\(([^)]+)\)$")


@pytest.fixture
def builds(request):
    """``{family: out_dir}`` of the test's family (``fam``): the shared builds (fabrication
    formats asked: stl, step; tests/conftest.py), only the one the test reads."""
    from tests.conftest import family_build

    fam = request.node.callspec.params["fam"]
    if fam == "hoeken":
        return {fam: request.getfixturevalue("hoeken_sim_build")[1]}
    return {fam: family_build(request, fam)[1]}


def _md_steps(out: Path) -> list[dict]:
    """``[{number, title, names, images}]`` of assembly.md."""
    steps = []
    for line in (out / "assembly.md").read_text(encoding="utf-8").splitlines():
        if m := _STEP.match(line):
            steps.append({"number": int(m[1]), "title": m[2], "names": [], "images": []})
        elif (m := _BULLET.match(line)) and steps:
            steps[-1]["names"].append(m[1])
        elif (m := _IMAGE.match(line)) and steps:
            steps[-1]["images"].append(m[1])
    return steps


class _StepImages(HTMLParser):
    """The ``<h2>`` headings in order and the step pictures (``img.step``) after each."""

    def __init__(self):
        super().__init__()
        self.sections: list[list] = []
        self._h2 = False

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "h2":
            self._h2 = True
            self.sections.append(["", 0])
        elif tag == "img" and a.get("class") == "step" and self.sections:
            assert a["src"].startswith("data:image/png;base64,")
            self.sections[-1][1] += 1

    def handle_endtag(self, tag):
        self._h2 = self._h2 and tag != "h2"

    def handle_data(self, data):
        if self._h2:
            self.sections[-1][0] += data


@pytest.mark.parametrize("fam", FAMILIES)
def test_every_step_has_its_picture_on_disk(builds, fam):
    from PIL import Image

    from cad.pipeline.family import NO_SOLID_STEP
    from cad.report.step_views import STEP_SIZE_PX

    out = builds[fam]
    steps = _md_steps(out)
    linked = []
    for s in steps:
        expect = [f"steps/step_{s['number']:02d}.png"] if s["names"] and s["title"] != NO_SOLID_STEP else []
        assert s["images"] == expect, s
        linked += s["images"]
    assert len(linked) >= 4
    on_disk = sorted(p.relative_to(out).as_posix() for p in (out / "steps").iterdir())
    assert on_disk == sorted(linked)
    for rel in linked:
        with Image.open(out / rel) as im:
            assert im.format == "PNG" and im.size == STEP_SIZE_PX
            px = np.asarray(im.convert("RGB")).reshape(-1, 3)
        drawn = (px < 250).any(axis=1)
        assert drawn.mean() > 0.01, rel  # parts cover more than 1 % of the picture
        assert len(np.unique(px[drawn], axis=0)) > 20, rel  # shaded faces, several parts
    rep = json.loads((out / "report.json").read_text())
    assert set(linked) <= set(rep["files"])
    listed = {r["path"] for r in json.loads((out / "manifest.json").read_text())["files"]}
    assert set(linked) <= listed
    p = _StepImages()
    p.feed((out / "report.html").read_text(encoding="utf-8"))
    heads = [h for h, _ in p.sections]
    assert heads.index("Bill of materials") < heads.index("Assembly steps")
    assert dict(p.sections)["Assembly steps"] == len(linked)
    assert sum(n for _, n in p.sections) == len(linked)


def _model(fam: str):
    """``(instances, tf_world_body, plan, checks, no_solid_rows)`` laid out again by the
    family's own ``assemble`` (same fidelity as the shared build)."""
    from cad.design import load_design

    if fam == "hoeken":
        from cad.families.fourbar import assemble
        from cad.families.fourbar.build import ASSEMBLY_CHECKS, encoder_bom_row

        d = load_design(ROOT / "designs" / "hoeken.toml")
        m = assemble(d, "preview")
        return m.instances, m.tf_world_body, None, ASSEMBLY_CHECKS, [encoder_bom_row(d)]
    from cad.families.powermouse import assemble
    from cad.families.powermouse.build import ASSEMBLY_PLAN

    m = assemble(load_design(ROOT / "designs" / "powermouse.toml"), "inertia")
    return m.instances, m.tf_world_body, ASSEMBLY_PLAN, (), ()


@pytest.mark.parametrize("fam", ["hoeken", "powermouse"])
def test_each_scene_displaces_exactly_its_steps_parts(builds, fam):
    """The data the renderer is given: per step, the instances drawn on a displaced body
    are exactly the step's new instances (a fastener towards its own head, another part along
    the step's axis); the others drawn are exactly those of earlier steps; across the steps
    every listed instance is displaced once."""
    from cad.export.gltf import kind_meshes
    from cad.pipeline.family import build_steps
    from cad.pipeline.views import instance_colors
    from cad.report.step_views import step_scenes
    from cad.tolerances import VIEW_ANGULAR_TOLERANCE_RAD, VIEW_TOLERANCE_MM

    insts, tfs, plan, checks, no_solid = _model(fam)
    steps = build_steps(insts, plan, checks, no_solid)
    md = _md_steps(builds[fam])
    assert [s.title for s in steps] == [s["title"] for s in md]  # the steps of assembly.md
    assert [s.new for s in steps] == [s["names"] for s in md]
    meshes = kind_meshes(insts, VIEW_TOLERANCE_MM, VIEW_ANGULAR_TOLERANCE_RAD)
    scenes = step_scenes(steps, insts, tfs, meshes, instance_colors(insts))
    assert [k for k, _ in scenes] == [s["number"] for s in md if s["images"]]
    listed = {i.name for i in insts if i.kind.listed}
    by_name = {i.name: i for i in insts}
    seen: list[str] = []
    for k, sc in scenes:
        new = set(steps[k - 1].new) & listed
        moved = {i.name for i in sc.instances if i.body.startswith("explode:")}
        assert moved == set(sc.displaced) == new, k
        assert {i.name for i in sc.instances} - moved == set(seen) & listed, k
        for i in sc.instances:
            if i.name in moved:  # its own body: the assembled pose moved by the offset
                T = np.asarray(tfs[by_name[i.name].body], float).reshape(4, 4)
                shift = sc.tf_world_body[i.body][0] - T
                assert np.allclose(shift[:3, 3], sc.displaced[i.name])
                assert np.allclose(shift[:3, :3], 0.0) and np.linalg.norm(shift[:3, 3]) > 1.0
                # a fastener towards its own head (its local +z), any other part along the axis
                u = sc.axis if i.fastener is None else (T @ i.tf_body_part)[:3, 2]
                u = u / np.linalg.norm(u)
                d = sc.displaced[i.name]
                assert abs(abs(d @ u) - np.linalg.norm(d)) < 1e-9 and (i.fastener is None or d @ u > 0)
        assert len(sc.lines) == len(new)
        seen += steps[k - 1].new
    displaced = [n for _, sc in scenes for n in sc.displaced]
    assert sorted(displaced) == sorted(listed)


def test_no_pictures_without_a_fabrication_format(tmp_path):
    """An evaluation build (check, fit, render: no part files asked) writes no picture."""
    from cad.pipeline.family import write_assembly_md

    insts, tfs, plan, checks, no_solid = _model("hoeken")
    files = write_assembly_md(tmp_path, "t", insts, plan, checks, no_solid, tf_world_body=tfs,
                              formats={"glb", "mjcf"})
    assert files == ["assembly.md"] and not (tmp_path / "steps").exists()
    assert "![" not in (tmp_path / "assembly.md").read_text()


def _box(lo, hi):
    """Closed box mesh (8 vertices, 12 outward triangles), mm."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    v = np.array([[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0],
                  [x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]], float)
    f = np.array([[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
                  [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]])
    return v, f


def test_added_part_is_drawn_in_its_colour_away_from_its_place():
    """A 40 x 40 x 10 mm plate (assembled) and a 10 mm cube on it (this step, pure red):
    the cube is drawn red around its displaced centre (projected by the same frame; the axis
    line runs through it), its
    assembled place shows no red (the plate's grey, the axis line or the background), and
    the plate is grey."""
    from cad.parts import PartInstance, PartKind
    from cad.report.render import picture_px, render_images
    from cad.report.step_views import (
        ASSEMBLED_GREY,
        ASSEMBLED_RGB,
        EXPLODE_FRACTION,
        STEP_SIZE_PX,
        step_scene,
    )

    meshes = {"plate": _box((-20, -20, 0), (20, 20, 10)), "cube": _box((-5, -5, 10), (5, 5, 20))}
    insts = [PartInstance("plate", PartKind("plate", None, "aluminium 6061", True), "ground"),
             PartInstance("cube", PartKind("cube", None, "aluminium 6061", True), "ground")]
    tf = {"ground": np.eye(4)}
    colors = {"plate": (0.2, 0.4, 0.9), "cube": (1.0, 0.0, 0.0)}
    sc = step_scene(["cube"], ["plate"], insts, tf, meshes, colors)
    diag = np.linalg.norm([40, 40, 20])
    assert np.allclose(sc.displaced["cube"], [0, 0, EXPLODE_FRACTION * diag + 10.0])  # +z, up
    assert np.allclose(sc.colors["plate"], (1 - ASSEMBLED_GREY) * np.array(colors["plate"])
                       + ASSEMBLED_GREY * np.array(ASSEMBLED_RGB))
    (img,) = render_images(sc.instances, sc.tf_world_body, meshes, sc.colors, [0],
                           size_px=STEP_SIZE_PX, supersample=1, lines=sc.lines)
    px = np.asarray(img, dtype=int)
    moved = np.array([0.0, 0.0, 15.0]) + sc.displaced["cube"]
    (xm, ym), (xa, ya), (xp, yp) = picture_px(
        [moved, [0, 0, 15.0], [10.0, -10.0, 10.0]], sc.instances, sc.tf_world_body, meshes, [0],
        STEP_SIZE_PX)

    def red(x, y) -> bool:
        r, g, b = px[int(y), int(x)]
        return r > 80 and g < 10 and b < 10  # shaded red: (s, 0, 0), s >= AMBIENT

    # around the displaced centre, beside the 1 px axis line drawn through it
    assert all(red(xm + dx, ym + dy) for dx in (-3, -2, 2, 3) for dy in (-3, 0, 3))
    assert not any(red(xa + dx, ya + dy) for dx in range(-6, 7) for dy in range(-6, 7))
    r, g, b = px[int(yp), int(xp)]  # the plate's top face: grey-blue, not red
    assert abs(r - g) < 40 and b >= r and g > 120


def test_screws_driven_from_above_and_below_come_out_on_their_own_sides():
    """A step fastening screws of which some are driven from below (head down, local +z turned
    to world -z) and some from above (the twin's raised motor's mount screws): each moves
    towards its own head, by EXPLODE_FRACTION x scene + its distance from the step's middle
    along the axis (the first screw's +z), by hand."""
    from cad.assembly.fasteners import Fastener
    from cad.parts import PartInstance, PartKind, flip_x, translation
    from cad.report.step_views import EXPLODE_FRACTION, explode

    V = np.array([[-1.0, -1, 0], [1, 1, 10]])  # a 10 mm screw along its +z
    kind = PartKind("screw", None, "steel", False)
    f = Fastener("ISO 4762", "M3-0.5", 10.0, ("motor_mount",), "base_plate:h", 5.0)
    below = PartInstance("below", kind, "ground", translation(0, 0, -5) @ flip_x(), fastener=f)
    above = PartInstance("above", kind, "ground", translation(50, 0, 5), fastener=f)
    axis, off = explode([below, above], [], {"ground": np.eye(4)}, {"screw": (V, None)}, 100.0)
    assert axis == pytest.approx([0, 0, -1])
    # centres along the axis (-z): below at z = -10 -> 10, above at z = 10 -> -10; middle 0
    assert off["below"] == pytest.approx([0, 0, -(EXPLODE_FRACTION * 100 + 10)])
    assert off["above"] == pytest.approx([0, 0, EXPLODE_FRACTION * 100 + 10])
