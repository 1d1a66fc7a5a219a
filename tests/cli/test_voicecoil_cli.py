"""``hapticad voicecoil``: JSON output and bad inputs (exit 2, one line naming the flag)."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from cad.actuators import voicecoil as vc

BASE = [
    "--magnet-length-mm",
    "20",
    "--magnet-width-mm",
    "8",
    "--magnet-thickness-mm",
    "4",
    "--rattle-mm",
    "6",
]


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "cad", "voicecoil", *args], capture_output=True, text=True
    )


def test_json_keys_and_values_match_the_api():
    r = run(*BASE, "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    for key in ("optimal_gap_mm", "coil_width_mm", "Bg_T", "force_N", "model"):
        assert key in out
    api = vc.optimal_gap(vc.VoiceCoilParams(20.0, 8.0, 4.0, 6.0))
    assert out["model"] == "closed-form"
    assert out["optimal_gap_mm"] == pytest.approx(api.optimal_gap_mm, abs=1e-9)
    assert abs(out["optimal_gap_mm"] - 11.0) < 0.5  # Fig. 8
    assert out["coil_width_mm"] == pytest.approx(out["optimal_gap_mm"] - 6.0)
    assert out["Bg_T"] == pytest.approx(
        float(vc.bg_eq9_T(out["optimal_gap_mm"], 20, 8, 4, 1.2)), rel=1e-12
    )
    assert out["force_N"] == pytest.approx(api.force_N, rel=1e-12)


def test_images_model_with_options_and_fixed_gap():
    r = run(
        *BASE, "--model", "images", "--power-W", "2", "--br-T", "1.3", "--gap-mm", "11", "--json"
    )
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    p = vc.VoiceCoilParams(20.0, 8.0, 4.0, 6.0, power_W=2.0, br_T=1.3)
    assert out["model"] == "images"
    assert out["optimal_gap_mm"] == pytest.approx(
        vc.optimal_gap(p, "images").optimal_gap_mm, abs=1e-9
    )
    bg = vc.bg_image_converged_T(11.0, 20, 8, 4, 1.3)
    assert out["Bg_at_gap_T"] == pytest.approx(bg, rel=1e-12)
    assert out["force_at_gap_N"] == pytest.approx(float(vc.force_eq8_N(bg, 11.0, p)), rel=1e-12)


def test_human_output():
    r = run(*BASE)
    assert r.returncode == 0 and "optimal gap" in r.stdout and "mm" in r.stdout


@pytest.mark.parametrize(
    ("args", "flag"),
    [
        (["--magnet-length-mm", "0"], "--magnet-length-mm"),
        (["--magnet-width-mm", "-8"], "--magnet-width-mm"),
        (["--magnet-thickness-mm", "abc"], "--magnet-thickness-mm"),
        (["--rattle-mm", "-1"], "--rattle-mm"),
        (["--gap-mm", "6"], "--gap-mm"),  # d <= d_r: no room for a coil
        (["--model", "fem"], "--model"),
        (["--power-W", "0"], "--power-W"),
    ],
)
def test_bad_inputs_exit_2_one_line(args, flag):
    base = list(BASE)
    for i in range(0, len(args), 2):  # override a base flag or append
        if args[i] in base:
            base[base.index(args[i]) + 1] = args[i + 1]
        else:
            base += args[i : i + 2]
    r = run(*base, "--json")
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and flag in lines[0] and "Traceback" not in r.stderr
    assert r.stdout == ""


def test_missing_required_flag_one_line():
    r = run(*BASE[:6])
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "--rattle-mm" in lines[0]
