"""GII maximization problems in the form :mod:`cad.isotropy.culling` takes.

A problem holds M candidate parameter sets (a Cartesian grid of free
parameters, the ``[optimize]`` table: ``name = [min, max, count]``) and N
workspace samples, and evaluates sigma_min / sigma_max of the normalized
Jacobian (isotropy paper eq 2) for any list of (candidate, sample) pairs.
Samples that are unreachable or singular for a candidate give (0, 0), so the
candidate's GII is 0 (eq 5).
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping, Sequence

import numpy as np

from cad.errors import DesignError
from cad.isotropy.gii import boundary_first_order, scale_vector, singular_value_extremes
from cad.kinematics import fivebar as kfivebar
from cad.kinematics import haptic_pen as kpen
from cad.kinematics import twin_pantograph as ktwin
from cad.kinematics.delta import STATUS_OK, DeltaArrays, jacobian_kernel


def _params(params, names: Sequence[str], nonnegative: Sequence[str] = ()) -> dict[str, np.ndarray]:
    """The (M,) arrays of ``names`` from ``params``: finite, > 0 (>= 0 for ``nonnegative``)."""
    out = {}
    for name in names:
        if name not in params:
            raise DesignError(f"optimize.{name}", "missing parameter")
        try:
            v = np.asarray(params[name], dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise DesignError(
                f"optimize.{name}", f"must be numbers, got {params[name]!r}"
            ) from None
        bad = ~np.isfinite(v) | ((v < 0) if name in nonnegative else (v <= 0))
        if bad.any():
            limit = ">= 0" if name in nonnegative else "> 0"
            raise DesignError(f"optimize.{name}", f"must be finite and {limit}, got {v[bad][0]!r}")
        out[name] = v
    sizes = {v.size for v in out.values()}
    if len(sizes) > 1:
        raise DesignError("optimize", f"parameter arrays differ in length: {sorted(sizes)}")
    return out


def _points(points, d: int, grid_shape: tuple[int, ...]) -> np.ndarray:
    X = np.asarray(points, dtype=float)
    if X.ndim != 2 or X.shape[1] != d or not np.all(np.isfinite(X)):
        raise DesignError("workspace", f"samples must be finite with shape (N, {d}), got {X.shape}")
    if int(np.prod(grid_shape)) != X.shape[0]:
        raise DesignError(
            "workspace", f"grid {grid_shape} does not match the {X.shape[0]} samples given"
        )
    return X


def _positive(value, field: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise DesignError(field, f"must be a number, got {value!r}") from None
    if not (np.isfinite(v) and v > 0):
        raise DesignError(field, f"must be finite and > 0, got {value!r}")
    return v


def candidate_grid(
    ranges: Mapping[str, Sequence[float]], fixed: Mapping[str, float]
) -> tuple[list[str], dict[str, np.ndarray]]:
    """Cartesian product of ``name = (min, max, count)`` ranges, plus fixed values.

    Returns (free parameter names in the order given, {name: (M,) array} for
    every free and fixed name). Candidate k is the k-th tuple of
    ``itertools.product`` over the ranges (first name outermost).
    """
    names = list(ranges)
    axes = []
    for name in names:
        lo, hi, count = ranges[name]
        if isinstance(count, float) and count.is_integer():
            count = int(count)
        if not isinstance(count, int) or isinstance(count, bool) or count < 1:
            raise DesignError(f"optimize.{name}", f"count must be an integer >= 1, got {count!r}")
        if not (np.isfinite(lo) and np.isfinite(hi)) or hi < lo:
            raise DesignError(f"optimize.{name}", f"needs finite min <= max, got [{lo}, {hi}]")
        axes.append(np.linspace(lo, hi, count) if count > 1 else np.array([float(lo)]))
    if axes:
        grid = np.array(list(itertools.product(*axes)), dtype=float)
    else:
        grid = np.zeros((1, 0))
    M = grid.shape[0]
    params = {name: grid[:, k].copy() for k, name in enumerate(names)}
    for name, value in fixed.items():
        if name not in params:
            v = _positive(value, f"mechanism.{name}") if value != 0 else 0.0
            params[name] = np.full(M, v)
    return names, params


def centre_seed(n_per_axis: tuple[int, ...]) -> np.ndarray:
    """Index of the middle sample of a C-ordered grid (the culling seed).

    One seed is enough: every candidate is evaluated there, the one with the
    best local isotropy is completed first, and its worst samples follow.
    (Measured on the Fig. 2 problem, 6800 candidates x 121 samples: ~11k
    evaluations with the centre alone against > 34k with the four corners
    plus the centre, which cost 5 per candidate before any culling.)
    """
    mid = tuple(n // 2 for n in n_per_axis)
    return np.array([np.ravel_multi_index(mid, n_per_axis)], dtype=np.int64)


class FiveBarProblem:
    """Symmetric 5-bar over a square workspace grid (Fig. 2 study, issue 6 §3).

    params: {"base_mm", "proximal_mm", "distal_mm": (M,) arrays}; points_mm:
    (N, 2) samples from :func:`cad.isotropy.gii.square_grid_mm` with
    ``grid_n`` per side; torque_max_Nm: (2,) S_J; force_max_N: (2,) S_T.
    """

    param_names = ("base_mm", "proximal_mm", "distal_mm")

    def __init__(
        self, params, points_mm, grid_n: int, torque_max_Nm=(1.0, 1.0), force_max_N=(1.0, 1.0)
    ):
        p = _params(params, self.param_names, nonnegative=("base_mm",))
        self.a, self.l2, self.l3 = p["base_mm"], p["proximal_mm"], p["distal_mm"]
        self.grid_n = int(grid_n)
        self.points_mm = _points(points_mm, 2, (self.grid_n, self.grid_n))
        self.n_candidates = int(self.a.size)
        self.n_points = int(self.points_mm.shape[0])
        self.sj = scale_vector(torque_max_Nm, 2, "actuators.torque_max_Nm")
        self.st = scale_vector(force_max_N, 2, "actuators.force_max_N")

    def sigma(self, cand: np.ndarray, point: np.ndarray):
        a = self.a[cand]
        l2 = self.l2[cand]
        l3 = self.l3[cand]
        p = self.points_mm[point]
        J, status = kfivebar.jacobian_arrays(
            -a / 2, 0.0, a / 2, 0.0, l2, l2, l3, l3, 1.0, -1.0, p[:, 0], p[:, 1]
        )
        Jh = J * 1e3 * self.sj[:, None] / self.st[None, :]
        s0, s1 = singular_value_extremes(Jh)
        ok = status == 0
        return np.where(ok, s0, 0.0), np.where(ok, s1, 0.0)

    def point_order(self) -> np.ndarray:
        return boundary_first_order((self.grid_n, self.grid_n))

    def seed_points(self) -> np.ndarray:
        return centre_seed((self.grid_n, self.grid_n))

    def candidate(self, k: int) -> dict[str, float]:
        return {
            "base_mm": float(self.a[k]),
            "proximal_mm": float(self.l2[k]),
            "distal_mm": float(self.l3[k]),
        }


def _grid_order(shape: tuple[int, ...]) -> np.ndarray:
    return boundary_first_order(shape)


class TwinPantographProblem:
    """Twin-pantograph mouse (two identical symmetric 5-bars) over (x, y, theta) samples.

    params: base_mm, proximal_mm, distal_mm, crank_mm (M,) arrays; points:
    (N, 3) = (x_mm, y_mm, theta_rad) in C order of ``grid_shape``;
    S_J = torque_max_Nm (4,) or scalar; S_T = (F, F, M), M = moment_max_Nm or
    F * crank / 2 per candidate (eq 7).
    """

    param_names = ("base_mm", "proximal_mm", "distal_mm", "crank_mm")

    def __init__(
        self, params, points, grid_shape, torque_max_Nm=1.0, force_max_N=1.0, moment_max_Nm=None
    ):
        self.p = _params(params, self.param_names, nonnegative=("base_mm",))
        self.grid_shape = tuple(int(g) for g in grid_shape)
        self.points = _points(points, 3, self.grid_shape)
        self.n_candidates = int(self.p["base_mm"].size)
        self.n_points = int(self.points.shape[0])
        self.sj = scale_vector(torque_max_Nm, 4, "actuators.torque_max_Nm")
        self.F = _positive(force_max_N, "actuators.force_max_N")
        self.M = (
            None if moment_max_Nm is None else _positive(moment_max_Nm, "actuators.moment_max_Nm")
        )

    def sigma(self, cand, point):
        a = self.p["base_mm"][cand]
        l2 = self.p["proximal_mm"][cand]
        l3 = self.p["distal_mm"][cand]
        l6 = self.p["crank_mm"][cand]
        fb = (-a / 2, 0.0, a / 2, 0.0, l2, l2, l3, l3, 1.0, -1.0)
        X = self.points[point]
        J, status = ktwin.jacobian_arrays(fb, fb, l6, X[:, 0], X[:, 1], X[:, 2])
        M = self.F * l6 * 1e-3 / 2 if self.M is None else np.full(l6.shape, self.M)
        st = np.stack([np.full(l6.shape, self.F), np.full(l6.shape, self.F), M], axis=-1)
        Jh = J * self.sj[None, :, None] / st[:, None, :]
        s0, s1 = singular_value_extremes(Jh)
        ok = status == 0
        return np.where(ok, s0, 0.0), np.where(ok, s1, 0.0)

    def point_order(self):
        # theta has no boundary (full turn): order by the (y, x) boundary only
        ny, nx, nt = self.grid_shape
        return boundary_first_order((ny, nx, 1)).repeat(nt) * nt + np.tile(np.arange(nt), ny * nx)

    def seed_points(self):
        return centre_seed(self.grid_shape)

    def candidate(self, k: int) -> dict[str, float]:
        return {name: float(self.p[name][k]) for name in self.param_names}


class PenProblem:
    """Haptic pen (two 3-DOF 5-bars) over (x, y, z, yaw, pitch) samples.

    params: shoulder_base_mm, proximal_mm, distal_mm, pen_mm, waist_torque_ratio
    and optionally arm_spacing_mm (default = pen_mm) as (M,) arrays; points
    (N, 5) mm / rad in C order of ``grid_shape``; S_T = (F, F, F, M, M) with
    M = F * moment_arm_mm; S_J = (Q1, 1, 1, Q1, 1, 1) * torque_max_Nm.
    """

    param_names = ("shoulder_base_mm", "proximal_mm", "distal_mm", "pen_mm", "waist_torque_ratio")

    def __init__(
        self, params, points, grid_shape, torque_max_Nm=1.0, force_max_N=1.0, moment_arm_mm=35.0
    ):
        self.p = _params(params, self.param_names)
        if "arm_spacing_mm" in params:
            self.l4 = _params(params, ("arm_spacing_mm",))["arm_spacing_mm"]
        else:
            self.l4 = self.p["pen_mm"]
        self.grid_shape = tuple(int(g) for g in grid_shape)
        self.points = _points(points, 5, self.grid_shape)
        self.n_candidates = int(self.p["pen_mm"].size)
        self.n_points = int(self.points.shape[0])
        self.tau = float(scale_vector(torque_max_Nm, 1, "actuators.torque_max_Nm")[0])
        F = _positive(force_max_N, "actuators.force_max_N")
        M = F * _positive(moment_arm_mm, "actuators.moment_arm_mm") * 1e-3
        self.st = scale_vector([F, F, F, M, M], 5, "actuators.moment_arm_mm")

    def sigma(self, cand, point):
        p = {k: v[cand] for k, v in self.p.items()}
        X = self.points[point]
        J, status = kpen.jacobian_arrays(
            p["shoulder_base_mm"],
            p["proximal_mm"],
            p["distal_mm"],
            p["pen_mm"],
            self.l4[cand],
            X[:, 0],
            X[:, 1],
            X[:, 2],
            X[:, 3],
            X[:, 4],
        )
        q = p["waist_torque_ratio"]
        one = np.ones_like(q)
        sj = np.stack([q, one, one, q, one, one], axis=-1) * self.tau
        Jh = J * sj[:, :, None] / self.st[None, None, :]
        s0, s1 = singular_value_extremes(Jh)
        ok = status == 0
        return np.where(ok, s0, 0.0), np.where(ok, s1, 0.0)

    def point_order(self):
        return _grid_order(self.grid_shape)

    def seed_points(self):
        return centre_seed(self.grid_shape)

    def candidate(self, k: int) -> dict[str, float]:
        return {name: float(self.p[name][k]) for name in self.param_names}


class DeltaProblem:
    """Delta candidates over a workspace grid (C order of ``grid_shape``).

    params: {"base_radius_mm", "effector_radius_mm", "upper_arm_mm", "lower_arm_mm":
    (M,) arrays}; points_mm (N, 3); template: the design's
    :class:`cad.kinematics.delta.Delta`, whose azimuths, joint range and offsets every
    candidate keeps; torque_max_Nm (3,) or scalar S_J; force_max_N (3,) or scalar S_T
    (eqs 2-4).
    """

    param_names = ("base_radius_mm", "effector_radius_mm", "upper_arm_mm", "lower_arm_mm")

    def __init__(self, params, points_mm, grid_shape, template, torque_max_Nm=1.0,
                 force_max_N=1.0):
        self.p = _params(params, self.param_names, nonnegative=("effector_radius_mm",))
        self.grid_shape = tuple(int(g) for g in grid_shape)
        self.points_mm = _points(points_mm, 3, self.grid_shape)
        self.n_candidates = int(self.p["upper_arm_mm"].size)
        self.n_points = int(self.points_mm.shape[0])
        self.template = template
        self.sj = scale_vector(torque_max_Nm, 3, "actuators.torque_max_Nm")
        self.st = scale_vector(force_max_N, 3, "actuators.force_max_N")

    def sigma(self, cand: np.ndarray, point: np.ndarray):
        t = self.template
        d = DeltaArrays(*(self.p[n][cand] for n in self.param_names),
                        motor_azimuth_rad=t.motor_azimuth_rad, theta_min_rad=t.theta_min_rad,
                        theta_max_rad=t.theta_max_rad, joint_offset_mm=t.joint_offset_mm,
                        axis_offset_mm=t.axis_offset_mm)
        J, status = jacobian_kernel(d, self.points_mm[point])
        s0, s1 = singular_value_extremes(J * self.sj[:, None] / self.st[None, :])
        ok = status == STATUS_OK
        return np.where(ok, s0, 0.0), np.where(ok, s1, 0.0)

    def point_order(self) -> np.ndarray:
        return boundary_first_order(self.grid_shape)

    def seed_points(self) -> np.ndarray:
        return centre_seed(self.grid_shape)

    def candidate(self, k: int) -> dict[str, float]:
        return {n: float(self.p[n][k]) for n in self.param_names}
