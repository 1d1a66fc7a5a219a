"""CLI conventions: --version, bare help, progress off a terminal, provenance of written designs."""

from __future__ import annotations

import io
import tomllib

from cad import __version__
from cad.cli.cmd_massprops import format_g
from cad.cli.progress import stages
from tests.cli_helpers import hapticad


def test_version_and_bare_help():
    code, out, err = hapticad("--version")
    assert (code, out.strip(), err) == (0, f"hapticad {__version__}", "")
    code, out, err = hapticad()
    assert code == 0 and "Usage: hapticad" in out and "analyze" in out and err == ""


def test_progress_lines_off_a_terminal():
    buf = io.StringIO()  # not a TTY
    with stages("build", stream=buf) as progress:
        for i, s in enumerate(("layers", "layers", "parts", "exports")):
            progress(s, i, 4)
    assert buf.getvalue().splitlines() == [
        "hapticad: [0/4] layers", "hapticad: [2/4] parts", "hapticad: [3/4] exports"]


def test_massprops_text_rounding():
    assert format_g([8589.709636763706, 0.023192216019262007]) == "8589.71  0.0231922"
    # round-off below 1e-9 of the group's scale is printed as 0, not as 1e-19
    assert format_g([1.2172e-06, -1.58e-19, 2.59e-08]) == "1.2172e-06  0  2.59e-08"


def test_synth_out_provenance_and_source_targets(tmp_path):
    out = tmp_path / "synth.toml"
    code, _, err = hapticad("synth", "designs/hoeken.toml", "--objective", "min-torque-variation",
                            "--stroke-mm", "60", "--out", out)
    assert code == 0, err
    text = out.read_text()
    assert "--stroke-mm 60" in text.splitlines()[0] and "--objective min-torque-variation" in text
    raw = tomllib.loads(text)
    # the paper's H / M values of the Hoeken prototype are not targets of the new mechanism
    assert "targets" not in raw
    assert "H11_kg_m2" in text.splitlines()[1] and "not carried over" in text.splitlines()[1]


def test_swap_keeps_bounds_drops_source_values(tmp_path):
    src = tmp_path / "h.toml"
    src.write_text('name = "h"\n[mechanism]\nfamily = "hoeken"\n[targets]\n'
                   'H11_kg_m2 = { value = 2.97e-5, tol_rel = 0.3 }\nM11_max_g = { max = 60.0 }\n'
                   'dy_max_mm = { max = 0.5 }\n')
    out = tmp_path / "r.toml"
    code, _, err = hapticad("swap", src, "--to", "roberts", "--out", out)
    assert code == 0, err
    raw = tomllib.loads(out.read_text())
    assert raw["targets"] == {"M11_max_g": {"max": 60.0}, "dy_max_mm": {"max": 0.5}}
    assert "H11_kg_m2" in out.read_text().splitlines()[1]


def test_optimize_out_writes_the_optimum(tmp_path):
    """The written design reproduces the optimum's GII when evaluated on its own (gii command)."""
    import json

    out = tmp_path / "best.toml"
    code, o, err = hapticad("optimize", "designs/pantograph.toml", "--out", out, "--json")
    assert code == 0, err
    rep = json.loads(o)
    raw = tomllib.loads(out.read_text())
    assert {k: raw["mechanism"][k] for k in rep["best"]} == rep["best"]
    code, g, err = hapticad("gii", out, "--json")
    assert code == 0, err
    assert json.loads(g)["gii"] == rep["gii"]
    code, _, err = hapticad("optimize", "designs/pantograph.toml", "--out", "designs/pantograph.toml")
    assert code == 2 and "--out" in err and "input design" in err


def test_swap_out_names_the_design(tmp_path):
    out = tmp_path / "my_roberts.toml"
    code, _, err = hapticad("swap", "designs/hoeken.toml", "--to", "roberts", "--out", out)
    assert code == 0, err
    assert tomllib.loads(out.read_text())["name"] == "my_roberts"


FAMILY_DESIGNS = {"hoeken": "designs/hoeken.toml", "pantograph": "designs/pantograph.toml",
                  "twin-pantograph": "designs/haptic_mouse.toml",
                  "haptic-pen": "designs/haptic_pen.toml", "powermouse": "designs/powermouse.toml"}


def test_refusals_point_to_commands_that_accept_the_family():
    from cad.cli.families import COMMAND_FAMILIES

    for family, path in FAMILY_DESIGNS.items():
        for cmd in ("analyze", "gii"):
            if family in COMMAND_FAMILIES[cmd]:
                continue
            code, _, err = hapticad(cmd, path)
            assert code == 2 and "mechanism.family" in err and family in err, err
            hinted = [w for w in err.split("use:")[1].replace(",", " ").split() if w != "hapticad"]
            assert hinted and all(family in COMMAND_FAMILIES[c] for c in hinted), err
            assert cmd not in hinted


def test_written_designs_keep_their_handle_script(tmp_path):
    """A design written into another folder (synth/swap/fit/optimize --out) still names the
    same handle script (rebase_paths)."""
    from pathlib import Path

    from cad.design.writer import rebase_paths

    src = Path("designs/hoeken_cq_handle.toml").resolve()
    script = (src.parent / tomllib.loads(src.read_text())["parts"]["handle_script"]).resolve()
    out = tmp_path / "sub" / "s.toml"
    out.parent.mkdir()
    code, _, err = hapticad("synth", src, "--out", out)
    assert code == 0, err
    rel = tomllib.loads(out.read_text())["parts"]["handle_script"]
    assert (out.parent / rel).resolve() == script
    raw = rebase_paths({"parts": {"handle_script": "/abs/h.py"}}, src, out)
    assert raw["parts"]["handle_script"] == "/abs/h.py"


def test_analyze_report_only_into_a_folder_it_owns(tmp_path):
    from tests.cli_helpers import assert_one_line_error

    rep = tmp_path / "rep"
    code, _, err = hapticad("analyze", "designs/hoeken.toml", "--report", rep)
    assert code == 0, err
    assert (rep / "analysis.md").is_file() and (rep / "manifest.json").is_file()
    code, _, err = hapticad("analyze", "designs/hoeken.toml", "--report", rep)  # its own: fine
    assert code == 0, err
    (rep / "notes.txt").write_text("mine")
    code, _, err = hapticad("analyze", "designs/hoeken.toml", "--report", rep)
    assert_one_line_error(code, err, "--report", "notes.txt")
    assert (rep / "notes.txt").read_text() == "mine"


def test_optimize_method_is_for_pantographs_only():
    from tests.cli_helpers import assert_one_line_error

    code, _, err = hapticad("optimize", "designs/hoeken.toml", "--method", "culling")
    assert_one_line_error(code, err, "--method", "pantograph")


def test_wall_names_the_design_key_of_a_slipped_period(tmp_path):
    from pathlib import Path

    from tests.cli_helpers import assert_one_line_error

    d = tmp_path / "h.toml"
    d.write_text(Path("designs/hoeken.toml").read_text().replace("Te_s = 0.00033", "Te_s = 0.33"))
    code, _, err = hapticad("wall", d)
    assert_one_line_error(code, err, "stiffness.Te_s", "0.33")


def test_sweep_refuses_a_design_with_a_script_up_front(tmp_path):
    from tests.cli_helpers import assert_one_line_error

    code, _, err = hapticad("sweep", "designs/hoeken_cq_handle.toml", "--vary",
                            "parts.bar_thickness_mm=5,6", "--workers", "1", "--out", tmp_path / "sw")
    assert_one_line_error(code, err, "parts.handle_script")
    assert not (tmp_path / "sw").exists()


def test_help_texts_are_consistent():
    """Every option's help is a sentence (capitalised unless it starts with a value or a
    choice list, ending with a period), and no help loses text to markup ("[parts]")."""
    import typer

    from cad.cli.app import register_commands, app

    register_commands()
    for name, cmd in typer.main.get_command(app).commands.items():
        for p in cmd.params:
            h = getattr(p, "help", None)
            if h is None:
                continue
            first = h.split()[0]
            assert h.endswith("."), (name, p.opts, h)
            assert not (first.isalpha() and first.islower() and len(first) > 1
                        and " | " not in h[:60]), (name, p.opts, h)
    code, out, _ = hapticad("build", "--help")
    assert code == 0 and "[parts].fidelity" in " ".join(out.split())
