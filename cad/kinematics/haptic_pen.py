"""Twin-pantograph haptic pen: two 3-DOF 5-bars holding a pen (isotropy paper §4.2, Table 2).

Geometry used here (the paper gives symbols, not drawings; this is our
reading, stated so it can be checked):

* Two arms, A and B, with waist axes parallel to z through (-l4/2, 0, 0) and
  (+l4/2, 0, 0); l4 = l6 (the paper sets the base length equal to the pen
  length).
* Each arm is a symmetric planar 5-bar whose base line (shoulder joints
  l1 apart, centred on the base point) lies ON its waist axis; the waist joint
  (q1 for A, q4 for B) turns the 5-bar's plane about that axis ("folding"
  the plane about its base line). In the plane the 5-bar's coordinates are
  (along the axis, away from it) = (z, rho), rho = horizontal distance from
  the waist axis; so an arm reaches a point by cylindrical coordinates:
  waist angle psi = atan2(py, px), 5-bar IK at E = (z, rho) with the elbow
  conventions of :mod:`cad.kinematics.fivebar`.
* The pen, of length l6, joins the two arm end points by passive spherical
  joints (roll about the pen is passive): task X = (x, y, z, yaw, pitch) of
  the pen centre c and direction u = (cos yaw cos pitch, sin yaw cos pitch,
  sin pitch); P_A = c - l6/2 u, P_B = c + l6/2 u. Home: u = +x, pen parallel
  to the base line, workspace at distance y from the base.
* Task velocity (c_dot [m/s], w1, w2 [rad/s]) with u_dot = w1 e_yaw + w2 e_pitch,
  e_yaw = (-sin yaw, cos yaw, 0), e_pitch = du/dpitch: two proper angular rates
  about axes normal to the pen.

Jacobian q_dot = J X_dot, 6 x 5 (eq 1); S_J = diag(Q1 tau, tau, tau, Q1 tau,
tau, tau) with Q1 the waist:shoulder torque ratio of Table 2; S_T = diag(F, F,
F, M, M). The paper does not give M / F for the pen; the default moment arm
M / F = 35 mm makes a pen of the minimum length 70 mm exactly balanced
(M = F l6 / 2, as eq 7 does for the mouse) -- consistent with Table 2, where
l6 always sits at its 7.0 cm minimum.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cad.errors import DesignError
from cad.isotropy.gii import gii_from_jacobians
from cad.kinematics import fivebar as fb5
from cad.kinematics.pantograph_tolerances import ON_WAIST_AXIS_MM

#: Table 2 of the isotropy paper: distance [cm] -> (l1, l2, l3, l6 [cm], Q1, GII).
TABLE2 = {
    15: (2.4, 13.0, 16.0, 7.0, 1.6, 0.089),
    20: (2.4, 14.5, 20.0, 7.0, 1.7, 0.182),
    25: (2.4, 17.0, 23.0, 7.0, 1.6, 0.234),
    30: (3.6, 19.5, 27.0, 7.0, 1.6, 0.262),
    35: (3.6, 22.5, 30.5, 7.0, 1.6, 0.280),
    40: (4.0, 25.5, 34.5, 7.0, 1.6, 0.292),
}

STATUS_ON_WAIST_AXIS = 7
ARM_B_STATUS_OFFSET = 10


def _names() -> dict[int, str]:
    base = dict(fb5.STATUS_NAMES)
    base[STATUS_ON_WAIST_AXIS] = "singular: pen end on the waist axis (waist angle undefined)"
    names = {0: "ok"}
    for code, text in base.items():
        if code:
            names[code] = f"arm A: {text}"
            names[code + ARM_B_STATUS_OFFSET] = f"arm B: {text}"
    return names


STATUS_NAMES = _names()


@dataclass(frozen=True)
class HapticPen:
    """Pen geometry (mm) and actuator ratio.

    shoulder_base_mm: l1 (distance between the shoulder axes of one arm);
    proximal_mm: l2; distal_mm: l3; pen_mm: l6; arm_spacing_mm: l4 (None ->
    l6, as in the paper); waist_torque_ratio: Q1 (waist : shoulder max torque).
    """

    shoulder_base_mm: float
    proximal_mm: float
    distal_mm: float
    pen_mm: float
    arm_spacing_mm: float | None = None
    waist_torque_ratio: float = 1.6

    def __post_init__(self) -> None:
        for name in (
            "shoulder_base_mm",
            "proximal_mm",
            "distal_mm",
            "pen_mm",
            "waist_torque_ratio",
        ):
            v = getattr(self, name)
            if not (np.isfinite(v) and v > 0):
                raise DesignError(f"mechanism.{name}", f"must be > 0, got {v!r}")
        if self.arm_spacing_mm is not None and not (
            np.isfinite(self.arm_spacing_mm) and self.arm_spacing_mm > 0
        ):
            raise DesignError(
                "mechanism.arm_spacing_mm", f"must be > 0, got {self.arm_spacing_mm!r}"
            )

    @property
    def l4_mm(self) -> float:
        return float(self.pen_mm if self.arm_spacing_mm is None else self.arm_spacing_mm)


def _arm_jacobian(x0, l1, l2, l3, px, py, pz):
    """One arm: J (..., 3, 3) SI rows (waist, shoulder 1, shoulder 2), status (...)."""
    dx = px - x0
    rho = np.hypot(dx, py)
    on_axis = rho <= ON_WAIST_AXIS_MM
    rs = np.where(on_axis, 1.0, rho)
    J5, st = fb5.jacobian_arrays(-l1 / 2, 0.0, l1 / 2, 0.0, l2, l2, l3, l3, 1.0, -1.0, pz, rho)
    J5 = J5 * 1e3  # rad/m, columns (z, rho)
    ex, ey = dx / rs, py / rs
    shape = np.broadcast(st, on_axis).shape
    J = np.zeros(shape + (3, 3))
    # waist: psi_dot = (dx * py_dot - py * px_dot) / rho^2  (rho in m)
    rm = rs * 1e-3
    J[..., 0, 0] = -ey / rm
    J[..., 0, 1] = ex / rm
    # shoulders: q_dot = J5[:, 0] z_dot + J5[:, 1] rho_dot, rho_dot = ex px_dot + ey py_dot
    J[..., 1:3, 0] = J5[..., :, 1] * ex[..., None]
    J[..., 1:3, 1] = J5[..., :, 1] * ey[..., None]
    J[..., 1:3, 2] = J5[..., :, 0]
    st = np.where(on_axis, STATUS_ON_WAIST_AXIS, st)
    J = np.where((st == 0)[..., None, None], J, 0.0)
    return J, st


def pen_directions(yaw, pitch):
    """u, e_yaw, e_pitch (..., 3): pen direction and the two unit rates normal to it."""
    cy, sy = np.cos(yaw), np.sin(yaw)
    cp, sp = np.cos(pitch), np.sin(pitch)
    u = np.stack([cy * cp, sy * cp, sp * np.ones_like(cy)], axis=-1)
    e_yaw = np.stack([-sy, cy, np.zeros_like(cy * cp)], axis=-1)
    e_pitch = np.stack([-cy * sp, -sy * sp, cp * np.ones_like(cy)], axis=-1)
    return u, e_yaw, e_pitch


def jacobian_arrays(l1, l2, l3, l6, l4, cx, cy, cz, yaw, pitch):
    """Vectorized pen Jacobian kernel (broadcast; mm, rad): (J (..., 6, 5) SI, status).

    Rows (q1 waist A, q2, q3, q4 waist B, q5, q6); columns (x, y, z [rad/m],
    w_yaw, w_pitch [rad/rad]).
    """
    u, ea, eb = pen_directions(np.asarray(yaw, float), np.asarray(pitch, float))
    c = np.stack(np.broadcast_arrays(cx, cy, cz), axis=-1)
    half = np.asarray(l6, float)[..., None] / 2
    PA = c - half * u
    PB = c + half * u
    l4 = np.asarray(l4, float)
    JA, sA = _arm_jacobian(-l4 / 2, l1, l2, l3, PA[..., 0], PA[..., 1], PA[..., 2])
    JB, sB = _arm_jacobian(l4 / 2, l1, l2, l3, PB[..., 0], PB[..., 1], PB[..., 2])
    shape = np.broadcast(sA, sB).shape
    J = np.zeros(shape + (6, 5))
    hm = half[..., None] * 1e-3  # m
    rot = np.stack([ea, eb], axis=-1)  # (..., 3, 2): d P / d w for unit half length
    J[..., 0:3, 0:3] = JA
    J[..., 3:6, 0:3] = JB
    J[..., 0:3, 3:5] = -np.einsum("...ij,...jk->...ik", JA, rot) * hm
    J[..., 3:6, 3:5] = np.einsum("...ij,...jk->...ik", JB, rot) * hm
    status = np.where(sA != 0, sA, np.where(sB != 0, sB + ARM_B_STATUS_OFFSET, 0)).astype(np.int16)
    return J, status


def _task(X) -> np.ndarray:
    X = np.asarray(X, dtype=float)
    if X.ndim == 1:
        X = X[None, :]
    if X.ndim != 2 or X.shape[1] != 5 or not np.all(np.isfinite(X)):
        raise DesignError(
            "X", f"must be finite (N, 5) = (x, y, z mm, yaw, pitch rad), got {np.shape(X)}"
        )
    return X


def jacobian_si(pen: HapticPen, X) -> tuple[np.ndarray, np.ndarray]:
    """J (N, 6, 5) and status (N,) at task poses X (N, 5) = (x, y, z mm, yaw, pitch rad)."""
    X = _task(X)
    return jacobian_arrays(
        pen.shoulder_base_mm,
        pen.proximal_mm,
        pen.distal_mm,
        pen.pen_mm,
        pen.l4_mm,
        X[:, 0],
        X[:, 1],
        X[:, 2],
        X[:, 3],
        X[:, 4],
    )


def ik(pen: HapticPen, X) -> tuple[np.ndarray, np.ndarray]:
    """Joint angles q (N, 6) rad = (waist A, shoulders A, waist B, shoulders B); status (N,)."""
    X = _task(X)
    u, _, _ = pen_directions(X[:, 3], X[:, 4])
    out, sts = [], []
    for sign, x0 in ((-1, -pen.l4_mm / 2), (1, pen.l4_mm / 2)):
        P = X[:, :3] + sign * pen.pen_mm / 2 * u
        dx, py = P[:, 0] - x0, P[:, 1]
        rho = np.hypot(dx, py)
        q1, q2, *_, st = fb5.ik_arrays(
            -pen.shoulder_base_mm / 2,
            0.0,
            pen.shoulder_base_mm / 2,
            0.0,
            pen.proximal_mm,
            pen.proximal_mm,
            pen.distal_mm,
            pen.distal_mm,
            1.0,
            -1.0,
            P[:, 2],
            rho,
        )
        out.append(np.stack([np.arctan2(py, dx), q1, q2], axis=-1))
        sts.append(np.where(rho <= ON_WAIST_AXIS_MM, STATUS_ON_WAIST_AXIS, st))
    status = np.where(sts[0] != 0, sts[0], np.where(sts[1] != 0, sts[1] + ARM_B_STATUS_OFFSET, 0))
    return np.concatenate(out, axis=1), status.astype(np.int16)


def actuator_scale(waist_torque_ratio: float, shoulder_torque_Nm: float = 1.0) -> np.ndarray:
    """S_J diagonal (eq 3): (Q1 tau, tau, tau, Q1 tau, tau, tau)."""
    t = float(shoulder_torque_Nm)
    q = float(waist_torque_ratio) * t
    return np.array([q, t, t, q, t, t])


def workspace_grid(center_mm, size_mm, grid, rotation_deg: float, rotation_grid: int) -> np.ndarray:
    """Task samples (N, 5) = (x, y, z mm, yaw, pitch rad): a box (boundary included)
    of ``size_mm`` around ``center_mm`` times yaw, pitch in [-rotation, +rotation].

    C order over (x, y, z, yaw, pitch); ``grid`` = samples per translation axis.
    """
    c = np.asarray(center_mm, float).reshape(-1)
    s = np.asarray(size_mm, float).reshape(-1)
    g = [int(v) for v in np.asarray(grid).reshape(-1)]
    if c.size != 3 or s.size != 3 or len(g) != 3:
        raise DesignError("workspace", "center_mm, size_mm and grid need 3 entries each")
    if np.any(s <= 0) or min(g) < 2 or rotation_grid < 1 or not (0 <= rotation_deg < 90):
        raise DesignError(
            "workspace",
            f"need size_mm > 0, grid >= 2, rotation_grid >= 1, 0 <= rotation_deg < 90; "
            f"got {s.tolist()}, {g}, {rotation_grid}, {rotation_deg}",
        )
    axes = [c[k] + np.linspace(-0.5, 0.5, g[k]) * s[k] for k in range(3)]
    r = np.radians(rotation_deg)
    ang = np.linspace(-r, r, rotation_grid) if rotation_grid > 1 else np.zeros(1)
    mesh = np.meshgrid(*axes, ang, ang, indexing="ij")
    return np.stack([m.ravel() for m in mesh], axis=-1)


def pen_gii(
    pen: HapticPen,
    center_mm,
    size_mm,
    grid,
    rotation_deg: float = 45.0,
    rotation_grid: int = 3,
    force_N: float = 1.0,
    moment_arm_mm: float = 35.0,
):
    """GII (eq 5) of the pen over its box x rotation workspace.

    S_T = (F, F, F, M, M) with M = F * moment_arm_mm; S_J from Q1. Points of
    the result are (x, y, z mm, yaw, pitch deg).
    """
    for name, v in (("force_max_N", force_N), ("moment_arm_mm", moment_arm_mm)):
        if not (np.isfinite(v) and v > 0):
            raise DesignError(f"actuators.{name}", f"must be finite and > 0, got {v!r}")
    M = force_N * moment_arm_mm * 1e-3
    if not (np.isfinite(M) and M >= np.finfo(float).tiny):  # a denormal M would overflow J_hat
        raise DesignError(
            "actuators.moment_arm_mm",
            f"the moment scale F * arm = {M!r} N m is outside float64 (F = {force_N!r} N)",
        )
    X = workspace_grid(center_mm, size_mm, grid, rotation_deg, rotation_grid)
    J, status = jacobian_si(pen, X)
    pts = X.copy()
    pts[:, 3:] = np.degrees(pts[:, 3:])
    S_T = np.array([force_N] * 3 + [M] * 2)
    return gii_from_jacobians(
        J, status, pts, actuator_scale(pen.waist_torque_ratio), S_T, STATUS_NAMES
    )
