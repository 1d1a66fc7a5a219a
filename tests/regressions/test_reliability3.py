"""Reproducers of the third reliability trial (../shared/cases/reliability3/, inputs built
here) that are not covered by a dedicated test file: massprops names the file, prices through
the CLI (one line, exit 2, no traceback), encoder_zero_deg bounded, print_walls 10 builds, free design strings
with a line break refused at load (report-md-injection-from-design-strings)."""

from __future__ import annotations

import os
import struct
from pathlib import Path

import pytest

from tests.cli_helpers import hapticad

ROOT = Path(__file__).resolve().parents[2]
TETRA = [(0, 0, 0), (10, 0, 0), (0, 10, 0), (0, 0, 10)]
FACES = ((0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3))


def _stl(path: Path, tris) -> Path:
    b = bytearray(80) + struct.pack("<I", len(tris))
    for t in tris:
        b += struct.pack("<12fH", 0, 0, 0, *t, 0)
    path.write_bytes(bytes(b))
    return path


def test_massprops_refusals_name_the_file(tmp_path):
    tris = [(*TETRA[a], *TETRA[b], *TETRA[c]) for a, b, c in FACES]
    # three faces of a tetrahedron: its three rim edges bound one triangle each (closed form)
    code, _, err = hapticad("massprops", str(_stl(tmp_path / "open.stl", tris[:3])), "--density", "1000")
    assert code == 2 and err.count("\n") == 1 and "open.stl: the mesh is not closed (3 open edges)" in err
    huge = [tuple(x * 1e37 for x in t) for t in tris]
    code, _, err = hapticad("massprops", str(_stl(tmp_path / "huge.stl", huge)), "--density", "1000")
    assert code == 2 and err.count("\n") == 1 and "huge.stl: coordinates reach 5e+37 mm" in err


@pytest.mark.parametrize("content, expect", [
    ("designation,unit_price\n618/8 (8x16x4),1e308\ncrank,1e308\n", "row 2 column unit_price"),
    ("designation,unit_price\n" + "y" * 200_000 + ",1\n", "row 2: not a valid CSV row"),
])
def test_bad_price_file_is_one_line_through_the_cli(tmp_path, content, expect):
    (tmp_path / "p.csv").write_text(content)
    code, _, err = hapticad("build", str(ROOT / "designs" / "hoeken.toml"), "--fidelity", "preview",
                            "--formats", "step", "--out", str(tmp_path / "o"), "--prices", str(tmp_path / "p.csv"))
    assert code == 2 and err.strip().count("\n") == 0 and "--prices" in err and expect in err
    assert "Traceback" not in err and not (tmp_path / "o").exists()


@pytest.mark.parametrize("kind", ["fifo", "dev-zero"])
def test_price_file_not_a_regular_file_is_one_line_through_the_cli(tmp_path, kind):
    """Case prices-file-unguarded-hang-memory: a FIFO hung ``build --prices`` for ever, a link to
    /dev/zero died with a MemoryError traceback. Now one line at once naming --prices, the file
    and what it is (docs/reliability.md "Files hapticad reads"), exit 2, nothing written."""
    p = tmp_path / "p.csv"
    if kind == "fifo":
        os.mkfifo(p)
    else:
        p.symlink_to("/dev/zero")
    code, _, err = hapticad("build", str(ROOT / "designs" / "hoeken.toml"), "--fidelity", "preview",
                            "--formats", "step", "--out", str(tmp_path / "o"), "--prices", str(p))
    what = "is a FIFO (named pipe)" if kind == "fifo" else "character device (a symbolic link to /dev/zero)"
    assert code == 2 and err.strip().count("\n") == 0 and "Traceback" not in err, err
    assert err.startswith("hapticad: error: --prices: ") and "p.csv" in err and what in err, err
    assert not (tmp_path / "o").exists()


def test_encoder_zero_beyond_two_turns_is_refused(tmp_path):
    text = (ROOT / "designs" / "hoeken.toml").read_text() + "\n[firmware]\nencoder_zero_deg = 1e308\n"
    (tmp_path / "d.toml").write_text(text)
    code, _, err = hapticad("check", str(tmp_path / "d.toml"))
    assert code == 2 and "firmware.encoder_zero_deg: must be of magnitude <= 720 deg" in err


def test_print_walls_10_builds(tmp_path):
    text = (ROOT / "designs" / "hoeken_printed.toml").read_text()
    assert "print_walls = 2" in text
    (tmp_path / "d.toml").write_text(text.replace("print_walls = 2", "print_walls = 10"))
    code, _, err = hapticad("build", str(tmp_path / "d.toml"), "--fidelity", "preview", "--formats", "step",
                            "--out", str(tmp_path / "o"))
    assert code == 0, err


HOSTILE = "x\\n# INJECTED heading\\n![i](http://example.invalid/t.png)"  # TOML escapes: a real newline


@pytest.mark.parametrize("design", ["hoeken.toml", "pantograph.toml", "haptic_pen.toml"])
@pytest.mark.parametrize(("table", "field"), [
    (f'[motor]\nsource = "{HOSTILE}"\ntorque_constant_mNm_per_A = 38.9\n', "motor.source"),
    (f'[motor]\nname = "{HOSTILE}"\n', "motor.name"),
    ('[prices]\ncurrency = "EUR\\n# INJECTED currency"\ncrank = 1.0\n', "prices.currency"),
    ('[prices]\n"cr\\nank" = 1.0\n', "prices.cr"),
], ids=["motor-source", "motor-name", "prices-currency", "prices-key"])
def test_design_strings_with_a_line_break_are_refused_at_load(tmp_path, design, table, field):
    """Case report-md-injection-from-design-strings: a free string of a design ([motor] name
    and source, a [prices] key and its currency) holding a newline put a heading and a remote
    image into report.md. Now refused at load in every family that takes these tables: one
    line naming the key and the character (U+000A), exit 2, nothing written."""
    text = (ROOT / "designs" / design).read_text()
    assert "\n[motor]" not in text and "\n[prices]" not in text
    (tmp_path / "d.toml").write_text(text + "\n" + table)
    code, out, err = hapticad("build", str(tmp_path / "d.toml"), "--fidelity", "preview", "--formats", "step",
                              "--out", str(tmp_path / "o"))
    assert code == 2 and err.strip().count("\n") == 0 and "Traceback" not in err, err
    assert err.startswith(f"hapticad: error: {field}") and "U+000A" in err, err
    assert "INJECTED" not in out and not (tmp_path / "o").exists()
