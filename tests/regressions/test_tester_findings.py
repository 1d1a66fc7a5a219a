"""Faults a new-user trial found on the merged tree (this session's tester): a design name with
``--`` in the MJCF/URDF comments (XML 1.0 section 2.5 forbids ``--`` inside a comment), and a
four-bar whose stated encoder is not the one its ``[stiffness]`` Delta describes."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from cad.io.escape import xml_comment
from tests.cli_helpers import hapticad

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("text", ["a--b", "x-", "---", "--->", "a\nb--"])
def test_xml_comment_text_parses_inside_a_comment(text):
    root = ET.fromstring(f"<r><!-- {xml_comment(text)} --></r>")  # the XML parser is the reference
    assert root.tag == "r"


def test_a_name_with_double_dashes_builds_mjcf_and_urdf_that_parse(tmp_path):
    mujoco = pytest.importorskip("mujoco")
    d = tmp_path / "d.toml"
    d.write_text((ROOT / "designs" / "hoeken.toml").read_text().replace('name = "hoeken"', 'name = "a--b-"', 1))
    code, _, err = hapticad("build", str(d), "--fidelity", "preview", "--formats", "mjcf,urdf",
                            "--out", str(tmp_path / "o"))
    assert code == 0, err
    mjcf = next((tmp_path / "o").glob("*.xml"))
    ET.parse(mjcf)
    ET.parse(next((tmp_path / "o").glob("*.urdf")))
    mujoco.MjModel.from_xml_path(str(mjcf))


def test_a_stated_encoder_sets_eq25_delta_in_every_output(tmp_path):
    text = (ROOT / "designs" / "hoeken.toml").read_text()
    d = tmp_path / "d.toml"
    d.write_text(text.replace("[parts]\n", "[parts]\nencoder_counts_per_rev = 1000\n", 1))
    code, _, err = hapticad("build", str(d), "--fidelity", "inertia", "--formats", "firmware",
                            "--out", str(tmp_path / "o"))
    assert code == 0, err
    assert "stiffness.encoder_resolution_m = 5.46e-05 m is the mid-stroke step of 3837" in err
    import json

    o = tmp_path / "o"
    chai = json.loads((o / "firmware" / "chai3d_device.json").read_text())
    ino = (o / "firmware" / "wall_example" / "wall_example.ino").read_text()
    k_ino = float(next(ln.split()[2] for ln in ino.splitlines() if ln.startswith("#define WALL_K_N_PER_M")))
    rep = json.loads((o / "report.json").read_text())
    row = next(r for r in rep["datasheet"]["rows"] if r["key"] == "eq25_K_max_N_per_m")
    # eq (25) by hand with Delta = 5.46e-5 m x 3837 / 1000 (the table's Delta is the step of
    # 3837 counts: the 1000-count encoder's step is 3.837x it, to the table's rounding)
    delta = 5.46e-5 * 3836.75 / 1000  # 3836.75: 2 pi |dx/dphi1| / 5.46e-5 at mid-stroke
    k_hand = 2 * (0.083 + 0.12 * 0.04) / (delta + 0.04 * 0.00033)
    assert chai["encoder_counts_per_rev"] == 1000
    assert chai["m_maxLinearStiffness"] == pytest.approx(k_ino, rel=1e-12)
    assert row["value"] == pytest.approx(k_ino, rel=1e-12)
    assert k_ino == pytest.approx(k_hand, rel=1e-5)
    assert not math.isclose(k_ino, 2590.0, rel_tol=0.1)


def test_an_error_quoting_a_control_character_does_not_reach_the_terminal_raw(tmp_path):
    d = tmp_path / "d.toml"
    text = (ROOT / "designs" / "hoeken.toml").read_text()
    d.write_text(text.replace("[parts]\n", '[parts]\n"x\\u001b]52;c;cHdu\\u0007" = 1\n', 1))
    code, _, err = hapticad("check", str(d))
    assert code == 2 and err.count("\n") == 1
    assert "\x1b" not in err and "\x07" not in err
    assert "\\x1b]52;c;cHdu\\x07" in err  # shown as its escape, as a value's repr is


@pytest.mark.parametrize("table, ok", [
    # 0.5 A x 38.9 mN m/A (the catalog RE 35's Kt) carries at most 19.45 mN m, not its 97.2
    ("current_continuous_A = 0.5\n", False),
    ("current_continuous_A = 1e-300\n", False),
    # 60 mN m/A x 1.5 A = 90 mN m exactly (I0 left out: the upper end of the relation)
    ("torque_constant_mNm_per_A = 60.0\ncurrent_continuous_A = 1.5\ntorque_continuous_mNm = 90.0\n", True),
    # maxon's relation with I0: 60 x (1.5 - 0.1) = 84 mN m
    ("torque_constant_mNm_per_A = 60.0\ncurrent_continuous_A = 1.5\nno_load_current_mA = 100.0\n"
     "torque_continuous_mNm = 84.0\n", True),
    ("torque_constant_mNm_per_A = 60.0\ncurrent_continuous_A = 1.5\ntorque_continuous_mNm = 120.0\n", False),
])
def test_a_motor_table_states_one_continuous_limit(tmp_path, table, ok):
    d = tmp_path / "d.toml"
    d.write_text((ROOT / "designs" / "hoeken.toml").read_text() + "\n[motor]\n" + table)
    code, _, err = hapticad("check", str(d))
    if ok:
        assert code in (0, 1), err
    else:
        assert code == 2 and err.count("\n") == 1 and "one continuous limit per motor" in err


@pytest.mark.parametrize("name", ["a\u2028b", "a\u202eb", "a\u2066b", "a\u200bb", "ab."])
def test_a_name_with_invisible_or_line_breaking_characters_is_refused(tmp_path, name):
    d = tmp_path / "d.toml"
    text = (ROOT / "designs" / "hoeken.toml").read_text()
    d.write_text(text.replace('name = "hoeken"', f'name = "{name}"', 1))
    code, _, err = hapticad("check", str(d))
    assert code == 2 and err.count("\n") == 1 and "name: must be a plain folder name" in err


@pytest.mark.parametrize("price", ["1_000", "\uff11\uff12", "0x10", "1e3e3"])
def test_a_price_cell_must_be_an_ascii_number(tmp_path, price):
    p = tmp_path / "p.csv"
    p.write_text(f"designation,unit_price\n618/8 (8x16x4),{price}\n", encoding="utf-8")
    code, _, err = hapticad("build", str(ROOT / "designs" / "hoeken.toml"), "--prices", str(p),
                            "--fidelity", "preview", "--out", str(tmp_path / "o"))
    assert code == 2 and err.count("\n") == 1 and "is not a number" in err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("out", ["/proc/self/x", "/sys/kernel/x"])
def test_an_out_folder_on_a_file_system_that_takes_none_is_named(out):
    if not Path(out).parent.exists():
        pytest.skip(f"{Path(out).parent} does not exist on this system (Linux /proc and /sys)")
    code, _, err = hapticad("build", str(ROOT / "designs" / "hoeken.toml"), "--out", out,
                            "--fidelity", "preview", "--formats", "stl")
    assert code == 2 and err.count("\n") == 1
    assert f"--out: cannot write {out}: " in err and ".tmp." not in err
