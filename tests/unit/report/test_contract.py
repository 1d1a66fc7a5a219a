"""The typed report.json contract (issue 32 §6, :mod:`cad.report.contract`): the checker finds
every kind of break on hand-made documents, every family's type extends the common one, and a
build whose report breaks its contract publishes nothing."""

from __future__ import annotations

import typing

import pytest

from cad.report import contract
from cad.report.contract import CommonReport, problems
from tests.bundled import DESIGNS

BODY = {"mass_kg": 0.01, "com_mm": [0.0, 0.0, 0.0], "inertia_com_kg_m2": [[0.0] * 3] * 3,
        "principal_moments_kg_m2": [0.0] * 3}


def _common() -> dict:
    """A document with every common key, of the right JSON type (written by hand)."""
    doc = {}
    for k, tp in typing.get_type_hints(CommonReport).items():
        doc[k] = {"float": 1.5, "str": "x"}.get(getattr(tp, "__name__", ""), None)
    doc.update(name="d", family="hoeken", source="d.toml", fidelity="preview", notes=[], bom=[],
               files=[], bodies={"crank": dict(BODY)}, min_clearance_mm=0.3, overlap_volume_mm3=0.0,
               **{k: {} for k in ("order", "interference", "fasteners", "tapped_holes", "fits",
                                  "part_materials", "placement", "datasheet", "device", "build")})
    return doc


def test_a_complete_document_keeps_to_the_common_contract():
    assert problems(_common()) == []


@pytest.mark.parametrize("change, expect", [
    (lambda d: d.pop("total_mass_g"), "missing key 'total_mass_g'"),
    (lambda d: d.update(moving_mass_g="12 g"), "'moving_mass_g' is str"),
    (lambda d: d.update(moving_mass_g=True), "'moving_mass_g' is bool"),  # a bool is no number
    (lambda d: d.update(extra_g=1.0), "key 'extra_g' is not in the contract"),
    (lambda d: d["bodies"]["crank"].pop("com_mm"), "bodies['crank'] is not a Body"),
    (lambda d: d.update(notes="one line"), "'notes' is str"),
])
def test_each_kind_of_break_is_named(change, expect):
    doc = _common()
    change(doc)
    found = problems(doc)
    assert any(expect in p for p in found), found


def test_optional_and_nullable_keys():
    doc = _common()
    doc.pop("source")  # NotRequired: a design made in code has no file
    doc["min_clearance_mm"] = None  # float | None
    assert problems(doc) == []
    doc["moving_mass_g"] = 3  # an int is a JSON number
    assert problems(doc) == []


def test_check_raises_one_line_naming_the_type():
    doc = _common()
    doc.pop("bom")
    with pytest.raises(contract.ReportContractError) as e:
        contract.check(doc)
    assert "\n" not in str(e.value) and "CommonReport" in str(e.value) and "'bom'" in str(e.value)


@pytest.mark.parametrize("family", ["hoeken", "pantograph", "twin-pantograph", "haptic-pen",
                                    "powermouse", "delta"])
def test_every_family_type_extends_the_common_one(family):
    from cad.families import family_package

    rt = family_package(family).report_type.resolve()
    assert issubclass(rt, dict) and set(typing.get_type_hints(CommonReport)) <= set(typing.get_type_hints(rt))
    assert CommonReport.__required_keys__ <= rt.__required_keys__


def test_a_report_that_breaks_its_contract_is_not_published(tmp_path, monkeypatch):
    """A family report with a key its type does not declare: the build refuses in one line and
    the output folder is not made."""
    import cad.families.pantograph.build as pb
    from cad.design import load_design
    from cad.pipeline import build_design

    real = pb.build_report  # the caller's binding: what the build calls
    monkeypatch.setattr(pb, "build_report", lambda *a, **k: {**real(*a, **k), "stray_g": 1.0})
    out = tmp_path / "out"
    with pytest.raises(contract.ReportContractError) as e:
        build_design(load_design(DESIGNS / "pantograph.toml"), out, set(), fidelity="preview",
                     use_cache=False)
    assert "stray_g" in str(e.value) and "PantographReport" in str(e.value)
    assert not out.exists()
