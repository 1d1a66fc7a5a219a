"""Every command ends cleanly at any moment (issue 22 §4), with real processes and real signals.

Reproducers of ``shared/cases/reliability/``: ``signal-after-publish-dies-by-signal`` (SIGTERM /
SIGINT 50-150 ms after the build's folder is published: exit 0, never a death by the signal)
and ``ctrl-c-in-optuna-prints-traceback`` (SIGINT inside an optuna trial of ``optimize`` and
``fit``: ``hapticad: aborted`` last, exit 130, no traceback, no optuna log, nothing written).
The signal inside a trial is sent by the process to itself from a patched evaluation (the
n-th call), so it lands inside the trials every run instead of at a guessed moment.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from cad.export.manifest import verify_manifest

ROOT = Path(__file__).resolve().parents[2]
pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="POSIX signals")


def _env(tmp_path: Path) -> dict:
    return {**os.environ, "PYTHONPATH": str(ROOT), "HAPTICAD_CACHE_DIR": str(tmp_path / "cache")}


def _entry_cmd() -> list[str]:
    return [sys.executable, "-c", "from cad.cli.entry import main; main()"]


@pytest.mark.slow  # an end-to-end search or build run (20-40 s): CI's slow set keeps the default suite under 10 min
def test_a_signal_after_the_publish_ends_the_build_with_exit_0(tmp_path):
    env = _env(tmp_path)
    args = ["build", str(ROOT / "designs" / "hoeken.toml"), "--fidelity", "preview",
            "--formats", "step", "--out", str(tmp_path / "o")]
    warm = subprocess.run([*_entry_cmd(), *args], env=env, capture_output=True, timeout=600, check=False)
    assert warm.returncode == 0, warm.stderr
    for sig, delay_s in ((signal.SIGTERM, 0.05), (signal.SIGINT, 0.15)):  # the trial's window
        for p in sorted((tmp_path / "o").rglob("*"), reverse=True):
            p.rmdir() if p.is_dir() else p.unlink()
        (tmp_path / "o").rmdir()
        proc = subprocess.Popen([*_entry_cmd(), *args], env=env, stdout=subprocess.DEVNULL,
                                stderr=subprocess.PIPE, text=True, start_new_session=True)
        t0 = time.monotonic()
        while proc.poll() is None and not (tmp_path / "o" / "manifest.json").exists():
            assert time.monotonic() - t0 < 600
            time.sleep(0.005)
        time.sleep(delay_s)
        if proc.poll() is None:
            proc.send_signal(sig)
        _, err = proc.communicate(timeout=120)
        assert proc.returncode == 0, (sig, delay_s, proc.returncode, err[-2000:])  # published
        assert "Traceback" not in err and verify_manifest(tmp_path / "o") is not None


def test_a_finished_command_is_not_killed_by_a_late_signal():
    """:func:`cad.io.signals.finish`: after it, SIGTERM is held and dropped at exit."""
    code = ("import os, signal, sys\nfrom cad.io import signals\nsignals.install()\n"
            "signals.finish()\nos.kill(os.getpid(), signal.SIGTERM)\nprint('finished')\nsys.exit(0)\n")
    r = subprocess.run([sys.executable, "-c", code], env={**os.environ, "PYTHONPATH": str(ROOT)},
                       capture_output=True, text=True, timeout=60, check=False)
    assert (r.returncode, r.stdout.strip()) == (0, "finished"), r.stderr


PATCHED = r"""
import os, signal, sys
from cad.cli import entry  # installs the handlers, as the console script does
import {module} as target
real, calls = target.{name}, [0]
def patched(*a, **k):
    calls[0] += 1
    if calls[0] == {at}:
        os.kill(os.getpid(), signal.SIGINT)  # Ctrl-C inside a trial
    return real(*a, **k)
target.{name} = patched
sys.argv = ["hapticad", *{argv!r}]
entry.main()
"""


def _interrupted(tmp_path: Path, module: str, name: str, at: int, argv: list[str]):
    code = PATCHED.format(module=module, name=name, at=at, argv=argv)
    r = subprocess.run([sys.executable, "-c", code], env=_env(tmp_path), cwd=tmp_path,
                       capture_output=True, text=True, timeout=600, check=False)
    return r


@pytest.mark.parametrize("command", ["optimize", "fit"])
def test_ctrl_c_in_optuna_trials_is_aborted_without_a_traceback(tmp_path, command):
    out = tmp_path / "f.toml"
    if command == "optimize":
        argv = ["optimize", str(ROOT / "designs" / "hoeken_light_brief.toml"), "--objective",
                "min-apparent-mass", "--trials", "40", "--exact-top", "1", "--out", str(out)]
        r = _interrupted(tmp_path, "cad.studies.codesign.search", "evaluate", 5, argv)
    else:
        argv = ["fit", str(ROOT / "designs" / "hoeken.toml"), "--target", "M11_max_g<=60",
                "--free", "parts.bar_thickness_mm=5:8", "--out", str(out)]
        r = _interrupted(tmp_path, "cad.design", "parse_design", 3, argv)
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert r.returncode == 130, r.stderr[-3000:]
    assert lines[-1] == "hapticad: aborted", r.stderr[-3000:]
    assert "Traceback" not in r.stderr and "Trial" not in r.stderr, r.stderr[-3000:]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cache"]  # nothing written


def test_optimize_study_stops_at_an_interrupt_and_logs_nothing(capfd):
    """The helper both commands use, in-process without handlers (the Python API): an
    interrupt in trial 2 stops the study there (3 trials: 2 complete, 1 pruned), optuna logs
    nothing at the WARNING level both commands set, and ``KeyboardInterrupt`` reaches the
    caller."""
    import optuna

    from cad.studies.codesign.search import optimize_study

    was = optuna.logging.get_verbosity()
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    study = optuna.create_study(sampler=optuna.samplers.RandomSampler(seed=0))

    def objective(trial):
        x = trial.suggest_float("x", 0.0, 1.0)
        if trial.number == 2:
            raise KeyboardInterrupt
        return x

    try:
        with pytest.raises(KeyboardInterrupt):
            optimize_study(study, objective, 50)
    finally:
        optuna.logging.set_verbosity(was)
    states = [t.state.name for t in study.trials]
    assert states == ["COMPLETE", "COMPLETE", "PRUNED"]
    err = capfd.readouterr().err
    assert err == "", err  # optuna logged the interrupted trial with its traceback before


@pytest.mark.parametrize(("module", "name", "argv"), [
    ("cad.bench.run", "goal_rows", ["bench", "--quick", "--only", "kinematics", "--out", "o"]),
    ("cad.export.manifest", "write_manifest",
     ["tolerance", str(ROOT / "designs" / "hoeken.toml"), "--hole-mm", "0.05", "--samples", "200", "--out", "o"]),
], ids=["bench", "tolerance"])
def test_an_interrupt_while_the_output_is_written_leaves_the_folder_as_it_was(tmp_path, module, name, argv):
    """The kind of ctrl-c-in-optuna-prints-traceback ("nothing half-written") for the commands
    that add files to an ``--out`` folder: Ctrl-C during ``bench`` (here after its topic wrote
    its charts) left the charts without their manifest, so every rerun refused the folder as
    foreign; ``tolerance`` had the same window. Now the folder is published whole at the end
    (:func:`cad.io.atomic.atomic_dir_update`): exit 130, ``aborted`` last, the folder byte for
    byte as it was, no temporary folder left; the rerun keeps the folder's other files."""
    from cad.export.manifest import write_manifest

    out = tmp_path / "o"
    out.mkdir()
    (out / "older.txt").write_text("an earlier command's file")
    write_manifest(out)
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    r = _interrupted(tmp_path, module, name, 1, argv)
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert r.returncode == 130 and lines[-1] == "hapticad: aborted", r.stderr[-3000:]
    assert "Traceback" not in r.stderr
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []  # no temporary folder
    if argv[0] == "tolerance":  # the rerun (cheap): the earlier file kept, every file listed
        r = subprocess.run([*_entry_cmd(), *argv], env=_env(tmp_path), cwd=tmp_path,
                           capture_output=True, text=True, timeout=600, check=False)
        assert r.returncode == 0, r.stderr
        listed = {row["path"] for row in verify_manifest(out)["files"]}
        assert listed == {"older.txt", "tolerance.json", "tolerance.png"}
