"""``[workspace] size_mm = [W, H]``: a rectangular workspace for the planar pantograph families
(issue 32 item 3), beside ``side_mm``; the GII, the datasheet and the structure poses use it.

References: the grid and the GII rebuilt by hand (numpy meshgrid, the 5-bar Jacobian,
isotropy paper eq 5 = min sigma_min / max sigma_max), and the identity size_mm = [s, s] ==
side_mm = s."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from cli_helpers import assert_one_line_error, hapticad, hapticad_json

from cad.design import load_design

DESIGNS = Path(__file__).resolve().parents[3] / "designs"


def _design_text(name: str, ws_line: str) -> str:
    """The bundled design with its ``side_mm`` line replaced by ``ws_line``."""
    text = (DESIGNS / name).read_text()
    lines = [ws_line if ln.startswith("side_mm") else ln for ln in text.splitlines()]
    return "\n".join(lines) + "\n"


@pytest.fixture
def rect(tmp_path) -> Path:
    p = tmp_path / "rect.toml"
    p.write_text(_design_text("pantograph.toml", "size_mm = [100.0, 60.0]"))
    return p


def test_rectangle_grid_and_gii_against_a_hand_computation(rect):
    from cad.kinematics.fivebar import STATUS_OK, FiveBar, jacobian_rad_per_m

    d = load_design(rect)
    t = np.linspace(-0.5, 0.5, 11)
    X, Y = np.meshgrid(0.0 + 100.0 * t, 200.0 + 60.0 * t)
    hand = np.column_stack([X.ravel(), Y.ravel()])
    np.testing.assert_array_equal(d.workspace_points(), hand)
    J, st = jacobian_rad_per_m(FiveBar.symmetric(75.0, 125.0, 175.0), hand)
    assert np.all(st == STATUS_OK)
    s = np.linalg.svd(J, compute_uv=False)
    out = hapticad_json("gii", rect)
    assert out["gii"] == pytest.approx(s[:, -1].min() / s[:, 0].max(), rel=1e-12)
    assert out["workspace_size_mm"] == [100.0, 60.0]
    code, text, _ = hapticad("gii", rect)
    assert code == 0 and "of a 100 x 60 mm workspace" in text


def test_square_size_equals_side(tmp_path):
    p = tmp_path / "sq.toml"
    p.write_text(_design_text("pantograph.toml", "size_mm = [100.0, 100.0]"))
    a, b = load_design(p), load_design(DESIGNS / "pantograph.toml")
    np.testing.assert_array_equal(a.workspace_points(), b.workspace_points())
    assert a.gii().gii == b.gii().gii


def test_twin_pantograph_rectangle(tmp_path):
    p = tmp_path / "mouse.toml"
    p.write_text(_design_text("haptic_mouse.toml", "size_mm = [80.0, 40.0]"))
    d = load_design(p)
    X = d.workspace_points()
    c = np.asarray(d.workspace["center_mm"])
    np.testing.assert_allclose(X[:, :2].min(axis=0), c - [40.0, 20.0], atol=1e-12)
    np.testing.assert_allclose(X[:, :2].max(axis=0), c + [40.0, 20.0], atol=1e-12)


def test_rectangle_in_the_datasheet_and_the_structure_poses(rect):
    from cad.families.pantograph.datasheet import rows_and_limits
    from cad.structure.pantograph import poses

    d = load_design(rect)
    rows = {r["key"]: r for r in rows_and_limits(d, {})[0]}
    assert rows["workspace"]["value"] == 100.0 * 60.0
    assert "rectangle 100 x 60 mm" in rows["workspace"]["figure"]
    pts, labels = poses(d)
    assert labels[1] == "corner -x -y" and pts[1].tolist() == [-50.0, 170.0]
    assert labels[4] == "corner +x +y" and pts[4].tolist() == [50.0, 230.0]


@pytest.mark.parametrize("line, needle", [
    ("side_mm = 100.0\nsize_mm = [100.0, 60.0]", "both"),
    ("# no side", "neither"),
])
def test_exactly_one_of_side_and_size(tmp_path, line, needle):
    p = tmp_path / "bad.toml"
    p.write_text(_design_text("pantograph.toml", line))
    code, _, err = hapticad("gii", p)
    assert_one_line_error(code, err, "workspace.side_mm", "exactly one", needle)


@pytest.mark.parametrize("value", ["[100.0]", "[100.0, -60.0]", "[100.0, 60.0, 5.0]"])
def test_bad_size_is_named(tmp_path, value):
    p = tmp_path / "bad.toml"
    p.write_text(_design_text("pantograph.toml", f"size_mm = {value}"))
    code, _, err = hapticad("gii", p)
    assert_one_line_error(code, err, "workspace.size_mm")
