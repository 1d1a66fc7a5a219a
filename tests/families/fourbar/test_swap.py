"""``hapticad swap``: same joint hardware, another bar set at the same stroke; round trip."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]


def swap(src: Path, fam: str, out: Path):
    r = subprocess.run(
        [sys.executable, "-m", "cad", "swap", str(src), "--to", fam, "--out", str(out), "--json"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    return r


def bar_lengths(d):
    fb = d.linkage
    return np.array(
        [fb.l1_mm, fb.l2_mm, fb.l3_mm, fb.l4_mm, fb.l5_mm, fb.le_mm, fb.phi_e_rad, fb.branch]
    )


def test_round_trip_hoeken_roberts_hoeken_gives_the_same_bar_set(tmp_path):
    from cad.families.fourbar.layers import choose_layers
    from cad.families.fourbar.pose import planar_transforms
    from cad.design import load_design
    from cad.kinematics.linkgeom import link_joints_mm

    src = ROOT / "designs" / "hoeken.toml"
    r1 = swap(src, "roberts", tmp_path / "r.toml")
    assert r1.returncode == 0, r1.stderr
    r2 = swap(tmp_path / "r.toml", "hoeken", tmp_path / "h.toml")
    assert r2.returncode == 0, r2.stderr
    a, mid, b = load_design(src), load_design(tmp_path / "r.toml"), load_design(tmp_path / "h.toml")
    assert mid.family == "roberts" and b.family == "hoeken"
    np.testing.assert_allclose(bar_lengths(b), bar_lengths(a), rtol=1e-12, atol=1e-12)
    assert (b.phi1_min_rad, b.phi1_max_rad) == pytest.approx(
        (a.phi1_min_rad, a.phi1_max_rad), abs=1e-15
    )
    assert b.parts == a.parts == mid.parts  # the joint hardware never changed
    # the same bar set: identical joint positions in every link frame and the same layer plan
    ja, jb = link_joints_mm(a.linkage), link_joints_mm(b.linkage)
    for link in ja:
        for j in ja[link]:
            np.testing.assert_allclose(jb[link][j], ja[link][j], atol=1e-11)
    phi = np.linspace(a.phi1_min_rad, a.phi1_max_rad, 30)
    pa = choose_layers(ja, a.parts, planar_transforms(a.linkage, phi))
    pb = choose_layers(jb, b.parts, planar_transforms(b.linkage, phi))
    assert pa.order == pb.order and pa.z_mm == pytest.approx(pb.z_mm)


def test_swap_keeps_the_stroke_and_prints_both_metric_sets(tmp_path):
    r = swap(ROOT / "designs" / "hoeken.toml", "chebyshev-v", tmp_path / "cv.toml")
    assert r.returncode == 0, r.stderr
    res = json.loads(r.stdout)
    assert res["new"]["stroke_mm"] == pytest.approx(res["old"]["stroke_mm"], rel=1e-9)
    assert res["old"]["family"] == "hoeken" and res["new"]["family"] == "chebyshev-v"
    assert res["layers"]["conflicts"] == []
    assert (tmp_path / "cv.toml").read_text().startswith("# written by `hapticad swap")


def test_bad_family_exits_2_and_writes_nothing(tmp_path):
    r = swap(ROOT / "designs" / "hoeken.toml", "peaucellier", tmp_path / "x.toml")
    assert r.returncode == 2 and "--to" in r.stderr and len(r.stderr.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []


def test_handle_script_path_follows_the_new_file(tmp_path, monkeypatch):
    from cad.design import load_design
    from cad.errors import DesignError
    from cad.parts.handle import resolve_script

    out = tmp_path / "sub" / "swapped.toml"
    r = swap(ROOT / "designs" / "hoeken_cq_handle.toml", "roberts", out)
    assert r.returncode == 0, r.stderr
    d = load_design(out)
    # the script now lies outside the new design's folder: the folder opt-in refuses it
    monkeypatch.setenv("HAPTICAD_ALLOW_SCRIPTS", "1")
    with pytest.raises(DesignError, match="outside the design's folder"):
        resolve_script(d.parts, d.source)
    monkeypatch.setenv("HAPTICAD_ALLOW_SCRIPTS", "anywhere")
    assert resolve_script(d.parts, d.source) == (ROOT / "designs" / "handle_cq.py").resolve()


def test_swapped_design_builds_without_interference(tmp_path):
    from cad.design import load_design
    from cad.pipeline import build_design

    r = swap(ROOT / "designs" / "hoeken.toml", "roberts", tmp_path / "r.toml")
    assert r.returncode == 0, r.stderr
    d = load_design(tmp_path / "r.toml")
    rep = build_design(d, tmp_path / "out", {"dxf"}, fidelity="inertia", use_cache=False)
    assert rep["overlap_volume_mm3"] == 0.0 and rep["interference"]["collisions"] == []
    assert rep["min_clearance_mm"] >= d.parts.clearance_min_mm


def test_swap_build_flag_builds_the_new_design(tmp_path, monkeypatch):
    """``swap --build``: the swapped design is also built into exports/<--out stem>/, and the
    JSON's ``build`` block is that build's own report (clearance, no overlap)."""
    from cli_helpers import hapticad

    monkeypatch.chdir(tmp_path)
    code, o, err = hapticad("swap", ROOT / "designs" / "hoeken.toml", "--to", "roberts",
                            "--out", "r.toml", "--build", "--json")
    assert code == 0, err
    b = json.loads(o)["build"]
    out = tmp_path / "exports" / "r"
    assert Path(b["out"]) == Path("exports") / "r" and (out / "manifest.json").is_file()
    rep = json.loads((out / "report.json").read_text())
    assert rep["overlap_volume_mm3"] == b["overlap_volume_mm3"] == 0.0
    assert rep["min_clearance_mm"] == pytest.approx(b["min_clearance_mm"], abs=1e-12)
    assert (out / "assembly.step").is_file() and (tmp_path / "r.toml").is_file()
