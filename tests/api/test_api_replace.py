"""``design.replace(**changes)`` validates exactly as loading the changed TOML file does
(issue 23: ``dataclasses.replace`` on a design skipped every check, a bar width of -5 mm gave
M11 = 65 g and no error).

The reference for a valid change is the bundled design file edited as text (an independent
route: no dict manipulation of ours) and loaded with :func:`cad.load_design`; the reference
for a bad one is the DesignError loading such a file raises.
"""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import pytest

import cad
from cad.errors import DesignError

ROOT = Path(__file__).resolve().parents[2]
DESIGNS = ROOT / "designs"


def _edited(tmp_path: Path, name: str, table: str, key: str, value: str) -> Path:
    """``designs/<name>`` with ``key = value`` set in ``[table]`` by editing its text."""
    text = (DESIGNS / name).read_text()
    head = f"[{table}]\n"
    start = text.index(head) + len(head)
    end = text.find("\n[", start)
    end = len(text) if end < 0 else end + 1
    body, n = re.subn(rf"(?m)^{key}\s*=.*$", f"{key} = {value}", text[start:end])
    if n == 0:
        body = f"{key} = {value}\n" + body
    out = tmp_path / name
    out.write_text(text[:start] + body + text[end:])
    return out


def _same(replaced, loaded) -> None:
    """Equal as designs (``source`` aside: the edited file lives elsewhere) and as TOML."""
    assert replaced == dataclasses.replace(loaded, source=replaced.source)
    assert replaced.raw == loaded.raw
    assert replaced.source == str(DESIGNS / Path(replaced.source).name)


def _load(name: str):
    return cad.load_design(DESIGNS / name)


# (file, table, key, new value, TOML text of the value)
VALID = [
    ("hoeken.toml", "parts", "bar_width_mm", 22.0, "22.0"),
    ("hoeken.toml", "parts", "bar_material", "steel-1018", '"steel-1018"'),
    ("hoeken.toml", "mechanism", "force_N", 3.0, "3.0"),
    ("pantograph.toml", "mechanism", "proximal_mm", 140.0, "140.0"),
    ("haptic_mouse.toml", "parts", "tube_od_mm", 9.0, "9.0"),
    ("powermouse.toml", "actuator", "rattle_mm", 7.0, "7.0"),
    ("powermouse.toml", "flotor", "edge_mm", 70.0, "70.0"),
]


@pytest.mark.parametrize("name, table, key, value, text", VALID)
def test_a_valid_change_equals_loading_the_changed_file(tmp_path, name, table, key, value, text):
    """All three forms of a change (dotted key, table mapping, the nested object's own
    ``replace`` where the design has one) give the design of the edited file."""
    d = _load(name)
    loaded = cad.load_design(_edited(tmp_path, name, table, key, text))
    assert loaded.raw[table][key] == value  # the edit took
    _same(d.replace({f"{table}.{key}": value}), loaded)
    _same(d.replace(**{table: {key: value}}), loaded)
    nested = getattr(d, table, None)
    if hasattr(nested, "replace") and dataclasses.is_dataclass(nested):
        _same(d.replace(**{table: nested.replace(**{key: value})}), loaded)
    assert d.raw[table].get(key) != value  # the original is untouched


def test_the_issue_example_negative_bar_width_is_refused_as_a_file_is(tmp_path):
    """-5 mm bar width: the DesignError of loading that file, naming ``parts.bar_width_mm``."""
    d = _load("hoeken.toml")
    with pytest.raises(DesignError) as from_file:
        cad.load_design(_edited(tmp_path, "hoeken.toml", "parts", "bar_width_mm", "-5"))
    for change in ({"parts.bar_width_mm": -5}, {"parts": {"bar_width_mm": -5}},
                   {"parts": d.parts.replace(bar_width_mm=-5)}):
        with pytest.raises(DesignError) as exc:
            d.replace(**change) if "parts" in change else d.replace(change)
        assert exc.value.field == "parts.bar_width_mm" == from_file.value.field
        assert str(exc.value) == str(from_file.value)
        assert "-5" in str(exc.value)


@pytest.mark.parametrize("change, field, reason", [
    ({"parts.bar_widht_mm": 20}, "parts.bar_widht_mm", "did you mean 'bar_width_mm'"),
    ({"mechanism.family": "hoekn"}, "mechanism.family", "unknown family"),
    ({"parts.bar_width_mm": [1, 2]}, "parts.bar_width_mm", "must be"),
    ({"parts.bar_width_mm": object()}, "parts.bar_width_mm", "no TOML value"),
    ({"name.x": 1}, "name", "is not a table"),
])
def test_bad_changes_name_the_dotted_field(change, field, reason):
    with pytest.raises(DesignError) as exc:
        _load("hoeken.toml").replace(change)
    assert exc.value.field == field and reason in str(exc.value)


def test_the_nested_replace_names_an_unknown_field_and_checks_its_type():
    d = _load("hoeken.toml")
    with pytest.raises(DesignError, match="bar_widht_mm.*did you mean 'bar_width_mm'"):
        d.parts.replace(bar_widht_mm=8)
    with pytest.raises(DesignError) as exc:
        d.replace(parts=_load("powermouse.toml").flotor)
    assert exc.value.field == "parts" and "design.parts.replace" in str(exc.value)


def test_none_removes_a_key_and_the_default_applies_again():
    """The default of a key (PartsSpec's) comes back when the key is removed."""
    from cad.design.parts import PartsSpec

    d = _load("hoeken.toml").replace({"parts.bar_width_mm": 22.0})
    back = d.replace({"parts.bar_width_mm": None})
    assert back.parts.bar_width_mm == PartsSpec().bar_width_mm
    assert "bar_width_mm" not in back.raw["parts"]


def test_replace_is_what_the_solids_see():
    """The issue's failure end to end, without CAD: the changed bar width reaches the cheap
    mass model (heavier bars, larger M11), the refused one never does."""
    from cad.studies.codesign.cheap import apparent_mass

    d = _load("hoeken.toml")
    wide = d.replace(parts={"bar_width_mm": 26.0})
    assert apparent_mass(wide)["M11_max_g"] > apparent_mass(d)["M11_max_g"]
