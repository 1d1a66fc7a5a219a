"""Stability of the GII and the culling optimizer where they break (issue 7 §3).

Edges (isotropy paper eqs 2-6): workspace samples that are unreachable or singular
for the pantograph, the twin pantograph and the pen (GII = 0 and the point named,
checked against independent geometry), a sequence approaching a type-2
singularity (GII -> 0 linearly, then flagged), degenerate scalings S_J / S_T
(zero, negative, NaN, inf, strings, wrong length, units so extreme that J_hat
leaves float64), non-finite Jacobians or points, culling over all-zero
candidates, empty candidate or sample sets, NaN / negative / inconsistent
"performance" (sigma) values, and absurd magnitudes or sample counts in design
files through ``hapticad gii`` (exit 2, one line naming the field).
"""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
import tomli_w
from cli_helpers import assert_one_line_error, hapticad

from cad.errors import DesignError
from cad.isotropy import gii as g
from cad.isotropy.culling import brute_force, culling
from cad.isotropy.problems import (
    FiveBarProblem,
    PenProblem,
    TwinPantographProblem,
    candidate_grid,
)
from cad.kinematics import fivebar as f
from cad.kinematics import haptic_pen as hp
from cad.kinematics import twin_pantograph as tp
from cad.kinematics.pantograph_tolerances import ON_WAIST_AXIS_MM

DESIGNS = Path(__file__).resolve().parents[3] / "designs"

# --------------------------------------------------------------------------- failing points


def test_pen_unreachable_workspace_gives_zero_and_names_the_arm_and_point():
    """Eq (5): a pen workspace 1 m away is out of reach; GII = 0, the first sample
    named, and that sample's arm-A end really is farther than l2 + l3 from the
    left shoulder joint (cylindrical coordinates of the arm plane, issue 6 §1)."""
    pen = hp.HapticPen(60.0, 140.0, 180.0, 70.0, None, 1.75)
    r = hp.pen_gii(pen, (0.0, 1000.0, 0.0), (100.0, 100.0, 100.0), (3, 3, 3), 10.0, 1)
    assert r.gii == 0.0 and r.sigma_min == 0.0
    assert r.failure.startswith("arm A:") and "unreachable" in r.failure
    x, y, z, yaw, pitch = r.failed_at
    assert (yaw, pitch) == (0.0, 0.0)
    pa = np.array([x - 35.0, y, z])  # pen end A = centre - l6/2 u, u = x at yaw = pitch = 0
    rho = math.hypot(pa[0] - (-35.0), pa[1])  # from arm A's waist axis x = -l4/2
    assert math.hypot(pa[2] + 30.0, rho) > 140.0 + 180.0  # left shoulder at z = -l1/2
    assert r.failed_index == 0 and r.n_failed == r.n_points == 27


def test_pen_end_on_the_waist_axis_is_a_named_singularity():
    """A pen end on its waist axis leaves the waist angle undefined: GII = 0, named;
    the failing samples are exactly those with arm A's end at rho = 0."""
    pen = hp.HapticPen(60.0, 150.0, 150.0, 70.0, None, 1.75)
    r = hp.pen_gii(pen, (0.0, 0.0, 0.0), (2.0, 2.0, 2.0), (3, 3, 3), 0.0, 1)
    X = hp.workspace_grid((0.0, 0.0, 0.0), (2.0, 2.0, 2.0), (3, 3, 3), 0.0, 1)
    # yaw = pitch = 0: pen end A at x - l6/2, arm A's waist axis at x = -l4/2 (l4 = l6)
    end_a_x = X[:, 0] - 70.0 / 2
    on_axis = np.hypot(end_a_x - (-70.0 / 2), X[:, 1]) <= ON_WAIST_AXIS_MM
    assert r.gii == 0.0 and "waist axis" in r.failure and r.failure.startswith("arm A:")
    assert r.failed_index == int(np.flatnonzero(on_axis)[0])
    expected = X[r.failed_index].copy()
    expected[3:] = np.degrees(expected[3:])  # reported points carry yaw, pitch in deg
    np.testing.assert_array_equal(r.failed_at, expected)
    assert r.n_failed == int(on_axis.sum()) == 3


def test_twin_knob_singularity_named_for_every_crank_angle():
    """Knob pantograph with base 2 l3: its distal links are collinear at E = (0, l2)
    (the 5-bar reference singularity); every crank angle there fails, and only there."""
    t = tp.TwinPantograph.symmetric(300.0, 100.0, 150.0)
    r = tp.twin_gii(t, (0.0, 100.0), 10.0, 3, 4)
    assert r.gii == 0.0 and r.sigma_min == 0.0
    assert r.failure == "knob pantograph: " + f.STATUS_NAMES[f.STATUS_SINGULAR_DISTAL]
    np.testing.assert_allclose(r.failed_at, [0.0, 100.0, 0.0], atol=1e-12)
    assert r.n_failed == 4


def test_gii_goes_to_zero_linearly_then_the_singularity_is_flagged():
    """Approaching the type-2 singularity E = (0, l2 + delta) of a 5-bar with base 2 l3:
    sigma_min(J_hat) vanishes to first order (GII / delta -> const, never NaN); once
    the distal links' sine drops below DISTAL_SINGULAR_SIN the point is flagged
    "collinear" with GII exactly 0, and named."""
    l2, l3 = 100.0, 150.0
    fb = f.FiveBar.symmetric(2 * l3, l2, l3)
    ratios, flagged = [], []
    for k in range(0, 16):
        d = 10.0 ** (-k)
        E = np.array([[0.0, l2 + d]])
        J, st = f.jacobian_rad_per_m(fb, E)
        r = g.gii_from_jacobians(J, st, E, 1.0, 1.0, f.STATUS_NAMES)
        assert math.isfinite(r.gii) and math.isfinite(r.sigma_max)
        if r.failure is None:
            assert not flagged, "a flagged singularity cannot become regular closer in"
            ratios.append(r.gii / d)
        else:
            assert r.gii == 0.0 and "collinear" in r.failure
            np.testing.assert_array_equal(r.failed_at, E[0])
            flagged.append(d)
    assert len(ratios) >= 6 and flagged and max(flagged) <= 1e-7
    # first-order vanishing: GII / delta settles (to 1e-6 over the last decades)
    assert max(ratios[2:6]) / min(ratios[2:6]) - 1 < 1e-6


# --------------------------------------------------------------------------- scalings


def _eye_stack(n=3, m=2):
    return np.tile(np.eye(m), (n, 1, 1)), np.zeros(n, int), np.zeros((n, m))


@pytest.mark.parametrize(
    "sj, st, field",
    [
        (0.0, 1.0, "actuator_scale"),
        (-1.0, 1.0, "actuator_scale"),
        (math.nan, 1.0, "actuator_scale"),
        (math.inf, 1.0, "actuator_scale"),
        ((1.0, math.nan), 1.0, "actuator_scale"),
        ("one", 1.0, "actuator_scale"),
        ((1.0, 2.0, 3.0), 1.0, "actuator_scale"),
        (1.0, 0.0, "task_scale"),
        (1.0, (1.0, -2.0), "task_scale"),
        (1.0, math.nan, "task_scale"),
        (1.0, -math.inf, "task_scale"),
        (1.0, [], "task_scale"),
        (1.0, None, "task_scale"),
    ],
)
def test_degenerate_scalings_are_named(sj, st, field):
    """S_J = diag(tau_max) and S_T = diag(F, M) (eqs 3-4) must be finite and > 0."""
    J, status, pts = _eye_stack()
    with pytest.raises(DesignError, match=f"^{field}:"):
        g.gii_from_jacobians(J, status, pts, sj, st)


def test_extreme_units_do_not_change_the_gii():
    """Eq (5) is invariant to a factor on S_J and on S_T: GII with S_J ~ 1e-200 and
    S_T ~ 1e100 equals the unit-scaled GII bit for bit, and the reported singular
    values scale by S_J / S_T; beyond float64 (1e-300 / 1e300) the scale is named."""
    fb = f.FiveBar.symmetric(60.0, 100.0, 150.0)
    ref = g.fivebar_gii(fb, (0.0, 150.0), 60.0, 5, (1.0, 2.0), (3.0, 1.0))
    r = g.fivebar_gii(fb, (0.0, 150.0), 60.0, 5, (1e-200, 2e-200), (3e100, 1e100))
    assert r.gii == ref.gii and 0 < r.gii < 1
    assert r.sigma_min == pytest.approx(ref.sigma_min * 1e-300, rel=1e-12)
    assert r.sigma_max == pytest.approx(ref.sigma_max * 1e-300, rel=1e-12)
    with pytest.raises(DesignError, match="actuator_scale"):
        g.fivebar_gii(fb, (0.0, 150.0), 60.0, 5, (1e-300, 2e-300), (3e300, 1e300))


def test_non_finite_jacobian_at_an_ok_point_is_named_not_averaged():
    """A NaN or inf in J at a point whose status says ok is a bug upstream: DesignError
    naming the sample. The same NaN at a failed point is masked by its status."""
    J, status, pts = _eye_stack(4)
    pts = np.arange(8.0).reshape(4, 2)
    for bad in (math.nan, math.inf):
        Jb = J.copy()
        Jb[2, 1, 0] = bad
        with pytest.raises(DesignError, match=r"sample 2 \(point \[4\.0, 5\.0\]\)"):
            g.gii_from_jacobians(Jb, status, pts, 1.0, 1.0)
        st = status.copy()
        st[2] = 1
        r = g.gii_from_jacobians(Jb, st, pts, 1.0, 1.0, {1: "unreachable (test)"})
        assert r.gii == 0.0 and r.failure == "unreachable (test)"
        np.testing.assert_array_equal(r.failed_at, [4.0, 5.0])
    J3 = np.tile(np.eye(3), (2, 1, 1))
    J3[1, 2, 2] = math.nan  # LAPACK path (3x3) fails the same way, not with LinAlgError
    with pytest.raises(DesignError, match="sample 1"):
        g.gii_from_jacobians(J3, np.zeros(2, int), np.zeros((2, 3)), 1.0, 1.0)


def test_non_finite_points_are_named():
    J, status, pts = _eye_stack()
    pts[1, 0] = math.nan
    with pytest.raises(DesignError, match="^points:"):
        g.gii_from_jacobians(J, status, pts, 1.0, 1.0)


def test_twin_and_pen_scalings_name_the_design_key():
    """The moment scale M = F l6 / 2 (eq 7) or F * arm underflowing is named by the key
    that produced it, not by an internal array name."""
    t = tp.TwinPantograph.symmetric(75.0, 125.0, 175.0)
    with pytest.raises(DesignError, match="^actuators.force_max_N:"):
        tp.twin_gii(t, (0.0, 200.0), 100.0, 3, 2, 1.0, 5e-324)
    with pytest.raises(DesignError, match="^actuators.moment_max_Nm:"):
        tp.twin_gii(t, (0.0, 200.0), 100.0, 3, 2, 1.0, 1.0, -1.0)
    pen = hp.HapticPen(60.0, 140.0, 180.0, 70.0)
    with pytest.raises(DesignError, match="^actuators.moment_arm_mm:"):
        hp.pen_gii(pen, (0.0, 200.0, 0.0), (160.0, 100.0, 100.0), (3, 3, 3), 10.0, 1, 1.0, 1e-320)
    with pytest.raises(DesignError, match="^actuators.force_max_N:"):
        hp.pen_gii(pen, (0.0, 200.0, 0.0), (160.0, 100.0, 100.0), (3, 3, 3), 10.0, 1, math.nan)


# --------------------------------------------------------------------------- culling


class TableProblem:
    """A problem given by tables of sigma_min / sigma_max (tests the optimizers alone)."""

    def __init__(self, smin, smax):
        self.smin, self.smax = np.asarray(smin, float), np.asarray(smax, float)
        self.n_candidates, self.n_points = self.smin.shape

    def sigma(self, c, p):
        return self.smin[c, p], self.smax[c, p]

    def point_order(self):
        return np.arange(self.n_points)

    def seed_points(self):
        return np.array([0]) if self.n_points else np.zeros(0, int)


def test_all_zero_candidates_give_index_zero_and_gii_zero_for_both_methods():
    """Eq (6) when every sample fails for every candidate: GII = 0 everywhere, the first
    candidate wins the tie (numpy argmax convention), brute force and culling agree."""
    z = np.zeros((7, 5))
    rb, rc = brute_force(TableProblem(z, z)), culling(TableProblem(z, z))
    assert (rb.best_index, rb.gii) == (rc.best_index, rc.gii) == (0, 0.0)
    np.testing.assert_array_equal(rb.gii_all, np.zeros(7))
    assert rc.jacobian_evaluations <= rb.jacobian_evaluations == 35


@pytest.mark.parametrize("shape, field", [((0, 5), "optimize"), ((4, 0), "workspace")])
def test_empty_candidate_or_sample_set_is_named(shape, field):
    z = np.zeros(shape)
    for method in (brute_force, culling):
        with pytest.raises(DesignError, match=f"^{field}:"):
            method(TableProblem(z, z))


@pytest.mark.parametrize(
    "s0, s1",
    [(math.nan, 2.0), (1.0, math.nan), (1.0, math.inf), (-0.5, 2.0), (3.0, 2.0)],
)
def test_nan_or_inconsistent_performance_is_named_by_both_methods(s0, s1):
    """Singular values satisfy 0 <= sigma_min <= sigma_max < inf. A value breaking that
    (a NaN from a kernel) used to make brute force return GII = NaN at that candidate
    while culling returned another one; now both name the candidate and the sample."""
    a, b = np.full((4, 5), 1.0), np.full((4, 5), 2.0)
    a[2, 3], b[2, 3] = s0, s1
    for method in (brute_force, culling):
        with pytest.raises(DesignError, match="candidate 2 at workspace sample 3"):
            method(TableProblem(a, b))


@pytest.mark.parametrize(
    "make, field",
    [
        (
            lambda pts: FiveBarProblem(
                {"base_mm": [math.nan], "proximal_mm": [100.0], "distal_mm": [150.0]}, pts, 3
            ),
            "optimize.base_mm",
        ),
        (
            lambda pts: FiveBarProblem(
                {"base_mm": [60.0], "proximal_mm": [math.inf], "distal_mm": [150.0]}, pts, 3
            ),
            "optimize.proximal_mm",
        ),
        (
            lambda pts: FiveBarProblem(
                {"base_mm": [60.0], "proximal_mm": [100.0], "distal_mm": [150.0]},
                pts,
                3,
                (1.0, math.nan),
            ),
            "actuators.torque_max_Nm",
        ),
        (
            lambda pts: FiveBarProblem(
                {"base_mm": [60.0], "proximal_mm": [100.0], "distal_mm": [150.0]},
                pts,
                3,
                (1.0, -1.0),
            ),
            "actuators.torque_max_Nm",
        ),
        (
            lambda pts: FiveBarProblem(
                {"base_mm": [60.0], "proximal_mm": [100.0], "distal_mm": [150.0]}, pts, 3, 1.0, 0.0
            ),
            "actuators.force_max_N",
        ),
        (
            lambda pts: FiveBarProblem(
                {"base_mm": [60.0], "proximal_mm": [100.0], "distal_mm": [150.0]}, pts[:4], 3
            ),
            "workspace",
        ),
    ],
)
def test_fivebar_problem_rejects_degenerate_inputs(make, field):
    """Eq (6) over a candidate set: NaN geometry or a zero / negative / NaN scaling used to
    give GII = 0 or a plausible GII silently (a negative torque was taken as positive)."""
    pts = g.square_grid_mm((0.0, 150.0), 50.0, 3)
    with pytest.raises(DesignError, match=f"^{field}"):
        make(pts)


def test_twin_and_pen_problems_reject_degenerate_inputs():
    X3 = tp.workspace_grid((0.0, 200.0), 100.0, 3, 2)
    ok = {"base_mm": [75.0], "proximal_mm": [125.0], "distal_mm": [175.0], "crank_mm": [20.0]}
    TwinPantographProblem(ok, X3, (3, 3, 2))  # the reference case is fine
    with pytest.raises(DesignError, match="^optimize.crank_mm"):
        TwinPantographProblem({**ok, "crank_mm": [0.0]}, X3, (3, 3, 2))
    with pytest.raises(DesignError, match="^actuators.moment_max_Nm"):
        TwinPantographProblem(ok, X3, (3, 3, 2), 1.0, 1.0, math.nan)
    with pytest.raises(DesignError, match="^actuators.torque_max_Nm"):
        TwinPantographProblem(ok, X3, (3, 3, 2), (1.0, 1.0, 0.0, 1.0))
    X5 = hp.workspace_grid((0.0, 200.0, 0.0), (160.0, 100.0, 100.0), (3, 3, 3), 45.0, 1)
    pen = {
        "shoulder_base_mm": [60.0],
        "proximal_mm": [140.0],
        "distal_mm": [180.0],
        "pen_mm": [70.0],
        "waist_torque_ratio": [1.75],
    }
    PenProblem(pen, X5, (3, 3, 3, 1, 1))
    with pytest.raises(DesignError, match="^optimize.waist_torque_ratio"):
        PenProblem({**pen, "waist_torque_ratio": [-1.0]}, X5, (3, 3, 3, 1, 1))
    with pytest.raises(DesignError, match="^actuators.moment_arm_mm"):
        PenProblem(pen, X5, (3, 3, 3, 1, 1), 1.0, 1.0, 0.0)
    with pytest.raises(DesignError, match="^workspace"):
        PenProblem(pen, X5, (3, 3, 3, 3, 3))  # grid shape disagrees with the samples


def test_candidate_grid_rejects_non_finite_fixed_values():
    with pytest.raises(DesignError, match="^mechanism.distal_mm"):
        candidate_grid({"base_mm": (0.0, 50.0, 2)}, {"proximal_mm": 100.0, "distal_mm": math.nan})


# --------------------------------------------------------------------------- design files


def _design(tmp_path, name, section, key, value):
    with (DESIGNS / f"{name}.toml").open("rb") as fh:
        raw = tomllib.load(fh)
    raw.setdefault(section, {})[key] = value
    p = tmp_path / f"{name}.toml"
    p.write_text(tomli_w.dumps(raw))
    return p


@pytest.mark.parametrize(
    "name, section, key, value, needle",
    [
        ("pantograph", "mechanism", "proximal_mm", 1e300, "mechanism.proximal_mm"),
        ("pantograph", "mechanism", "distal_mm", 1e-300, "mechanism.distal_mm"),
        ("pantograph", "workspace", "side_mm", 1.7e308, "workspace.side_mm"),
        ("pantograph", "workspace", "center_mm", [0.0, -1e300], "workspace.center_mm"),
        ("pantograph", "actuators", "torque_max_Nm", 5e-324, "actuators.torque_max_Nm"),
        ("pantograph", "workspace", "grid", 100_000, "workspace.grid"),
        ("pantograph", "optimize", "distal_mm", [25.0, 500.0, 10**9], "optimize"),
        ("haptic_mouse", "mechanism", "knob_diameter_mm", 1.7e308, "mechanism.knob_diameter_mm"),
        ("haptic_mouse", "workspace", "theta_grid", 10**6, "workspace.grid"),
        ("haptic_mouse", "actuators", "moment_max_Nm", 1e-300, "actuators.moment_max_Nm"),
        ("haptic_pen", "actuators", "moment_arm_mm", 1e300, "actuators.moment_arm_mm"),
        ("haptic_pen", "workspace", "rotation_grid", 10**5, "workspace.grid"),
        ("haptic_pen", "mechanism", "waist_torque_ratio", 1e-300, "mechanism.waist_torque_ratio"),
    ],
)
def test_absurd_magnitudes_and_sample_counts_exit_2_one_line(
    tmp_path, name, section, key, value, needle
):
    """Before the bounds these overflowed in the IK (RuntimeWarning: two more stderr lines),
    asked numpy for terabytes (MemoryError traceback), reported a false "singular" GII = 0
    (pen moment arm 1e300) or a wrong GII by denormal round-off (torque 5e-324: 0.455
    instead of 0.623)."""
    code, out, err = hapticad("gii", _design(tmp_path, name, section, key, value), "--json")
    assert_one_line_error(code, err, needle)
    assert out == ""


def test_bounds_leave_the_bundled_designs_unchanged():
    """The bundled designs sit well inside the bounds: their GII is as before (docs/papers.md)."""
    for name, ref in (
        ("pantograph", 0.6232007997359527),
        ("haptic_mouse", 0.20744437413513309),
        ("haptic_pen", 0.4637387645509308),
    ):
        code, out, err = hapticad("gii", DESIGNS / f"{name}.toml", "--json")
        assert code == 0, err
        assert json.loads(out)["gii"] == pytest.approx(ref, rel=1e-12)
