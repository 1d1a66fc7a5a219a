"""The Python snippet that docs/families/pen.md gives for the haptic pen's capstan figures (the
same functions the datasheet calls, without a build) runs as printed and prints the figures the
page states."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_the_pen_capstan_snippet_runs_and_prints_the_pages_figures():
    page = (ROOT / "docs" / "families" / "pen.md").read_text()
    (code,) = [b for b in re.findall(r"```python\n(.*?)```", page, re.S) if "haptic_pen_capstan" in b]
    r = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    rows = dict(ln.split(None, 1) for ln in r.stdout.splitlines())
    assert rows["continuous_force_N"].startswith("3.023 N")  # the page's 3.02 N
    assert rows["cable_handle_stiffness_N_per_m"].startswith("1.677e+05 N/m")  # the page's 168 000 N/m
    assert [rows[f"drum_sector_deg_{i}"][:4] for i in (1, 2)] == ["88.5", "119."]  # 89 deg, 119 deg
    assert {f"cable_safety_factor_{i}" for i in range(1, 7)} <= rows.keys()
