"""A capstan on the four-bar's crank (issue 35): its layout, its datasheet rows and limits,
and its bill-of-materials lines, all from the resolved device's transmission
(:class:`cad.device.Transmission`) and the model of :mod:`cad.actuators.capstan`.

The motor stands beside the drum at the design's ``transmission.centre_distance_mm``, else with
its capstan :data:`CAPSTAN_GAP_MM` from the drum (C = r_d + r_c + gap, pitch radii); each free
run of rope is the open-belt tangent L = sqrt(C^2 - (r_d - r_c)^2). The rope lies on the drum
over the crank's range plus an anchor of :data:`ANCHOR_LENGTH_MM` at each end; :data:`ANCHOR_TAIL_MM` of rope is left beyond
each anchor. These three are layout choices of this module (no part is drawn yet), stated in
every row that uses them (the gap is :data:`cad.actuators.capstan.CAPSTAN_GAP_MM`).

Figures at the peak load (the motor's peak torque through the ratio): the rope load
dT = n tau_peak / r_d, the pretension (the design's ``pretension_N``, else the smallest that
holds dT at the stated wraps: slip margin 1), the slip margin from the capstan equation, the
rope's safety factor against its breaking load, the bend ratio against the rope's minimum, the
drum sector. With the rope's ``cable_EA_N`` the two runs are a torsional spring at the crank,
k_q = EA (2 / L) r_d^2, holding the crank at A1 in the structure's frame
(:func:`cad.structure.device.crank_rope_stiffness_Nm_per_rad`: the first mode and the handle's
compliance include it), the renderable stiffness is bounded by k_q / Jx^2 in series with
K_max, and the crank's inertia on that spring with the links rigid, D_links(phi1) (the
linkage's without the rotor: the servo holds the motor), has its own mode
sqrt(k_q / D_links) / 2 pi.

Pure numpy (no CAD import).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cad.actuators import capstan as cap
from cad.datasheet import row
from cad.datasheet.limits import Limit
from cad.device import Transmission, resolve_device
from cad.dynamics.inertia import InertiaCoefficients, equivalent_inertia
from cad.kinematics.fourbar import solve

CAPSTAN_GAP_MM = cap.CAPSTAN_GAP_MM
#: Arc length an anchor (a clamping screw and washer) takes on the drum at each end, mm.
ANCHOR_LENGTH_MM = 10.0
#: Rope left beyond each anchor to clamp and trim, mm (cut length).
ANCHOR_TAIL_MM = 20.0
CAPSTAN_CHANGE = ("transmission.capstan_diameter_mm, transmission.cable, transmission.wraps or "
                  "transmission.pretension_N")


@dataclass(frozen=True)
class CapstanLayout:
    """Where the rope runs (mm, deg): ``centre_distance_mm`` C, ``run_length_mm`` L of each
    free run, ``joint_range_deg`` the crank's range, ``sector_deg`` the drum arc the rope and
    anchors need, ``cut_mm`` the rope's cut length by part
    (:func:`cad.actuators.capstan.cable_cut_length_mm`)."""

    centre_distance_mm: float
    run_length_mm: float
    joint_range_deg: float
    sector_deg: float
    cut_mm: dict


def crank_transmission(design, device=None) -> Transmission:
    """The resolved transmission of the crank's motor."""
    dev = device if device is not None else resolve_device(design)
    return dev.transmission("crank")


def layout(design, t: Transmission) -> CapstanLayout:
    """The rope's layout of a capstan transmission ``t`` on ``design``'s crank (module
    docstring)."""
    dc, dd = t.capstan_diameter_mm, t.drum_diameter_mm
    C = cap.centre_distance_mm(dc, dd, t.centre_distance_mm)
    L = float(cap.free_run_length_mm(dc, dd, C))
    rng = math.degrees(design.phi1_max_rad - design.phi1_min_rad)
    sector = float(cap.drum_sector_needed_deg(rng, dd, ANCHOR_LENGTH_MM))
    cut = cap.cable_cut_length_mm(dc, dd, t.wraps, L, sector, ANCHOR_TAIL_MM)
    return CapstanLayout(C, L, rng, sector, cut)


def figures(design, device=None) -> cap.CapstanJointFigures:
    """:func:`cad.actuators.capstan.capstan_joint_figures` of the crank's capstan at the motor's
    peak torque through the ratio (ValueError when the crank is driven directly)."""
    dev = device if device is not None else resolve_device(design)
    t = dev.transmission("crank")
    if not t.is_capstan:
        raise ValueError(f"{design.name}: the crank is driven directly (no capstan)")
    m = dev.motor
    tau = (m.spec.torque_peak_mNm or 0.0) * 1e-3 * t.ratio
    return cap.capstan_joint_figures(
        t.capstan_diameter_mm, t.drum_diameter_mm, t.cable, m.rotor_inertia_kg_m2, tau,
        2.0 * math.pi * t.wraps, motor_friction_Nm=_friction_Nm(m.spec),
        pretension_given_N=t.pretension_N)


def _friction_Nm(spec) -> float | None:
    f = spec.friction_torque_mNm()
    return None if f is None else f * 1e-3


def cable_stiffness_Nm_per_rad(t: Transmission, lay: CapstanLayout) -> float | None:
    """k_q = EA (1/L + 1/L) r_d^2 of the two free runs at the crank (N m/rad); None without the
    rope's E A (the resolved device's: the design's ``transmission.cable_EA_N`` or the rope
    catalog's)."""
    if t.cable_EA_N is None:
        return None
    return float(cap.cable_torsional_stiffness_Nm_per_rad(
        t.cable_EA_N, t.drum_diameter_mm, (lay.run_length_mm, lay.run_length_mm)))


def links_inertia_kg_m2(design, report: dict, phi1_rad: np.ndarray) -> np.ndarray:
    """D(phi1) of the linkage without the motor rotor (kg m^2): the report's H with its
    ``Jm_kg_m2`` taken out of H11 (Hoeken paper eq 14)."""
    H = InertiaCoefficients(report["H11_kg_m2"] - report.get("Jm_kg_m2", 0.0), report["H12_kg_m2"],
                            report["H22_kg_m2"], report["H33_kg_m2"],
                            math.radians(report.get("beta2_deg", 0.0)))
    return equivalent_inertia(design.linkage, solve(design.linkage, phi1_rad), H)


def datasheet_rows(design, report: dict, phi1_rad, Jx, device=None,
                   K_max_N_per_m: float | None = None) -> tuple[list[dict], dict]:
    """(rows, limits) of the crank's capstan (module docstring); ``([], {})`` for direct drive.
    ``phi1_rad``, ``Jx`` (m/rad): the datasheet's crank angles and lever over the stroke;
    ``K_max_N_per_m``: the datasheet's simulated K_max (the rope's spring in series bounds it)."""
    dev = device if device is not None else resolve_device(design)
    t = dev.transmission("crank")
    if not t.is_capstan:
        return [], {}
    fig, lay, c = figures(design, dev), layout(design, t), t.cable
    unv = c.is_unverified("min_bend_ratio")
    bend = t.capstan_diameter_mm / c.diameter_mm
    given = t.pretension_N is not None
    rows = [
        row("transmission_ratio", "capstan ratio n (drum / capstan)", t.ratio, "",
            f"{t.drum_diameter_mm:g} mm drum / {t.capstan_diameter_mm:g} mm capstan; joint torque = n "
            "motor torque, counts per crank turn = n counts per motor turn; forces, resolution and "
            "friction above are through it"),
        row("reflected_rotor_inertia_g_cm2", "rotor inertia at the crank (n^2 J_m)",
            fig.reflected_inertia_kg_m2 * 1e7, "g cm^2",
            f"n^2 J_m = {t.ratio:.4g}^2 x {dev.motor.spec.rotor_inertia_g_cm2:g} g cm^2, in H11 and M11"),
        row("bend_ratio", f"bend ratio D/d of {c.key} on the capstan", bend, "",
            f"capstan {t.capstan_diameter_mm:g} mm / rope {c.diameter_mm:g} mm against the rope's minimum "
            f"{c.min_bend_ratio:g} ({c.source_of('min_bend_ratio')})", unverified=unv),
        row("cable_pretension_N", "rope pretension (the tensioner's setting)", fig.pretension_N, "N",
            ("transmission.pretension_N" if given else
             f"the smallest that holds the peak load: T0 = (dT / 2)(e^(mu theta) + 1) / (e^(mu theta) - 1), "
             f"dT = {fig.tension_difference_N:.4g} N, {t.wraps:g} turns, mu = {cap.MU_STEEL_ROPE_ON_STEEL:g}; "
             "set the tensioner to at least this")),
        row("cable_slip_margin", "rope slip margin at the peak force", float(f"{fig.slip_margin:.9g}"), "",
            f"e^(mu theta) / (T_t / T_s), capstan equation, {t.wraps:g} turns, mu = "
            f"{cap.MU_STEEL_ROPE_ON_STEEL:g} (Tribology Handbook B12), T0 = {fig.pretension_N:.4g} N, "
            f"dT = n tau_peak / r_d = {fig.tension_difference_N:.4g} N"),
        row("cable_safety_factor", "rope safety factor at the peak force",
            None if c.min_breaking_load_N is None else
            float(cap.cable_safety_factor(c.min_breaking_load_N, fig.tension_difference_N, fig.pretension_N)),
            "", fig.strength[1] + f"; {c.source_of('min_breaking_load_N')}",
            unverified=c.is_unverified("min_breaking_load_N")),
        row("drum_sector_deg", "drum arc the rope needs", lay.sector_deg, "deg",
            f"crank range {lay.joint_range_deg:.4g} deg + two anchors of {ANCHOR_LENGTH_MM:g} mm "
            f"(2 L_a / r_d each) on the {t.drum_diameter_mm:g} mm drum"),
        row("cable_cut_length_mm", f"rope {c.key} to cut", lay.cut_mm["total"], "mm", _cut_text(t, lay)),
    ]
    limits = {
        "bend_ratio": Limit(">=", c.min_bend_ratio, f"rope makers' minimum D/d for {c.construction}",
                            "transmission.capstan_diameter_mm or transmission.cable"),
        "cable_slip_margin": Limit(">=", 1.0, "the rope must not slip on the capstan at the peak force",
                                   "transmission.pretension_N or transmission.wraps"),
        "cable_safety_factor": Limit(">=", cap.CABLE_SAFETY_FACTOR,
                                     "breaking load over the tight run's tension (rope sellers: 4:1 or 5:1)",
                                     CAPSTAN_CHANGE),
        "drum_sector_deg": Limit("<=", 360.0, "the rope and both anchors fit on one drum",
                                 "transmission.drum_diameter_mm"),
    }
    rows += _spring_rows(design, report, t, lay, phi1_rad, Jx)
    k = cable_stiffness_Nm_per_rad(t, lay)
    if k is not None and K_max_N_per_m is not None:
        rows.append(row("K_max_with_cable_N_per_m", "renderable stiffness, rope in series",
                        k_max_with_cable_N_per_m(K_max_N_per_m, k, Jx), "N/m",
                        f"1 / (1 / K_max + (dx/dphi1)^2 / k_q), weakest over the stroke: the simulated "
                        f"K_max {K_max_N_per_m:.4g} N/m in series with the rope's spring at the handle"))
    return rows, limits


def _cut_text(t: Transmission, lay: CapstanLayout) -> str:
    p = lay.cut_mm
    gap = ("transmission.centre_distance_mm" if t.centre_distance_mm is not None
           else f"rim gap {CAPSTAN_GAP_MM:g} mm")
    return (f"{t.wraps:g} turns on the capstan {p['wraps']:.0f} + two free runs {p['runs']:.0f} (L = "
            f"{lay.run_length_mm:.1f} mm, centre distance {lay.centre_distance_mm:.1f} mm, "
            f"{gap}) + drum arc {p['drum']:.0f} + anchor tails {p['anchors']:.0f} mm")


def _spring_rows(design, report, t, lay, phi1_rad, Jx) -> list[dict]:
    """The rope as a spring: at the crank, at the handle, the crank's own mode on it."""
    k = cable_stiffness_Nm_per_rad(t, lay)
    if k is None:
        return [row("cable_stiffness_Nm_per_rad", "rope stiffness at the crank", None, "N m/rad",
                    f"not computed: no E A for {t.cable.key} in the rope catalog; give "
                    "transmission.cable_EA_N from the rope maker's sheet. The first mode, compliance "
                    "and K_max above take the rope as rigid", unverified=True)]
    J2 = np.asarray(Jx, float) ** 2
    src = (f"k_q = EA (2 / L) r_d^2, EA = {t.cable_EA_N:.4g} N, L = {lay.run_length_mm:.1f} mm; EA from "
           f"{t.cable_EA_source}")
    out = [row("cable_stiffness_Nm_per_rad", "rope stiffness at the crank", k, "N m/rad", src),
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


def k_max_with_cable_N_per_m(K_max_N_per_m: float | None, k_q: float | None, Jx) -> float | None:
    """The renderable stiffness with the rope in series: 1 / (1 / K_max + Jx^2 / k_q), weakest
    over the stroke (N/m); K_max itself without the rope's stiffness, None without K_max."""
    if K_max_N_per_m is None or k_q is None:
        return K_max_N_per_m
    return float(cap.series_stiffness(K_max_N_per_m, k_q / float(np.max(np.asarray(Jx) ** 2))))


#: Drum (or sector) thickness along the shaft, mm: room for the rope's turns on the drum side
#: and the anchors' screws. A layout choice (no part drawn yet).
DRUM_THICKNESS_MM = 10.0
#: The drum sector's material (machined plate): its solid's and the cheap model's.
DRUM_MATERIAL = "aluminium-6061"


def _row(part: str, desc: str, quantity: int, made: bool, process: str, material: str,
         designation: str, stock: str = "") -> dict:
    return {"part": part, "description": desc, "material": material, "quantity": quantity,
            "made_or_bought": "made" if made else "bought", "process": process, "fits": "",
            "mass_g": 0.0, "group": "capstan transmission", "designation": designation,
            "order_code": "", "stock": stock}


def bom_lines(design, device=None) -> list[dict]:
    """The crank's capstan part that is not a solid of the assembly, as a BOM line (the bom.csv
    row form of :func:`cad.device.encoder_bom_rows`): the rope with its cut length (its free runs
    are drawn, as part of this line). The drum, the capstan, its set screw, the anchor screw and
    the tensioner (screw and lock nut) are solids (:mod:`cad.families.fourbar.capstan_solids`):
    their lines come from the solids. Empty for direct drive."""
    dev = device if device is not None else resolve_device(design)
    t = dev.transmission("crank")
    if not t.is_capstan:
        return []
    c, lay = t.cable, layout(design, t)
    mbl = ("breaking load not known" if c.min_breaking_load_N is None else
           f"breaking load {c.min_breaking_load_N:.0f} N" + (" (unverified)" if c.is_unverified(
               "min_breaking_load_N") else ""))
    cut = lay.cut_mm["total"]
    return [
        _row("capstan_cable", f"{c.description}, cut length {cut:.0f} mm ({_cut_text(t, lay)}); {mbl}; "
             f"source: cad.data.cables ({c.source_of('min_breaking_load_N')})", 1, False,
             "bought; cut to length", "steel", f"wire rope {c.construction} {c.diameter_mm:g} mm x {cut:.0f} mm"),
    ]


def assembly_checks(design, device=None) -> tuple[str, ...]:
    """``assembly.md``'s winding and tensioning steps of the crank's capstan (empty for direct
    drive): the rope's cut length, its path from one anchor over the drum, round the capstan and
    back to the other anchor, and the tensioner's setting (the datasheet's pretension)."""
    dev = device if device is not None else resolve_device(design)
    t = dev.transmission("crank")
    if not t.is_capstan:
        return ()
    lay, fig = layout(design, t), figures(design, dev)
    return (
        f"wind the rope: cut {lay.cut_mm['total']:.0f} mm of {t.cable.key} (bom.csv capstan_cable); "
        "clamp one end under capstan_anchor_1 with the crank at the end of its range nearest that "
        f"anchor, lay it on the drum's rim to the tangent point, wind {t.wraps:g} turns on the capstan "
        "(its helical groove, side by side), lay it back on the drum's rim to capstan_tensioner and "
        "wind its tail on the tensioner screw's shank between the lock nut and the head (the 20 mm "
        "tail: about two turns)",
        f"tension the rope: turn capstan_tensioner (it winds the rope on its shank) until the rope "
        f"holds at least {fig.pretension_N:.1f} N (datasheet cable_pretension_N; a spring scale on "
        "a free run), lock it with capstan_tensioner_nut against the rim, then turn the crank over "
        "its whole range: the rope stays on the drum's rim and in the capstan's turns, no anchor "
        "reaches a tangent point",
    )
