"""Bad input is one stderr line even when the value is also implausible (cad/design/bounds.py
:func:`error_line`, the CLI's error boundary in cad/cli/app.py).

The adversarial tester's designs (bundled PowerMouse / Hoeken design with one key changed):
each used to print a ``warning: ... implausible ...; did you give metres?`` line before the
error line. Now: exit 2, exactly one line naming the field and the value, the unit-slip hint
in it where the slip is plain, nothing written, no CAD library imported. A run that succeeds
still prints its warning line (and lists it in ``--json``).
"""

from __future__ import annotations

import copy
import io
import json
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
import tomli_w
from cli_helpers import assert_one_line_error, hapticad

from cad.design import bounds

ROOT = Path(__file__).resolve().parents[2]
DESIGNS = ROOT / "designs"
CAD_MODULES = ("build123d", "OCP", "cadquery")

#: (bundled design, key, value, words the one line must hold). Hints are checked by value:
#: 0.01 m = 10 mm >= the 5.3 mm the M4 tip needs; 6.4 cm = 64 mm >= the 45.6 mm edge the
#: inner magnets need; 0.6 cm = 6 mm = 2 x the 3 mm motion range.
CASES = [
    ("powermouse", "handle.diameter_mm", 0.01,
     ["handle.diameter_mm", "0.01 mm", "need >= 5.3", "did you give metres? (0.01 metres = 10 mm)"]),
    ("powermouse", "stator.post_diameter_mm", 0.008,
     ["stator.post_diameter_mm", "0.008 mm", "did you give metres? (0.008 metres = 8 mm)"]),
    ("powermouse", "flotor.edge_mm", 0.064,
     ["flotor.edge_mm", "use edge_mm >= 45.6", "did you give metres? (0.064 metres = 64 mm)"]),
    ("powermouse", "flotor.edge_mm", 6.4,
     ["flotor.edge_mm", "use edge_mm >= 45.6", "did you give cm? (6.4 cm = 64 mm)"]),
    # refused as a corner hole too small for the post's motion: the note names the real slip,
    # not a "did you give cm?" for the corner hole the user did not change
    ("powermouse", "flotor.edge_mm", 640,
     ["flotor.corner_hole_mm", "with flotor.edge_mm = 640 mm",
      "note: flotor.edge_mm = 640 mm is implausible"]),
    # plausible edge, same rule: both keys named, no slip guessed for the corner hole
    ("powermouse", "flotor.edge_mm", 300,
     ["flotor.corner_hole_mm: 25.8 mm", "with flotor.edge_mm = 300 mm", "use corner_hole_mm >= "]),
    ("powermouse", "stator.housing_wall_mm", 400,
     ["stator.housing_wall_mm", "400 mm", "implausible", "over 300 mm"]),
    ("powermouse", "actuator.rattle_mm", 0.6,
     ["motion.range_mm", "3 mm", "actuator.rattle_mm = 0.6 mm", "<= actuator.rattle_mm/2 = 0.3",
      "actuator.rattle_mm = 0.6: did you give cm? (0.6 cm = 6 mm)"]),
    ("hoeken", "parts.post_diameter_mm", 1000,
     ["A4 post", "note: parts.post_diameter_mm = 1000 mm is implausible"]),
    ("hoeken", "parts.layer_gap_mm", 0.002,
     ["parts.layer_gap_mm", "0.002 mm", "clearance_min_mm = 0.5",
      "did you give metres? (0.002 metres = 2 mm)"]),
]


def _design(tmp_path: Path, name: str, field: str, value) -> Path:
    raw = copy.deepcopy(tomllib.loads((DESIGNS / f"{name}.toml").read_text()))
    table, key = field.split(".", 1)
    raw.setdefault(table, {})[key] = value
    p = tmp_path / f"{name}.toml"
    p.write_text(tomli_w.dumps(raw))
    return p


@pytest.mark.parametrize("name, field, value, needles", CASES,
                         ids=[f"{c[1]}={c[2]}" for c in CASES])
def test_tester_input_is_one_line(tmp_path, name, field, value, needles):
    design = _design(tmp_path, name, field, value)
    out_dir = tmp_path / "out"
    had_cad = [m for m in CAD_MODULES if m in sys.modules]
    code, out, err = hapticad("build", design, "--out", out_dir)
    assert_one_line_error(code, err, "hapticad: error: ", *needles)
    assert "warning" not in err
    assert "(25.8 cm" not in err  # the bundled corner hole is no slip
    assert out == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == [design.name]  # nothing written
    assert not [m for m in CAD_MODULES if m in sys.modules and m not in had_cad]


def test_tester_inputs_import_no_cad_library(tmp_path):
    """All the cases in one fresh interpreter: every refusal comes before any CAD import."""
    paths = []
    for i, (name, field, value, _) in enumerate(CASES):
        (tmp_path / f"c{i}").mkdir()
        paths.append(str(_design(tmp_path / f"c{i}", name, field, value)))
    code = (
        "import sys\n"
        "sys.path.insert(0, 'tests')\n"
        "from cli_helpers import hapticad\n"
        f"codes = [hapticad('build', p, '--out', p + '.out')[0] for p in {paths!r}]\n"
        "assert codes == [2] * len(codes), codes\n"
        f"bad = [m for m in {CAD_MODULES!r} if m in sys.modules]\n"
        "assert not bad, bad\n"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT,
                       env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin",
                            "HAPTICAD_CACHE_DIR": str(tmp_path / "cache")})
    assert r.returncode == 0, r.stderr
    assert not any(Path(p + ".out").exists() for p in paths)


def test_successful_run_still_prints_its_warning(tmp_path):
    """analyze does not mesh the parts: a 0.0005 mm STL tolerance is implausible, not fatal."""
    design = _design(tmp_path, "hoeken", "parts.stl_tolerance_mm", 0.0005)
    code, out, err = hapticad("analyze", design, "--json")
    assert code == 0, err
    warns = json.loads(out)["warnings"]
    assert len(warns) == 1 and warns[0].startswith("parts.stl_tolerance_mm = 0.0005 mm is implausible")
    assert "did you give metres? (0.0005 metres = 0.5 mm)" in warns[0]
    assert err.splitlines() == [f"hapticad: warning: {warns[0]}"]


def test_other_implausible_values_are_named_in_the_note(tmp_path):
    """Two implausible keys, an error about a third thing: one line, the slip first."""
    raw = tomllib.loads((DESIGNS / "powermouse.toml").read_text())
    raw["stator"]["housing_wall_mm"] = 400
    raw["handle"]["knob_diameter_mm"] = 0.024
    raw["actuator"]["peak_power_W"] = 1.0  # below power_W = 8: refused at load
    p = tmp_path / "d.toml"
    p.write_text(tomli_w.dumps(raw))
    code, out, err = hapticad("build", p, "--out", tmp_path / "out")
    assert_one_line_error(code, err, "actuator.peak_power_W: 1 W must be >= actuator.power_W = 8 W",
                          "note: handle.knob_diameter_mm = 0.024 mm looks like metres "
                          "(0.024 metres = 24 mm)", "(also implausible: stator.housing_wall_mm)")
    assert not (tmp_path / "out").exists()


def test_error_line_unit_slip_must_meet_the_stated_limit():
    """The slip is named only when the converted value meets the limit the message states."""
    bounds.reset()
    try:
        bounds.check_number("flotor.edge_mm", 6.4, bounds.PART_MM)  # plausible: no warning
        assert bounds.collected() == []
        line = bounds.error_line("flotor.edge_mm: too small; use edge_mm >= 45.6")
        assert line.endswith("; did you give cm? (6.4 cm = 64 mm)")
        # 64 mm (cm) or 162.56 mm (inches) would not meet ">= 200": nothing is added
        assert bounds.error_line("flotor.edge_mm: too small; use edge_mm >= 200") == \
            "flotor.edge_mm: too small; use edge_mm >= 200"
        # a limit the value already meets is about something else: nothing is added
        assert bounds.error_line("flotor.edge_mm: odd; need >= 2 mm") == "flotor.edge_mm: odd; need >= 2 mm"
        # within a factor 2 of the limit: a design choice, not a slip (25.8 cm would meet 30)
        bounds.check_number("flotor.corner_hole_mm", 25.8, bounds.PART_MM)
        assert bounds.error_line("flotor.corner_hole_mm: use corner_hole_mm >= 30") == \
            "flotor.corner_hole_mm: use corner_hole_mm >= 30"
        # a key not typed (no value recorded): nothing is added
        assert bounds.error_line("flotor.lid_mm: need >= 45") == "flotor.lid_mm: need >= 45"
    finally:
        bounds.reset()


def test_warnings_print_before_the_first_progress_line():
    """build's long stages: pending warnings come first (seen before minutes of work)."""
    from cad.cli.progress import stages

    bounds.reset()
    try:
        bounds.check_number("flotor.edge_mm", 640.0, bounds.PART_MM)
        buf = io.StringIO()
        with stages("build", stream=buf) as progress:
            progress("solids", 0, 2)
            progress("checks", 1, 2)
        lines = buf.getvalue().splitlines()
        assert lines[0].startswith("hapticad: warning: flotor.edge_mm = 640 mm is implausible")
        assert lines[1:] == ["hapticad: [0/2] solids", "hapticad: [1/2] checks"]
    finally:
        bounds.reset()
