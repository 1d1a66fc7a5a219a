"""Faults found by a third reliability trial (t3tester, after issue 22's fixes), each a test.

Each test runs the real console entry point in a subprocess with a timeout, so a regression
hangs there (a ``subprocess.TimeoutExpired`` failure), never in the suite.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from cli_helpers import assert_one_line_error
from unit.io.test_file_guard import _device_folder

ROOT = Path(__file__).resolve().parents[2]
DESIGNS = ROOT / "designs"
pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="FIFOs, /dev/zero")


def _cli(args: list, cwd: Path, timeout: float = 60) -> subprocess.CompletedProcess:
    """The console entry point (signals installed, as a user runs it) in a subprocess."""
    return subprocess.run([sys.executable, "-m", "cad.cli.entry", *map(str, args)],
                          capture_output=True, text=True, timeout=timeout, cwd=cwd,
                          env={**os.environ, "PYTHONPATH": str(ROOT)})


MJCF_WITH_MESH = """<mujoco>
  <compiler angle="radian" meshdir="parts"/>
  <asset><mesh name="coupler" file="coupler.stl" scale="0.001 0.001 0.001"/></asset>
  <worldbody><body name="b"><geom type="mesh" mesh="coupler"/></body></worldbody>
</mujoco>
"""


@pytest.mark.parametrize("hostile", ["fifo", "folder", "dangling"])
def test_wall_build_dir_mesh_that_is_not_a_regular_file_is_refused(tmp_path, hostile):
    """``wall --build-dir DIR --model mujoco`` where a mesh the MJCF names (``parts/*.stl``,
    which mujoco opens itself) is a FIFO: mujoco's open() blocked forever in a thread and
    SIGTERM did not end the process (measured: still blocked 11 min after ``timeout 120``).
    Every file the MJCF names is checked like the MJCF itself: one line naming the mesh."""
    folder = _device_folder(tmp_path)
    (folder / "hoeken.xml").write_text(MJCF_WITH_MESH)
    (folder / "parts").mkdir()
    mesh = folder / "parts" / "coupler.stl"
    if hostile == "fifo":
        os.mkfifo(mesh)
    elif hostile == "folder":
        mesh.mkdir()
    else:
        mesh.symlink_to(tmp_path / "missing.stl")
    r = _cli(["wall", DESIGNS / "hoeken.toml", "--build-dir", folder, "--model", "mujoco"], tmp_path)
    assert_one_line_error(r.returncode, r.stderr, "MJCF:", str(mesh))


SELF_INTERRUPT = r"""
import os, signal, sys
from cad.cli import entry  # installs the handlers, as the console script does
import {module} as target
real = target.{name}
def patched(*a, **k):
    os.kill(os.getpid(), signal.{sig})  # the signal lands inside the work
    return real(*a, **k)
target.{name} = patched
sys.argv = ["hapticad", *{argv!r}]
entry.main()
"""


@pytest.mark.parametrize(("sig", "code"), [("SIGINT", 130), ("SIGTERM", 143)])
def test_tolerance_interrupted_after_a_warning_ends_with_the_aborted_line(tmp_path, sig, code):
    """The signal fuzz of ``tolerance`` (seed 22: 2 of 2 runs hit mid-study): the warning
    recorded before the study (the design's inertia targets not computed) was printed AFTER
    ``hapticad: aborted``, so ``aborted`` was not the last line. Warnings come first."""
    argv = ["tolerance", str(DESIGNS / "hoeken.toml"), "--hole-mm", "0.05", "--samples", "100"]
    prog = SELF_INTERRUPT.format(module="cad.studies.tolerance_study", name="run", sig=sig, argv=argv)
    r = subprocess.run([sys.executable, "-c", prog], capture_output=True, text=True, timeout=120,
                       cwd=tmp_path, env={**os.environ, "PYTHONPATH": str(ROOT),
                                          "HAPTICAD_CACHE_DIR": str(tmp_path / "cache")})
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert r.returncode == code, r.stderr
    assert "hapticad: warning: [targets]" in r.stderr  # the warning is still said ...
    assert lines[-1] == "hapticad: aborted", r.stderr  # ... before the last line
    assert "Traceback" not in r.stderr


EARLY_INTERRUPT = r"""
import sys
class Interrupt:  # Ctrl-C while entry.py imports cad.io.signals (Python's handler still on)
    def find_spec(self, name, path=None, target=None):
        if name == "cad.io.signals":
            raise KeyboardInterrupt
sys.meta_path.insert(0, Interrupt())
sys.argv = ["hapticad", "analyze", {design!r}]
from cad.cli.entry import main
main()
"""


def test_ctrl_c_before_the_handlers_are_installed_is_the_abort(tmp_path):
    """The signal fuzz of ``swap`` (seed 22, run 33: SIGINT 0.107 s after the start, on the
    loaded machine): the interrupt landed while entry.py imported ``cad.io.signals`` (Python's
    default handler still active): a KeyboardInterrupt traceback and death by SIGINT (-2)."""
    prog = EARLY_INTERRUPT.format(design=str(DESIGNS / "hoeken.toml"))
    r = subprocess.run([sys.executable, "-c", prog], capture_output=True, text=True, timeout=60,
                       cwd=tmp_path, env={**os.environ, "PYTHONPATH": str(ROOT)})
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert (r.returncode, lines) == (130, ["hapticad: aborted"]), r.stderr


@pytest.mark.parametrize("value", ["abc", "true"])
def test_sweep_varied_number_that_is_not_a_number_is_refused_at_load(tmp_path, value):
    """``sweep --vary parts.bar_thickness_mm=abc``: ``-5`` is refused at load (its bound),
    but a word ran a Dask cluster and wrote a table of one ``error`` row, exit 0. A key
    with a numeric bound takes numbers only: refused at load, nothing written."""
    out = tmp_path / "sw"
    r = _cli(["sweep", DESIGNS / "hoeken.toml", "--vary", f"parts.bar_thickness_mm={value}",
              "--workers", "1", "--out", out], tmp_path, timeout=300)
    assert_one_line_error(r.returncode, r.stderr, "--vary parts.bar_thickness_mm: must be a number")
    assert not out.exists()


@pytest.mark.parametrize(("command", "folder"), [
    (["swap", DESIGNS / "hoeken.toml", "--to", "roberts"], False),
    (["tolerance", DESIGNS / "hoeken.toml", "--hole-mm", "0.05", "--samples", "100"], True),
    (["build", DESIGNS / "hoeken.toml", "--fidelity", "preview", "--formats", "step"], True),
], ids=["swap", "tolerance", "build"])
@pytest.mark.parametrize("shape", ["path-too-long", "name-too-long"])
def test_out_path_too_long_names_the_flag(tmp_path, command, folder, shape):
    """``--out`` longer than the system allows (6000 characters, or one 300-character name):
    the line was the bare ``hapticad: error: [Errno 36] File name too long: '...'`` naming no
    flag. Now ``--out:`` first, at load."""
    name = "d/" * 3000 + "x" if shape == "path-too-long" else "n" * 300
    out = tmp_path / (name if folder else name + ".toml")
    r = _cli([*command, "--out", out], tmp_path)
    assert_one_line_error(r.returncode, r.stderr, "--out:", "too long")


#: A sparse file far larger than anything hapticad writes: hashing it reads 200 GiB of zeros
#: (measured: 54 GB read in the first 120 s, so ~8 min; a sparse 1 TiB file costs nothing to
#: make and ~40 min to hash).
HUGE_SPARSE_BYTES = 200 << 30

VERIFY = r"""
import json, os, sys
from pathlib import Path
out = Path(sys.argv[1])
(out / "parts").mkdir(parents=True)
with open(out / "parts" / "x.step", "wb") as f:
    f.truncate({n})
(out / "manifest.json").write_text(json.dumps({{"files": [
    {{"path": "parts/x.step", "sha256": "0" * 64, "bytes": {n}}}]}}))
{call}
print("returned")
"""


@pytest.mark.parametrize("reader", ["build-verify", "sweep-roll-forward"])
def test_a_manifest_listing_a_huge_file_is_refused_without_reading_it(tmp_path, reader):
    if reader == "build-verify":
        call = "from cad.export.manifest import verify_manifest\nverify_manifest(out)"
    else:
        call = ("import hashlib\nfrom cad.studies.sweep import table\nos.rename(out / 'parts' / 'x.step', "
                "out / 'results.csv')\n(out / 'manifest.json').write_text(json.dumps({'files': "
                "[{'path': 'results.csv', 'sha256': '0' * 64, 'bytes': %d}], 'pending': "
                "{'results.csv': '1' * 64}}))\ntable.roll_forward(out)").replace("%d", str(HUGE_SPARSE_BYTES))
    prog = VERIFY.format(n=HUGE_SPARSE_BYTES, call=call)
    r = subprocess.run([sys.executable, "-c", prog, str(tmp_path / "o")], capture_output=True,
                       text=True, timeout=20, env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert r.stdout.strip() == "returned", r.stderr
