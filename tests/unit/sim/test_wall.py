"""Virtual-wall simulation (issue 14): energy conservation, passivity-side stability in both
models, eq (25) and the passivity bound beside K_max, CLI errors."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from cli_helpers import assert_one_line_error, hapticad

ROOT = Path(__file__).resolve().parents[3]
#: Energy drift bounds over 10 s of free motion (friction, control and hand off), relative:
#: reduced model, semi-implicit Euler at 1 ms (first order in dt; measured 1.5e-5);
#: mujoco model, RK4 at 0.1 ms with the soft loop constraint (measured 7e-7).
DRIFT_REDUCED = 1e-4
DRIFT_MUJOCO = 1e-5


@pytest.fixture(scope="module")
def device(hoeken_sim_build):
    from cad.dynamics.inertia import InertiaCoefficients
    from cad.sim import wall

    d, out, rep, _ = hoeken_sim_build
    H = InertiaCoefficients(rep["H11_kg_m2"], rep["H12_kg_m2"], rep["H22_kg_m2"], rep["H33_kg_m2"],
                            math.radians(rep["beta2_deg"]))
    tab = wall.device_tables(d, H)
    st = d.stiffness
    counts = 2 * math.pi * abs(tab.J_wall) / st.encoder_resolution_m
    spec = wall.WallSpec(st.Te_s, counts, st.Fv_N_s_per_m, st.Fs_N, 0.167, st.xdot_max_m_per_s)
    return d, out, tab, spec


def test_tables_carry_eq22(device):
    """The reduced model's mass at the wall is M11 of eq (22) (path frame), from the report's H."""
    from cad.analysis import apparent_mass_curves
    from cad.sim import wall

    d, out, tab, _ = device
    rep = json.loads((out / "report.json").read_text())
    M11_g = (tab.at(tab.a, tab.phi_wall) / tab.J_wall**2) * 1e3
    assert rep["apparent_mass"]["M11_min_g"] <= M11_g <= rep["apparent_mass"]["M11_max_g"]
    from cad.dynamics.inertia import InertiaCoefficients

    H = InertiaCoefficients(rep["H11_kg_m2"], rep["H12_kg_m2"], rep["H22_kg_m2"], rep["H33_kg_m2"],
                            math.radians(rep["beta2_deg"]))
    c = apparent_mass_curves(d, H, 2001)
    assert M11_g == pytest.approx(np.interp(tab.phi_wall, c["phi1_rad"], c["M_kg"][:, 0, 0]) * 1e3, rel=1e-6)
    assert wall.WALL_AT == 0.5


def test_energy_conserved_without_friction_and_control(device):
    from cad.sim import wall

    d, out, tab, spec0 = device
    spec = wall.WallSpec(1e-3, spec0.counts_per_rev, 0.12, 0.083, 0.167, 0.0, T_sim_s=10.0)
    phi0 = d.phi1_min_rad + 0.05
    om0 = 0.004 / tab.J_wall  # 4 mm/s: 40 mm of the stroke in 10 s, M11 varies by ~50 %
    t, xs, phi, om = wall.simulate_reduced(tab, spec, 0.0, 0.0, control=False, friction=False,
                                           hand=False, phi0=phi0, omega0=om0, substep_s=1e-3)
    E0 = 0.5 * tab.at(tab.a, phi0) * om0**2
    E1 = 0.5 * tab.at(tab.a, phi[0]) * om[0] ** 2
    assert xs[-1, 0] - xs[0, 0] > 0.035  # it did travel over the stroke
    assert abs(E1 - E0) / E0 < DRIFT_REDUCED
    plant = wall.MujocoWall(out / "hoeken.xml", tab, spec)
    t, x, e = plant.run(0.0, 0.0, control=False, friction=False, hand=False, phi0=phi0, omega0=om0)
    assert x[-1] - x[0] > 0.035
    assert np.abs(e - e[0]).max() / e[0] < DRIFT_MUJOCO
    # both models start with the same kinetic energy (MuJoCo's mass matrix vs eq 22 along x)
    assert e[0] == pytest.approx(E0, rel=2e-3)


def test_walls_either_side_of_passivity_in_both_models(device):
    """Colgate-Schenkel: K < 2 (Fv - |B|) / Te = 727 N/m is passive. Half of it is stable;
    137x it is unstable, in both models."""
    from cad.sim import wall

    d, out, tab, spec = device
    kp = wall.passivity_K_max(spec.Fv_N_s_per_m, 0.0, spec.Te_s)
    assert kp == pytest.approx(2 * 0.12 / 0.00033)
    lo, hi = 0.5 * kp, 1e5
    tol = wall.AMPLITUDE_COUNTS * tab.delta_m(spec.counts_per_rev)
    t, xs, *_ = wall.simulate_reduced(tab, spec, np.array([lo, hi]), 0.0)
    amp = wall.amplitude_m(t, xs)
    assert amp[0] < tol and amp[1] > 5 * tol
    plant = wall.MujocoWall(out / "hoeken.xml", tab, spec)
    for K, stable in ((lo, True), (hi, False)):
        t, x, _ = plant.run(K, 0.0)
        a = wall.amplitude_m(t, x[:, None])[0]
        assert (a < tol) if stable else (a > 5 * tol), (K, a / tol)


def test_k_section_finds_a_known_threshold():
    from cad.sim import wall

    for n in (1, 15):
        r = wall.k_max(lambda K: np.asarray(K) < 4321.0, n_probe=n)
        assert r["K_max_N_per_m"] < 4321.0 <= r["K_unstable_N_per_m"]
        assert r["K_unstable_N_per_m"] / r["K_max_N_per_m"] <= 1 + wall.K_RTOL
    assert wall.k_max(lambda K: np.zeros(len(K), bool))["K_max_N_per_m"] is None


def test_wall_cli_paper_numbers(hoeken_sim_build):
    """Defaults from [stiffness]: eq (25) gives the paper's ~2500 N/m (2590), passivity 727 N/m."""
    _, out, *_ = hoeken_sim_build
    code, o, err = hapticad("wall", ROOT / "designs" / "hoeken.toml", "--build-dir", out,
                            "--K-N-per-m", "400", "--json")
    assert code == 0, err
    r = json.loads(o)
    assert r["eq25_K_max_N_per_m"] == pytest.approx(2589.97, abs=0.01)
    assert r["passivity_K_max_N_per_m"] == pytest.approx(727.27, abs=0.01)
    assert r["encoder_resolution_m"] == pytest.approx(5.46e-5, rel=1e-12)
    assert r["stable"] is True and r["K_N_per_m"] == 400
    # Coulomb friction carries the wall well past the passivity bound (Diolaiti et al.)
    assert r["K_max_stable_N_per_m"] > r["passivity_K_max_N_per_m"]
    assert r["K_max_stable_N_per_m"] < r["K_first_unstable_N_per_m"]
    # --B-N-s-per-m reaches both the bound and the simulation: Colgate-Schenkel with the wall's
    # damping, K < 2 (Fv - |B|) / Te = 2 (0.12 - 0.05) / 0.33e-3 = 424.24 N/m (closed form); the
    # simulated K_max of the damped wall stays far above it, with its own sampling error
    code, o, err = hapticad("wall", ROOT / "designs" / "hoeken.toml", "--build-dir", out,
                            "--B-N-s-per-m", "0.05", "--json")
    assert code == 0, err
    rb = json.loads(o)
    assert rb["B_N_s_per_m"] == 0.05
    assert rb["passivity_K_max_N_per_m"] == pytest.approx(2 * (0.12 - 0.05) / 0.33e-3, rel=1e-12)
    assert rb["K_max_stable_N_per_m"] > 10 * rb["passivity_K_max_N_per_m"]
    assert 0 < rb["K_max_sampling_error_rel"] < 0.15 and 0 < r["K_max_sampling_error_rel"] < 0.15


@pytest.mark.parametrize(
    "args, needles",
    [
        (["--Te-s", "0.33"], ("--Te-s", "ms")),
        (["--model", "ode"], ("--model", "ode")),
        (["--encoder-counts-per-rev", "0"], ("--encoder-counts-per-rev",)),
        (["--K-N-per-m", "-5"], ("--K-N-per-m",)),
    ],
)
def test_wall_cli_bad_flags(args, needles):
    code, _, err = hapticad("wall", ROOT / "designs" / "hoeken.toml", *args)
    assert_one_line_error(code, err, *needles)


def test_wall_cli_bad_designs(tmp_path):
    code, _, err = hapticad("wall", ROOT / "designs" / "powermouse.toml")
    assert_one_line_error(code, err, "mechanism.family")
    # no [stiffness] table: the design's encoder and the friction estimate (issue 24), so the
    # empty --build-dir is what is refused
    code, _, err = hapticad("wall", ROOT / "designs" / "roberts.toml", "--build-dir", tmp_path)
    assert_one_line_error(code, err, "--build-dir")
    code, _, err = hapticad("wall", ROOT / "designs" / "hoeken.toml", "--build-dir", tmp_path)
    assert_one_line_error(code, err, "--build-dir")


def test_wall_without_stiffness_uses_encoder_and_friction_estimate(tmp_path):
    """Issue 24: a design with no [stiffness] table (hoeken_light) gets the wall inputs from its
    encoder and the datasheet's Coulomb friction estimate (Kt I0 / |dx/dphi1|, max over the
    stroke, by hand here), Fv = 0, the paper's Te and xdot_max; saying so."""
    from cad.design import load_design
    from cad.kinematics.fourbar import jacobian_mm_per_rad, solve
    from cad.kinematics.metrics import path_frame
    from cad.sim.device import wall_inputs

    d = load_design(ROOT / "designs" / "hoeken_light.toml")
    assert d.stiffness is None
    s, src = wall_inputs(d)
    phi = np.linspace(d.phi1_min_rad, d.phi1_max_rad, 401)
    fr = path_frame(d.linkage, d.phi1_min_rad, d.phi1_max_rad)
    Jx = np.abs(fr.rotate(jacobian_mm_per_rad(d.linkage, solve(d.linkage, phi)))[:, 0]) * 1e-3
    m = d.motor_spec()  # maxon RE 40 148877: Kt 60.3 mN m/A, I0 68.6 mA (data sheet)
    assert s["Fs"] == pytest.approx((60.3e-3 * 68.6e-3 / Jx).max(), rel=1e-9)
    assert m.key == "maxon-re40" and s["Fv"] == 0.0 and s["Te"] == 0.33e-3
    assert s["counts"] == 2000.0 and "friction estimate" in src and "encoder" in src
    d2 = load_design(_with_parts(tmp_path, "encoder_counts_per_rev = 10000"))
    assert wall_inputs(d2)[0]["counts"] == 10000.0


def _with_parts(tmp_path, line):
    text = (ROOT / "designs" / "hoeken_light.toml").read_text()
    p = tmp_path / "enc.toml"
    p.write_text(text.replace("[parts]\n", f"[parts]\n{line}\n", 1))
    return p


def _intermittent(K0: float, width: float, seed: int):
    """A stable_of whose walls are unstable with probability 1 / (1 + exp(-ln(K/K0) / width))
    (a logistic in log K, median K0), drawn once per K from a hash of K: a threshold known in
    closed form (K0) hidden in interleaved stable / unstable stiffnesses, like the wall's."""
    def f(K):
        K = np.asarray(K, float)
        u = np.array([np.random.default_rng([seed, int(k * 1e6) % 2**32]).random() for k in K])
        p = 1.0 / (1.0 + np.exp(-np.log(K / K0) / width))
        return u >= p
    return f


def test_k_max_estimate_finds_the_median_of_an_intermittent_threshold():
    """K_max of an intermittent stability (islands of both kinds over ~20 % of K) is the
    closed-form median K0 of the logistic: over 20 seeded draws, at least 90 % within their
    stated sampling error (a 95 % interval; measured 29 of 30), none beyond twice it."""
    from cad.sim import wall

    K0 = 15000.0
    hits = 0
    for seed in range(20):
        r = wall.k_max_estimate(_intermittent(K0, 0.05, seed))
        e = r["sampling_error_rel"]
        assert 0 < e < 0.15  # a stated error, not a shrug (measured 0.04 .. 0.11)
        assert r["K_first_unstable_N_per_m"] < K0 < r["K_last_stable_N_per_m"]
        assert r["exceptions"] > 0
        assert r["K_max_N_per_m"] == pytest.approx(K0, rel=2 * e)
        hits += abs(r["K_max_N_per_m"] / K0 - 1) <= e
    assert hits >= 18


def test_threshold_split_fewest_exceptions():
    """threshold_split by hand: 1 1 0 1 1 | 0 0 1 0 0 -> split 5 with 2 exceptions."""
    from cad.sim import wall

    ok = np.array([1, 1, 0, 1, 1, 0, 0, 1, 0, 0], bool)
    assert wall.threshold_split(ok) == (5, 2)
    assert wall.threshold_split(np.ones(3, bool)) == (3, 0)
    assert wall.threshold_split(np.zeros(3, bool)) == (0, 0)
