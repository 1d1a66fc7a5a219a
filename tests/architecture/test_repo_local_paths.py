"""Tests run anywhere (issue 34 item 5): no test or module reads a file by an absolute path
outside the repository. Rule: the source of ``tests/`` and ``cad/`` names no path under the
machine's work folders (``/work/``, ``/home/``); test data lives under ``tests/``."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
_OUTSIDE = re.compile(r"""["'](/work/|/home/)""")


def test_no_absolute_path_outside_the_repository():
    bad = []
    for sub in ("tests", "cad"):
        for f in sorted((ROOT / sub).rglob("*.py")):
            for n, line in enumerate(f.read_text(encoding="utf-8").splitlines(), 1):
                if _OUTSIDE.search(line):
                    bad.append(f"{f.relative_to(ROOT)}:{n}: {line.strip()}")
    assert not bad, "absolute paths outside the repository:\n" + "\n".join(bad)
