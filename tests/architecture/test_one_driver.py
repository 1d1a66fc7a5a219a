"""One build driver (issue 23 "one pipeline"): a family adds layout code, never its own copy of
a check or an export. The pen, pantograph, PowerMouse and four-bar builders are one call to
:func:`cad.pipeline.run.run_family` (the four-bar's extra stages are the driver's optional
hooks: its plots after the dynamics, a sweep given the build, the encoder row); none of their
modules calls the shared stages the driver owns (read from the source with :mod:`ast`,
function-level calls included).
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FAMILIES = ROOT / "cad" / "families"
#: Families built through the driver (every family).
DRIVEN = ("pen", "pantograph", "powermouse", "fourbar")
#: What the driver does for every family (cad/pipeline/run.py, cad/pipeline/family.py).
DRIVER_OWNS = {"fastener_report", "kind_props", "bom_rows", "write_viewer_outputs",
               "lowest_z_mm", "report_md_lines", "write_report_md", "write_bom", "write_assembly_md", "part_materials",
               "fits_report", "placement_report", "start", "cancel_on_error"}
#: Known calls, each with its reason: the PowerMouse's single-actuator test rig (Fig. 7) is a
#: second assembly, not part of the device; its BOM rows are made from its own kinds. The
#: four-bar's inertia model (``hapticad check`` / ``fit``) is mass properties without a build.
KNOWN = {("cad/families/powermouse/build.py", "bom_rows"),
         ("cad/families/powermouse/build.py", "kind_props"),
         ("cad/families/fourbar/inertia.py", "kind_props")}


def _calls(path: Path) -> set[str]:
    """Names of every function called in ``path`` (``f(...)`` and ``x.f(...)``)."""
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Call):
            f = node.func
            out.add(f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", ""))
    return out


def _build_body(path: Path) -> list[ast.stmt]:
    tree = ast.parse(path.read_text())
    (fn,) = [n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == "build"]
    return [s for s in fn.body if not (isinstance(s, ast.Expr) and isinstance(s.value, ast.Constant))]


def test_driven_families_call_none_of_the_drivers_stages():
    """No module of a driven family calls a stage the driver owns (a copy of a check, an
    export, the report tail or the forking)."""
    bad = sorted(
        (p.relative_to(ROOT).as_posix(), name)
        for fam in DRIVEN for p in (FAMILIES / fam).glob("*.py")
        for name in _calls(p) & DRIVER_OWNS
    )
    assert [b for b in bad if b not in KNOWN] == []
    assert set(bad) == KNOWN  # the exceptions are real (drop one when it goes)


def test_each_driven_build_is_one_call_to_run_family():
    """``build()`` is one ``return run_family(...)`` (``run_family`` imported at module level
    or, where an import cycle asks for it, in the function)."""
    for fam in DRIVEN:
        body = _build_body(FAMILIES / fam / "build.py")
        assert [type(s) for s in body] in ([ast.ImportFrom, ast.Return], [ast.Return]), fam
        call = body[-1].value
        assert isinstance(call, ast.Call) and getattr(call.func, "id", "") == "run_family", fam


def test_the_check_sees_a_copied_stage(tmp_path):
    """The scan finds a family-level call of a driver stage, as a method or a bare name."""
    p = tmp_path / "m.py"
    p.write_text("def f(family, x):\n    family.write_outputs(x)\n    lowest_z_mm(x)\n")
    assert {"write_outputs", "lowest_z_mm"} <= _calls(p)
    assert _calls(p) & DRIVER_OWNS == {"lowest_z_mm"}
