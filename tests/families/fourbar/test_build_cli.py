"""``hapticad build``: the four bundled four-bars build with zero interference; report.json
keys; masses and H consistent with the parts; DXF profiles; bad input -> exit 2 with one
line and nothing written; an unchanged design is served from the cache without CAD."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
FAMILIES = ["hoeken", "roberts", "chebyshev", "chebyshev_v"]
LINKAGE_KEYS = [
    "l1_mm",
    "l2_mm",
    "l3_mm",
    "l4_mm",
    "l5_mm",
    "le_mm",
    "phi_e_deg",
    "phi1_min_deg",
    "phi1_max_deg",
    "branch",
]


def run_cli(*args, cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "cad", *map(str, args)],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=600,
    )


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """The four bundled designs built in-process (inertia fidelity, DXF only: fast)."""
    from cad.design import load_design
    from cad.pipeline import build_design

    root = tmp_path_factory.mktemp("builds")
    out = {}
    for fam in FAMILIES:
        d = load_design(ROOT / "designs" / f"{fam}.toml")
        rep = build_design(d, root / fam, {"dxf"}, fidelity="inertia", use_cache=False)
        out[fam] = (d, rep, root / fam)
    return out


@pytest.mark.parametrize("fam", FAMILIES)
def test_bundled_designs_build_with_zero_interference(built, fam):
    d, rep, _ = built[fam]
    assert rep["overlap_volume_mm3"] == 0.0
    assert rep["interference"]["collisions"] == []
    assert rep["min_clearance_mm"] >= d.parts.clearance_min_mm
    assert rep["interference"]["method"] == "fcl+occt"


@pytest.mark.parametrize("fam", FAMILIES)
def test_report_json_carries_the_contract_keys(built, fam):
    d, rep, out = built[fam]
    doc = json.loads((out / "report.json").read_text())
    for k in [
        *LINKAGE_KEYS,
        "H11_kg_m2",
        "H12_kg_m2",
        "H22_kg_m2",
        "H33_kg_m2",
        "apparent_mass",
        "min_clearance_mm",
        "overlap_volume_mm3",
        "bom",
        "part_masses_g",
        "links",
        "stroke_mm",
        "dy_max_mm",
        "linearity",
        "torque_mean_mNm",
        "fidelity_costs",
    ]:
        assert k in doc, k
    for k in ("M11_min_g", "M11_max_g", "M12_min_g", "M22_max_g"):
        assert k in doc["apparent_mass"]
    assert doc["l1_mm"] == pytest.approx(d.linkage.l1_mm) and doc["branch"] == d.linkage.branch
    assert "timings_s" not in doc and "_timings_s" not in doc
    manifest = json.loads((out / "manifest.json").read_text())
    listed = {r["path"] for r in manifest["files"]}
    assert {"report.json", "bom.csv", "preview.png", "report.md"} <= listed


def test_masses_add_up_and_H_follows_eqs_16_to_19(built):
    """Independent recomputation from the per-link numbers in the report (Hoeken paper eqs 16-19)."""
    d, rep, _ = built["hoeken"]
    links = rep["links"]
    for k, v in links.items():
        assert sum(p["mass_g"] for p in v["parts"]) == pytest.approx(v["mass_g"], rel=1e-12), k
    moving = sum(v["mass_g"] for v in links.values())
    assert moving + rep["ground_mass_g"] == pytest.approx(rep["total_mass_g"], rel=1e-9)
    l1 = d.linkage.l1_mm * 1e-3
    m1, m2, m3 = (links[k]["mass_g"] * 1e-3 for k in ("crank", "coupler", "rocker"))
    lG = {k: links[k]["lG_mm"] * 1e-3 for k in links}
    J = {k: links[k]["Jzz_com_kg_m2"] for k in links}
    assert rep["H11_kg_m2"] == pytest.approx(
        m1 * lG["crank"] ** 2 + m2 * l1**2 + rep["Jm_kg_m2"] + J["crank"], rel=1e-12
    )
    assert rep["H22_kg_m2"] == pytest.approx(m2 * lG["coupler"] ** 2 + J["coupler"], rel=1e-12)
    assert rep["H33_kg_m2"] == pytest.approx(m3 * lG["rocker"] ** 2 + J["rocker"], rel=1e-12)
    assert rep["H12_kg_m2"] == pytest.approx(m2 * l1 * lG["coupler"], rel=1e-12)
    # the handle at P sits on the coupler: the coupler COM lies beyond A3 for Hoeken (le = 2 l2)
    assert links["coupler"]["lG_mm"] > 0.5 * d.linkage.l2_mm


def test_bearing_masses_are_catalog_masses(built):
    from cad.data import catalog

    _, rep, _ = built["hoeken"]
    b = catalog.get_bearing("M8-16-4")
    assert rep["part_masses_g"]["bearing_M8-16-4"] == pytest.approx(b.mass_kg * 1e3, rel=1e-12)


def test_dxf_cut_layer_and_milled_seats_give_the_part_volume(built):
    """CUT area x t minus the milled seat rings minus the reaming stock left in the pin bores
    (cut at 8 - 0.2 mm: the 5-20 mm row of the reaming-allowance table,
    cad.data.fits.REAM_ALLOWANCE_SOURCE) = the part's volume (from its mass)."""
    import ezdxf

    from cad.data import catalog
    from cad.data.materials import get_material
    from cad.export.dxf import dxf_profile_area_mm2

    d, rep, out = built["hoeken"]
    p = d.parts
    b = catalog.get_bearing(p.bearing)
    rho = get_material(p.bar_material).density_kg_m3
    for link in ("crank", "coupler", "rocker"):
        text = (out / "parts" / f"{link}.dxf").read_text()
        seats = sum(1 for s in rep["layers"]["joints"].values() if s["upper"] == link)
        assert ("MILL_Z0.00_4.00" in text) == (seats > 0)
        vol = rep["part_masses_g"][link] * 1e-3 / rho * 1e9
        milled = seats * math.pi * ((b.D_mm / 2) ** 2 - (b.Da_mm / 2) ** 2) * b.B_mm
        msp = ezdxf.readfile(out / "parts" / f"{link}.dxf").modelspace()
        cut_r = [e.dxf.radius for e in msp if e.dxftype() == "CIRCLE" and e.dxf.layer == "CUT"]
        pins = sum(s["lower"] == link for s in rep["layers"]["joints"].values())
        ds = catalog.get_shoulder_screw(p.pin).ds_mm  # 8 mm (Hoeken, ISO 7379 M6)
        assert 5.0 < ds <= 20.0  # the table row used below
        assert sum(r == pytest.approx((ds - 0.2) / 2, abs=1e-12) for r in cut_r) == pins
        stock = pins * math.pi * ((ds / 2) ** 2 - (ds / 2 - 0.1) ** 2) * p.bar_thickness_mm
        assert dxf_profile_area_mm2(text) * p.bar_thickness_mm - milled - stock == pytest.approx(
            vol, rel=1e-9
        )


@pytest.mark.parametrize(
    ("parts", "field"),
    [
        ("bar_width_mm = 14.0", "parts.bar_width_mm"),
        ("bar_thickness_mm = -3.0", "parts.bar_thickness_mm"),
    ],
)
def test_bad_part_parameters_exit_2_one_line_nothing_written(tmp_path, parts, field):
    src = (ROOT / "designs" / "hoeken.toml").read_text().replace("[parts]\n", f"[parts]\n{parts}\n")
    design = tmp_path / "bad.toml"
    design.write_text(src)
    out = tmp_path / "out"
    r = run_cli("build", design, "--out", out)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and field in lines[0] and "Traceback" not in r.stderr
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]


@pytest.mark.parametrize(
    ("args", "field"),
    [
        (("--formats", "step,iges"), "--formats"),
        (("--phi1-deg", "10"), "--phi1-deg"),
        (("--fidelity", "draft"), "--fidelity"),
    ],
)
def test_bad_options_exit_2(tmp_path, args, field):
    out = tmp_path / "out"
    r = run_cli("build", ROOT / "designs" / "hoeken.toml", "--out", out, *args)
    assert r.returncode == 2 and field in r.stderr and len(r.stderr.strip().splitlines()) == 1
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_unchanged_rebuild_is_cached_without_cad_imports(tmp_path):
    """Two processes build the same design: the second imports no CAD library."""
    out = tmp_path / "hoeken"
    code = (
        "import sys, json; from pathlib import Path; from cad.design import load_design;"
        "from cad.pipeline import build_design;"
        f"r = build_design(load_design({str(ROOT / 'designs' / 'hoeken.toml')!r}), Path({str(out)!r}), {{'dxf'}},"
        " fidelity='inertia');"
        "print(json.dumps({'cached': r['cached'], 'cad': sorted(m for m in ('OCP', 'build123d', 'cadquery')"
        " if m in sys.modules)}))"
    )
    first = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert json.loads(first.stdout)["cached"] is False
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert json.loads(r.stdout) == {"cached": True, "cad": []}


def test_a_changed_part_parameter_invalidates_the_cache(built, tmp_path):
    from cad.design import load_design
    from cad.pipeline import build_key

    d = load_design(ROOT / "designs" / "hoeken.toml")
    src = (
        (ROOT / "designs" / "hoeken.toml")
        .read_text()
        .replace("[parts]\n", "[parts]\nbar_thickness_mm = 7.0\n")
    )
    (tmp_path / "h.toml").write_text(src)
    d2 = load_design(tmp_path / "h.toml")
    assert build_key(d, {"dxf"}, "inertia", False, None) != build_key(
        d2, {"dxf"}, "inertia", False, None
    )
    assert build_key(d, {"dxf"}, "inertia", False, None) != build_key(
        d, {"dxf"}, "fabrication", False, None
    )


@pytest.mark.slow
def test_cli_fabrication_build_is_deterministic(tmp_path):
    """Two fresh `hapticad build` runs: every file byte-identical (STEP, STL, DXF, report ...)."""
    outs = []
    for k in ("a", "b"):
        r = run_cli(
            "build", "designs/hoeken.toml", "--out", tmp_path / k, "--no-cache", "--json", cwd=ROOT
        )
        assert r.returncode == 0, r.stderr
        outs.append(json.loads((tmp_path / k / "manifest.json").read_text())["files"])
    assert outs[0] == outs[1]
    names = {f["path"] for f in outs[0]}
    assert {
        "assembly.step",
        "parts/crank.stl",
        "parts/crank.step",
        "parts/crank.dxf",
        "bom.csv",
    } <= names


@pytest.mark.parametrize("design", ["powermouse.toml", "haptic_mouse.toml"])
def test_cli_builds_the_other_families(tmp_path, design):
    """`hapticad build` (human summary, not only --json) works for every buildable family."""
    from cli_helpers import hapticad

    code, out, err = hapticad("build", ROOT / "designs" / design, "--out", tmp_path / "o",
                              "--fidelity", "preview", "--formats", "step,glb")
    assert code == 0, err
    assert "built" in out
    assert (tmp_path / "o" / "report.json").exists()
    assert (tmp_path / "o" / "manifest.json").exists()
    page = (tmp_path / "o" / "report.html").read_text()  # every family has its page
    assert "Bill of materials" in page and "<h2>Checks</h2>" in page
    from viz_checks import check_family_glb

    check_family_glb(tmp_path / "o", ROOT / "designs" / design)  # glb read back, motion checked
