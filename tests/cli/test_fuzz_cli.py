"""Hypothesis fuzzing of the bundled design files of every family with a schema.

Issue 7 §3 / SPEC "Bad input": random mutations of ``designs/*.toml`` (keys
deleted, wrong types, negative / zero / NaN / inf / huge / tiny values, unknown
keys, tables replaced by scalars, lists cut or padded) are fed through the
in-process CLI (``analyze`` for the four-bar families, ``gii`` for the
pantograph families) or, for the PowerMouse whose only command builds CAD,
through :func:`cad.design.load_design`. The property, for every mutation:

* never a traceback (no exception escapes the CLI; pytest turns warnings into
  errors, so a numpy RuntimeWarning that would print a multi-line warning on a
  user's terminal fails the test too);
* exit code 0 or 2; on 2 exactly one stderr line, ``hapticad: error: FIELD: ...``
  where FIELD is a dotted key of the design (its first component a top-level
  key of the design or of the family's schema);
* on 0, stdout is one JSON object without NaN or infinities;
* nothing is written on failure (the report directory is not created, the
  working directory holds only the design file).

Randomness is hypothesis' (derandomized by the ``ci`` profile in conftest.py).
"""

from __future__ import annotations

import contextlib
import copy
import json
import math
import os
import re
import tomllib
from pathlib import Path

import pytest
import tomli_w
from cli_helpers import hapticad
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cad.design import load_design
from cad.errors import DesignError

DESIGNS = Path(__file__).resolve().parents[2] / "designs"
FOURBAR_DESIGNS = ("hoeken", "roberts", "chebyshev", "chebyshev_v", "custom_example")
PANTOGRAPH_DESIGNS = ("pantograph", "haptic_mouse", "haptic_pen")

#: Top-level keys of each schema (cad/design/fourbar.py, pantograph.py, powermouse.py):
#: an error may name a table the mutation deleted.
FOURBAR_TOP = (
    "name",
    "description",
    "mechanism",
    "analysis",
    "inertia",
    "stiffness",
    "parts",
    "targets",
    "fit",
)
PANTOGRAPH_TOP = ("name", "description", "mechanism", "workspace", "actuators", "optimize", "parts")
POWERMOUSE_TOP = ("name", "mechanism", "actuator", "flotor", "stator", "handle", "motion")

#: Values that sit on or past the edge of every validator.
EDGE_VALUES = (
    0,
    0.0,
    -0.0,
    -1,
    -1.0,
    -1e-9,
    1e-300,
    5e-324,
    1e300,
    1.7e308,
    1e30,
    10**12,
    -(10**12),
    math.nan,
    math.inf,
    -math.inf,
    True,
    False,
    "",
    "abc",
    "1.0",
    [],
    [1.0],
    [math.nan, 1.0],
    [1.0, 2.0, 3.0, 4.0],
    {},
    {"x": 1.0},
)
values = st.one_of(
    st.sampled_from(EDGE_VALUES),
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(-(10**6), 10**6),
    st.text(max_size=3),
)
#: Factors applied to an existing number (keeps the design near-valid, probing ranges).
FACTORS = (-1.0, 0.0, 1e-12, 1e-3, 0.5, 0.99, 1.01, 2.0, 10.0, 1e3, 1e12, math.nan, math.inf)

LINE = re.compile(r"^hapticad: error: (?P<field>[^:\s]+): \S")


def _load(name: str) -> dict:
    with (DESIGNS / f"{name}.toml").open("rb") as fh:
        return tomllib.load(fh)


def _paths(node: dict, prefix: tuple = ()) -> list[tuple]:
    out = []
    for k, v in node.items():
        out.append((*prefix, k))
        if isinstance(v, dict):
            out.extend(_paths(v, (*prefix, k)))
    return out


def _tables(node: dict, prefix: tuple = ()) -> list[tuple]:
    out = [prefix]
    for k, v in node.items():
        if isinstance(v, dict):
            out.extend(_tables(v, (*prefix, k)))
    return out


def _get(node: dict, path: tuple):
    for k in path:
        node = node[k]
    return node


@st.composite
def mutated(draw, raw: dict) -> tuple[dict, list]:
    """1-3 random mutations of a design mapping; returns (mutated copy, description)."""
    raw = copy.deepcopy(raw)
    log = []
    for _ in range(draw(st.integers(1, 3))):
        paths = _paths(raw)
        op = draw(st.sampled_from(("delete", "set", "scale", "unknown", "list")))
        if op == "unknown" or not paths:
            table = draw(st.sampled_from(_tables(raw)))
            _get(raw, table)["zz_unknown"] = copy.deepcopy(draw(values))
            log.append(("unknown", table))
            continue
        path = draw(st.sampled_from(paths))
        parent, key = _get(raw, path[:-1]), path[-1]
        old = parent[key]
        if op == "delete":
            del parent[key]
        elif op == "scale" and isinstance(old, (int, float)) and not isinstance(old, bool):
            parent[key] = old * draw(st.sampled_from(FACTORS))
        elif op == "list" and isinstance(old, list) and old:
            how = draw(st.sampled_from(("cut", "pad", "element")))
            if how == "cut":
                old.pop()
            elif how == "pad":
                old.append(copy.deepcopy(draw(values)))
            else:
                old[draw(st.integers(0, len(old) - 1))] = copy.deepcopy(draw(values))
        else:
            parent[key] = copy.deepcopy(draw(values))
        log.append((op, path, parent.get(key, "<deleted>")))
    return raw, log


def _toml_text(raw: dict) -> str | None:
    try:
        return tomli_w.dumps(raw)
    except (TypeError, ValueError):  # e.g. a mixed-type array TOML cannot hold
        return None


def _no_nan(text: str):
    def bad(token):
        raise AssertionError(f"non-finite number {token} in JSON output")

    return json.loads(text, parse_constant=bad)


def _check_failure(code: int, out: str, err: str, top_keys: set, log) -> None:
    """Exit 2, one stderr line naming a field of the design, nothing on stdout."""
    assert code == 2, (code, err, log)
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1, (err, log)
    m = LINE.match(lines[0])
    assert m, (lines[0], log)
    head = m["field"].split(".")[0]
    assert head in top_keys, (lines[0], log)
    assert out == "", (out, log)


@contextlib.contextmanager
def _cwd(path: Path):
    old = os.getcwd()
    os.chdir(path)
    try:
        yield
    finally:
        os.chdir(old)


_FUZZ = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@_FUZZ
@given(st.sampled_from(FOURBAR_DESIGNS), st.data())
def test_fourbar_designs_analyze_never_traceback(tmp_path_factory, name, data):
    """Four-bar families through ``hapticad analyze --json --report DIR``."""
    raw, log = data.draw(mutated(_load(name)))
    text = _toml_text(raw)
    if text is None:
        return
    tmp = tmp_path_factory.mktemp("fuzz4")
    design = tmp / "design.toml"
    design.write_text(text)
    with _cwd(tmp):
        code, out, err = hapticad("analyze", design, "--json", "--report", tmp / "report")
    if code == 0:
        res = _no_nan(out)
        assert res["stroke_mm"] > 0 and math.isfinite(res["stroke_mm"]), log
        assert (tmp / "report" / "analysis.json").is_file()
    else:
        _check_failure(code, out, err, set(raw) | set(FOURBAR_TOP), log)
        assert sorted(p.name for p in tmp.iterdir()) == ["design.toml"], log


@_FUZZ
@given(st.sampled_from(PANTOGRAPH_DESIGNS), st.data())
def test_pantograph_designs_gii_never_traceback(tmp_path_factory, name, data):
    """Pantograph, twin-pantograph and haptic-pen designs through ``hapticad gii --json``."""
    raw, log = data.draw(mutated(_load(name)))
    text = _toml_text(raw)
    if text is None:
        return
    tmp = tmp_path_factory.mktemp("fuzzp")
    design = tmp / "design.toml"
    design.write_text(text)
    with _cwd(tmp):
        code, out, err = hapticad("gii", design, "--json")
    if code == 0:
        res = _no_nan(out)
        assert 0.0 <= res["gii"] <= 1.0, (res["gii"], log)
        # GII = 0 always comes with the point that caused it (isotropy paper eq 5)
        if res["gii"] == 0.0:
            assert res["failure"] and res["failed_at"], (res, log)
    else:
        _check_failure(code, out, err, set(raw) | set(PANTOGRAPH_TOP), log)
    assert sorted(p.name for p in tmp.iterdir()) == ["design.toml"], log


@_FUZZ
@given(st.data())
def test_powermouse_design_never_traceback(tmp_path_factory, data):
    """PowerMouse: only ``build`` reads it (CAD), so the loader is fuzzed directly:
    a valid design or one DesignError line naming a field, nothing else."""
    raw, log = data.draw(mutated(_load("powermouse")))
    text = _toml_text(raw)
    if text is None:
        return
    tmp = tmp_path_factory.mktemp("fuzzpm")
    design = tmp / "design.toml"
    design.write_text(text)
    try:
        d = load_design(design)
    except DesignError as exc:
        msg = str(exc)
        assert "\n" not in msg, (msg, log)
        head = exc.field.split(".")[0]
        assert head in set(raw) | set(POWERMOUSE_TOP), (msg, log)
        assert msg.startswith(exc.field + ": ") and exc.reason, (msg, log)
        return
    a = d.actuator
    for v in (
        a.magnet_length_mm,
        a.magnet_width_mm,
        a.magnet_thickness_mm,
        a.rattle_mm,
        a.power_W,
        a.br_T,
        d.flotor.edge_mm,
        d.motion.range_mm,
    ):
        assert math.isfinite(v) and v > 0, (d, log)
    assert a.gap_mm is None or a.gap_mm > a.rattle_mm, (d, log)
    assert d.motion.range_mm <= a.rattle_mm / 2


# --------------------------------------------------------------------------- four-bar edges
# Deterministic extreme cases the fuzzer can draw but rarely does. Each one used to overflow,
# divide by zero or exhaust memory (found by this file); the design loader now bounds
# magnitudes (cad/tolerances.py LENGTH_*, FORCE_MAX_N, SAMPLES_MAX) and says which field.
FOURBAR_EDGES = [
    (
        "hoeken",
        ("mechanism", "force_N"),
        1.7e308,
        "force_N = 1.7e308: RuntimeWarning overflow in the torque metrics",
    ),
    (
        "hoeken",
        ("mechanism", "stroke_mm"),
        1e300,
        "stroke_mm = 1e300: RuntimeWarning overflow (lengths squared in eqs 4-6)",
    ),
    ("hoeken", ("stiffness", "Fv_N_s_per_m"), 1.7e308, "eq (25) K_min/K_max = inf/NaN in the JSON"),
    ("hoeken", ("stiffness", "Fs_N"), 1.7e308, "eq (25) K_max = inf in the JSON"),
    ("hoeken", ("stiffness", "Te_s"), 5e-324, "eq (25) K_min = inf in the JSON"),
    ("hoeken", ("analysis", "samples"), 10**13, "analysis.samples has no upper bound: MemoryError"),
    ("custom_example", ("mechanism", "l1_mm"), 1e300, "OverflowError (python float **) in eqs 4-6"),
    ("custom_example", ("mechanism", "l1_mm"), 5e-324, "RuntimeWarning divide by zero"),
    ("custom_example", ("mechanism", "l2_mm"), 5e-324, "RuntimeWarning overflow in divide"),
    ("custom_example", ("mechanism", "le_mm"), 1e300, "RuntimeWarning overflow in dot"),
    ("custom_example", ("mechanism", "l4_mm"), -1e300, "OverflowError in eqs 4-6"),
    ("custom_example", ("mechanism", "l5_mm"), 1e300, "OverflowError in eqs 4-6"),
]


@pytest.mark.parametrize(
    "name, path, value",
    [
        pytest.param(
            n,
            p,
            v,
            id=f"{n}-{'.'.join(p)}={v:g}",
        )
        for n, p, v, why in FOURBAR_EDGES
    ]
    + [
        pytest.param("hoeken", ("mechanism", "stroke_mm"), 1e-300, id="hoeken-stroke=1e-300"),
        pytest.param(
            "custom_example", ("mechanism", "phi1_max_deg"), 1e300, id="custom-phi1max=1e300"
        ),
    ],
)
def test_fourbar_extreme_values_exit_cleanly(tmp_path, name, path, value):
    """``hapticad analyze``: exit 0 with finite JSON, or exit 2 with one line naming a field."""
    raw = _load(name)
    node = raw
    for k in path[:-1]:
        node = node.setdefault(k, {})
    node[path[-1]] = value
    design = tmp_path / "design.toml"
    design.write_text(tomli_w.dumps(raw))
    code, out, err = hapticad("analyze", design, "--json")
    if code == 0:
        _no_nan(out)
    else:
        _check_failure(code, out, err, set(raw) | set(FOURBAR_TOP), path)


def test_analyze_samples_flag_is_bounded():
    code, out, err = hapticad(
        "analyze", DESIGNS / "hoeken.toml", "--json", "--samples", str(10**13)
    )
    _check_failure(code, out, err, {"--samples"}, "--samples")
