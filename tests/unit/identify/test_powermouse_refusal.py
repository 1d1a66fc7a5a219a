"""``identify`` and ``bench-log`` refuse the PowerMouse in one line saying why (issue 37): its
generated firmware senses no position (the family gives no kinematic model, only the
current-to-wrench map), so there are no encoder counts to log."""

from __future__ import annotations

from pathlib import Path

import pytest

from cad.families import family_package
from cli_helpers import assert_one_line_error, hapticad

DESIGN = Path(__file__).resolve().parents[3] / "designs" / "powermouse.toml"


@pytest.mark.parametrize("args", [("bench-log", str(DESIGN), "--out", "NEW"), ("identify", str(DESIGN), "LOG")])
def test_powermouse_is_refused_with_its_reason(tmp_path, args):
    log = tmp_path / "log.csv"
    log.write_text("t_s,counts_0,current_A_0\n0.0,0,0.0\n")
    paths = {"LOG": str(log), "NEW": str(tmp_path / "new.csv")}
    code, _, err = hapticad(*(paths.get(a, a) for a in args))
    assert_one_line_error(code, err, "mechanism.family", "reads no position", "no encoder")
    assert family_package("powermouse").firmware_model is None  # what the reason says


def test_other_refusals_keep_the_generic_line(tmp_path):
    code, _, err = hapticad("wall", str(DESIGN.with_name("delta.toml")))  # every family with firmware is identified
    assert_one_line_error(code, err, "mechanism.family")
    assert "reads no position" not in err
