"""``check`` / ``fit`` of the delta (issue 32 §3, issue 36): ``[targets]`` and ``--target`` take
its datasheet's figures, ``--free`` its four link lengths, every fit candidate is held to its
default limits and refused before any CAD when its workspace is out of reach.

Independent references: the limits are the design's ``[actuators] force_max_N`` and the
default first mode (:data:`cad.datasheet.limits.FIRST_MODE_MIN_HZ`, Hoeken paper §III.B.1);
the pre-CAD force is checked against the brute-force sampling of the statics
(tau = J^-T f over 2000 directions, :func:`test_delta_limits.sampled_force_in_every_direction_N`);
the refusal against the inverse kinematics' own status (a second path: the IK, not the
Jacobian); the ``check`` build's figures against the build's datasheet rows read back.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import cad
from cad.data.catalog import get_motor
from cad.datasheet.limits import FIRST_MODE_MIN_HZ
from cad.errors import DesignError
from cad.families.delta import FAMILY
from cad.families.delta.targets import default_limit_targets, parse_free, precad
from cad.kinematics.delta import ik
from tests.families.delta.test_delta_limits import sampled_force_in_every_direction_N

ROOT = Path(__file__).resolve().parents[3]
DESIGN = ROOT / "designs" / "delta.toml"


def _with(tmp_path, extra: str, replace=("", "")) -> Path:
    p = tmp_path / "d.toml"
    p.write_text(DESIGN.read_text().replace(*replace) + extra)
    return p


def test_targets_table_takes_the_datasheet_keys_and_refuses_others(tmp_path):
    d = cad.load_design(_with(tmp_path, "\n[targets]\nfirst_mode_Hz = {min = 180.0}\n"))
    assert [(t.key, t.min) for t in d.targets] == [("first_mode_Hz", 180.0)]
    with pytest.raises(DesignError, match=r"targets\.M11_g"):
        cad.load_design(_with(tmp_path, "\n[targets]\nM11_g = {max = 30.0}\n"))
    assert set(FAMILY.targets.keys) >= {"continuous_force_N", "first_mode_Hz", "resolution_um"}


def test_free_takes_the_link_lengths_only():
    d = cad.load_design(DESIGN)
    f = parse_free("mechanism.upper_arm_mm=100:120", d)
    assert (f.path, f.kind, f.lo, f.hi) == ("mechanism.upper_arm_mm", "numeric", 100.0, 120.0)
    g = parse_free("mechanism.lower_arm_mm", d)  # default 0.5x .. 1.5x the design's 190 mm
    assert (g.lo, g.hi) == pytest.approx((95.0, 285.0))
    for bad in ("parts.motor", "mechanism.parallelogram_width", "upper_arm_mm"):
        with pytest.raises(DesignError, match="not a free parameter of a delta design"):
            parse_free(bad, d)


def test_fit_limits_are_the_default_limits():
    d = cad.load_design(DESIGN)
    got = {t.key: (t.min, t.max) for t in default_limit_targets(d)}
    # aluminium-6061 (the arms' material): strength 276 MPa / safety factor 3 = 92 MPa
    assert got == {"first_mode_Hz": (FIRST_MODE_MIN_HZ, None),
                   "continuous_force_N": (d.actuators["force_max_N"], None),
                   "max_stress_MPa": (None, pytest.approx(276.0 / 3)),
                   "rod_buckling_margin": (3.0, None),
                   "overlap_volume_mm3": (None, 0.0),  # no two solids overlap (OVERLAP_LIMIT)
                   # the default ball link's range: its drawing's 78 deg opening less asin(2.5 / 4.8), to 0.1 deg
                   "ball_joint_tilt_max_deg": (None, pytest.approx(78.0 - math.degrees(math.asin(2.5 / 4.8)), abs=0.05))}


def test_precad_force_is_the_sampled_statics_and_an_unreachable_candidate_is_refused(tmp_path):
    d = cad.load_design(DESIGN)
    values, why = precad(d)
    assert why is None
    tau = get_motor("maxon-re40").torque_continuous_mNm * 1e-3
    sampled = sampled_force_in_every_direction_N(d, tau)  # an upper bound of the exact minimum
    assert values["continuous_force_N"] <= sampled <= values["continuous_force_N"] * 1.01
    short = cad.load_design(_with(tmp_path, "", ("upper_arm_mm = 110.0", "upper_arm_mm = 100.0")))
    assert not np.all(ik(short.mechanism, short.workspace_points()).ok)  # the IK's own verdict
    values, why = precad(short)
    assert values == {} and why.startswith("workspace: ") and "not ok" in why


@pytest.mark.slow
def test_check_builds_the_delta_and_names_the_missed_target(tmp_path):
    """One build (about 30 s): a met and a missed target; exit 1 with one line naming the
    miss; the JSON's figures are the datasheet rows of the same design's build."""
    cmd = [sys.executable, "-m", "cad", "check", str(DESIGN), "--json",
           "--target", "continuous_force_N>=1.1", "--target", "first_mode_Hz>=400"]
    p = subprocess.run(cmd, capture_output=True, text=True, cwd=tmp_path)
    assert p.returncode == 1, p.stderr
    doc = json.loads(p.stdout)
    rows = {r["key"]: r for r in doc["rows"]}
    assert rows["continuous_force_N"]["ok"] and not rows["first_mode_Hz"]["ok"]
    rep = cad.build_design(cad.load_design(DESIGN), tmp_path / "b", formats="step",
                           fidelity="inertia")
    ds = {r["key"]: r["value"] for r in rep["datasheet"]["rows"]}
    assert rows["continuous_force_N"]["computed"] == pytest.approx(ds["continuous_force_N"], rel=1e-12)
    assert rows["first_mode_Hz"]["computed"] == pytest.approx(ds["first_mode_Hz"], rel=1e-9)
