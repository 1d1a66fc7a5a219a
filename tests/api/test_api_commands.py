"""``cad.api`` covers every ``hapticad`` command (issue 23 §2): the table in its docstring
(``cad.api.COMMANDS``) against the command list of the CLI app itself, and the functions
added for it called on bundled designs. References: the CLI's ``--json`` output for the same
input (same process, the CLI's own flag parsing), independent recomputations (a synthesized
or swapped linkage re-analysed, an optimum's GII recomputed) and, for commands too slow to
run here (fit, sweep, bench, render, wall), the CLI's one-line error for the same bad input.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest

import cad
from cad import api
from cad.errors import DesignError
from tests.cli_helpers import hapticad, hapticad_json

ROOT = Path(__file__).resolve().parents[2]
DESIGNS = ROOT / "designs"
HOEKEN = DESIGNS / "hoeken.toml"
#: The Hoeken paper's CAD inertia (§III.B.2), as --inertia flag and as the API's dict.
H = {"H11": 2.97e-5, "H12": 3.22e-5, "H22": 1.17e-4, "H33": 7.09e-5}
H_FLAG = ",".join(f"{k}={v}" for k, v in H.items())


def _cli_commands() -> set[str]:
    from cad.cli.app import register_commands, app

    register_commands()
    return {c.name for c in app.registered_commands}


def _json(*args) -> dict:
    out = hapticad_json(*args)
    out.pop("warnings")
    return out


def _without(d: dict, *keys: str) -> dict:
    return {k: v for k, v in d.items() if k not in keys}


def _normal(obj):
    """JSON round trip: tuples as lists, numpy scalars as numbers, as --json prints them."""
    return json.loads(json.dumps(obj, default=float))


def test_every_cli_command_has_an_api_function_and_the_table_says_which():
    cmds = _cli_commands()
    assert len(cmds) >= 17
    assert set(api.COMMANDS) == cmds
    for cmd, fn in api.COMMANDS.items():
        assert callable(getattr(api, fn)) and fn in api.__all__
        assert re.search(rf"``hapticad {cmd}``\s+:func:`{fn}`", api.__doc__), cmd
    assert cad.__all__ == api.__all__


def test_no_api_name_is_shadowed_by_a_subpackage_of_cad():
    """``cad.<name>`` is the API function even after every subpackage of cad is imported
    (a submodule binds its name on the package: cad.studies.fit, cad.studies.sweep, cad.bench ...)."""
    import importlib
    import pkgutil

    for m in pkgutil.iter_modules(cad.__path__):
        if m.name not in ("__main__",):
            importlib.import_module(f"cad.{m.name}")
    for name in api.__all__:
        assert getattr(cad, name) is getattr(api, name), name


def test_voicecoil_matches_the_cli():
    args = dict(magnet_length_mm=30.0, magnet_width_mm=10.0, magnet_thickness_mm=5.0,
                rattle_mm=2.0, gap_mm=6.0)
    got = cad.voicecoil(**args)
    cli = _json("voicecoil", "--magnet-length-mm", "30", "--magnet-width-mm", "10",
                "--magnet-thickness-mm", "5", "--rattle-mm", "2", "--gap-mm", "6")
    assert _normal(got) == cli
    assert got["coil_width_mm"] == pytest.approx(got["optimal_gap_mm"] - 2.0, rel=1e-12)
    with pytest.raises(DesignError) as exc:
        cad.voicecoil(30.0, 10.0, 5.0, 2.0, gap_mm=1.5)
    assert exc.value.field == "gap_mm"


def test_cache_matches_the_cli(tmp_path, monkeypatch):
    monkeypatch.setenv("HAPTICAD_CACHE_DIR", str(tmp_path / "c"))
    (tmp_path / "c").mkdir()
    got = cad.cache()
    assert got == _json("cache")
    assert got["cache_dir"] == str(tmp_path / "c") and got["enabled"]


def test_synth_matches_the_cli_and_its_linkage_reanalysed():
    d = cad.load_design(HOEKEN)
    got = cad.synth(d, "max-stroke", "range")
    cli = _json("synth", HOEKEN, "--objective", "max-stroke", "--free", "range")
    assert _normal(_without(got, "mechanism")) == _without(cli, "command", "measured")
    new = d.replace(mechanism=got["mechanism"], name="hoeken_synth")  # family custom
    assert new.family == "custom"
    assert cad.analyze(new)["stroke_mm"] == pytest.approx(got["result"]["stroke_mm"], rel=1e-6)


def test_swap_matches_the_cli_and_keeps_the_stroke(tmp_path):
    """Hoeken paper §III.A: the new bar set at the same stroke on the same hardware."""
    d = cad.load_design(HOEKEN)
    out = tmp_path / "roberts.toml"
    got = cad.swap(d, "roberts", out)
    cli = _json("swap", HOEKEN, "--to", "roberts", "--out", out)
    assert _normal({k: got[k] for k in ("old", "new", "layers")}) == \
        _without(cli, "out", "replaced")
    assert got["design"] == cad.load_design(out).replace(name=got["design"].name)
    assert cad.analyze(got["design"])["stroke_mm"] == pytest.approx(
        cad.analyze(d)["stroke_mm"], rel=1e-6)
    assert got["design"].parts == d.parts


def test_tolerance_matches_the_cli():
    d = cad.load_design(HOEKEN)
    got = cad.tolerance(d, hole_mm=0.05, samples=200, angles=101, inertia=H)
    cli = _json("tolerance", HOEKEN, "--hole-mm", "0.05", "--samples", "200", "--angles", "101",
                "--inertia", H_FLAG)
    timing = [k for k in cli if k.endswith("_s") or k.startswith("wall")]
    assert _normal(_without(got, *timing)) == _without(cli, *timing)
    assert got["inertia_source"] == "--inertia"


def test_optimize_pantograph_matches_the_cli_and_its_gii_recomputes():
    """The culling optimum (isotropy paper eq 6) equals the CLI's, and the GII of the design
    with the optimum's parameters, computed again by gii() (eq 5), is the reported GII."""
    d = cad.load_design(DESIGNS / "pantograph.toml")
    got = cad.optimize(d)
    cli = _json("optimize", DESIGNS / "pantograph.toml")
    assert _without(_normal(got), "wall_time_s") == _without(cli, "wall_time_s")
    best = d.replace(mechanism=got["best"])
    assert cad.gii(best)["gii"] == pytest.approx(got["gii"], rel=1e-9)
    with pytest.raises(DesignError) as exc:
        cad.optimize(d, objective="min-apparent-mass")
    assert exc.value.field == "--objective"


def test_device_datasheet_matches_the_cli():
    d = cad.load_design(DESIGNS / "powermouse.toml")
    got = cad.device_datasheet(d)
    cli = _json("datasheet", DESIGNS / "powermouse.toml")
    assert _normal(got) == cli
    assert got["datasheet"]["rows"]


def _cli_error(*args) -> str:
    code, _, err = hapticad(*args)
    assert code == 2, err
    return err.strip()


def _thick_plate_pen() -> Path:
    """A pen whose waist bracket plate is too thick for the shoulder shafts (cwd)."""
    bad = Path("thick_plate_pen.toml")
    bad.write_text((DESIGNS / "haptic_pen.toml").read_text().replace(
        "[parts]\n", "[parts]\nmotor_mount_thickness_mm = 15.0\n"))
    return bad


@pytest.mark.parametrize("call, argv", [
    (lambda: cad.fit_design(cad.load_design(HOEKEN), free=["parts.bar_width_mm"],
                            targets=["no_such_key<=1"]),
     ("fit", HOEKEN, "--free", "parts.bar_width_mm", "--target", "no_such_key<=1")),
    (lambda: cad.sweep_design(HOEKEN, ["parts.bar_width_mm=10,12,12x"], "unused"),
     ("sweep", HOEKEN, "--vary", "parts.bar_width_mm=10,12,12x", "--out", "unused")),
    (lambda: cad.run_bench("unused", only="nosuchtopic"),
     ("bench", "--out", "unused", "--only", "nosuchtopic")),
    # the haptic pen renders now (issue 23): the refused design is a pen whose build is
    # refused (tests/unit/report/test_report_html.py), written into the test's folder by the API call
    (lambda: cad.render([_thick_plate_pen()], "unused"),
     ("render", "thick_plate_pen.toml", "--out", "unused")),
    (lambda: cad.wall(cad.load_design(DESIGNS / "pantograph.toml")),
     ("wall", DESIGNS / "pantograph.toml")),
])
def test_slow_commands_refuse_bad_input_as_the_cli_does(call, argv, tmp_path, monkeypatch):
    """The API's DesignError is the CLI's one error line (same field, same reason)."""
    monkeypatch.chdir(tmp_path)  # nothing may be written; "unused" stays absent
    with pytest.raises(DesignError) as exc:
        call()
    err = _cli_error(*argv)
    assert err.startswith(f"hapticad: error: {exc.value}"), (err, str(exc.value))
    assert not (tmp_path / "unused").exists()


def test_analyze_inertia_is_checked_like_the_flag():
    d = cad.load_design(HOEKEN)
    with pytest.raises(DesignError) as exc:
        cad.analyze(d, inertia={**H, "H11": -1.0})
    assert exc.value.field == "inertia.H11_kg_m2"
    am = cad.analyze(d, inertia=H)["apparent_mass"]
    assert am == _json("analyze", HOEKEN, "--inertia", H_FLAG)["apparent_mass"]
    assert math.isfinite(am["M11_min_g"])
