"""The README cannot drift from the CLI: its tables and command lines are checked against
the registered commands, and its command blocks are run (tests/readme_blocks.py)."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest
import typer

from cad.cli.app import _register_commands, app
from cad.cli.families import COMMAND_FAMILIES, NO_DESIGN_COMMANDS, markdown_table

README = Path(__file__).resolve().parents[1] / "README.md"


def _commands() -> dict:
    _register_commands()
    return typer.main.get_command(app).commands


def _options(cmd) -> set[str]:
    return {o for p in cmd.params for o in (*p.opts, *p.secondary_opts) if o.startswith("--")}


def readme_command_lines() -> list[str]:
    """Every `hapticad ...` line inside a fenced code block of the README."""
    lines, in_block = [], False
    for raw in README.read_text().splitlines():
        if raw.startswith("```"):
            in_block = not in_block
            continue
        s = raw.strip().removeprefix("$ ")
        if in_block and s.startswith("hapticad "):
            lines.append(s.split(" #")[0].rstrip(" \\"))
    return lines


def test_commands_table_matches_the_code():
    assert markdown_table() in README.read_text()


def test_every_command_is_in_the_family_table():
    assert set(_commands()) == set(COMMAND_FAMILIES) | set(NO_DESIGN_COMMANDS)


def test_commands_table_flags_exist():
    """Every `--flag` in the README's Commands table exists on that command."""
    cmds = _commands()
    rows = re.findall(r"^\| `hapticad (\w+)([^`]*)`", README.read_text(), flags=re.M)
    assert {r[0] for r in rows} == set(cmds), "every command has a row in the Commands table"
    for name, rest in rows:
        flags = set(re.findall(r"--[a-zA-Z][\w-]*", rest))
        assert flags <= _options(cmds[name]), (name, flags - _options(cmds[name]))


@pytest.mark.parametrize("line", readme_command_lines())
def test_readme_command_lines_parse(line):
    """Every command line in a README code block names a real command and real flags."""
    words = shlex.split(line)
    cmds = _commands()
    assert words[1] in cmds, line
    flags = {w.split("=")[0] for w in words[2:] if w.startswith("--")}
    assert flags <= _options(cmds[words[1]]) | {"--help"}, (line, flags - _options(cmds[words[1]]))
