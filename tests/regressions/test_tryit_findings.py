"""Defects found by trying the finished commands as a new user (tryit session), each with
the check that failed before its fix.

* The structure frame's revolute ties were stiff penalty springs (1e6 x the largest
  diagonal term): the first mode and compliance of one device changed in the 4th-5th
  digit with the node numbering, which followed Python's per-process string hashing, so
  ``hapticad check DESIGN --target first_mode_Hz>=150`` printed 178.918 / 178.940 /
  178.929 Hz on three runs of the same design, and two builds of one design wrote
  different report.json files.
* ``hapticad render --out DIR`` rewrote a ``DIR/manifest.json`` it had not written (a web
  app manifest, say) with its own list, losing the user's content.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from unit.structure.test_structure import E, _section  # one aluminium 10 x 5 mm section

from cad.structure.frame import Frame

ROOT = Path(__file__).resolve().parents[2]
def test_tied_cantilever_is_the_closed_form_exactly():
    """Two 50 mm beams tied end to end (all DOFs but rz) bend out of plane as one 100 mm
    cantilever: u_z = P L^3 / (3 E I_y); with penalty ties this was off by ~1e-6."""
    s = _section()
    fr = Frame()
    a, b = fr.node((0, 0)), fr.node((0.05, 0))
    c, d = fr.node((0.05, 0)), fr.node((0.1, 0))
    fr.element(a, b, s, "one", n_sub=3)
    fr.element(c, d, s, "two", n_sub=3)
    fr.ties.append((b, c))
    fr.fixed[a] = (0, 1, 2, 3, 4, 5)
    u = fr.solve({d: np.r_[0, 0, 1.0, 0, 0, 0]})
    assert u[6 * d + 2] == pytest.approx(0.1**3 / (3 * E * s.Iy), rel=1e-12)
    assert u[6 * b + 2] == u[6 * c + 2]  # one unknown, not two close ones


def _relabelled(fr: Frame, perm: np.ndarray) -> Frame:
    """The same frame with node i renamed perm[i]."""
    out = Frame()
    out.nodes = [None] * len(fr.nodes)
    for i, xy in enumerate(fr.nodes):
        out.nodes[perm[i]] = xy
    out.elements = [(int(perm[i]), int(perm[j]), s, k) for i, j, s, k in fr.elements]
    out.ties = [(int(perm[a]), int(perm[b])) for a, b in fr.ties]
    out.fixed = {int(perm[i]): v for i, v in fr.fixed.items()}
    out.point_mass_kg = {int(perm[i]): m for i, m in fr.point_mass_kg.items()}
    return out


def test_hoeken_frame_does_not_depend_on_node_numbering():
    """The bundled Hoeken's frame at mid-stroke, its nodes renumbered at random: same first
    mode and handle compliance to 1e-9 (penalty ties: 3e-5 apart)."""
    import cad
    from cad.families.fourbar.pose import planar_transforms
    from cad.structure.device import build_frame

    d = cad.load_design(ROOT / "designs" / "hoeken.toml")
    phi = 0.5 * (d.phi1_min_rad + d.phi1_max_rad)
    tfs = planar_transforms(d.linkage, np.array([phi]))
    fr, P = build_frame(d, {k: v[0] for k, v in tfs.items()}, [], {}, "beam")
    f0 = fr.modes_Hz(1)[0]
    u0 = fr.solve({P: np.r_[1.0, 0, 0, 0, 0, 0]})[6 * P]
    rng = np.random.default_rng(0)
    for _ in range(4):
        perm = rng.permutation(len(fr.nodes))
        fp = _relabelled(fr, perm)
        assert fp.modes_Hz(1)[0] == pytest.approx(f0, rel=1e-9)
        assert fp.solve({int(perm[P]): np.r_[1.0, 0, 0, 0, 0, 0]})[6 * perm[P]] == pytest.approx(
            u0, rel=1e-9)
    assert math.isfinite(f0) and f0 > 0


@pytest.mark.parametrize("content", [
    '{"name": "My docs", "icons": [{"src": "logo.png"}]}\n',  # a web app manifest
    "not json at all\n",
])
def test_render_never_rewrites_a_manifest_it_did_not_write(tmp_path, content):
    from cli_helpers import assert_one_line_error, hapticad

    out = tmp_path / "site docs ü"
    out.mkdir()
    (out / "manifest.json").write_text(content)
    code, _, err = hapticad("render", ROOT / "designs" / "hoeken.toml", "--out", out,
                            "--fidelity", "preview")
    assert_one_line_error(code, err, "--out", "manifest.json")
    assert (out / "manifest.json").read_text() == content
    assert sorted(p.name for p in out.iterdir()) == ["manifest.json"]


def test_render_refuses_a_design_script_before_building_anything(tmp_path, monkeypatch):
    """render of [hoeken, hoeken_cq_handle] without the script opt-in built the Hoeken,
    wrote its pictures, then stopped with exit 2 on the script: now refused up front."""
    from cli_helpers import assert_one_line_error, hapticad

    monkeypatch.delenv("HAPTICAD_ALLOW_SCRIPTS", raising=False)
    out = tmp_path / "pictures"
    code, _, err = hapticad("render", ROOT / "designs" / "hoeken.toml",
                            ROOT / "designs" / "hoeken_cq_handle.toml", "--out", out,
                            "--fidelity", "preview")
    assert_one_line_error(code, err, "parts.handle_script", "HAPTICAD_ALLOW_SCRIPTS")
    assert not out.exists()


def test_render_refuses_two_designs_of_one_name(tmp_path):
    """Two designs named alike wrote DIR/<name>.png twice (the second silently over the
    first, both reported as written): refused before any build."""
    import shutil

    from cli_helpers import assert_one_line_error, hapticad

    other = tmp_path / "mine" / "hoeken.toml"
    other.parent.mkdir()
    shutil.copy(ROOT / "designs" / "hoeken.toml", other)
    out = tmp_path / "pictures"
    code, _, err = hapticad("render", ROOT / "designs" / "hoeken.toml", other, "--out", out)
    assert_one_line_error(code, err, "hoeken", "also the name of")
    assert not out.exists()


def test_fit_free_layer_order_never_returns_an_order_the_build_refuses():
    """``fit DESIGN --free parts.layer_order`` started from the coupler under the crank hub
    (``hapticad build`` of that Hoeken: "coupler / crank_hub collide at phi1 = 216.00 deg
    (overlap 337.110 mm^3)", exit 2) kept that order and said "ok" when the targets did not
    see interference. Every order is scored alike here, so only the planner's verdict
    decides: the fitted order is one the build's planner accepts, and the clashing orders
    are logged as errors naming parts.layer_order."""
    import tomllib

    from cad.design import parse_design
    from cad.design.targets import parse_cli_target
    from cad.studies.codesign.search import layer_problem
    from cad.studies.fit import fit, parse_free

    path = ROOT / "designs" / "hoeken.toml"
    raw = tomllib.loads(path.read_text())
    raw.setdefault("parts", {})["layer_order"] = ["coupler", "crank", "rocker"]
    start = parse_design(raw, str(path))
    assert layer_problem(start)[1]  # the planner objects to the start
    free = [parse_free("parts.layer_order", start.parts)]
    targets = (parse_cli_target("M11_max_g<=100"),)
    res = fit(raw, str(path), targets, free, lambda d: {"M11_max_g": 50.0})
    order = res.values["parts.layer_order"]
    assert order != ["coupler", "crank", "rocker"]
    raw["parts"]["layer_order"] = order
    assert layer_problem(parse_design(raw, str(path)))[1] is None
    assert res.met and len(res.log) == 6
    bad = [e["params"]["parts.layer_order"] for e in res.log if math.isinf(e["objective"])]
    assert ["coupler", "crank", "rocker"] in bad
