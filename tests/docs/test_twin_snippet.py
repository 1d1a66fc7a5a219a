"""The Python snippet that docs/families/pantograph-powermouse.md gives for the twin
pantograph's capstan figures (its solids are not built, so the CLI's datasheet refuses it)
runs as printed and prints the figures the page states."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_the_twin_capstan_snippet_runs_and_prints_the_pages_force():
    page = (ROOT / "docs" / "families" / "pantograph-powermouse.md").read_text()
    (code,) = [b for b in re.findall(r"```python\n(.*?)```", page, re.S) if "twin_pantograph_capstan" in b]
    r = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    rows = dict(ln.split(None, 1) for ln in r.stdout.splitlines())
    assert rows["continuous_force_N"].startswith("4.089 N")  # the page's 4.09 N
    assert {f"cable_safety_factor_{i}" for i in range(1, 5)} <= rows.keys()
