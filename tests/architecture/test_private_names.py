"""No private name is imported across modules (issue 32 §6).

A name that starts with one underscore is private to the module that defines it; a module
that needs it from another imports a public name (the module then owns it as API). Read from
the source with :mod:`ast`: every ``from cad... import _name`` (absolute or relative) in
``cad/`` fails this test, naming the importing file, the module and the name.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _private_imports(path: Path, root: Path = ROOT) -> list[str]:
    out = []
    for node in ast.walk(ast.parse(path.read_text())):
        if not isinstance(node, ast.ImportFrom):
            continue
        if not (node.level or (node.module or "").split(".")[0] == "cad"):
            continue
        for alias in node.names:
            if alias.name.startswith("_") and not alias.name.startswith("__"):
                mod = "." * node.level + (node.module or "")
                out.append(f"{path.relative_to(root)}: from {mod} import {alias.name}")
    return out


def test_no_private_name_is_imported_across_modules():
    found = [line for p in sorted((ROOT / "cad").rglob("*.py")) for line in _private_imports(p)]
    assert not found, "make these public in their module (or move the code):\n" + "\n".join(found)


def test_the_rule_sees_a_private_import(tmp_path):
    """The check itself: a relative and an absolute private import are both found."""
    f = tmp_path / "probe.py"
    f.write_text("from cad.io.figures import _x\nfrom .design import _y\nfrom cad import ok\n")
    got = _private_imports(f, tmp_path)
    assert [g.split(" import ")[1] for g in got] == ["_x", "_y"]
