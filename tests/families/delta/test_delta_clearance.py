"""The Falcon's knee (Stamper's joint offset g > 0): its fold angle over the workspace and
where the knee's cross bar meets the upper arm's fork plates, and the inner rods against the
motor brackets (cad.families.delta.clearance.py).

References: the fold angle against the layout's body frames (arccos of -x_upper . x_knee,
signed by the knee's side, :func:`cad.families.delta.layout.body_poses`: a second path
through the kinematics); the clash limit of eq (1) against OCCT's exact common volume of the
posed solids (slow). Eq (1) is checked at its crank angle beta = 0 (a straight fork and the
brackets at the g = 0 stack, ``hardware`` patched: the layout before issue 36's fix, whose
knee folds under the limit at the top of the Falcon's cube) layer by layer -- knee pairs
collide at the layer whose fold is under the limit and at no other, rod pairs where the
predicted gap is negative -- and with the family's hardware (the cranked fork, the brackets
30 mm out) over the Falcon's whole 90 mm cube: nothing meets.
"""

from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from cad.design import parse_design
from cad.errors import DesignError
from cad.families.delta import hardware as hw
from cad.families.delta.clearance import (
    fold_deg,
    fold_limit_deg,
    knee_clash,
    rod_bracket_clash,
    rod_bracket_gap_mm,
)
from cad.families.delta.layout import body_poses

ROOT = Path(__file__).resolve().parents[3]
RAW = tomllib.loads((ROOT / "designs" / "delta_falcon.toml").read_text())


@pytest.fixture
def straight_fork(monkeypatch):
    """The layout before the crank: a straight fork (beta = 0), the brackets at the g = 0
    stack."""
    monkeypatch.setattr(hw, "CRANK_ANGLE_DEG", 0.0)
    monkeypatch.setattr(hw, "KNEE_BRACKET_OFFSET_MM", 0.0)


def _layer(z_mm: float):
    """The Falcon with its workspace one thin layer (90 x 90 mm, 1 mm high) whose top is z."""
    raw = copy.deepcopy(RAW)
    raw["workspace"] = {"shape": "box", "center_mm": [0.0, 0.0, z_mm - 0.5],
                        "size_mm": [90.0, 90.0, 1.0], "grid": 5}
    return parse_design(raw, "falcon_layer.toml")


def test_fold_angle_against_the_layout_frames():
    d = parse_design(copy.deepcopy(RAW), "f.toml")
    X = d.workspace_points()
    psi = fold_deg(d.mechanism, X)
    tf = body_poses(d.mechanism, X, d.parallelogram_width_mm)
    for i in range(3):
        x_up, x_k = tf[f"upper_{i}"][:, :3, 0], tf[f"knee_{i}"][:, :3, 0]
        ref = np.degrees(np.arccos(-np.einsum("nj,nj->n", x_up, x_k)))
        # the knee's side: below the arm line (body -z of upper_i) is positive
        ref *= np.where(np.einsum("nj,nj->n", tf[f"upper_{i}"][:, :3, 2], x_k) > 0, -1.0, 1.0)
        assert np.allclose(psi[:, i], ref, rtol=0, atol=1e-9)
    # the Falcon's workspace top folds the knees almost flat (8 deg), its bottom opens them;
    # they stay on one side of the arm (the side the fork is cranked away from)
    assert psi.min() == pytest.approx(7.86, abs=0.01) and psi.max() > 100


def _clevis_outline_mm() -> float:
    """The knee clevis solid's largest radius about the cross bar's axis (the clevis frame's
    y axis, :func:`cad.families.delta.assembly.knee_hinge_tf`): over its OCCT vertices."""
    from cad.families.delta import parts as dp

    h = hw.knee_hinge()
    shape = dp.clevis_shape(hw.KNEE_EAR_RADIUS_MM, h.pin_d_mm, h.ear_z0_mm, h.ear_z1_mm,
                            h.bridge_y0_mm, h.bridge_y1_mm)
    from OCP.BRep import BRep_Tool
    from OCP.TopAbs import TopAbs_VERTEX
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopoDS import TopoDS

    r, ex = 0.0, TopExp_Explorer(shape, TopAbs_VERTEX)
    while ex.More():
        p = BRep_Tool.Pnt_s(TopoDS.Vertex_s(ex.Current()))
        r = max(r, math.hypot(p.X(), p.Z()))
        ex.Next()
    return r


def test_knee_outline_is_the_clevis_solids():
    # the clevis's corner: hypot(ear radius 3.5, 623's B/2 + gap + ear = 4.5) = 5.70 mm, from
    # the drawn solid's vertices (the straight edges' ends: a box's corners bound its radius)
    assert hw.knee_outline_radius_mm() == pytest.approx(_clevis_outline_mm(), rel=1e-9)
    assert hw.knee_outline_radius_mm() == pytest.approx(math.hypot(3.5, 4.0 / 2 + 0.5 + 2.0), rel=1e-12)
    assert hw.knee_outline_radius_mm() > hw.CROSS_BAR_D_MM / 2


def test_fold_limit_of_eq1(straight_fork):
    # the bar's axis g sin(psi + beta) from the plate leg's centre line = half the plate + the
    # knee's outline (the clevis solid's largest radius about the bar's axis); beta = 0 here
    # (straight fork)
    lim = fold_limit_deg(22.5)
    r_k = _clevis_outline_mm()
    assert 22.5 * math.sin(math.radians(lim)) == pytest.approx(hw.ARM_WIDTH_MM / 2 + r_k, rel=1e-9)
    assert lim == pytest.approx(37.51, abs=0.01)
    assert fold_limit_deg(0.0) == -180.0
    assert fold_limit_deg((hw.ARM_WIDTH_MM / 2 + r_k) * 0.99) == 180.0


def test_fold_limit_with_the_crank():
    lim = fold_limit_deg(22.5)
    beta = hw.CRANK_ANGLE_DEG
    r_k = _clevis_outline_mm()
    assert 22.5 * math.sin(math.radians(lim + beta)) == pytest.approx(hw.ARM_WIDTH_MM / 2 + r_k,
                                                                       rel=1e-9)
    assert lim == pytest.approx(-2.49, abs=0.01)  # under the Falcon's 7.86 deg: clear
    # the crank's vertex: beta off the arm line seen from the pin, g + w_a/2 + r_k from it
    x, y = hw.crank_vertex_mm(60.0, 22.5)
    r = 22.5 + hw.ARM_WIDTH_MM / 2 + r_k
    assert r == pytest.approx(36.20, abs=0.01)
    assert math.hypot(60.0 - x, y) == pytest.approx(r, rel=1e-9)
    assert math.degrees(math.atan2(y, 60.0 - x)) == pytest.approx(beta, rel=1e-12)


@pytest.mark.parametrize("z_mm,clash", [(-86.0, False), (-85.0, True)])
def test_knee_clash_edges(z_mm, clash, straight_fork):
    d = _layer(z_mm)
    psi = fold_deg(d.mechanism, d.workspace_points()).min()
    assert (psi < fold_limit_deg(22.5)) == clash  # the two layers straddle the limit
    assert abs(psi - fold_limit_deg(22.5)) < 1.5
    msg = knee_clash(d)
    assert (msg is not None) == clash
    if clash:
        assert "folds to 36.9 deg" in msg and "below 37.5 deg" in msg and "\n" not in msg


def test_the_falcon_refusal_names_the_knee_clash(tmp_path, straight_fork):
    """The refusal before any CAD, on the layout before the crank."""
    import cad

    d = cad.load_design(ROOT / "designs" / "delta_falcon.toml")
    with pytest.raises(DesignError, match="mechanism.joint_offset_mm") as e:
        cad.build_design(d, tmp_path / "f", formats="step")
    assert "knee 0 folds to 7.9 deg" in str(e.value) and "25 of 125 workspace points" in str(e.value)
    assert "inner rod of arm 2 meets its motor bracket" in str(e.value)
    assert "\n" not in str(e.value)


@pytest.mark.parametrize("z_mm,pairs", [(-88.5, 0), (-86.0, 3), (-80.0, 37)])
def test_rod_bracket_pairs_by_layer(z_mm, pairs, straight_fork):
    d = _layer(z_mm)
    gap = rod_bracket_gap_mm(d, d.workspace_points())
    assert int((gap < 0).sum()) == pairs
    assert (rod_bracket_clash(d) is None) == (pairs == 0)


def test_the_falcon_clears_with_the_family_hardware():
    d = parse_design(copy.deepcopy(RAW), "delta_falcon.toml")
    assert knee_clash(d) is None and rod_bracket_clash(d) is None
    # mm: the inner rods' closest approach to the brackets 30 mm out; regression pin (measured)
    assert rod_bracket_gap_mm(d, d.workspace_points()).min() == pytest.approx(5.26, abs=0.01)


def test_the_bundled_delta_clears_both():
    d = parse_design(tomllib.loads((ROOT / "designs" / "delta.toml").read_text()), "delta.toml")
    assert knee_clash(d) is None and rod_bracket_clash(d) is None
    # mm: far from its brackets (the RE 40's); regression pin of the measured 29.48 mm
    assert rod_bracket_gap_mm(d, d.workspace_points()).min() == pytest.approx(29.48, abs=0.01)


def _label(P) -> str:
    return "P = ({:.1f}, {:.1f}, {:.1f}) mm".format(*P)


@pytest.mark.slow  # four every-pair checks of the Falcon's solids at 125 poses each (~2 min)
@pytest.mark.parametrize("z_mm", [-88.5, -86.0, -85.0, -80.0])
def test_predictions_against_the_solids(z_mm, straight_fork):
    from cad.assembly import interference as itf
    from cad.families.delta.assembly import assemble

    d = _layer(z_mm)
    X = d.workspace_points()
    rep = itf.check_model(assemble(d, "preview"), fail_fast=False).as_dict()
    hits = rep.get("collisions") or []
    knee = [c for c in hits if any(p.startswith("knee_") and (".cross_bar" in p or ".clevis_" in p)
                                   for p in c["parts"])]
    assert bool(knee) == (fold_deg(d.mechanism, X).min() < fold_limit_deg(22.5))
    rod_hits = [c for c in hits for i in range(3)
                if sorted(c["parts"]) == [f"lower_{i}_a.rod", f"motor_bracket_{i}"]]
    rod = {(c["pose"], int(c["parts"][0][-1] if c["parts"][0].startswith("motor") else c["parts"][1][-1]))
           for c in rod_hits}
    gap = rod_bracket_gap_mm(d, X)
    assert rod == {(_label(X[n]), i) for n, i in zip(*np.nonzero(gap < 0), strict=True)}
    assert len(hits) == len(knee) + len(rod_hits)  # nothing else meets


@pytest.mark.slow  # one every-pair check of the Falcon's solids at 125 poses (~40 s)
def test_the_falcon_cube_clears_with_the_solids():
    """The family's hardware (cranked fork, brackets 30 mm out) over the Falcon's 90 mm cube:
    OCCT finds no pair of solids meeting at any of its 125 points."""
    from cad.assembly import interference as itf
    from cad.families.delta.assembly import assemble

    d = parse_design(copy.deepcopy(RAW), "delta_falcon.toml")
    rep = itf.check_model(assemble(d, "preview"), fail_fast=False).as_dict()
    assert not rep.get("collisions")
    assert rep["n_poses"] == 125


@pytest.mark.parametrize("offset_mm,clear", [(23.7, False), (23.8, True)])
def test_the_least_bracket_offset_for_the_falcon_cube(monkeypatch, offset_mm, clear):
    """hardware.KNEE_BRACKET_OFFSET_MM's comment: 23.8 mm is the least offset that clears."""
    monkeypatch.setattr(hw, "KNEE_BRACKET_OFFSET_MM", offset_mm)
    d = parse_design(copy.deepcopy(RAW), "delta_falcon.toml")
    assert (rod_bracket_gap_mm(d, d.workspace_points()).min() >= 0) == clear
