"""The documentation cannot drift from the CLI: README.md and the pages under docs/ have their
tables and command lines checked against the registered commands, and their command blocks run
(every `sh` line, every `python` block, wherever the text lives)."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest
import typer

from cad.cli.app import register_commands, app
from cad.cli.families import COMMAND_FAMILIES, NO_DESIGN_COMMANDS, markdown_table

README = Path(__file__).resolve().parents[2] / "README.md"
DOCS = README.parent / "docs"
#: every page of the documentation: the README and the site's Markdown pages
PAGES = [README, *sorted(DOCS.rglob("*.md"))]
COMMANDS_PAGE = DOCS / "commands.md"  # the commands x families table and the Commands table
DESIGN_PAGE = DOCS / "design-files.md"  # the design-file key tables


def _commands() -> dict:
    register_commands()
    return typer.main.get_command(app).commands


def _options(cmd) -> set[str]:
    return {o for p in cmd.params for o in (*p.opts, *p.secondary_opts) if o.startswith("--")}


def readme_command_lines() -> list[str]:
    """Every `hapticad ...` line inside a fenced code block of the README or a docs page."""
    lines = []
    for page in PAGES:
        in_block = False
        for raw in page.read_text().splitlines():
            if raw.startswith("```"):
                in_block = not in_block
                continue
            s = raw.strip().removeprefix("$ ")
            if in_block and s.startswith("hapticad "):
                lines.append(s.split(" #")[0].rstrip(" \\"))
    return lines


def test_pages_are_read():
    """The pages the blocks moved to are found: the first session in the README, the rest in docs/."""
    names = {p.relative_to(ROOT).as_posix() for p in PAGES}
    assert {"README.md", "docs/commands.md", "docs/design-files.md", "docs/papers.md"} <= names
    assert len(readme_command_lines()) >= 28  # the 28 lines the one-page README had, and more


def test_commands_table_matches_the_code():
    assert markdown_table() in COMMANDS_PAGE.read_text()


def test_every_command_is_in_the_family_table():
    assert set(_commands()) == set(COMMAND_FAMILIES) | set(NO_DESIGN_COMMANDS)


def test_commands_table_flags_exist():
    """Every `--flag` in the Commands table (docs/commands.md) exists on that command."""
    cmds = _commands()
    rows = re.findall(r"^\| `hapticad ([\w-]+)([^`]*)`", COMMANDS_PAGE.read_text(), flags=re.M)
    assert {r[0] for r in rows} == set(cmds), "every command has a row in the Commands table"
    for name, rest in rows:
        flags = set(re.findall(r"--[a-zA-Z][\w-]*", rest))
        assert flags <= _options(cmds[name]), (name, flags - _options(cmds[name]))


@pytest.mark.parametrize("line", readme_command_lines())
def test_readme_command_lines_parse(line):
    """Every command line in a README code block names a real command and real flags."""
    words = shlex.split(line)
    if words[1] in {"--version", "--help"}:
        return
    cmds = _commands()
    assert words[1] in cmds, line
    flags = {w.split("=")[0] for w in words[2:] if w.startswith("--")}
    assert flags <= _options(cmds[words[1]]) | {"--help"}, (line, flags - _options(cmds[words[1]]))


def test_readme_global_flag_lines_are_known():
    """`hapticad --version` style lines use a global flag the CLI has."""
    for line in readme_command_lines():
        words = shlex.split(line)
        if words[1].startswith("--"):
            assert words[1] in {"--version", "--help"}, line


# ---- the runnable blocks: every `sh` line is run, every `python` block executed ----

ROOT = README.parent


def _page_blocks(lang: str) -> list[tuple[str, str]]:
    """(page, body) of every fenced block opened with ```<lang> in the README and docs pages."""
    return [(page.relative_to(ROOT).as_posix(), body) for page in PAGES
            for body in re.findall(rf"^```{lang}\n(.*?)^```", page.read_text(), flags=re.M | re.S)]


def _blocks(lang: str) -> list[str]:
    """The bodies of the fenced blocks opened with ```<lang>, every page."""
    return [body for _, body in _page_blocks(lang)]


def _sh_lines(block: str) -> list[tuple[list[str], int]]:
    """(argv after `hapticad`, expected exit code) per line; `# exit N` sets the code."""
    out = []
    for raw in block.splitlines():
        if not raw.strip():
            continue
        cmd, _, comment = raw.partition(" #")
        m = re.search(r"exit (\d+)", comment)
        words = shlex.split(cmd)
        assert words[0] == "hapticad", f"an sh block holds only hapticad lines: {raw!r}"
        out.append((words[1:], int(m.group(1)) if m else 0))
    return out


@pytest.fixture
def designs_copy(tmp_path, monkeypatch):
    """cwd = a temporary folder holding a copy of the repository's designs/."""
    import shutil

    shutil.copytree(ROOT / "designs", tmp_path / "designs")
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_readme_has_runnable_blocks():
    """Blocks are found: fences start at column 0 (an indented one would escape the runner)."""
    for page in PAGES:
        assert not re.search(r"^ +```", page.read_text(), flags=re.M), page
    assert len(_blocks("sh")) >= 5 and len(_blocks("python")) >= 1
    assert sum(len(_sh_lines(b)) for b in _blocks("sh")) >= 12


@pytest.mark.parametrize("block", _blocks("sh"), ids=lambda b: b.split("\n")[0][:40])
def test_readme_sh_block_runs(block, designs_copy):
    """Each line of the block exits as its page says (in-process, cad.cli.app.run)."""
    from tests.cli_helpers import hapticad

    for argv, expected in _sh_lines(block):
        code, out, err = hapticad(*argv)
        assert code == expected, (argv, code, err[-2000:])
        if expected == 0:
            assert out.strip(), f"{argv}: printed nothing"
    # files a block says it writes are there, read back by a second tool
    for argv, expected in _sh_lines(block):
        if "--out" in argv and expected == 0:
            target = designs_copy / argv[argv.index("--out") + 1]
            assert target.exists(), target
            if target.suffix == ".toml":
                import tomllib

                assert tomllib.loads(target.read_text())["name"]


@pytest.mark.parametrize(("page", "block"), _page_blocks("python"), ids=lambda x: x.split("\n")[0][:40])
def test_readme_python_block_runs(page, block, designs_copy, capsys):
    exec(compile(block, page, "exec"), {"__name__": "__readme__"})
    assert capsys.readouterr().out.strip()


def _section(title: str) -> str:
    text = DESIGN_PAGE.read_text()
    start = text.index(title)
    nxt = re.search(r"^##+ ", text[start + len(title):], flags=re.M)
    return text[start: start + len(title) + (nxt.start() if nxt else len(text))]


def test_schema_tables_list_every_key_the_parsers_accept():
    """[parts] of four-bars and pantographs, the pen, the PowerMouse and the pantograph targets."""
    from dataclasses import fields

    from cad.design.pantograph import ACT_KEYS, MECH_KEYS, WS_KEYS, OPTIMIZABLE, PantographParts
    from cad.design.parts import ALLOWED_KEYS
    from cad.design.targets import PANTOGRAPH_TARGET_KEYS

    parts = _section("## `[parts]` keys")
    for key in ALLOWED_KEYS:
        assert re.search(rf"^\| `{key}` \|", parts, flags=re.M), key
    panto = _section("## Pantographs and the PowerMouse")
    for f in fields(PantographParts):
        assert f"`{f.name}`" in panto, f.name
    for table in (MECH_KEYS, WS_KEYS, ACT_KEYS, OPTIMIZABLE):
        for keys in table.values():
            for key in keys:
                assert key == "family" or f"{key}`" in panto, key
    for key in PANTOGRAPH_TARGET_KEYS:
        assert f"`{key}`" in panto, key
    for key in ("magnet_length_mm", "rattle_mm", "gap_mm", "edge_mm", "housing_wall_mm",
                "knob_diameter_mm", "range_deg", "plate_alpha", "peak_power_W"):
        assert f"{key}`" in panto, key


def test_handle_params_are_all_documented():
    """Every key the handle script receives is named in the design-file page and the parts docstring."""
    import inspect

    import cad.design.parts as parts_mod
    from cad.parts import handle

    keys = re.findall(r'"(\w+_mm)":', inspect.getsource(handle.handle_params))
    assert len(keys) == 5
    row = next(ln for ln in DESIGN_PAGE.read_text().splitlines() if ln.startswith("| `handle_script`"))
    for key in keys:
        assert f"`{key}`" in row and f"``{key}``" in parts_mod.__doc__, key


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_readme_points_nowhere_outside_and_names_no_internal_issue(page):
    text = page.read_text()
    assert "../shared" not in text
    assert not re.search(r"\bissues? \d+|\(issue|where the issues", text)
    assert not re.search(r":(class|data|mod|func):`", text)


def _anchor(heading: str) -> str:
    """The anchor a code host (and the site, pymdownx.slugs with case=lower) gives a heading."""
    text = re.sub(r"[`*]", "", heading).strip().lower()
    return re.sub(r"[^\w\- ]", "", text).replace(" ", "-")


def test_readme_is_the_front_door_and_its_links_resolve():
    """README.md stays short (at most ~250 lines) and opens with the two commands; every link
    it gives into docs/ names a page that exists and, with an anchor, a heading of that page
    (the site build checks links between pages; the README is not part of the site)."""
    text = README.read_text()
    assert len(text.splitlines()) <= 250
    assert text.startswith("```\npython3 -m venv .venv && .venv/bin/pip install -q -c constraints.txt -e . && "
                           ".venv/bin/hapticad build designs/hoeken_capstan.toml\n")
    links = re.findall(r"\]\((docs/[^)#]+)(?:#([^)]+))?\)", text) + re.findall(r'src="(docs/[^"]+)"()', text)
    assert len(links) >= 20
    for path, anchor in links:
        page = ROOT / path
        assert page.is_file(), path
        if anchor:
            heads = re.findall(r"^#{1,6} (.+)$", page.read_text(), flags=re.M)
            assert anchor in {_anchor(h) for h in heads}, (path, anchor)


def test_the_first_command_builds_a_device_meeting_every_limit(tmp_path):
    """Issue 35 item 5: the README's first command builds a design whose datasheet meets every
    limit; read back from ``hapticad datasheet --json`` (the datasheet's own verdicts), with the
    continuous force the README types beside the picture."""
    import json
    import subprocess
    import sys

    first = README.read_text().splitlines()[1]
    design = re.search(r"hapticad build (\S+)$", first).group(1)
    r = subprocess.run([sys.executable, "-m", "cad", "datasheet", design, "--json"], cwd=ROOT,
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    rows = json.loads(r.stdout)["datasheet"]["rows"]
    limited = [x for x in rows if x.get("limit") is not None]
    assert len(limited) >= 8 and all(x["verdict"] == "ok" for x in limited), [
        (x["key"], x["value"], x["verdict"]) for x in limited if x["verdict"] != "ok"]
    cont = next(x for x in rows if x["key"] == "continuous_force_N")["value"]
    assert f"{cont:.2f} N continuous at the handle" in README.read_text()
