"""Datasheet force of the 5-bar families from the motors the BOM orders (issue 32 item 3).

Reference: a brute-force direction scan, independent of the SVD: with the torque ellipsoid
``tau = S_J u, |u| <= 1`` the largest force along the unit direction d at one pose is
``1 / |A^-1 d|`` (A = J^T S_J, square for the 5-bar pantograph); its minimum over 3600
directions and every workspace sample must equal the row. The motor torque is read straight
from the catalog (maxon RE 35 data sheet, 97.2 mN m continuous), not through the device.
"""

from pathlib import Path

import numpy as np
import pytest

from cad.data.catalog import get_motor
from cad.design import load_design
from cad.families.pantograph.datasheet import motor_force_rows
from cad.kinematics.fivebar import STATUS_OK, jacobian_rad_per_m

DESIGNS = Path(__file__).resolve().parents[3] / "designs"


def _scan_min_force_N(J, ok, tau_Nm: float) -> float:
    t = np.linspace(0.0, 2 * np.pi, 3600, endpoint=False)
    d = np.stack([np.cos(t), np.sin(t)])  # (2, K)
    worst = np.inf
    for Ji in J[ok]:
        A = Ji.T * tau_Nm  # (2 force rows, 2 motors), both motors alike
        u = np.linalg.solve(A, d)  # torque-ellipsoid coordinates needed for a unit force along d
        worst = min(worst, float((1.0 / np.linalg.norm(u, axis=0)).min()))
    return worst


@pytest.mark.parametrize("key, field", [("continuous_force_N", "torque_continuous_mNm"),
                                        ("peak_force_N", "torque_peak_mNm")])
def test_pantograph_force_from_bom_motor_matches_direction_scan(key, field):
    d = load_design(DESIGNS / "pantograph.toml")
    rows = {r["key"]: r for r in motor_force_rows(d)}
    tau_Nm = getattr(get_motor(d.parts.motor), field) * 1e-3
    J, st = jacobian_rad_per_m(d.mechanism, d.workspace_points())
    ref = _scan_min_force_N(np.asarray(J), np.asarray(st) == STATUS_OK, tau_Nm)
    assert rows[key]["value"] == pytest.approx(ref, rel=1e-5)
    assert d.parts.motor in rows[key]["model"]


def test_pantograph_continuous_force_is_the_re35_not_the_normalisation():
    # [actuators] torque_max_Nm = 1.0 (GII normalisation) gives ~6.96 N; the RE 35's 97.2 mN m
    # continuous torque gives 0.0972 of the normalised figure (force is linear in S_J).
    d = load_design(DESIGNS / "pantograph.toml")
    assert d.actuators["torque_max_Nm"] == 1.0
    row = {r["key"]: r for r in motor_force_rows(d)}["continuous_force_N"]
    J, st = jacobian_rad_per_m(d.mechanism, d.workspace_points())
    ok = np.asarray(st) == STATUS_OK
    normalised = _scan_min_force_N(np.asarray(J), ok, 1.0)
    assert row["value"] == pytest.approx(0.0972 * normalised, rel=1e-4)
    assert 0.6 < row["value"] < 0.75
