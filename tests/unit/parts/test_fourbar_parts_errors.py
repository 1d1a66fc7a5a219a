"""Four-bar ``[parts]`` values no hardware fits: one stderr line naming the key that was
changed, its value and the reason, exit 2, before any CAD import, nothing written.

Reference for each reason: the catalog and the bundled design's numbers, independent of the
message code -- the M3 mount screw needs 1.5 d = 4.5 mm of thread (a 3 mm base plate has 3);
the longest bd_warehouse ISO 4762 M3 screw is 30 mm (< 60 mm bar + 4.5 mm); the maxon RE35
shaft (22 mm) minus the 6 mm base and 5 mm mount plates leaves 11 mm above the base, less the
1 mm base clearance = 10 mm in the hub (< 100 mm asked; with 100 mm clearance, -89 mm); a
0.1 mm tall knob cannot take the default 3 mm edge round (2 x 3 mm).
"""

from __future__ import annotations

from pathlib import Path

import pytest
from cli_helpers import assert_one_line_error, hapticad

ROOT = Path(__file__).resolve().parents[3]

CASES = [
    ("base_thickness_mm", "3", ("base_plate:mount_1 holds only 3 mm of M3 thread", "4.5 mm")),
    ("base_thickness_mm", "0.6", ("holds only 0.6 mm of M3 thread", "4.5 mm")),
    ("bar_thickness_mm", "60", ("60 mm", "longest M3 ISO 4762 screw (30 mm)", "64.5")),
    ("hub_shaft_engagement_min_mm", "100", ("100 mm", "reaches only 10.00 mm")),
    ("base_clearance_mm", "100", ("100 mm", "reaches only -89.00 mm")),
    ("handle_height_mm", "0.1", ("0.1 mm", "3 mm edge round")),
    ("motor_mount_thickness_mm", "0.5", ("0.5 mm", "motor:face_1", "3.5 mm of thread")),
]


@pytest.mark.parametrize(("key", "value", "needles"), CASES)
def test_parts_error_names_the_changed_key(key, value, needles, tmp_path, monkeypatch):
    import cad.parts.lazy_import as li

    text = (ROOT / "designs" / "hoeken.toml").read_text()
    assert f"\n{key} =" not in text  # the key is not set already: appended below [parts]
    src = tmp_path / "d.toml"
    src.write_text(text.replace("[parts]\n", f"[parts]\n{key} = {value}\n", 1))
    monkeypatch.setattr(li, "import_build123d", lambda: pytest.fail("CAD imported"))
    out = tmp_path / "out"
    code, _, err = hapticad("build", src, "--out", out)
    assert_one_line_error(code, err, f"parts.{key}:", *needles)
    assert not out.exists()
    for other in ("parts.handle_fillet_mm:", "parts.motor:", "1e+09", "parts.hub_screw:"):
        assert other not in err
