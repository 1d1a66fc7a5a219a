"""One ``name`` validator for every family (issue 11 item 2): path tricks never reach the disk."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
import tomli_w
from cli_helpers import assert_one_line_error, hapticad

from cad.design import load_design
from cad.design.fields import NAME_MAX_BYTES, check_name
from cad.errors import DesignError

ROOT = Path(__file__).resolve().parents[3]
CASES = ROOT / "tests" / "cases" / "unsafe-designs"  # copied from the trial's shared/cases
#: One shipped design per family module (four-bar, pantograph family, PowerMouse).
FAMILY_DESIGNS = ("hoeken.toml", "custom_example.toml", "pantograph.toml", "haptic_mouse.toml",
                  "haptic_pen.toml", "powermouse.toml")
BAD_NAMES = ("../../escaped", "/tmp/abs", "", ".", "..", "a\x00b", "x" * 250, "a/b", "a\\b",
             ".hidden", "-rf", " lead", "trail ", "tab\there", "CON", "what?", "é" * 51)


def _with_name(tmp_path: Path, design: str, name: str) -> Path:
    raw = tomllib.loads((ROOT / "designs" / design).read_text(encoding="utf-8"))
    raw["name"] = name
    p = tmp_path / "d.toml"
    p.write_text(tomli_w.dumps(raw), encoding="utf-8")
    return p


@pytest.mark.parametrize("design", FAMILY_DESIGNS)
@pytest.mark.parametrize("name", BAD_NAMES, ids=repr)
def test_every_family_refuses_unsafe_names_at_load(tmp_path, design, name):
    with pytest.raises(DesignError) as ei:
        load_design(_with_name(tmp_path, design, name))
    assert ei.value.field == "name"
    assert repr(name)[:40] in str(ei.value)


@pytest.mark.parametrize("design", FAMILY_DESIGNS)
def test_every_family_keeps_a_plain_name(tmp_path, design):
    for good in ("hoeken", "my design 2", "a.b_c-d+e", "x" * NAME_MAX_BYTES):
        assert load_design(_with_name(tmp_path, design, good)).name == good


def test_name_is_bytes_not_characters():
    with pytest.raises(DesignError, match="at most 100 bytes"):
        check_name("é" * 51)  # 102 UTF-8 bytes
    assert check_name("é" * 50) == "é" * 50


@pytest.mark.parametrize("name", ["../../escaped", "", ".", "/tmp/hapticad-abs-escape"])
def test_build_of_the_trial_case_writes_nothing_anywhere(tmp_path, monkeypatch, name):
    """The twin-pantograph case of the trial: exit 2, one line naming the field, no folder
    created or deleted (an earlier build in exports/ survives)."""
    raw = tomllib.loads((CASES / "twin_pantograph_name_dotdot.toml").read_text(encoding="utf-8"))
    raw["name"] = name
    work = tmp_path / "a" / "b" / "W"
    (work / "exports" / "older").mkdir(parents=True)
    (work / "exports" / "older" / "keep.txt").write_text("mine")
    (work / "d.toml").write_text(tomli_w.dumps(raw), encoding="utf-8")
    monkeypatch.chdir(work)
    before = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*"))
    code, _, err = hapticad("build", "d.toml", "--json")
    assert_one_line_error(code, err, "name:", "plain folder name")
    assert sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*")) == before
    assert not Path("/tmp/hapticad-abs-escape").exists()
