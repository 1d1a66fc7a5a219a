"""Issue 32 item 2: no ISO 286 fit (H7 ...) on a printed part. A printed hole is stated with
the printing process's tolerance, never an ISO reaming class; a build whose BOM says
otherwise is not published.

Every bundled design with printed parts is built with drawings; every drawing's feature
callouts and the BOM's fits column are read back (xml.etree, csv). Independent reference:
the FDM tolerance rule of the cited guideline, +-0.5 mm or +-1 % of the size, whichever is
greater ("FDM Quality Guideline", https://imaginethat3d.atlassian.net/wiki/spaces/IMAGINETHA/
pages/196679/FDM+QUALITY+GUIDELINE), computed here for each bore; the bore's diameter from
the part's STEP read back by build123d.
"""

from __future__ import annotations

import csv
import re
import tomllib
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DESIGNS = ROOT / "designs"
NS = "{http://www.w3.org/2000/svg}"
PRINTED = tuple(sorted(p.name for p in DESIGNS.glob("*.toml")
                       if tomllib.loads(p.read_text()).get("parts", {}).get("process") == "printed"))
#: An ISO 286 class in a callout ("Ø8 H7 (pin bore)") or at the end of a fit ("bore 8 H7").
ISO_CALLOUT = re.compile(r"Ø[\d.]+ [A-Za-z]{1,2}\d{1,2} \(")
ISO_FIT = re.compile(r" \d+(?:\.\d+)? [A-Za-z]{1,2}\d{1,2}$")
PRINTED_CALLOUT = re.compile(r"Ø([\d.]+) printed \((.+) ([\d.]+): (.*)\), ")


def fdm_tol_mm(d_mm: float) -> float:
    """The guideline's rule (module docstring)."""
    return max(0.5, 0.01 * d_mm)


def _rows(path: Path) -> list[dict]:
    with path.open(newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def test_the_bundled_printed_designs_are_found():
    assert "hoeken_printed.toml" in PRINTED


#: The formats read here (step, drawings) and the DXF: the same build as
#: tests/regressions/test_stock_agrees.py, made once per run (tests/conftest.py ``shared_build``).
FORMATS = {"step", "dxf", "drawings"}


@pytest.fixture(scope="module", params=PRINTED)
def build(request, shared_build):
    return shared_build(request.param, FORMATS, "preview")[1]


def test_no_printed_part_states_an_iso_fit(build):
    bom = {r["part"]: r for r in _rows(build / "bom.csv")}
    printed = {p for p, r in bom.items() if r["made_or_bought"] == "made" and "print" in r["process"].lower()}
    assert printed
    for p in printed:
        assert not [f for f in bom[p]["fits"].split("; ") if ISO_FIT.search(f)], (p, bom[p]["fits"])
    seen = 0
    for p in printed:
        texts = ["".join(t.itertext()) for t in ET.parse(build / "drawings" / f"{p}.svg").getroot().iter(NS + "text")]
        assert not [t for t in texts if ISO_CALLOUT.search(t)], p
        seen += sum(1 for t in texts if PRINTED_CALLOUT.search(t))
    assert seen >= 5  # the spacers', hub's, mount's and post's bores at least


def test_each_printed_bore_states_the_fdm_tolerance_at_its_size(build):
    """A bore printed at nominal (the spacers, hub, mount, post): its callout states the
    guideline's tolerance for its diameter, drilled to size after printing; the diameter is
    the STEP's cylinder."""
    import build123d as bd

    bom = {r["part"]: r for r in _rows(build / "bom.csv")}
    checked = 0
    for p, r in bom.items():
        if r["made_or_bought"] != "made" or "print" not in r["process"].lower():
            continue
        texts = ["".join(t.itertext()) for t in ET.parse(build / "drawings" / f"{p}.svg").getroot().iter(NS + "text")]
        step = bd.import_step(build / "parts" / f"{p}.step")
        radii = [f.radius for f in step.faces().filter_by(bd.GeomType.CYLINDER)]
        for t in texts:
            m = PRINTED_CALLOUT.search(t)
            if m is None or "FDM" not in m[4]:
                continue
            d_printed, nominal = float(m[1]), float(m[3])
            assert d_printed == nominal  # printed at nominal, drilled to size
            assert min(abs(2 * r - d_printed) for r in radii) < 0.005 + 1e-9
            tol = fdm_tol_mm(nominal)
            assert m[4].startswith(f"FDM +-{tol:g} mm; drill to {nominal:g} after printing, not H7"), t
            checked += 1
    assert checked >= 5


def test_a_printed_part_with_an_iso_fit_is_not_published(tmp_path, monkeypatch):
    """The printed fits turned back into ISO ones: the build reads bom.csv back and refuses."""
    from cad import printing
    from cad.design import load_design
    from cad.device.readback import OutputsDisagree
    from cad.pipeline import build_design

    monkeypatch.setattr(printing, "printed_fit", lambda text: text)
    monkeypatch.setattr("cad.assembly.printed.printed_fit", lambda text: text)  # its caller
    out = tmp_path / "out"
    with pytest.raises(OutputsDisagree) as e:
        build_design(load_design(DESIGNS / "hoeken_printed.toml"), out, {"step"}, fidelity="preview",
                     use_cache=False)
    msg = str(e.value)
    assert "\n" not in msg and "bom.csv: printed part " in msg and "ISO 286 fit" in msg and "H7" in msg
    assert not out.exists()
