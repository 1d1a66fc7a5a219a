"""The [transmission] table (issue 35, a public contract): cad.design.transmission.parse_transmission
returns the ratio the table implies (n = drum / capstan, by hand) and refuses bad input with one
line naming the field, the value, the reason and the likely unit slip."""

from __future__ import annotations

import pytest

from cad.design.transmission import DEFAULT_WRAPS, DIRECT, Transmission, parse_transmission
from cad.errors import DesignError

ISSUE_TABLE = {"kind": "capstan", "capstan_diameter_mm": 10.0, "drum_diameter_mm": 120.0,
               "cable": "steel-7x19-0.6"}


def test_the_issue_table_parses_to_ratio_12():
    t = parse_transmission(ISSUE_TABLE)
    assert t == Transmission("capstan", 12.0, 10.0, 120.0, "steel-7x19-0.6", DEFAULT_WRAPS)
    assert t.is_capstan and t.pretension_N is None and t.cable_EA_N is None


def test_wraps_pretension_and_rope_stiffness_are_read_when_given():
    t = parse_transmission({**ISSUE_TABLE, "wraps": 4.5, "pretension_N": 40, "cable_EA_N": 2.0e4})
    assert (t.wraps, t.pretension_N, t.cable_EA_N) == (4.5, 40.0, 2.0e4)


def test_ratio_instead_of_drum_gives_the_drum():
    t = parse_transmission({"kind": "capstan", "capstan_diameter_mm": 10, "ratio": 16,
                            "cable": "steel-7x7-0.54"})
    assert t.drum_diameter_mm == pytest.approx(160.0) and t.ratio == 16.0


def test_omitted_or_direct_is_direct_drive():
    assert parse_transmission(None) is DIRECT
    assert parse_transmission({"kind": "direct"}) == Transmission()
    assert parse_transmission({}).ratio == 1.0 and not DIRECT.is_capstan


@pytest.mark.parametrize("tab, field, words", [
    ({**ISSUE_TABLE, "kind": "belt"}, "transmission.kind", "must be one of direct, capstan, got 'belt'"),
    ({"kind": "direct", "ratio": 3}, "transmission.ratio", 'only for kind = "capstan"'),
    ({**ISSUE_TABLE, "ratio": 12}, "transmission.drum_diameter_mm", "not both"),
    ({k: v for k, v in ISSUE_TABLE.items() if k != "drum_diameter_mm"},
     "transmission.drum_diameter_mm", "missing"),
    ({**ISSUE_TABLE, "capstan_diameter_mm": 0.01}, "transmission.capstan_diameter_mm",
     "did you give metres? (0.01 metres = 10 mm)"),
    ({**ISSUE_TABLE, "drum_diameter_mm": 0.12}, "transmission.drum_diameter_mm",
     "did you give metres? (0.12 metres = 120 mm)"),
    ({**ISSUE_TABLE, "drum_diameter_mm": 8.0}, "transmission.drum_diameter_mm",
     "8 mm must be larger than capstan_diameter_mm = 10 mm"),
    ({"kind": "capstan", "capstan_diameter_mm": 10, "ratio": 0.25, "cable": "steel-7x7-0.54"},
     "transmission.ratio", "did you give capstan / drum? (1 / 0.25 = 4)"),
    # 0 and below: the same lower bound as 0.25 (a new user found "> 0" for 0, "> 1" for 0.25)
    ({"kind": "capstan", "capstan_diameter_mm": 10, "ratio": 0, "cable": "steel-7x7-0.54"},
     "transmission.ratio", "must be > 1 (drum / capstan), got 0"),
    ({"kind": "capstan", "capstan_diameter_mm": 10, "ratio": -4.0, "cable": "steel-7x7-0.54"},
     "transmission.ratio", "must be > 1 (drum / capstan), got -4.0"),
    ({"kind": "capstan", "capstan_diameter_mm": 10, "ratio": 80, "cable": "steel-7x7-0.54"},
     "transmission.ratio", "must be in (1, 50], got 80"),
    # the drum a ratio implies is held to the drum's own bound (a tester: ratio 50 on a 32 mm
    # capstan passed with a warning while drum_diameter_mm = 1600 was refused)
    ({"kind": "capstan", "capstan_diameter_mm": 32, "ratio": 50, "cable": "steel-7x7-0.54"},
     "transmission.ratio", "50 on a 32 mm capstan asks for a 1600 mm drum, above 1000 mm"),
    ({**ISSUE_TABLE, "cable": "steel-7x19-0.54"}, "transmission.cable", "unknown cable 'steel-7x19-0.54'"),
    ({**ISSUE_TABLE, "cable": 0.6}, "transmission.cable", "must be a catalog key"),
    ({k: v for k, v in ISSUE_TABLE.items() if k != "cable"}, "transmission.cable", "missing"),
    ({**ISSUE_TABLE, "capstan_diam_mm": 10}, "transmission.capstan_diam_mm", "unknown key"),
    ({**ISSUE_TABLE, "capstan_diameter_mm": "10"}, "transmission.capstan_diameter_mm", "must be a number"),
])
def test_bad_tables_one_line_naming_field_value_reason(tab, field, words):
    with pytest.raises(DesignError) as e:
        parse_transmission(tab)
    assert e.value.field == field
    assert words in str(e.value) and "\n" not in str(e.value)


def test_prefix_names_the_motor_table():
    with pytest.raises(DesignError, match=r"^motors\.1\.transmission\.kind:"):
        parse_transmission({"kind": "gear"}, prefix="motors.1.transmission")


def test_one_table_per_motor_or_one_for_all():
    from cad.design.transmission import parse_transmissions

    assert parse_transmissions(None, 2) == (DIRECT, DIRECT)
    both = parse_transmissions(ISSUE_TABLE, 2)
    assert both[0] == both[1] and both[0].ratio == 12.0
    mixed = parse_transmissions([{"kind": "direct"}, ISSUE_TABLE], 2)
    assert mixed[0] is DIRECT and mixed[1].is_capstan
    with pytest.raises(DesignError, match=r"^transmission: must be one table or 2 \(one per motor\), got an array of 3 tables"):
        parse_transmissions([ISSUE_TABLE] * 3, 2)
    with pytest.raises(DesignError, match=r"^transmission\.2\.kind: must be one of"):
        parse_transmissions([ISSUE_TABLE, {"kind": "belt"}], 2)
    with pytest.raises(DesignError, match=r"^transmission: must be a table or an array"):
        parse_transmissions("capstan", 1)


def test_a_twin_pantograph_takes_a_transmission_on_its_four_motors_and_names_what_cannot_be_laid_out(tmp_path):
    """[transmission] on a twin-pantograph (haptic mouse) design: validated at load for its four
    motors (``check`` gets past the design); a capstan whose solids cannot be placed is refused
    in one line naming the field, exit 2: the 20 mm capstan on a 60 mm drum puts the motor
    (20 + 60) / 2 + 2 = 42 mm from its joint, under the RE 35's 55 mm mount plate plus 1 mm;
    the analyses and the built design: tests/families/pantograph/test_twin_capstan.py."""
    from pathlib import Path

    from cli_helpers import assert_one_line_error, hapticad

    src = Path(__file__).resolve().parents[3] / "designs" / "haptic_mouse.toml"
    p = tmp_path / "p.toml"
    p.write_text(src.read_text() + '\n[transmission]\nkind = "capstan"\ncapstan_diameter_mm = 20.0\n'
                 'ratio = 3.0\ncable = "steel-7x7-0.45"\n')
    code, _, err = hapticad("check", p)
    assert_one_line_error(code, err, "transmission.centre_distance_mm", "42 mm", ">= 56")
    p.write_text(src.read_text() + '\n[[transmission]]\nkind = "direct"\n\n[[transmission]]\nkind = "direct"\n')
    code, _, err = hapticad("check", p)
    assert_one_line_error(code, err, "transmission: must be one table or 4 (one per motor), got an array of 2 tables")
