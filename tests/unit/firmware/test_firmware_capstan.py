"""The generated firmware of a four-bar with a capstan on its crank (issue 35): the C code is
compiled and run, counts -> crank angle through the ratio and joint torque -> motor current
through the ratio against hand formulas (q = zero + 2 pi counts / (counts_per_rev n),
i = tau / (n Kt)), the test vectors against the C code, the CHAI3D force against the written
vectors' Jacobian. The report is a hand-made one (the Hoeken paper's CAD H coefficients, §III.B.2,
and plain link masses): the firmware reads only H, the links and the resolved device, so no
CAD build is needed.
"""

from __future__ import annotations

import json
import math
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

from cad import tolerances as tol
from tests.compilers import compiler

ROOT = Path(__file__).resolve().parents[3]
KT = 38.9e-3  # maxon RE 35 catalog (cad.data.catalog maxon-re35)
TC = 97.2e-3
JM = 79.2e-7


def _report(n: float) -> dict:
    links = {k: {"mass_kg": m, "com_mm": [c, 1.0, 0.0], "inertia_com_kg_m2": [[0, 0, 0], [0, 0, 0], [0, 0, iz]]}
             for k, m, c, iz in (("crank", 0.02, 10.0, 2e-6), ("coupler", 0.04, 40.0, 3e-5),
                                 ("rocker", 0.02, 30.0, 1e-5))}
    return {"H11_kg_m2": 2.97e-5 + n * n * JM, "H12_kg_m2": 3.22e-5, "H22_kg_m2": 1.17e-4,
            "H33_kg_m2": 7.09e-5, "beta2_deg": 0.0, "links": links, "Jm_kg_m2": n * n * JM}


@pytest.fixture(scope="module")
def fw(tmp_path_factory):
    from cad.design import load_design
    from cad.firmware import firmware_files

    out = tmp_path_factory.mktemp("fwcap")
    d = load_design(ROOT / "designs" / "hoeken_capstan.toml")
    for rel, text in firmware_files(d, _report(2.0), "h").items():
        (out / rel).parent.mkdir(parents=True, exist_ok=True)
        (out / rel).write_text(text)
    return out / "firmware"


def _defines(text: str) -> dict[str, str]:
    return dict(re.findall(r"^#define (\w+) (.+)$", text, re.M))


def test_header_states_the_ratio_from_the_design(fw):
    import tomllib

    t = tomllib.loads((ROOT / "designs" / "hoeken_capstan.toml").read_text())["transmission"]
    n = t["drum_diameter_mm"] / t["capstan_diameter_mm"]
    h = _defines((fw / "hapticad_device.h").read_text())
    assert h["HC_GEAR"] == f"{{ HC_R({n!r}) }}"
    assert h["HC_KT_NM_PER_A"] == f"HC_R({KT!r})"  # the motor's own Kt: the BOM's motor


def test_counts_and_currents_through_the_ratio_in_c(fw, tmp_path):
    from cad.design import load_design
    from cad.firmware.device import device_spec
    from cad.firmware.spec import angles_from_counts, motor_currents_A

    (tmp_path / "m.c").write_text(
        '#include <stdio.h>\n#include "hapticad_device.h"\nint main(void){hc_encoder_t e = HC_ENCODER_DEFAULT;'
        'long c[1]={1000};hc_real q[1],t[1]={0.05},a[1];int s;hc_counts_to_angles(&e,c,q);'
        's=hc_motor_currents(t,HC_LIMIT_CONTINUOUS,a);printf("%.17g %d %.17g %ld %.17g\\n",q[0],s,a[0],'
        'e.counts_per_rev,e.zero_rad[0]);return 0;}\n')
    exe = tmp_path / "m"
    subprocess.run([compiler(), "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", f"-I{fw}", "-o",
                    str(exe), str(tmp_path / "m.c"), str(fw / "hapticad_device.c"), "-lm"], check=True, timeout=120)
    q, s, a, cpr, zero = subprocess.run([str(exe)], capture_output=True, text=True,
                                        check=True).stdout.split()
    q, a, cpr, zero = float(q), float(a), int(cpr), float(zero)
    assert q == pytest.approx(zero + 2 * math.pi * 1000 / (cpr * 2.0), rel=1e-14)
    assert (int(s), a) == (0, pytest.approx(0.05 / (2.0 * KT), rel=1e-14))
    spec = device_spec(load_design(ROOT / "designs" / "hoeken_capstan.toml"), _report(2.0), "h", "t")
    assert angles_from_counts(spec, [[1000]])[0, 0] == pytest.approx(q, rel=1e-14)
    assert motor_currents_A(spec, [[0.05]])[0, 0] == pytest.approx(a, rel=1e-14)


def test_c_matches_the_vectors_with_the_ratio(fw, tmp_path):
    exe = tmp_path / "t"
    subprocess.run([compiler(), "-std=c99", "-O2", "-Wall", "-Wextra", "-pedantic", "-Werror", "-o", str(exe),
                    str(fw / "test_device.c"), str(fw / "hapticad_device.c"), "-lm"], check=True, timeout=120)
    tols = (tol.FIRMWARE_DOUBLE_POSITION_M, tol.FIRMWARE_DOUBLE_TORQUE_NM, tol.FIRMWARE_FD_JACOBIAN)
    r = subprocess.run([str(exe), str(fw / "test_vectors.json"), *map(repr, tols)], capture_output=True,
                       text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    doc = json.loads((fw / "test_vectors.json").read_text())
    rows = np.array([x for x in doc["rows"] if x[0] == 0])
    # counts -> angle in the written vectors: q = zero + direction 2 pi counts / (cpr n)
    enc = doc["encoder"]
    want = enc["zero_rad"][0] + enc["direction"][0] * 2 * math.pi * rows[:, 1] / (enc["counts_per_rev"] * 2.0)
    np.testing.assert_allclose(rows[:, 2], want, rtol=1e-14, atol=1e-15)


def test_chai3d_force_through_the_ratio(fw):
    doc = json.loads((fw / "test_vectors.json").read_text())
    rows = np.array([x for x in doc["rows"] if x[0] == 0])
    J = rows[:, 8:10]  # layout: status, counts, q_from_counts, q, F[2], X[2], J[2x1]
    assert doc["layout"][6].startswith("J[2x1]")
    chai = json.loads((fw / "chai3d_device.json").read_text())
    assert chai["m_maxLinearForce"] == pytest.approx(np.min(2.0 * TC / np.linalg.norm(J, axis=1)), rel=1e-12)
    assert chai["transmission_ratio"] == [2.0]


def test_direct_drive_firmware_has_no_ratio(tmp_path):
    from cad.design import load_design
    from cad.firmware import firmware_files

    files = firmware_files(load_design(ROOT / "designs" / "hoeken.toml"), _report(1.0), "h")
    assert "HC_GEAR" not in files["firmware/hapticad_device.h"]
    assert "hc_gear" not in files["firmware/hapticad_device.c"]
    assert "torques are motor torques on the joints" in files["firmware/hapticad_device.h"]
    assert "transmission_ratio" not in json.loads(files["firmware/chai3d_device.json"])
