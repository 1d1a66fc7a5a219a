"""``[motor]`` and ``[firmware]`` on the pantograph families and the pen (issue 32 item 3):
one motor for the BOM, the datasheet, the firmware header and the MJCF force range.

Builds the bundled 5-bar and haptic mouse with a ``[motor]`` table and a ``[firmware]``
encoder count, then reads the WRITTEN files back (``csv`` for bom.csv, a regex over the C
header's ``#define`` lines, ``json``, ``xml.etree`` for the MJCF) and compares them with the
numbers of the ``[motor]`` table typed here (data, not our computation) and with the force
recomputed by hand (5-bar Jacobian, SVD of J^T S_J over the workspace grid).
"""

from __future__ import annotations

import csv
import json
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from cad.design import load_design

DESIGNS = Path(__file__).resolve().parents[3] / "designs"
KT, I_CONT, T_CONT, T_PEAK, MASS_G = 60.0, 2.6, 150.0, 1500.0, 500.0  # mN m/A, A, mN m, mN m, g
MOTOR = (f'\n[motor]\nname = "acme-60"\ntorque_constant_mNm_per_A = {KT}\ncurrent_continuous_A = {I_CONT}\n'
         f"torque_continuous_mNm = {T_CONT}\ntorque_peak_mNm = {T_PEAK}\nmass_g = {MASS_G}\n")
FIRMWARE = "\n[firmware]\nencoder_counts_per_rev = 8192\n"
#: numbers written with repr() read back exactly; a quotient to ~1 ulp
EXACT_REL = 1e-12


def _build(tmp: Path, name: str, formats: set[str]) -> tuple[Path, dict]:
    from cad.pipeline import build_design

    src = tmp / name
    src.write_text((DESIGNS / name).read_text() + MOTOR + FIRMWARE)
    out = tmp / "out"
    build_design(load_design(src), out, formats, fidelity="preview", use_cache=False)
    return out, json.loads((out / "report.json").read_text())


def _header(out: Path) -> dict[str, str]:
    return dict(re.findall(r"^#define (\w+) (.+)$", (out / "firmware" / "hapticad_device.h").read_text(), re.M))


def _real(v: str) -> float:
    return float(re.fullmatch(r"HC_R\((.+)\)", v.strip()).group(1))


def _check_bom_and_header(out: Path, n_motors: int) -> None:
    with (out / "bom.csv").open(newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    (motor,) = [r for r in rows if r["part"] == "motor"]
    assert "acme-60" in motor["description"] and int(motor["quantity"]) == n_motors
    assert float(motor["mass_g"]) == pytest.approx(MASS_G, abs=0.005)
    h = _header(out)
    assert _real(h["HC_KT_NM_PER_A"]) == KT * 1e-3
    assert _real(h["HC_CURRENT_CONTINUOUS_A"]) == I_CONT
    assert _real(h["HC_CURRENT_PEAK_A"]) == pytest.approx(T_PEAK / KT, rel=EXACT_REL)
    assert re.match(r"\{\s*8192L", h["HC_ENCODER_DEFAULT"])


def test_pantograph_reads_the_motor_table_everywhere(tmp_path):
    from cad.kinematics.fivebar import STATUS_OK, jacobian_rad_per_m

    out, rep = _build(tmp_path, "pantograph.toml", {"firmware"})
    _check_bom_and_header(out, 2)
    assert [m["name"] for m in rep["device"]["motors"]] == ["acme-60"] * 2
    d = load_design(DESIGNS / "pantograph.toml")
    J, st = jacobian_rad_per_m(d.mechanism, d.workspace_points())
    per_Nm = min(np.linalg.svd(J[i].T, compute_uv=False)[-1] for i in np.flatnonzero(st == STATUS_OK))
    rows = {r["key"]: r for r in rep["datasheet"]["rows"]}
    assert rows["continuous_force_N"]["value"] == pytest.approx(per_Nm * T_CONT * 1e-3, rel=1e-9)
    assert rows["peak_force_N"]["value"] == pytest.approx(per_Nm * T_PEAK * 1e-3, rel=1e-9)
    # 150 mN m continuous: 1.04 N >= the 1 N asked for -> the force verdict is met
    assert rows["continuous_force_N"]["verdict"] == "ok"
    assert "8192 counts" in rows["resolution_um"]["model"]


def test_haptic_mouse_mjcf_force_range_is_the_motor_peak(tmp_path):
    out, rep = _build(tmp_path, "haptic_mouse.toml", {"firmware", "mjcf"})
    _check_bom_and_header(out, 4)
    (xml,) = [p for p in out.glob("*.xml") if "<mujoco" in p.read_text()[:400]]
    motors = list(ET.parse(xml).getroot().iter("motor"))
    assert len(motors) == 4
    for m in motors:
        assert float(m.get("forcerange").split()[1]) == pytest.approx(T_PEAK * 1e-3, rel=EXACT_REL)


def test_pen_motor_table_reaches_the_arm_motors_not_the_waist(tmp_path):
    from cad.device import resolve_device

    src = tmp_path / "pen.toml"
    src.write_text((DESIGNS / "haptic_pen.toml").read_text() + MOTOR)
    dev = resolve_device(load_design(src))
    kts = {m.joint: m.spec.torque_constant_mNm_per_A for m in dev.motors}
    base = {m.joint: m.spec.torque_constant_mNm_per_A for m in resolve_device(load_design(DESIGNS / "haptic_pen.toml")).motors}
    for joint, kt in kts.items():
        assert kt == (base[joint] if joint.endswith("waist") else KT), joint


def test_bad_motor_table_is_named(tmp_path):
    from tests.cli_helpers import assert_one_line_error, hapticad

    src = tmp_path / "p.toml"
    src.write_text((DESIGNS / "pantograph.toml").read_text() + "\n[motor]\ntorque_peak_mNm = -3.0\n")
    code, _, err = hapticad("check", src)
    assert_one_line_error(code, err, "motor.torque_peak_mNm")


def test_pen_firmware_encoder_count_reaches_the_bom_encoder_and_the_resolution(tmp_path):
    from cad.device import encoder_bom_rows, resolve_device
    from cad.families.pantograph.datasheet import resolution_m

    src = tmp_path / "pen.toml"
    src.write_text((DESIGNS / "haptic_pen.toml").read_text() + FIRMWARE)
    d = load_design(src)
    dev = resolve_device(d)
    assert {e.counts_per_rev for e in dev.encoders} == {8192} and len(dev.encoders) == 6
    assert all("8192" in r["description"] for r in encoder_bom_rows(dev))
    # the resolution scales as 1 / counts: the paper's 4000 cpt against 8192
    ref = resolution_m(load_design(DESIGNS / "haptic_pen.toml"), 4000)
    np.testing.assert_allclose(resolution_m(d, 8192), ref * 4000 / 8192, rtol=1e-12)
    src.write_text((DESIGNS / "haptic_pen.toml").read_text() + '\n[firmware]\nplane = "vertical"\n')
    from tests.cli_helpers import assert_one_line_error, hapticad

    code, _, err = hapticad("check", src)
    assert_one_line_error(code, err, "firmware.plane", "no plane to choose")
