"""A capstan joint's datasheet rows, limits, BOM line and winding steps, for any family: a
joint is its motor-angle range (deg), its motor (peak torque, rotor inertia, friction) and its
resolved :class:`cad.device.Transmission` (:class:`CapstanJoint`, :func:`capstan_joint`). The
four-bar's crank (:mod:`cad.families.fourbar.capstan`) and every motor of the other families
read these; a family adds only its lever (the handle's dx/dq) and its links' inertia.

The motor stands beside the drum at the design's ``transmission.centre_distance_mm``, else with
its capstan :data:`CAPSTAN_GAP_MM` from the drum (C = r_d + r_c + gap, pitch radii); each free
run of rope is the open-belt tangent L = sqrt(C^2 - (r_d - r_c)^2). The rope lies on the drum
over the joint's range plus an anchor of :data:`ANCHOR_LENGTH_MM` at each end;
:data:`ANCHOR_TAIL_MM` of rope is left beyond each anchor. These are layout choices, stated in
every row that uses them (the gap is :data:`cad.actuators.capstan.CAPSTAN_GAP_MM`).

Figures at the peak load (the motor's peak torque through the ratio): the rope load
dT = n tau_peak / r_d, the pretension (the design's ``pretension_N``, else the smallest that
holds dT at the stated wraps: slip margin 1), the slip margin from the capstan equation, the
rope's safety factor against its breaking load, the bend ratio against the rope's minimum, the
drum sector. With the rope's ``cable_EA_N`` the two runs are a torsional spring at the joint,
k_q = EA (2 / L) r_d^2 (:func:`cable_stiffness_Nm_per_rad`), and the renderable stiffness is
bounded by k_q / J^2 in series with K_max (:func:`k_max_with_cable_N_per_m`).

Pure numpy (no CAD import).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cad.actuators import capstan as cap
from cad.datasheet import row
from cad.datasheet.limits import Limit
from cad.device import Transmission
from cad.errors import DesignError
from cad.tolerances import CAPSTAN_RANGE_MARGIN_DEG

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
    free run, ``joint_range_deg`` the joint's range, ``sector_deg`` the drum arc the rope and
    anchors need, ``cut_mm`` the rope's cut length by part
    (:func:`cad.actuators.capstan.cable_cut_length_mm`)."""

    centre_distance_mm: float
    run_length_mm: float
    joint_range_deg: float
    sector_deg: float
    cut_mm: dict


@dataclass(frozen=True)
class CapstanJoint:
    """One capstan-driven joint: ``name`` (the device's motor joint), ``label`` (the words the
    rows use, "crank"), ``range_deg`` its motor-angle range (deg), ``transmission`` the resolved
    :class:`cad.device.Transmission`, ``motor`` the :class:`cad.device.ResolvedMotor` on it,
    ``suffix`` appended to every row key and BOM part name ("" for a one-motor device, "_1" ...
    for one row set per motor), ``inertia_in`` where the reflected rotor inertia enters (the
    rows' words)."""

    name: str
    label: str
    range_deg: float
    transmission: Transmission
    motor: object
    suffix: str = ""
    inertia_in: str = "H11 and M11"


def capstan_joint(device, joint: str, range_deg: float, label: str | None = None,
                  suffix: str = "", inertia_in: str = "H11 and M11") -> CapstanJoint:
    """The :class:`CapstanJoint` of the motor on ``joint`` of the resolved ``device``
    (KeyError naming the joint when it has no motor)."""
    m = next((x for x in device.motors if x.joint == joint), None)
    if m is None:
        raise KeyError(f"no motor on joint {joint!r}")
    return CapstanJoint(joint, label or joint, float(range_deg), device.transmission(joint), m, suffix,
                        inertia_in)


def ik_ranges_deg(q_rad, status) -> np.ndarray:
    """(n_joints, 2) [[q_min, q_max]] deg of joint angles ``q_rad`` (n_samples, n_joints) over a
    workspace grid, unwrapped along the samples and widened by
    :data:`cad.tolerances.CAPSTAN_RANGE_MARGIN_DEG` on each side: a drum's arc covers them.
    DesignError (``workspace``) when a sample's ``status`` is not 0 (not reached)."""
    bad = int(np.sum(np.asarray(status) != 0))
    if bad:
        raise DesignError("workspace", f"a capstan's drum needs the whole workspace reachable: {bad} grid "
                          "points are not")
    q = np.degrees(np.unwrap(np.asarray(q_rad, float), axis=0))
    return np.column_stack([q.min(axis=0) - CAPSTAN_RANGE_MARGIN_DEG, q.max(axis=0) + CAPSTAN_RANGE_MARGIN_DEG])


def capstan_joints_of(device, joints, ranges_deg, labels, inertia_in: str) -> tuple:
    """A :class:`CapstanJoint` for each capstan-driven joint of ``joints`` (names, in the
    family's motor order, their rows suffixed ``_1`` .. ``_k`` by position): ``ranges_deg``
    (len(joints), 2) deg (:func:`ik_ranges_deg`), ``labels`` the joints' names in the rows."""
    return tuple(capstan_joint(device, j, float(r[1] - r[0]), lab, f"_{i + 1}", inertia_in=inertia_in)
                 for i, (j, r, lab) in enumerate(zip(joints, ranges_deg, labels, strict=True))
                 if device.transmission(j).is_capstan)


def layout(j: CapstanJoint) -> CapstanLayout:
    """The rope's layout of ``j``'s capstan (module docstring)."""
    t = j.transmission
    dc, dd = t.capstan_diameter_mm, t.drum_diameter_mm
    C = cap.centre_distance_mm(dc, dd, t.centre_distance_mm)
    L = float(cap.free_run_length_mm(dc, dd, C))
    sector = float(cap.drum_sector_needed_deg(j.range_deg, dd, ANCHOR_LENGTH_MM))
    cut = cap.cable_cut_length_mm(dc, dd, t.wraps, L, sector, ANCHOR_TAIL_MM)
    return CapstanLayout(C, L, j.range_deg, sector, cut)


def figures(j: CapstanJoint) -> cap.CapstanJointFigures:
    """:func:`cad.actuators.capstan.capstan_joint_figures` of ``j`` at its motor's peak torque
    through the ratio (ValueError when the joint is driven directly)."""
    t, m = j.transmission, j.motor
    if not t.is_capstan:
        raise ValueError(f"{j.name}: the {j.label} is driven directly (no capstan)")
    tau = (m.spec.torque_peak_mNm or 0.0) * 1e-3 * t.ratio
    f = m.spec.friction_torque_mNm()
    return cap.capstan_joint_figures(
        t.capstan_diameter_mm, t.drum_diameter_mm, t.cable, m.rotor_inertia_kg_m2, tau,
        2.0 * math.pi * t.wraps, motor_friction_Nm=None if f is None else f * 1e-3,
        pretension_given_N=t.pretension_N)


def cable_stiffness_Nm_per_rad(t: Transmission, lay: CapstanLayout) -> float | None:
    """k_q = EA (1/L + 1/L) r_d^2 of the two free runs at the joint (N m/rad); None without the
    rope's E A (the resolved device's: the design's ``transmission.cable_EA_N`` or the rope
    catalog's)."""
    if t.cable_EA_N is None:
        return None
    return float(cap.cable_torsional_stiffness_Nm_per_rad(
        t.cable_EA_N, t.drum_diameter_mm, (lay.run_length_mm, lay.run_length_mm)))


def k_max_with_cable_N_per_m(K_max_N_per_m: float | None, k_q: float | None, Jx) -> float | None:
    """The renderable stiffness with the rope in series: 1 / (1 / K_max + Jx^2 / k_q), weakest
    over the stroke (N/m; ``Jx`` the handle's travel per joint radian, m/rad, any shape); K_max
    itself without the rope's stiffness, None without K_max."""
    if K_max_N_per_m is None or k_q is None:
        return K_max_N_per_m
    return float(cap.series_stiffness(K_max_N_per_m, k_q / float(np.max(np.asarray(Jx) ** 2))))


def datasheet_rows(j: CapstanJoint) -> tuple[list[dict], dict]:
    """(rows, limits) of ``j``'s capstan at the peak load (module docstring): ratio, reflected
    rotor inertia, bend ratio, pretension, slip margin, rope safety factor, drum sector, cut
    length; ``([], {})`` for direct drive. Row and limit keys carry ``j.suffix``."""
    t = j.transmission
    if not t.is_capstan:
        return [], {}
    fig, lay, c, s, lab = figures(j), layout(j), t.cable, j.suffix, j.label
    bend = t.capstan_diameter_mm / c.diameter_mm
    given = t.pretension_N is not None
    jc = t.capstan_inertia_kg_m2(j.motor.spec.shaft_diameter_mm) * t.ratio ** 2 * 1e7  # g cm^2
    rows = [
        row("transmission_ratio" + s, "capstan ratio n (drum / capstan)", t.ratio, "",
            f"{t.drum_diameter_mm:g} mm drum / {t.capstan_diameter_mm:g} mm capstan; joint torque = n "
            f"motor torque, counts per {lab} turn = n counts per motor turn; forces, resolution and "
            "friction above are through it"),
        row("reflected_rotor_inertia_g_cm2" + s, f"rotor inertia at the {lab} (n^2 J_m)",
            fig.reflected_inertia_kg_m2 * 1e7, "g cm^2",
            f"n^2 J_m = {t.ratio:.4g}^2 x {j.motor.spec.rotor_inertia_g_cm2:g} g cm^2; with the capstan's own "
            f"n^2 J_c = {jc:.4g} g cm^2 (it turns with the rotor), n^2 (J_m + J_c) = "
            f"{fig.reflected_inertia_kg_m2 * 1e7 + jc:.4g} g cm^2 is what {j.inertia_in} take"),
        row("bend_ratio" + s, f"bend ratio D/d of {c.key} on the capstan", bend, "",
            f"capstan {t.capstan_diameter_mm:g} mm / rope {c.diameter_mm:g} mm against the rope's minimum "
            f"{c.min_bend_ratio:g} ({c.source_of('min_bend_ratio')})"
            + ("" if (fix := cap.bend_ratio_fix(c, t.capstan_diameter_mm)) is None else f"; {fix}"),
            unverified=c.is_unverified("min_bend_ratio")),
        row("cable_pretension_N" + s, "rope pretension (the tensioner's setting)", fig.pretension_N, "N",
            ("transmission.pretension_N" if given else
             f"the smallest that holds the peak load: T0 = (dT / 2)(e^(mu theta) + 1) / (e^(mu theta) - 1), "
             f"dT = {fig.tension_difference_N:.4g} N, {t.wraps:g} turns, mu = {cap.MU_STEEL_ROPE_ON_STEEL:g}; "
             "set the tensioner to at least this")),
        row("cable_slip_margin" + s, f"rope slip margin at the {lab} (peak force)", float(f"{fig.slip_margin:.9g}"), "",
            f"e^(mu theta) / (T_t / T_s), capstan equation, {t.wraps:g} turns, mu = "
            f"{cap.MU_STEEL_ROPE_ON_STEEL:g} (Tribology Handbook B12), T0 = {fig.pretension_N:.4g} N, "
            f"dT = n tau_peak / r_d = {fig.tension_difference_N:.4g} N"),
        row("cable_safety_factor" + s, f"rope safety factor at the {lab} (peak force)",
            None if c.min_breaking_load_N is None else
            float(cap.cable_safety_factor(c.min_breaking_load_N, fig.tension_difference_N, fig.pretension_N)),
            "", fig.strength[1] + f"; {c.source_of('min_breaking_load_N')}",
            unverified=c.is_unverified("min_breaking_load_N")),
        row("drum_sector_deg" + s, "drum arc the rope needs", lay.sector_deg, "deg",
            f"{lab} range {lay.joint_range_deg:.4g} deg + two anchors of {ANCHOR_LENGTH_MM:g} mm "
            f"(2 L_a / d_d = L_a / r_d each) on the {t.drum_diameter_mm:g} mm drum"),
        row("cable_cut_length_mm" + s, f"rope {c.key} to cut", lay.cut_mm["total"], "mm", cut_text(t, lay)),
    ]
    return rows, limits(j)


def limits(j: CapstanJoint) -> dict:
    """The capstan rows' limits (keys with ``j.suffix``): bend ratio >= the rope's minimum,
    slip margin >= 1, safety factor >= :data:`cad.actuators.capstan.CABLE_SAFETY_FACTOR`, drum
    sector <= 360 deg. Each reason names the joint (``j.label``): a device's joints each get
    their own warning line; the safety factor's states the rope's breaking load and the tight
    run's tension T0 + dT / 2 at the peak torque (N)."""
    c, s, lab = j.transmission.cable, j.suffix, j.label
    return {
        "bend_ratio" + s: Limit(">=", c.min_bend_ratio, f"rope makers' minimum D/d for {c.construction}; the {lab}",
                                "transmission.capstan_diameter_mm or transmission.cable"),
        "cable_slip_margin" + s: Limit(">=", 1.0, f"the rope must not slip on the capstan at the peak force; the {lab}",
                                       "transmission.pretension_N or transmission.wraps"),
        "cable_safety_factor" + s: Limit(">=", cap.CABLE_SAFETY_FACTOR, safety_reason(j), CAPSTAN_CHANGE),
        "drum_sector_deg" + s: Limit("<=", 360.0, f"the rope and both anchors fit on one drum; the {lab}",
                                     "transmission.drum_diameter_mm"),
    }


def safety_reason(j: CapstanJoint) -> str:
    """The safety factor limit's reason for ``j``: the joint, its rope's breaking load and the
    tight run's tension T0 + dT / 2 at the motor's peak torque (N, :func:`figures`), then the
    rule (rope sellers: 4:1 or 5:1)."""
    c, fig = j.transmission.cable, figures(j)
    tight = fig.pretension_N + 0.5 * fig.tension_difference_N
    mbl = ("breaking load not known" if c.min_breaking_load_N is None else
           f"breaking load {c.min_breaking_load_N:.4g} N" + (" (unverified)" if c.is_unverified(
               "min_breaking_load_N") else ""))
    return (f"the {lab_of(j)} rope ({c.key}): {mbl} over the tight run's tension {tight:.4g} N "
            f"(T0 {fig.pretension_N:.4g} N + dT/2 {0.5 * fig.tension_difference_N:.4g} N at the motor's peak "
            "torque); rope sellers: 4:1 or 5:1")


def lab_of(j: CapstanJoint) -> str:
    """``"<label>'s"`` with the motor's number when the joint's rows carry one and the label
    does not say it already (``"knob left proximal link's (motor 1)"``; the delta's ``"arm 1's"``)."""
    n = j.suffix.lstrip("_")
    said = j.label.split()[-1] == n
    return f"{j.label}'s" + (f" (motor {n})" if n.isdigit() and not said else "")


def cut_text(t: Transmission, lay: CapstanLayout) -> str:
    """The rope's cut length, part by part, as the rows and the BOM state it."""
    p = lay.cut_mm
    gap = ("transmission.centre_distance_mm" if t.centre_distance_mm is not None
           else f"rim gap {CAPSTAN_GAP_MM:g} mm")
    return (f"{t.wraps:g} turns on the capstan {p['wraps']:.0f} + two free runs {p['runs']:.0f} (L = "
            f"{lay.run_length_mm:.1f} mm, centre distance {lay.centre_distance_mm:.1f} mm, "
            f"{gap}) + drum arc {p['drum']:.0f} + anchor tails {p['anchors']:.0f} mm")


def stiffness_row(j: CapstanJoint, lay: CapstanLayout) -> tuple[dict, float | None, str]:
    """(row, k_q, source text) of the rope's torsional stiffness at ``j`` (N m/rad); without
    the rope's E A the row's value is None (unverified) and k_q None."""
    t, s = j.transmission, j.suffix
    k = cable_stiffness_Nm_per_rad(t, lay)
    if k is None:
        return (row("cable_stiffness_Nm_per_rad" + s, f"rope stiffness at the {j.label}", None, "N m/rad",
                    f"not computed: no E A for {t.cable.key} in the rope catalog; give "
                    "transmission.cable_EA_N from the rope maker's sheet. The first mode, compliance "
                    "and K_max above take the rope as rigid", unverified=True), None, "")
    src = (f"k_q = EA (2 / L) r_d^2, EA = {t.cable_EA_N:.4g} N, L = {lay.run_length_mm:.1f} mm; EA from "
           f"{t.cable_EA_source}")
    return row("cable_stiffness_Nm_per_rad" + s, f"rope stiffness at the {j.label}", k, "N m/rad", src), k, src


def joints_rows(joints) -> tuple[list[dict], dict, dict[str, float]]:
    """(rows, limits, k_q) of several capstan joints (one per motor): each joint's
    :func:`datasheet_rows` followed by its :func:`stiffness_row`, in the joints' order, the
    limits of all (keys carry each joint's suffix), and ``{joint name: k_q}`` (N m/rad) of the
    joints whose rope states its E A (capstan joints: :func:`capstan_joint` of capstan
    transmissions). ``([], {}, {})`` for no joint. The delta's per-arm rows and the 5-bar's and
    twin's per-motor rows use it (:func:`cad.families.delta.capstan.datasheet_rows`,
    :func:`cad.families.pantograph.capstan.capstan_rows`)."""
    rows: list[dict] = []
    lims: dict = {}
    k_q: dict[str, float] = {}
    for j in joints:
        r, lim = datasheet_rows(j)
        st_row, k, _ = stiffness_row(j, layout(j))
        rows += [*r, st_row]
        lims.update(lim)
        if k is not None:
            k_q[j.name] = k
    return rows, lims, k_q


def bom_row(part: str, desc: str, quantity: int, made: bool, process: str, material: str,
            designation: str, stock: str = "") -> dict:
    """One bom.csv row of the capstan transmission group (no solid: mass 0)."""
    return {"part": part, "description": desc, "material": material, "quantity": quantity,
            "made_or_bought": "made" if made else "bought", "process": process, "fits": "",
            "mass_g": 0.0, "group": "capstan transmission", "designation": designation,
            "order_code": "", "stock": stock}


def cable_bom_line(j: CapstanJoint, quantity: int = 1) -> dict:
    """The rope of ``j`` with its cut length, as a bom.csv row ``capstan_cable`` + suffix
    (the free runs are drawn, as part of this line); ``quantity`` ropes of that cut."""
    t = j.transmission
    c, lay = t.cable, layout(j)
    mbl = ("breaking load not known" if c.min_breaking_load_N is None else
           f"breaking load {c.min_breaking_load_N:.0f} N" + (" (unverified)" if c.is_unverified(
               "min_breaking_load_N") else ""))
    cut = lay.cut_mm["total"]
    return bom_row("capstan_cable" + j.suffix, f"{c.description}, cut length {cut:.0f} mm ({cut_text(t, lay)}); "
                   f"{mbl}; source: cad.data.cables ({c.source_of('min_breaking_load_N')})", quantity, False,
                   "bought; cut to length", "steel", f"wire rope {c.construction} {c.diameter_mm:g} mm x {cut:.0f} mm")


def tension_ceiling(j: CapstanJoint) -> str:
    """The winding step's words after its minimum tension (the pretension the capstan equation
    asks, the datasheet's): at most the one at which the tight run at peak force still meets the
    rope's safety factor (:func:`cad.actuators.capstan.max_pretension_N`), that the minimum
    already misses it when the two cross, or that no maximum is known (no breaking load)."""
    t, fig = j.transmission, figures(j)
    lo, mbl = fig.pretension_N, t.cable.min_breaking_load_N
    if mbl is None:
        return " (no maximum known: the rope's breaking load has no source)"
    hi = float(cap.max_pretension_N(mbl, fig.tension_difference_N))
    sf = f"the safety factor {cap.CABLE_SAFETY_FACTOR:g} against the rope's {mbl:.0f} N breaking load"
    if hi < lo:
        return f"; at that the tight run at peak force already misses {sf} (the datasheet's safety factor row)"
    return f" and at most {hi:.1f} N (above it the tight run at peak force misses {sf})"


def winding_steps(j: CapstanJoint, parts: tuple[str, str, str] | None = None,
                  label: str | None = None) -> tuple[str, ...]:
    """``assembly.md``'s winding and tensioning steps of ``j``'s capstan (empty for direct
    drive): the rope's cut length, its path from one anchor over the drum, round the capstan and
    back to the other anchor, and the tensioner's setting (the datasheet's pretension).
    ``parts``: the instance names of its anchor screw, tensioner screw and lock nut (default
    ``capstan_anchor<suffix>_1``, ``capstan_tensioner<suffix>``, ``capstan_tensioner_nut<suffix>``);
    ``label``: the joint's words there (default ``j.label``) -- one rope of a transmission that
    several joints share."""
    t, s = j.transmission, j.suffix
    if not t.is_capstan:
        return ()
    anchor, tensioner, nut = parts or (f"capstan_anchor{s}_1", f"capstan_tensioner{s}", f"capstan_tensioner_nut{s}")
    lab = label or j.label
    lay = layout(j)
    return (
        f"wind the rope: cut {lay.cut_mm['total']:.0f} mm of {t.cable.key} (bom.csv capstan_cable{s}); "
        f"clamp one end under {anchor} with the {lab} at the end of its range nearest that "
        f"anchor, lay it on the drum's rim to the tangent point, wind {t.wraps:g} turns on the capstan "
        f"(its helical groove, side by side), lay it back on the drum's rim to {tensioner} and "
        "wind its tail on the tensioner screw's shank between the lock nut and the head (the 20 mm "
        "tail: about two turns)",
        f"tension the rope: turn {tensioner} (it winds the rope on its shank) until the rope "
        f"holds at least {figures(j).pretension_N:.1f} N (datasheet cable_pretension_N{s}; a spring scale on "
        f"a free run){tension_ceiling(j)}, lock it with {nut} against the rim, then turn the {lab} over "
        "its whole range: the rope stays on the drum's rim and in the capstan's turns, no anchor "
        "reaches a tangent point",
    )
