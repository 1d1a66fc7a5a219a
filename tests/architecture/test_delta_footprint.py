"""The measure of the family protocol: the lines the delta took outside ``cad/families/delta/``.

Counted from the source as it is (docs/architecture.md states the total and this test reads it
back): every module named ``delta.py`` outside the package, whole (its math layers:
``cad/kinematics/delta.py``, ``cad/dynamics/delta.py``); every module-level definition of
another module whose name starts with ``delta`` / ``Delta`` / ``DELTA`` (``delta_gii``,
``DeltaProblem``, ``DELTA_TARGET_KEYS``, the ``DELTA_*`` tolerances), from its first to its
last line; and the family's registry row (the ``Family("delta", ...)`` call). A name with a
leading underscore or another word first (``_delta_of_the_encoder``: eq 25's encoder step
Delta of the four-bar) is not the family's.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = "cad/families/delta"
NAME = re.compile(r"^(delta|Delta|DELTA)")


def _names(node: ast.stmt) -> list[str]:
    if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
        return [node.name]
    if isinstance(node, ast.Assign):
        return [t.id for t in node.targets if isinstance(t, ast.Name)]
    if isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
        return [node.target.id]
    return []


def _span(node: ast.AST) -> int:
    first = min([node.lineno, *(d.lineno for d in getattr(node, "decorator_list", []))])
    return node.end_lineno - first + 1


def _registry_rows(tree: ast.Module) -> int:
    """Lines of every ``Family("delta", ...)`` call of a module."""
    return sum(_span(n) for n in ast.walk(tree)
               if isinstance(n, ast.Call) and getattr(n.func, "id", None) == "Family"
               and n.args and isinstance(n.args[0], ast.Constant) and n.args[0].value == "delta")


def module_footprint(path: Path) -> int:
    """The delta's lines in one module (module docstring)."""
    text = path.read_text()
    if path.name == "delta.py":
        return len(text.splitlines())
    tree = ast.parse(text)
    defs = sum(_span(n) for n in tree.body if any(NAME.match(x) for x in _names(n)))
    return defs + _registry_rows(tree)


def delta_footprint(root: Path = ROOT) -> dict[str, int]:
    """``{module path: lines}`` of every module outside the package with delta lines."""
    out = {}
    for f in sorted((root / "cad").rglob("*.py")):
        rel = f.relative_to(root).as_posix()
        if not rel.startswith(PACKAGE + "/") and (n := module_footprint(f)):
            out[rel] = n
    return out


def test_the_architecture_page_states_the_delta_footprint():
    """docs/architecture.md's count is the one the source gives, and so is each module's."""
    counts = delta_footprint()
    text = (ROOT / "docs" / "architecture.md").read_text()
    m = re.search(r"took (\d+) lines outside `cad/families/delta/`", text)
    assert m, "docs/architecture.md states no count of the delta's lines outside its package"
    assert int(m.group(1)) == sum(counts.values()), counts
    for rel, n in counts.items():
        assert f"| `{rel}` | {n} |" in text, (rel, n)


def test_the_count_is_not_blind(tmp_path):
    """A planted module: a delta definition, a registry row and a four-bar's ``_delta`` name."""
    f = tmp_path / "m.py"
    f.write_text('X = 1\n\n\ndef delta_f(a):\n    """doc"""\n    return a\n\n\n'
                 'DELTA_K = (1,\n           2)\n\n\ndef _delta_of_the_encoder():\n    return 0\n\n\n'
                 'ROWS = [Family("delta", "x",\n                "y")]\n')
    assert module_footprint(f) == 3 + 2 + 2
    g = tmp_path / "delta.py"
    g.write_text("a = 1\nb = 2\n")
    assert module_footprint(g) == 2
