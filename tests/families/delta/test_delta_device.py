"""The delta's motors and encoders from the one resolved device (issue 36, SPEC "The resolved
device"): ``[parts] motor``, the ``[motor]`` table and the encoder fields reach the BOM's
encoder line, the datasheet (force, resolution, apparent mass with the rotor) and the
firmware alike. No CAD here (the built files are read back in
``tests/regressions/test_outputs_agree.py`` and ``test_delta_sim.py``).

Independent references: the design file's own numbers (the ``[motor]`` table, the catalog
entry of ``parts.motor``, the encoder count stated); the Jacobian dx/dtheta by central
finite differences of the forward kinematics (a second path beside the analytic
:func:`cad.kinematics.delta.jacobian_rad_per_m`); the rotor term of eq (1) written out as
J_m (dtheta/dx)^T (dtheta/dx) from those differences.
"""

from __future__ import annotations

import copy
import math
import tomllib
import types
from pathlib import Path

import numpy as np
import pytest

from cad.data.catalog import get_motor
from cad.design import parse_design
from cad.device import resolve_device
from cad.kinematics.delta import fk, ik

ROOT = Path(__file__).resolve().parents[3]
#: the bundled delta without its [motor] table (the RE 40's drive limit, 1500 mN m): the tests
#: below vary parts.motor, and a drive limit above another motor's stall torque is refused
RAW = {k: v for k, v in tomllib.loads((ROOT / "designs" / "delta.toml").read_text()).items()
       if k != "motor"}
#: maxon HEDL 5540: 500 counts per turn, x4 quadrature = 2000 (maxon catalog).
HEDL_COUNTS = 2000
#: Central differences at h = 1e-6 rad: truncation ~h^2 |P'''| ~ 1e-13 m/rad, round-off
#: ~1e-16 m / 1e-6 rad = 1e-10 m/rad on a 0.15 m/rad Jacobian: 1e-6 relative is ample.
FD_REL = 1e-6
MOTOR = {"name": "acme-60", "torque_constant_mNm_per_A": 60.0, "current_continuous_A": 1.5,
         "torque_continuous_mNm": 90.0, "torque_peak_mNm": 500.0, "rotor_inertia_g_cm2": 20.0}


def _design(**tables):
    raw = copy.deepcopy(RAW)
    raw.update(tables)
    return parse_design(raw, "variant.toml")


def fd_jacobian_m_per_rad(d, X_mm) -> np.ndarray:
    """dx/dtheta (N, 3, 3) m/rad by central differences of :func:`cad.kinematics.delta.fk`."""
    d = d.mechanism
    th = ik(d, X_mm).theta_rad
    h = 1e-6
    cols = []
    for k in range(3):
        e = np.zeros(3)
        e[k] = h
        cols.append((fk(d, th + e).P_mm - fk(d, th - e).P_mm) / (2 * h) * 1e-3)
    return np.stack(cols, axis=-1)


def test_default_device_is_the_re35_with_the_hedl_encoder_on_each_arm():
    raw = {k: v for k, v in RAW.items() if k != "parts"}  # the bundled file names the RE 40
    dev = resolve_device(parse_design(raw, "variant.toml"))
    assert [m.joint for m in dev.motors] == ["theta_0", "theta_1", "theta_2"]
    assert {m.catalog_key for m in dev.motors} == {"maxon-re35"}
    assert [e.counts_per_rev for e in dev.encoders] == [HEDL_COUNTS] * 3
    assert dev.encoder.catalog_key == "maxon-hedl5540-500"


def test_the_bundled_delta_orders_three_re40_with_the_hedl_encoder():
    dev = resolve_device(_design())
    assert [m.joint for m in dev.motors] == ["theta_0", "theta_1", "theta_2"]
    assert {m.catalog_key for m in dev.motors} == {RAW["parts"]["motor"]} == {"maxon-re40"}
    assert [e.counts_per_rev for e in dev.encoders] == [HEDL_COUNTS] * 3
    assert dev.encoder.catalog_key == "maxon-hedl5540-500"


@pytest.mark.parametrize("parts,counts", [({"encoder_counts_per_rev": 4096}, 4096),
                                          ({"encoder": "optical-4000"}, 4000)])
def test_encoder_fields_reach_the_bom_line(parts, counts):
    from cad.families.delta.build import _encoder_rows

    d = _design(parts=parts)
    (row,) = _encoder_rows(d)
    assert row["quantity"] == 3 and f"{counts} counts/rev" in row["description"]


def test_firmware_and_parts_encoder_fields_that_disagree_are_refused():
    from cad.errors import DesignError

    d = _design(parts={"encoder_counts_per_rev": 4096}, firmware={"encoder_counts_per_rev": 2048})
    with pytest.raises(DesignError, match="4096 counts/rev disagrees"):
        resolve_device(d)


def test_datasheet_force_and_resolution_follow_the_motor_table_and_the_encoder():
    from cad.families.delta.datasheet import rows_and_limits

    d = _design(parts={"motor": "maxon-re40", "encoder_counts_per_rev": 4096}, motor=MOTOR)
    rows = {r["key"]: r for r in rows_and_limits(d, {})[0]}
    Jx = fd_jacobian_m_per_rad(d, d.workspace_points())
    smax = np.linalg.svd(Jx, compute_uv=False)[:, 0]
    # |tau|_2 <= T in every direction: F = T / sigma_max(dx/dtheta), worst over the grid
    assert rows["continuous_force_N"]["value"] == pytest.approx(0.090 / smax.max(), rel=FD_REL)
    assert rows["peak_force_N"]["value"] == pytest.approx(0.500 / smax.max(), rel=FD_REL)
    res = rows["resolution_um"]
    assert res["value"] == pytest.approx(smax.max() * 2 * math.pi / 4096 * 1e6, rel=FD_REL)
    assert "2 pi / 4096 counts" in res["model"]


def test_apparent_mass_takes_the_resolved_rotor():
    """Massless bodies: Lambda is the rotor term alone, J_m (dtheta/dx)^T (dtheta/dx)."""
    from cad.families.delta.build import _dynamics

    d = _design(parts={"motor": "maxon-re40"}, motor={"rotor_inertia_g_cm2": 20.0})
    X = d.workspace_points()
    b = types.SimpleNamespace(design=d, model=types.SimpleNamespace(
        extra=types.SimpleNamespace(workspace_mm=X), instances=()), bodies={},
        instances=(), props={})  # no solid: no drum, the rods' end joints by default
    dyn = _dynamics(b)
    assert dyn.rotor_inertia_kg_m2 == pytest.approx(20.0e-7, rel=1e-15)
    assert get_motor("maxon-re40").rotor_inertia_g_cm2 != 20.0  # the table, not the catalog
    Ji = np.linalg.inv(fd_jacobian_m_per_rad(d, X))
    eig = np.linalg.eigvalsh(20.0e-7 * np.swapaxes(Ji, 1, 2) @ Ji)
    assert dyn.Lambda_max_eig_g == pytest.approx(eig[:, -1].max() * 1e3, rel=FD_REL)
    assert dyn.Lambda_min_eig_g == pytest.approx(eig[:, 0].min() * 1e3, rel=FD_REL)
