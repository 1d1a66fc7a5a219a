"""Four-bar design files: validation at load, one-line errors, bundled designs."""

import math
from pathlib import Path

import pytest
import tomli_w
from cli_helpers import assert_one_line_error, hapticad
from hypothesis import given
from hypothesis import strategies as st

from cad.design import load_design, parse_design
from cad.design.fourbar import FourBarDesign
from cad.errors import DesignError

DESIGNS = Path(__file__).resolve().parents[3] / "designs"
CUSTOM = {
    "name": "t",
    "mechanism": {"family": "custom", "l1_mm": 25.0, "l2_mm": 62.5, "l3_mm": 62.5, "l4_mm": 0.0,
                  "l5_mm": 50.0, "le_mm": 125.0, "phi_e_deg": 0.0, "phi1_min_deg": 132.0,
                  "phi1_max_deg": 216.0, "branch": -1, "force_N": 5.0},
}


@pytest.mark.parametrize("name", ["hoeken", "roberts", "chebyshev", "chebyshev_v", "custom_example"])
def test_bundled_designs_load(name):
    d = load_design(DESIGNS / f"{name}.toml")
    assert isinstance(d, FourBarDesign)
    assert d.linkage.branch in (1, -1)


def test_custom_equals_family():
    d = parse_design(CUSTOM)
    h = load_design(DESIGNS / "hoeken.toml")
    assert d.linkage == h.linkage
    assert d.phi1_min_rad == pytest.approx(h.phi1_min_rad)


def test_stroke_mm_scales_family():
    from cad.kinematics.metrics import compute_metrics

    raw = {"name": "h", "mechanism": {"family": "hoeken", "stroke_mm": 80.0}}
    d = parse_design(raw)
    m = compute_metrics(d.linkage, d.phi1_min_rad, d.phi1_max_rad)
    assert m.stroke_mm == pytest.approx(80.0, rel=1e-9)


def _with(path, value):
    import copy

    raw = copy.deepcopy(CUSTOM)
    node = raw
    *head, last = path.split(".")
    for k in head:
        node = node[k]
    if value is None:
        del node[last]
    else:
        node[last] = value
    return raw


@pytest.mark.parametrize(
    "path, value, field",
    [
        ("mechanism.l1_mm", -3.0, "mechanism.l1_mm"),
        ("mechanism.l2_mm", 0, "mechanism.l2_mm"),
        ("mechanism.l3_mm", None, "mechanism.l3_mm"),
        ("mechanism.l1mm", 3.0, "mechanism.l1mm"),  # typo: unknown key
        ("mechanism.family", "peaucellier", "mechanism.family"),
        ("mechanism.branch", 0, "mechanism.branch"),
        ("mechanism.branch", None, "mechanism.branch"),
        ("mechanism.phi1_max_deg", 100.0, "mechanism.phi1_max_deg"),  # max < min
        ("mechanism.l1_mm", "25", "mechanism.l1_mm"),
        ("mechanism.l1_mm", 200.0, "mechanism"),  # cannot close over the range
        ("name", None, "name"),
        ("colour", "red", "colour"),
        ("targets", {"H11_kg_m2": {"value": 1e-5, "tol": 0.1}}, "targets.H11_kg_m2.tol"),
        ("targets", {"H99_kg_m2": 1.0}, "targets.H99_kg_m2"),
        ("inertia", {"H11_kg_m2": 1e-5}, "inertia.H12_kg_m2"),
    ],
)
def test_bad_designs_name_the_field(path, value, field):
    with pytest.raises(DesignError) as ei:
        parse_design(_with(path, value))
    assert str(ei.value).startswith(field), str(ei.value)


def test_bad_design_cli_exit_2_one_line(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text(tomli_w.dumps(_with("mechanism.l1_mm", -3.0)))
    code, out, err = hapticad("analyze", p, "--json")
    assert_one_line_error(code, err, "mechanism.l1_mm", "> 0")
    assert out == ""


def test_bad_toml_syntax(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text("name = \n[mechanism")
    code, _, err = hapticad("analyze", p)
    assert_one_line_error(code, err, "not valid TOML")


scalars = st.one_of(st.none(), st.booleans(), st.integers(-1000, 1000),
                    st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=5))
keys = st.sampled_from(["family", "l1_mm", "l2_mm", "l3_mm", "l4_mm", "l5_mm", "le_mm", "phi_e_deg",
                        "phi1_min_deg", "phi1_max_deg", "branch", "force_N", "stroke_mm", "zz"])


@given(st.dictionaries(keys, scalars, max_size=8), st.sampled_from(["hoeken", "custom", "roberts", 3]))
def test_fuzzed_designs_never_traceback(tmp_path_factory, mech, family):
    """Any mechanism table: either a valid design or one DesignError line; never another exception."""
    raw = {"name": "fuzz", "mechanism": {**{k: v for k, v in mech.items() if v is not None}, "family": family}}
    try:
        tomli_w.dumps(raw)
    except (TypeError, ValueError):
        return  # not representable as TOML (e.g. NaN is fine, None is not)
    try:
        d = parse_design(raw)
    except DesignError as exc:
        assert "\n" not in str(exc)
        return
    assert d.phi1_max_rad > d.phi1_min_rad
    assert math.isfinite(d.linkage.l1_mm)


@given(st.dictionaries(keys, scalars, max_size=6))
def test_fuzzed_design_files_cli_exit_2_nothing_written(tmp_path_factory, mech):
    tmp = tmp_path_factory.mktemp("fuzz")
    raw = {"name": "fuzz", "mechanism": {"family": "custom", **{k: v for k, v in mech.items() if v is not None}}}
    try:
        text = tomli_w.dumps(raw)
    except (TypeError, ValueError):
        return
    p = tmp / "d.toml"
    p.write_text(text)
    code, out, err = hapticad("analyze", p, "--json", "--report", tmp / "rep")
    if code != 0:
        assert_one_line_error(code, err)
        assert not (tmp / "rep").exists()
