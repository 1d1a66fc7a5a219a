"""Issue 23 try-it (tester t23): bad inputs to the Python API give one DesignError naming the
field, as the command's flags do (reference: the CLI's flag checks, cad/cli/flags.py and
cad.design.bounds.FLAGS), never a TypeError/AttributeError or a silent result."""

from __future__ import annotations

from pathlib import Path

import pytest

import cad
from cad.errors import DesignError

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(autouse=True)
def _at_root(monkeypatch):
    monkeypatch.chdir(ROOT)  # the bundled designs by their relative paths, as the docs give them


@pytest.fixture(scope="module")
def hoeken():
    return cad.load_design(ROOT / "designs" / "hoeken.toml")


@pytest.mark.parametrize("samples, field", [("x", "--samples"), (-3, "--samples"),
                                            (1, "--samples"), (2.5, "--samples"),
                                            (True, "--samples")])
def test_analyze_bad_samples(hoeken, samples, field):
    with pytest.raises(DesignError) as e:
        cad.analyze(hoeken, samples=samples)
    assert e.value.field == field and "\n" not in str(e.value)


def test_analyze_inertia_not_a_mapping(hoeken):
    with pytest.raises(DesignError, match="^inertia: "):
        cad.analyze(hoeken, inertia=[1e-4, 0, 1e-4, 1e-5])


@pytest.mark.parametrize("kw, field", [
    ({"model": "x"}, "--model"),                 # was silently run as 'reduced'
    ({"K_N_per_m": -5}, "--K-N-per-m"),          # was a result for a negative wall
    ({"K_N_per_m": "5"}, "--K-N-per-m"),         # was silently ignored
    ({"encoder_counts_per_rev": 2.5}, "--encoder-counts-per-rev"),
])
def test_wall_bad_options(hoeken, kw, field):
    with pytest.raises(DesignError) as e:
        cad.wall(hoeken, **kw)
    assert e.value.field == field


@pytest.mark.parametrize("call", [
    lambda d: cad.analyze("designs/hoeken.toml"), lambda d: cad.gii(None),
    lambda d: cad.device_datasheet("designs/hoeken.toml"), lambda d: cad.assemble(None),
    lambda d: cad.load_design(None), lambda d: cad.load_design(5),
])
def test_not_a_design(hoeken, call):
    with pytest.raises(DesignError) as e:
        call(hoeken)
    assert e.value.field == "design"


@pytest.mark.parametrize("to", [None, 5])
def test_swap_bad_to(hoeken, to):
    with pytest.raises(DesignError) as e:
        cad.swap(hoeken, to=to)
    assert e.value.field == "--to"


@pytest.mark.parametrize("targets", [[5], None])
def test_check_bad_targets(hoeken, targets):
    with pytest.raises(DesignError) as e:
        cad.check(hoeken, targets=targets)
    assert e.value.field == "targets"


def test_synth_and_optimize_bad_numbers(hoeken):
    with pytest.raises(DesignError) as e:
        cad.synth(hoeken, mu_min_deg="30")
    assert e.value.field == "--mu-min-deg"
    with pytest.raises(DesignError) as e:
        cad.synth(hoeken, mu_min_deg=100)  # a transmission angle lies in [0, 90)
    assert e.value.field == "--mu-min-deg"
    for trials in (-1, "5"):
        with pytest.raises(DesignError) as e:
            cad.optimize(hoeken, trials=trials)
        assert e.value.field == "--trials"


def test_voicecoil_metres_refused_as_the_command_does():
    # hapticad voicecoil --magnet-length-mm 0.02 ... exits 2 ("did you give metres?")
    with pytest.raises(DesignError, match="metres") as e:
        cad.voicecoil(0.02, 0.008, 0.004, 0.006)
    assert e.value.field == "magnet_length_mm"


@pytest.mark.parametrize("kw, field", [
    ({"formats": ("xyz",)}, "formats"),          # was built with no error
    ({"formats": 5}, "formats"),
    ({"phi1_deg": "x", "formats": ("step",)}, "--phi1-deg"),
    ({"allow_scripts": True, "formats": ("step",)}, "allow_scripts"),  # was a TypeError
])
def test_build_design_bad_options(hoeken, tmp_path, kw, field):
    with pytest.raises(DesignError) as e:
        cad.build_design(hoeken, tmp_path / "out", fidelity="inertia", **kw)
    assert e.value.field == field
    assert not (tmp_path / "out").exists()


def test_cache_clear_must_be_bool():
    with pytest.raises(DesignError) as e:  # "no" is truthy: it cleared the cache
        cad.cache(clear="no")
    assert e.value.field == "clear"


@pytest.mark.parametrize("changes", ["parts.bar_width_mm", [("parts.bar_width_mm", 24)]])
def test_replace_positional_not_a_mapping(hoeken, changes):
    with pytest.raises(DesignError) as e:  # was TypeError: 'str' object is not a mapping
        hoeken.replace(changes)
    assert e.value.field == "changes"


def test_pen_workspace_out_of_reach_is_one_design_error():
    """A pen workspace partly out of reach (centre 330 mm out; the arms reach ~320 mm) loads,
    then `hapticad build` / cad.assemble died with a bare ValueError traceback (exit 1, the
    code of a missed target). It is the workspace's fault: DesignError naming it."""
    pen = cad.load_design("designs/haptic_pen.toml").replace(
        {"workspace.center_mm": [0.0, 330.0, 0.0]})
    with pytest.raises(DesignError) as e:
        cad.assemble(pen, fidelity="inertia")
    assert e.value.field == "workspace" and "cannot be reached" in str(e.value)


def test_pantograph_workspace_out_of_reach_is_a_design_error_not_a_collision():
    panto = cad.load_design("designs/pantograph.toml").replace({"workspace.center_mm": [0.0, 60.0]})
    with pytest.raises(DesignError) as e:  # was InterferenceError "workspace motion: ..."
        cad.assemble(panto, fidelity="inertia")
    assert e.value.field == "workspace" and "cannot be reached" in str(e.value)


def test_pen_build_cli_out_of_reach_exits_2_in_one_line(tmp_path):
    import subprocess
    import sys
    src = Path("designs/haptic_pen.toml").read_text()
    assert "center_mm = [0.0, 200.0, 0.0]" in src
    (tmp_path / "pen.toml").write_text(src.replace("center_mm = [0.0, 200.0, 0.0]",
                                                   "center_mm = [0.0, 330.0, 0.0]"))
    r = subprocess.run([sys.executable, "-m", "cad", "build", str(tmp_path / "pen.toml"),
                        "--fidelity", "inertia", "--formats", "step", "--out",
                        str(tmp_path / "out")], capture_output=True, text=True, timeout=600)
    assert r.returncode == 2, r.stderr[-2000:]
    assert "Traceback" not in r.stderr
    assert "hapticad: error: workspace:" in r.stderr
    assert not (tmp_path / "out").exists()


def test_pen_report_places_every_part_file_as_assembly_step(shared_build):
    """report.json ``placement`` (issue 23: every per-part file in its instance frame, for every
    family) was missing from the haptic pen's report. Reference: each ``parts/<kind>.step``
    moved by ``tf_world_body @ tf_body_part`` has the volume and centroid of its instance in
    ``assembly.step`` read back with OCCT (the check of tests/unit/assembly/test_part_frames.py)."""
    import numpy as np
    from step_pairs import read_parts
    from unit.assembly.test_part_frames import (
        located_volume_props,
        read_step_solids,
        unplaced_volume_props,
    )

    from tests.conftest import PEN_FORMATS

    _, out, rep = shared_build("haptic_pen.toml", PEN_FORMATS, "inertia")  # report.json read back
    pl = rep["placement"]
    files = {n: unplaced_volume_props(read_step_solids(out / k["file"]))[:2]
             for n, k in pl["kinds"].items() if k["file"] is not None}
    in_step = dict(read_parts(out / "assembly.step"))
    checked = 0
    for name, inst in pl["instances"].items():
        if inst["kind"] not in files:
            continue
        vol, c_part = files[inst["kind"]]
        T = np.array(pl["tf_world_body"][inst["body"]]) @ np.array(inst["tf_body_part"])
        vol_asm, c_asm = located_volume_props(in_step[name])
        assert vol_asm == pytest.approx(vol, rel=1e-9), name
        assert np.abs(T[:3, :3] @ c_part + T[:3, 3] - c_asm).max() <= 1e-9 * max(
            np.linalg.norm(c_asm), 1.0), name
        checked += 1
    assert checked >= 100  # 114 listed instances, the motor shafts have no file


def _sh_block_lines() -> list[tuple[str, str]]:
    import re

    pages = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
    return [(p.relative_to(ROOT).as_posix(), line) for p in pages
            for body in re.findall(r"^```sh\n(.*?)^```", p.read_text(), flags=re.M | re.S)
            for line in body.splitlines() if line.strip()]


@pytest.mark.parametrize("page, line", _sh_block_lines())
def test_sh_lines_mean_in_a_shell_what_the_readme_test_runs(page, line, tmp_path):
    """tests/docs/test_readme.py runs each `sh` line split by shlex, with no shell; a user pastes it
    into one. `--target gii>=0.6` (docs/papers.md) is, in sh, `--target gii` with stdout sent to
    a file named `=0.6` (exit 2). Reference: bash itself, `hapticad` a function printing its
    argv; the same words as shlex gives, and no file made."""
    import shlex
    import subprocess

    cmd = line.partition(" #")[0]
    r = subprocess.run(["bash", "-c", 'hapticad() { printf "%s\\0" "$@"; }\n' + cmd],
                       cwd=tmp_path, capture_output=True, timeout=30)
    assert r.returncode == 0, (page, line, r.stderr)
    assert r.stdout.decode().split("\0")[:-1] == shlex.split(cmd)[1:], (page, line)
    assert not list(tmp_path.iterdir()), (page, line, "the shell made a file")


@pytest.mark.parametrize("call, field", [
    (lambda d: cad.fit_design(d, targets=5, free=["parts.bar_width_mm"]), "targets"),
    (lambda d: cad.fit_design(d, targets=["M11_max_g<=60"], free=None), "free"),
    (lambda d: cad.fit_design("designs/hoeken.toml"), "design"),
    (lambda d: cad.tolerance(d, hole_mm=0.05, samples=200, targets=5), "targets"),
    (lambda d: cad.tolerance(d, hole=5, samples=200), "hole"),
    (lambda d: cad.tolerance(d, hole_mm="0.05", samples=200), "--hole-mm"),
    (lambda d: cad.tolerance(d, hole_mm=0.05, samples=200, seed="a"), "--seed"),
    (lambda d: cad.tolerance("designs/hoeken.toml", hole_mm=0.05, samples=200), "design"),
    (lambda d: cad.sweep_design("designs/hoeken.toml", 5, "/nonexistent/unused"), "vary"),
    (lambda d: cad.sweep_design(d, ["parts.bar_width_mm=10,12"], "/nonexistent/unused"), "design"),
    (lambda d: cad.mass_properties(None), "FILE"),
])
def test_study_functions_bad_types(hoeken, call, field):
    with pytest.raises(DesignError) as e:  # were TypeError / AttributeError tracebacks
        call(hoeken)
    assert e.value.field == field


def test_cad_api_commands_after_a_bare_import_cad():
    """docs/python-api.md: ``cad.api.COMMANDS`` after ``import cad`` (was AttributeError: module
    'cad' has no attribute 'api', until some function had loaded it)."""
    import subprocess
    import sys

    code = ("import cad; c = cad.api.COMMANDS; assert getattr(cad, c['analyze']) is cad.analyze; "
            "import sys; assert 'build123d' not in sys.modules")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                       cwd=ROOT)
    assert r.returncode == 0, r.stderr


def test_api_design_error_is_the_command_error_line(tmp_path):
    """docs/python.md: a DesignError "naming the dotted field ..., as the command's one error
    line does". A bar width typed in metres: the command's line ends "did you give metres?
    (0.012 metres = 12 mm)"; cad.load_design and design.replace dropped that hint.
    Reference: the CLI's error line for the same file."""
    from cli_helpers import hapticad

    src = (ROOT / "designs" / "hoeken.toml").read_text()
    bad = tmp_path / "hw.toml"
    bad.write_text(src.replace("[parts]\n", "[parts]\nbar_width_mm = 0.012\n", 1))
    code, _, err = hapticad("check", bad)
    assert code == 2 and "did you give metres?" in err, err
    line = err.strip().removeprefix("hapticad: error: ")
    with pytest.raises(DesignError) as e:
        cad.load_design(bad)
    assert str(e.value) == line
    with pytest.raises(DesignError) as e:
        cad.load_design(ROOT / "designs" / "hoeken.toml").replace(parts={"bar_width_mm": 0.012})
    assert str(e.value) == line and e.value.field == "parts.bar_width_mm"
