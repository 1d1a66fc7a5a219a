"""Global isotropy index over a sampled workspace (isotropy paper eqs 2-5).

The Jacobian J (q_dot = J x_dot, so f = J^T tau, eq 1) is normalized by the
actuator and task scaling matrices

    J_hat = S_J J S_T^-1,  S_J = diag(tau_max_i),  S_T = diag(F_i, ..., M_i)   (eqs 2-4)

and the GII of a design is the worst smallest singular value over the
workspace divided by the worst largest one (eq 5):

    GII = min_x0 sigma_min(J_hat(x0)) / max_x1 sigma_max(J_hat(x1)).

0 <= GII <= 1; GII = 1 only if J_hat is isotropic with the same singular value
everywhere. A sampled point that is unreachable or singular makes GII = 0 and
the result names it. Units: J in SI (rad/m for translations, rad/rad for
rotations), S_J in N m, S_T in N (forces) and N m (moments), so J_hat is
dimensionless. Workspace points are in mm (reporting only).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from cad.errors import DesignError
from cad.kinematics import delta as kdelta
from cad.kinematics import fivebar as kfivebar


def scale_vector(values, n: int, name: str) -> np.ndarray:
    try:
        v = np.asarray(values, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise DesignError(name, f"must be {n} numbers (or one), got {values!r}") from None
    if v.size == 1:
        v = np.full(n, float(v[0]))
    if v.size != n:
        raise DesignError(name, f"must have {n} entries, got {v.size}")
    if not np.all(np.isfinite(v)) or np.any(v <= 0):
        raise DesignError(name, f"must be finite and > 0, got {v.tolist()!r}")
    return v


def normalized_jacobian(J: np.ndarray, actuator_scale, task_scale) -> np.ndarray:
    """J_hat = S_J J S_T^-1 (isotropy paper eq 2) for a stack of Jacobians.

    J: (..., m, n) with m actuators (rows) and n task coordinates (columns).
    actuator_scale: (m,) maximum actuator torques [N m] (S_J, eq 3); a scalar
    is broadcast. task_scale: (n,) required forces [N] / moments [N m]
    (S_T, eq 4). Returns an array shaped like J.
    """
    J = np.asarray(J, dtype=float)
    if J.ndim < 2:
        raise DesignError("jacobian", f"must be at least 2-D (..., m, n), got shape {J.shape}")
    m, n = J.shape[-2:]
    sj = scale_vector(actuator_scale, m, "actuator_scale")
    st = scale_vector(task_scale, n, "task_scale")
    return J * sj[:, None] / st[None, :]


def singular_value_extremes(A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Smallest and largest singular values of a stack of matrices (..., m, n).

    2x2 uses the closed form sigma = |Q +- R| with Q = |((a+d)/2, (c-b)/2)|,
    R = |((a-d)/2, (c+b)/2)| (exact, elementwise, so batching never changes a
    value); anything else uses LAPACK (``numpy.linalg.svd``). For m != n the
    smallest of the min(m, n) singular values is returned.
    """
    A = np.asarray(A, dtype=float)
    if A.shape[-2:] == (2, 2):
        a, b = A[..., 0, 0], A[..., 0, 1]
        c, d = A[..., 1, 0], A[..., 1, 1]
        Q = np.hypot(0.5 * (a + d), 0.5 * (c - b))
        R = np.hypot(0.5 * (a - d), 0.5 * (c + b))
        return np.abs(Q - R), Q + R
    if A.size == 0:
        shape = A.shape[:-2]
        return np.zeros(shape), np.zeros(shape)
    s = np.linalg.svd(A, compute_uv=False)
    return s[..., -1], s[..., 0]


def gii_ratio(sigma_min: np.ndarray, sigma_max: np.ndarray) -> np.ndarray:
    """sigma_min / sigma_max with 0/0 -> 0 (no valid point at all)."""
    sigma_min = np.asarray(sigma_min, dtype=float)
    sigma_max = np.asarray(sigma_max, dtype=float)
    safe = np.where(sigma_max > 0, sigma_max, 1.0)
    return np.where(sigma_max > 0, sigma_min / safe, 0.0)


@dataclass(frozen=True)
class GIIResult:
    """GII of one design over sampled workspace points (eq 5).

    gii: the index (0..1). sigma_min / sigma_max: the extremes of the normalized
    Jacobian's singular values and the indices / coordinates of the points where
    they occur (``*_at`` in the units of the points given, mm for positions).
    failure / failed_index / failed_at: the first unreachable or singular point
    (then gii = sigma_min = 0), else None. jacobian_evaluations: points sampled.
    """

    gii: float
    sigma_min: float
    sigma_max: float
    sigma_min_index: int
    sigma_max_index: int
    sigma_min_at: np.ndarray
    sigma_max_at: np.ndarray
    n_points: int
    jacobian_evaluations: int
    failure: str | None = None
    failed_index: int | None = None
    failed_at: np.ndarray | None = field(default=None)
    n_failed: int = 0


def _checked_samples(J, status, points) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Validated (J (N, m, n), status (N,), points (N, d), ok (N,) bool) of :func:`gii_from_jacobians`.

    Raises :class:`DesignError` on shapes that disagree, non-finite points, or a
    non-finite J at a point whose status is ok.
    """
    J = np.asarray(J, dtype=float)
    status = np.asarray(status).reshape(-1)
    points = np.asarray(points, dtype=float)
    if J.ndim != 3 or J.shape[0] == 0:
        raise DesignError("jacobian", f"must have shape (N, m, n) with N >= 1, got {J.shape}")
    if status.shape[0] != J.shape[0] or points.shape[0] != J.shape[0]:
        raise DesignError(
            "jacobian",
            f"J, status and points disagree on N: {J.shape[0]}, {status.shape[0]}, {points.shape[0]}",
        )
    ok = status == 0
    if points.ndim != 2 or not np.all(np.isfinite(points)):
        raise DesignError("points", f"must be finite with shape (N, d), got shape {points.shape}")
    bad = ok & ~np.all(np.isfinite(J), axis=(1, 2))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise DesignError(
            "jacobian",
            f"non-finite entries at sample {i} (point {points[i].tolist()}) whose status is ok: "
            "a failed point must carry a non-zero status, never NaN",
        )
    return J, status, points, ok


def _normalized_singular_values(J, ok, points, sj, st) -> tuple[np.ndarray, np.ndarray]:
    """(sigma_min (N,), sigma_max (N,)) of J_hat with S_J and S_T scaled to a largest entry of 1.

    Failed samples (``ok`` false) get 0 for both. Raises :class:`DesignError`
    ("task_scale") when J_hat overflows float64.
    """
    # eq (5) is invariant to a uniform factor on S_J and on S_T: evaluate with both
    # normalized to a largest entry of 1 (no over/underflow from the units chosen),
    # then report the singular values in the caller's units.
    with np.errstate(over="ignore", invalid="ignore"):
        Jh = np.where(ok[:, None, None], J, 0.0) * (sj / sj.max())[:, None] / (st / st.max())
    over = ~np.all(np.isfinite(Jh), axis=(1, 2))
    if over.any():
        i = int(np.flatnonzero(over)[0])
        raise DesignError(
            "task_scale",
            f"J_hat = S_J J S_T^-1 overflows float64 at sample {i} (point {points[i].tolist()}): "
            f"the entries of S_T span {np.log10(st.max()) - np.log10(st.min()):.0f} decades",
        )
    smin, smax = singular_value_extremes(Jh)
    return np.where(ok, smin, 0.0), np.where(ok, smax, 0.0)


def _in_caller_units(smin_i: float, smax_i: float, k: float) -> tuple[float, float]:
    """(sigma_min, sigma_max) of normalized J_hat times k = max S_J / max S_T.

    Raises :class:`DesignError` ("actuator_scale") when the product leaves float64.
    """
    with np.errstate(over="ignore", under="ignore"):
        s_min, s_max = float(smin_i * k), float(smax_i * k)
    if (
        not (np.isfinite(s_max) and np.isfinite(s_min))
        or (s_max == 0.0 and smax_i > 0)
        or (s_min == 0.0 and smin_i > 0)
    ):
        raise DesignError(
            "actuator_scale",
            f"S_J / S_T = {k:.3g} puts the singular values of J_hat = S_J J S_T^-1 outside "
            "float64: give torques in N m and forces in N",
        )
    return s_min, s_max


def _first_failure(status, ok, points, smin, i_min, status_names):
    """(failure text | None, failed_index | None, failed_at (d,) | None, n_failed, i_min).

    The first sample whose status is not ok, else the first with sigma_min = 0;
    i_min moves to a failed status sample so that sigma_min_at points at it.
    """
    n_failed = int(np.count_nonzero(~ok))
    if n_failed:
        failed_index = int(np.flatnonzero(~ok)[0])
        code = int(status[failed_index])
        failure = (status_names or {}).get(code, f"status {code}")
        return failure, failed_index, points[failed_index].copy(), n_failed, failed_index
    if smin[i_min] == 0.0:
        n_failed = int(np.count_nonzero(smin == 0.0))
        return "singular: sigma_min(J_hat) = 0", i_min, points[i_min].copy(), n_failed, i_min
    return None, None, None, 0, i_min


def gii_from_jacobians(
    J: np.ndarray,
    status: np.ndarray,
    points: np.ndarray,
    actuator_scale,
    task_scale,
    status_names: dict[int, str] | None = None,
) -> GIIResult:
    """GII (eq 5) from Jacobians sampled at workspace points.

    J: (N, m, n) SI Jacobians; status: (N,) int, 0 = ok, anything else names a
    failure through ``status_names``; points: (N, d) coordinates of the
    samples, reported back. Scales as :func:`normalized_jacobian`.

    Bad input is a :class:`DesignError`: non-finite J at a point whose status is
    ok (a failure must be a status, never a NaN), non-finite points, scales that
    are not finite and > 0, or scales that push J_hat out of float64. The
    singular values are computed with S_J and S_T divided by their largest
    entry (eq 5 is invariant to that), so the units chosen cannot lose
    precision; ``sigma_min`` / ``sigma_max`` are reported in the given units.
    """
    J, status, points, ok = _checked_samples(J, status, points)
    m, n = J.shape[1:]
    sj = scale_vector(actuator_scale, m, "actuator_scale")
    st = scale_vector(task_scale, n, "task_scale")
    smin, smax = _normalized_singular_values(J, ok, points, sj, st)
    i_min = int(np.argmin(smin))
    i_max = int(np.argmax(smax))
    gii = float(gii_ratio(smin[i_min], smax[i_max]))
    s_min, s_max = _in_caller_units(smin[i_min], smax[i_max], sj.max() / st.max())
    failure, failed_index, failed_at, n_failed, i_min = _first_failure(
        status, ok, points, smin, i_min, status_names)
    return GIIResult(
        gii=gii,
        sigma_min=s_min,
        sigma_max=s_max,
        sigma_min_index=i_min,
        sigma_max_index=i_max,
        sigma_min_at=points[i_min].copy(),
        sigma_max_at=points[i_max].copy(),
        n_points=int(J.shape[0]),
        jacobian_evaluations=int(J.shape[0]),
        failure=failure,
        failed_index=failed_index,
        failed_at=failed_at,
        n_failed=n_failed,
    )


def _check_grid(n, field_name: str) -> int:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 2:
        raise DesignError(
            field_name, f"must be an integer >= 2 (the boundary is sampled), got {n!r}"
        )
    return int(n)


def size_pair_mm(side_mm, field_name: str = "workspace.side_mm") -> tuple[float, float]:
    """(W, H) mm of a planar workspace: a square's side (scalar) or a rectangle's [W, H].

    Raises DesignError naming ``field_name`` for a value that is not one or two finite
    numbers > 0."""
    a = np.asarray(side_mm, dtype=float).reshape(-1) if np.ndim(side_mm) else np.array([side_mm] * 2, float)
    if a.size != 2 or not np.all(np.isfinite(a)) or np.any(a <= 0):
        raise DesignError(field_name, f"must be > 0 (a side or [W, H]), got {side_mm!r}")
    return float(a[0]), float(a[1])


def workspace_half_mm(ws: dict) -> tuple[float, float]:
    """Half extents (W/2, H/2) mm of a planar design's ``[workspace]`` (its ``size_mm``)."""
    w, h = size_pair_mm(ws["size_mm"], "workspace.size_mm")
    return w / 2, h / 2


def square_grid_mm(center_mm, side_mm, n: int) -> np.ndarray:
    """n x n grid over a square or rectangular workspace, boundary included, (n*n, 2) mm.

    center_mm: (x, y) of the centre, base frame; side_mm: a square's side, or [W, H] of a
    rectangle (W along x, H along y; ``[workspace] size_mm``). Points are ordered row by
    row (y outer, x inner). Raises DesignError naming the workspace field.
    """
    n = _check_grid(n, "workspace.grid")
    c = np.asarray(center_mm, dtype=float).reshape(-1)
    if c.size != 2 or not np.all(np.isfinite(c)):
        raise DesignError("workspace.center_mm", f"must be a finite [x, y], got {center_mm!r}")
    w, h = size_pair_mm(side_mm, "workspace.size_mm" if np.ndim(side_mm) else "workspace.side_mm")
    t = np.linspace(-0.5, 0.5, n)
    X, Y = np.meshgrid(c[0] + t * w, c[1] + t * h)
    return np.stack([X.ravel(), Y.ravel()], axis=-1)


def boundary_first_order(n_per_axis: tuple[int, ...]) -> np.ndarray:
    """Indices of a C-ordered grid sorted corners first, then edges, then interior.

    For a grid with ``n_per_axis`` samples along each axis (C order, last axis
    fastest). Extremes of sigma usually lie on the workspace boundary, so the
    culling optimizer samples there first; only the count of evaluations
    depends on this order, never the optimum.
    """
    idx = np.indices(n_per_axis).reshape(len(n_per_axis), -1)
    on_bound = np.zeros(idx.shape[1], dtype=int)
    for ax, n in enumerate(n_per_axis):
        if n > 1:
            on_bound += (idx[ax] == 0) | (idx[ax] == n - 1)
    return np.argsort(-on_bound, kind="stable")


def fivebar_gii(
    fb,
    center_mm,
    side_mm,
    grid: int,
    torque_max_Nm=1.0,
    force_max_N=1.0,
) -> GIIResult:
    """GII of a 5-bar over a square (side_mm scalar) or rectangular (side_mm = [W, H])
    workspace (eqs 2-5), grid incl. boundary.

    fb: :class:`cad.kinematics.fivebar.FiveBar`; torque_max_Nm: (2,) or scalar
    (S_J); force_max_N: (2,) or scalar (S_T). Equal scalars leave the GII that
    of the plain Jacobian (uniform scaling does not change it).
    """
    pts = square_grid_mm(center_mm, side_mm, grid)
    J, status = kfivebar.jacobian_rad_per_m(fb, pts)
    return gii_from_jacobians(J, status, pts, torque_max_Nm, force_max_N, kfivebar.STATUS_NAMES)


def delta_gii(d, points_mm, torque_max_Nm=1.0, force_max_N=1.0) -> GIIResult:
    """GII (eqs 2-5) of a 3-DOF delta over workspace points ``points_mm`` (N, 3), mm.

    d: :class:`cad.kinematics.delta.Delta`; torque_max_Nm (3,) or scalar (S_J);
    force_max_N (3,) or scalar (S_T). A point outside the reachable, regular, in-limits
    workspace makes the GII 0 and is named (:data:`cad.kinematics.delta.STATUS_NAMES`).
    """
    J, status = kdelta.jacobian_rad_per_m(d, points_mm)
    return gii_from_jacobians(J, status, np.asarray(points_mm, float), torque_max_Nm,
                              force_max_N, kdelta.STATUS_NAMES)
