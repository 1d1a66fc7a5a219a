"""An output folder holding a FIFO is refused at once, never read (found by trying, t1tester).

``hapticad sweep --out sw`` with ``sw/results.parquet`` (or ``sw/manifest.json``) replaced
by a named pipe hung for ever: the owned-folder check (``cad.io.outdir``) opened every
entry to hash it, and opening a FIFO for reading waits for a writer. The same check
guards ``build --out``, so a FIFO of any name in any output folder hung every command.
Each check here runs in a thread; a check still blocked after a while is released by
opening the FIFO for writing (so the test itself cannot hang) and fails the test.
"""

from __future__ import annotations

import os
import threading
from pathlib import Path

import pytest

from cad.errors import DesignError

#: long enough for a check of three small files on a loaded machine; a blocked open never ends
BLOCKED_AFTER_S = 20.0

pytestmark = pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes are POSIX")


def _sweep_folder(out: Path) -> None:
    """A folder as the sweep writes it: its files and a manifest naming them."""
    from cad.studies.sweep.table import publish

    publish(out, {"results.parquet": lambda p: p.write_bytes(b"PAR1 not really"),
                  "results.csv": lambda p: p.write_text("variant\n0\n")})


def _outcome(check, fifo: Path) -> BaseException | None:
    """What ``check()`` raised (None if nothing); fails the test if it blocked on ``fifo``."""
    box: list = []

    def run():
        try:
            check()
            box.append(None)
        except BaseException as exc:  # noqa: BLE001 - handed to the test
            box.append(exc)

    t = threading.Thread(target=run, daemon=True)
    t.start()
    t.join(BLOCKED_AFTER_S)
    if t.is_alive():
        fd = os.open(fifo, os.O_WRONLY | os.O_NONBLOCK)  # a reader waits: this releases it
        os.close(fd)
        t.join(BLOCKED_AFTER_S)
        pytest.fail(f"the check blocked reading the FIFO {fifo.name}")
    return box[0]


@pytest.mark.parametrize("name", ["results.parquet", "manifest.json", "other.bin"])
def test_sweep_folder_with_a_fifo_refused_naming_it(tmp_path, name):
    """sweep's --out check (cad.studies.sweep.table.check_folder): one DesignError naming the entry."""
    from cad.studies.sweep.table import check_folder

    out = tmp_path / "sw"
    _sweep_folder(out)
    fifo = out / name
    if fifo.exists():
        fifo.unlink()
    os.mkfifo(fifo)
    exc = _outcome(lambda: check_folder(out, str(tmp_path / "d.toml")), fifo)
    assert isinstance(exc, DesignError) and exc.field == "--out"
    assert name in str(exc) and "not a regular file" in str(exc)


def test_build_folder_with_a_fifo_refused(tmp_path):
    """The owned-folder rule of every command (cad.io.outdir.check_out_dir)."""
    from cad.io.outdir import check_out_dir

    out = tmp_path / "b"
    _sweep_folder(out)
    os.mkfifo(out / "parts.fifo")
    exc = _outcome(lambda: check_out_dir(out), out / "parts.fifo")
    assert isinstance(exc, DesignError) and "parts.fifo" in str(exc)


def test_a_manifest_naming_files_outside_its_folder_or_not_regular_is_not_verified(tmp_path):
    """cad.export.manifest.verify_manifest (is a built folder complete and unchanged?): a
    listed path that is absolute (``/dev/zero`` was read for ever: 0 bytes listed, 0 bytes
    found), leaves the folder (``../``) or is not a regular file is not the folder's: None
    (a rebuild), even when its sha256 and size match; never opened when not regular."""
    import hashlib
    import json

    from cad.export.manifest import verify_manifest

    outside = tmp_path / "outside.txt"
    outside.write_text("x")
    sha = hashlib.sha256(b"x").hexdigest()
    out = tmp_path / "b"
    out.mkdir()
    os.mkfifo(out / "pipe")
    for listed in (str(outside), "../outside.txt", "pipe"):
        row = {"path": listed, "sha256": sha if listed != "pipe" else "0" * 64,
               "bytes": 1 if listed != "pipe" else 0}
        (out / "manifest.json").write_text(json.dumps({"files": [row]}))
        assert _outcome(lambda: verify_manifest(out), out / "pipe") is None  # nothing raised
        assert verify_manifest(out) is None, listed
