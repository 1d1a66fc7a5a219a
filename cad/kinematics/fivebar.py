"""Planar 5-bar (pantograph) kinematics: IK, FK and the Jacobian, vectorized.

Symbols (isotropy paper §3-4, issue 6 §1): actuated joints B1 (left) and B2
(right); proximal links l2 from Bi to the elbow Ci at absolute angle qi; distal
links l3 from Ci to the end effector E. The symmetric 5-bar has B1 = (-a/2, 0),
B2 = (+a/2, 0) and equal arms. Frame: the base frame, x along B1 -> B2, y
towards the workspace "above" the base; lengths in mm, angles in rad.

Elbow conventions (signs ``elbow_left = +1``, ``elbow_right = -1``)::

    q1 = atan2(E - B1) + acos((l2^2 + |E - B1|^2 - l3^2) / (2 l2 |E - B1|))
    q2 = atan2(E - B2) - acos(...)

i.e. elbows out when E is above the base (and elbows in below it).

Jacobian: q_dot = J x_dot, so the end-effector force is f = J^T tau
(isotropy paper eq 1). Row i of J is (E - Ci)^T / (l2 * cross(u(qi), E - Ci)),
from differentiating |E - Ci|^2 = l3^2.

Failures are explicit: every point carries a status code (:data:`STATUS_NAMES`),
unreachable and singular points are masked, never NaN.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cad.errors import DesignError, KinematicsError
from cad.kinematics.pantograph_tolerances import (
    ARM_SINGULAR_SIN,
    DISTAL_SINGULAR_SIN,
    ON_JOINT_MM,
    REACH_REL_EPS,
)

STATUS_OK = 0
STATUS_UNREACHABLE_LEFT = 1
STATUS_UNREACHABLE_RIGHT = 2
STATUS_SINGULAR_LEFT = 3
STATUS_SINGULAR_RIGHT = 4
STATUS_SINGULAR_DISTAL = 5
STATUS_NO_CLOSURE = 6

#: status code -> human-readable reason (used in error messages and reports).
STATUS_NAMES: dict[int, str] = {
    STATUS_OK: "ok",
    STATUS_UNREACHABLE_LEFT: "unreachable by the left arm (|E - B1| outside [|l2 - l3|, l2 + l3])",
    STATUS_UNREACHABLE_RIGHT: "unreachable by the right arm (|E - B2| outside [|l2 - l3|, l2 + l3])",
    STATUS_SINGULAR_LEFT: "singular: left arm fully stretched or folded (type-1)",
    STATUS_SINGULAR_RIGHT: "singular: right arm fully stretched or folded (type-1)",
    STATUS_SINGULAR_DISTAL: "singular: distal links collinear (type-2)",
    STATUS_NO_CLOSURE: "distal links cannot close (|C2 - C1| outside [|l3L - l3R|, l3L + l3R])",
}

UNREACHABLE_CODES = (STATUS_UNREACHABLE_LEFT, STATUS_UNREACHABLE_RIGHT, STATUS_NO_CLOSURE)
SINGULAR_CODES = (STATUS_SINGULAR_LEFT, STATUS_SINGULAR_RIGHT, STATUS_SINGULAR_DISTAL)


@dataclass(frozen=True)
class FiveBar:
    """A general planar 5-bar; the symmetric one via :meth:`symmetric`.

    base_left_mm, base_right_mm: actuated joints B1, B2 (x, y), base frame, mm.
    proximal_*_mm: l2 of each arm (Bi -> Ci); distal_*_mm: l3 (Ci -> E).
    elbow_left / elbow_right: sign in front of the acos in the IK (+1 / -1 is
    the convention of issue 6: elbows out above the base).
    """

    base_left_mm: tuple[float, float]
    base_right_mm: tuple[float, float]
    proximal_left_mm: float
    proximal_right_mm: float
    distal_left_mm: float
    distal_right_mm: float
    elbow_left: int = 1
    elbow_right: int = -1

    def __post_init__(self) -> None:
        for name in ("base_left_mm", "base_right_mm"):
            v = getattr(self, name)
            if len(v) != 2 or not all(np.isfinite(float(c)) for c in v):
                raise DesignError(f"fivebar.{name}", f"must be a finite (x, y), got {v!r}")
        for name in ("proximal_left_mm", "proximal_right_mm", "distal_left_mm", "distal_right_mm"):
            v = float(getattr(self, name))
            if not np.isfinite(v) or v <= 0:
                raise DesignError(f"fivebar.{name}", f"must be > 0, got {v!r}")
        for name in ("elbow_left", "elbow_right"):
            if getattr(self, name) not in (1, -1):
                raise DesignError(
                    f"fivebar.{name}", f"must be +1 or -1, got {getattr(self, name)!r}"
                )

    @classmethod
    def symmetric(cls, base_mm: float, proximal_mm: float, distal_mm: float) -> FiveBar:
        """Symmetric 5-bar: B1 = (-a/2, 0), B2 = (+a/2, 0), equal arms (mm)."""
        if not np.isfinite(base_mm) or base_mm < 0:
            raise DesignError("fivebar.base_mm", f"must be >= 0, got {base_mm!r}")
        a = float(base_mm)
        return cls((-a / 2, 0.0), (a / 2, 0.0), proximal_mm, proximal_mm, distal_mm, distal_mm)

    def scaled(self, k: float) -> FiveBar:
        """All lengths multiplied by ``k`` (> 0); the GII is invariant under this
        when the workspace is scaled too."""
        if not k > 0:
            raise DesignError("fivebar.scale", f"must be > 0, got {k!r}")
        return FiveBar(
            (self.base_left_mm[0] * k, self.base_left_mm[1] * k),
            (self.base_right_mm[0] * k, self.base_right_mm[1] * k),
            self.proximal_left_mm * k,
            self.proximal_right_mm * k,
            self.distal_left_mm * k,
            self.distal_right_mm * k,
            self.elbow_left,
            self.elbow_right,
        )

    def arrays(self) -> tuple:
        """The parameters as the scalar tuple the array kernels take."""
        return (
            float(self.base_left_mm[0]),
            float(self.base_left_mm[1]),
            float(self.base_right_mm[0]),
            float(self.base_right_mm[1]),
            float(self.proximal_left_mm),
            float(self.proximal_right_mm),
            float(self.distal_left_mm),
            float(self.distal_right_mm),
            float(self.elbow_left),
            float(self.elbow_right),
        )


@dataclass(frozen=True)
class FiveBarPose:
    """Configurations of a 5-bar at N end-effector points (arrays, base frame, mm/rad).

    E_mm (N,2) end effector; q_rad (N,2) actuated angles (q1, q2);
    C_left_mm / C_right_mm (N,2) elbows; status (N,) codes of :data:`STATUS_NAMES`.
    Entries of non-ok points that have no meaning (unreachable) are 0, not NaN.
    """

    E_mm: np.ndarray
    q_rad: np.ndarray
    C_left_mm: np.ndarray
    C_right_mm: np.ndarray
    status: np.ndarray

    @property
    def reachable(self) -> np.ndarray:
        """(N,) bool: the point can be assembled (possibly singular)."""
        return ~np.isin(self.status, UNREACHABLE_CODES)

    @property
    def singular(self) -> np.ndarray:
        """(N,) bool: reachable but at a type-1 or type-2 singularity."""
        return np.isin(self.status, SINGULAR_CODES)

    @property
    def ok(self) -> np.ndarray:
        """(N,) bool: reachable and regular."""
        return self.status == STATUS_OK

    def describe(self, i: int) -> str:
        """One-line description of point ``i`` and its status."""
        x, y = self.E_mm[i]
        return f"E = ({x:.3f}, {y:.3f}) mm: {STATUS_NAMES[int(self.status[i])]}"


# ----------------------------------------------------------------------------
# Array kernels (no validation; broadcast over any leading shape)
# ----------------------------------------------------------------------------


def _arm_ik(bx, by, l2, l3, s, ex, ey):
    """One arm: angle q, elbow C, and status flags (unreachable, singular)."""
    dx = ex - bx
    dy = ey - by
    r = np.hypot(dx, dy)
    r_safe = np.where(r > ON_JOINT_MM, r, 1.0)
    c = (l2 * l2 + r * r - l3 * l3) / (2.0 * l2 * r_safe)
    too_far = r > (l2 + l3) * (1.0 + REACH_REL_EPS)
    too_near = r < np.abs(l2 - l3) * (1.0 - REACH_REL_EPS)
    on_joint = r <= ON_JOINT_MM
    unreachable = too_far | too_near | (on_joint & (np.abs(l2 - l3) > ON_JOINT_MM))
    q = np.arctan2(dy, dx) + s * np.arccos(np.clip(c, -1.0, 1.0))
    q = np.where(unreachable, 0.0, q)
    cx = bx + l2 * np.cos(q)
    cy = by + l2 * np.sin(q)
    return q, cx, cy, unreachable, on_joint


def ik_arrays(b1x, b1y, b2x, b2y, l2l, l2r, l3l, l3r, sl, sr, ex, ey):
    """Vectorized IK kernel (all arguments broadcast; mm, rad).

    Returns (q1, q2, c1x, c1y, c2x, c2y, status) arrays of the broadcast shape.
    Status precedence: unreachable left, unreachable right, singular left,
    singular right, singular distal.
    """
    q1, c1x, c1y, un1, on1 = _arm_ik(b1x, b1y, l2l, l3l, sl, ex, ey)
    q2, c2x, c2y, un2, on2 = _arm_ik(b2x, b2y, l2r, l3r, sr, ex, ey)
    status = _status(q1, q2, c1x, c1y, c2x, c2y, l3l, l3r, ex, ey, un1, un2, on1, on2)
    return q1, q2, c1x, c1y, c2x, c2y, status


def _status(q1, q2, c1x, c1y, c2x, c2y, l3l, l3r, ex, ey, un1, un2, on1, on2):
    d1x, d1y = ex - c1x, ey - c1y
    d2x, d2y = ex - c2x, ey - c2y
    sin1 = (np.cos(q1) * d1y - np.sin(q1) * d1x) / l3l
    sin2 = (np.cos(q2) * d2y - np.sin(q2) * d2x) / l3r
    sin12 = (d1x * d2y - d1y * d2x) / (l3l * l3r)
    status = np.full(np.broadcast(sin1, sin2, sin12).shape, STATUS_OK, dtype=np.int8)
    status = np.where(np.abs(sin12) < DISTAL_SINGULAR_SIN, STATUS_SINGULAR_DISTAL, status)
    status = np.where((np.abs(sin2) < ARM_SINGULAR_SIN) | on2, STATUS_SINGULAR_RIGHT, status)
    status = np.where((np.abs(sin1) < ARM_SINGULAR_SIN) | on1, STATUS_SINGULAR_LEFT, status)
    status = np.where(un2, STATUS_UNREACHABLE_RIGHT, status)
    status = np.where(un1, STATUS_UNREACHABLE_LEFT, status)
    return status.astype(np.int8)


def jacobian_arrays(b1x, b1y, b2x, b2y, l2l, l2r, l3l, l3r, sl, sr, ex, ey):
    """Vectorized Jacobian kernel: q_dot = J x_dot, J in rad/mm.

    Returns (J, status) with J of shape broadcast + (2, 2); rows of non-ok
    points are 0 (never NaN), status as :func:`ik_arrays`.
    Isotropy paper eq (1): f = J^T tau.
    """
    q1, q2, c1x, c1y, c2x, c2y, status = ik_arrays(
        b1x, b1y, b2x, b2y, l2l, l2r, l3l, l3r, sl, sr, ex, ey
    )
    ok = status == STATUS_OK
    d1x, d1y = ex - c1x, ey - c1y
    d2x, d2y = ex - c2x, ey - c2y
    den1 = l2l * (np.cos(q1) * d1y - np.sin(q1) * d1x)
    den2 = l2r * (np.cos(q2) * d2y - np.sin(q2) * d2x)
    den1 = np.where(ok, den1, 1.0)
    den2 = np.where(ok, den2, 1.0)
    shape = status.shape
    J = np.zeros(shape + (2, 2))
    J[..., 0, 0] = np.where(ok, d1x / den1, 0.0)
    J[..., 0, 1] = np.where(ok, d1y / den1, 0.0)
    J[..., 1, 0] = np.where(ok, d2x / den2, 0.0)
    J[..., 1, 1] = np.where(ok, d2y / den2, 0.0)
    return J, status


# ----------------------------------------------------------------------------
# Functional layer
# ----------------------------------------------------------------------------


def _points(E_mm, field: str = "E_mm") -> np.ndarray:
    E = np.asarray(E_mm, dtype=float)
    if E.ndim == 1:
        E = E[None, :]
    if E.ndim != 2 or E.shape[1] != 2:
        raise DesignError(field, f"must have shape (N, 2), got {np.shape(E_mm)}")
    if not np.all(np.isfinite(E)):
        raise DesignError(field, "must be finite")
    return E


def ik(fb: FiveBar, E_mm) -> FiveBarPose:
    """Inverse kinematics at end-effector points ``E_mm`` (N,2), base frame, mm."""
    E = _points(E_mm)
    q1, q2, c1x, c1y, c2x, c2y, status = ik_arrays(*fb.arrays(), E[:, 0], E[:, 1])
    return FiveBarPose(
        E_mm=E,
        q_rad=np.stack([q1, q2], axis=-1),
        C_left_mm=np.stack([c1x, c1y], axis=-1),
        C_right_mm=np.stack([c2x, c2y], axis=-1),
        status=status,
    )


def fk(fb: FiveBar, q_rad, assembly: int = 1) -> FiveBarPose:
    """Forward kinematics at actuated angles ``q_rad`` (N,2) rad.

    assembly: +1 puts E on the left of the vector C1 -> C2 (the usual mode
    with elbows out above the base), -1 on the right. Points where the distal
    links cannot close get status :data:`STATUS_NO_CLOSURE` and E = 0.
    """
    if assembly not in (1, -1):
        raise DesignError("assembly", f"must be +1 or -1, got {assembly!r}")
    q = np.asarray(q_rad, dtype=float)
    if q.ndim == 1:
        q = q[None, :]
    if q.ndim != 2 or q.shape[1] != 2 or not np.all(np.isfinite(q)):
        raise DesignError("q_rad", f"must be finite with shape (N, 2), got {np.shape(q_rad)}")
    b1x, b1y, b2x, b2y, l2l, l2r, l3l, l3r, _, _ = fb.arrays()
    c1x = b1x + l2l * np.cos(q[:, 0])
    c1y = b1y + l2l * np.sin(q[:, 0])
    c2x = b2x + l2r * np.cos(q[:, 1])
    c2y = b2y + l2r * np.sin(q[:, 1])
    vx, vy = c2x - c1x, c2y - c1y
    d = np.hypot(vx, vy)
    no_close = (d > (l3l + l3r) * (1 + REACH_REL_EPS)) | (d < abs(l3l - l3r) * (1 - REACH_REL_EPS))
    no_close |= d <= ON_JOINT_MM
    d_safe = np.where(no_close, 1.0, d)
    a = (l3l * l3l - l3r * l3r + d_safe * d_safe) / (2 * d_safe)
    h = np.sqrt(np.clip(l3l * l3l - a * a, 0.0, None))
    ex_, ey_ = vx / d_safe, vy / d_safe
    Ex = c1x + a * ex_ - assembly * h * ey_
    Ey = c1y + a * ey_ + assembly * h * ex_
    Ex = np.where(no_close, 0.0, Ex)
    Ey = np.where(no_close, 0.0, Ey)
    z = np.zeros_like(no_close)
    status = _status(q[:, 0], q[:, 1], c1x, c1y, c2x, c2y, l3l, l3r, Ex, Ey, z, z, z, z)
    status = np.where(no_close, STATUS_NO_CLOSURE, status).astype(np.int8)
    return FiveBarPose(
        E_mm=np.stack([Ex, Ey], axis=-1),
        q_rad=q.copy(),
        C_left_mm=np.stack([c1x, c1y], axis=-1),
        C_right_mm=np.stack([c2x, c2y], axis=-1),
        status=status,
    )


def assembly_mode(pose: FiveBarPose) -> np.ndarray:
    """(N,) sign of cross(C2 - C1, E - C1): the FK assembly mode of each pose."""
    v = pose.C_right_mm - pose.C_left_mm
    w = pose.E_mm - pose.C_left_mm
    return np.sign(v[:, 0] * w[:, 1] - v[:, 1] * w[:, 0]).astype(int)


def jacobian_rad_per_m(fb: FiveBar, E_mm) -> tuple[np.ndarray, np.ndarray]:
    """Jacobian q_dot = J x_dot at points ``E_mm`` (N,2) mm.

    Returns (J (N,2,2) in rad/m, status (N,)). Rows of non-ok points are 0.
    Isotropy paper eq (1): f [N] = J^T tau [N m].
    """
    E = _points(E_mm)
    J, status = jacobian_arrays(*fb.arrays(), E[:, 0], E[:, 1])
    return J * 1e3, status


def require_ok(pose: FiveBarPose) -> None:
    """Raise :class:`KinematicsError` naming the first non-ok point, if any."""
    bad = np.flatnonzero(~pose.ok)
    if bad.size:
        raise KinematicsError(
            f"{bad.size} of {pose.status.size} points not usable; first: {pose.describe(int(bad[0]))}"
        )


# ----------------------------------------------------------------------------
# Mass matrix in end-effector coordinates
# ----------------------------------------------------------------------------


@dataclass(frozen=True)
class LinkMass:
    """Planar mass properties of one rigid link, in its own frame (SI).

    mass_kg; com_link_m: (x, y) of the COM in the link frame (origin at the
    link's first joint, x towards its second joint); izz_com_kg_m2: inertia
    about the COM, normal to the plane.
    """

    mass_kg: float
    com_link_m: tuple[float, float] = (0.0, 0.0)
    izz_com_kg_m2: float = 0.0

    def __post_init__(self) -> None:
        if not (np.isfinite(self.mass_kg) and self.mass_kg >= 0):
            raise DesignError("mass.mass_kg", f"must be >= 0, got {self.mass_kg!r}")
        if not (np.isfinite(self.izz_com_kg_m2) and self.izz_com_kg_m2 >= 0):
            raise DesignError("mass.izz_com_kg_m2", f"must be >= 0, got {self.izz_com_kg_m2!r}")


@dataclass(frozen=True)
class FiveBarMass:
    """Mass properties of a 5-bar's moving links plus actuator rotor inertia.

    proximal_*: frame origin Bi, x towards Ci; distal_*: origin Ci, x towards E;
    rotor_kg_m2: inertia of each actuator rotor about its joint axis, kg m^2 (adds J_m q_dot^2):
    one number for both, or (left, right) -- a rotor behind a capstan of ratio n counts
    n^2 J_m at its joint (:meth:`cad.device.ResolvedDevice.joint_rotor_inertia_kg_m2`).
    The end-effector hardware (journal, bearings) belongs to the body it drives.
    """

    proximal_left: LinkMass
    proximal_right: LinkMass
    distal_left: LinkMass
    distal_right: LinkMass
    rotor_kg_m2: float | tuple[float, float] = 0.0


def _rot(angle, v):
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * v[0] - s * v[1], s * v[0] + c * v[1]], axis=-1)


def link_twist_maps(fb: FiveBar, E_mm, mass: FiveBarMass) -> dict[str, np.ndarray]:
    """Map from end-effector velocity to each link's COM velocity and spin.

    Returns {link: A (N, 3, 2)} with (v_Gx [m/s], v_Gy [m/s], omega [rad/s]) =
    A @ E_dot [m/s], for the links proximal_left/right, distal_left/right.
    Raises :class:`KinematicsError` if any point is unreachable or singular.
    """
    E = _points(E_mm)
    pose = ik(fb, E)
    require_ok(pose)
    J, _ = jacobian_rad_per_m(fb, E)
    Em = E * 1e-3
    out = {}
    l2 = (fb.proximal_left_mm * 1e-3, fb.proximal_right_mm * 1e-3)
    C = (pose.C_left_mm * 1e-3, pose.C_right_mm * 1e-3)
    prox = (mass.proximal_left, mass.proximal_right)
    dist = (mass.distal_left, mass.distal_right)
    side = ("left", "right")
    N = E.shape[0]
    for i in range(2):
        q = pose.q_rad[:, i]
        # proximal: rotation about B_i at q_dot_i = J[i, :] E_dot
        w = J[:, i, :]  # (N, 2)
        r = _rot(q, np.asarray(prox[i].com_link_m, dtype=float))  # (N, 2): G - B_i
        A = np.zeros((N, 3, 2))
        A[:, 0, :] = -r[:, 1, None] * w
        A[:, 1, :] = r[:, 0, None] * w
        A[:, 2, :] = w
        out[f"proximal_{side[i]}"] = A
        # elbow velocity per unit E_dot: C_dot = l2 u'(q) q_dot
        up = np.stack([-np.sin(q), np.cos(q)], axis=-1)  # (N, 2)
        Cd = l2[i] * up[:, :, None] * w[:, None, :]  # (N, 2, 2): column k for E_dot = e_k
        d = Em - C[i]
        psi = np.arctan2(d[:, 1], d[:, 0])
        dd = np.einsum("nj,nj->n", d, d)
        rel = np.eye(2)[None, :, :] - Cd  # E_dot - C_dot, (N, 2, 2)
        psid = (d[:, 0, None] * rel[:, 1, :] - d[:, 1, None] * rel[:, 0, :]) / dd[:, None]
        r = _rot(psi, np.asarray(dist[i].com_link_m, dtype=float))  # G - C_i
        A = np.zeros((N, 3, 2))
        A[:, 0, :] = Cd[:, 0, :] - r[:, 1, None] * psid
        A[:, 1, :] = Cd[:, 1, :] + r[:, 0, None] * psid
        A[:, 2, :] = psid
        out[f"distal_{side[i]}"] = A
    return out


def mass_matrix_kg(fb: FiveBar, E_mm, mass: FiveBarMass) -> np.ndarray:
    """5-bar mass matrix in end-effector coordinates, (N, 2, 2) kg.

    Kinetic energy T = 1/2 E_dot^T M E_dot, summed over the four links
    (m v_G^2 + Izz omega^2) and the two rotors (J_m q_dot^2, q_dot = J E_dot).
    """
    E = _points(E_mm)
    maps = link_twist_maps(fb, E, mass)
    links = {
        "proximal_left": mass.proximal_left,
        "proximal_right": mass.proximal_right,
        "distal_left": mass.distal_left,
        "distal_right": mass.distal_right,
    }
    M = np.zeros((E.shape[0], 2, 2))
    for name, A in maps.items():
        lm = links[name]
        Av = A[:, :2, :]
        Aw = A[:, 2, :]
        M += lm.mass_kg * np.einsum("nik,nil->nkl", Av, Av)
        M += lm.izz_com_kg_m2 * np.einsum("nk,nl->nkl", Aw, Aw)
    J, _ = jacobian_rad_per_m(fb, E)
    jm = np.broadcast_to(np.asarray(mass.rotor_kg_m2, float), (2,))
    M += np.einsum("i,nik,nil->nkl", jm, J, J)
    return M
