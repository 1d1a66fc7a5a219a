"""Numbers typed in README.md that come from a run, recomputed from the code's current output
at the printed rounding (issue 34 §4: a typed run number is generated or checked, never left to
drift). Pure kinematics only: no CAD build, well under a second."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cad.design import load_design
from cad.kinematics.metrics import compute_metrics

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text()


@pytest.fixture(scope="module")
def hoeken_metrics():
    """``hapticad analyze designs/hoeken.toml``'s kinematic metrics (cad.analysis.analyze calls
    the same compute_metrics with the design's range, force and samples)."""
    d = load_design(ROOT / "designs/hoeken.toml")
    return compute_metrics(d.linkage, d.phi1_min_rad, d.phi1_max_rad, force_N=d.force_N, samples=d.samples)


def test_analyze_sentence_matches_the_hoeken_design(hoeken_metrics):
    """README's analyze sentence: stroke, dy_max and torque variation at their printed rounding
    (the paper's 0.2 mm and 0.012 beside them are Table I values, ledger `paper:`)."""
    m = hoeken_metrics
    assert f"stroke {m.stroke_mm:.2f} mm" in README
    assert f"dy_max {m.dy_max_mm:.3f} mm against the paper's 0.2" in " ".join(README.split())
    assert f"torque variation {m.as_dict()['torque_variation']:.5f} against 0.012" in " ".join(README.split())


def test_swap_keeps_the_hoeken_stroke(hoeken_metrics):
    """`swap` keeps the source design's stroke: the README's kept stroke is hoeken's, to 3 decimals."""
    assert f"`swap` keeps the stroke ({hoeken_metrics.stroke_mm:.3f} mm)" in README


def test_continuous_force_sentence_matches_a_finite_difference_lever():
    """README's datasheet sentence: the continuous force at the handle of designs/hoeken.toml is
    T_cont / max |dx/dphi1| over the stroke. Independent of the datasheet's analytic Jacobian:
    the lever is a central finite difference of the solved handle point P in the path frame;
    T_cont is the catalog's RE 35 value (hoeken.toml names no motor: the parts default
    ``maxon-re35``, cad/design/parts.py)."""
    from cad.data.catalog import MOTORS
    from cad.design.parts import PartsSpec
    from cad.kinematics.fourbar import solve
    from cad.kinematics.metrics import path_frame
    d = load_design(ROOT / "designs/hoeken.toml")
    assert PartsSpec.__dataclass_fields__["motor"].default == "maxon-re35"
    fr = path_frame(d.linkage, d.phi1_min_rad, d.phi1_max_rad)
    phi = np.linspace(d.phi1_min_rad, d.phi1_max_rad, 2001)
    h = 1e-6
    x = lambda p: fr.to_path(solve(d.linkage, p).P_mm)[:, 0]  # noqa: E731
    lever_m = np.abs(x(phi + h) - x(phi - h)) / (2 * h) * 1e-3
    force_N = MOTORS["maxon-re35"].torque_continuous_mNm * 1e-3 / lever_m.max()
    assert f"continuous force at the handle of {force_N:.2f} N" in " ".join(README.split())


def test_swap_sentence_matches_the_swapped_design_and_its_json(hoeken_metrics):
    """README's swap sentence. dy_max and torque variation of Roberts are recomputed from the
    committed swapped design (docs/swap/hoeken_roberts.toml) with the current kinematics; the
    bounding boxes (a build's output) must equal the committed swap capture
    docs/swap/hoeken_to_roberts.json, which generates the table in docs/fabrication.md."""
    import json
    d = load_design(ROOT / "docs/swap/hoeken_roberts.toml")
    m = compute_metrics(d.linkage, d.phi1_min_rad, d.phi1_max_rad, force_N=d.force_N, samples=d.samples)
    text = " ".join(README.split())
    assert f"dy_max {m.dy_max_mm:.3f} mm against {hoeken_metrics.dy_max_mm:.3f}" in text
    tv_new, tv_old = m.as_dict()["torque_variation"], hoeken_metrics.as_dict()["torque_variation"]
    assert f"torque variation {tv_new:.3f} against {tv_old:.3f}" in text
    assert abs(m.stroke_mm - hoeken_metrics.stroke_mm) < 5e-4  # swap keeps the stroke
    data = json.loads((ROOT / "docs/swap/hoeken_to_roberts.json").read_text())
    box = [" × ".join(f"{v:.1f}" for v in data[k]["bbox_mm"]) for k in ("new", "old")]
    assert f"bounding box {box[0]} mm against {box[1]} mm" in text


def _datasheet_rows(path: str) -> dict[str, dict]:
    import json
    return {r["key"]: r for r in json.loads((ROOT / path).read_text())["datasheet"]["rows"]}


def test_datasheet_sentence_matches_the_committed_datasheet_run():
    """README's datasheet sentence (first mode, peak stress, M11 range and their limits) at its
    printed rounding, against the committed capture docs/datasheets/hoeken.json (the run whose
    every row docs/datasheet.md's generated table shows; a regression pin of our own run, so the
    README cannot disagree with that table)."""
    import json
    text = " ".join(README.split())
    data = json.loads((ROOT / "docs/datasheets/hoeken.json").read_text())
    assert data["command"] == "hapticad datasheet designs/hoeken.toml --fidelity fabrication --json"
    rows = _datasheet_rows("docs/datasheets/hoeken.json")
    mode, stress, m11 = rows["first_mode_Hz"], rows["max_stress_MPa"], rows["M11_g"]
    assert (f"a first structural mode of {mode['value']:.0f} Hz (ok, ≥ {mode['limit']['value']:g} Hz)"
            in text) and mode["verdict"] == "ok"
    assert (f"a peak stress of {stress['value']:.1f} MPa (ok, ≤ {stress['limit']['value']:.0f} MPa)"
            in text) and stress["verdict"] == "ok"
    assert f"an apparent mass of {m11['min']:.0f}–{m11['max']:.0f} g" in text


def test_check_sentence_matches_the_committed_check_run():
    """README's check sentence: the Hoeken's M11 maximum against its target, every target missed
    (exit 1), against the committed capture docs/check/hoeken.json (the run docs/check-fit.md's
    generated table shows; a regression pin of our own run)."""
    import json
    data = json.loads((ROOT / "docs/check/hoeken.json").read_text())
    row, = (r for r in data["rows"] if r["key"] == "M11_max_g")
    t = row["target"]
    text = " ".join(README.split())
    assert (f"M11 up to {row['computed']:.1f} g against the target {t['value']:g} g ± "
            f"{100 * t['tol_rel']:.0f} %") in text
    n = {1: "one", 2: "two", 3: "three", 4: "four", 5: "five", 6: "six"}[len(data["rows"])]
    assert f"all {n} targets are missed and it exits 1" in text
    assert data["exit_code"] == 1 and not any(r["ok"] for r in data["rows"])
