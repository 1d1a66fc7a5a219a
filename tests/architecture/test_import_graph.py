"""The import graph has no back-edge (issue 23 §2, SPEC "Pipeline (one direction, no back-edges)").

* Nothing outside ``cad/cli/`` imports ``cad.cli`` but the entry point ``cad/__main__.py``
  (the API is a layer under the CLI, never the reverse).
* The math and data layers (``cad.kinematics``, ``cad.dynamics``, ``cad.actuators``,
  ``cad.isotropy``, the pure modules of ``cad.massprops``, ``cad.data``, ``cad.design``,
  ``cad.device``: the resolved device and its read-back of the written files, ``cad.identify``:
  the identification log, excitation and regression)
  never reach a CAD-layer package, counting every import of every module they reach,
  function-level (lazy) imports included: read from the source with :mod:`ast`.
* Importing every module of those layers in a fresh interpreter loads no CAD library
  (build123d, OCP, cadquery), read from ``sys.modules``.
* Only ``cad/occ/``, ``cad/parts/``, ``cad/massprops/occt.py`` and ``cad/export/`` (its
  ``drawings/`` included) import a CAD library (OCP, build123d, cadquery, bd_warehouse,
  ocp_vscode), at module level or inside a function (issue 23's layout: ``occ/`` is "the only
  non-part package that imports OCP/build123d besides parts/, massprops/occt, export/"),
  and a family's own solids, ``cad/families/<name>/parts.py`` (issue 32 §6: a family is one
  package; the PowerMouse's geometry and solids live in ``cad/families/powermouse/parts.py``).
"""

from __future__ import annotations

import ast
import json
import subprocess
import sys
from functools import cache
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PKG = ROOT / "cad"
CAD_LIBRARIES = ("build123d", "OCP", "cadquery")
MATH_PACKAGES = ("kinematics", "dynamics", "actuators", "isotropy", "data", "design", "device",
                 "identify")
#: The modules of cad.massprops that import no CAD library (occt.py is its one OCP module).
MASSPROPS_PURE = ("cad.massprops.props", "cad.massprops.mesh", "cad.massprops.shells",
                  "cad.massprops.io")
#: Packages of the CAD layers (and the layers above them) the math layers must never import.
CAD_LAYERS = ("parts", "assembly", "pipeline", "families", "export", "report", "cli", "occ",
              "drawings")
#: Libraries only :data:`CAD_IMPORTERS` may import (issue 23).
CAD_IMPORT_LIBRARIES = ("OCP", "build123d", "cadquery", "bd_warehouse", "ocp_vscode")
#: The modules allowed to import them: module-name prefixes (a package and what is below it)
#: and single modules.
CAD_IMPORTERS = ("cad.occ", "cad.parts", "cad.export", "cad.massprops.occt")
#: Known edges into a CAD-layer package, each with its reason (none today: the isotropy
#: studies write their charts with cad.io.figures, the writer cad.report.figures re-exports).
KNOWN: set[tuple[str, str]] = set()


def _name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {_name(p): p for p in PKG.rglob("*.py")}


@cache
def imports_of(module: str) -> frozenset[str]:
    """Every ``cad.*`` module ``module`` imports anywhere in its source (absolute names)."""
    path = MODULES[module]
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    out: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(up + ([base] if base else []))
            subs = {f"{base}.{a.name}" for a in node.names if f"{base}.{a.name}" in MODULES}
            out |= subs
            if len(subs) < len(node.names):  # a name defined in the module itself
                out.add(base)
    # the root package: every cad module imports it as a parent; its lazy ``__getattr__``
    # (the API names of ``import cad``) is the public face, not a dependency of the layers
    return frozenset(_resolve(n) for n in out if n.startswith("cad."))


def _resolve(name: str) -> str:
    """The module of ``name`` (``cad.x.y.func`` -> ``cad.x.y``)."""
    while name not in MODULES and "." in name:
        name = name.rpartition(".")[0]
    return name


def _layer(module: str) -> str:
    return module.split(".")[1] if module.count(".") else ""


def _math_modules() -> list[str]:
    return sorted(m for m in MODULES if _layer(m) in MATH_PACKAGES) + list(MASSPROPS_PURE)


def test_the_module_table_is_complete():
    """The scan sees the package: every layer named above exists, and a module known to
    import another lazily (inside a function) is seen doing so."""
    layers = {_layer(m) for m in MODULES}
    assert set(MATH_PACKAGES) <= layers and {"parts", "pipeline", "cli", "families"} <= layers
    assert set(MASSPROPS_PURE) <= set(MODULES)
    # cad.design.parse_design imports cad.design.bounds inside the function
    assert "cad.design.bounds" in imports_of("cad.design")


def test_nothing_but_the_entry_point_imports_the_cli():
    """``cad.api`` and every other module outside ``cad/cli/`` are below the CLI."""
    offenders = sorted(
        (m, i) for m in MODULES if _layer(m) != "cli" and m != "cad.__main__"
        for i in imports_of(m) if _layer(i) == "cli"
    )
    assert offenders == []
    assert any(_layer(i) == "cli" for i in imports_of("cad.__main__"))


def test_math_layers_never_reach_a_cad_layer():
    """Transitively: from every math/data/design module, following every cad import (lazy
    ones too), no CAD-layer package is reached except by the :data:`KNOWN` edges."""
    bad = []
    for start in _math_modules():
        seen, stack = {start}, [(start, (start,))]
        while stack:
            mod, path = stack.pop()
            for dep in imports_of(mod):
                if dep in seen:
                    continue
                seen.add(dep)
                if _layer(dep) in CAD_LAYERS:
                    if (mod, dep) not in KNOWN:
                        bad.append(" -> ".join((*path, dep)))
                    continue
                stack.append((dep, (*path, dep)))
    assert bad == []
    for src, dst in KNOWN:  # the exceptions are real (drop one when it is fixed) ...
        assert dst in imports_of(src), (src, dst)
        # ... and lead nowhere further up
        assert {_layer(d) for d in imports_of(dst)} <= {"errors", "io", ""}, imports_of(dst)


def test_importing_the_math_layers_loads_no_cad_library():
    """Every module of the math/data/design layers imported in one fresh interpreter."""
    mods = _math_modules()
    code = (
        "import importlib, json, sys\n"
        f"for m in {mods!r}: importlib.import_module(m)\n"
        f"print(json.dumps(sorted({{k.split('.')[0] for k in sys.modules}} & {set(CAD_LIBRARIES)!r})))"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT,
                       timeout=300)
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout.strip().splitlines()[-1]) == []
    assert len(mods) > 40  # the whole layer, not an empty list


def cad_library_imports(module: str) -> set[str]:
    """Top-level names of the CAD libraries (:data:`CAD_IMPORT_LIBRARIES`) ``module`` imports
    anywhere in its source: ``import``/``from`` statements at any depth (inside functions
    too) and ``importlib.import_module("...")``/``__import__("...")`` with a literal name."""
    out: set[str] = set()
    for node in ast.walk(ast.parse(MODULES[module].read_text())):
        names: list[str] = []
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
            names = [node.module]
        elif (isinstance(node, ast.Call) and node.args
              and isinstance(node.args[0], ast.Constant) and isinstance(node.args[0].value, str)
              and ((isinstance(node.func, ast.Attribute) and node.func.attr == "import_module")
                   or (isinstance(node.func, ast.Name) and node.func.id == "__import__"))):
            names = [node.args[0].value]
        out |= {n.split(".")[0] for n in names} & set(CAD_IMPORT_LIBRARIES)
    return out


def _may_import_cad(module: str) -> bool:
    """In :data:`CAD_IMPORTERS`, or a family's own solids: ``cad.families.<name>.parts``
    (issue 32 §6: a family is one package, its geometry and solids included)."""
    fam = module.split(".")
    if len(fam) == 4 and fam[:2] == ["cad", "families"] and fam[3] == "parts":
        return True
    return any(module == p or module.startswith(p + ".") for p in CAD_IMPORTERS)


def test_the_cad_library_scan_sees_lazy_imports():
    """The scan finds function-level imports: cad.occ.bbox imports OCP inside ``tight_box``,
    cad.parts.lazy_import names build123d to ``importlib.import_module``; a plain module that
    only mentions the names in text (cad.data.catalog reads bd_warehouse's CSV tables) has
    none."""
    assert cad_library_imports("cad.occ.bbox") == {"OCP"}
    assert "build123d" in cad_library_imports("cad.parts.lazy_import")
    assert cad_library_imports("cad.data.catalog") == set()
    assert all(_may_import_cad(m) for m in ("cad.occ", "cad.export.drawings.features",
                                            "cad.massprops.occt", "cad.parts.pen",
                                            "cad.families.powermouse.parts"))
    assert not any(_may_import_cad(m) for m in ("cad.occupancy", "cad.massprops.mesh",
                                                "cad.exporter", "cad.assembly.interference",
                                                "cad.families.powermouse.build",
                                                "cad.families.parts"))


def test_only_the_cad_layers_import_cad_libraries():
    """Every module under ``cad/`` outside :data:`CAD_IMPORTERS` imports none of OCP,
    build123d, cadquery, bd_warehouse, ocp_vscode (it calls ``cad.occ``, a part script or a
    writer of ``cad.export`` instead)."""
    offenders = sorted(
        f"{m}: {', '.join(sorted(libs))}"
        for m in MODULES if not _may_import_cad(m) and (libs := cad_library_imports(m))
    )
    assert offenders == []
    assert sum(1 for m in MODULES if cad_library_imports(m)) > 20  # the importers are seen
