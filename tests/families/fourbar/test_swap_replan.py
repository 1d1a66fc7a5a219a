"""Every bundled four-bar design swapped to every other family either gives a design the
build accepts or is refused by ``swap`` itself (exit 2, one line, nothing written).

Reference for "the build accepts": the file ``swap`` wrote, read back from disk and
loaded, passes the build's pre-CAD layout check (:func:`cad.families.fourbar.build.check_layout`,
the same gate ``build`` runs first: no clear layer order -> exit 2 before any CAD); one
product whose copied ``parts.layer_order`` had to be dropped is built at ``preview``
fidelity and its ``assembly.step`` read back with an every-pair check
(``tests/step_pairs.clashes``). Reference for a refusal: the plain swap (no re-planning,
:func:`cad.cli.cmd_swap.swap_raw`) fed to ``check_layout`` raises the same line.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_helpers import assert_one_line_error, hapticad

ROOT = Path(__file__).resolve().parents[3]
SOURCES = ("hoeken", "roberts", "chebyshev", "chebyshev_v", "custom_example", "hoeken_light",
           "hoeken_light_brief", "hoeken_paper")
FAMILIES = ("hoeken", "roberts", "chebyshev", "chebyshev-v")
#: Swaps that must be refused: the chebyshev-v crank at these strokes (l1 = 13.0 / 13.5 mm)
#: puts the A2 washer and nut in the crank hub in every layer order (hub radius 10 + washer
#: radius 6 > l1), stated by the tester's build of the unchecked swap.
REFUSED = {("chebyshev", "chebyshev-v"), ("custom_example", "chebyshev-v")}


def _cases():
    from cad.design import load_design

    out = []
    for s in SOURCES:
        fam = load_design(ROOT / "designs" / f"{s}.toml").family
        out += [(s, f) for f in FAMILIES if f != fam]
    return out


@pytest.mark.parametrize(("src", "family"), _cases())
def test_swap_product_passes_the_build_gate_or_swap_refuses(src, family, tmp_path):
    from cad.cli.cmd_swap import swap_raw
    from cad.design import load_design, parse_design
    from cad.errors import DesignError
    from cad.families.fourbar.build import check_layout

    out = tmp_path / "new.toml"
    code, _, err = hapticad("swap", ROOT / "designs" / f"{src}.toml", "--to", family,
                            "--out", out, "--json")
    d0 = load_design(ROOT / "designs" / f"{src}.toml")
    plain = parse_design(swap_raw(d0, family, out), str(out))
    if (src, family) in REFUSED:
        assert_one_line_error(code, err, "mechanism.stroke_mm", "A2", "clears it")
        assert not out.exists()
        with pytest.raises(DesignError) as e:
            check_layout(plain, plain.parts.fidelity, False)
        assert f"hapticad: error: {e.value}" == err.strip()  # no slip hint on swap's stroke
        return
    assert code == 0, err
    assert "did you give" not in err  # no unit-slip hint about values swap computed
    new = load_design(out)
    assert new.family == family
    check_layout(new, new.parts.fidelity, False)  # what build runs first: passes
    copied = d0.parts.layer_order
    if copied and new.parts.layer_order != copied:  # dropped: the copy was not clear
        assert "parts.layer_order" in err and "dropped" in err
        with pytest.raises(DesignError, match="parts.layer_order"):
            check_layout(plain, plain.parts.fidelity, False)


def test_dropped_layer_order_product_builds_with_no_overlap(tmp_path):
    """hoeken_light (layer_order crank, coupler, rocker) to roberts: the copied order clashes
    for the roberts bars (the build used to refuse the written file); swap drops it, and the
    written file builds at preview fidelity -- the exact sweep included: the A4 screw head
    under the coupler is kept ``clearance_min_mm`` below it, where it used to touch -- with no
    two solids sharing volume, read back from disk."""
    from step_pairs import clashes

    from cad.design import load_design
    from cad.pipeline import build_design

    out = tmp_path / "hl_roberts.toml"
    code, _, err = hapticad("swap", ROOT / "designs" / "hoeken_light.toml", "--to", "roberts",
                            "--out", out, "--json")
    assert code == 0, err
    assert "parts.layer_order: crank, coupler, rocker" in err
    d = load_design(out)
    assert d.parts.layer_order is None
    rep = build_design(d, tmp_path / "b", {"step"}, fidelity="preview", use_cache=False)
    assert rep["overlap_volume_mm3"] == 0.0
    assert rep["min_clearance_mm"] >= d.parts.clearance_min_mm - 1e-6
    assert clashes(tmp_path / "b" / "assembly.step") == []
