"""Straight-line metrics of a four-bar over its crank range (Hoeken paper Tables I, II).

All metrics are computed in the **path frame**: origin at P(phi1_min), x
towards P(phi1_max), y = x rotated by +90 deg. Definitions (N uniform samples
of phi1 over [phi1_min, phi1_max], extrema refined by a root finder):

- ``stroke_mm``: |P(phi1_max) - P(phi1_min)|, the chord of the straight segment.
- ``dy_max_mm``: max |y| over the range (deviation from the chord). The best
  sample is refined by zooming local grids to 1e-12 rad around it, i.e. the
  extremum where dy/dphi1 = J . y_hat = 0 (or an end of the range).
- ``slope_max``: max |dy/dx| = max |J.y_hat / J.x_hat| (local path slope).
- ``linearity``: 1 - max |x(phi1) - x_lin(phi1)| / stroke, where x_lin is the
  straight line through the two end points of x(phi1) (the end-point linearity
  of a transducer). The paper's defining figure is lost; this definition and
  three alternatives are compared with Table II in the report: ``linearity_fit`` (the
  same with the least-squares line), ``linearity_velocity`` = min / max of |dx/dphi1| and
  ``linearity_velocity_mean`` = min / mean of |dx/dphi1| (closest to Table II on all four
  families, 0.988 / 0.776 / 0.868 / 0.985 against 0.990 / 0.819 / 0.875 / 0.991; a
  reading, not a proof of the paper's definition).
- ``torque_mean_mNm``: mean over phi1 of the motor torque tau = F * dx/dphi1
  needed for a force ``force_N`` along the path (virtual work, tau dphi1 = F dx).
- ``torque_variation``: max |tau - <tau>| / <tau>, Table I's
  Delta tau_max / <tau> read as the largest deviation from the mean: this
  reproduces the paper's Hoeken (0.012) and Chebyshev-V (0.015) exactly,
  where the peak-to-peak reading gives 0.014 and 0.025.
  ``torque_range_ratio`` = (max tau - min tau) / <tau> is reported beside it.
- ``bbox_mm``: [width, height] of the box holding every joint A1..A4 and P over
  the range (the paper's "Dimensions"; ours excludes part widths).
- ``min_transmission_angle_deg``: min over the range of asin|sin(phi2 - phi3)|.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from cad.errors import KinematicsError
from cad.kinematics.fourbar import (
    FourBar,
    coupler_point_and_jacobian,
    jacobian_mm_per_rad,
    solve,
    transmission_angle_rad,
)


@dataclass(frozen=True)
class PathFrame:
    """Path frame: origin (mm, R0), unit x and y axes (R0)."""

    origin_mm: np.ndarray
    x_hat: np.ndarray
    y_hat: np.ndarray

    def to_path(self, pts_mm: np.ndarray) -> np.ndarray:
        """Map R0 points (N,2) to path-frame coordinates (N,2)."""
        d = np.asarray(pts_mm) - self.origin_mm
        return np.stack([d @ self.x_hat, d @ self.y_hat], axis=-1)

    def rotate(self, vec: np.ndarray) -> np.ndarray:
        """Express R0 vectors (N,2) in path axes."""
        v = np.asarray(vec)
        return np.stack([v @ self.x_hat, v @ self.y_hat], axis=-1)


def path_frame(fb: FourBar, phi1_min_rad: float, phi1_max_rad: float) -> PathFrame:
    """Path frame of the straight segment between P(phi1_min) and P(phi1_max)."""
    ends = solve(fb, np.array([phi1_min_rad, phi1_max_rad])).P_mm
    chord = ends[1] - ends[0]
    n = np.linalg.norm(chord)
    if n == 0:

        raise KinematicsError("P(phi1_min) == P(phi1_max): the range has no stroke")
    x_hat = chord / n
    return PathFrame(ends[0], x_hat, np.array([-x_hat[1], x_hat[0]]))


@dataclass(frozen=True)
class Metrics:
    """Table I / II metrics; see the module docstring for definitions."""

    stroke_mm: float
    dy_max_mm: float
    slope_max: float
    linearity: float
    linearity_velocity: float
    linearity_fit: float
    linearity_velocity_mean: float
    torque_mean_mNm: float
    torque_variation: float
    torque_range_ratio: float
    bbox_mm: tuple[float, float]
    min_transmission_angle_deg: float
    force_N: float
    samples: int

    def as_dict(self) -> dict:
        d = asdict(self)
        d["bbox_mm"] = list(self.bbox_mm)
        return d


def _refine_abs_max(f, phi: np.ndarray, vals: np.ndarray, points: int = 21, xtol: float = 1e-12) -> float:
    """Max |f| over [phi0, phiN]: the best sample, then zoom in by vectorized local grids.

    ``f`` maps an array of phi1 to values. Each pass evaluates ``points`` angles
    across the bracket around the current best and shrinks the bracket by
    (points - 1) / 2; the extremum of a smooth f is then exact to ~xtol^2.
    """
    i = int(np.argmax(np.abs(vals)))
    best_x, best = float(phi[i]), float(abs(vals[i]))
    half = float(phi[1] - phi[0]) if len(phi) > 1 else 0.0
    lo_lim, hi_lim = float(phi[0]), float(phi[-1])
    while half > xtol:
        grid = np.linspace(max(best_x - half, lo_lim), min(best_x + half, hi_lim), points)
        v = np.abs(f(grid))
        j = int(np.argmax(v))
        if v[j] >= best:
            best, best_x = float(v[j]), float(grid[j])
        half = 2.0 * half / (points - 1)
    return best


def compute_metrics(
    fb: FourBar, phi1_min_rad: float, phi1_max_rad: float, force_N: float = 5.0,
    samples: int = 2001, refine: bool = True,
) -> Metrics:
    """Straight-line metrics of ``fb`` over [phi1_min, phi1_max] (see module docstring).

    ``samples`` uniform crank angles; ``refine`` polishes the extrema of |y| and
    |dy/dx| by zooming vectorized local grids (the exact extremum to ~1e-12 rad).
    """
    phi = np.linspace(phi1_min_rad, phi1_max_rad, samples)
    pose = solve(fb, phi)
    fr = path_frame(fb, phi1_min_rad, phi1_max_rad)
    xy = fr.to_path(pose.P_mm)
    J = fr.rotate(jacobian_mm_per_rad(fb, pose))
    stroke = float(np.linalg.norm(pose.P_mm[-1] - pose.P_mm[0]))
    slope = J[:, 1] / J[:, 0]

    if refine:
        def y_of(t):
            return fr.to_path(coupler_point_and_jacobian(fb, t)[0])[:, 1]

        def slope_of(t):
            j = fr.rotate(coupler_point_and_jacobian(fb, t)[1])
            return j[:, 1] / j[:, 0]

        dy_max = _refine_abs_max(y_of, phi, xy[:, 1])
        slope_max = _refine_abs_max(slope_of, phi, slope)
    else:
        dy_max = float(np.abs(xy[:, 1]).max())
        slope_max = float(np.abs(slope).max())

    x = xy[:, 0]
    x_lin = x[0] + (x[-1] - x[0]) * (phi - phi[0]) / (phi[-1] - phi[0])
    linearity = 1.0 - float(np.abs(x - x_lin).max()) / stroke
    coef = np.polyfit(phi, x, 1)
    linearity_fit = 1.0 - float(np.abs(x - np.polyval(coef, phi)).max()) / stroke
    jx = np.abs(J[:, 0])
    linearity_vel = float(jx.min() / jx.max())
    linearity_vel_mean = float(jx.min() / jx.mean())

    tau = force_N * J[:, 0]  # N * mm/rad = mN.m
    tau_mean = float(np.mean(np.abs(tau)))
    tau_var = float(np.abs(tau - tau.mean()).max() / tau_mean)
    tau_range = float((tau.max() - tau.min()) / tau_mean)

    pts = np.concatenate([np.zeros((1, 2)), fb.A4_mm[None], pose.A2_mm, pose.A3_mm, pose.P_mm])
    span = pts.max(axis=0) - pts.min(axis=0)
    mu = float(np.degrees(transmission_angle_rad(pose).min()))
    return Metrics(
        stroke_mm=stroke, dy_max_mm=float(dy_max), slope_max=float(slope_max),
        linearity=linearity, linearity_velocity=linearity_vel, linearity_fit=linearity_fit,
        linearity_velocity_mean=linearity_vel_mean,
        torque_mean_mNm=tau_mean, torque_variation=tau_var, torque_range_ratio=tau_range,
        bbox_mm=(float(span[0]), float(span[1])), min_transmission_angle_deg=mu,
        force_N=force_N, samples=samples,
    )
