"""A capstan on each motor of the plain 5-bar pantograph (issue 35 items 1 and 5): the design
takes ``[transmission]`` (one table or one per motor), and every output reads the resolved
device's ratio n.

References, each independent of the code under test:

* force in every direction: the Jacobian by central finite differences of the 5-bar's inverse
  kinematics (not the analytic Jacobian the datasheet uses), J = dq/dx, F = sigma_min(J^T diag(n
  tau_c)) (= (dx/dq)^-T n tau);
* reflected inertia: n^2 (J_m + J_c) with J_c the capstan tube's m (r_o^2 + r_i^2) / 2 written
  out here (pi (r_o^2 - r_i^2) L rho) from the catalog motor's rotor inertia (data);
* MuJoCo: its joint-space inertia reduced onto the loop (``cad.sim.mj``) against the report's
  apparent mass, which includes n^2 (J_m + J_c); its gear and force range against the catalog
  motor's peak torque (data);
* firmware: the generated C compiled with gcc and run: counts -> angle and torque -> current
  through n against the hand formulas, its mass matrix at home against the report's.
"""

from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import assert_one_line_error, hapticad

from tests.compilers import compiler

ROOT = Path(__file__).resolve().parents[3]
N = 6.0
DC_MM, ROPE = 32.0, "steel-7x7-0.8"
CAPSTAN = (f'\n[transmission]\nkind = "capstan"\ncapstan_diameter_mm = {DC_MM}\nratio = {N}\n'
           f'cable = "{ROPE}"\n')
#: Same mechanics in double precision, two methods (measured ~1e-13 relative).
DYN_REL = 1e-9


def _plain() -> str:
    """designs/pantograph.toml without its [optimize] table (a built design)."""
    text = (ROOT / "designs" / "pantograph.toml").read_text()
    return text[:text.index("\n[optimize]") + 1]


def _load(tmp_path: Path, extra: str, name: str = "p.toml"):
    from cad.design import load_design

    p = tmp_path / name
    p.write_text(_plain() + extra)
    return load_design(p)


BUNDLED = ROOT / "designs" / "pantograph_capstan.toml"
#: The bundled design's capstan (its file): ratio drum / capstan, rope diameter, wraps.
NB, DC_B, ROPE_D_B, WRAPS_B = 128.0 / 32.0, 32.0, 0.8, 3.0


@pytest.fixture(scope="module")
def built(shared_build):
    """designs/pantograph_capstan.toml built once (MJCF, meshes, firmware): the run's shared
    preview build (tests/conftest.py ``CAPSTAN_FORMATS``, read-only), also read by
    tests/unit/assembly/test_capstan_fastening_steps.py."""
    from tests.conftest import CAPSTAN_FORMATS

    fmts = CAPSTAN_FORMATS[BUNDLED.name]
    assert set(fmts) == {"mjcf", "stl", "firmware"}
    return shared_build(BUNDLED.name, fmts, "preview")


def test_bundled_file_states_its_capstan():
    import tomllib

    t = tomllib.loads(BUNDLED.read_text())["transmission"]
    assert (t["drum_diameter_mm"] / t["capstan_diameter_mm"], t["capstan_diameter_mm"], t["wraps"]) == (
        NB, DC_B, WRAPS_B)
    assert t["cable"] == "steel-7x7-0.8"


def _capstan_izz_by_hand(rope_d: float, wraps: float, bore_mm: float, dc_mm: float = DC_B) -> float:
    """J_c of the capstan: the grooved steel capstan of
    :func:`tests.capstan_ref.grooved_capstan_izz_kg_m2` (cad.actuators.capstan_geometry's
    dimensions: pitch less one rope to the groove's bottom, 0.35 d crests, 1.5 d per turn + 8 mm hub)."""
    from cad.data.materials import get_material
    from tests.capstan_ref import grooved_capstan_izz_kg_m2

    return grooved_capstan_izz_kg_m2(dc_mm, rope_d, wraps, bore_mm, get_material("steel-1018").density_kg_m3)


def _fd_jacobian(fb, xy_mm: np.ndarray, h_mm: float = 1e-4) -> np.ndarray:
    """dq/dx (2, 2) rad/m by central differences of the inverse kinematics."""
    from cad.kinematics import fivebar as fb5

    J = np.empty((2, 2))
    for k in range(2):
        e = np.zeros(2)
        e[k] = h_mm
        qp, qm = fb5.ik(fb, (xy_mm + e)[None]).q_rad[0], fb5.ik(fb, (xy_mm - e)[None]).q_rad[0]
        J[:, k] = (qp - qm) / (2 * h_mm * 1e-3)
    return J


# ----------------------------------------------------------------------------- the design
def test_both_forms_reach_the_resolved_device(tmp_path):
    from cad.device import resolve_device

    one = resolve_device(_load(tmp_path, CAPSTAN, "a.toml"))
    assert [t.motor_joint for t in one.transmissions] == ["q_left", "q_right"]
    assert all(t.is_capstan and t.ratio == N and t.cable.key == ROPE for t in one.transmissions)
    per = (f'\n[[transmission]]\nkind = "direct"\n\n[[transmission]]\nkind = "capstan"\n'
           f'capstan_diameter_mm = {DC_MM}\ndrum_diameter_mm = 128.0\ncable = "{ROPE}"\n')
    two = resolve_device(_load(tmp_path, per, "b.toml"))
    assert [t.ratio for t in two.transmissions] == [1.0, 4.0]
    assert two.joint_counts_per_rev("q_right") == 4 * two.joint_counts_per_rev("q_left")


@pytest.mark.parametrize("extra, field", [
    (CAPSTAN.replace(f"ratio = {N}", "ratio = 0.25"), "transmission.ratio"),
    (CAPSTAN.replace(ROPE, "nylon-1"), "transmission.cable"),
    ('\n[[transmission]]\nkind = "capstan"\n', "transmission"),
    ('\n[[transmission]]\nkind = "direct"\n\n[[transmission]]\nkind = "belt"\n', "transmission.2.kind"),
])
def test_a_bad_transmission_exits_2_naming_the_field(tmp_path, extra, field):
    p = tmp_path / "bad.toml"
    p.write_text(_plain() + extra)
    code, _, err = hapticad("check", p)
    assert_one_line_error(code, err, field)


# ----------------------------------------------------------------------------- force
def test_motor_force_is_n_times_through_the_ratio_against_finite_differences(tmp_path):
    from cad.data.catalog import get_motor
    from cad.families.pantograph.datasheet import motor_force_rows

    d = _load(tmp_path, CAPSTAN)
    rows = {r["key"]: r for r in motor_force_rows(d)}
    tau = get_motor(d.parts.motor).torque_continuous_mNm * 1e-3
    X = d.workspace_points()
    by_hand = []
    for xy in X:
        J = _fd_jacobian(d.mechanism, xy)
        A = J.T @ np.diag([N * tau, N * tau])  # f = (dx/dq)^-T n tau, J = dq/dx
        by_hand.append(np.linalg.svd(A, compute_uv=False)[-1])
    assert rows["continuous_force_N"]["value"] == pytest.approx(min(by_hand), rel=1e-6)  # FD step error
    assert rows["continuous_force_N"]["max"] == pytest.approx(max(by_hand), rel=1e-6)
    assert "x capstan n = 6" in rows["continuous_force_N"]["model"]


def test_resolution_is_n_times_finer(tmp_path):
    from cad.families.pantograph.datasheet import resolution_m

    d = _load(tmp_path, CAPSTAN)
    xy = np.asarray(d.workspace["center_mm"], float)
    J = _fd_jacobian(d.mechanism, xy)
    k = len(d.workspace_points()) // 2  # the grid's centre sample
    np.testing.assert_allclose(d.workspace_points()[k], xy)
    want = np.linalg.norm(np.linalg.inv(J), 2) * 2 * math.pi / (4000 * N)
    assert resolution_m(d, 4000 * N)[k] == pytest.approx(want, rel=1e-6)


# ----------------------------------------------------------------------------- inertia
def test_reflected_rotor_inertia_in_the_apparent_mass(built):
    """report.json's apparent mass at home = the links' (the dynamics module on the report's
    bodies) + J^T diag(n^2 (J_m + J_c)) J with J from finite differences and J_c by hand."""
    from cad.data.catalog import get_motor
    from cad.kinematics import fivebar as fb5

    d, _, rep = built
    m = get_motor(d.parts.motor)
    jq = NB * NB * (m.rotor_inertia_g_cm2 * 1e-7 + _capstan_izz_by_hand(ROPE_D_B, WRAPS_B, m.shaft_diameter_mm))

    def lm(b):
        mp = rep["bodies"][b]
        return fb5.LinkMass(mp["mass_kg"], (mp["com_mm"][0] * 1e-3, mp["com_mm"][1] * 1e-3),
                            mp["inertia_com_kg_m2"][2][2])

    home = np.asarray(rep["effective_mass_home"]["at_mm"], float)
    links = fb5.FiveBarMass(lm("proximal_left"), lm("proximal_right"), lm("distal_left"), lm("distal_right"))
    M_links = fb5.mass_matrix_kg(d.mechanism, home[None], links)[0] + rep["bodies"]["handle"]["mass_kg"] * np.eye(2)
    J = _fd_jacobian(d.mechanism, home)
    want_g = (M_links + jq * J.T @ J) * 1e3
    got_g = np.asarray(rep["effective_mass_home"]["mass_matrix_g"])
    np.testing.assert_allclose(got_g, want_g, rtol=1e-6)  # FD Jacobian
    assert got_g[0, 0] > M_links[0, 0] * 1e3 + 30.0  # the rotors count (n = 4)


def test_mjcf_in_mujoco_has_gear_n_and_the_reflected_armature(built):
    from cad.data.catalog import get_motor
    from cad.sim import mj

    d, out, rep = built
    spec = get_motor(d.parts.motor)
    m, data = mj.load(out / f"{d.name}.xml")
    jq = NB * NB * (spec.rotor_inertia_g_cm2 * 1e-7 + _capstan_izz_by_hand(ROPE_D_B, WRAPS_B, spec.shaft_diameter_mm))
    for i, joint in enumerate(("q_left", "q_right")):
        assert m.actuator_gear[i, 0] == NB
        np.testing.assert_allclose(m.actuator_forcerange[i], [-spec.torque_peak_mNm * 1e-3,
                                                             spec.torque_peak_mNm * 1e-3], rtol=1e-12)
        assert m.dof_armature[mj.joint_dof(m, joint)] == pytest.approx(jq, rel=1e-9)
    r = mj.fivebar_task_mass_matrix(m, data)
    home = np.array(rep["effective_mass_home"]["mass_matrix_g"])
    np.testing.assert_allclose(r["M_xy"] * 1e3, home, rtol=DYN_REL, atol=DYN_REL * np.abs(home).max())


# ----------------------------------------------------------------------------- firmware
def test_firmware_compiled_with_gcc_goes_through_the_ratio(built, tmp_path):
    d, out, rep = built
    fw = out / "firmware"
    h = (fw / "hapticad_device.h").read_text()
    assert f"#define HC_GEAR {{ HC_R({NB!r}), HC_R({NB!r}) }}" in h
    (tmp_path / "m.c").write_text(
        '#include <stdio.h>\n#include "hapticad_device.h"\nint main(void){hc_encoder_t e = HC_ENCODER_DEFAULT;'
        'long c[2]={1000,-500};hc_real q[2],q0[2],t[2]={0.3,-0.1},a[2],M[4];long z[2]={0,0};int s;'
        'hc_counts_to_angles(&e,c,q);hc_counts_to_angles(&e,z,q0);s=hc_motor_currents(t,HC_LIMIT_PEAK,a);'
        'hc_mass_matrix(q0,M);printf("%.17g %.17g %.17g %.17g %d %.17g %.17g %.17g %.17g %.17g %.17g\\n",'
        'q[0],q[1],q0[0],q0[1],s,a[0],a[1],M[0],M[1],M[2],M[3]);return 0;}\n')
    exe = tmp_path / "m"
    subprocess.run([compiler(), "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", f"-I{fw}", "-o",
                    str(exe), str(tmp_path / "m.c"), str(fw / "hapticad_device.c"), "-lm"], check=True, timeout=120)
    v = [float(x) for x in subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout.split()]
    q, q0, s, a, M = v[0:2], v[2:4], int(v[4]), v[5:7], np.reshape(v[7:11], (2, 2))
    step = 2 * math.pi / (4000 * NB)  # the motor encoder's count through the ratio
    assert q[0] - q0[0] == pytest.approx(1000 * step, rel=1e-12)
    assert q[1] - q0[1] == pytest.approx(-500 * step, rel=1e-12)
    kt = 38.9e-3  # maxon RE 35 catalog (cad.data.catalog maxon-re35)
    assert s == 0 and a == pytest.approx([0.3 / (NB * kt), -0.1 / (NB * kt)], rel=1e-12)
    np.testing.assert_allclose(M * 1e3, rep["effective_mass_home"]["mass_matrix_g"], rtol=1e-9)
    ch = json.loads((fw / "chai3d_device.json").read_text())
    cont = next(r for r in rep["datasheet"]["rows"] if r["key"] == "continuous_force_N")
    assert ch["m_maxLinearForce"] == pytest.approx(cont["value"], rel=1e-12)
    assert ch["transmission_ratio"] == [NB, NB]


# ----------------------------------------------------------------------------- structure
def test_rope_spring_in_series_against_the_two_spring_closed_form(built, tmp_path):
    """The handle compliance with the ropes = the frame's with the links held rigidly at B +
    the two rope springs through the linkage, J^-1 diag(1 / k_q) J^-T (J = dq/dx; the distal
    links are two-force members, so the joint torques are J^-T F whatever the frame's
    elasticity), with k_q = EA (2 / L) r_d^2 by hand."""
    from cad.data.cables import CABLES
    from cad.design import load_design
    from cad.structure import pantograph as sp

    d, _, rep = built
    text = BUNDLED.read_text()
    (tmp_path / "direct.toml").write_text(text[:text.index("\n[transmission]") + 1])
    direct = load_design(tmp_path / "direct.toml")
    rd, rc = NB * DC_B / 2, DC_B / 2
    C = rd + rc + 2.0  # the pitch circles 2 mm apart (cad.actuators.capstan.CAPSTAN_GAP_MM)
    L = math.sqrt(C * C - (rd - rc) ** 2) * 1e-3
    k = CABLES["steel-7x7-0.8"].axial_stiffness_EA_N * 2 / L * (rd * 1e-3) ** 2
    with_rope = sp.analyse(d, rep["bodies"], 1.0, 10.0)
    rigid = sp.analyse(direct, rep["bodies"], 1.0, 10.0)
    assert with_rope["rope_stiffness_Nm_per_rad"] == pytest.approx({"q_left": k, "q_right": k}, rel=1e-12)
    assert rigid["rope_stiffness_Nm_per_rad"] == {}
    X, labels = sp.poses(d)
    for x, lab in zip(X, labels, strict=True):
        Jinv = np.linalg.inv(_fd_jacobian(d.mechanism, x))
        extra = Jinv @ np.diag([1 / k, 1 / k]) @ Jinv.T  # m/N
        for i, ax in enumerate("xy"):
            got = with_rope["per_pose"][lab]["compliance_um_per_N"][ax]
            want = rigid["per_pose"][lab]["compliance_um_per_N"][ax] + extra[i, i] * 1e6
            assert got == pytest.approx(want, rel=1e-5), (lab, ax)  # FD Jacobian
        assert with_rope["per_pose"][lab]["compliance_um_per_N"]["z"] == pytest.approx(
            rigid["per_pose"][lab]["compliance_um_per_N"]["z"], rel=1e-9)  # the ropes act in plane only
    assert with_rope["first_mode_in_plane_Hz"] < rigid["first_mode_in_plane_Hz"]


def test_one_capstan_and_one_direct_motor_is_refused_before_cad(tmp_path):
    """Both motors through a capstan or neither (the motors would sit at different heights):
    one line naming ``transmission``, at the layout (no solid made)."""
    from cad.errors import DesignError
    from cad.families.pantograph.capstan import layout

    per = (f'\n[[transmission]]\nkind = "direct"\n\n[[transmission]]\nkind = "capstan"\n'
           f'capstan_diameter_mm = {DC_MM}\ndrum_diameter_mm = 128.0\ncable = "{ROPE}"\n')
    with pytest.raises(DesignError, match=r"^transmission: .*give both motors a capstan"):
        layout(_load(tmp_path, per))


def test_bundled_design_meets_every_default_limit(built):
    """designs/pantograph_capstan.toml: >= 4 N continuous in every direction over its workspace,
    first mode >= 150 Hz, and every limit of its datasheet (report.json) met, no warning."""
    _, _, rep = built
    ds = rep["datasheet"]
    rows = {r["key"]: r for r in ds["rows"]}
    assert rows["continuous_force_N"]["value"] >= 4.0 and rows["continuous_force_N"]["limit"]["value"] == 4.0
    assert rows["first_mode_Hz"]["value"] >= 150.0 and rows["first_mode_Hz"]["limit"]["value"] == 150.0
    judged = [r for r in ds["rows"] if r.get("limit")]
    assert {"continuous_force_N", "first_mode_Hz", "max_stress_MPa", "bend_ratio_1", "cable_slip_margin_2",
            "cable_safety_factor_1", "drum_sector_deg_2"} <= {r["key"] for r in judged}
    assert [r["key"] for r in judged if r["verdict"] != "ok"] == []
    assert ds["ok"] and ds["warnings"] == []
    assert rep["interference"]["collisions"] == []


def test_bundled_design_figures_regression_pin(built):
    """Regression pin (our own run of designs/pantograph_capstan.toml, typed in
    docs/families/pantograph-powermouse.md and the design's header): 4.99 N continuous in every
    direction, first mode 203 Hz."""
    rows = {r["key"]: r for r in built[2]["datasheet"]["rows"]}
    assert round(rows["continuous_force_N"]["value"], 2) == 4.99
    assert round(rows["first_mode_Hz"]["value"]) == 203


def test_drums_carry_the_rope_groove_read_back_from_the_solid(built):
    """Each drum of the bundled design carries the rope's groove between its anchors: OCCT's
    exact section at the groove's mid-angle dips from the crests ((128 - 0.8) / 2 + 0.35 x 0.8 =
    63.88 mm) to the groove's bottom (63.6 mm) at mid-thickness (z 5 mm of the 10 mm drum), as
    wide as the 0.4 mm circle's chord at the crests, 2 sqrt(2 r h - h^2); the drum's mass in
    report.json's BOM (from the grooved solid) is the annular sector to the crests less the two
    anchor holes (9 mm below the groove's bottom, out through the crests) and the groove
    (Pappus: its section's area and centroid by quadrature here, round the arc between the
    anchors less a land of one tap drill and one rope diameter each side)."""
    from cad.data.catalog import tap_drill_mm
    from cad.data.materials import get_material
    from cad.families.pantograph import capstan_solids as pcs
    from cad.families.pantograph.layout import layout
    from cad.massprops.occt import volume_props_mm
    from tests.capstan_ref import radial_hole_mm3, section_profile

    d, _, rep = built
    lay = layout(d)
    kinds = pcs.capstan_kinds(d, lay)
    bom = {r["part"]: r for r in rep["bom"]}
    rho = get_material("aluminium-6061").density_kg_m3
    r_b, r_o, r_i = (128.0 - 0.8) / 2, (128.0 - 0.8) / 2 + 0.28, 6.0 / 2  # the RE 35's 6 mm shaft
    x, w = np.polynomial.legendre.leggauss(400)
    u = -0.4 + 0.5 * 0.28 * (x + 1.0)  # radial offset from the section circle's centre at 64 mm
    chord = 2.0 * np.sqrt(0.16 - u * u)
    area = 0.5 * 0.28 * np.sum(w * chord)
    rbar = 0.5 * 0.28 * np.sum(w * chord * (64.0 + u)) / area
    hole = radial_hole_mm3(tap_drill_mm("M3-0.5") / 2, r_o, 9.0 + 0.28)
    land = math.degrees((tap_drill_mm("M3-0.5") + 0.8) / r_b)
    for sd in lay["capstan"]["sides"]:
        side = sd.joint.split("_")[1]
        shape = kinds[f"drum_{sd.joint}"].shape
        lo, hi = sorted(sd.anchors_deg)
        zr = section_profile(shape, 0.5 * (lo + hi))
        outer = zr[zr[:, 1] > r_b - 0.1]
        assert outer[:, 1].max() == pytest.approx(r_o, abs=1e-6)
        assert outer[:, 1].min() == pytest.approx(r_b, abs=3e-3)
        assert outer[outer[:, 1] < r_o - 1e-6][:, 0].mean() == pytest.approx(5.0, abs=1e-3)
        crest = outer[np.abs(outer[:, 1] - r_o) < 1e-6][:, 0]
        width = crest[crest > 5.0].min() - crest[crest < 5.0].max()
        assert width == pytest.approx(2 * math.sqrt(2 * 0.4 * 0.28 - 0.28 ** 2), abs=1e-6)
        groove = area * rbar * math.radians(hi - lo - 2 * land)
        sector = 0.5 * math.radians(sd.arc_span_deg) * (r_o ** 2 - r_i ** 2) * 10.0
        m_ref = (sector - 2 * hole - groove) * 1e-9 * rho
        assert volume_props_mm(shape, eps=1e-9)[0] * 1e-9 * rho == pytest.approx(m_ref, rel=1e-9)
        # the build integrates in OCCT's default Gauss mode: ~1e-5 of the part on the holes' faces
        assert bom[f"capstan_drum_{side}"]["mass_g"] == pytest.approx(m_ref * 1e3, rel=2e-5)


def test_identification_prediction_sees_the_motors_through_the_ratio(built):
    """The 5-bar's identification prediction (cad.sim.identify_fivebar.predict) of the bundled
    design: K_t, counts, rotor and Coulomb friction at the joints, n K_t, n 4000, n^2 (J_m +
    J_c) and n K_t I_0 from the catalog motor (data) and the hand formula of J_c."""
    from cad.data.catalog import get_motor
    from cad.sim.identify_fivebar import predict

    d, _, rep = built
    m = get_motor(d.parts.motor)
    p = predict(d, rep)
    assert p.kt_Nm_per_A == pytest.approx(NB * m.torque_constant_mNm_per_A * 1e-3, rel=1e-12)
    assert p.counts_per_rev == 4000 * NB
    jq = NB * NB * (m.rotor_inertia_g_cm2 * 1e-7 + _capstan_izz_by_hand(ROPE_D_B, WRAPS_B, m.shaft_diameter_mm))
    assert p.rotor_kg_m2 == pytest.approx(jq, rel=1e-9)
    assert p.Tc_Nm == pytest.approx(NB * m.torque_constant_mNm_per_A * m.no_load_current_mA * 1e-6, rel=1e-9)


def test_capstan_rows_bom_and_winding_steps_of_each_motor(built):
    """Each motor's capstan rows (the shared cad.datasheet.capstan_rows) against hand figures
    of the bundled design: bend ratio D/d, the rope load and safety factor at the RE 35's peak
    torque (its header's numbers), the rope's cut length part by part, the ropes' stiffness at
    the handle from finite-difference Jacobians, K_max in series; one rope line per motor in
    bom.csv and order.csv, the winding steps naming the anchors and tensioners the solids carry."""
    import csv

    from cad.data.cables import CABLES
    from cad.data.catalog import get_motor

    d, out, rep = built
    rows = {r["key"]: r for r in rep["datasheet"]["rows"]}
    rope = CABLES["steel-7x7-0.8"]
    tau = get_motor(d.parts.motor).torque_peak_mNm * 1e-3
    dT = tau / (DC_B / 2e3)  # n tau / r_d = tau / r_c
    e = math.exp(0.12 * 2 * math.pi * WRAPS_B)
    T0 = dT / 2 * (e + 1) / (e - 1)
    rd, rc = NB * DC_B / 2, DC_B / 2
    L = math.sqrt((rd + rc + 2.0) ** 2 - (rd - rc) ** 2)
    k = rope.axial_stiffness_EA_N * 2 / (L * 1e-3) * (rd * 1e-3) ** 2
    sides = {s["joint"]: s for s in rep["layout_mm"]["capstan"]["sides"]}
    for s, joint in (("_1", "q_left"), ("_2", "q_right")):
        assert rows["transmission_ratio" + s]["value"] == NB
        assert rows["bend_ratio" + s]["value"] == DC_B / 0.8 and rows["bend_ratio" + s]["verdict"] == "ok"
        assert rows["cable_pretension_N" + s]["value"] == pytest.approx(T0, rel=1e-9)
        assert rows["cable_safety_factor" + s]["value"] == pytest.approx(
            rope.min_breaking_load_N / (T0 + dT / 2), rel=1e-9)
        rng = np.subtract(*sides[joint]["joint_range_deg"][::-1])
        arc = rng + 2 * math.degrees(2 * 10.0 / (NB * DC_B))
        cut = math.pi * DC_B * WRAPS_B + 2 * L + math.pi * NB * DC_B * arc / 360 + 2 * 20.0
        assert rows["cable_cut_length_mm" + s]["value"] == pytest.approx(cut, rel=1e-9)
        assert rows["cable_stiffness_Nm_per_rad" + s]["value"] == pytest.approx(k, rel=1e-9)
    worst = math.inf
    for xy in d.workspace_points():
        Jinv = np.linalg.inv(_fd_jacobian(d.mechanism, xy))
        worst = min(worst, 1.0 / np.linalg.eigvalsh(Jinv @ Jinv.T / k)[-1])
    assert rows["cable_handle_stiffness_N_per_m"]["value"] == pytest.approx(worst, rel=1e-5)  # FD
    K = rows["eq25_K_max_N_per_m"]["value"]
    assert rows["K_max_with_cable_N_per_m"]["value"] == pytest.approx(1 / (1 / K + 1 / rows[
        "cable_handle_stiffness_N_per_m"]["value"]), rel=1e-12)
    bom = list(csv.DictReader((out / "bom.csv").read_text().splitlines()))
    ropes = [r for r in bom if r["part"].startswith("capstan_cable")]
    assert [r["part"] for r in ropes] == ["capstan_cable_1", "capstan_cable_2"]
    assert all(f"cut length {rows['cable_cut_length_mm_1']['value']:.0f} mm" in r["description"] for r in ropes)
    order = (out / "order.csv").read_text()
    assert f"wire rope 7x7 0.8 mm x {rows['cable_cut_length_mm_1']['value']:.0f} mm" in order
    names = {i for i in (out / "assembly.md").read_text().split("`")}
    steps = (out / "assembly.md").read_text()
    for s in ("_1", "_2"):
        assert f"capstan_anchor{s}_1" in names and f"capstan_tensioner{s}" in names
        assert f"until the rope holds at least {T0:.1f} N (datasheet cable_pretension_N{s}" in steps


def test_one_ratio_per_motor_scales_each_joint_torque(tmp_path):
    """``[[transmission]]`` with two ratios: S_J = diag(n_left tau, n_right tau), the force in
    every direction against finite-difference Jacobians; the per-joint rotor inertias of the
    firmware's mass matrix n_i^2 (J_m + J_c)."""
    from cad.data.catalog import get_motor
    from cad.device import resolve_device
    from cad.families.pantograph.datasheet import motor_force_rows

    per = (f'\n[[transmission]]\nkind = "capstan"\ncapstan_diameter_mm = {DC_MM}\ndrum_diameter_mm = 128.0\n'
           f'cable = "{ROPE}"\n\n[[transmission]]\nkind = "capstan"\ncapstan_diameter_mm = {DC_MM}\n'
           f'drum_diameter_mm = 112.0\ncable = "{ROPE}"\n')
    d = _load(tmp_path, per)
    m = get_motor(d.parts.motor)
    n = np.array([128.0 / DC_MM, 112.0 / DC_MM])
    tau = m.torque_continuous_mNm * 1e-3
    by_hand = [np.linalg.svd(_fd_jacobian(d.mechanism, xy).T @ np.diag(n * tau), compute_uv=False)[-1]
               for xy in d.workspace_points()]
    rows = {r["key"]: r for r in motor_force_rows(d)}
    assert rows["continuous_force_N"]["value"] == pytest.approx(min(by_hand), rel=1e-6)
    dev = resolve_device(d)
    jc = _capstan_izz_by_hand(0.8, 3.0, m.shaft_diameter_mm, DC_MM)
    for j, nj in zip(("q_left", "q_right"), n, strict=True):
        assert dev.joint_rotor_inertia_kg_m2(j) == pytest.approx(nj * nj * (m.rotor_inertia_g_cm2 * 1e-7 + jc),
                                                                 rel=1e-9)


def test_generated_test_program_passes_the_vectors_with_gcc(built, tmp_path):
    """The build's own firmware/test_device.c, compiled with gcc, checks hapticad_device.c against
    test_vectors.json (the numpy model: counts through the ratio, the mass matrix with the
    rotors n^2 (J_m + J_c) at their joints): no failure."""
    _, out, _ = built
    fw = out / "firmware"
    exe = tmp_path / "td"
    subprocess.run([compiler(), "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", f"-I{fw}", "-o", str(exe),
                    str(fw / "test_device.c"), str(fw / "hapticad_device.c"), "-lm"], check=True, timeout=120)
    r = subprocess.run([str(exe), str(fw / "test_vectors.json"), "1e-9", "1e-9", "1e-7"], capture_output=True,
                       text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    assert " failures 0 " in r.stdout and " ok " in r.stdout
    vec = json.loads((fw / "test_vectors.json").read_text())
    assert vec["layout"][:3] == ["status", "counts[2]", "q_from_counts_rad[2]"]
    enc = vec["encoder"]
    assert enc["counts_per_rev"] == 4000  # the motor's encoder; the joint turns n times slower
    for row in vec["rows"][:20]:
        want = np.asarray(enc["zero_rad"]) + 2 * math.pi * np.asarray(row[1:3]) / (4000 * NB)
        np.testing.assert_allclose(row[3:5], want, rtol=0, atol=1e-12)


def test_drums_that_would_meet_are_refused_in_one_line(tmp_path):
    """The bundled capstan 5-bar with its motors 300 mm off the joints (centre_distance_mm): the
    tangent points' half angle gamma = acos((r_d - r_c) / C) grows to 81 deg, each drum's arc to
    2 gamma + the link's range + anchors, and no pair of motor directions keeps the two drums
    apart over the workspace; the build exits 2 naming the transmission, the drum and what met,
    nothing written."""
    p = tmp_path / "far.toml"
    p.write_text(BUNDLED.read_text().replace("wraps = 3.0", "wraps = 3.0\ncentre_distance_mm = 300.0"))
    out = tmp_path / "out"
    code, _, err = hapticad("build", p, "--out", out)
    assert_one_line_error(code, err, "transmission", "drum 128 mm", "swept drums meet", "centre_distance_mm")
    assert not out.exists() or not any(out.iterdir())


def test_written_files_agree_with_the_resolved_device(built):
    """bom.csv, the datasheet, hapticad_device.h and the MJCF read back state the resolved
    device's facts (encoder counts, K_t and currents, armature n^2 (J_m + J_c), force range
    n T_peak through the gear): cad.device.readback finds no disagreement."""
    from cad.device import resolve_device
    from cad.device.readback import device_values, disagreements, output_facts

    d, out, _ = built
    dev = resolve_device(d)
    assert disagreements(dev, out) == []
    keys = {f[3] for f in output_facts(out)}
    assert {"armature:q_left", "forcerange:q_right"} <= keys & set(device_values(dev))


def test_the_haptic_pens_capstans_off_the_shaft_are_refused(tmp_path):
    """The haptic pen with one [transmission] for its six motors (and its 5 mm motor plate):
    the far shoulder band's capstan leaves the RE 35 shaft, so check is one line naming the
    table, exit 2 (the analyses: tests/families/pen/test_pen_capstan.py; the pen that builds:
    designs/haptic_pen_capstan.toml)."""
    p = tmp_path / "pen.toml"
    p.write_text((ROOT / "designs" / "haptic_pen.toml").read_text() + CAPSTAN)
    code, _, err = hapticad("check", p)
    assert_one_line_error(code, err, "transmission", "the haptic pen's capstans cannot be laid out",
                          "shaft's tip", "parts.motor_mount_thickness_mm <=")


def test_chai3d_stiffness_is_the_datasheets_with_the_ropes_in_series(built):
    """chai3d_device.json m_maxLinearStiffness read back = the datasheet's renderable stiffness
    with the ropes in series (report.json ``K_max_with_cable_N_per_m``; tester finding: it stated
    eq (25)'s K_max without the ropes) = the two-spring closed form 1 / (1 / K_max + 1 / K_rope)
    on the datasheet's eq (25) K_max and its ropes' stiffness at the handle, each rope's k_q
    = EA (2 / L) r_d^2 by hand."""
    from cad.data.cables import CABLES

    _, out, rep = built
    ds = {r["key"]: r["value"] for r in rep["datasheet"]["rows"]}
    rd, rc = NB * DC_B / 2, DC_B / 2
    L = math.sqrt((rd + rc + 2.0) ** 2 - (rd - rc) ** 2) * 1e-3  # pitch circles 2 mm apart
    k_q = CABLES["steel-7x7-0.8"].axial_stiffness_EA_N * 2 / L * (rd * 1e-3) ** 2
    assert ds["cable_stiffness_Nm_per_rad_1"] == pytest.approx(k_q, rel=1e-12)
    K = json.loads((out / "firmware" / "chai3d_device.json").read_text())["m_maxLinearStiffness"]
    two_springs = 1.0 / (1.0 / ds["eq25_K_max_N_per_m"] + 1.0 / ds["cable_handle_stiffness_N_per_m"])
    assert K == pytest.approx(two_springs, rel=1e-12)
    assert K == pytest.approx(ds["K_max_with_cable_N_per_m"], rel=1e-12)
    assert K < ds["eq25_K_max_N_per_m"]  # the ropes in series soften the wall
