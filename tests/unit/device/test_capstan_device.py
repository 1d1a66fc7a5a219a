"""A capstan on the four-bar's crank (issue 35), without CAD: the ``[transmission]`` table in
the design, the resolved device, the capstan's datasheet rows and limits, its BOM lines and
the MJCF motor, each against a hand formula written here:

* ratio n = drum / capstan; joint torque n tau_m (RE 35 catalog: 97.2 mN m continuous,
  972.5 mN m peak, Kt 38.9 mN m/A, J_m 79.2 g cm^2); counts per crank turn n counts;
* rope load dT = tau_peak / r_c (the same as n tau_peak / r_d, written the other way);
  pretension (dT / 2)(e + 1)/(e - 1) with e = exp(mu 2 pi wraps); safety factor MBL / (T0 + dT/2);
* free run L = sqrt(C^2 - (r_d - r_c)^2) with C = r_d + r_c + gap; cut length pi d_c wraps + 2 L
  + pi d_d sector / 360 + 2 tails; sector = range + 2 (2 L_a / d_d) in degrees;
* two runs of stiffness EA / L each, both pulling at r_d: k_q = 2 (EA / L) r_d^2 (two springs in
  parallel); in series at the handle with K: 1 / (1/K + Jx^2 / k_q); in the structure's frame
  the handle's compliance gains Jx^2 / k_q (Jx by central finite differences);
* the crank's mode on the rope sqrt(k_q / D) / 2 pi with D(phi1) from Hoeken paper eq (14),
  its velocity ratios a2, a3 by central finite differences of the loop closure.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from cad.design import load_design
from cad.errors import DesignError

ROOT = Path(__file__).resolve().parents[3]
CAPSTAN = ROOT / "designs" / "hoeken_capstan.toml"
#: maxon RE 35 catalog values of cad.data.catalog (the catalog's own sources).
TC_NM, TP_NM, KT, JM = 97.2e-3, 972.5e-3, 38.9e-3, 79.2e-7
MU = 0.12  # Tribology Handbook B12, wire rope on steel (the value cad.actuators.capstan states)
#: 480 lbf (1/16 in 7x7, the catalog's source) x 4.448222 N/lbf x (0.8 / 1.5875)^2
MBL_08_N = 480 * 4.448222 * (0.8 / 1.5875) ** 2
#: Loos & Co's stretch formula (E% = W G / D^2, G = 0.0000120 for 7x7 stainless, D in inches):
#: EA = 100 D^2 / G lbf for the 0.8 mm rope, in N.
EA_08_N = 100 * (0.8 / 25.4) ** 2 / 0.0000120 * 4.448222


#: the Hoeken paper's CAD coefficients (§III.B.2) as a report's H, its rotor n^2 J_m (n = 2) in H11
PAPER_H = {"H11": 2.97e-5, "H12": 3.22e-5, "H22": 1.17e-4, "H33": 7.09e-5, "beta2": 0.0}
PAPER_REPORT = {"H11_kg_m2": PAPER_H["H11"] + 4 * JM, "H12_kg_m2": PAPER_H["H12"],
                "H22_kg_m2": PAPER_H["H22"], "H33_kg_m2": PAPER_H["H33"], "beta2_deg": 0.0,
                "Jm_kg_m2": 4 * JM}


def _design(tmp_path: Path, table: str, name: str = "cap") -> object:
    p = tmp_path / f"{name}.toml"
    p.write_text(f'name = "{name}"\n[mechanism]\nfamily = "hoeken"\nforce_N = 5.0\n'
                 f"[transmission]\n{table}\n[parts]\n")
    return load_design(p)


def test_bundled_capstan_design_resolves_its_transmission_once():
    from cad.device import resolve_device

    d = load_design(CAPSTAN)
    dev = resolve_device(d)
    t = dev.transmission("crank")
    assert (t.kind, t.ratio, t.capstan_diameter_mm, t.drum_diameter_mm) == ("capstan", 64 / 32, 32.0, 64.0)
    assert t.cable.key == "steel-7x7-0.8" and t.cable_diameter_mm == 0.8 and t.wraps == 3.0
    j = dev.joint_motor("crank")
    assert j.torque_continuous_mNm == pytest.approx(2 * 97.2, rel=1e-15)
    assert j.torque_peak_mNm == pytest.approx(2 * 972.5, rel=1e-15)
    assert j.torque_constant_mNm_per_A == pytest.approx(2 * 38.9, rel=1e-15)
    assert j.current_continuous_A == dev.motor.spec.current_continuous_A  # currents unchanged
    assert "x n (capstan, n = 2)" in j.source_of("torque_continuous_mNm")
    # n^2 (J_m + J_capstan): the capstan grooved steel (7870 kg/m^3, catalog steel-1018) from the
    # RE 35's 6 mm shaft to its crests, 3 turns of the 0.8 mm rope (tests/capstan_ref.py)
    from tests.capstan_ref import grooved_capstan_izz_kg_m2

    assert dev.joint_rotor_inertia_kg_m2("crank") == pytest.approx(
        4 * (JM + grooved_capstan_izz_kg_m2(32.0, 0.8, 3.0, 6.0, 7870.0)), rel=1e-9)
    assert dev.joint_counts_per_rev("crank") == 2 * dev.encoder.counts_per_rev
    rec = dev.as_dict()["transmissions"][0]
    assert rec["cable"]["min_breaking_load_N"]["unverified"] is True
    assert "480 lbf" in rec["cable"]["min_breaking_load_N"]["source"]
    assert rec["cable"]["axial_stiffness_EA_N"]["value"] == pytest.approx(EA_08_N, rel=1e-12)
    assert "unverified" not in rec["cable"]["axial_stiffness_EA_N"]
    assert t.cable_EA_N == pytest.approx(EA_08_N, rel=1e-12) and "strandcore.com" in rec["cable_EA_source"]


def test_direct_drive_device_record_is_unchanged():
    """A design without [transmission]: the record report.json has always carried."""
    from cad.device import resolve_device

    dev = resolve_device(load_design(ROOT / "designs" / "hoeken.toml"))
    assert dev.as_dict()["transmissions"] == [{
        "motor_joint": "crank", "kind": "direct", "ratio": 1.0, "cable_diameter_mm": None,
        "drum_diameter_mm": None, "capstan_diameter_mm": None,
        "source": "direct drive: the motor shaft is the joint (Hoeken paper §III.A; isotropy paper §3.2)"}]
    assert dev.joint_motor("crank") is dev.motor.spec


@pytest.mark.parametrize(("table", "field"), [
    ('kind = "capstan"\ncapstan_diameter_mm = 20.0\nratio = 3.0\ncable = "steel-7x7-0.45"\nwraps = 0.1', "transmission.wraps"),
    ('kind = "capstan"\ncapstan_diameter_mm = 20.0\nratio = 3.0\ncable = "steel-7x7-0.45"\npretension_N = -4', "transmission.pretension_N"),
    ('kind = "capstan"\ncapstan_diameter_mm = 20.0\nratio = 3.0\ncable = "rope"', "transmission.cable"),
    ('kind = "direct"\nwraps = 3.0', "transmission.wraps"),
    ('kind = "capstan"\ncapstan_diameter_mm = 20.0\nratio = 3.0\ncable = "steel-7x7-0.45"\nspeed = 1', "transmission.speed"),
])
def test_bad_transmission_table_names_the_field(tmp_path, table, field):
    with pytest.raises(DesignError) as e:
        _design(tmp_path, table)
    assert e.value.field == field and "\n" not in str(e.value)


def test_cli_refuses_a_bad_transmission_in_one_line(tmp_path):
    import subprocess
    import sys

    p = tmp_path / "bad.toml"
    p.write_text('name = "bad"\n[mechanism]\nfamily = "hoeken"\n[transmission]\nkind = "capstan"\n'
                 'capstan_diameter_mm = 20.0\nratio = 0.5\ncable = "steel-7x7-0.45"\n')
    r = subprocess.run([sys.executable, "-m", "cad", "check", str(p)], capture_output=True, text=True,
                       timeout=120, cwd=ROOT)
    assert r.returncode == 2, r.stderr
    lines = [s for s in r.stderr.splitlines() if s.strip()]
    assert len(lines) == 1 and "transmission.ratio" in lines[0] and "Traceback" not in r.stderr


def test_woodenhaptics_joint_warns_at_load_naming_rope_ratio_and_fix(tmp_path):
    """WoodenHaptics: 10 mm capstan, 0.54 mm 7x7 rope, 120 mm drum (issue 35): D/d = 18.5 < 40."""
    from cad.design.bounds import collected, reset

    reset()
    _design(tmp_path, 'kind = "capstan"\ncapstan_diameter_mm = 10.0\ndrum_diameter_mm = 120.0\n'
                      'cable = "steel-7x7-0.54"')
    w = [x for x in collected() if x.startswith("transmission: cable")]
    assert len(w) == 1
    assert "steel-7x7-0.54" in w[0] and f"D/d = {10 / 0.54:.1f}" in w[0]
    assert f"at least {40 * 0.54:.1f} mm" in w[0]
    assert not any("not drawn" in x for x in collected())  # every capstan part is a solid


def test_capstan_rows_against_hand_formulas():
    from cad.families.fourbar import capstan as fc
    from cad.families.fourbar.datasheet import lever

    d = load_design(CAPSTAN)
    phi, Jx, *_ = lever(d)
    rows, limits = fc.datasheet_rows(d, PAPER_REPORT, phi, Jx)
    v = {r["key"]: r["value"] for r in rows}
    dT = TP_NM / 0.016  # tau_peak / r_c
    e = math.exp(MU * 2 * math.pi * 3)
    T0 = dT / 2 * (e + 1) / (e - 1)
    assert v["transmission_ratio"] == 2.0
    assert v["reflected_rotor_inertia_g_cm2"] == pytest.approx(4 * 79.2, rel=1e-12)
    assert v["bend_ratio"] == pytest.approx(32 / 0.8, rel=1e-15)
    assert v["cable_pretension_N"] == pytest.approx(T0, rel=1e-12)
    assert v["cable_slip_margin"] == pytest.approx(1.0, rel=1e-9)
    assert v["cable_safety_factor"] == pytest.approx(MBL_08_N / (T0 + dT / 2), rel=1e-12)
    rng = 216 - 132  # Hoeken paper Fig. 2: crank 132..216 deg
    sector = rng + 2 * math.degrees(2 * 10 / 64)
    assert v["drum_sector_deg"] == pytest.approx(sector, rel=1e-9)
    L = math.sqrt(85 ** 2 - (32 - 16) ** 2)  # the design's transmission.centre_distance_mm
    cut = math.pi * 32 * 3 + 2 * L + math.pi * 64 * sector / 360 + 2 * 20
    assert v["cable_cut_length_mm"] == pytest.approx(cut, rel=1e-9)
    assert v["cable_stiffness_Nm_per_rad"] == pytest.approx(2 * EA_08_N / (L * 1e-3) * 0.032 ** 2, rel=1e-12)
    assert {k: limits[k].value for k in limits} == {"bend_ratio": 40.0, "cable_slip_margin": 1.0,
                                                     "cable_safety_factor": 5.0, "drum_sector_deg": 360.0}
    from cad.datasheet import judge

    assert judge(rows, limits) == []  # every capstan verdict of the bundled design is met


def test_rope_below_its_bend_ratio_misses_with_a_warning_line(tmp_path):
    from cad.datasheet import judge
    from cad.families.fourbar import capstan as fc
    from cad.families.fourbar.datasheet import lever

    d = _design(tmp_path, 'kind = "capstan"\ncapstan_diameter_mm = 10.0\ndrum_diameter_mm = 120.0\n'
                          'cable = "steel-7x7-0.54"')
    phi, Jx, *_ = lever(d)
    rows, limits = fc.datasheet_rows(d, PAPER_REPORT, phi, Jx)
    w = judge(rows, limits)
    assert any(x.startswith("bend ratio D/d of steel-7x7-0.54 on the capstan = 18.52") and
               "transmission.capstan_diameter_mm" in x for x in w), w
    # 0.9725 N m over r_c = 5 mm: dT = 194.5 N; MBL 480 lbf (0.54/1.5875)^2 = 247 N: SF < 5
    assert any(x.startswith("rope safety factor") for x in w), w


def _D_links(design, H: dict, phi: np.ndarray) -> np.ndarray:
    """Hoeken paper eq (14) without the rotor, a2 = dphi2/dphi1, a3 = dphi3/dphi1 by central
    finite differences of the loop closure."""
    from cad.kinematics.fourbar import solve

    h = 1e-6
    p0, pp, pm = (solve(design.linkage, phi + s) for s in (0.0, h, -h))
    a2 = (pp.phi2_rad - pm.phi2_rad) / (2 * h)
    a3 = (pp.phi3_rad - pm.phi3_rad) / (2 * h)
    return (H["H11"] + 2 * H["H12"] * np.cos(phi - p0.phi2_rad - H["beta2"]) * a2
            + H["H22"] * a2 ** 2 + H["H33"] * a3 ** 2)


def test_rope_spring_against_two_spring_closed_forms(tmp_path):
    from cad.families.fourbar import capstan as fc
    from cad.families.fourbar.datasheet import lever

    EA = 20000.0
    d = _design(tmp_path, 'kind = "capstan"\ncapstan_diameter_mm = 32.0\ndrum_diameter_mm = 64.0\n'
                          f'cable = "steel-7x7-0.8"\ncable_EA_N = {EA}')
    phi, Jx, *_ = lever(d)
    H = PAPER_H
    rows, _ = fc.datasheet_rows(d, PAPER_REPORT, phi, Jx, K_max_N_per_m=1.0e5)
    v = {r["key"]: r["value"] for r in rows}
    L = math.sqrt(50 ** 2 - 16 ** 2) * 1e-3
    k_run = EA / L  # one run in tension, N/m
    k_q = 2 * k_run * 0.032 ** 2  # two runs in parallel, each at r_d
    assert v["cable_stiffness_Nm_per_rad"] == pytest.approx(k_q, rel=1e-12)
    J2 = np.asarray(Jx) ** 2
    assert v["cable_handle_stiffness_N_per_m"] == pytest.approx((k_q / J2).min(), rel=1e-12)
    assert v["K_max_with_cable_N_per_m"] == pytest.approx(1 / (1 / 1e5 + J2.max() / k_q), rel=1e-12)
    f_c = math.sqrt(k_q / _D_links(d, H, np.asarray(phi)).max()) / (2 * math.pi)
    assert v["cable_mode_Hz"] == pytest.approx(f_c, rel=1e-6)  # FD a2, a3: ~1e-9


def test_frame_holds_the_crank_through_the_rope(tmp_path):
    """The structure's frame with the rope at A1: the handle compliance along the path is the
    crank-held frame's plus Jx^2 / k_q (a spring in series through the lever: the reaction
    moment at A1 is Jx F by virtual work), at each pose: between the catalog rope (EA from
    Loos & Co's formula, 85 mm centres) and a softer one (EA 20 kN, 50 mm centres) the handle's
    compliance differs by Jx^2 (1/k_soft - 1/k_stiff); no mode rises, one drops."""
    from cad.families.fourbar.pose import planar_transforms
    from cad.kinematics.metrics import path_frame
    from cad.structure import device as sd

    held = load_design(CAPSTAN)
    rope = _design(tmp_path, 'kind = "capstan"\ncapstan_diameter_mm = 32.0\ndrum_diameter_mm = 64.0\n'
                             'cable = "steel-7x7-0.8"\ncable_EA_N = 20000.0')
    k_held = sd.crank_rope_stiffness_Nm_per_rad(held)
    assert k_held == pytest.approx(2 * EA_08_N / (math.sqrt(85 ** 2 - 16 ** 2) * 1e-3) * 0.032 ** 2, rel=1e-12)
    k_q = sd.crank_rope_stiffness_Nm_per_rad(rope)
    assert k_q == pytest.approx(2 * 20000.0 / (math.sqrt(50 ** 2 - 16 ** 2) * 1e-3) * 0.032 ** 2, rel=1e-12)
    fb = held.linkage
    ex = path_frame(fb, held.phi1_min_rad, held.phi1_max_rad).x_hat
    phis = np.linspace(held.phi1_min_rad, held.phi1_max_rad, 3)
    tfs = planar_transforms(fb, phis)
    h = 1e-6
    for i, phi in enumerate(phis):
        c, f1 = [], []
        for d in (held, rope):
            fr, P = sd.build_frame(d, {k: v[i] for k, v in tfs.items()}, [], {}, "beam")
            u = fr.solve({P: np.r_[ex[0], ex[1], 0, 0, 0, 0]})
            c.append(float(u[6 * P:6 * P + 2] @ ex))
            f1.append(fr.modes_Hz(6))
        from cad.kinematics.fourbar import coupler_point_and_jacobian

        Pp, Pm = (coupler_point_and_jacobian(fb, np.array([phi + s]))[0][0] * 1e-3 for s in (h, -h))
        Jx = float((Pp - Pm) @ ex / (2 * h))
        assert c[1] - c[0] == pytest.approx(Jx * Jx * (1 / k_q - 1 / k_held), rel=1e-6)
        # a softer support lowers every mode (Rayleigh), at least one of them visibly
        assert np.all(f1[1] <= f1[0] * (1 + 1e-9)) and np.any(f1[1] < 0.99 * f1[0]), (f1[0], f1[1])


def test_bom_lines_of_the_capstan():
    from cad.families.fourbar import capstan as fc

    d = load_design(CAPSTAN)
    rows = {r["part"]: r for r in fc.bom_lines(d)}
    # the drum, the capstan, the anchor and the tensioner are solids: their lines come from them
    assert set(rows) == {"capstan_cable"}
    L = math.sqrt(85 ** 2 - 16 ** 2)  # the design's transmission.centre_distance_mm
    sector = 84 + 2 * math.degrees(20 / 64)
    cut = math.pi * 32 * 3 + 2 * L + math.pi * 64 * sector / 360 + 40
    assert f"cut length {cut:.0f} mm" in rows["capstan_cable"]["description"]
    assert rows["capstan_cable"]["designation"] == f"wire rope 7x7 0.8 mm x {cut:.0f} mm"
    assert "unverified" in rows["capstan_cable"]["description"]
    assert fc.bom_lines(load_design(ROOT / "designs" / "hoeken.toml")) == []


def test_mjcf_motor_gear_and_the_reader_take_the_ratio():
    from cad.device.readback import mjcf_motors
    from cad.export.sim import SimBody, SimModel, SimMotor, mjcf_text

    body = SimBody(name="crank", parent="world", pos_m=np.zeros(3), rot=np.eye(3), joint="crank",
                   joint_ref_rad=0.0, mass_kg=0.01, com_m=np.zeros(3), inertia_com_kg_m2=np.eye(3) * 1e-6,
                   armature_kg_m2=4 * JM, meshes=(), sites={})
    model = SimModel(name="m", bodies=(body,), world_meshes=(), loops=(),
                     motors=(SimMotor("motor", "crank", TP_NM, gear=2.0),), meshdir="parts")
    text = mjcf_text(model)
    assert 'gear="2.0"' in text and 'forcerange="-0.9725 0.9725"' in text
    import tempfile

    with tempfile.TemporaryDirectory() as t:
        p = Path(t) / "m.xml"
        p.write_text(text)
        assert mjcf_motors(p)["crank"] == {"armature": pytest.approx(4 * JM), "forcerange": pytest.approx(2 * TP_NM)}
