"""The identification log (issue 37): the documented CSV columns, a round trip, and every bad
log refused in one line naming the problem (API: FileDamaged field LOG; CLI: exit 2)."""

from __future__ import annotations

import numpy as np
import pytest

from cad.errors import FileDamaged
from cad.identify import logfile
from tests.cli_helpers import assert_one_line_error, hapticad

H = "ab" * 32
HEAD = f"# hapticad identification log; design hoeken; design hash sha256:{H}"


def test_columns_are_the_documented_contract():
    # docs/identify.md: t_s, counts_0[, counts_1 ...], current_A_0[, current_A_1 ...]
    assert logfile.columns(1) == ["t_s", "counts_0", "current_A_0"]
    assert logfile.columns(2) == ["t_s", "counts_0", "counts_1", "current_A_0", "current_A_1"]


def test_docs_page_states_the_columns():
    from tests.unit.identify.conftest import ROOT

    text = (ROOT / "docs" / "identify.md").read_text()
    assert "t_s,counts_0,current_A_0" in text and "sha256:" in text


def test_round_trip_is_exact():
    rng = np.random.default_rng(0)
    t = np.arange(50) * 3.3e-4
    c = rng.integers(-5000, 5000, (50, 2))
    i = rng.normal(0, 1, (50, 2))
    text = logfile.format_log(HEAD, t, c, i)
    assert text.splitlines()[1] == "t_s,counts_0,counts_1,current_A_0,current_A_1"
    log = logfile.parse_log(text, "x.csv", 2, 10.0)
    assert log.design_hash == H
    np.testing.assert_array_equal(log.t_s, t)
    np.testing.assert_array_equal(log.counts, c)
    np.testing.assert_array_equal(log.current_A, i)


GOOD = [HEAD, "t_s,counts_0,current_A_0"] + [f"{k * 0.001!r},{k},0.1" for k in range(200)]


def _bad(edit):
    lines = list(GOOD)
    edit(lines)
    return "\n".join(lines) + "\n"


CASES = {
    "empty": ("", "is empty"),
    "no hash": (_bad(lambda ln: ln.__setitem__(0, "# a log")), "no design hash"),
    "wrong columns": (_bad(lambda ln: ln.__setitem__(1, "t,counts,current")), "has the columns"),
    "two motors' columns": (_bad(lambda ln: ln.__setitem__(1, "t_s,counts_0,counts_1,current_A_0,current_A_1")),
                            "has the columns"),
    "header only": ("\n".join(GOOD[:2]) + "\n", "has no rows"),
    "short row": (_bad(lambda ln: ln.__setitem__(5, "0.003,3")), "line 6 has 2 cells"),
    "non-numeric cell": (_bad(lambda ln: ln.__setitem__(7, "0.005,abc,0.1")), "'abc' is not a number"),
    "not finite": (_bad(lambda ln: ln.__setitem__(7, "0.005,5,nan")), "is not finite"),
    "time backwards": (_bad(lambda ln: ln.__setitem__(9, "0.001,7,0.1")), "time is not increasing"),
    "time repeated": (_bad(lambda ln: ln.__setitem__(9, repr(6 * 0.001) + ",7,0.1")), "time is not increasing"),
    "fractional counts": (_bad(lambda ln: ln.__setitem__(9, "0.007,7.5,0.1")), "must be integers"),
    "saturated": (_bad(lambda ln: [ln.__setitem__(k, f"{(k - 2) * 0.001!r},{k},2.63") for k in range(2, 40)]),
                  "is saturated"),
}


@pytest.mark.parametrize("case", CASES)
def test_bad_log_is_refused_naming_the_problem(case):
    text, needle = CASES[case]
    with pytest.raises(FileDamaged) as e:
        logfile.parse_log(text, "bad.csv", 1, 2.63)
    assert e.value.field == "LOG" and needle in str(e.value) and "\n" not in str(e.value)


@pytest.mark.parametrize("case", ["empty", "wrong columns", "non-numeric cell", "time backwards", "saturated"])
def test_cli_bad_log_one_line_exit_2(tmp_path, case):
    from tests.unit.identify.conftest import ROOT

    text, needle = CASES[case]
    log = tmp_path / "bad.csv"
    log.write_text(text)
    code, _, err = hapticad("identify", ROOT / "designs" / "hoeken.toml", log)
    assert_one_line_error(code, err, "LOG", needle)


def test_cli_log_that_is_a_folder_or_missing(tmp_path):
    from tests.unit.identify.conftest import ROOT

    for p in (tmp_path, tmp_path / "none.csv"):
        code, _, err = hapticad("identify", ROOT / "designs" / "hoeken.toml", p)
        assert_one_line_error(code, err, "LOG")
