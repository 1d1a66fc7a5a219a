"""A design's ``handle_script`` never runs behind the user's back (issue 11 item 3).

No opt-in -> refused before anything runs (build, check, fit); with ``--allow-scripts`` /
``HAPTICAD_ALLOW_SCRIPTS=1`` only scripts inside the design's folder; the resolved path is
printed when one runs; ``sys.exit`` and endless loops are contained in a child process.
"""

from __future__ import annotations

import shutil
import time
from pathlib import Path

import pytest
from cli_helpers import assert_one_line_error, hapticad

from cad.errors import DesignError

ROOT = Path(__file__).resolve().parents[3]
CASE = ROOT / "tests" / "cases" / "unsafe-designs"  # copied from the trial's shared/cases
COMMANDS = {
    "build": ["--fidelity", "preview", "--json"],
    "check": ["--json"],
    "fit": ["--target", "H11_kg_m2=3e-5", "--free", "parts.handle_height_mm", "--json"],
}


@pytest.fixture
def stranger(tmp_path, monkeypatch):
    monkeypatch.delenv("HAPTICAD_ALLOW_SCRIPTS", raising=False)
    for f in ("from_a_stranger.toml", "marker_handle.py"):
        shutil.copy(CASE / f, tmp_path / f)
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.mark.parametrize("cmd", sorted(COMMANDS))
def test_no_opt_in_runs_nothing(stranger, cmd):
    before = sorted(p.name for p in stranger.iterdir())
    code, _, err = hapticad(cmd, "from_a_stranger.toml", *COMMANDS[cmd])
    assert_one_line_error(code, err, "parts.handle_script", str(stranger / "marker_handle.py"),
                          "--allow-scripts", "HAPTICAD_ALLOW_SCRIPTS=1")
    assert not (stranger / "script_ran.txt").exists()
    assert sorted(p.name for p in stranger.iterdir()) == before  # no exports/, no .fit.toml


@pytest.mark.parametrize("where", ["../outside.py", "ABSOLUTE", "link.py"])
def test_opt_in_is_limited_to_the_design_folder(stranger, monkeypatch, where):
    outside = stranger.parent / f"{stranger.name}_elsewhere" / "outside.py"
    outside.parent.mkdir()
    shutil.copy(stranger / "marker_handle.py", outside)
    design = stranger / "from_a_stranger.toml"
    if where == "link.py":  # a symbolic link inside the folder pointing out of it
        (stranger / "link.py").symlink_to(outside)
        ref = "link.py"
    else:
        ref = str(outside) if where == "ABSOLUTE" else f"../{outside.parent.name}/outside.py"
    design.write_text(design.read_text().replace('"marker_handle.py"', f'"{ref}"'))
    code, _, err = hapticad("build", design.name, "--allow-scripts", "--json")
    assert_one_line_error(code, err, "parts.handle_script", str(outside), "outside the design's folder",
                          "--allow-scripts-anywhere")
    monkeypatch.setenv("HAPTICAD_ALLOW_SCRIPTS", "1")
    code, _, err = hapticad("check", design.name, "--json")
    assert_one_line_error(code, err, "outside the design's folder")
    assert not (outside.parent / "script_ran.txt").exists()
    from cad.design import load_design
    from cad.parts.handle import resolve_script

    monkeypatch.setenv("HAPTICAD_ALLOW_SCRIPTS", "anywhere")
    d = load_design(design)
    assert resolve_script(d.parts, d.source) == outside.resolve()


def _params():
    from cad.design.parts import PartsSpec
    from cad.parts.handle import handle_params

    return handle_params(PartsSpec(), floor_mm=10.0)


@pytest.mark.parametrize(
    ("body", "words"),
    [
        ("import sys\nsys.exit(0)\n", "called sys.exit(0) instead of returning a shape"),
        ("def make_handle(p):\n    raise SystemExit(3)\n", "make_handle() called sys.exit(3)"),
        ("import os\nos._exit(0)\n", "ended (exit status 0) without returning a shape"),
        ("import os, signal\nos.kill(os.getpid(), signal.SIGKILL)\n", "ended (exit status -9)"),
    ],
    ids=["sys.exit", "SystemExit-in-make_handle", "os._exit", "SIGKILL"],
)
def test_a_script_that_exits_is_an_error_naming_it(tmp_path, body, words):
    from cad.parts.handle import user_handle_shape

    script = tmp_path / "quits.py"
    script.write_text(body)
    with pytest.raises(DesignError) as ei:
        user_handle_shape(script, _params())
    assert ei.value.field == "parts.handle_script" and "quits.py" in str(ei.value)
    assert words in str(ei.value)


def test_an_endless_script_is_stopped_at_the_time_limit(tmp_path, monkeypatch, capsys):
    from cad.parts.handle import user_handle_shape

    script = tmp_path / "forever.py"
    script.write_text("while True:\n    pass\n")
    monkeypatch.setenv("HAPTICAD_SCRIPT_TIMEOUT_S", "1.5")
    t0 = time.monotonic()
    with pytest.raises(DesignError, match=r"forever\.py did not finish within 1\.5 s"):
        user_handle_shape(script, _params())
    assert time.monotonic() - t0 < 30  # contained: the build does not hang
    assert f"running design script {script}" in capsys.readouterr().err


def test_bad_time_limit_is_refused(tmp_path, monkeypatch):
    from cad.parts.handle import script_timeout_s

    for bad in ("0", "-1", "abc", "nan", "inf"):
        monkeypatch.setenv("HAPTICAD_SCRIPT_TIMEOUT_S", bad)
        with pytest.raises(DesignError, match="HAPTICAD_SCRIPT_TIMEOUT_S"):
            script_timeout_s()


def test_build_with_an_exiting_script_fails_and_publishes_nothing(stranger):
    """The trial's sys.exit(0) script: the build used to exit 0 with nothing written."""
    (stranger / "marker_handle.py").write_text("import sys\nsys.exit(0)\n")
    code, _, err = hapticad("build", "from_a_stranger.toml", "--allow-scripts", "--fidelity",
                            "preview", "--json")
    assert code == 2 and "Traceback" not in err, err
    lines = err.strip().splitlines()
    assert lines[0] == f"hapticad: running design script {stranger / 'marker_handle.py'}"
    assert "parts.handle_script" in lines[-1] and "marker_handle.py called sys.exit(0)" in lines[-1]
    assert sorted(p.name for p in stranger.iterdir()) == ["from_a_stranger.toml", "marker_handle.py"]


@pytest.mark.parametrize("argv", [
    ("fit", "--free", "parts.bar_width_mm", "--trials", "3"),  # a key the script does not touch
    ("datasheet",), ("wall",), ("tolerance", "--hole-mm", "0.05", "--samples", "100"),
    ("render", "--out", "pictures"), ("bench-log", "--out", "bench"),
], ids=lambda a: a[0] + ("-other-key" if a[0] == "fit" else ""))
def test_every_command_that_builds_refuses_a_script_at_load(stranger, argv):
    """Case unsafe-designs/from_a_stranger.toml, the whole kind: every command that builds the
    design refuses its script at load, before any work. ``fit --free parts.bar_width_mm``
    (a key the script does not touch) ran its whole search first, one log line per candidate
    each naming the refusal, then exit 2; now one line and nothing printed, nothing run."""
    before = sorted(p.name for p in stranger.iterdir())
    code, out, err = hapticad(argv[0], "from_a_stranger.toml", *argv[1:])
    assert_one_line_error(code, err, "parts.handle_script", str(stranger / "marker_handle.py"),
                          "HAPTICAD_ALLOW_SCRIPTS=1")
    assert out == "" and not (stranger / "script_ran.txt").exists()
    assert sorted(p.name for p in stranger.iterdir()) == before


def test_the_api_searches_refuse_a_script_before_their_first_candidate(stranger):
    """The same kind through the Python API (``cad.api.fit_design`` / ``cad.api.optimize``):
    with no opt-in, ``optimize`` returned ``best`` None (every candidate refused, reliability
    case optimize-script-design-misleading-exit1) and ``fit_design`` ran its search before
    the refusal. Now both raise DesignError ``parts.handle_script`` before the first candidate."""
    from cad.api import fit_design, load_design, optimize
    from cad.parts.handle import script_policy

    assert script_policy() == "off"  # the fixture removed HAPTICAD_ALLOW_SCRIPTS; no CLI override
    d = load_design(stranger / "from_a_stranger.toml")
    said: list[str] = []
    with pytest.raises(DesignError) as e:
        fit_design(d, free=("parts.bar_width_mm",), trials=3, echo=said.append)
    assert e.value.field == "parts.handle_script" and said == []
    with pytest.raises(DesignError) as e:
        optimize(d, objective="min-apparent-mass", trials=2, exact_top=1)
    assert e.value.field == "parts.handle_script" and "HAPTICAD_ALLOW_SCRIPTS=1" in str(e.value)
    assert not (stranger / "script_ran.txt").exists()
