"""Twin-pantograph haptic mouse: two 5-bars driving a crankshaft (isotropy paper §4.1, Fig. 1).

Two planar 5-bars, stacked in two parallel planes, drive the two journals of a
crankshaft end effector: the *knob* pantograph drives the main journal, whose
axis carries the knob (diameter l5), and the *crank* pantograph drives the
crank pin, l6 from the main journal. Task coordinates X = (x, y, theta): the
main journal (knob axis) position in the base frame (mm) and the crank angle
theta (rad, unlimited: the two planes let the linkages pass over each other).

    P_knob  = (x, y)
    P_crank = (x, y) + l6 (cos theta, sin theta)

Four actuators for three DOF (one redundant). Reading of the paper used here:
"the radius of the crankshaft l6" is the crank throw, so the crank pantograph
sees the knob workspace grown by l6 on all four sides, as §4.1 says.

Crank length from the hand's force/torque ratio (eq 7):
    l6 = 2 tau_max / (d f_max) * l5 = 1.6 l5.
Read as the torque of a couple of journal forces, eq 7 says the moment
requirement is M = F l6 / 2, which is the default task scaling here
(S_T = diag(F, F, F l6 / 2), eq 4).

Jacobian (q_dot = J X_dot, eq 1), rows (q1, q2) of the knob pantograph and
(q3, q4) of the crank pantograph:
    J = [[J_knob, 0], [J_crank, J_crank l6 (-sin theta, cos theta)^T]]   (4 x 3)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cad.errors import DesignError
from cad.isotropy.gii import gii_from_jacobians, square_grid_mm
from cad.kinematics import fivebar as fb5

#: Eq (7): l6 / l5 = 2 tau_max / (d f_max) = 1.6 (hand data from the scaling paper, ref [21]).
CRANK_RATIO_EQ7 = 1.6

#: Status offset of the crank pantograph's codes (knob pantograph codes are fb5's).
CRANK_STATUS_OFFSET = 10


def _twin_status_names() -> dict[int, str]:
    names = {0: "ok"}
    for code, text in fb5.STATUS_NAMES.items():
        if code:
            names[code] = f"knob pantograph: {text}"
            names[code + CRANK_STATUS_OFFSET] = f"crank pantograph: {text}"
    return names


#: status code -> reason, for both pantographs.
STATUS_NAMES = _twin_status_names()


def crank_length_mm(knob_diameter_mm: float, ratio: float = CRANK_RATIO_EQ7) -> float:
    """Crank length l6 = ratio * l5 (isotropy paper eq 7; ratio 1.6)."""
    if not (np.isfinite(knob_diameter_mm) and knob_diameter_mm > 0):
        raise DesignError("mechanism.knob_diameter_mm", f"must be > 0, got {knob_diameter_mm!r}")
    return float(ratio * knob_diameter_mm)


@dataclass(frozen=True)
class TwinPantograph:
    """Twin-pantograph geometry (mm).

    knob: 5-bar driving the main journal (knob axis); crank: 5-bar driving the
    crank pin; both in the common base frame (they may coincide in plan: they
    work in different planes). crank_mm: l6; knob_diameter_mm: l5.
    """

    knob: fb5.FiveBar
    crank: fb5.FiveBar
    crank_mm: float
    knob_diameter_mm: float = 12.5

    def __post_init__(self) -> None:
        if not (np.isfinite(self.crank_mm) and self.crank_mm > 0):
            raise DesignError("mechanism.crank_mm", f"must be > 0, got {self.crank_mm!r}")

    @classmethod
    def symmetric(
        cls,
        base_mm: float,
        proximal_mm: float,
        distal_mm: float,
        knob_diameter_mm: float = 12.5,
        crank_mm: float | None = None,
    ) -> TwinPantograph:
        """Two identical symmetric 5-bars on the same base line; l6 from eq (7) by default."""
        f = fb5.FiveBar.symmetric(base_mm, proximal_mm, distal_mm)
        l6 = crank_length_mm(knob_diameter_mm) if crank_mm is None else float(crank_mm)
        return cls(f, f, l6, float(knob_diameter_mm))


def _task(X) -> np.ndarray:
    X = np.asarray(X, dtype=float)
    if X.ndim == 1:
        X = X[None, :]
    if X.ndim != 2 or X.shape[1] != 3 or not np.all(np.isfinite(X)):
        raise DesignError(
            "X", f"must be finite (N, 3) = (x_mm, y_mm, theta_rad), got {np.shape(X)}"
        )
    return X


def journals_mm(tp: TwinPantograph, X) -> tuple[np.ndarray, np.ndarray]:
    """Main-journal and crank-pin positions (N, 2) mm for task poses X (N, 3)."""
    X = _task(X)
    pk = X[:, :2].copy()
    pc = pk + tp.crank_mm * np.stack([np.cos(X[:, 2]), np.sin(X[:, 2])], axis=-1)
    return pk, pc


@dataclass(frozen=True)
class TwinPose:
    """IK of the twin pantograph at N task poses: q_rad (N, 4) = (q1, q2) knob,
    (q3, q4) crank; status (N,) codes of :data:`STATUS_NAMES`; the two 5-bar poses."""

    X: np.ndarray
    q_rad: np.ndarray
    status: np.ndarray
    knob: fb5.FiveBarPose
    crank: fb5.FiveBarPose


def _combine_status(sk: np.ndarray, sc: np.ndarray) -> np.ndarray:
    return np.where(sk != 0, sk, np.where(sc != 0, sc + CRANK_STATUS_OFFSET, 0)).astype(np.int16)


def ik(tp: TwinPantograph, X) -> TwinPose:
    """Actuator angles for task poses X (N, 3) = (x_mm, y_mm, theta_rad)."""
    X = _task(X)
    pk, pc = journals_mm(tp, X)
    a = fb5.ik(tp.knob, pk)
    b = fb5.ik(tp.crank, pc)
    return TwinPose(
        X, np.concatenate([a.q_rad, b.q_rad], axis=1), _combine_status(a.status, b.status), a, b
    )


def jacobian_arrays(knob_params, crank_params, crank_mm, x_mm, y_mm, theta):
    """Vectorized 4x3 Jacobian kernel (broadcast): (J (..., 4, 3) SI, status).

    knob_params / crank_params: the 10-tuples of :meth:`FiveBar.arrays`
    (entries may be arrays); columns x [rad/m], y [rad/m], theta [rad/rad].
    """
    c, s = np.asarray(np.cos(theta)), np.asarray(np.sin(theta))
    Jk, sk = fb5.jacobian_arrays(*knob_params, x_mm, y_mm)
    Jc, sc = fb5.jacobian_arrays(*crank_params, x_mm + crank_mm * c, y_mm + crank_mm * s)
    Jk = Jk * 1e3
    Jc = Jc * 1e3
    shape = np.broadcast(sk, sc).shape
    J = np.zeros(shape + (4, 3))
    J[..., 0:2, 0:2] = Jk
    J[..., 2:4, 0:2] = Jc
    l6 = np.asarray(crank_mm, dtype=float) * 1e-3
    J[..., 2:4, 2] = (Jc[..., :, 0] * (-s)[..., None] + Jc[..., :, 1] * c[..., None]) * np.asarray(
        l6
    )[..., None]
    return J, _combine_status(sk, sc)


def jacobian_si(tp: TwinPantograph, X) -> tuple[np.ndarray, np.ndarray]:
    """J (N, 4, 3) with q_dot = J (x_dot [m/s], y_dot [m/s], theta_dot [rad/s]); status (N,).

    Rows of a pantograph at a non-ok point are 0. Isotropy paper eq (1).
    """
    X = _task(X)
    return jacobian_arrays(
        tp.knob.arrays(), tp.crank.arrays(), tp.crank_mm, X[:, 0], X[:, 1], X[:, 2]
    )


def task_scale(force_N: float, crank_mm: float, moment_Nm: float | None = None) -> np.ndarray:
    """S_T diagonal (F, F, M) (eq 4); M defaults to F l6 / 2 (eq 7 read as a couple)."""
    if not (np.isfinite(force_N) and force_N > 0):
        raise DesignError("actuators.force_max_N", f"must be > 0, got {force_N!r}")
    M = force_N * crank_mm * 1e-3 / 2 if moment_Nm is None else float(moment_Nm)
    if not (np.isfinite(M) and M > 0):
        if moment_Nm is None:
            raise DesignError(
                "actuators.force_max_N",
                f"the default moment scale F * l6 / 2 = {M!r} N m is outside float64 "
                f"(F = {force_N!r} N, l6 = {crank_mm!r} mm): give moment_max_Nm",
            )
        raise DesignError("actuators.moment_max_Nm", f"must be > 0, got {moment_Nm!r}")
    return np.array([force_N, force_N, M])


def workspace_grid(center_mm, side_mm, grid: int, theta_grid: int) -> np.ndarray:
    """Task samples (grid * grid * theta_grid, 3) = (x_mm, y_mm, theta_rad), C order (y, x, theta).

    The square (side_mm scalar) or rectangle (side_mm = [W, H] mm), boundary included, times theta_grid angles over the full turn
    [0, 2 pi) (the rotation range is unlimited).
    """
    if (
        isinstance(theta_grid, bool)
        or not isinstance(theta_grid, (int, np.integer))
        or theta_grid < 1
    ):
        raise DesignError("workspace.theta_grid", f"must be an integer >= 1, got {theta_grid!r}")
    xy = square_grid_mm(center_mm, side_mm, grid)
    th = np.linspace(0.0, 2 * np.pi, int(theta_grid), endpoint=False)
    X = np.repeat(xy, th.size, axis=0)
    return np.column_stack([X, np.tile(th, xy.shape[0])])


def twin_gii(
    tp: TwinPantograph,
    center_mm,
    side_mm,
    grid: int,
    theta_grid: int,
    torque_max_Nm=1.0,
    force_max_N: float = 1.0,
    moment_max_Nm: float | None = None,
):
    """GII (eq 5) of the twin pantograph over the square x full-turn workspace.

    Returns a :class:`cad.isotropy.gii.GIIResult` whose points are
    (x_mm, y_mm, theta_deg).
    """
    X = workspace_grid(center_mm, side_mm, grid, theta_grid)
    J, status = jacobian_si(tp, X)
    pts = X.copy()
    pts[:, 2] = np.degrees(pts[:, 2])
    S_T = task_scale(force_N=force_max_N, crank_mm=tp.crank_mm, moment_Nm=moment_max_Nm)
    return gii_from_jacobians(J, status, pts, torque_max_Nm, S_T, STATUS_NAMES)


# ----------------------------------------------------------------------------
# Mass matrix and effective mass at home
# ----------------------------------------------------------------------------


@dataclass(frozen=True)
class TwinMass:
    """Mass properties of the moving parts: both 5-bars (with rotors) and the
    crankshaft body (crankshaft, journals, knob; frame origin at the main
    journal, x towards the crank pin)."""

    knob: fb5.FiveBarMass
    crank: fb5.FiveBarMass
    crankshaft: fb5.LinkMass


def task_mass_matrix(tp: TwinPantograph, X, mass: TwinMass) -> np.ndarray:
    """Mass matrix in task coordinates (N, 3, 3): kg, kg m, kg m^2 blocks.

    T = 1/2 X_dot^T M X_dot with X_dot = (x_dot [m/s], y_dot [m/s], theta_dot [rad/s]):
    M = T_k^T M_knob T_k + T_c^T M_crank T_c + crankshaft, where T_k, T_c map
    X_dot to the journal velocities.
    """
    X = _task(X)
    pk, pc = journals_mm(tp, X)
    Mk = fb5.mass_matrix_kg(tp.knob, pk, mass.knob)
    Mc = fb5.mass_matrix_kg(tp.crank, pc, mass.crank)
    N = X.shape[0]
    th = X[:, 2]
    l6 = tp.crank_mm * 1e-3
    Tk = np.zeros((N, 2, 3))
    Tk[:, 0, 0] = Tk[:, 1, 1] = 1.0
    Tc = Tk.copy()
    Tc[:, 0, 2] = -l6 * np.sin(th)
    Tc[:, 1, 2] = l6 * np.cos(th)
    M = np.einsum("nik,nij,njl->nkl", Tk, Mk, Tk) + np.einsum("nik,nij,njl->nkl", Tc, Mc, Tc)
    cs = mass.crankshaft
    r = _rot2(th, np.asarray(cs.com_link_m, dtype=float))  # G - main journal, (N, 2) m
    Tg = Tk.copy()
    Tg[:, 0, 2] = -r[:, 1]
    Tg[:, 1, 2] = r[:, 0]
    M += cs.mass_kg * np.einsum("nik,nil->nkl", Tg, Tg)
    M[:, 2, 2] += cs.izz_com_kg_m2
    return M


def _rot2(angle, v):
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * v[0] - s * v[1], s * v[0] + c * v[1]], axis=-1)


def effective_mass_home(tp: TwinPantograph, home, mass: TwinMass) -> dict[str, float]:
    """Effective mass at the home pose ``home`` = (x_mm, y_mm, theta_rad).

    Two readings, both reported: ``*_diag`` are the diagonal of the task mass
    matrix (the mass felt moving along one axis with the others held still);
    ``*_apparent`` are 1 / (M^-1)_ii (the mass felt pushing along one axis with
    the others free). Compare with the paper's Table 1 (395 g x, 370 g y,
    4781 g cm^2 rotation).
    """
    M = task_mass_matrix(tp, np.asarray(home, dtype=float)[None, :], mass)[0]
    Mi = np.linalg.inv(M)
    return {
        "mass_x_g_diag": float(M[0, 0] * 1e3),
        "mass_y_g_diag": float(M[1, 1] * 1e3),
        "inertia_theta_g_cm2_diag": float(M[2, 2] * 1e7),
        "mass_x_g_apparent": float(1e3 / Mi[0, 0]),
        "mass_y_g_apparent": float(1e3 / Mi[1, 1]),
        "inertia_theta_g_cm2_apparent": float(1e7 / Mi[2, 2]),
    }
