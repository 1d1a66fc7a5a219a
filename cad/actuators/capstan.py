"""Capstan (cable) transmission model: pure numpy, no CAD import (issue 35).

A steel rope is wrapped round a small capstan (diameter d_c) on the motor shaft and anchored at
both ends on a large drum or sector (diameter d_d) on the link. With r_c = d_c / 2 and
r_d = d_d / 2 the transmission is a reduction of ratio

    n = d_d / d_c                                   (no-slip rolling: r_c dtheta_m = r_d dq)

so a joint angle q is a motor angle theta_m = n q, and (ideal, lossless)

    tau_joint = n tau_motor,     F_tangential_on_drum = tau_joint / r_d.

Every function states its equation; SI inside (m, N, kg m^2, rad) unless a name carries
another unit. Arrays broadcast (numpy), so a function takes one joint or many.

Sources: the capstan (Euler-Eytelwein) equation T_tight / T_slack = exp(mu theta) (any
statics text; e.g. Meriam & Kraige, Engineering Mechanics: Statics, 7th edition 2012, §6/9);
the friction coefficient of wire rope on an iron or steel sheave at slip, dry, mu = 0.12
(:data:`MU_STEEL_ROPE_ON_STEEL`); springs in series 1/k = sum 1/k_i; a reduction's
reflected inertia n^2 J_m (kinetic energy J_m (n qdot)^2 / 2 seen at the joint).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cad.data.cables import CABLES, CableSpec
from cad.errors import DesignError

#: Friction coefficient at slip, dry, wire rope on an iron or steel sheave: 0.12. Source:
#: The Tribology Handbook (M. J. Neale, ed.), section B12 'Capstans and drums', table
#: 'Direct drives' (page 226 of the copy at https://digilib.universitaspertamina.ac.id/ebook/
#: The%20Tribology%20Handbook/files/basic-html/page226.html; edition not identified there).
MU_STEEL_ROPE_ON_STEEL = 0.12
#: Safety factor of a cable's breaking load over its working tension: "Normally, the safety
#: factors are 4:1 or 5:1 of the minimum breaking strength" (The Cable Connection, 'Choosing
#: the right cable', https://www.thecableconnection.com/resources/choosing-the-right-cable/,
#: page read 2026-12); the larger value is kept.
CABLE_SAFETY_FACTOR = 5.0


# --------------------------------------------------------------------------- ratio and scaling
def ratio(capstan_diameter_mm, drum_diameter_mm):
    """Reduction ratio n = d_drum / d_capstan (dimensionless; arrays broadcast)."""
    return np.asarray(drum_diameter_mm, float) / np.asarray(capstan_diameter_mm, float)


def joint_torque_Nm(motor_torque_Nm, n):
    """Joint torque from the motor's: tau_q = n tau_m (lossless reduction), N m."""
    return np.asarray(n, float) * np.asarray(motor_torque_Nm, float)


def motor_torque_Nm(joint_torque_Nm, n):
    """Motor torque needed for a joint torque: tau_m = tau_q / n, N m."""
    return np.asarray(joint_torque_Nm, float) / np.asarray(n, float)


def cable_tension_difference_N(joint_torque_Nm, drum_diameter_mm):
    """T_tight - T_slack that carries a joint torque: dT = tau_q / r_d (r_d = d_d / 2 in m), N.
    The same dT acts on the capstan: dT r_c = tau_m."""
    return np.asarray(joint_torque_Nm, float) / (np.asarray(drum_diameter_mm, float) * 0.5e-3)


def reflected_inertia_kg_m2(rotor_inertia_kg_m2, n):
    """Rotor inertia seen at the joint: J_refl = n^2 J_m, kg m^2.

    Kinetic energy: J_m (n qdot)^2 / 2 = (n^2 J_m) qdot^2 / 2."""
    return np.asarray(n, float) ** 2 * np.asarray(rotor_inertia_kg_m2, float)


def add_reflected_inertia(M_q, n, rotor_inertia_kg_m2):
    """Joint-space mass matrix with each motor's reflected inertia on its joint's diagonal.

    M_q : (..., k, k) joint-space mass matrix (kg m^2), e.g. the four-bar's D(phi1) as (..., 1, 1)
    or a 5-bar's 2x2 H over a grid of poses. n, rotor_inertia_kg_m2 : (k,) per actuated joint
    (n = 1 for a direct-drive joint; 0 inertia for an unactuated one). Returns
    M_q + diag(n_i^2 J_m,i). The operational mass Lambda = J^-T M_q J^-1 (and M11) follows
    from the returned matrix by the caller's usual formula; the added term is
    J^-T diag(n^2 J_m) J^-1.
    """
    M = np.asarray(M_q, float)
    add = reflected_inertia_kg_m2(rotor_inertia_kg_m2, n)
    add = np.broadcast_to(add, M.shape[-1:])
    return M + np.diag(add)


def reflected_friction_Nm(motor_friction_Nm, n):
    """Motor friction (brush + bearing, Kt I0) seen at the joint: tau_f,q = n tau_f,m, N m.

    A reduction multiplies the motor's friction like its torque: the handle feels n times the
    motor's friction through the same lever."""
    return np.asarray(n, float) * np.asarray(motor_friction_Nm, float)


# --------------------------------------------------------------------------- bend ratio
def bend_ratio(capstan_diameter_mm, cable_diameter_mm):
    """Bend ratio D/d of the rope on the capstan (the smaller of the two pulleys)."""
    return np.asarray(capstan_diameter_mm, float) / np.asarray(cable_diameter_mm, float)


def bend_ratio_fix(cable: CableSpec, capstan_diameter_mm: float) -> str | None:
    """What fixes a rope bent below its minimum on the capstan: "use a capstan of at least
    ... mm, or a 7x19 rope of the same diameter (...)"; None when D/d meets the minimum."""
    if float(bend_ratio(capstan_diameter_mm, cable.diameter_mm)) >= cable.min_bend_ratio:
        return None
    fix = f"use a capstan of at least {cable.min_capstan_diameter_mm():.1f} mm"
    alt = next((c for c in CABLES.values() if c.construction == "7x19"
                and c.diameter_mm == cable.diameter_mm), None)
    if cable.construction != "7x19":
        alt_need = 26.0 * cable.diameter_mm if alt is None else alt.min_capstan_diameter_mm()
        fix += (f", or a 7x19 rope of the same diameter ({alt.key if alt else 'not in the catalog'}"
                f", D/d >= {(alt.min_bend_ratio if alt else 26.0):g}: capstan >= {alt_need:.1f} mm)")
    return fix


def bend_ratio_warning(cable: CableSpec, capstan_diameter_mm: float) -> str | None:
    """A one-line warning when the capstan bends ``cable`` (a :class:`cad.data.cables.CableSpec`)
    below its minimum bend ratio, naming the rope, the ratio, the capstan diameter that meets
    the minimum and the 7x19 alternative (:func:`bend_ratio_fix`); None when D/d meets it.

    D/d_min = cable.min_bend_ratio (rope makers: about 40 for 7x7, 25-28 for 7x19)."""
    fix = bend_ratio_fix(cable, capstan_diameter_mm)
    if fix is None:
        return None
    dd = float(bend_ratio(capstan_diameter_mm, cable.diameter_mm))
    mark = " (unverified)" if cable.is_unverified("min_bend_ratio") else ""
    return (f"cable {cable.key} on a {capstan_diameter_mm:g} mm capstan: bend ratio D/d = "
            f"{dd:.1f} is below the rope's minimum {cable.min_bend_ratio:g}{mark}; {fix}")


# --------------------------------------------------------------------------- capstan equation
def capstan_tension_ratio(mu, wrap_angle_rad):
    """Largest T_tight / T_slack before the rope slips: exp(mu theta) (capstan equation)."""
    return np.exp(np.asarray(mu, float) * np.asarray(wrap_angle_rad, float))


def wraps(wrap_angle_rad):
    """Turns of rope on the capstan: theta / (2 pi)."""
    return np.asarray(wrap_angle_rad, float) / (2.0 * math.pi)


def pretension_needed_N(tension_difference_N, mu, wrap_angle_rad):
    """Smallest pretension T0 that carries dT without slip.

    Both runs start at T0; under load the tight run rises and the slack run falls by dT/2
    (equal run stiffness), T_t = T0 + dT/2, T_s = T0 - dT/2. No slip: T_t / T_s <= e^{mu theta}
    gives T0 >= (dT / 2) (e^{mu theta} + 1) / (e^{mu theta} - 1), N."""
    e = capstan_tension_ratio(mu, wrap_angle_rad)
    return 0.5 * np.asarray(tension_difference_N, float) * (e + 1.0) / (e - 1.0)


def slip_margin(tension_difference_N, pretension_N, mu, wrap_angle_rad):
    """e^{mu theta} / (T_t / T_s) with T_t = T0 + dT/2, T_s = T0 - dT/2: > 1 holds, <= 1
    slips; 0 when T_s <= 0 (the slack run has gone slack)."""
    dT = np.asarray(tension_difference_N, float)
    T0 = np.asarray(pretension_N, float)
    Ts = np.maximum(T0 - 0.5 * dT, 0.0)
    return capstan_tension_ratio(mu, wrap_angle_rad) * Ts / (T0 + 0.5 * dT)


def wrap_angle_needed_rad(tension_difference_N, pretension_N, mu):
    """Smallest wrap angle that holds dT at pretension T0: theta = ln(T_t / T_s) / mu, rad.
    Raises DesignError when T0 <= dT / 2 (the slack run goes slack whatever the wraps)."""
    dT = np.asarray(tension_difference_N, float)
    T0 = np.asarray(pretension_N, float)
    if np.any(T0 <= 0.5 * dT):
        raise DesignError("transmission.pretension_N",
                          f"{float(np.min(T0)):g} N does not exceed half the tension difference "
                          f"({float(np.max(dT)) / 2:g} N): the slack run goes slack; raise it")
    return np.log((T0 + 0.5 * dT) / (T0 - 0.5 * dT)) / np.asarray(mu, float)


# --------------------------------------------------------------------------- strength
def cable_safety_factor(min_breaking_load_N, tension_difference_N, pretension_N):
    """Breaking load over the tight run's tension: SF = MBL / (T0 + dT/2)."""
    return np.asarray(min_breaking_load_N, float) / (
        np.asarray(pretension_N, float) + 0.5 * np.asarray(tension_difference_N, float))


def max_pretension_N(min_breaking_load_N, tension_difference_N, required: float | None = None):
    """The largest pretension T0 (N) at which the tight run at peak force still meets the safety
    factor ``required`` (default :data:`CABLE_SAFETY_FACTOR`): MBL / SF - dT/2, from
    :func:`cable_safety_factor` solved for T0 (below 0: no pretension meets it)."""
    sf = CABLE_SAFETY_FACTOR if required is None else required
    return np.asarray(min_breaking_load_N, float) / sf - 0.5 * np.asarray(tension_difference_N, float)


def cable_strength_verdict(cable: CableSpec, tension_difference_N: float, pretension_N: float,
                           required: float = CABLE_SAFETY_FACTOR) -> tuple[str, str]:
    """("ok" | "fails" | "unverified", one-line reason) of the tight run against the rope's
    minimum breaking load with safety factor ``required`` (default :data:`CABLE_SAFETY_FACTOR`)."""
    if cable.min_breaking_load_N is None:
        return "unverified", f"cable {cable.key}: no breaking load known (no public source)"
    sf = float(cable_safety_factor(cable.min_breaking_load_N, tension_difference_N, pretension_N))
    mark = " (breaking load unverified)" if cable.is_unverified("min_breaking_load_N") else ""
    verdict = "ok" if sf >= required else "fails"
    if mark and verdict == "ok":
        verdict = "unverified"
    return verdict, (f"cable {cable.key}: safety factor {sf:.1f} against {required:g} "
                     f"(MBL {cable.min_breaking_load_N:.0f} N{mark})")


# --------------------------------------------------------------------------- stiffness
def cable_torsional_stiffness_Nm_per_rad(EA_N, drum_diameter_mm, run_lengths_mm):
    """The two free runs of rope between capstan and drum as a torsional spring at the joint.

    With the motor held, a joint rotation dq stretches one run and relaxes the other by
    r_d dq; both stay in tension (pretension), so both springs act:
    k_q = EA (1/L_1 + 1/L_2) r_d^2, N m/rad. run_lengths_mm: (..., 2), L_1 and L_2 in mm."""
    L = np.asarray(run_lengths_mm, float) * 1e-3
    r = np.asarray(drum_diameter_mm, float) * 0.5e-3
    return np.asarray(EA_N, float) * (1.0 / L[..., 0] + 1.0 / L[..., 1]) * r * r


def series_stiffness(*k):
    """Springs in series: k = 1 / sum(1 / k_i) (same units as the k_i; arrays broadcast).
    The cable spring in series with the joint's structural stiffness gives the joint's total."""
    inv = sum(1.0 / np.asarray(ki, float) for ki in k)
    return 1.0 / inv


# --------------------------------------------------------------------------- drum range
def drum_sector_needed_deg(joint_range_deg, drum_diameter_mm, anchor_length_mm):
    """Arc of drum the rope needs: the joint's range (the tangent point travels it) plus, at each
    end, the anchor's own arc 2 * anchor_length / d_d (rad) so the anchor never reaches the
    tangent point: sector = dq + 2 * (2 L_a / d_d) (in deg)."""
    anchor = np.degrees(2.0 * np.asarray(anchor_length_mm, float) / np.asarray(drum_diameter_mm, float))
    return np.asarray(joint_range_deg, float) + 2.0 * anchor


def check_drum_range(joint_range_deg: float, drum_diameter_mm: float, anchor_length_mm: float,
                     sector_available_deg: float = 360.0,
                     field: str = "transmission.drum_diameter_mm") -> float:
    """The drum sector needed (deg) when it fits in ``sector_available_deg`` (360: a full drum,
    less for a sector the link's shape allows); DesignError(field) naming the sector needed,
    the one available and the drum diameter that would fit otherwise."""
    need = float(drum_sector_needed_deg(joint_range_deg, drum_diameter_mm, anchor_length_mm))
    if need <= sector_available_deg:
        return need
    room = sector_available_deg - joint_range_deg
    if room <= 0:
        raise DesignError(field, f"the joint's range {joint_range_deg:g} deg exceeds the "
                          f"{sector_available_deg:g} deg the drum may span: no drum covers it")
    d_fit = 4.0 * anchor_length_mm / math.radians(room)
    raise DesignError(field, f"{drum_diameter_mm:g} mm drum needs a {need:.1f} deg sector (joint "
                      f"range {joint_range_deg:g} deg + anchors of {anchor_length_mm:g} mm) but "
                      f"{sector_available_deg:g} deg is available; use a drum of at least "
                      f"{d_fit:.1f} mm or shorter anchors")


# --------------------------------------------------------------------------- one joint
@dataclass(frozen=True)
class CapstanJointFigures:
    """Every figure of one capstan joint at its peak load (SI; see the functions above).

    ratio : n. reflected_inertia_kg_m2 : n^2 J_m. reflected_friction_Nm : n K_t I_0 (None
    without motor friction data). tension_difference_N : dT at the peak joint torque.
    pretension_N : T_0 needed for no slip at the stated wraps (``pretension_given_N`` when the
    design states one). slip_margin : at that pretension. wraps : turns on the capstan.
    strength : (verdict, reason) of :func:`cable_strength_verdict`. warnings : one-line
    warnings (bend ratio)."""

    ratio: float
    reflected_inertia_kg_m2: float
    reflected_friction_Nm: float | None
    tension_difference_N: float
    pretension_N: float
    slip_margin: float
    wraps: float
    strength: tuple[str, str]
    warnings: tuple[str, ...]


def capstan_joint_figures(capstan_diameter_mm: float, drum_diameter_mm: float, cable: CableSpec,
                          rotor_inertia_kg_m2: float, peak_joint_torque_Nm: float,
                          wrap_angle_rad: float, motor_friction_Nm: float | None = None,
                          pretension_given_N: float | None = None,
                          mu: float = MU_STEEL_ROPE_ON_STEEL) -> CapstanJointFigures:
    """The figures above for one joint: the transmission's diameters (mm), its rope, the motor's
    rotor inertia (and friction K_t I_0, N m), the joint's peak torque (N m) and the wrap angle
    on the capstan (rad). Without ``pretension_given_N`` the pretension is the smallest that
    holds the peak (slip margin 1 exactly)."""
    n = float(ratio(capstan_diameter_mm, drum_diameter_mm))
    dT = float(cable_tension_difference_N(peak_joint_torque_Nm, drum_diameter_mm))
    T0 = (float(pretension_needed_N(dT, mu, wrap_angle_rad)) if pretension_given_N is None
          else float(pretension_given_N))
    bend = bend_ratio_warning(cable, capstan_diameter_mm)
    return CapstanJointFigures(
        ratio=n,
        reflected_inertia_kg_m2=float(reflected_inertia_kg_m2(rotor_inertia_kg_m2, n)),
        reflected_friction_Nm=(None if motor_friction_Nm is None
                               else float(reflected_friction_Nm(motor_friction_Nm, n))),
        tension_difference_N=dT,
        pretension_N=T0,
        slip_margin=float(slip_margin(dT, T0, mu, wrap_angle_rad)),
        wraps=float(wraps(wrap_angle_rad)),
        strength=cable_strength_verdict(cable, dT, T0),
        warnings=() if bend is None else (bend,),
    )


# --------------------------------------------------------------------------- layout of the rope
#: Gap between the capstan's rim and the drum's rim, mm: the rope (up to 1.6 mm) passes
#: between them without rubbing. A layout choice (no part is drawn yet).
CAPSTAN_GAP_MM = 2.0


def centre_distance_mm(capstan_diameter_mm: float, drum_diameter_mm: float,
                       given_mm: float | None = None) -> float:
    """The drum's axis to the capstan's, mm: ``given_mm`` (the design's
    ``transmission.centre_distance_mm``) or the pitch circles :data:`CAPSTAN_GAP_MM` apart,
    r_d + r_c + gap."""
    if given_mm is not None:
        return float(given_mm)
    return 0.5 * (capstan_diameter_mm + drum_diameter_mm) + CAPSTAN_GAP_MM


def rope_stiffness_Nm_per_rad(capstan_diameter_mm: float, drum_diameter_mm: float,
                              EA_N: float, centre_distance_given_mm: float | None = None) -> float:
    """The two free runs as a torsional spring at the joint (N m/rad) at the
    :func:`centre_distance_mm` (open-belt runs): :func:`cable_torsional_stiffness_Nm_per_rad`
    of :func:`free_run_length_mm` twice."""
    C = centre_distance_mm(capstan_diameter_mm, drum_diameter_mm, centre_distance_given_mm)
    L = float(free_run_length_mm(capstan_diameter_mm, drum_diameter_mm, C))
    return float(cable_torsional_stiffness_Nm_per_rad(EA_N, drum_diameter_mm, (L, L)))


def free_run_length_mm(capstan_diameter_mm, drum_diameter_mm, centre_distance_mm):
    """Length of each free run of rope between its tangent points on the capstan and the drum,
    both runs on the outside (an open belt): L = sqrt(C^2 - (r_d - r_c)^2), mm."""
    rc = 0.5 * np.asarray(capstan_diameter_mm, float)
    rd = 0.5 * np.asarray(drum_diameter_mm, float)
    return np.sqrt(np.asarray(centre_distance_mm, float) ** 2 - (rd - rc) ** 2)


def cable_cut_length_mm(capstan_diameter_mm: float, drum_diameter_mm: float, wraps_: float,
                        run_length_mm: float, drum_arc_deg: float, anchor_tail_mm: float) -> dict:
    """The rope to cut for one capstan joint, mm, by part: ``wraps`` (pi d_c per turn), ``runs``
    (the two free runs, 2 L), ``drum`` (the arc the rope lies on the drum: the sector the joint
    sweeps plus both anchors' arcs, pi d_d sector / 360), ``anchors`` (a tail of
    ``anchor_tail_mm`` beyond each anchor to clamp and trim) and their sum ``total``."""
    parts = {"wraps": math.pi * capstan_diameter_mm * wraps_, "runs": 2.0 * run_length_mm,
             "drum": math.pi * drum_diameter_mm * drum_arc_deg / 360.0,
             "anchors": 2.0 * anchor_tail_mm}
    parts["total"] = sum(parts.values())
    return parts
