"""Coulomb friction of the joints at the handle (cad.dynamics.friction) against a second
method: sweep the handle's direction of motion v, turn the joints at qdot = J v, let each
joint's friction oppose its rate (tau = -f sign(qdot)) and take |J^T tau| (virtual work), the
largest over 20 000 directions; and the 5-bar's datasheet row against the same sweep with the
catalog's K_t and I_0 (maxon RE 35: 38.9 mN m/A, 126 mA) times the capstan's n."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cad.dynamics.friction import coulomb_friction_at_handle_N

ROOT = Path(__file__).resolve().parents[3]


def _sweep(J: np.ndarray, f: np.ndarray, n_dir: int = 20000) -> float:
    """Largest |J^T tau| over handle directions v on the unit circle (2-D) or sphere (3-D)."""
    rng = np.random.default_rng(0)
    d = J.shape[1]
    if d == 2:
        a = np.linspace(0.0, 2 * np.pi, n_dir, endpoint=False)
        V = np.column_stack([np.cos(a), np.sin(a)])
    else:
        V = rng.normal(size=(n_dir, d))
    qd = V @ J.T
    tau = -f[None, :] * np.sign(qd)
    return float(np.linalg.norm(tau @ J, axis=1).max())


@pytest.mark.parametrize("shape", [(2, 2), (3, 3)])
def test_sign_patterns_equal_the_direction_sweep_for_a_square_jacobian(shape):
    rng = np.random.default_rng(7)
    for _ in range(20):
        J = rng.normal(size=shape) * 40.0  # rad/m
        f = rng.uniform(1e-3, 2e-2, size=shape[0])  # N m
        got = coulomb_friction_at_handle_N((J.T * f[None, :])[None])[0]
        want = _sweep(J, f, 200000 if shape[1] == 3 else 20000)
        # the sweep samples directions: it reaches the corner pattern only approximately in 3-D
        assert want <= got * (1 + 1e-12)
        assert got == pytest.approx(want, rel=2e-3 if shape[1] == 3 else 1e-9)


def test_one_joint_is_its_torque_over_the_lever():
    """A single joint of lever J = 1 / r (rad/m): friction f / r."""
    assert coulomb_friction_at_handle_N(np.array([[[0.02 * 25.0]]]))[0] == pytest.approx(0.5)


def test_a_shape_it_cannot_take_is_refused():
    with pytest.raises(ValueError, match="JT_f must be"):
        coulomb_friction_at_handle_N(np.zeros((2, 2)))


def test_the_capstan_five_bars_datasheet_row_is_the_sweep_with_n_kt_i0():
    from cad.design import load_design
    from cad.families.pantograph.datasheet import friction_row
    from cad.kinematics import fivebar

    d = load_design(ROOT / "designs" / "pantograph_capstan.toml")
    n = 128.0 / 32.0  # the design's drum / capstan
    f = np.full(2, n * 38.9e-3 * 0.126)  # N m: n K_t I_0 of the RE 35 (cad/data/catalog.py sources)
    J, st = fivebar.jacobian_rad_per_m(d.mechanism, d.workspace_points())
    want = [_sweep(Jk, f) for Jk, s in zip(J, st, strict=True) if s == fivebar.STATUS_OK]
    r = friction_row(d)
    assert r["value"] == pytest.approx(max(want), rel=1e-8)
    assert r["min"] == pytest.approx(min(want), rel=1e-8)
    assert "x capstan n = 4" in r["model"] and r["unverified"]  # I_0 is derived (catalog)
