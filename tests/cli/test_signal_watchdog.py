"""Issue 33 item 1: Ctrl-C acts within about a second at any moment, even while the main
thread is inside one long C call that holds the interpreter (an OCCT boolean or offset; here
``sum(range(10**12))``, a single C call that never checks for signals and runs for hours).

The process is started like the ``hapticad`` entry point (``install`` then
``start_watchdog``); the reference is the same program without the watchdog, still running
when the test gives up on it. No timing is asserted beyond "ended before the 60 s cap".
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PROGRAM = """
import sys
from cad.io import signals
signals.install()
if sys.argv[1] == "watchdog":
    signals.start_watchdog()
print("ready", flush=True)
sum(range(10**12))
"""


def _run(tmp_path: Path, mode: str, cap_s: float):
    (tmp_path / "p.py").write_text(PROGRAM)
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    env.pop("HAPTICAD_FORK", None)
    p = subprocess.Popen([sys.executable, str(tmp_path / "p.py"), mode], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, env=env)
    try:
        assert p.stdout.readline() == b"ready\n"
        time.sleep(1.0)  # the next statement is the C call: let it start
        p.send_signal(signal.SIGINT)
        try:
            _, err = p.communicate(timeout=cap_s)
            return p.returncode, err.decode()
        except subprocess.TimeoutExpired:
            return None, ""
    finally:
        if p.poll() is None:
            p.kill()
            p.communicate()


@pytest.mark.skipif(not hasattr(os, "fork"), reason="the watchdog is forked")
def test_ctrl_c_inside_a_long_c_call_aborts(tmp_path):
    code, err = _run(tmp_path, "watchdog", 60)
    assert code == -signal.SIGKILL and err.splitlines()[-1] == "hapticad: aborted"


def test_without_the_watchdog_the_same_call_ignores_ctrl_c(tmp_path):
    code, _ = _run(tmp_path, "plain", 5)
    assert code is None  # still running: the watchdog is what ends it
