"""Numbers typed in docs/build-outputs.md, recomputed now at the printed rounding (issue 34 §4):
the layer planner's refusal as the build prints it, the hub set screws from the ISO 4026
catalog and the closed form, the motor's catalog values. No CAD import; about two seconds."""

from __future__ import annotations

import math
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TEXT = " ".join((ROOT / "docs/build-outputs.md").read_text(encoding="utf-8").split())


def test_layer_refusal_example_is_what_the_build_prints(tmp_path):
    """The quoted refusal (and the arithmetic beside it) is the one line `hapticad build` prints
    for tests/cases/assembly-clashes/hoeken_stroke24.toml, before any CAD, nothing written."""
    proc = subprocess.run([sys.executable, "-m", "cad", "build", "tests/cases/assembly-clashes/hoeken_stroke24.toml",
                           "--out", str(tmp_path / "out")], cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 2 and not (tmp_path / "out").exists()
    line, = [ln for ln in proc.stderr.splitlines() if ln.startswith("hapticad: error: ")]
    msg = line.removeprefix("hapticad: error: ")
    assert f"`{msg}`" in TEXT
    over, crank, stroke = (re.search(p, msg).group(1) for p in (r"overlap by ([\d.]+) mm", r"crank l1 ([\d.]+) ->",
                                                                  r"stroke_mm >= ([\d.]+) clears it"))
    assert f"its {float(crank):.1f} mm crank puts the A2 nut" in TEXT
    assert f"hub radius 10 + washer radius 6 - crank {crank} = {over} mm, the number in the error" in TEXT
    assert abs(10 + 6 - float(crank) - float(over)) < 0.006
    assert f"the stroke the error names, {stroke} mm, builds" in TEXT


def test_hub_set_screw_sizes_are_the_catalog_and_the_closed_form():
    """Hub set screws for 20, 17, 16, 14 mm hubs on the 6 mm shaft, and the 12 mm hub no size
    fits: cad.assembly.fasteners.size_set_screw over bd_warehouse's ISO 4026 lengths, its depth
    the closed form sqrt(R^2 - (d/2)^2) - r written out here."""
    from cad.assembly.fasteners import size_set_screw
    from cad.errors import DesignError
    from cad.families.pantograph.layout import SET_SCREW_SIZES
    r = 3.0

    def pick(hub_mm):
        size, L, depth = size_set_screw(r, hub_mm / 2, SET_SCREW_SIZES, "hub", "parts.hub_diameter_mm")
        d = float(size.split("-")[0][1:])
        assert abs(depth - (math.sqrt((hub_mm / 2) ** 2 - (d / 2) ** 2) - r)) < 1e-12
        return f"{size.split('-')[0]} × {L:g}", depth

    name, depth = pick(20.0)
    assert f"(20 mm hub, 6 mm RE 35 / RE 40 shaft): **{name}** in a hole of {depth:.2f} mm of full thread" in TEXT
    assert (f"A 17 mm hub takes {pick(17.0)[0]}, 16 mm {pick(16.0)[0]}, 14 mm {pick(14.0)[0]};") in TEXT
    try:
        pick(12.0)
        raise AssertionError("a 12 mm hub took a set screw")
    except DesignError as e:
        full = re.search(r"\(([\d.]+) mm of full M2 thread\)", str(e)).group(1)
    assert f"a hub no size fits (12 mm: {full} mm of full M2 thread)" in TEXT
    assert f"over the recorded {depth:.2f} mm (to 0.01 mm)" in TEXT


def test_motor_catalog_values():
    """The RE 35's rotor inertia and mass as cad/data/catalog.py states them (both marked
    unverified there: the maxon sheet's edition is not named)."""
    from cad.data.catalog import MOTORS
    m = MOTORS["maxon-re35"]
    assert f"rotor inertia Jm = {m.rotor_inertia_g_cm2:g} g·cm², mass {1e3 * m.mass_kg:g} g — both unverified" in TEXT
    assert {"rotor_inertia_g_cm2", "mass_kg"} <= set(m.unverified)
