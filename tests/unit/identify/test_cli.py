"""``hapticad identify`` and ``hapticad bench-log`` at the command line: the refusal of the
families they do not cover (the 5-bar pantograph's own: tests/unit/identify/test_fivebar_logs.py), bad flags in one line, and (slow: one simulator build) the whole
day on the bench -- bench-log, identify --out, the files and the verdicts."""

from __future__ import annotations

import json

import pytest

from tests.cli_helpers import assert_one_line_error, hapticad
from tests.unit.identify.conftest import ROOT

HOEKEN = ROOT / "designs" / "hoeken.toml"


@pytest.mark.parametrize("design", ["powermouse.toml"])
def test_other_families_are_refused_in_one_line(tmp_path, design):
    path = ROOT / "designs" / design
    log = tmp_path / "log.csv"
    log.write_text("# x sha256:" + "0" * 64 + "\nt_s,counts_0,current_A_0\n0,0,0\n")
    for argv in (("identify", path, log), ("bench-log", path, "--out", tmp_path / "b.csv")):
        code, _, err = hapticad(*argv)
        assert_one_line_error(code, err, "mechanism.family", "four-bar")


@pytest.mark.parametrize("bad,why", [("mass", "KEY=VALUE"), ("mass=abc", "not a number"),
                                     ("encoder=2", "must be in")])
def test_bench_log_bad_perturb_one_line(tmp_path, bad, why):
    code, _, err = hapticad("bench-log", HOEKEN, "--out", tmp_path / "b.csv", "--perturb", bad)
    assert_one_line_error(code, err, "--perturb", why)
    assert not (tmp_path / "b.csv").exists()


def test_bench_log_never_replaces_a_file_it_did_not_write(tmp_path):
    mine = tmp_path / "notes.csv"
    mine.write_text("my notes\n")
    code, _, err = hapticad("bench-log", HOEKEN, "--out", mine)
    assert_one_line_error(code, err, "--out", "not a log hapticad wrote")
    assert mine.read_text() == "my notes\n"


@pytest.mark.slow
def test_the_day_on_the_bench(hoeken_sim_build, tmp_path):
    """bench-log then identify --out on the Hoeken's simulator build (covered cheaply without a
    build by test_recovery.py)."""
    _, build, _, _ = hoeken_sim_build
    log = tmp_path / "log.csv"
    code, out, err = hapticad("bench-log", HOEKEN, "--out", log, "--build-dir", build, "--perturb", "mass=1.15",
                              "--perturb", "friction=2", "--perturb", "offset_mNm=3", "--json")
    assert code == 0, err
    truth = json.loads((tmp_path / "log.true.json").read_text())
    assert truth["perturb"]["mass"] == 1.15 and truth["status"] == "done"
    code, out, err = hapticad("identify", HOEKEN, log, "--build-dir", build, "--out", tmp_path / "id", "--json")
    assert code == 0, err
    res = json.loads(out)
    assert {p.name for p in (tmp_path / "id").iterdir()} == {"identify.json", "identify.md", "identify_fit.svg",
                                                           "identify_residual.svg", "manifest.json"}
    assert res["hash_matches"] and "Fs_N" in res["misses"] and "offset_mNm" not in res["misses"]
    fs = next(r for r in res["figures"] if r["key"] == "Fs_N")
    assert fs["value"] == pytest.approx(truth["Fs_N"], rel=0.10)
    assert all(r["verdict"] == "MISS" for r in res["figures"] if r["key"].startswith("M11_g@"))
    page = (tmp_path / "id" / "identify.md").read_text()
    assert "identify_fit.svg" in page
    # each figure's row starts with its key as identify.json names it (a tester found the page
    # gave only the description), then its description
    rows = [ln for ln in page.splitlines() if ln.startswith("| `")]
    assert [ln.split("`")[1] for ln in rows] == [r["key"] for r in res["figures"]]
    assert all(r["what"] in ln for r, ln in zip(res["figures"], rows, strict=True) if r.get("what"))


@pytest.mark.slow
def test_the_day_on_the_bench_through_a_capstan(tmp_path):
    """The capstan Hoeken (n = 2) on the MuJoCo bench: the MJCF's motor has gear n, the bench
    commands the crank's torque / n (cad.sim.mj.joint_torque_drive); links 15 % heavier and
    twice the friction are identified back against the bench's own truth (log.true.json: M11
    of the perturbed model, Fs at the handle), 3 % and 10 % as in test_recovery.py. With the
    crank's torque sent as ctrl MuJoCo applied n x it and the fit read M11 / n."""
    import numpy as np

    design = ROOT / "designs" / "hoeken_capstan.toml"
    build = tmp_path / "build"
    code, _, err = hapticad("build", design, "--formats", "mjcf", "--fidelity", "preview", "--out", build)
    assert code == 0, err
    log = tmp_path / "log.csv"
    code, _, err = hapticad("bench-log", design, "--out", log, "--build-dir", build, "--perturb", "mass=1.15",
                            "--perturb", "friction=2", "--json")
    assert code == 0, err
    truth = json.loads((tmp_path / "log.true.json").read_text())
    assert truth["model"] == "mujoco" and truth["status"] == "done"
    code, out, err = hapticad("identify", design, log, "--build-dir", build, "--json")
    assert code == 0, err
    figs = json.loads(out)["figures"]
    at = sorted((float(k), v) for k, v in truth["M11_g_at"].items())
    for f in (f for f in figs if f["key"].startswith("M11_g@")):
        phi = float(f["key"].split("@")[1].removesuffix("deg"))
        ref = np.interp(phi, [a for a, _ in at], [v for _, v in at])
        assert f["value"] == pytest.approx(ref, rel=0.03), f["key"]
    fs = next(f for f in figs if f["key"] == "Fs_N")
    assert fs["value"] == pytest.approx(truth["Fs_N"], rel=0.10)
