"""Inertia coefficients H11..H33, equivalent inertia D(phi1) and apparent mass M(phi1).

Hoeken paper eqs (13)-(22). Units: SI inside (kg, m, kg.m^2); the
four-bar lengths (mm) are converted once here.

Generalization for a centre of mass off the joint line: each moving link i
has its COM at distance ``lG_i`` from its first joint (crank: A1, coupler: A2,
rocker: A4) at angle ``beta_i`` from the link's x axis (towards its second
joint). Kinetic energy of the coupler, whose first joint A2 moves with speed
l1*phi1', gives the cross term m2*l1*lG2*cos(phi1 - phi2 - beta2)*phi1'*phi2',
so eq (14) becomes

    D = H11 + 2 H12 cos(phi1 - phi2 - beta2) alpha1 + H22 alpha1^2 + H33 alpha2

with the paper's H11..H33 (eqs 16-19) unchanged; beta2 = 0 is the paper's
form exactly. The crank and rocker rotate about fixed pivots, so their COM
angles do not enter D. J_i are the link inertias about their COM (z axis).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cad import tolerances as tol
from cad.errors import DesignError, SingularJacobianError
from cad.kinematics.fourbar import FourBar, FourBarPose, jacobian_mm_per_rad, velocity_ratios
from cad.kinematics.metrics import PathFrame

MM = 1e-3


@dataclass(frozen=True)
class PlanarLinkInertia:
    """Planar mass properties of one link in its own frame (SI).

    mass_kg : link mass.
    lG_m : distance first joint -> COM (m).
    beta_rad : angle of the COM from the link's x axis (rad).
    Jzz_com_kg_m2 : inertia about the COM, z axis (kg.m^2).
    """

    mass_kg: float
    lG_m: float
    beta_rad: float
    Jzz_com_kg_m2: float

    def __post_init__(self) -> None:
        for name in ("mass_kg", "lG_m", "Jzz_com_kg_m2"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v >= 0):
                raise DesignError(f"inertia.{name}", f"must be finite and >= 0, got {v!r}")
        if not np.isfinite(self.beta_rad):
            raise DesignError("inertia.beta_rad", f"must be finite, got {self.beta_rad!r}")

    @classmethod
    def from_com(cls, mass_kg: float, com_link_m: np.ndarray, Jzz_com_kg_m2: float) -> PlanarLinkInertia:
        """From a COM (x, y[, z]) in the link frame, m."""
        x, y = float(com_link_m[0]), float(com_link_m[1])
        return cls(mass_kg, float(np.hypot(x, y)), float(np.arctan2(y, x)), Jzz_com_kg_m2)


@dataclass(frozen=True)
class InertiaCoefficients:
    """H11, H12, H22, H33 in kg.m^2 and the coupler COM angle beta2 (rad).

    Hoeken paper eqs (16)-(19). ``beta2_rad = 0`` reproduces eq (14) exactly.
    """

    H11_kg_m2: float
    H12_kg_m2: float
    H22_kg_m2: float
    H33_kg_m2: float
    beta2_rad: float = 0.0

    def __post_init__(self) -> None:
        for name in ("H11_kg_m2", "H12_kg_m2", "H22_kg_m2", "H33_kg_m2", "beta2_rad"):
            v = getattr(self, name)
            if not np.isfinite(v):
                raise DesignError(f"inertia.{name}", f"must be finite, got {v!r}")
        for name in ("H11_kg_m2", "H22_kg_m2", "H33_kg_m2"):
            v = getattr(self, name)
            if v < 0:
                raise DesignError(f"inertia.{name}", f"must be >= 0, got {v!r}")
        # D(phi1) >= 0 for every motion needs H12^2 <= H11 H22 (physically H11 >= m2 l1^2 and
        # H22 >= m2 lG2^2, so it always holds for real links)
        if self.H12_kg_m2**2 > self.H11_kg_m2 * self.H22_kg_m2 * (1 + 1e-12):
            raise DesignError(
                "inertia.H12_kg_m2",
                f"|H12| = {abs(self.H12_kg_m2):.4g} exceeds sqrt(H11 H22) = "
                f"{np.sqrt(self.H11_kg_m2 * self.H22_kg_m2):.4g}: D(phi1) of eq (14) would be negative",
            )

    def as_dict(self) -> dict[str, float]:
        return {
            "H11_kg_m2": self.H11_kg_m2, "H12_kg_m2": self.H12_kg_m2,
            "H22_kg_m2": self.H22_kg_m2, "H33_kg_m2": self.H33_kg_m2,
            "beta2_deg": float(np.degrees(self.beta2_rad)),
        }


#: The paper's CAD values (Hoeken paper §III.B.2, text before Fig. 6), kg.m^2.
PAPER_H = InertiaCoefficients(2.97e-5, 3.22e-5, 1.17e-4, 7.09e-5)


def h_from_links(
    fb: FourBar,
    crank: PlanarLinkInertia,
    coupler: PlanarLinkInertia,
    rocker: PlanarLinkInertia,
    Jm_kg_m2: float = 0.0,
) -> InertiaCoefficients:
    """H11..H33 from the three moving links and the motor rotor inertia Jm.

    H11 = m1 lG1^2 + m2 l1^2 + Jm + J1 (eq 16), H22 = m2 lG2^2 + J2 (eq 17),
    H33 = m3 lG3^2 + J3 (eq 18), H12 = m2 l1 lG2 (eq 19); beta2 = coupler COM angle.
    The handle (at P) belongs to the coupler's mass properties.
    """
    if not (np.isfinite(Jm_kg_m2) and Jm_kg_m2 >= 0):
        raise DesignError("parts.motor_rotor_inertia_g_cm2", f"rotor inertia must be finite and >= 0, got {Jm_kg_m2!r} kg m^2")
    l1 = fb.l1_mm * MM
    H11 = crank.mass_kg * crank.lG_m**2 + coupler.mass_kg * l1**2 + Jm_kg_m2 + crank.Jzz_com_kg_m2
    H22 = coupler.mass_kg * coupler.lG_m**2 + coupler.Jzz_com_kg_m2
    H33 = rocker.mass_kg * rocker.lG_m**2 + rocker.Jzz_com_kg_m2
    H12 = coupler.mass_kg * l1 * coupler.lG_m
    return InertiaCoefficients(H11, H12, H22, H33, coupler.beta_rad)


def equivalent_inertia(fb: FourBar, pose: FourBarPose, H: InertiaCoefficients) -> np.ndarray:
    """D(phi1) in kg.m^2, shape (N,) (Hoeken paper eqs 14-15, generalized by beta2)."""
    a1, a3 = velocity_ratios(fb, pose)
    c = np.cos(pose.phi1_rad - pose.phi2_rad - H.beta2_rad)
    return H.H11_kg_m2 + 2.0 * H.H12_kg_m2 * c * a1 + H.H22_kg_m2 * a1**2 + H.H33_kg_m2 * a3**2


def apparent_mass_matrix(
    fb: FourBar, pose: FourBarPose, H: InertiaCoefficients, frame: PathFrame | None = None,
) -> np.ndarray:
    """M(phi1) = J^+T D J^+ (eq 22), kg, shape (N, 2, 2), in ``frame`` axes (R0 if None).

    J (2x1, m/rad) has the pseudo-inverse J^+ = J^T / (J^T J); a J with
    |J| below PINV_RCOND times the linkage's own scale (l1 + le, the largest
    |J| a unit velocity ratio gives; also never below max|J| over the poses) is
    singular (SingularJacobianError naming phi1). The scale does not depend on
    which poses are passed, so a batch holding only the singular pose is caught.
    """
    J = jacobian_mm_per_rad(fb, pose) * MM
    if frame is not None:
        J = frame.rotate(J)
    n2 = np.einsum("ni,ni->n", J, J)
    ref = max(float(n2.max()) if n2.size else 0.0, ((fb.l1_mm + fb.le_mm) * MM) ** 2)
    bad = n2 <= (tol.PINV_RCOND**2) * ref
    if bad.any():
        where = np.degrees(pose.phi1_rad[bad]) if bad.any() else np.degrees(pose.phi1_rad)
        raise SingularJacobianError(
            f"J = dP/dphi1 vanishes at phi1 = {where.min():.3f} deg: the apparent mass "
            "(eq 22) is unbounded there; restrict the crank range"
        )
    D = equivalent_inertia(fb, pose, H)
    Jp = J / n2[:, None]  # rows of J^+ (1x2 each)
    return D[:, None, None] * Jp[:, :, None] * Jp[:, None, :]


def apparent_mass_summary(M_kg: np.ndarray) -> dict[str, float]:
    """Ranges of M11, M12, M22 over the stroke, grams (Fig. 6)."""
    g = 1e3
    return {
        "M11_min_g": float(M_kg[:, 0, 0].min() * g), "M11_max_g": float(M_kg[:, 0, 0].max() * g),
        "M12_min_g": float(M_kg[:, 0, 1].min() * g), "M12_max_g": float(M_kg[:, 0, 1].max() * g),
        "M22_min_g": float(M_kg[:, 1, 1].min() * g), "M22_max_g": float(M_kg[:, 1, 1].max() * g),
    }
