"""Bad logs of a 2-motor device (the 5-bar pantograph, issue 37): every case refused in one
line naming the problem (API: FileDamaged field LOG; CLI: exit 2, no traceback), the
column count checked against the design's motors -- before any build is needed -- and the
bench's flags at the command line."""

from __future__ import annotations

import numpy as np
import pytest

from cad.errors import FileDamaged
from cad.identify import logfile
from cad.sim import bench, bench_fivebar
from cad.sim.identify_fivebar import identify
from tests.cli_helpers import assert_one_line_error, hapticad
from tests.unit.identify.conftest import ROOT

PANTO = ROOT / "designs" / "pantograph.toml"
H = "cd" * 32
HEAD = f"# hapticad identification log; design pantograph-fig2-200; design hash sha256:{H}"
COLS2 = "t_s,counts_0,counts_1,current_A_0,current_A_1"


def _rows(n=20, i1=0.1):
    return "".join(f"{k * 1e-3!r},{k},{-k},0.1,{i1}\n" for k in range(n))


BAD = {
    "one motor's columns": (f"{HEAD}\nt_s,counts_0,current_A_0\n0.0,0,0.1\n", "this 2-motor device logs"),
    "three motors' columns": (f"{HEAD}\nt_s,counts_0,counts_1,counts_2,current_A_0,current_A_1,current_A_2\n"
                              "0.0,0,0,0,0.1,0.1,0.1\n", "this 2-motor device logs"),
    "columns swapped": (f"{HEAD}\nt_s,counts_0,current_A_0,counts_1,current_A_1\n0.0,0,0.1,0,0.1\n",
                        "this 2-motor device logs"),
    "a row short": (f"{HEAD}\n{COLS2}\n{_rows(3)}0.004,1,2,0.1\n", "has 4 cells, the header 5"),
    "no hash": (f"# a log\n{COLS2}\n{_rows(3)}", "no design hash"),
    "not a number": (f"{HEAD}\n{COLS2}\n0.0,0,x,0.1,0.1\n", "is not a number"),
    "time backwards": (f"{HEAD}\n{COLS2}\n0.0,0,0,0.1,0.1\n0.002,1,1,0.1,0.1\n0.001,2,2,0.1,0.1\n",
                       "time is not increasing"),
    "fractional counts of motor 1": (f"{HEAD}\n{COLS2}\n0.0,0,0.5,0.1,0.1\n", "must be integers"),
    "motor 1 saturated": (f"{HEAD}\n{COLS2}\n{_rows(20, 2.63)}", "is saturated"),
    "empty": ("", "is empty"),
    "only the header": (f"{HEAD}\n{COLS2}\n", "has no rows"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_log_api(case):
    text, why = BAD[case]
    with pytest.raises(FileDamaged, match=why):
        logfile.parse_log(text, "bad.csv", 2, 2.63)


@pytest.mark.parametrize("case", ["one motor's columns", "a row short", "motor 1 saturated", "time backwards"])
def test_bad_log_cli_one_line_before_any_build(tmp_path, case):
    """The pantograph's motor data says 2.63 A continuous (RE 35): the log is refused before
    the build that the prediction needs (no --build-dir, nothing built: seconds)."""
    text, why = BAD[case]
    log = tmp_path / "bad.csv"
    log.write_text(text)
    code, _, err = hapticad("identify", PANTO, log)
    assert_one_line_error(code, err, "LOG", why)


def _log(pred, t, c, i):
    text = logfile.format_log(logfile.header_line("p", pred.design_hash, "t", pred.Te_s), t, c, i)
    return logfile.parse_log(text, "t.csv", 2, pred.i_max_A)


def test_a_motor_that_does_not_move_is_too_little_excitation(panto_pred):
    """Motor 1's encoder reads a constant (unplugged): refused in one line, naming the travel."""
    t, c, i, _ = bench_fivebar.simulate(panto_pred, bench.parse_perturb([]), 0)
    c = c.copy()
    c[:, 1] = c[0, 1]
    with pytest.raises(FileDamaged, match="too little excitation: a joint travelled 0 counts") as err:
        identify(panto_pred, _log(panto_pred, t, c, i), "t.csv")
    assert "cut short" not in str(err.value)  # the whole routine is in the log


def test_a_log_cut_short_says_so(panto_pred):
    """A log that stops 0.3 s after the current starts (a tester's log cut mid-routine): the
    refusal says it ends early and how long the routine runs from there (the plan's 2 T_settle
    + T_chirp), not only that it excites too little."""
    t, c, i, _ = bench_fivebar.simulate(panto_pred, bench.parse_perturb([]), 0)
    k0 = int(np.flatnonzero(np.any(i != 0.0, axis=1))[0])
    keep = k0 + int(round(0.3 / panto_pred.Te_s))
    p = panto_pred.plan
    with pytest.raises(FileDamaged, match="too little excitation") as err:
        identify(panto_pred, _log(panto_pred, t[:keep], c[:keep], i[:keep]), "t.csv")
    assert "cut short" in str(err.value)
    assert f"the routine runs {2 * p.T_settle_s + p.T_chirp_s:.2f} s" in str(err.value)


def test_bench_log_refuses_an_unknown_model(tmp_path):
    code, _, err = hapticad("bench-log", PANTO, "--out", tmp_path / "b.csv", "--model", "adams")
    assert_one_line_error(code, err, "--model", "mujoco")
    assert not (tmp_path / "b.csv").exists()


def test_bench_log_bad_perturb_one_line(tmp_path):
    code, _, err = hapticad("bench-log", PANTO, "--out", tmp_path / "b.csv", "--perturb", "kt=0.01")
    assert_one_line_error(code, err, "--perturb", "|kt| must be >= 0.1")


def test_log_rows_are_the_documented_columns(panto_pred):
    t, c, i, _ = bench_fivebar.simulate(panto_pred, bench.parse_perturb(["encoder=-1"]), 0)
    text = logfile.format_log(logfile.header_line("p", panto_pred.design_hash, "t", panto_pred.Te_s), t, c, i)
    lines = text.splitlines()
    assert lines[1] == COLS2
    assert all(len(ln.split(",")) == 5 for ln in lines[2:])
    assert np.array_equal(_log(panto_pred, t, c, i).counts, c)


@pytest.mark.slow
def test_the_day_on_the_bench_five_bar(tmp_path):
    """build --formats mjcf, bench-log (MuJoCo: the exported MJCF, the default), identify --out
    on the bundled 5-bar (one CAD build; covered cheaply without a build, on the reduced bench,
    by test_fivebar_recovery.py and the cases above)."""
    import json

    build = tmp_path / "build"
    code, _, err = hapticad("build", PANTO, "--formats", "mjcf", "--out", build)
    assert code == 0, err
    log = tmp_path / "log.csv"
    code, out, err = hapticad("bench-log", PANTO, "--out", log, "--build-dir", build, "--perturb", "mass=1.15",
                              "--perturb", "friction=2", "--perturb", "offset_mNm=3", "--json")
    assert code == 0, err
    truth = json.loads((tmp_path / "log.true.json").read_text())
    assert truth["perturb"]["mass"] == 1.15 and truth["status"] == "done" and truth["model"] == "mujoco"
    code, out, err = hapticad("identify", PANTO, log, "--build-dir", build, "--out", tmp_path / "id", "--json")
    assert code == 0, err
    res = json.loads(out)
    assert {p.name for p in (tmp_path / "id").iterdir()} == {"identify.json", "identify.md", "identify_fit.svg",
                                                           "identify_residual.svg", "manifest.json"}
    assert res["hash_matches"] and {"Mxx_g@home", "Myy_g@home", "Tc0_mNm", "Tc1_mNm"} <= set(res["misses"])
    rep = json.loads((build / "report.json").read_text())
    mxx = next(r for r in res["figures"] if r["key"] == "Mxx_g@home")
    # the prediction is the datasheet's effective mass at home (report.json)
    assert mxx["predicted"] == pytest.approx(rep["effective_mass_home"]["mass_x_g_diag"], rel=1e-9)
    assert mxx["value"] == pytest.approx(truth["Mxx_g_home"], rel=0.02)
    for j in range(2):  # the tolerances of test_fivebar_recovery.py, on the MuJoCo bench
        tc = next(r for r in res["figures"] if r["key"] == f"Tc{j}_mNm")
        off = next(r for r in res["figures"] if r["key"] == f"offset{j}_mNm")
        assert tc["value"] * 1e-3 == pytest.approx(truth["Tc_Nm"][j], rel=0.10)
        assert off["value"] * 1e-3 == pytest.approx(truth["offset_Nm"][j], abs=3e-4)
