"""STEP bytes do not depend on what the cache held, or on what the process wrote before (issue 22 §6).

Reproducer ``shared/cases/reliability/step-bytes-depend-on-cache-history``: the pantograph's
``assembly.step`` differed after the cache held another build -- OCCT numbers
``NEXT_ASSEMBLY_USAGE_OCCURRENCE`` ids with a process-wide counter, and renumbering the text
afterwards kept the line wrapping of the wider original id. Reference: the bytes of the first
(cold) build, and of the first export of a fresh process.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]

CHILD = r"""
import hashlib, json
from build123d import Box
from cad.export.step import assembly_step_bytes, step_bytes
box = Box(10, 20, 30).wrapped
# names of 20..60 characters: some put the NAUO line right at OCCT's 72-column wrap
names = ["p" * n for n in range(20, 61)]
items = [(f"proximal_left.pin_short{i}", box, (1.0, 0.0, 0.0)) for i in range(12)]
def snapshot():
    return {"parts": [hashlib.sha256(step_bytes(box, n, None)).hexdigest() for n in names],
            "assembly": hashlib.sha256(assembly_step_bytes(items, "asm")).hexdigest()}
first = snapshot()  # the counter starts low in a fresh process: ids of one digit
for _ in range(120):
    assembly_step_bytes(items[:1], "burn")  # counter past 100: three-digit ids
print(json.dumps({"first": first, "later": snapshot()}))
"""


def test_step_bytes_do_not_depend_on_earlier_exports_of_the_process():
    r = subprocess.run([sys.executable, "-c", CHILD], capture_output=True, text=True, timeout=600,
                       env={**os.environ, "PYTHONPATH": str(ROOT)}, check=False)
    assert r.returncode == 0, r.stderr
    got = json.loads(r.stdout)
    assert got["later"] == got["first"]


def _steps(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*.step"))}


def _drop_assembly_entries(cache: Path) -> int:
    """Remove the derived-cache entries holding an assembly STEP (more than one NAUO): the
    partial cache of the reproducer -- every part STEP a hit, the assembly written afresh."""
    n = 0
    for p in sorted((cache / "derived-v2").rglob("*.bin")):
        data = p.read_bytes()
        if data.startswith(b"ISO-10303-21") and data.count(b"NEXT_ASSEMBLY_USAGE_OCCURRENCE") > 1:
            p.unlink()
            p.with_name(p.name + ".sha256").unlink()
            n += 1
    return n


def test_pantograph_step_files_are_the_same_bytes_cold_warm_and_with_a_partial_cache(tmp_path):
    cache = tmp_path / "cache"
    env = {**os.environ, "PYTHONPATH": str(ROOT), "HAPTICAD_CACHE_DIR": str(cache)}
    runs = {}
    for run in ("cold", "warm", "partial"):
        if run == "partial":
            assert _drop_assembly_entries(cache) >= 1
        r = subprocess.run([sys.executable, "-m", "cad", "build", str(ROOT / "designs" / "pantograph.toml"),
                            "--fidelity", "preview", "--formats", "step", "--out", str(tmp_path / run)],
                           capture_output=True, text=True, env=env, timeout=600, check=False)
        assert r.returncode == 0, r.stderr
        runs[run] = _steps(tmp_path / run)
    assert "assembly.step" in runs["cold"] and len(runs["cold"]) > 10
    for run in ("warm", "partial"):
        assert runs[run].keys() == runs["cold"].keys()
        assert [k for k in runs["cold"] if runs[run][k] != runs["cold"][k]] == [], run
