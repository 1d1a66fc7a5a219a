"""Tester findings on ``hapticad synth --stroke-mm`` (t2tester).

Reference: an independent brute force (tests below) -- a 0.5 deg grid of phi1_min over the
full turn of the bundled Hoeken's bar set, phi1_max root-found for a 100 mm chord, keeping
segments with x(phi1) monotone and a transmission angle >= 30 deg. It finds phi1 = 77.5 ..
259.668 deg with dy_max 0.169 mm (checked here by ``hapticad analyze``), so a 100 mm stroke
*is* reachable under the default ``--dy-tol-mm 0.2``; docs/synthesis.md's own run [1] reaches 110.2 mm.
"""
from __future__ import annotations

import json
from pathlib import Path

import pytest
from cli_helpers import assert_one_line_error, hapticad

ROOT = Path(__file__).resolve().parents[2]

HOEKEN_100 = """name = "hoeken_100_brute"
[mechanism]
family = "custom"
l1_mm = 25.0
l2_mm = 62.5
l3_mm = 62.5
l4_mm = 0.0
l5_mm = 50.0
le_mm = 125.0
phi_e_deg = 0.0
phi1_min_deg = 77.5
phi1_max_deg = 259.6677545304832
branch = -1
force_N = 5.0
[parts]
"""


def _analyze(tmp_path, text: str) -> dict:
    p = tmp_path / "brute.toml"
    p.write_text(text)
    code, out, err = hapticad("analyze", str(p), "--json")
    assert code == 0, err
    return json.loads(out)


def test_brute_force_reference_holds_100_mm_within_the_constraints(tmp_path):
    m = _analyze(tmp_path, HOEKEN_100)
    assert abs(m["stroke_mm"] - 100.0) < 1e-6
    assert m["dy_max_mm"] < 0.2 and m["min_transmission_angle_deg"] >= 30.0


def test_max_stroke_holds_a_reachable_100_mm_stroke(tmp_path):
    out = tmp_path / "h100.toml"
    code, text, err = hapticad("synth", ROOT / "designs" / "hoeken.toml", "--stroke-mm", "100",
                               "--json", "--out", out)
    assert code == 0, err
    res = json.loads(text)["result"]
    assert abs(res["stroke_mm"] - 100.0) <= 1e-3
    # at least as straight as the brute-force reference (0.1690 mm on its 0.5 deg grid)
    assert res["dy_max_mm"] <= 0.1690 + 1e-3 and res["min_transmission_angle_deg"] >= 30.0 - 1e-6


def test_unreachable_stroke_message_does_not_call_the_start_the_best(tmp_path):
    code, _, err = hapticad("synth", ROOT / "designs" / "hoeken.toml", "--stroke-mm", "150")
    assert_one_line_error(code, err, "hapticad: error: --stroke-mm:", "150 mm")
    assert "best 48.87 mm" not in err  # 48.87 mm is the start's stroke, not a best


HOEKEN_110 = HOEKEN_100.replace("hoeken_100_brute", "hoeken_110_brute").replace(
    "phi1_min_deg = 77.5", "phi1_min_deg = 77.0").replace(
    "phi1_max_deg = 259.6677545304832", "phi1_max_deg = 283.02340337090294")


def test_max_stroke_finds_the_110_mm_segment_the_brute_force_finds(tmp_path):
    ref = _analyze(tmp_path, HOEKEN_110)
    assert ref["stroke_mm"] > 109.99 and ref["dy_max_mm"] < 0.2
    assert ref["min_transmission_angle_deg"] >= 30.0
    code, text, err = hapticad("synth", ROOT / "designs" / "hoeken.toml", "--json")
    assert code == 0, err
    assert json.loads(text)["result"]["stroke_mm"] >= ref["stroke_mm"] - 0.5
