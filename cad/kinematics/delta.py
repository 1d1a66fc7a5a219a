"""3-DOF delta (Clavel) kinematics: closed-form IK and FK, the Jacobian, vectorized.

Geometry (issue 36 §2). Base frame: origin at the centre of the base, z up, the effector
below the base (z < 0). Motor i (i = 0, 1, 2) sits at azimuth ``phi_i`` (0°, 120°, 240° for
the symmetric delta) at radius ``R`` (``base_radius_mm``), its axis horizontal and tangent to
the base circle; u_i = (cos phi_i, sin phi_i, 0) is its radial direction. The upper arm of
length ``L_a`` turns by the joint angle theta_i, measured from the horizontal radial
direction u_i, positive DOWNWARD (the convention of Clavel's delta and of R. L. Williams II,
"The Delta Parallel Robot: Kinematics Solutions", 2016). The elbow is

    E_i = R u_i + L_a (cos theta_i u_i - sin theta_i z).

The parallelogram lower arm of length ``L_b`` joins E_i to the effector joint P + r u_i
(``r`` = ``effector_radius_mm``; the effector translates, the parallelograms keep it level),
so with the shifted elbow C_i = E_i - r u_i every arm states one sphere:

    |P - C_i(theta_i)|^2 = L_b^2.                                              (1)

IK (per arm, closed form). In the arm's plane, with x' = u_i . P - (R - r),
y' = (z x u_i) . P, z = P_z, equation (1) is A cos theta + B sin theta = K with
A = 2 L_a x', B = -2 L_a z, K = x'^2 + y'^2 + z^2 + L_a^2 - L_b^2, whose two roots
atan2(B, A) +- acos(K / sqrt(A^2 + B^2)) are the two branches of the arm. Branch stated: ``elbow out``, the root whose elbow lies farther from
the z axis (the larger cos theta), the configuration of the Falcon and of every delta built.

FK (closed form): the intersection of the three spheres (1); of its two points the lower
one (the effector below the plane of the three shifted elbows) is the assembly mode.

Jacobian: differentiating (1), A_x x_dot + diag(b) theta_dot = 0 with rows
A_x[i] = (P - C_i)^T and b_i = -(P - C_i) . dC_i/dtheta_i, so

    theta_dot = J x_dot,   J = -diag(b)^-1 A_x,   f = J^T tau                  (2)

(the convention of the isotropy paper eq 1 and of :mod:`cad.kinematics.fivebar`).
Singularities, named: serial (an arm's lower arm perpendicular to its elbow's velocity,
b_i = 0: the arm fully stretched or folded against its reach; J unbounded) and parallel
(the three lower arms parallel to one plane, det A_x = 0: the effector cannot resist a
force along that plane's normal; J loses rank). Joint limits: the design's motor angle
range. Failures are status codes (:data:`STATUS_NAMES`), never NaN.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cad.errors import DesignError, KinematicsError
from cad.tolerances import (
    DELTA_FK_NEWTON_STEPS,
    DELTA_FK_RESIDUAL_REL,
    DELTA_PARALLEL_SINGULAR,
    DELTA_SERIAL_SINGULAR,
    REACH_REL_EPS,
)

STATUS_OK = 0
STATUS_UNREACHABLE = 1
STATUS_JOINT_LIMIT = 2
STATUS_SINGULAR_SERIAL = 3
STATUS_SINGULAR_PARALLEL = 4
STATUS_NO_ASSEMBLY = 5

#: status code -> reason (messages and reports).
STATUS_NAMES: dict[int, str] = {
    STATUS_OK: "ok",
    STATUS_UNREACHABLE: "unreachable: an arm cannot reach (|K| > sqrt(A^2 + B^2) in its IK)",
    STATUS_JOINT_LIMIT: "outside the motor angle range",
    STATUS_SINGULAR_SERIAL: "singular (serial): a lower arm perpendicular to its elbow's path",
    STATUS_SINGULAR_PARALLEL: "singular (parallel): the three lower arms parallel to one plane",
    STATUS_NO_ASSEMBLY: "the three lower arms cannot meet (the spheres do not intersect)",
}

UNREACHABLE_CODES = (STATUS_UNREACHABLE, STATUS_NO_ASSEMBLY)
SINGULAR_CODES = (STATUS_SINGULAR_SERIAL, STATUS_SINGULAR_PARALLEL)


@dataclass(frozen=True)
class Delta:
    """A delta's kinematic parameters (mm, rad); :meth:`symmetric` for motors 120° apart.

    base_radius_mm R: motor axes' distance from the z axis. effector_radius_mm r: the lower
    arms' effector joints' distance from the effector centre. upper_arm_mm L_a, lower_arm_mm
    L_b (the parallelogram's length). motor_azimuth_rad: (3,) phi_i. theta_min_rad /
    theta_max_rad: the motor angle range (joint limits), same for every motor.
    Two offsets of Stamper's model of the Novint Falcon (R. E. Stamper, PhD thesis, U.
    Maryland 1997, as libnifalcon implements it; 0 for Clavel's delta): ``joint_offset_mm`` g,
    the sum of the knee and effector universal joints' offsets along the lower arm's
    projection in the arm's plane (the in-plane distance knee -> effector joint is
    L_b sin(theta_3) + g), and ``axis_offset_mm`` delta, the effector joint's offset from the
    base joint along the motor axis t_i = z x u_i.
    Raises :class:`DesignError` naming the field on a non-finite or non-positive length.
    """

    base_radius_mm: float
    effector_radius_mm: float
    upper_arm_mm: float
    lower_arm_mm: float
    motor_azimuth_rad: tuple[float, float, float] = (0.0, 2 * np.pi / 3, 4 * np.pi / 3)
    theta_min_rad: float = -np.pi / 2
    theta_max_rad: float = np.pi / 2
    joint_offset_mm: float = 0.0
    axis_offset_mm: float = 0.0

    def __post_init__(self) -> None:
        for name in ("joint_offset_mm", "axis_offset_mm"):
            if not np.isfinite(float(getattr(self, name))):
                raise DesignError(f"delta.{name}", f"must be finite, got {getattr(self, name)!r}")
        if self.joint_offset_mm < 0:
            raise DesignError("delta.joint_offset_mm", f"must be >= 0, got {self.joint_offset_mm!r}")
        for name in ("base_radius_mm", "upper_arm_mm", "lower_arm_mm"):
            v = float(getattr(self, name))
            if not np.isfinite(v) or v <= 0:
                raise DesignError(f"delta.{name}", f"must be > 0, got {v!r}")
        r = float(self.effector_radius_mm)
        if not np.isfinite(r) or r < 0:
            raise DesignError("delta.effector_radius_mm", f"must be >= 0, got {r!r}")
        if len(self.motor_azimuth_rad) != 3 or not np.all(np.isfinite(self.motor_azimuth_rad)):
            raise DesignError("delta.motor_azimuth_rad", "must be 3 finite angles")
        if not self.theta_min_rad < self.theta_max_rad:
            raise DesignError(
                "delta.theta_max_rad",
                f"must exceed theta_min_rad ({self.theta_min_rad!r}), got {self.theta_max_rad!r}",
            )

    @property
    def radial(self) -> np.ndarray:
        """(3, 3) u_i: each motor's radial unit vector (rows), base frame."""
        phi = np.asarray(self.motor_azimuth_rad, dtype=float)
        return np.stack([np.cos(phi), np.sin(phi), np.zeros(3)], axis=-1)

    @property
    def tangential(self) -> np.ndarray:
        """(3, 3) t_i = z x u_i: each motor's axis direction (rows), base frame."""
        phi = np.asarray(self.motor_azimuth_rad, dtype=float)
        return np.stack([-np.sin(phi), np.cos(phi), np.zeros(3)], axis=-1)

    def shifted_elbows_mm(self, theta_rad) -> np.ndarray:
        """C_i (..., 3, 3): the elbows less r u_i at joint angles ``theta_rad`` (..., 3)."""
        return _shifted_elbows(self, np.asarray(theta_rad, dtype=float))


@dataclass(frozen=True)
class DeltaArrays:
    """K deltas at once for the array kernels (the GII optimizer's candidates): the length
    fields of :class:`Delta` as (K,) arrays (mm), one azimuth set and joint range for all.
    No validation (the caller's candidate grid is checked)."""

    base_radius_mm: np.ndarray
    effector_radius_mm: np.ndarray
    upper_arm_mm: np.ndarray
    lower_arm_mm: np.ndarray
    motor_azimuth_rad: tuple[float, float, float] = (0.0, 2 * np.pi / 3, 4 * np.pi / 3)
    theta_min_rad: float = -np.pi / 2
    theta_max_rad: float = np.pi / 2
    joint_offset_mm: float = 0.0
    axis_offset_mm: float = 0.0

    radial = Delta.radial
    tangential = Delta.tangential


def _lengths(d) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(R - r, L_a, L_b) as arrays: 0-d for a :class:`Delta`, (K,) for :class:`DeltaArrays`."""
    return (np.asarray(d.base_radius_mm, float) - np.asarray(d.effector_radius_mm, float),
            np.asarray(d.upper_arm_mm, float), np.asarray(d.lower_arm_mm, float))


def _shifted_elbows(d, t: np.ndarray) -> np.ndarray:
    rr, la, _ = _lengths(d)
    C = (rr[..., None] + la[..., None] * np.cos(t))[..., None] * d.radial
    C = C + d.axis_offset_mm * d.tangential
    C[..., 2] = -la[..., None] * np.sin(t)
    return C


@dataclass(frozen=True)
class DeltaPose:
    """Configurations at N points (base frame, mm / rad).

    P_mm (N, 3) effector centre; theta_rad (N, 3) joint angles; status (N,) codes of
    :data:`STATUS_NAMES`. Entries of unreachable points are 0, not NaN.
    """

    P_mm: np.ndarray
    theta_rad: np.ndarray
    status: np.ndarray

    @property
    def ok(self) -> np.ndarray:
        """(N,) bool: reachable, inside the joint limits and regular."""
        return self.status == STATUS_OK

    def describe(self, i: int) -> str:
        """One line naming point ``i`` and its status."""
        x, y, z = self.P_mm[i]
        return f"P = ({x:.3f}, {y:.3f}, {z:.3f}) mm: {STATUS_NAMES[int(self.status[i])]}"


def _points(P_mm, field: str = "P_mm") -> np.ndarray:
    P = np.asarray(P_mm, dtype=float)
    if P.ndim == 1:
        P = P[None, :]
    if P.ndim != 2 or P.shape[1] != 3 or not np.all(np.isfinite(P)):
        raise DesignError(field, f"must be finite with shape (N, 3), got {np.shape(P_mm)}")
    return P


def _arm_ik(d: Delta, P: np.ndarray, i: int) -> tuple[np.ndarray, np.ndarray]:
    """Arm i's joint angle (N,) and its unreachable flags (N,) at effector points P (N, 3).

    In the arm's plane (x' radial from the shifted base joint, y' along the motor axis less
    the axis offset, z), the in-plane distance knee -> effector joint is
    rho = g + sqrt(L_b^2 - y'^2), so (x' - L_a cos t)^2 + (z + L_a sin t)^2 = rho^2, i.e.
    A cos t + B sin t = K with A = 2 L_a x', B = -2 L_a z, K = x'^2 + z^2 + L_a^2 - rho^2;
    t = atan2(B, A) + acos(K / sqrt(A^2 + B^2)) (elbow out: the root with the larger cos t,
    i.e. the elbow farther out). With g = 0 this is the sphere of Clavel's delta.
    """
    u = d.radial[i]
    rr, la, lb = _lengths(d)
    xp = P @ u - rr
    yp = P @ d.tangential[i] - d.axis_offset_mm
    z = P[:, 2]
    off_axis = np.abs(yp) > lb * (1 + REACH_REL_EPS)
    rho = d.joint_offset_mm + np.sqrt(np.clip(lb * lb - yp * yp, 0.0, None))
    A, B = 2 * la * xp, -2 * la * z
    K = xp * xp + z * z + la * la - rho * rho
    norm = np.hypot(A, B)
    c = K / np.where(norm > 0, norm, 1.0)
    unreachable = (np.abs(c) > 1 + REACH_REL_EPS) | off_axis
    base = np.arctan2(B, A)
    roots = base[:, None] + np.array([1.0, -1.0]) * np.arccos(np.clip(c, -1, 1))[:, None]
    pick = np.argmax(np.cos(roots), axis=1)
    t = np.take_along_axis(roots, pick[:, None], axis=1)[:, 0]
    t = np.angle(np.exp(1j * t))  # wrapped to (-pi, pi]
    return np.where(unreachable, 0.0, t), unreachable


def _status(d: Delta, P: np.ndarray, theta: np.ndarray, unreachable: np.ndarray) -> np.ndarray:
    """Status codes (N,) at consistent (P, theta); precedence: reach, limits, singular."""
    A, b = _constraint_jacobians(d, P, theta)
    _, la, lb = _lengths(d)
    serial = np.min(np.abs(b), axis=1) / (la * lb)
    parallel = np.abs(np.linalg.det(A)) / lb**3
    limits = (theta < d.theta_min_rad) | (theta > d.theta_max_rad)
    status = np.full(P.shape[0], STATUS_OK, dtype=np.int8)
    status = np.where(parallel < DELTA_PARALLEL_SINGULAR, STATUS_SINGULAR_PARALLEL, status)
    status = np.where(serial < DELTA_SERIAL_SINGULAR, STATUS_SINGULAR_SERIAL, status)
    status = np.where(np.any(limits, axis=1), STATUS_JOINT_LIMIT, status)
    return np.where(unreachable, STATUS_UNREACHABLE, status).astype(np.int8)


def _constraint_jacobians(d: Delta, P: np.ndarray, theta: np.ndarray):
    """A_x (N, 3, 3) = d f_i/dP / 2 and b (N, 3) = d f_i/dtheta_i / 2 (mm^2) of the arm
    constraints f_i = (rho_i - g)^2 + y'_i^2 - L_b^2 (rho_i the in-plane distance knee ->
    effector joint); with w = P - C_i and w_p its part in the arm's plane,
    A_x[i] = w - (g / rho) w_p and b_i = -(1 - g / rho) w_p . dC_i/dtheta_i (g = 0: the
    sphere's (P - C_i) and -(P - C_i) . dC_i/dtheta_i)."""
    C = _shifted_elbows(d, theta)
    w = P[:, None, :] - C
    t = d.tangential
    wp = w - np.einsum("nij,ij->ni", w, t)[..., None] * t
    rho = np.linalg.norm(wp, axis=-1)
    k = d.joint_offset_mm / np.where(rho > 0, rho, 1.0)
    A = w - k[..., None] * wp
    _, la, _ = _lengths(d)
    dC = -la[..., None, None] * np.sin(theta)[..., None] * d.radial
    dC[..., 2] = -la[..., None] * np.cos(theta)
    b = -(1 - k) * np.einsum("nij,nij->ni", wp, dC)
    return A, b


def ik(d: Delta, P_mm) -> DeltaPose:
    """Inverse kinematics at effector points ``P_mm`` (N, 3), base frame, mm (elbow out)."""
    P = _points(P_mm)
    arms = [_arm_ik(d, P, i) for i in range(3)]
    theta = np.stack([a[0] for a in arms], axis=-1)
    unreachable = np.any(np.stack([a[1] for a in arms], axis=-1), axis=1)
    return DeltaPose(P_mm=P, theta_rad=theta, status=_status(d, P, theta, unreachable))


def fk(d: Delta, theta_rad) -> DeltaPose:
    """Forward kinematics at joint angles ``theta_rad`` (N, 3): the lower intersection of
    the three spheres (1) (closed form); with a joint offset g > 0 (Stamper's Falcon model)
    that point for spheres of radius L_b + g, refined by Newton's method on the arm
    constraints to round-off (:data:`cad.tolerances.DELTA_FK_NEWTON_STEPS` steps). Points
    where the arms cannot meet get :data:`STATUS_NO_ASSEMBLY` and P = 0. Raises
    :class:`DesignError` on a non-finite or mis-shaped input."""
    t = np.asarray(theta_rad, dtype=float)
    t = t[None, :] if t.ndim == 1 else t
    if t.ndim != 2 or t.shape[1] != 3 or not np.all(np.isfinite(t)):
        raise DesignError("theta_rad", f"must be finite with shape (N, 3), got {np.shape(theta_rad)}")
    P, no_assembly = _sphere_point(d, t, d.lower_arm_mm + d.joint_offset_mm)
    if d.joint_offset_mm > 0:
        P, no_assembly = _newton_fk(d, t, P, no_assembly)
    P = np.where(no_assembly[:, None], 0.0, P)
    status = _status(d, P, t, np.zeros(len(t), bool))
    status = np.where(no_assembly, STATUS_NO_ASSEMBLY, status).astype(np.int8)
    return DeltaPose(P_mm=P, theta_rad=t.copy(), status=status)


def _sphere_point(d: Delta, t: np.ndarray, radius_mm: float) -> tuple[np.ndarray, np.ndarray]:
    """The lower intersection (N, 3) of the spheres of ``radius_mm`` about the shifted elbows
    at joint angles t (N, 3), and where there is none (N,)."""
    C = _shifted_elbows(d, t)
    n = np.cross(C[:, 1] - C[:, 0], C[:, 2] - C[:, 0])
    n_len = np.linalg.norm(n, axis=1)
    degenerate = n_len <= 1e-12 * d.upper_arm_mm**2
    n_hat = n / np.where(degenerate, 1.0, n_len)[:, None]
    n_hat *= np.where(n_hat[:, 2] < 0, -1.0, 1.0)[:, None]  # z-up normal
    # P0: the point of the plane of the C_i equidistant from them (circumcentre)
    M = np.stack([2 * (C[:, 1] - C[:, 0]), 2 * (C[:, 2] - C[:, 0]), n_hat], axis=1)
    rhs = np.stack([
        np.sum(C[:, 1] ** 2 - C[:, 0] ** 2, axis=1),
        np.sum(C[:, 2] ** 2 - C[:, 0] ** 2, axis=1),
        np.sum(n_hat * C[:, 0], axis=1),
    ], axis=1)
    M = np.where(degenerate[:, None, None], np.eye(3), M)
    P0 = np.linalg.solve(M, rhs[..., None])[..., 0]
    h2 = radius_mm**2 - np.sum((P0 - C[:, 0]) ** 2, axis=1)
    no_assembly = degenerate | (h2 < -REACH_REL_EPS * radius_mm**2)
    return P0 - np.sqrt(np.clip(h2, 0, None))[:, None] * n_hat, no_assembly


def _newton_fk(d: Delta, t: np.ndarray, P: np.ndarray, bad: np.ndarray):
    """Newton's method on f_i(P) = (rho_i - g)^2 + y'_i^2 - L_b^2 = 0 from P (N, 3); points
    whose residual stays above round-off (or whose Jacobian is singular) join ``bad``."""

    def residual(X):
        C = _shifted_elbows(d, t)
        w = X[:, None, :] - C
        y = np.einsum("nij,ij->ni", w, d.tangential)
        rho = np.linalg.norm(w - y[..., None] * d.tangential, axis=-1)
        return (rho - d.joint_offset_mm) ** 2 + y * y - d.lower_arm_mm**2

    X = np.where(bad[:, None], 0.0, P)
    for _ in range(DELTA_FK_NEWTON_STEPS):
        A, _ = _constraint_jacobians(d, X, t)
        ok = np.abs(np.linalg.det(A)) > 1e-12 * d.lower_arm_mm**3
        A = np.where(ok[:, None, None], A, np.eye(3))
        X = X - np.linalg.solve(2 * A, residual(X)[..., None])[..., 0]
        bad = bad | ~ok
    converged = np.max(np.abs(residual(X)), axis=1) <= DELTA_FK_RESIDUAL_REL * d.lower_arm_mm**2
    return X, bad | ~converged


def jacobian_rad_per_m(d: Delta, P_mm) -> tuple[np.ndarray, np.ndarray]:
    """J (N, 3, 3) with theta_dot = J x_dot in rad/m at points ``P_mm`` (N, 3) mm, and the
    status (N,). Rows of non-ok points are 0. f [N] = J^T tau [N m] (eq 2)."""
    return jacobian_kernel(d, _points(P_mm))


def jacobian_kernel(d, P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`jacobian_rad_per_m` without input checks, for a :class:`Delta` or a
    :class:`DeltaArrays` of K deltas paired with K points P (K, 3) mm."""
    arms = [_arm_ik(d, P, i) for i in range(3)]
    theta = np.stack([a[0] for a in arms], axis=-1)
    unreachable = np.any(np.stack([a[1] for a in arms], axis=-1), axis=1)
    status = _status(d, P, theta, unreachable)
    A, b = _constraint_jacobians(d, P, theta)
    ok = status == STATUS_OK
    b_safe = np.where(ok[:, None], b, 1.0)
    J = -A / b_safe[..., None] * 1e3
    return np.where(ok[:, None, None], J, 0.0), status


def joint_torques_Nm(d: Delta, P_mm, force_N) -> np.ndarray:
    """The joint torques tau (N, 3) [N m] that make the effector exert ``force_N`` (N, 3) [N]
    at ``P_mm`` (N, 3) mm: statics by virtual work, f = J^T tau (eq 2), so tau = J^-T f.
    Raises :class:`KinematicsError` naming the first non-ok point."""
    J, status = jacobian_rad_per_m(d, P_mm)
    bad = np.flatnonzero(status != STATUS_OK)
    if bad.size:
        P = _points(P_mm)
        raise KinematicsError(f"P = {P[bad[0]].round(3).tolist()} mm: {STATUS_NAMES[int(status[bad[0]])]}")
    F = np.broadcast_to(np.asarray(force_N, dtype=float), (J.shape[0], 3))
    return np.linalg.solve(np.swapaxes(J, -1, -2), F[..., None])[..., 0]


def require_ok(pose: DeltaPose) -> None:
    """Raise :class:`KinematicsError` naming the first non-ok point, if any."""
    bad = np.flatnonzero(~pose.ok)
    if bad.size:
        raise KinematicsError(f"{bad.size} point(s) not ok; first {pose.describe(int(bad[0]))}")


def box_grid_mm(center_mm, size_mm, n: int) -> np.ndarray:
    """An n x n x n grid over a box workspace, faces included: (n^3, 3) mm, base frame.

    center_mm: (x, y, z) of the box centre; size_mm: (W, D, H) along x, y, z (> 0); n >= 2.
    Raises :class:`DesignError` naming ``workspace.*`` on a bad value.
    """
    c = _vector3(center_mm, "workspace.center_mm")
    s = _vector3(size_mm, "workspace.size_mm")
    if np.any(s <= 0):
        raise DesignError("workspace.size_mm", f"must be > 0 on every axis, got {s.tolist()}")
    n = _grid_n(n)
    axes = [c[k] + np.linspace(-0.5, 0.5, n) * s[k] for k in range(3)]
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)


def cylinder_grid_mm(center_mm, diameter_mm: float, height_mm: float, n: int) -> np.ndarray:
    """Points over a vertical cylinder workspace (axis along z through ``center_mm``): the
    axis plus n rings of 6k points (k = 1..n-1, the rim included) on each of n levels,
    faces included. (N, 3) mm, base frame."""
    c = _vector3(center_mm, "workspace.center_mm")
    for name, v in (("workspace.diameter_mm", diameter_mm), ("workspace.height_mm", height_mm)):
        if not np.isfinite(v) or v <= 0:
            raise DesignError(name, f"must be > 0, got {v!r}")
    n = _grid_n(n)
    ring = [np.zeros((1, 2))]
    for k in range(1, n):
        a = np.linspace(0, 2 * np.pi, 6 * k, endpoint=False)
        rho = 0.5 * diameter_mm * k / (n - 1)
        ring.append(rho * np.stack([np.cos(a), np.sin(a)], axis=-1))
    xy = np.concatenate(ring)
    z = np.linspace(-0.5, 0.5, n) * height_mm
    pts = np.concatenate([np.column_stack([xy, np.full(len(xy), zk)]) for zk in z])
    return pts + c


def inverse_condition(d: Delta, P_mm) -> tuple[np.ndarray, np.ndarray]:
    """sigma_min / sigma_max of J (N,) at ``P_mm`` (0 at a non-ok point) and the status (N,).
    The well-conditioned workspace is where this is at least the design's threshold."""
    J, status = jacobian_rad_per_m(d, P_mm)
    s = np.linalg.svd(J, compute_uv=False)
    ratio = np.where(status == STATUS_OK, s[:, -1] / np.where(s[:, 0] > 0, s[:, 0], 1.0), 0.0)
    return ratio, status


def _vector3(v, field: str) -> np.ndarray:
    a = np.asarray(v, dtype=float).reshape(-1)
    if a.size != 3 or not np.all(np.isfinite(a)):
        raise DesignError(field, f"must be 3 finite numbers [x, y, z], got {v!r}")
    return a


def _grid_n(n) -> int:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 2:
        raise DesignError("workspace.grid", f"must be an integer >= 2 (faces sampled), got {n!r}")
    return int(n)


def largest_cube_mm(d: Delta, z_range_mm: tuple[float, float], n: int = 5,
                    tol_mm: float = 0.1) -> dict:
    """The largest cube on the z axis (faces sampled n x n x n) every point of which is
    reachable, regular and inside the joint range: {"side_mm", "center_z_mm"}.

    For each centre z on a 1 mm grid over ``z_range_mm`` the side is found by bisection to
    ``tol_mm`` (the reachable set need not be convex, so a side is accepted only when every
    sample is ok; the bisection assumes a smaller cube about the same centre is ok when a
    larger one is, true of the sampled faces of the workspaces met here). A side of 0 means
    no centre in the range is reachable."""
    best = {"side_mm": 0.0, "center_z_mm": None}
    for zc in np.arange(z_range_mm[0], z_range_mm[1] + 0.5, 1.0):
        if not ik(d, [0.0, 0.0, zc]).ok[0]:
            continue
        lo, hi = 0.0, 2.0 * (d.upper_arm_mm + d.lower_arm_mm)
        while hi - lo > tol_mm:
            mid = 0.5 * (lo + hi)
            pts = box_grid_mm([0.0, 0.0, zc], [mid] * 3, n)
            lo, hi = (mid, hi) if np.all(ik(d, pts).ok) else (lo, mid)
        if lo > best["side_mm"]:
            best = {"side_mm": float(lo), "center_z_mm": float(zc)}
    return best


#: The inverse condition number sigma_min / sigma_max of J above which a point counts as
#: well conditioned (:func:`workspace_volumes`): our choice (no standard value read); the
#: bundled delta's worst over its 100 mm cube is 0.46.
WELL_CONDITIONED_MIN = 0.3
#: Grid step of :func:`workspace_volumes` (mm): docs/families/delta.md gives its volumes
#: at 10, 5 and 2.5 mm.
VOLUME_STEP_MM = 10.0


def reach_box_mm(d: Delta) -> tuple[np.ndarray, np.ndarray]:
    """(lo, hi) (3,) mm, base frame: a box holding every point the effector can reach below
    the base plane (z <= 0): |x|, |y| <= R + r + L_a + L_b + g + |delta|, z >= -(L_a + L_b + g)."""
    a = (d.base_radius_mm + d.effector_radius_mm + d.upper_arm_mm + d.lower_arm_mm
         + abs(d.joint_offset_mm) + abs(d.axis_offset_mm))
    return np.array([-a, -a, -(d.upper_arm_mm + d.lower_arm_mm + abs(d.joint_offset_mm))]), np.array([a, a, 0.0])


def workspace_volumes(d: Delta, step_mm: float = VOLUME_STEP_MM,
                      threshold: float = WELL_CONDITIONED_MIN, chunk: int = 200_000) -> dict:
    """The reachable and the well-conditioned workspace below the base plane, by counting
    the centres of a regular grid of cells ``step_mm`` over :func:`reach_box_mm`:
    ``reachable_cm3`` (IK status ok: reached, inside the motor angle range, not singular),
    ``well_conditioned_cm3`` (also sigma_min / sigma_max of J >= ``threshold``,
    :func:`inverse_condition`), ``points``, ``step_mm``, ``threshold``. The error is the
    boundary's cells: it falls as the step (docs/families/delta.md)."""
    lo, hi = reach_box_mm(d)
    axes = [np.arange(a + step_mm / 2, b, step_mm) for a, b in zip(lo, hi, strict=True)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    n_ok = n_good = 0
    for k in range(0, len(grid), chunk):
        ratio, status = inverse_condition(d, grid[k:k + chunk])
        n_ok += int(np.sum(status == STATUS_OK))
        n_good += int(np.sum((status == STATUS_OK) & (ratio >= threshold)))
    cell_cm3 = step_mm ** 3 * 1e-3
    return {"reachable_cm3": n_ok * cell_cm3, "well_conditioned_cm3": n_good * cell_cm3,
            "points": int(len(grid)), "step_mm": float(step_mm), "threshold": float(threshold)}
