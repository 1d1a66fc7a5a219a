"""Material table: required keys, densities against handbook values, lookup errors."""

from __future__ import annotations

import subprocess
import sys

import pytest

from cad.data.materials import DEFAULT_MATERIAL, MATERIALS, Material, get_material
from cad.errors import DesignError

REQUIRED = (
    "aluminium-6061",
    "aluminium-7075",
    "steel-1018",
    "stainless-304",
    "brass-360",
    "carbon-fibre",
    "pla",
    "petg",
    "ndfeb-n42",
    "copper",
    "soft-iron",
    "abs",
    "delrin",
)

# Independent reference values (g/cm^3) with the spread found across handbooks/datasheets:
# CRC Handbook (Cu 8.96, Fe 7.87), ASM Handbook Vol. 2 (6061 2.70, 7075 2.81), ASM Vol. 1
# (1018 7.87, 304 7.9-8.0), CDA C36000 8.49-8.50, NdFeB sintered 7.4-7.6, CFRP 1.5-1.6,
# PLA 1.24-1.25, PETG 1.27, ABS 1.03-1.07, POM 1.41-1.42.
HANDBOOK_G_CM3 = {
    "aluminium-6061": (2.69, 2.71),
    "aluminium-7075": (2.80, 2.82),
    "steel-1018": (7.85, 7.88),
    "stainless-304": (7.90, 8.03),
    "brass-360": (8.47, 8.53),
    "copper": (8.89, 8.97),
    "soft-iron": (7.86, 7.88),
    "ndfeb-n42": (7.40, 7.60),
    "carbon-fibre": (1.50, 1.60),
    "pla": (1.21, 1.25),
    "petg": (1.23, 1.29),
    "abs": (1.02, 1.08),
    "delrin": (1.40, 1.43),
}


def test_required_materials_present():
    assert set(REQUIRED) <= set(MATERIALS)
    assert DEFAULT_MATERIAL in MATERIALS


@pytest.mark.parametrize("name", sorted(HANDBOOK_G_CM3))
def test_density_matches_handbook(name):
    lo, hi = HANDBOOK_G_CM3[name]
    rho = MATERIALS[name].density_kg_m3
    assert lo * 1000 <= rho <= hi * 1000, f"{name}: {rho} kg/m^3 outside handbook {lo}-{hi} g/cm^3"


@pytest.mark.parametrize("mat", list(MATERIALS.values()), ids=lambda m: m.name)
def test_entries_well_formed(mat: Material):
    assert MATERIALS[mat.name] is mat
    assert len(mat.color_rgb) == 3 and all(0.0 <= c <= 1.0 for c in mat.color_rgb)
    assert len(mat.source) > 10
    with pytest.raises(AttributeError):
        mat.density_kg_m3 = 1.0  # frozen


def test_lookup_aliases():
    assert get_material("Aluminum_6061") is MATERIALS["aluminium-6061"]
    assert get_material(" PLA ") is MATERIALS["pla"]
    assert get_material("carbon-fiber") is MATERIALS["carbon-fibre"]


def test_unknown_material_names_field_and_lists_known():
    with pytest.raises(DesignError) as exc:
        get_material("unobtainium", "parts.bar.material")
    assert exc.value.field == "parts.bar.material"
    msg = str(exc.value)
    assert "unknown material 'unobtainium'" in msg
    assert "aluminium-6061" in msg and "delrin" in msg
    with pytest.raises(DesignError):
        get_material(42)  # type: ignore[arg-type]


def test_materials_import_is_cad_free():
    code = "import sys, cad.data.materials; print(any(m.split('.')[0] in ('OCP','build123d','cadquery') for m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_printed_pla_uses_printed_part_values():
    """PLA is only printed here, so its stiffness and strength are printed-part values:
    Pro3D Composites PLA data sheet, XY axis, ASTM D638 Type 1 (typed from the sheet):
    tensile modulus 2539 MPa, tensile strength at yield 26 MPa, not the ~50 MPa / 3.5 GPa of
    injection-moulded PLA; the printed-modulus filament table agrees."""
    from cad.printing import FILAMENTS
    from cad.structure.elastic import ELASTIC

    pla = ELASTIC["pla"]
    assert (pla.E_GPa, pla.strength_MPa) == (2.539, 26.0)
    assert "printed XY" in pla.source and "Pro3D" in pla.source
    assert "unverified" in pla.source  # Poisson's ratio: no printed-PLA source states it
    assert FILAMENTS["pla"].E_xy_GPa == pla.E_GPa
