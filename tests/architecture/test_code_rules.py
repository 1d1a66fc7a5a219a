"""Code rules of STYLE.md and issue 23 §2, checked on the source of ``cad/`` with ``ast``.

(a) No function longer than :data:`MAX_FUNCTION_LINES` lines unless the line above its ``def``
    (or above its first decorator) is a comment ``# long-function: <reason>``.
(b) No module-level constant with a tolerance-like name (:data:`TOLERANCE_NAME`) and a
    numeric value outside ``cad/tolerances.py`` ("Tolerances live in one documented place").
(c) Every constant in ``cad/tolerances.py`` carries its reason: a comment directly above it
    (or above the run of assignments it belongs to), a comment on its line, or a docstring
    line right after it.

Each test names every offender (file:line and name), so a failure says what to move or split.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

CAD = Path(__file__).resolve().parents[2] / "cad"
TOLERANCES = CAD / "tolerances.py"

#: Issue 23 §2: "No function over 80 lines without a reason written beside it".
MAX_FUNCTION_LINES = 80
#: A tolerance-like constant name: one of its underscore-separated words is TOL(S),
#: TOLERANCE(S), EPS, ATOL, RTOL, XTOL, FTOL, MARGIN(S), SLACK, THRESH(OLD) or RESIDUAL.
#: (Word-wise, so CODE_DEPS or EPSILON_... spelled inside another word do not match.)
TOLERANCE_NAME = re.compile(
    r"(?:^|_)(?:TOLS?|TOLERANCES?|EPS|ATOL|RTOL|XTOL|FTOL|MARGINS?|SLACK|THRESH(?:OLD)?|RESIDUAL)(?:_|$)"
)
LONG_FUNCTION = re.compile(r"^\s*#\s*long-function:\s*\S")


def _sources() -> list[Path]:
    return sorted(p for p in CAD.rglob("*.py") if "__pycache__" not in p.parts)


def _rel(p: Path) -> str:
    return p.relative_to(CAD.parent).as_posix() if p.is_relative_to(CAD.parent) else p.name


def _functions(tree: ast.AST):
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            yield node


def long_functions(path: Path) -> list[str]:
    """``file:line name (N lines)`` of every function over the limit without its reason."""
    text = path.read_text(encoding="utf-8")
    lines = text.splitlines()
    out = []
    for fn in _functions(ast.parse(text)):
        n = fn.end_lineno - fn.lineno + 1
        if n <= MAX_FUNCTION_LINES:
            continue
        first = min([fn.lineno, *(d.lineno for d in fn.decorator_list)])
        above = lines[first - 2] if first >= 2 else ""
        if not LONG_FUNCTION.match(above):
            out.append(f"{_rel(path)}:{fn.lineno} {fn.name} ({n} lines)")
    return out


def _numeric(node: ast.AST) -> bool:
    """A constant expression of numbers: literals, +/-, arithmetic, tuples/lists of them,
    and calls such as ``math.radians(15.0)`` on them (not strings, not objects)."""
    if isinstance(node, ast.Constant):
        return isinstance(node.value, (int, float)) and not isinstance(node.value, bool)
    if isinstance(node, ast.UnaryOp):
        return _numeric(node.operand)
    if isinstance(node, ast.BinOp):
        return _numeric(node.left) and _numeric(node.right)
    if isinstance(node, (ast.Tuple, ast.List)):
        return bool(node.elts) and all(_numeric(e) for e in node.elts)
    if isinstance(node, ast.Call):
        return bool(node.args) and not node.keywords and all(_numeric(a) for a in node.args)
    return False


def _module_constants(tree: ast.Module):
    """(name, node) of each module-level assignment (plain or annotated) to one name."""
    for node in tree.body:
        if isinstance(node, ast.Assign):
            for t in node.targets:
                if isinstance(t, ast.Name):
                    yield t.id, node
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name) and node.value:
            yield node.target.id, node


def tolerance_constants(path: Path) -> list[str]:
    """``file:line NAME`` of each module-level numeric constant with a tolerance-like name."""
    out = []
    for name, node in _module_constants(ast.parse(path.read_text(encoding="utf-8"))):
        bare = name.lstrip("_")
        if bare.isupper() and TOLERANCE_NAME.search(bare) and _numeric(node.value):
            out.append(f"{_rel(path)}:{node.lineno} {name}")
    return out


def undocumented_constants(path: Path) -> list[str]:
    """``NAME (line N)`` of each module-level constant of ``path`` with no reason beside it."""
    text = path.read_text(encoding="utf-8")
    lines = text.splitlines()
    tree = ast.parse(text)
    body = tree.body
    ends = {n.end_lineno: n for n in body if isinstance(n, (ast.Assign, ast.AnnAssign))}
    out = []
    for i, node in enumerate(body):
        if not isinstance(node, (ast.Assign, ast.AnnAssign)):
            continue
        name = next((nm for nm, nd in _module_constants(tree) if nd is node), None)
        if name is None:
            continue
        if "#" in lines[node.lineno - 1].split("=", 1)[-1]:  # a comment on its own line
            continue
        nxt = body[i + 1] if i + 1 < len(body) else None
        if (isinstance(nxt, ast.Expr) and isinstance(nxt.value, ast.Constant)
                and isinstance(nxt.value.value, str) and nxt.lineno == node.end_lineno + 1):
            continue  # attribute docstring
        first = node.lineno
        while first - 1 in ends:  # one comment may document a run of assignments
            first = ends[first - 1].lineno
        above = lines[first - 2].strip() if first >= 2 else ""
        reason = above.lstrip("#:").strip()
        if not (above.startswith("#") and reason and not reason.startswith("---")):
            out.append(f"{name} (line {node.lineno})")
    return out


@pytest.mark.parametrize("path", _sources(), ids=_rel)
def test_no_function_over_80_lines_without_a_reason(path):
    found = long_functions(path)
    assert not found, "split these into named steps (or write '# long-function: <reason>' above):\n" + "\n".join(found)


@pytest.mark.parametrize("path", [p for p in _sources() if p != TOLERANCES], ids=_rel)
def test_tolerance_like_constants_live_in_cad_tolerances(path):
    found = tolerance_constants(path)
    assert not found, "move these to cad/tolerances.py with their reason:\n" + "\n".join(found)


def test_every_constant_in_cad_tolerances_has_its_reason():
    found = undocumented_constants(TOLERANCES)
    assert not found, "give these their reason in a comment above:\n" + "\n".join(found)
    assert tolerance_constants(TOLERANCES), "the tolerance checks above found no constant at all"


# ---------------------------------------------------------------- the checkers themselves


def _write(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "m.py"
    p.write_text(text, encoding="utf-8")
    return p


def _body(n: int) -> str:
    return "".join(f"    x{i} = {i}\n" for i in range(n - 1))


def test_long_function_checker_counts_lines_and_reads_the_reason(tmp_path):
    p = _write(tmp_path, "def ok():\n" + _body(80) + "\n\ndef bad():\n" + _body(81)
               + "\n\n# long-function: one table of cases, read top to bottom\n@staticmethod\n"
               + "def excused():\n" + _body(81))
    assert [s.split(" ", 1)[1] for s in long_functions(p)] == ["bad (81 lines)"]


def test_tolerance_name_checker_matches_words_and_numbers_only(tmp_path):
    p = _write(tmp_path, "A_TOL_MM = 1e-9\nCODE_DEPS = (1, 2)\nK_RTOL = 0.01\nSTL_TOL_MM = Bound('mm', 1)\n"
               "GENERAL_TOLERANCE = 'ISO 2768-m'\nANG_TOL_RAD = math.radians(15.0)\n_LB_SLACK_MM = -1e-9\n"
               "MESH_TOLERANCES_MM = (0.1, 0.01)\nLEG_INSET_MM = 8.0\nEPSILON = 1e-9\n")
    found = [s.split(" ", 1)[1] for s in tolerance_constants(p)]
    assert found == ["A_TOL_MM", "K_RTOL", "ANG_TOL_RAD", "_LB_SLACK_MM", "MESH_TOLERANCES_MM"]


def test_reason_checker_accepts_comments_above_runs_and_docstrings(tmp_path):
    p = _write(tmp_path, '"""Module."""\n\n#: Why A and B.\nA = 1\nB = 2\n\nC = 3  # why C\nD = 4\n"""Why D."""\n'
               "\nE = 5\n#:\nF = 6\n# ---------------- a section\nG = 7\n")
    assert undocumented_constants(p) == ["E (line 11)", "F (line 13)", "G (line 15)"]
