"""Issue 32 item 2: every bought part is its own instance in the assembly, and the BOM and
``order.csv`` order exactly what ``assembly.step`` fits (a plain pin's retaining rings were
fused into its solid and ordered on top: 8 rings ordered where 5 are fitted).

``assembly.step`` is read back with OCCT's XCAF reader (:func:`tests.step_pairs.read_parts`,
one label per part instance, its name from the file, not the tool's reader); instances are
mapped to their kind by report.json ``placement``; ``bom.csv`` / ``order.csv`` with ``csv``.
Reference for the rings: each plain pin (``pin_<joint>``) holds one ring above its head
spacer, and one more below the lower link where a screw would take a nut (``nut_<joint>``);
the A4 pin sits in the post (catalog: a ``dowel-<d>`` pin "retained by DIN 471 rings in
grooves").
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from tests.bundled import buildable
from tests.step_pairs import read_parts

ROOT = Path(__file__).resolve().parents[2]
DESIGNS = ROOT / "designs"
BUILDS = tuple(sorted(p.name for p in DESIGNS.glob("*.toml") if buildable(p)))
FAST = ("hoeken.toml", "hoeken_light.toml")


def _rows(path: Path) -> list[dict]:
    with path.open(newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def _build(name: str, tmp: Path) -> Path:
    from cad.design import load_design
    from cad.pipeline import build_design

    for extra in DESIGNS.glob("*.py"):  # handle scripts named by a bundled design
        (tmp / extra.name).write_text(extra.read_text())
    (tmp / name).write_text((DESIGNS / name).read_text())
    out = tmp / "out"
    build_design(load_design(tmp / name), out, {"step"}, fidelity="preview", use_cache=False)
    return out


def check_bought_instances(out: Path) -> dict[str, int]:
    """Every bought BOM line with a solid: quantity == instances of its kind in assembly.step;
    every bought order line: quantity == the BOM lines of its designation. Returns the counts."""
    placed = json.loads((out / "report.json").read_text())["placement"]["instances"]
    count: dict[str, int] = {}
    for name, solids in read_parts(out / "assembly.step"):
        if name in placed:
            assert solids, name  # an instance in the file is a solid, not an empty label
            kind = placed[name]["kind"]
            count[kind] = count.get(kind, 0) + 1
    assert sum(count.values()) == len(placed)  # every instance of the model is in the file
    bom = _rows(out / "bom.csv")
    want: dict[str, int] = {}
    for r in bom:
        if r["made_or_bought"] != "bought":
            continue
        if r["part"] in count:
            assert int(r["quantity"]) == count[r["part"]], (r["part"], r["quantity"], count[r["part"]])
        want[r["designation"]] = want.get(r["designation"], 0) + int(r["quantity"])
    per: dict[str, int] = {}
    for o in _rows(out / "order.csv"):
        if o["group"] == "total" or o["group"].startswith("stock:"):
            continue
        per[o["designation"]] = per.get(o["designation"], 0) + int(o["quantity"])
    assert per == want  # each bought designation ordered exactly as often as the BOM lists it
    return count


@pytest.mark.parametrize("name", FAST)
def test_bought_parts_are_ordered_as_fitted(tmp_path, name):
    out = _build(name, tmp_path)
    count = check_bought_instances(out)
    if name == "hoeken_light.toml":  # plain pins: every ring its own instance
        names = json.loads((out / "report.json").read_text())["placement"]["instances"]
        pins = [n for n in names if n.startswith("pin_")]
        nuts = [n for n in names if n.startswith("nut_")]  # the lower rings
        assert len(pins) == 3 and len(nuts) == 2, (pins, nuts)
        assert count["nut_dowel-4"] == len(pins) + len(nuts) == 5
        rings = [o for o in _rows(out / "order.csv") if o["designation"] == "DIN 471 4"]
        assert [int(o["quantity"]) for o in rings] == [5]


@pytest.mark.slow
@pytest.mark.parametrize("name", [n for n in BUILDS if n not in FAST])
def test_bought_parts_are_ordered_as_fitted_every_bundled_design(tmp_path, monkeypatch, name):
    monkeypatch.setenv("HAPTICAD_ALLOW_SCRIPTS", "1")  # hoeken_cq_handle's bundled handle script
    check_bought_instances(_build(name, tmp_path))


def test_an_order_with_rings_on_top_is_not_published(tmp_path, monkeypatch):
    """``order.csv`` ordering rings beyond the fitted ones (the old pin description): refused."""
    from cad.design import load_design
    from cad.device.readback import OutputsDisagree
    from cad.export import order
    from cad.pipeline import build_design

    real = order.order_lines

    def corrupt(rows):
        return [{**o, "quantity": int(o["quantity"]) + 6} if o["designation"] == "DIN 471 4" else o
                for o in real(rows)]

    monkeypatch.setattr(order, "order_lines", corrupt)
    out = tmp_path / "out"
    with pytest.raises(OutputsDisagree) as e:
        build_design(load_design(DESIGNS / "hoeken_light.toml"), out, {"step"}, fidelity="preview",
                     use_cache=False)
    msg = str(e.value)
    assert "\n" not in msg and "order.csv: DIN 471 4 quantity = 11, bom.csv lines sum to 5" in msg
    assert not out.exists()
