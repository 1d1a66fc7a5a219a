"""Estimate of the handle compliance the rigid-joint structure model leaves out: the radial
deflection of the deep-groove ball bearings at A2, A3 and A4 (numpy only, no CAD).

Why an estimate: bd_warehouse's bearing tables (the SKT columns of
``single_row_deep_groove_ball_bearing_parameters.csv`` and its capped, angular-contact,
cylindrical- and tapered-roller siblings) give dimensions, load ratings C / C0, masses and
the factors kr / f0, but no stiffness, ball count or ball size, and no flanged sizes; the
frame of :mod:`cad.structure.device` therefore ties the links rigidly at the joints. This
module estimates what that leaves out, as a separate number (never added to the FE
compliance):

* ball set: the one bd_warehouse draws for the size (``bearing.py``: ball diameter
  Dw = 0.625 (D1 - d1), pitch radius (D1 + d1) / 4, Z = int(1.8 pi r_pitch / Dw)) -- a drawing
  convention, not a maker's data sheet (real miniature bearings carry 7-9 balls);
* most loaded ball, radial load Fr, zero clearance: Q = 5 Fr / Z (Stribeck; Palmgren 1959);
* Palmgren's radial deflection of a ball bearing (A. Palmgren, *Ball and Roller Bearing
  Engineering*, 3rd ed., SKF Industries 1959): delta_r = 0.002 (Q^2 / Dw)^(1/3) mm with Q in
  kgf and Dw in mm, i.e. delta_r = 4.36e-4 (Q^2 / Dw)^(1/3) mm with Q in N (steel on steel,
  contact angle 0). Hertz's elliptical contact at the inner and outer race (Hamrock & Brewe's
  approximations, groove radius 0.52 Dw, steel E = 208 GPa, nu = 0.3) gives 2.5-2.6 % more for these
  sizes (``tests/unit/structure/test_bearing_compliance.py``);
* joint loads: the links rigid, the crank held at A1, the rocker a two-force member, a force
  F at P along the path direction x: the rocker carries s along A4-A3 with
  s = -((P - A2) x F) / ((A3 - A2) x u34) (moments on the coupler about A2), and A2 carries
  -F - s u34 (coupler equilibrium); A4 carries the rocker's force;
* handle displacement by virtual work (the unit-load method): u_x = sum_j |r_j| delta_r(F |r_j|),
  r_j the joint force per newton at P; reported as the secant compliance u_x / F at the
  design's ``force_N`` (the Hertz contact stiffens with load: delta ~ F^(2/3), so the
  compliance at 1 N is (F / 1 N)^(1/3) times larger). Worst of the three structure poses.

Not included: radial internal clearance (play, not compliance: a preloaded or C2 bearing is
assumed), the bearing's tilt stiffness (out-of-plane z), the motor's own bearings at A1, the
seats' and pins' contact compliance.
"""

from __future__ import annotations

import math

import numpy as np

from cad.data import catalog
from cad.kinematics.fourbar import solve
from cad.kinematics.metrics import path_frame

#: Palmgren's coefficient in SI (mm, N): 0.002 mm kgf^(-2/3) mm^(1/3) x 9.80665^(-2/3).
PALMGREN_MM = 0.002 * 9.80665 ** (-2.0 / 3.0)
#: Stribeck's factor for the most loaded ball (Q = 5 Fr / Z).
STRIBECK = 5.0
FORMULA = ("Palmgren (1959) radial deflection of a deep-groove ball bearing: delta_r = 0.002 "
           "(Q^2/Dw)^(1/3) mm (Q kgf, Dw mm) = 4.36e-4 (Q^2/Dw)^(1/3) mm (Q N), Q = 5 Fr/Z; "
           "joint loads from rigid-link statics, handle displacement by virtual work; "
           "ball set as bd_warehouse draws it; zero clearance; secant compliance at force_N")


def ball_set(bearing: str) -> tuple[int, float]:
    """(ball count Z, ball diameter Dw mm) of bd_warehouse's model of a catalog bearing."""
    b = catalog.get_bearing(bearing)
    dw = 0.625 * (b.D1_mm - b.d1_mm)
    r = (b.D1_mm + b.d1_mm) / 4.0
    return int(1.8 * math.pi * r / dw), dw


def radial_deflection_mm(Fr_N, Z: int, Dw_mm: float):
    """Palmgren's radial deflection (mm) of a ball bearing under a radial load Fr (N), zero
    clearance, contact angle 0 (module docstring). Array-friendly."""
    Q = STRIBECK * np.asarray(Fr_N, dtype=float) / Z
    return PALMGREN_MM * np.cbrt(Q**2 / Dw_mm)


def joint_forces_per_N(fb, phi1_rad: np.ndarray, direction: np.ndarray) -> dict[str, np.ndarray]:
    """|joint force| per newton at P along ``direction`` (unit, R0), shape (N,), at A2, A3 and
    A4 (rigid links, crank held at A1, rocker a two-force member; module docstring)."""
    p = solve(fb, np.asarray(phi1_rad, dtype=float))
    f = np.broadcast_to(np.asarray(direction, dtype=float), p.P_mm.shape)

    def cross(a, b):
        return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]

    u34 = (p.A3_mm - p.A4_mm) / np.linalg.norm(p.A3_mm - p.A4_mm, axis=1)[:, None]
    s = -cross(p.P_mm - p.A2_mm, f) / cross(p.A3_mm - p.A2_mm, u34)
    r2 = -f - s[:, None] * u34
    return {"A2": np.linalg.norm(r2, axis=1), "A3": np.abs(s), "A4": np.abs(s)}


def bearing_compliance(design, phi1_rad: np.ndarray) -> dict:
    """The estimate (module docstring) at the poses ``phi1_rad``: ``x_um_per_N`` (worst pose),
    ``joint_deflection_um`` at that pose, ``force_N``, ball set, ``formula``."""
    fb, parts, F = design.linkage, design.parts, float(design.force_N)
    ex = path_frame(fb, design.phi1_min_rad, design.phi1_max_rad).x_hat
    Z, dw = ball_set(parts.bearing)
    r = joint_forces_per_N(fb, phi1_rad, ex)
    defl = {j: radial_deflection_mm(F * v, Z, dw) for j, v in r.items()}  # mm, (N,)
    u = sum(r[j] * defl[j] for j in r)  # mm along x
    i = int(np.argmax(u))
    return {
        "x_um_per_N": float(u[i] / F * 1e3),
        "force_N": F,
        "phi1_deg": float(np.degrees(np.asarray(phi1_rad)[i])),
        "joint_load_N": {j: float(F * v[i]) for j, v in r.items()},
        "joint_deflection_um": {j: float(v[i] * 1e3) for j, v in defl.items()},
        "bearing": parts.bearing, "balls": Z, "ball_diameter_mm": dw,
        "formula": FORMULA,
        "included_in_compliance_um_per_N": False,
    }
