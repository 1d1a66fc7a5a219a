"""A capstan on the four-bar's crank (issue 35): the crank as a joint of the shared capstan
rows (:mod:`cad.datasheet.capstan_rows`: layout, figures at the peak load, ratio, bend ratio,
pretension, slip margin, safety factor, drum sector, cut length, the rope's torsional spring
k_q = EA (2 / L) r_d^2, K_max with the rope in series, the rope's BOM line and winding steps),
all from the resolved device's transmission (:class:`cad.device.Transmission`), plus the
four-bar's own: the rope's stiffness at the handle k_q / Jx^2 and the crank's mode on the rope
with the links rigid, sqrt(k_q / D_links) / 2 pi, D_links(phi1) the linkage's inertia without
the rotor (Hoeken paper eq 14). The rope holds the crank at A1 in the structure's frame
(:func:`cad.structure.device.crank_rope_stiffness_Nm_per_rad`).

Pure numpy (no CAD import).
"""

from __future__ import annotations

import math

import numpy as np

from cad.actuators import capstan as cap
from cad.assembly import capstan_hardware as hwc
from cad.datasheet import capstan_rows as cr
from cad.datasheet import row
from cad.device import Transmission, resolve_device
from cad.dynamics.inertia import InertiaCoefficients, equivalent_inertia
from cad.kinematics.fourbar import solve

CAPSTAN_GAP_MM = cr.CAPSTAN_GAP_MM
ANCHOR_LENGTH_MM = cr.ANCHOR_LENGTH_MM
ANCHOR_TAIL_MM = cr.ANCHOR_TAIL_MM
CAPSTAN_CHANGE = cr.CAPSTAN_CHANGE
CapstanLayout = cr.CapstanLayout
cable_stiffness_Nm_per_rad = cr.cable_stiffness_Nm_per_rad
k_max_with_cable_N_per_m = cr.k_max_with_cable_N_per_m


def crank_transmission(design, device=None) -> Transmission:
    """The resolved transmission of the crank's motor."""
    dev = device if device is not None else resolve_device(design)
    return dev.transmission("crank")


def crank_joint(design, device=None) -> cr.CapstanJoint:
    """The crank as a :class:`cad.datasheet.capstan_rows.CapstanJoint` (its range phi1_min..max)."""
    dev = device if device is not None else resolve_device(design)
    return cr.capstan_joint(dev, "crank", math.degrees(design.phi1_max_rad - design.phi1_min_rad))


def layout(design, t: Transmission) -> CapstanLayout:
    """The rope's layout of a capstan transmission ``t`` on ``design``'s crank
    (:func:`cad.datasheet.capstan_rows.layout`)."""
    rng = math.degrees(design.phi1_max_rad - design.phi1_min_rad)
    return cr.layout(cr.CapstanJoint("crank", "crank", rng, t, None))


def figures(design, device=None) -> cap.CapstanJointFigures:
    """:func:`cad.actuators.capstan.capstan_joint_figures` of the crank's capstan at the motor's
    peak torque through the ratio (ValueError when the crank is driven directly)."""
    j = crank_joint(design, device)
    if not j.transmission.is_capstan:
        raise ValueError(f"{design.name}: the crank is driven directly (no capstan)")
    return cr.figures(j)


def links_inertia_kg_m2(design, report: dict, phi1_rad: np.ndarray) -> np.ndarray:
    """D(phi1) of the linkage without the motor rotor (kg m^2): the report's H with its
    ``Jm_kg_m2`` taken out of H11 (Hoeken paper eq 14)."""
    H = InertiaCoefficients(report["H11_kg_m2"] - report.get("Jm_kg_m2", 0.0), report["H12_kg_m2"],
                            report["H22_kg_m2"], report["H33_kg_m2"],
                            math.radians(report.get("beta2_deg", 0.0)))
    return equivalent_inertia(design.linkage, solve(design.linkage, phi1_rad), H)


def datasheet_rows(design, report: dict, phi1_rad, Jx, device=None,
                   K_max_N_per_m: float | None = None, eq25_N_per_m: float | None = None) -> tuple[list[dict], dict]:
    """(rows, limits) of the crank's capstan (module docstring); ``([], {})`` for direct drive.
    ``phi1_rad``, ``Jx`` (m/rad): the datasheet's crank angles and lever over the stroke;
    ``K_max_N_per_m``: the datasheet's simulated K_max, ``eq25_N_per_m`` its eq (25) bound (the
    rope's spring in series bounds each: the second is the CHAI3D file's stiffness,
    :func:`cad.firmware.extras.chai3d_stiffness`). The shared rows:
    :func:`cad.datasheet.capstan_rows.datasheet_rows`."""
    j = crank_joint(design, device)
    rows, limits = cr.datasheet_rows(j)
    if not rows:
        return [], {}
    lay = cr.layout(j)
    rows += _spring_rows(design, report, j, lay, phi1_rad, Jx)
    k = cable_stiffness_Nm_per_rad(j.transmission, lay)
    if k is not None and K_max_N_per_m is not None:
        rows.append(row("K_max_with_cable_N_per_m", "renderable stiffness, rope in series",
                        k_max_with_cable_N_per_m(K_max_N_per_m, k, Jx), "N/m",
                        f"1 / (1 / K_max + (dx/dphi1)^2 / k_q), weakest over the stroke: the simulated "
                        f"K_max {K_max_N_per_m:.4g} N/m in series with the rope's spring at the handle"))
    if k is not None and eq25_N_per_m is not None:
        rows.append(row("eq25_K_max_with_cable_N_per_m", "renderable stiffness, eq (25) bound, rope in series",
                        k_max_with_cable_N_per_m(eq25_N_per_m, k, Jx), "N/m",
                        f"1 / (1 / K_max + (dx/dphi1)^2 / k_q), weakest over the stroke: the eq (25) bound "
                        f"{eq25_N_per_m:.4g} N/m in series with the rope's spring at the handle (the CHAI3D file's "
                        "m_maxLinearStiffness)"))
    return rows, limits


def _spring_rows(design, report, j, lay, phi1_rad, Jx) -> list[dict]:
    """The rope as a spring: at the crank, at the handle, the crank's own mode on it."""
    first, k, src = cr.stiffness_row(j, lay)
    if k is None:
        return [first]
    J2 = np.asarray(Jx, float) ** 2
    out = [first,
           row("cable_handle_stiffness_N_per_m", "rope stiffness at the handle", float((k / J2).min()), "N/m",
               f"k_q / (dx/dphi1)^2, weakest over the stroke; {src}", lo=float((k / J2).min()),
               hi=float((k / J2).max()))]
    D = links_inertia_kg_m2(design, report, np.asarray(phi1_rad, float))
    fc = float(np.sqrt(k / D.max()) / (2 * math.pi))
    out.append(row("cable_mode_Hz", "crank mode on the rope (links rigid)", fc, "Hz",
                   "sqrt(k_q / D_links) / 2 pi, D_links(phi1) the linkage's inertia at the crank without the "
                   "rotor (Hoeken paper eq 14), lowest over the stroke; the first mode and the compliance above "
                   "take the rope in the frame (crank held at A1 by k_q)",
                   boundary="motor held by the servo, rope elastic, rocker pinned at A4; handle free"))
    return out


#: Drum thickness and material: every family's (:mod:`cad.assembly.capstan_hardware`).
DRUM_THICKNESS_MM, DRUM_MATERIAL = hwc.DRUM_THICKNESS_MM, hwc.DRUM_MATERIAL


def bom_lines(design, device=None) -> list[dict]:
    """The crank's capstan part that is not a solid of the assembly, as a BOM line (the bom.csv
    row form of :func:`cad.device.encoder_bom_rows`): the rope with its cut length (its free runs
    are drawn, as part of this line). The drum, the capstan, its set screw, the anchor screw and
    the tensioner (screw and lock nut) are solids (:mod:`cad.families.fourbar.capstan_solids`):
    their lines come from the solids. Empty for direct drive."""
    j = crank_joint(design, device)
    return [cr.cable_bom_line(j)] if j.transmission.is_capstan else []


def assembly_checks(design, device=None) -> tuple[str, ...]:
    """``assembly.md``'s winding and tensioning steps of the crank's capstan (empty for direct
    drive): the rope's cut length, its path from one anchor over the drum, round the capstan and
    back to the other anchor, and the tensioner's setting (the datasheet's pretension)."""
    return cr.winding_steps(crank_joint(design, device))
