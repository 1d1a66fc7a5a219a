"""Four-bar loop closure, velocity ratios and Jacobian, vectorized over phi1.

Symbols follow the Hoeken paper (Joinié-Maurin et al.), Fig. 1: frame R0 has
its origin at the crank pivot A1; the rocker pivot is A4 = (l5, l4);
l1 = |A1A2| (crank), l2 = |A2A3| (coupler), l3 = |A4A3| (rocker). Angles
phi_i are measured from x0 to link i: phi1 (crank A1->A2), phi2 (coupler
A2->A3), phi3 (rocker A4->A3). The coupler point is
P = A2 + le * (cos(phi2 + phi_e), sin(phi2 + phi_e)) (eqs 9-10).

Lengths in mm, angles in rad. Every function takes arrays of phi1 of shape
(N,) and returns arrays over N.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from cad import tolerances as tol
from cad.errors import BranchJumpError, ClosureError, DesignError, ToggleError
from cad.kinematics.search import golden_minimize


@dataclass(frozen=True)
class FourBar:
    """A planar four-bar with a coupler point (Hoeken paper Fig. 1).

    Parameters
    ----------
    l1_mm, l2_mm, l3_mm : crank A1A2, coupler A2A3, rocker A4A3 lengths (> 0).
    l4_mm, l5_mm : rocker pivot A4 = (l5, l4) in R0 (mm).
    le_mm : distance A2 -> P along the coupler direction rotated by phi_e (>= 0).
    phi_e_rad : angle of A2P relative to A2A3 (rad).
    branch : assembly mode, +1 or -1: phi2 = atan2(B, A) + branch * acos(C / sqrt(A^2 + B^2)).
    """

    l1_mm: float
    l2_mm: float
    l3_mm: float
    l4_mm: float
    l5_mm: float
    le_mm: float
    phi_e_rad: float
    branch: int

    def __post_init__(self) -> None:
        lo, hi = tol.LENGTH_MIN_MM, tol.LENGTH_MAX_MM
        for name in ("l1_mm", "l2_mm", "l3_mm"):
            v = getattr(self, name)
            if not np.isfinite(v) or v <= 0:
                raise DesignError(f"mechanism.{name}", f"must be a finite length > 0, got {v!r}")
            if not lo <= v <= hi:
                raise DesignError(f"mechanism.{name}", f"must lie in [{lo:g}, {hi:g}] mm, got {v!r}")
        for name in ("l4_mm", "l5_mm", "phi_e_rad"):
            v = getattr(self, name)
            if not np.isfinite(v):
                raise DesignError(f"mechanism.{name}", f"must be finite, got {v!r}")
        for name in ("l4_mm", "l5_mm"):
            v = getattr(self, name)
            if abs(v) > hi:
                raise DesignError(f"mechanism.{name}", f"|value| must be <= {hi:g} mm, got {v!r}")
        if not np.isfinite(self.le_mm) or self.le_mm < 0:
            raise DesignError("mechanism.le_mm", f"must be >= 0, got {self.le_mm!r}")
        if self.le_mm > hi:
            raise DesignError("mechanism.le_mm", f"must be <= {hi:g} mm, got {self.le_mm!r}")
        if self.le_mm == 0 and self.phi_e_rad != 0:
            pass  # P coincides with A2; phi_e is irrelevant but harmless
        if self.branch not in (1, -1):
            raise DesignError("mechanism.branch", f"must be +1 or -1, got {self.branch!r}")
        if np.hypot(self.l4_mm, self.l5_mm) == 0:
            raise DesignError("mechanism.l5_mm", "A4 coincides with A1 (l4 = l5 = 0)")

    @property
    def A4_mm(self) -> np.ndarray:
        """Rocker pivot A4 = (l5, l4) in R0, mm."""
        return np.array([self.l5_mm, self.l4_mm])

    def scaled(self, k: float) -> FourBar:
        """The same linkage with every length multiplied by ``k`` (angles kept)."""
        return FourBar(
            self.l1_mm * k, self.l2_mm * k, self.l3_mm * k, self.l4_mm * k, self.l5_mm * k,
            self.le_mm * k, self.phi_e_rad, self.branch,
        )

    def lengths_mm(self) -> dict[str, float]:
        return {
            "l1_mm": self.l1_mm, "l2_mm": self.l2_mm, "l3_mm": self.l3_mm,
            "l4_mm": self.l4_mm, "l5_mm": self.l5_mm, "le_mm": self.le_mm,
        }


@dataclass(frozen=True)
class FourBarPose:
    """Poses of a four-bar at N crank angles. Points in R0, mm; angles rad."""

    phi1_rad: np.ndarray
    phi2_rad: np.ndarray
    phi3_rad: np.ndarray
    A1_mm: np.ndarray
    A4_mm: np.ndarray
    A2_mm: np.ndarray
    A3_mm: np.ndarray
    P_mm: np.ndarray

    def __len__(self) -> int:
        return len(self.phi1_rad)


def abc(fb: FourBar, phi1_rad: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Coefficients A, B, C of A cos(phi2) + B sin(phi2) = C (Hoeken paper eqs 4-6)."""
    phi1 = np.asarray(phi1_rad, dtype=float)
    c1, s1 = np.cos(phi1), np.sin(phi1)
    l1, l2, l3, l4, l5 = fb.l1_mm, fb.l2_mm, fb.l3_mm, fb.l4_mm, fb.l5_mm
    A = 2.0 * l2 * (l1 * c1 - l5)
    B = 2.0 * l2 * (l1 * s1 - l4)
    C = l3**2 - l1**2 - l2**2 - l4**2 - l5**2 + 2.0 * l1 * (l5 * c1 + l4 * s1)
    return A, B, C


def closure_margin(fb: FourBar, phi1_rad: np.ndarray) -> np.ndarray:
    """Relative closure margin 1 - C^2 / (A^2 + B^2), in (-inf, 1].

    >= 0 where the loop closes; 0 at a toggle of coupler and rocker
    (the two assembly modes meet); < 0 where the loop cannot close.
    """
    A, B, C = abc(fb, phi1_rad)
    R2 = A * A + B * B
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(R2 > 0, 1.0 - C * C / np.where(R2 > 0, R2, 1.0), -np.inf)


def _phi2_atan2(fb: FourBar, phi1: np.ndarray, branch: int) -> tuple[np.ndarray, np.ndarray]:
    A, B, C = abc(fb, phi1)
    R = np.hypot(A, B)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = C / R
    ok = np.isfinite(ratio) & (np.abs(ratio) <= 1.0 + 1e-12)
    phi2 = np.arctan2(B, A) + branch * np.arccos(np.clip(ratio, -1.0, 1.0))
    return phi2, ok


def _raise_closure(phi1: np.ndarray, ok: np.ndarray) -> None:
    bad = np.degrees(phi1[~ok])
    raise ClosureError(
        f"the loop cannot close for phi1 in [{bad.min():.3f}, {bad.max():.3f}] deg "
        f"({bad.size} of {phi1.size} samples; |C| > sqrt(A^2+B^2), Hoeken paper eqs 4-6): "
        "shorten the range or change the link lengths"
    )


def solve(fb: FourBar, phi1_rad: np.ndarray) -> FourBarPose:
    """Positions of every joint and of P at crank angles ``phi1_rad``.

    Uses phi2 = atan2(B, A) + branch * acos(C / sqrt(A^2 + B^2)) (the
    singularity-free form of eq 3), then phi3 from eqs 7-8 and P from eqs 9-10.
    phi2 and phi3 are unwrapped along the array so they are continuous.

    Raises ClosureError naming the phi1 interval where |C| > sqrt(A^2 + B^2).
    """
    phi1 = np.atleast_1d(np.asarray(phi1_rad, dtype=float))
    phi2, ok = _phi2_atan2(fb, phi1, fb.branch)
    if not ok.all():
        _raise_closure(phi1, ok)
    c1, s1 = np.cos(phi1), np.sin(phi1)
    A2 = np.stack([fb.l1_mm * c1, fb.l1_mm * s1], axis=-1)
    A3 = A2 + fb.l2_mm * np.stack([np.cos(phi2), np.sin(phi2)], axis=-1)
    d3 = A3 - fb.A4_mm
    phi3 = np.arctan2(d3[:, 1], d3[:, 0])  # eqs 7-8
    if phi1.size > 1:
        phi2 = np.unwrap(phi2)
        phi3 = np.unwrap(phi3)
    P = A2 + fb.le_mm * np.stack([np.cos(phi2 + fb.phi_e_rad), np.sin(phi2 + fb.phi_e_rad)], axis=-1)
    return FourBarPose(phi1, phi2, phi3, np.zeros(2), fb.A4_mm, A2, A3, P)


def phi2_tan_half(fb: FourBar, phi1_rad: np.ndarray, sign: int) -> np.ndarray:
    """Reference only: eq (3), phi2 = 2 atan((B +/- sqrt(A^2+B^2-C^2)) / (A + C)).

    Kept to document where it breaks: at A + C = 0 it divides by zero (one root
    becomes 0/0 and the other +/-inf), and near it loses precision. The tool
    uses :func:`solve` (atan2 form) everywhere. Returns NaN where undefined.
    """
    A, B, C = abc(fb, phi1_rad)
    disc = A * A + B * B - C * C
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (B + sign * np.sqrt(disc)) / (A + C)
        return 2.0 * np.arctan(t)


def tan_half_breakdown(fb: FourBar, phi1_rad: np.ndarray) -> np.ndarray:
    """Mask of samples where eq (3) is ill-conditioned: |A + C| / sqrt(A^2 + B^2) < TAN_HALF_EPS."""
    A, B, C = abc(fb, phi1_rad)
    return np.abs(A + C) < tol.TAN_HALF_EPS * np.hypot(A, B)


def velocity_ratios(fb: FourBar, pose: FourBarPose) -> tuple[np.ndarray, np.ndarray]:
    """dphi2/dphi1 and dphi3/dphi1 (Hoeken paper eq 11), shape (N,) each.

    Raises ToggleError where |sin(phi2 - phi3)| < TOGGLE_SIN.
    """
    s23 = np.sin(pose.phi2_rad - pose.phi3_rad)
    _check_toggle(pose, s23)
    a2 = fb.l1_mm * np.sin(pose.phi3_rad - pose.phi1_rad) / (fb.l2_mm * s23)
    a3 = fb.l1_mm * np.sin(pose.phi2_rad - pose.phi1_rad) / (fb.l3_mm * s23)
    return a2, a3


def _check_toggle(pose: FourBarPose, s23: np.ndarray) -> None:
    bad = np.abs(s23) < tol.TOGGLE_SIN
    if bad.any():
        where = np.degrees(pose.phi1_rad[bad])
        raise ToggleError(
            f"toggle (coupler and rocker aligned, |sin(phi2-phi3)| < {tol.TOGGLE_SIN}) at phi1 = "
            f"{where.min():.3f}..{where.max():.3f} deg: eq (11) is singular there; "
            "move the range away or change the link lengths"
        )


def jacobian_mm_per_rad(fb: FourBar, pose: FourBarPose) -> np.ndarray:
    """J = dP/dphi1 in R0, mm/rad, shape (N, 2) (Hoeken paper eq 12).

    J = l1 (-sin phi1, cos phi1) + le * alpha2 * (-sin(phi2+phi_e), cos(phi2+phi_e))
    with alpha2 = dphi2/dphi1 from eq (11).
    """
    a2, _ = velocity_ratios(fb, pose)
    ang = pose.phi2_rad + fb.phi_e_rad
    jx = -fb.l1_mm * np.sin(pose.phi1_rad) - fb.le_mm * a2 * np.sin(ang)
    jy = fb.l1_mm * np.cos(pose.phi1_rad) + fb.le_mm * a2 * np.cos(ang)
    return np.stack([jx, jy], axis=-1)


def transmission_angle_rad(pose: FourBarPose) -> np.ndarray:
    """Transmission angle folded into [0, pi/2]: asin(|sin(phi2 - phi3)|).

    pi/2 is ideal (coupler perpendicular to rocker); 0 is a toggle.
    """
    return np.arcsin(np.clip(np.abs(np.sin(pose.phi2_rad - pose.phi3_rad)), 0.0, 1.0))


def loop_residual_mm(fb: FourBar, pose: FourBarPose) -> np.ndarray:
    """Norm of the residual of eqs (1)-(2) at every pose, mm."""
    r1 = (fb.l1_mm * np.cos(pose.phi1_rad) + fb.l2_mm * np.cos(pose.phi2_rad)
          - fb.l3_mm * np.cos(pose.phi3_rad) - fb.l5_mm)
    r2 = (fb.l1_mm * np.sin(pose.phi1_rad) + fb.l2_mm * np.sin(pose.phi2_rad)
          - fb.l3_mm * np.sin(pose.phi3_rad) - fb.l4_mm)
    return np.hypot(r1, r2)


@dataclass(frozen=True)
class RangeCheck:
    """What happens over a crank range: closure, toggles, branch jumps.

    Angles in deg (edge quantities). ``problems`` is a list of one-line
    messages; empty when the range is usable.
    """

    closes: bool
    closure_gap_deg: tuple[float, float] | None
    toggle_at_deg: float | None
    branch_jump_at_deg: float | None
    min_transmission_angle_deg: float
    problems: tuple[str, ...]


def check_range(fb: FourBar, phi1_min_rad: float, phi1_max_rad: float, samples: int = 721) -> RangeCheck:
    """Sample [phi1_min, phi1_max] and detect non-closure, toggles and branch jumps.

    A branch jump is a discontinuity of the sampled phi2 that the velocity
    ratio of eq (11) cannot explain: the sampled motion skipped through a
    closure gap or a toggle narrower than the sample spacing.
    """
    phi1 = np.linspace(phi1_min_rad, phi1_max_rad, samples)
    problems: list[str] = []
    phi2, ok = _phi2_atan2(fb, phi1, fb.branch)
    gap = None
    jump = None
    if not ok.all():
        bad = np.degrees(phi1[~ok])
        gap = (float(bad.min()), float(bad.max()))
        problems.append(
            f"the loop cannot close for phi1 in [{gap[0]:.3f}, {gap[1]:.3f}] deg (|C| > sqrt(A^2+B^2))"
        )
    if ok.all() and samples >= 3:
        between = _margin_dip_between_samples(fb, phi1)
        if between is not None:
            a, b, m_min, phi_min = between
            if m_min < 0:
                jump = float(np.degrees(a))
                problems.append(
                    f"branch jump between phi1 = {np.degrees(a):.3f} and {np.degrees(b):.3f} deg: "
                    f"every sample closes but the loop cannot close near phi1 = "
                    f"{np.degrees(phi_min):.3f} deg (a gap narrower than the sampling); the "
                    "sampled motion changes assembly mode there. Sample more densely or shorten the range"
                )
    pose = solve(fb, phi1[ok]) if ok.any() else None
    toggle = None
    mu_min = float("nan")
    if pose is not None and len(pose) > 0:
        s23 = np.sin(pose.phi2_rad - pose.phi3_rad)
        mu = transmission_angle_rad(pose)
        mu_min = float(np.degrees(mu.min()))
        tog = np.abs(s23) < tol.TOGGLE_SIN
        # a sign change of sin(phi2 - phi3) between samples is a toggle crossed between them
        flips = np.nonzero(np.sign(s23[1:]) != np.sign(s23[:-1]))[0]
        if (tog.any() or flips.size) and jump is None:
            idx = int(np.argmin(np.abs(s23)))
            toggle = float(np.degrees(pose.phi1_rad[idx]))
            problems.append(
                f"toggle inside the range at phi1 = {toggle:.3f} deg (sin(phi2 - phi3) -> 0, "
                f"transmission angle {mu_min:.2f} deg)"
            )
        elif len(pose) > 2 and jump is None:
            a2 = fb.l1_mm * np.sin(pose.phi3_rad - pose.phi1_rad) / (fb.l2_mm * s23)
            dphi1 = np.diff(pose.phi1_rad)
            dphi2 = np.diff(pose.phi2_rad)
            bound = 3.0 * np.maximum(np.abs(a2[1:]), np.abs(a2[:-1])) * np.abs(dphi1)
            bad = (np.abs(dphi2) > bound) & (np.abs(dphi2) > tol.BRANCH_JUMP_RAD)
            if bad.any():
                i = int(np.nonzero(bad)[0][0])
                jump = float(np.degrees(pose.phi1_rad[i]))
                problems.append(
                    f"branch jump between phi1 = {jump:.3f} and "
                    f"{np.degrees(pose.phi1_rad[i + 1]):.3f} deg (phi2 jumps by "
                    f"{np.degrees(dphi2[i]):.1f} deg): the linkage passes a closure gap or toggle"
                )
    return RangeCheck(
        closes=bool(ok.all()), closure_gap_deg=gap, toggle_at_deg=toggle,
        branch_jump_at_deg=jump, min_transmission_angle_deg=mu_min, problems=tuple(problems),
    )


def _margin_dip_between_samples(fb: FourBar, phi1: np.ndarray):
    """Refine every local minimum of the closure margin between samples.

    Returns (phi_a, phi_b, min_margin, phi_at_min) of the deepest dip, or None.
    The margin 1 - C^2/(A^2+B^2) is smooth in phi1, so a gap or toggle hidden
    between two samples shows as a local minimum of the sampled margin.
    """
    m = closure_margin(fb, phi1)
    n = len(phi1)
    cand = [i for i in range(n) if (i == 0 or m[i] <= m[i - 1]) and (i == n - 1 or m[i] <= m[i + 1])]
    best = None
    for i in cand:
        a, b = phi1[max(i - 1, 0)], phi1[min(i + 1, n - 1)]
        if b <= a:
            continue
        x, fx = golden_minimize(lambda t: float(closure_margin(fb, np.array([t]))[0]), a, b,
                                xtol=tol.ROOT_XTOL_RAD)
        val = min(float(fx), float(m[i]))
        if best is None or val < best[2]:
            best = (a, b, val, float(x))
    return best


def require_range(fb: FourBar, phi1_min_rad: float, phi1_max_rad: float, samples: int = 721) -> RangeCheck:
    """:func:`check_range`, raising the matching named error on the first problem."""
    rc = check_range(fb, phi1_min_rad, phi1_max_rad, samples)
    if rc.closure_gap_deg is not None:
        raise ClosureError(rc.problems[0])
    if rc.toggle_at_deg is not None:
        raise ToggleError(rc.problems[0])
    if rc.branch_jump_at_deg is not None:
        raise BranchJumpError(rc.problems[0])
    return rc


def coupler_point_and_jacobian(fb: FourBar, phi1_rad: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """P (N,2) mm and J = dP/dphi1 (N,2) mm/rad in one fused pass (hot loops, benchmarks).

    Same equations as :func:`solve` + :func:`jacobian_mm_per_rad` (eqs 3-12), with the
    trigonometric identities sin(phi3 - phi1) = s3 c1 - c3 s1 and
    sin(phi2 - phi3) = s2 c3 - c2 s3 so that no angle beyond phi2 is formed: 5
    transcendental calls per pose instead of ~12. Raises ClosureError / ToggleError
    like the separate functions.
    """
    phi1 = np.asarray(phi1_rad, dtype=float)
    c1, s1 = np.cos(phi1), np.sin(phi1)
    l1, l2, l3, l4, l5 = fb.l1_mm, fb.l2_mm, fb.l3_mm, fb.l4_mm, fb.l5_mm
    dx, dy = l1 * c1 - l5, l1 * s1 - l4  # A2 - A4
    A, B = 2.0 * l2 * dx, 2.0 * l2 * dy
    C = l3 * l3 - l2 * l2 - (dx * dx + dy * dy)
    R = np.sqrt(A * A + B * B)
    ratio = C / R
    if not (np.abs(ratio) <= 1.0 + 1e-12).all():
        _raise_closure(np.atleast_1d(phi1), np.atleast_1d(np.abs(ratio) <= 1.0 + 1e-12))
    phi2 = np.arctan2(B, A) + fb.branch * np.arccos(np.clip(ratio, -1.0, 1.0))
    c2, s2 = np.cos(phi2), np.sin(phi2)
    c3, s3 = (dx + l2 * c2) / l3, (dy + l2 * s2) / l3  # eqs 7-8
    s23 = s2 * c3 - c2 * s3
    if (np.abs(s23) < tol.TOGGLE_SIN).any():
        raise ToggleError(f"toggle (|sin(phi2-phi3)| < {tol.TOGGLE_SIN}) inside the requested angles")
    a2 = l1 * (s3 * c1 - c3 * s1) / (l2 * s23)  # eq 11
    ce, se = np.cos(fb.phi_e_rad), np.sin(fb.phi_e_rad)
    cpe, spe = c2 * ce - s2 * se, s2 * ce + c2 * se  # cos/sin(phi2 + phi_e)
    P = np.empty(phi1.shape + (2,))
    J = np.empty(phi1.shape + (2,))
    P[..., 0] = l1 * c1 + fb.le_mm * cpe
    P[..., 1] = l1 * s1 + fb.le_mm * spe
    J[..., 0] = -l1 * s1 - fb.le_mm * a2 * spe
    J[..., 1] = l1 * c1 + fb.le_mm * a2 * cpe
    return P, J
