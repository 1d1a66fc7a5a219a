"""Every output of one build states the same device (issue 32 items 1-2).

Builds bundled designs (and variants: a ``[motor]`` table, an encoder count, a catalog
encoder, a process, prices; a seeded random sweep marked ``slow``), then reads the WRITTEN
files back with readers of this module (``csv`` for bom.csv / order.csv, a regex over the C
header's ``#define`` lines, ``json`` for chai3d_device.json / test_vectors.json / report.json,
``xml.etree`` for the MJCF) -- not :mod:`cad.device.readback` -- and compares them with each
other and with independent references:

* the encoder count from the design file (TOML read here): the catalog count of
  ``parts.encoder``, ``parts.encoder_counts_per_rev``, or for a ``[stiffness]`` table
  2 pi |dx/dphi1| / Delta at mid-stroke with dx/dphi1 by central finite differences of the
  coupler point (a second method beside the analytic Jacobian), else the papers' encoders:
  "a general purpose 2000 counts/rev optical encoder" (Hoeken paper §III.A) and "a 1000
  window (4000 cpt) optical encoder" (isotropy paper §3.2);
* the datasheet resolution recomputed from those counts and the finite-difference lever;
* Kt from the datasheet's force-per-ampere row times the lever (Kt / |dx/dphi1|, min over
  the stroke) against HC_KT_NM_PER_A; currents against the ``[motor]`` table / catalog data;
  the peak current as T_peak / Kt (closed form);
* K: eq (25) by hand from the design's ``[stiffness]`` table against the wall sketch, the
  CHAI3D file and the datasheet's eq (25) row; each other K labelled for what it is;
* masses: the BOM's lines summed against report.json; the MJCF bodies against report.json;
* a capstan on the crank (``[transmission]``, issue 35): its ratio n = drum / capstan read from
  the TOML here; the datasheet's force and force per ampere n times the motor's over the lever,
  the resolution 1 / n, the crank's armature and report.json Jm n^2 J_m, the MJCF motor's gear n
  with the motor's own torque range, HC_GEAR = n beside the motor's own Kt.

The two reproducers of ``cases/outputs-agree/encoder-counts-bom-vs-firmware`` and
``cases/reliability3/firmware-ignores-motor-table`` are tests here (their design changes are
written from the bundled hoeken.toml, as their cmd.sh does).
"""

from __future__ import annotations

import csv
import json
import math
import random
import re
import tomllib
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from cad.report import contract
from tests.bundled import buildable

ROOT = Path(__file__).resolve().parents[2]
DESIGNS = ROOT / "designs"
#: Hoeken paper §III.A and isotropy paper §3.2 (module docstring).
FOURBAR_PAPER_COUNTS = 2000
MOUSE_PAPER_COUNTS = 4000
#: maxon HEDL 5540: 500 counts per turn, x4 quadrature (maxon catalog).
HEDL_COUNTS = 2000
#: Finite-difference step of the lever dx/dphi1 (rad): central differences, error ~h^2 ~ 1e-12.
FD_STEP_RAD = 1e-6
#: Relative agreement of a finite-difference figure with the build's analytic one: the FD
#: truncation and round-off (~1e-9 at h = 1e-6 rad) well below it.
FD_REL = 1e-6
#: Numbers written with repr() read back exactly; derived ones (T/Kt in mN m or N m) to ~1 ulp.
EXACT_REL = 1e-12
#: bom.csv prints masses with 2 decimals (g): half a unit per line.
BOM_MASS_ABS_G = 0.005
MOTOR_TABLE = ('\n[motor]\nname = "acme-60"\ntorque_constant_mNm_per_A = 60.0\ncurrent_continuous_A = 1.5\n'
               'torque_continuous_mNm = 90.0\ntorque_peak_mNm = 500.0\nrotor_inertia_g_cm2 = 20.0\n')


# ------------------------------------------------------------------ second readers
def bom_rows(out: Path, name: str = "bom.csv") -> list[dict]:
    with (out / name).open(newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def bom_encoders(out: Path) -> list[tuple[int, int]]:
    """(counts per turn, quantity) of the encoder lines of bom.csv and order.csv."""
    found = []
    for r in bom_rows(out):
        if r["part"] == "encoder":
            found.append((int(re.search(r"(\d+) counts/rev", r["description"]).group(1)), int(r["quantity"])))
    if (out / "order.csv").is_file():
        for r in bom_rows(out, "order.csv"):
            if "encoder" in r["parts"].split():
                found.append((int(re.search(r"(\d+) counts/rev", r["designation"]).group(1)), int(r["quantity"])))
    return found


def defines(text: str) -> dict[str, str]:
    return dict(re.findall(r"^#define (\w+) (.+)$", text, re.M))


def c_real(v: str) -> float:
    return float(re.fullmatch(r"HC_R\((.+)\)", v.strip()).group(1))


def header(out: Path) -> dict:
    d = defines((out / "firmware" / "hapticad_device.h").read_text())

    def one(name):  # None in a header with one value per joint (motors that differ)
        return c_real(d[name]) if name in d else None

    def joints(name):
        return [float(v) for v in re.findall(r"HC_R\(([^)]+)\)", d[name])] if name in d else None

    return {"counts": int(re.match(r"\{\s*(\d+)L", d["HC_ENCODER_DEFAULT"]).group(1)),
            "kt": one("HC_KT_NM_PER_A"), "i_cont": one("HC_CURRENT_CONTINUOUS_A"),
            "i_peak": one("HC_CURRENT_PEAK_A"), "kt_joints": joints("HC_KT_NM_PER_A_JOINTS"),
            "i_cont_joints": joints("HC_CURRENT_CONTINUOUS_A_JOINTS"),
            "i_peak_joints": joints("HC_CURRENT_PEAK_A_JOINTS"),
            "zero": [float(z) for z in re.findall(r"HC_R\(([^)]+)\)", d["HC_ENCODER_DEFAULT"])],
            "motor_comment": re.search(r"/\* motor (\S+):", (out / "firmware" / "hapticad_device.h").read_text())}


def jread(p: Path) -> dict:
    return json.loads(p.read_text())


def ds_row(rep: dict, key: str) -> dict:
    return next(r for r in rep["datasheet"]["rows"] if r["key"] == key)


def mjcf(out: Path) -> ET.Element:
    (p,) = [p for p in out.glob("*.xml") if "<mujoco" in p.read_text()[:400]]
    return ET.parse(p).getroot()


# --------------------------------------------------------------- independent references
def lever_fd(toml: dict, n: int = 401) -> np.ndarray:
    """|dx/dphi1| (m/rad) along the path direction P(min) -> P(max), central finite
    differences of the coupler point (cad.kinematics loop closure) at n crank angles."""
    from cad.design import parse_design
    from cad.kinematics.fourbar import coupler_point_and_jacobian

    d = parse_design(toml)

    def P(phi):
        return coupler_point_and_jacobian(d.linkage, np.asarray(phi))[0] * 1e-3

    ends = P(np.array([d.phi1_min_rad, d.phi1_max_rad]))
    xhat = (ends[1] - ends[0]) / np.linalg.norm(ends[1] - ends[0])
    phi = np.linspace(d.phi1_min_rad, d.phi1_max_rad, n)
    dP = (P(phi + FD_STEP_RAD) - P(phi - FD_STEP_RAD)) / (2 * FD_STEP_RAD)
    return np.abs(dP @ xhat)


def expected_counts(toml: dict) -> int:
    parts, fam = toml.get("parts", {}), toml["mechanism"].get("family", "")
    if "encoder" in parts:
        return {"maxon-hedl5540-500": HEDL_COUNTS, "optical-2000": FOURBAR_PAPER_COUNTS}[parts["encoder"]]
    if "encoder_counts_per_rev" in parts:
        return parts["encoder_counts_per_rev"]
    if "encoder_counts_per_rev" in toml.get("firmware", {}):
        return toml["firmware"]["encoder_counts_per_rev"]
    if fam in ("pantograph", "twin-pantograph", "haptic-pen"):
        return MOUSE_PAPER_COUNTS
    if fam == "delta":  # maxon pairs the HEDL 5540 with the RE 35 (maxon catalog)
        return HEDL_COUNTS
    if "stiffness" in toml:
        J = lever_fd(toml, 3)[1]
        return round(2 * math.pi * J / toml["stiffness"]["encoder_resolution_m"])
    return FOURBAR_PAPER_COUNTS


def eq25_K_max(st: dict) -> float:
    """Hoeken paper eq (25): 2 (Fs + Fv xdot_max) / (Delta + xdot_max Te)."""
    return 2 * (st["Fs_N"] + st["Fv_N_s_per_m"] * st["xdot_max_m_per_s"]) / (
        st["encoder_resolution_m"] + st["xdot_max_m_per_s"] * st["Te_s"])


# ------------------------------------------------------------------------ the builds
FOURBAR_FORMATS = {"firmware", "mjcf"}
FORMATS = {"hoeken": FOURBAR_FORMATS, "pantograph": {"firmware", "mjcf"}, "twin-pantograph": {"firmware", "mjcf"},
           "haptic-pen": {"firmware", "mjcf"}, "powermouse": {"firmware"}, "delta": {"firmware", "mjcf"}}
#: Bundled designs built by default (the rest: slow).
FAST = ("hoeken.toml", "pantograph.toml", "haptic_mouse.toml", "powermouse.toml")
SLOW = tuple(sorted(p.name for p in DESIGNS.glob("*.toml") if p.name not in FAST and buildable(p)))


def _build(toml_text: str, tmp: Path, name: str) -> tuple[dict, Path]:
    from cad.design import load_design
    from cad.pipeline import build_design

    src = tmp / f"{name}.toml"
    src.write_text(toml_text)
    for extra in DESIGNS.glob("*.py"):  # handle scripts named by a bundled design
        (tmp / extra.name).write_text(extra.read_text())
    toml = tomllib.loads(toml_text)
    d = load_design(src)
    fam = toml["mechanism"].get("family", "")
    formats = FORMATS.get(fam, FOURBAR_FORMATS)
    out = tmp / f"out_{name}"
    build_design(d, out, formats, fidelity="preview", use_cache=False)
    return toml, out


class _Builds(dict):
    """``{name: (toml, out)}`` built on first use (a test reads only the builds it names: under
    xdist a worker that runs some of this module's tests makes only theirs)."""

    def __init__(self, make):
        super().__init__()
        self._make = make

    def __missing__(self, name):
        self[name] = self._make(name)
        return self[name]


@pytest.fixture(scope="module")
def builds(tmp_path_factory, shared_build):
    """The bundled FAST designs are the run's shared simulator builds (tests/conftest.py
    ``HOEKEN_SIM_FORMATS``, ``SIM_FORMATS``: preview, a superset of FORMATS, the same builds
    the simulator export tests read); the Hoeken variants are built here."""
    from tests.conftest import HOEKEN_SIM_FORMATS, SIM_FORMATS

    tmp = tmp_path_factory.mktemp("agree")
    hoeken = (DESIGNS / "hoeken.toml").read_text()
    texts = {"hoeken_motor_table": hoeken + MOTOR_TABLE,
             "hoeken_enc4096": hoeken.replace("[parts]\n", "[parts]\nencoder_counts_per_rev = 4096\n"),
             "hoeken_hedl": hoeken.replace("[parts]\n", '[parts]\nencoder = "maxon-hedl5540-500"\n')}
    fmts = {"hoeken.toml": HOEKEN_SIM_FORMATS, **SIM_FORMATS}

    def make(name):
        if name in texts:
            return _build(texts[name], tmp, name)
        toml = tomllib.loads((DESIGNS / name).read_text())
        assert set(fmts[name]) >= FORMATS.get(toml["mechanism"].get("family", ""), FOURBAR_FORMATS)
        return toml, shared_build(name, fmts[name], "preview")[1]

    return _Builds(make)


def report_type(family: str) -> type:
    """The ``TypedDict`` a ``family`` design's report.json keeps to (its package's)."""
    from cad.families import family_package

    rt = family_package(family).report_type
    return rt.resolve() if rt is not None else contract.CommonReport


@pytest.fixture(scope="module")
def capstan_build(shared_build):
    """designs/hoeken_capstan.toml built as the others (its own fixture: issue 35): the run's
    shared preview build with ``FOURBAR_FORMATS`` (tests/conftest.py ``CAPSTAN_FORMATS``, the
    one tests/unit/assembly/test_capstan_fastening_steps.py reads)."""
    from tests.conftest import CAPSTAN_FORMATS

    name = "hoeken_capstan.toml"
    assert set(CAPSTAN_FORMATS[name]) == FOURBAR_FORMATS
    return tomllib.loads((DESIGNS / name).read_text()), shared_build(name, CAPSTAN_FORMATS[name], "preview")[1]


def check_agree(toml: dict, out: Path) -> None:
    """Every cross-file comparison of the module docstring on one build."""
    rep = jread(out / "report.json")
    fam = toml["mechanism"].get("family", "")
    assert contract.problems(rep, report_type(rep["family"])) == []  # the typed report, read back
    dev = rep["device"]
    if fam == "powermouse":  # no encoder: the PowerMouse's flotor is sensed optically
        assert dev["encoders"] == [] and not [r for r in bom_rows(out) if r["part"] == "encoder"]
        return
    n = expected_counts(toml)
    enc = bom_encoders(out)
    assert enc and {c for c, _ in enc} == {n}, enc
    assert {q for _, q in enc} == {len(dev["motors"])}  # one encoder per motor, in bom and order
    assert [e["counts_per_rev"] for e in dev["encoders"]] == [n] * len(dev["motors"])
    res = ds_row(rep, "resolution_um")
    assert re.search(rf"2 pi / {n} counts", res["model"]), res["model"]
    fw = out / "firmware"
    if (fw / "hapticad_device.h").is_file():
        h = header(out)
        assert h["counts"] == n
        assert jread(fw / "chai3d_device.json")["encoder_counts_per_rev"] == n
        assert jread(fw / "test_vectors.json")["encoder"]["counts_per_rev"] == n
        if "wall_stiffness_N_per_m" not in toml.get("firmware", {}):  # one K: the datasheet's eq (25) row
            K_ino = float(defines((fw / "wall_example" / "wall_example.ino").read_text())["WALL_K_N_PER_M"])
            K_chai = _chai3d_K(rep, K_ino)
            assert jread(fw / "chai3d_device.json")["m_maxLinearStiffness"] == pytest.approx(K_chai, rel=EXACT_REL)
            assert ds_row(rep, "eq25_K_max_N_per_m")["value"] == pytest.approx(K_ino, rel=EXACT_REL)
    if "linkage" in toml or fam in ("hoeken", "roberts", "chebyshev", "chebyshev-v", "custom"):
        _check_fourbar(toml, out, rep, n)
    if fam == "delta":
        _check_delta(toml, out, rep, n)
    if fam == "haptic-pen" and (out / "firmware").is_dir():
        _check_pen_motors(out, rep)
    _check_masses(out, rep)


def _check_pen_motors(out: Path, rep: dict) -> None:
    """The pen's header states each joint's motor (RE 40 waists, RE 35 shoulders): the
    constants report.json's device section gives per motor, in its order; the BOM orders
    those motors (2 + 4)."""
    h, mot = header(out), rep["device"]["motors"]
    assert h["kt"] is None and len(h["kt_joints"]) == len(mot) == 6
    for i, m in enumerate(mot):
        c = {k: v["value"] for k, v in m["constants"].items()}
        kt = c["torque_constant_mNm_per_A"] * 1e-3
        assert h["kt_joints"][i] == pytest.approx(kt, rel=EXACT_REL)
        assert h["i_cont_joints"][i] == pytest.approx(c["current_continuous_A"], rel=EXACT_REL)
        assert h["i_peak_joints"][i] == pytest.approx(c["torque_peak_mNm"] * 1e-3 / kt, rel=EXACT_REL)
    with (out / "bom.csv").open(newline="") as f:
        bom = [r for r in csv.DictReader(f) if r["group"] == "motors"]
    ordered = {r["designation"]: int(r["quantity"]) for r in bom}
    assert ordered == {"maxon RE 40": 2, "maxon RE 35": 4}
    assert [m["catalog_key"] for m in mot] == ["maxon-re40", "maxon-re35", "maxon-re35"] * 2


def _ratio(toml: dict) -> float:
    """The crank's transmission ratio the design states: drum / capstan (or ``ratio``), 1 for
    direct drive."""
    t = toml.get("transmission") or {}
    if t.get("kind", "direct") == "direct":
        return 1.0
    return t["ratio"] if "ratio" in t else t["drum_diameter_mm"] / t["capstan_diameter_mm"]


def _motor_data(toml: dict) -> dict:
    """Kt (N m/A), continuous current (A), peak torque (N m), rotor inertia (kg m^2) the
    design states: its [motor] table, else the catalog entry (data, not our computation)."""
    from cad.data.catalog import get_motor

    m = get_motor(toml.get("parts", {}).get("motor", "maxon-re35"))
    t = toml.get("motor", {})
    return {"kt": t.get("torque_constant_mNm_per_A", m.torque_constant_mNm_per_A) * 1e-3,
            "i_cont": t.get("current_continuous_A", m.current_continuous_A),
            "tau_peak": t.get("torque_peak_mNm", m.torque_peak_mNm) * 1e-3,
            "tau_cont": t.get("torque_continuous_mNm", m.torque_continuous_mNm) * 1e-3,
            "Jm": t.get("rotor_inertia_g_cm2", toml.get("parts", {}).get("motor_rotor_inertia_g_cm2",
                                                                        m.rotor_inertia_g_cm2)) * 1e-7}


def _capstan_izz_kg_m2(toml: dict) -> float:
    """The capstan's inertia about the motor shaft from the design's numbers (0: direct drive):
    the grooved steel capstan (catalog steel-1018) of :func:`tests.capstan_ref.grooved_capstan_izz_kg_m2`
    on the motor's shaft."""
    from cad.data.cables import get_cable
    from cad.data.catalog import get_motor
    from cad.data.materials import get_material
    from tests.capstan_ref import grooved_capstan_izz_kg_m2

    t = toml.get("transmission", {})
    if t.get("kind") != "capstan":
        return 0.0
    d = get_cable(t["cable"]).diameter_mm
    bore = get_motor(toml.get("parts", {}).get("motor", "maxon-re35")).shaft_diameter_mm
    return grooved_capstan_izz_kg_m2(t["capstan_diameter_mm"], d, t["wraps"], bore,
                                     get_material("steel-1018").density_kg_m3)


def _check_fourbar(toml: dict, out: Path, rep: dict, n: int) -> None:
    L = lever_fd(toml)
    g = _ratio(toml)
    res = ds_row(rep, "resolution_um")
    assert res["value"] == pytest.approx(2 * math.pi / (n * g) * L.max() * 1e6, rel=FD_REL)
    m = _motor_data(toml)
    fpa = ds_row(rep, "force_per_ampere_N_per_A")  # n Kt / |dx/dphi1|, min over the stroke
    assert fpa["value"] * L.max() == pytest.approx(m["kt"] * g, rel=FD_REL)
    cont = ds_row(rep, "continuous_force_N")  # n T_cont / |dx/dphi1|, min over the stroke
    assert cont["value"] * L.max() == pytest.approx(m["tau_cont"] * g, rel=FD_REL)
    jm = (m["Jm"] + _capstan_izz_kg_m2(toml)) * g * g  # the motor side at the crank
    assert rep["Jm_kg_m2"] == pytest.approx(jm, rel=EXACT_REL)
    assert rep["motor"]["rotor_inertia_g_cm2"] == pytest.approx(m["Jm"] * 1e7, rel=EXACT_REL)
    root = mjcf(out)
    crank = next(j for j in root.iter("joint") if j.get("name") == "crank")
    assert float(crank.get("armature")) == pytest.approx(jm, rel=EXACT_REL)
    (motor,) = list(root.iter("motor"))
    assert float(motor.get("gear")) == g
    assert float(motor.get("forcerange").split()[1]) == pytest.approx(m["tau_peak"], rel=EXACT_REL)
    if (out / "firmware").is_dir():
        h = header(out)
        gear = defines((out / "firmware" / "hapticad_device.h").read_text()).get("HC_GEAR")
        assert gear == (None if g == 1.0 else f"{{ HC_R({g!r}) }}")
        assert h["kt"] == pytest.approx(m["kt"], rel=EXACT_REL)
        assert h["i_cont"] == pytest.approx(m["i_cont"], rel=EXACT_REL)
        assert h["i_peak"] == pytest.approx(m["tau_peak"] / m["kt"], rel=EXACT_REL)
        _check_K(toml, out, rep)
    bodies = {b.get("name"): b for b in root.iter("body")}
    for link in ("crank", "coupler", "rocker"):
        mass = float(bodies[link].find("inertial").get("mass"))
        assert mass == pytest.approx(rep["links"][link]["mass_kg"], rel=EXACT_REL)


def delta_jacobian_fd(toml: dict) -> np.ndarray:
    """dx/dtheta (N, 3, 3) m/rad at the design's workspace grid: central finite differences of
    the delta's forward kinematics (a second path beside the analytic Jacobian)."""
    from cad.design import parse_design
    from cad.kinematics.delta import fk, ik

    d = parse_design(toml)
    th = ik(d.mechanism, d.workspace_points()).theta_rad
    cols = []
    for k in range(3):
        e = np.zeros(3)
        e[k] = FD_STEP_RAD
        cols.append((fk(d.mechanism, th + e).P_mm - fk(d.mechanism, th - e).P_mm) / (2 * FD_STEP_RAD) * 1e-3)
    return np.stack(cols, axis=-1)


def _check_delta(toml: dict, out: Path, rep: dict, n: int) -> None:
    """Resolution and force from finite differences of the FK and the design's motor data;
    the MJCF's armature and force range and the header's motor constants from that data."""
    g = _ratio(toml)  # one [transmission] on every arm: the same n on each
    smax = np.linalg.svd(delta_jacobian_fd(toml), compute_uv=False)[:, 0].max()
    assert ds_row(rep, "resolution_um")["value"] == pytest.approx(smax * 2 * math.pi / (n * g) * 1e6, rel=FD_REL)
    m = _motor_data(toml)
    t_cont = toml.get("motor", {}).get("torque_continuous_mNm")
    if t_cont is not None:
        assert ds_row(rep, "continuous_force_N")["value"] == pytest.approx(g * t_cont * 1e-3 / smax, rel=FD_REL)
    if [p for p in out.glob("*.xml") if "<mujoco" in p.read_text()[:400]]:
        root = mjcf(out)
        for j in ("theta_0", "theta_1", "theta_2"):
            joint = next(x for x in root.iter("joint") if x.get("name") == j)
            assert float(joint.get("armature")) == pytest.approx(g * g * (m["Jm"] + _capstan_izz_kg_m2(toml)),
                                                                  rel=EXACT_REL)
        motors = list(root.iter("motor"))
        assert len(motors) == 3
        for mo in motors:
            assert float(mo.get("forcerange").split()[1]) == pytest.approx(m["tau_peak"], rel=EXACT_REL)
            assert float(mo.get("gear")) == g
    if (out / "firmware").is_dir():
        h = header(out)
        assert h["kt"] == pytest.approx(m["kt"], rel=EXACT_REL)
        assert h["i_cont"] == pytest.approx(m["i_cont"], rel=EXACT_REL)
        assert h["i_peak"] == pytest.approx(m["tau_peak"] / m["kt"], rel=EXACT_REL)


def _chai3d_K(rep: dict, K_eq25: float) -> float:
    """The CHAI3D stiffness: eq (25)'s K_max, with capstans in series with the datasheet's ropes'
    stiffness at the handle (two springs, closed form 1 / (1 / K_max + 1 / K_rope))."""
    keys = {r["key"] for r in rep["datasheet"]["rows"]}
    rope = next((ds_row(rep, k)["value"] for k in ("cable_handle_stiffness_N_per_m",
                                                   "cable_effector_stiffness_N_per_m") if k in keys), None)
    return K_eq25 if rope is None else 1.0 / (1.0 / K_eq25 + 1.0 / rope)


def _check_K(toml: dict, out: Path, rep: dict) -> None:
    fw = out / "firmware"
    ino = (fw / "wall_example" / "wall_example.ino").read_text()
    K_ino = float(defines(ino)["WALL_K_N_PER_M"])
    chai = jread(fw / "chai3d_device.json")
    assert "eq (25) K_max" in chai["notes"]["m_maxLinearStiffness"]
    assert "not the datasheet's simulated K_max" in chai["notes"]["m_maxLinearStiffness"]
    assert "WALL_K_N_PER_M is eq (25)'s K_max" in ino or "wall_stiffness_N_per_m" in toml.get("firmware", {})
    assert "simulated" in ds_row(rep, "K_max_N_per_m")["figure"]
    if "stiffness" in toml:
        st = _stiffness_of_the_encoder(toml)
        # the table's Delta: exact; Delta from the finite-difference lever: FD_REL
        rel = EXACT_REL if st == toml["stiffness"] else FD_REL
        assert K_ino == pytest.approx(eq25_K_max(st), rel=rel)
        assert chai["m_maxLinearStiffness"] == pytest.approx(_chai3d_K(rep, K_ino), rel=EXACT_REL)
        assert ds_row(rep, "eq25_K_max_N_per_m")["value"] == pytest.approx(K_ino, rel=EXACT_REL)
    else:
        assert chai["m_maxLinearStiffness"] == pytest.approx(_chai3d_K(rep, K_ino), rel=EXACT_REL)
    if _chai3d_K(rep, K_ino) != K_ino:  # with ropes, the CHAI3D stiffness is a datasheet row of its own
        rows = [ds_row(rep, k)["value"] for k in ("eq25_K_max_with_cable_N_per_m", "K_max_with_cable_N_per_m")
                if k in {r["key"] for r in rep["datasheet"]["rows"]}]
        assert any(v == pytest.approx(chai["m_maxLinearStiffness"], rel=EXACT_REL) for v in rows), rows


def _stiffness_of_the_encoder(toml: dict) -> dict:
    """The [stiffness] table with eq (25)'s Delta the step of the encoder the design orders:
    the table's own Delta when it rounds to that encoder's count at mid-stroke (finite
    differences of the coupler point), else 2 pi |dx/dphi1| / counts."""
    st = dict(toml["stiffness"])
    J = lever_fd(toml, 3)[1]
    counts = expected_counts(toml)
    if round(2 * math.pi * J / st["encoder_resolution_m"]) != counts:
        st["encoder_resolution_m"] = 2 * math.pi * J / counts
    return st


def _check_masses(out: Path, rep: dict) -> None:
    """BOM lines summed = report.json total; every MJCF body's mass = report.json's body
    (four-bars: ``links``, the 5-bars: ``bodies``)."""
    rows = bom_rows(out)
    total = sum(float(r["mass_g"]) * int(r["quantity"]) for r in rows)
    assert total == pytest.approx(rep["total_mass_g"], abs=BOM_MASS_ABS_G * sum(int(r["quantity"]) for r in rows))
    if not [p for p in out.glob("*.xml") if "<mujoco" in p.read_text()[:400]]:
        return
    bodies = rep.get("links") if isinstance(rep.get("links"), dict) else rep["bodies"]
    seen = 0
    for b in mjcf(out).iter("body"):
        if b.get("name") in bodies and isinstance(bodies[b.get("name")], dict):
            assert float(b.find("inertial").get("mass")) == pytest.approx(bodies[b.get("name")]["mass_kg"],
                                                                          rel=EXACT_REL)
            seen += 1
    assert seen >= 3


@pytest.mark.parametrize("name", [*FAST, "hoeken_motor_table", "hoeken_enc4096", "hoeken_hedl"])
def test_outputs_agree(builds, name):
    toml, out = builds[name]
    check_agree(toml, out)


def test_outputs_agree_with_a_capstan(capstan_build):
    check_agree(*capstan_build)


def test_the_capstan_hoeken_meets_every_limit_and_states_its_rope(builds, capstan_build):
    """designs/hoeken_capstan.toml (issue 35): the Hoeken's solids with a capstan on the crank.
    Against the direct Hoeken's build, H11 gains the reflected rotor, (n^2 - 1) J_m, the
    capstan turning with it, n^2 J_capstan, and the
    drum sector with its anchor screw and tensioner on the crank (the sector m (r_o^2 + r_i^2) / 2
    about A1 in closed form, the rim's hardware bounded by its radii) and the crank's axle;
    H12..H33 are unchanged; every
    datasheet verdict is met (continuous force >= 5 N); the rope's cut
    length is the same number in the datasheet, bom.csv and order.csv; report.json ``device``
    states the ratio and the rope with its source."""
    toml, out = capstan_build
    _, out_d = builds["hoeken.toml"]
    rep, rep_d = jread(out / "report.json"), jread(out_d / "report.json")
    g, m = _ratio(toml), _motor_data(toml)
    r_o, r_i = 31.6, 10.0  # the drum's rim (64 mm pitch - 0.8 mm rope) and bore (the hub), mm
    m_drum = rep["part_masses_g"]["capstan_drum"] * 1e-3
    I_drum = 0.5 * m_drum * (r_o ** 2 + r_i ** 2) * 1e-6  # holes: 0.4 % of the mass, bounded below
    # on the rim: the anchor screw (radial M3 x 8, head out), the tensioner's screw (its head
    # 4.8 mm out, on its lock nut) and nut, each between 8 mm inside the rim and its head's top
    m_rim = sum(rep["part_masses_g"][k] for k in ("capstan_anchor_screw", "capstan_tensioner_screw",
                                                   "capstan_tensioner_nut")) * 1e-3
    m_ax = rep["part_masses_g"]["crank_axle"] * 1e-3  # the crank's own axle at A1, 6 mm: m r^2 / 2
    gain = rep["H11_kg_m2"] - rep_d["H11_kg_m2"] - (g * g - 1) * m["Jm"] - g * g * _capstan_izz_kg_m2(toml)
    assert I_drum * 0.995 + m_rim * ((r_o - 8) * 1e-3) ** 2 < gain
    assert gain < I_drum + m_rim * ((r_o + 4.8 + 3) * 1e-3) ** 2 + 0.5 * m_ax * (3e-3) ** 2
    for k in ("H12_kg_m2", "H22_kg_m2", "H33_kg_m2"):
        assert rep[k] == rep_d[k]
    assert rep["datasheet"]["warnings"] == [] and rep["datasheet"]["ok"]
    assert ds_row(rep, "continuous_force_N")["value"] >= toml["mechanism"]["force_N"]
    judged = [r for r in rep["datasheet"]["rows"] if r["limit"] is not None]
    assert {r["key"] for r in judged} >= {"continuous_force_N", "first_mode_Hz", "bend_ratio",
                                          "cable_slip_margin", "cable_safety_factor", "drum_sector_deg"}
    assert all(r["verdict"] == "ok" for r in judged), [(r["key"], r["verdict"]) for r in judged]
    cut = f"{ds_row(rep, 'cable_cut_length_mm')['value']:.0f}"
    (rope,) = [r for r in bom_rows(out) if r["part"] == "capstan_cable"]
    assert f"cut length {cut} mm" in rope["description"]
    assert [o["designation"] for o in bom_rows(out, "order.csv") if o["parts"] == "capstan_cable"] == [
        f"wire rope 7x7 0.8 mm x {cut} mm"]
    t = rep["device"]["transmissions"][0]
    assert (t["kind"], t["ratio"], t["cable"]["key"]) == ("capstan", g, toml["transmission"]["cable"])
    assert t["cable"]["min_breaking_load_N"]["source"]


def test_the_capstan_page_states_the_builds_figures(builds, capstan_build):
    """docs/capstan.md's worked example (typed numbers, tests/docs/typed_numbers.json): the
    figures of the capstan Hoeken's datasheet and the direct Hoeken's M11 as this module's
    builds give them, at the digits the page types."""
    text = (ROOT / "docs" / "capstan.md").read_text(encoding="utf-8")
    rep = jread(capstan_build[1] / "report.json")
    rep_d = jread(builds["hoeken.toml"][1] / "report.json")
    m, md = ds_row(rep, "M11_g"), ds_row(rep_d, "M11_g")
    for typed in (f"{ds_row(rep, 'continuous_force_N')['value']:.2f} N",
                  f"{ds_row(rep, 'friction_N')['value']:.3f} N",
                  f"{ds_row(rep, 'resolution_um')['value']:.1f} µm",
                  f"{md['min']:.0f}–{md['max']:.0f} g to {m['min']:.0f}–{m['max']:.0f} g",
                  f"first mode ({ds_row(rep, 'first_mode_Hz')['value']:.0f} Hz",
                  f"k_q = {ds_row(rep, 'cable_stiffness_Nm_per_rad')['value']:.0f} N·m/rad",
                  f"{ds_row(rep, 'cable_handle_stiffness_N_per_m')['value'] / 1e3:.0f} kN/m at the handle",
                  f"from {ds_row(rep_d, 'compliance_x_um_per_N')['value']:.2f} to "
                  f"{ds_row(rep, 'compliance_x_um_per_N')['value']:.2f} µm/N",
                  f"links rigid, is\n{ds_row(rep, 'cable_mode_Hz')['value']:.0f} Hz",
                  f"`m_maxLinearStiffness`, {ds_row(rep, 'eq25_K_max_with_cable_N_per_m')['value']:.0f} N/m"):
        assert typed in text, typed


def test_encoder_counts_bom_vs_firmware(builds):
    """Reproducer outputs-agree/encoder-counts-bom-vs-firmware: with the BOM's encoder fitted,
    the firmware's crank angle from the counts is the real crank angle to one count over the
    whole range 132..216 deg (was: 2000 compiled for a 3837 encoder, 11 mm off, 6 poses refused)."""
    for name, n in (("hoeken.toml", 3837), ("hoeken_enc4096", 4096), ("hoeken_hedl", HEDL_COUNTS)):
        toml, out = builds[name]
        assert bom_encoders(out)[0][0] == n
        h = header(out)
        assert h["counts"] == n
        zero = h["zero"][0]
        d = defines((out / "firmware" / "hapticad_device.c").read_text())  # the range constants
        lo, hi = c_real(d["Q_MIN"]) - c_real(d["Q_SLACK"]), c_real(d["Q_MAX"]) + c_real(d["Q_SLACK"])
        for deg in np.linspace(132.0, 216.0, 13):
            counts = math.floor((math.radians(deg) - zero) / (2 * math.pi) * n + 0.5)  # nearest count
            q_fw = zero + 2 * math.pi * counts / n
            assert abs(q_fw - math.radians(deg)) <= math.pi / n + 1e-12
            assert lo <= q_fw <= hi, (deg, counts)  # hc_forward's range test: no pose of the range refused


def test_firmware_takes_the_motor_table(builds):
    """Reproducer reliability3/firmware-ignores-motor-table: HC_KT_NM_PER_A = 0.06,
    HC_CURRENT_CONTINUOUS_A = 1.5 as the [motor] table says; report.json names acme-60."""
    _, out = builds["hoeken_motor_table"]
    h = header(out)
    assert (h["kt"], h["i_cont"]) == (0.06, 1.5)
    assert h["i_peak"] == pytest.approx(500.0 / 60.0, rel=EXACT_REL)
    assert h["motor_comment"].group(1) == "acme-60"
    rep = jread(out / "report.json")
    assert rep["motor"]["name"] == "acme-60"
    assert rep["device"]["motors"][0]["name"] == "acme-60"
    assert rep["Jm_kg_m2"] == pytest.approx(20.0e-7, rel=EXACT_REL)


def test_two_encoder_fields_that_disagree_are_refused(tmp_path):
    from cad.design import load_design
    from cad.device import resolve_device
    from cad.errors import DesignError

    text = (DESIGNS / "hoeken.toml").read_text().replace("[parts]\n", "[parts]\nencoder_counts_per_rev = 4096\n")
    p = tmp_path / "d.toml"
    p.write_text(text + "\n[firmware]\nencoder_counts_per_rev = 2000\n")
    with pytest.raises(DesignError) as e:
        resolve_device(load_design(p))
    msg = str(e.value)
    assert "\n" not in msg and "parts.encoder_counts_per_rev" in msg and "firmware.encoder_counts_per_rev" in msg
    assert "4096" in msg and "2000" in msg
    p.write_text(text + "\n[firmware]\nencoder_counts_per_rev = 4096\n")  # the same count twice: one encoder
    assert resolve_device(load_design(p)).encoder.counts_per_rev == 4096


def test_the_cli_refuses_disagreeing_encoder_fields_before_building(tmp_path):
    from cli_helpers import assert_one_line_error, hapticad

    p = tmp_path / "d.toml"
    p.write_text((DESIGNS / "hoeken.toml").read_text().replace('[parts]\n', '[parts]\nencoder = "maxon-hedl5540-500"\n')
                 + "\n[firmware]\nencoder_counts_per_rev = 4096\n")
    code, _, err = hapticad("build", p, "--out", tmp_path / "o", "--fidelity", "preview", "--formats", "firmware")
    assert_one_line_error(code, err, "parts.encoder", "firmware.encoder_counts_per_rev", "2000", "4096")
    assert not (tmp_path / "o").exists()


def _corrupt_header(monkeypatch):
    from cad.firmware import csrc

    real = csrc.header
    monkeypatch.setattr(csrc, "header", lambda spec: re.sub(r"\{ \d+L,", "{ 2000L,", real(spec)))
    return "firmware/hapticad_device.h", "HC_ENCODER_DEFAULT"


def _corrupt_bom(monkeypatch):
    from cad.families.fourbar import build

    real = build.encoder_bom_row

    def row(design):
        r = dict(real(design))
        r["description"] = r["description"].replace("3837 counts/rev", "2000 counts/rev")
        return r

    monkeypatch.setattr(build, "encoder_bom_row", row)
    return "bom.csv", "encoder counts/rev"


@pytest.mark.parametrize("corrupt", [_corrupt_header, _corrupt_bom])
def test_a_build_whose_files_disagree_is_not_published(tmp_path, monkeypatch, corrupt):
    """A writer corrupted (the header compiled for, or the BOM ordering, 2000 counts whatever
    the device): the build reads its files back, refuses with one line naming the file, the
    fact and both values, and publishes nothing."""
    from cad.design import load_design
    from cad.device.readback import OutputsDisagree
    from cad.pipeline import build_design

    file, fact = corrupt(monkeypatch)
    out = tmp_path / "out"
    with pytest.raises(OutputsDisagree) as e:
        build_design(load_design(DESIGNS / "hoeken.toml"), out, {"firmware"}, fidelity="preview", use_cache=False)
    msg = str(e.value)
    assert "\n" not in msg
    assert msg.startswith(f"outputs disagree, nothing published: {file}: {fact}")
    assert "2000" in msg and "3837" in msg
    assert not out.exists()


# ------------------------------------------------------------ the slow, larger sweep
def _random_fourbar(rng: random.Random, bases=("hoeken.toml", "hoeken_printed.toml")) -> str:
    text = (DESIGNS / rng.choice(bases)).read_text()
    kt = rng.uniform(20.0, 80.0)
    cont = rng.uniform(50.0, 200.0)
    table = (f'\n[motor]\nname = "rand-{rng.randrange(1000)}"\ntorque_constant_mNm_per_A = {kt!r}\n'
             f"current_continuous_A = {cont / kt!r}\ntorque_continuous_mNm = {cont!r}\n"  # T_N = Kt I_N
             f"torque_peak_mNm = {cont * rng.uniform(2.0, 10.0)!r}\nrotor_inertia_g_cm2 = {rng.uniform(5.0, 150.0)!r}\n")
    enc = rng.choice(['encoder = "maxon-hedl5540-500"\n', f"encoder_counts_per_rev = {rng.randrange(500, 20000)}\n"])
    text = text.replace("[parts]\n", "[parts]\n" + enc, 1) + table
    if rng.random() < 0.5:
        text += f'\n[prices]\n"618/8 (8x16x4)" = {rng.uniform(1, 20):.2f}\n'
    return text


def _random_mouse(rng: random.Random, fn: str) -> str:
    return (DESIGNS / fn).read_text() + f"\n[firmware]\nencoder_counts_per_rev = {rng.randrange(500, 20000)}\n"


@pytest.mark.parametrize("seed", [101, 102])
def test_outputs_agree_one_random_variant_per_family(tmp_path, seed):
    """Default-suite share of the random sweep below: a seeded [motor] table, encoder and
    prices on the bundled Hoeken (same solids: cheap), a seeded [firmware] encoder count on
    the bundled pantograph."""
    rng = random.Random(seed)
    text = _random_fourbar(rng, ("hoeken.toml",)) if seed % 2 else _random_mouse(rng, "pantograph.toml")
    toml, out = _build(text, tmp_path, f"r{seed}")
    check_agree(toml, out)


@pytest.mark.slow
@pytest.mark.parametrize("name", SLOW)
def test_outputs_agree_every_bundled_design(tmp_path, monkeypatch, name):
    monkeypatch.setenv("HAPTICAD_ALLOW_SCRIPTS", "1")  # hoeken_cq_handle.toml runs its bundled handle script
    toml, out = _build((DESIGNS / name).read_text(), tmp_path, Path(name).stem)
    check_agree(toml, out)


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(6))
def test_outputs_agree_random_variants(tmp_path, seed):
    rng = random.Random(seed)
    text = _random_fourbar(rng) if seed % 2 == 0 else _random_mouse(rng, rng.choice(["pantograph.toml",
                                                                                     "haptic_mouse.toml"]))
    toml, out = _build(text, tmp_path, f"v{seed}")
    check_agree(toml, out)


@pytest.mark.slow  # a delta build (every pair of solids at 125 points); cheap share:
# tests/families/delta/test_delta_device.py, test_delta_firmware.py, test_delta_sim.py
def test_outputs_agree_delta_with_motor_table_and_encoder(tmp_path):
    """The delta with a [motor] table, another catalog motor and an encoder count: BOM,
    datasheet, firmware header, CHAI3D file, test vectors and MJCF state the same device."""
    bundled = (DESIGNS / "delta.toml").read_text()  # its [parts] and [motor] are the RE 40's: swap
    text = (re.sub(r"^\[(parts|motor)\]\n[^\[]*", "", bundled, flags=re.M)
            + '\n[parts]\nmotor = "maxon-re35"\nencoder_counts_per_rev = 4096\n' + MOTOR_TABLE)
    toml, out = _build(text, tmp_path, "delta_variant")
    assert expected_counts(toml) == 4096
    check_agree(toml, out)
