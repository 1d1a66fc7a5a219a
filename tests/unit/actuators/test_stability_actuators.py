"""Stability of the actuator models where they break (issue 7 §3).

Edges (isotropy paper section 6, eqs 8-9; section 5 for the PowerMouse):
the voice coil at and below d = d_r (no room for a coil), non-positive or
non-numeric sizes, gaps far beyond or just above d_r and actuators 1e-200 to
1e150 times the paper's (the gap optimizer must stay bracketed, interior and
NaN-free), the image series with K = 0 / negative / fractional slabs, the
infeasible NLP, the PowerMouse current-to-wrench map with a coil missing,
zero, duplicated or vanishing (rank deficient -> SingularJacobianError naming
the coil and the lost wrench), and ``hapticad voicecoil`` fuzzed flag by flag.

Independent references: eq (8) vanishes like sqrt(d - d_r) at the rattle
limit (B_g is smooth there); eqs (8)-(9) depend on length ratios only, so the
optimal gap scales exactly with the actuator; for d_r >> magnet sizes B_g
falls as d^-3 (dipole) and the optimum of d^-3 sqrt(d - d_r) is d = 1.2 d_r;
eq (9) at d = 0 is (2 B_r / pi) [pi/2 - atan(w l / (4t sqrt(16 t^2 + l^2 + w^2)))].
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from cli_helpers import hapticad
from hypothesis import given, settings
from hypothesis import strategies as st

from cad import tolerances as tol
from cad.actuators import powermouse as pm
from cad.actuators import voicecoil as vc
from cad.errors import DesignError, SingularJacobianError

PAPER = vc.VoiceCoilParams(20.0, 8.0, 4.0, 6.0)  # Fig. 8: l_m, w_m, t_m, d_r (mm)

# --------------------------------------------------------------------------- d <= d_r


def test_force_vanishes_like_sqrt_of_the_coil_width_then_below_d_r_is_named():
    """Eq (8): F = B_g(d) k sqrt(d - d_r) with B_g smooth at d_r, so F / sqrt(d - d_r)
    tends to B_g(d_r) k (exactly 0 at d = d_r); any d < d_r is a DesignError."""
    k = PAPER.eta_geom**0.5 * (PAPER.eta_pack * PAPER.power_W / PAPER.resistivity_ohm_m) ** 0.5
    k *= math.sqrt(2 * 8e-3 * 20e-3 * 1e-3)  # sqrt(2 w l) in m, (d - d_r) in mm -> m
    limit = float(vc.bg_eq9_T(6.0, 20.0, 8.0, 4.0, 1.2)) * k
    ratios = []
    for e in 10.0 ** -np.arange(1, 13):
        d = 6.0 + e
        F = float(vc.force_vs_gap_N(d, PAPER)[0])
        assert math.isfinite(F) and F > 0
        ratios.append(F / math.sqrt(d - 6.0))  # the coil width actually represented
    assert ratios[-1] == pytest.approx(limit, rel=1e-6)
    assert float(vc.force_vs_gap_N(6.0, PAPER)[0]) == 0.0
    for d in (6.0 - 1e-12, 3.0, 0.0, -1.0, math.nan, math.inf):
        with pytest.raises(DesignError, match="^gap_mm:"):
            vc.force_vs_gap_N([11.0, d], PAPER)


@pytest.mark.parametrize("d", [5.999, 0.0, -2.0, math.nan])
def test_every_gap_consumer_names_a_gap_without_room_for_a_coil(d):
    for call in (
        lambda: vc.ampere_turns(d, PAPER),
        lambda: vc.leg_boxes_mm(d, PAPER),
        lambda: vc.stroke_force(d, PAPER, [0.0], bz_fn=lambda P: np.ones(len(P))),
    ):
        with pytest.raises(DesignError, match="gap_mm"):
            call()


@pytest.mark.parametrize("model", ["closed-form", "images"])
@pytest.mark.parametrize("d", [0.0, -1.0, math.nan, -math.inf])
def test_field_models_refuse_a_non_positive_gap(model, d):
    """B_g of eq (9) is undefined for d <= 0 (it used to return a negative field at d < 0)."""
    with pytest.raises(DesignError, match="^gap_mm:"):
        vc.gap_field_T(d, PAPER, model)


def test_eq9_kernel_at_zero_gap_is_its_finite_limit():
    """The kernel itself takes the limit d -> 0 (pi/2 for the near face), no warning."""
    ref = (2 * 1.2 / math.pi) * (
        math.pi / 2 - math.atan(8 * 20 / (16 * math.sqrt(16**2 + 20**2 + 8**2)))
    )
    assert float(vc.bg_eq9_T(0.0, 20.0, 8.0, 4.0, 1.2)) == pytest.approx(ref, rel=1e-15)


# --------------------------------------------------------------------------- parameters


FIELDS = list(vc.VoiceCoilParams.__dataclass_fields__)


@pytest.mark.parametrize("field", FIELDS)
@pytest.mark.parametrize("bad", [0.0, -1.0, math.nan, math.inf, 1e101, 1e-101, True, "8", None])
def test_non_positive_or_non_numeric_parameters_are_named(field, bad):
    """Every VoiceCoilParams field: 0 (except d_r, which may be 0), negative, NaN, inf,
    a bool (used to pass as 1), a string or None (used to raise TypeError), or a
    magnitude beyond 1e+-100 (no float64 headroom left for the kernels) is named."""
    kw = {f: getattr(PAPER, f) for f in FIELDS}
    kw[field] = bad
    if field == "rattle_mm" and bad == 0.0 and not isinstance(bad, bool):
        assert vc.VoiceCoilParams(**kw).rattle_mm == 0.0
        return
    with pytest.raises(DesignError, match=f"^{field}:"):
        vc.VoiceCoilParams(**kw)


@pytest.mark.parametrize("n", [0, -3, 1.5, True])
def test_image_series_needs_a_positive_integer_slab_count(n):
    """K = 0 used to be a ZeroDivisionError in the tail, K = 1.5 silently truncated."""
    for call in (vc.bg_image_series_T, vc.image_series_tail_T):
        with pytest.raises(DesignError, match="^n_slabs:"):
            call(11.0, 20.0, 8.0, 4.0, 1.2, n)
    with pytest.raises(DesignError, match="^n_slabs:"):
        vc.gap_field_T(11.0, PAPER, "images", n_slabs=n)


def test_centerline_outside_the_gap_is_named():
    with pytest.raises(DesignError, match="^z_mm:"):
        vc.bz_centerline_eq9_T([0.0, 5.0], 10.0, 20.0, 8.0, 4.0, 1.2)


def test_infeasible_nlp_is_a_design_error_naming_the_height_bound():
    """2 alpha w_m + 2 t_m + d <= d_max cannot hold with d > d_r = 6 mm and d_max = 0.5."""
    b = vc.ActuatorBounds((1, 20), (1, 10), (1, 20), (1, 40), 0.5)
    with pytest.raises(DesignError, match="^d_max_mm:"):
        vc.optimize_actuator(PAPER, b)


# --------------------------------------------------------------------------- bracketing


@pytest.mark.parametrize("model", ["closed-form", "images"])
@pytest.mark.parametrize("k", [1e-90, 1e-6, 1e-3, 1e3, 1e6, 1e90])
def test_optimal_gap_scales_exactly_with_the_actuator(model, k):
    """Eqs (8)-(9) depend on ratios only: optimal_gap(k P) = k optimal_gap(P) and B_g is
    unchanged, from 1e-90 to 1e90 times the paper's actuator (it used to overflow,
    underflow to NaN, or stop at a search floor of 1e-6 mm)."""
    ref = vc.optimal_gap(PAPER, model)
    p = vc.VoiceCoilParams(20.0 * k, 8.0 * k, 4.0 * k, 6.0 * k)
    o = vc.optimal_gap(p, model)
    assert math.isfinite(o.optimal_gap_mm) and o.optimal_gap_mm > p.rattle_mm
    assert o.optimal_gap_mm / k == pytest.approx(ref.optimal_gap_mm, rel=1e-5)
    assert o.Bg_T == pytest.approx(ref.Bg_T, rel=1e-5)
    assert not o.at_bound


def test_huge_rattle_space_optimum_tends_to_six_fifths_of_d_r():
    """d_r >> magnets: B_g ~ d^-3, F ~ d^-3 sqrt(d - d_r), maximal at d = 1.2 d_r.
    The old default search bound d_r + 10 (l + w + t) returned d_r + 320 mm instead."""
    for dr in (1e4, 1e6):
        o = vc.optimal_gap(vc.VoiceCoilParams(20.0, 8.0, 4.0, dr))
        assert o.optimal_gap_mm / dr == pytest.approx(1.2, rel=5e-3)
        assert not o.at_bound


def test_huge_user_bound_keeps_the_bracket_and_tiny_bound_is_reported():
    """gap_max_mm = 1e300 finds the same interior optimum (the grid used to start at
    1e296 mm); a bound just above d_r returns the bound itself, flagged at_bound."""
    ref = vc.optimal_gap(PAPER)
    far = vc.optimal_gap(PAPER, gap_max_mm=1e300)
    assert far.optimal_gap_mm == pytest.approx(ref.optimal_gap_mm, rel=1e-6) and not far.at_bound
    near = vc.optimal_gap(PAPER, gap_max_mm=6.001)
    assert near.at_bound and near.optimal_gap_mm == pytest.approx(6.001, abs=1e-6)
    # it is the constrained maximum: the force still rises there
    f = vc.force_vs_gap_N([6.0009, 6.001], PAPER)
    assert f[1] > f[0] and near.force_N == pytest.approx(f[1], rel=1e-6)


@pytest.mark.parametrize("gmax", [6.0, 5.0, math.inf, math.nan, "far"])
def test_bad_gap_bounds_are_named(gmax):
    with pytest.raises(DesignError, match="^gap_max_mm:"):
        vc.optimal_gap(PAPER, gap_max_mm=gmax)


# --------------------------------------------------------------------------- PowerMouse

COILS = pm.coil_layout(30.0)


def test_full_layout_is_rank_six():
    """Reference: the cyclic layout's singular values sqrt(2) g (force) and sqrt(2) g a."""
    iso = pm.isotropy(pm.wrench_map(COILS, 2.0))
    np.testing.assert_allclose(iso.force_sv, [2 * math.sqrt(2)] * 3, rtol=1e-12)
    np.testing.assert_allclose(iso.torque_sv, [2 * math.sqrt(2) * 0.03] * 3, rtol=1e-12)


def test_missing_coil_is_named():
    """Five coils cannot drive six DOF (the map is 6 x 5)."""
    with pytest.raises(SingularJacobianError, match="only 5 coils for 6 DOF"):
        pm.isotropy(pm.wrench_map(COILS[:5], 1.0), faces=pm.FACES[:5])


@pytest.mark.parametrize("dead", range(6))
def test_zero_gain_coil_is_named_by_its_face(dead):
    """A disconnected coil (gain 0) used to give a tiny singular value and a plausible
    spread, without any error; now its face is named."""
    g = np.ones(6)
    g[dead] = 0.0
    with pytest.raises(SingularJacobianError, match=rf"coil\(s\) on \{pm.FACES[dead]} produce"):
        pm.isotropy(pm.wrench_map(COILS, g))


def test_duplicated_coil_names_the_lost_wrench():
    """Coil +x placed twice instead of -z: the map loses the combination that -z gave;
    the error names the coils whose currents cancel and the unreachable wrench."""
    coils = (*COILS[:5], COILS[0])
    faces = (*pm.FACES[:5], "+x (again)")
    with pytest.raises(SingularJacobianError) as ei:
        pm.isotropy(pm.wrench_map(coils, 1.0), faces=faces)
    msg = str(ei.value)
    assert "+x" in msg and "+x (again)" in msg and "wrench direction" in msg and "\n" not in msg


def test_vanishing_gain_threshold():
    """One coil's gain -> 0: sigma_min of the row-normalized map falls linearly with it;
    the map is declared rank deficient once sigma_min / sigma_max <= PINV_RCOND, and every
    value returned before that is finite."""
    for e in 10.0 ** -np.arange(0, 16):
        g = np.ones(6)
        g[4] = e
        W = pm.wrench_map(COILS, g)
        Wn = W.copy()
        Wn[:3] /= np.abs(Wn[:3]).max()
        Wn[3:] /= np.abs(Wn[3:]).max()
        s = np.linalg.svd(Wn, compute_uv=False)
        ratio = s[-1] / s[0]
        if ratio > 10 * tol.PINV_RCOND:
            iso = pm.isotropy(W)
            assert np.all(np.isfinite(iso.singular_values)) and math.isfinite(iso.coupling)
        elif ratio < 0.1 * tol.PINV_RCOND:
            with pytest.raises(SingularJacobianError, match="rank deficient"):
                pm.isotropy(W)


@pytest.mark.parametrize(
    "call, field",
    [
        (lambda: pm.wrench_map(COILS, math.nan), "gain_N_per_A"),
        (lambda: pm.wrench_map(COILS[:5], np.ones(6)), "gain_N_per_A"),
        (lambda: pm.wrench_map(COILS, 1.0, about_mm=(0.0, math.inf, 0.0)), "about_mm"),
        (lambda: pm.isotropy(np.ones((5, 6))), "wrench_map"),
        (lambda: pm.isotropy(np.full((6, 6), math.nan)), "wrench_map"),
        (lambda: pm.peak_force_N(-1.0), "actuator_peak_force_N"),
        (lambda: pm.peak_acceleration_m_s2(10.0, 0.0), "moving_mass_kg"),
        (lambda: pm.peak_acceleration_m_s2(10.0, math.inf), "moving_mass_kg"),
        (lambda: pm.coil_layout(-5.0), "coil_plane_half_mm"),
    ],
)
def test_bad_powermouse_inputs_are_named(call, field):
    """NaN gains used to stop in LAPACK (LinAlgError), a gain/coil count mismatch in numpy
    broadcasting (ValueError), a negative peak force gave a negative acceleration."""
    with pytest.raises(DesignError, match=f"^{field}:"):
        call()


# --------------------------------------------------------------------------- CLI

BASE = {
    "--magnet-length-mm": "20",
    "--magnet-width-mm": "8",
    "--magnet-thickness-mm": "4",
    "--rattle-mm": "6",
}
OPTIONAL = ("--power-W", "--br-T", "--rho-ohm-m", "--eta-pack", "--gap-mm", "--gap-max-mm")
EDGE_STRINGS = (
    "0",
    "-0",
    "-1",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e400",
    "1e-400",
    "abc",
    "",
    "1e300",
    "1e-300",
    "5e-324",
    "6",
    "6.0000001",
    "2",
    "0x10",
    " 7 ",
    "1_0",
)


@settings(max_examples=40, deadline=None)
@given(
    st.dictionaries(
        st.sampled_from((*BASE, *OPTIONAL)),
        st.one_of(st.sampled_from(EDGE_STRINGS), st.floats(allow_nan=True).map(repr)),
        min_size=1,
        max_size=3,
    )
)
def test_voicecoil_cli_flags_fuzzed(tmp_path_factory, flags):
    """Any value on any flag: exit 0 with one finite JSON object, or exit 2 with one
    stderr line naming a flag; never a traceback, never anything written."""
    args = {**BASE, **flags}
    tmp = tmp_path_factory.mktemp("vc")
    argv = ["voicecoil", "--json"]
    for k, v in args.items():
        argv += [k, v]
    import os

    old = os.getcwd()
    os.chdir(tmp)
    try:
        code, out, err = hapticad(*argv)
    finally:
        os.chdir(old)
    assert list(tmp.iterdir()) == []
    if code == 0:
        res = json.loads(out, parse_constant=lambda c: pytest.fail(f"{c} in JSON: {args}"))
        assert res["optimal_gap_mm"] > res["rattle_mm"] and res["force_N"] >= 0, args
        if "gap_mm" in res:
            assert res["gap_mm"] > res["rattle_mm"] and res["force_at_gap_N"] >= 0
        return
    assert code == 2, (args, err)
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("hapticad: error: "), (args, err)
    assert out == ""
    named = lines[0].removeprefix("hapticad: error: ").split(":")[0]
    assert named in (*BASE, *OPTIONAL, "force_N"), (args, lines[0])
