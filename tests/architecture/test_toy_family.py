"""A new family is one package and one registry row (issue 32 §6).

The toy family (``tests/architecture/toy_family/``: a block sliding on a base plate) is added
at run time with one :class:`cad.data.families.Family` row and nothing else: it loads, builds
(parts, assembly STEP, BOM, report.md/json, datasheet, manifest), is checked against its
``[targets]`` and refuses what it does not provide in one line. Then no module outside
``cad/families/`` names a family: the generic layers dispatch through the family protocol
(:mod:`cad.families.protocol`) only.

The toy's moving mass is checked against a hand computation (block volume x the catalog
density of aluminium 6061), independent of the solids.
"""

from __future__ import annotations

import ast
import csv
import json
import re
from pathlib import Path

import pytest

from cad.data import families as registry
from cad.errors import DesignError

ROOT = Path(__file__).resolve().parents[2]
TOY = "toy-slider"
DESIGN = """name = "toy"
[mechanism]
family = "toy-slider"
block_mm = [20.0, 10.0, 8.0]
travel_mm = 30.0
[targets]
moving_mass_g = {max = 10.0}
"""


@pytest.fixture
def toy(monkeypatch, tmp_path):
    """The one registry row; the design file."""
    row = registry.Family(TOY, TOY, "tests.architecture.toy_family.design",
                          "tests.architecture.toy_family", ("build", "check", "datasheet"))
    monkeypatch.setitem(registry.FAMILIES, TOY, row)
    path = tmp_path / "toy.toml"
    path.write_text(DESIGN)
    return path


def _hand_mass_g() -> float:
    from cad.data.materials import get_material

    return 20.0 * 10.0 * 8.0 * 1e-9 * get_material("aluminium-6061").density_kg_m3 * 1e3


def test_a_toy_family_builds_checks_and_refuses_through_the_protocol_alone(toy, tmp_path):
    import cad

    d = cad.load_design(toy)
    rep = cad.build_design(d, tmp_path / "out", formats="step")
    out = tmp_path / "out"
    for f in ("bom.csv", "report.md", "report.json", "manifest.json", "assembly.step",
              "parts/toy_block.step", "order.csv"):
        assert (out / f).is_file(), f
    doc = json.loads((out / "report.json").read_text())
    assert doc["moving_mass_g"] == pytest.approx(_hand_mass_g(), rel=1e-6)
    ds = {r["key"]: r for r in doc["datasheet"]["rows"]}
    assert ds["moving_mass_g"]["value"] == pytest.approx(_hand_mass_g(), rel=1e-6)
    bom = {r["part"]: r for r in csv.DictReader((out / "bom.csv").read_text().splitlines())}
    assert set(bom) == {"toy_base", "toy_block"} and bom["toy_block"]["quantity"] == "1"
    md = (out / "report.md").read_text()
    assert md.startswith("# toy (toy-slider)") and "moving mass" in md
    assert rep["device"]["family"] == TOY and not rep["device"]["motors"]
    chk = cad.check(d)
    assert chk["ok"] is (_hand_mass_g() <= 10.0)
    assert chk["computed"]["moving_mass_g"] == pytest.approx(_hand_mass_g(), rel=1e-12)
    for fmt in ("firmware", "mjcf", "glb"):
        with pytest.raises(DesignError, match=f"--formats: {fmt} is not written for 'toy-slider'"):
            cad.build_design(d, tmp_path / fmt, formats=fmt)
    with pytest.raises(DesignError, match="mechanism.family: optimize works on"):
        cad.optimize(d)


#: The generic layers: they reach a family only through its FamilyPackage.
GENERIC = ("cad/api.py", "cad/pipeline", "cad/firmware", "cad/datasheet", "cad/device",
           "cad/design/__init__.py", "cad/export", "cad/report", "cad/io", "cad/assembly",
           "cad/isotropy")
FAMILY_WORDS = re.compile(r"\b(hoeken|roberts|chebyshev|chebyshev-v|pantograph|"
                          r"twin-pantograph|haptic-pen|powermouse|delta|fourbar)\b")


def _code_strings_and_names(path: Path) -> list[tuple[int, str]]:
    """(line, text), sorted, of every short string constant outside docstrings and every
    string a comparison tests against, of a module."""
    tree = ast.parse(path.read_text())
    docs = {id(n.body[0].value) for n in ast.walk(tree)
            if isinstance(n, (ast.Module, ast.FunctionDef, ast.ClassDef, ast.AsyncFunctionDef))
            and n.body and isinstance(n.body[0], ast.Expr)
            and isinstance(n.body[0].value, ast.Constant)}
    out = set()
    for n in ast.walk(tree):
        if isinstance(n, ast.Compare):
            for c in [n.left, *n.comparators]:
                if isinstance(c, ast.Constant) and isinstance(c.value, str):
                    out.add((n.lineno, c.value))
                elif isinstance(c, (ast.Tuple, ast.List, ast.Set)):
                    out |= {(n.lineno, e.value) for e in c.elts
                            if isinstance(e, ast.Constant) and isinstance(e.value, str)}
        elif isinstance(n, ast.Constant) and isinstance(n.value, str) and id(n) not in docs:
            if len(n.value) < 40:  # names, not messages or C text
                out.add((n.lineno, n.value))
    return sorted(out)


def test_no_generic_module_names_a_family():
    """No comparison or short string constant in the generic layers names a family (a
    branch on the family); message text and docstrings may."""
    found = []
    for g in GENERIC:
        p = ROOT / g
        for f in sorted(p.rglob("*.py")) if p.is_dir() else [p]:
            for line, text in _code_strings_and_names(f):
                if FAMILY_WORDS.fullmatch(text.strip()):
                    found.append(f"{f.relative_to(ROOT)}:{line}: {text!r}")
    assert not found, "family branches outside cad/families/:\n" + "\n".join(found)


def test_the_scan_finds_a_family_branch(tmp_path):
    """The scan above is not blind: a planted ``if design.family == "pantograph"`` is found."""
    f = tmp_path / "m.py"
    f.write_text('def f(design):\n    """pantograph"""\n    if design.family == "pantograph":\n'
                 '        return 1\n    return design.kind in ("fourbar", "x")\n')
    hits = [t for _, t in _code_strings_and_names(f) if FAMILY_WORDS.fullmatch(t)]
    assert hits == ["pantograph", "fourbar"]
