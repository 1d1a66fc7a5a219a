"""Datasheet rows of the haptic pen: the pantograph families' rows
(:func:`cad.families.pantograph.datasheet.rows_and_limits`: workspace, force at the pen from
``[actuators] torque_max_Nm`` and the pen Jacobian, resolution, the effective mass at home,
masses), the continuous and peak force from the catalog motors' data-sheet torques (waist
motors on q1, q4, shoulder motors on the others; same ellipsoid model: the smallest singular
value of the translational rows of ``J^T S_J`` over the workspace samples, the moments left
free), with Table 3 of the isotropy paper beside the figures it gives, the interference
check over the motion, and the structure rows (:func:`cad.structure.pen.analyse`: first mode,
pen-end compliance, peak stress; each arm's 5-bar a planar beam frame, motors held, pen end
free, the lower arm's figure) with the default limits of the planar pantographs
(:func:`cad.families.pantograph.limits.pantograph_limits` with ``structure=True``). Behind
capstans (``[transmission]``) the planar rows already go through each ratio and add the shared
capstan rows and their limits (:func:`cad.families.pantograph.capstan.capstan_rows` with the
pen's joints and ropes, :mod:`cad.families.pen.capstan`), kept here. No CAD import.
"""

from __future__ import annotations

from cad.datasheet import row
from cad.datasheet.limits import OVERLAP_LIMIT
from cad.families.pantograph.datasheet import motor_force_rows as rows_of
from cad.families.pantograph.datasheet import rows_and_limits as pantograph_rows
from cad.families.pantograph.limits import pantograph_limits
from cad.structure.pen import analyse

#: report key of our figure -> the Table 3 key beside it.
_PAPER = {"effective_mass_home.mass_x_g_apparent": "mass_x_g",
          "effective_mass_home.mass_y_g_apparent": "mass_y_g",
          "effective_mass_home.mass_z_g_apparent": "mass_z_g"}


def rows_and_limits(design, report: dict, out_dir=None, simulate_wall: bool = True):
    """(rows, limits, notes) of a haptic-pen build report (module docstring)."""
    rows, planar_limits, notes = pantograph_rows(design, report, out_dir, simulate_wall)
    paper = report.get("paper_table3") or {}
    st = structure(design, report)
    out = []
    for r in rows:
        key = _PAPER.get(r.get("key", ""))
        if key and paper.get(key) is not None:
            r = {**r, "paper": paper[key]}
        if r.get("key") == "first_mode_Hz" and st is not None:  # the planar families' placeholder
            out += structure_rows(st)
            continue
        out.append(r)
    out += motor_force_rows(design, paper)
    bd = report.get("effective_mass_breakdown")
    if bd:
        out.append(row("mass_x_breakdown_g", "effective mass along x at home: contributions", bd["total_g"], "g",
                       breakdown_text(bd) + " (cad.families.pen.dynamics.mass_breakdown: kinetic energy part by "
                       "part)", paper=paper.get("mass_x_g")))
    itf = report.get("interference") or {}
    if itf:
        out.append(row("overlap_volume_mm3", "largest solid overlap over the motion",
                       itf.get("overlap_volume_mm3"), "mm^3",
                       f"every pair of solids at {itf.get('n_poses')} poses of the workspace "
                       "(home, box corners at the rotation extremes)"))
    limits = pantograph_limits(design, design.actuators.get("force_max_N"), st and st["strength_MPa"],
                               structure=st is not None)
    limits.update({k: v for k, v in planar_limits.items() if k not in limits})  # the capstan rows' limits
    if itf:
        limits["overlap_volume_mm3"] = OVERLAP_LIMIT
    return out, limits, notes


def structure(design, report: dict) -> dict | None:
    """:func:`cad.structure.pen.analyse` of the build report's ``bodies`` at ``[actuators]
    force_max_N``; None for a report without bodies."""
    if not report.get("bodies"):
        return None

    return analyse(design, report["bodies"], float(design.actuators["force_max_N"]))


#: The boundary conditions of every structure row (cad.structure.pen).
HELD = ("motors held (each arm's proximal links clamped at their shoulder axes B in all six DOFs; "
        "waist motors held, waist brackets rigid), revolute joints rigid but in their rotation")
APPROX = ("planar, per pantograph: each arm's 5-bar a beam frame in its own plane (carbon tubes joint "
          "to joint, clevises not credited) carrying its links' masses, its gimbal and its lever-rule "
          "share of the pen rod at its end point; the device's figure the worse arm's (with the rod, gimbals "
          "and waists rigid the arms coupled through the rod have their first mode at or above it: Rayleigh); "
          "out-of-plane coupling through the pen, the waist brackets' and gimbals' compliance and the rod's "
          "bending not modelled")


def held_text(st: dict) -> str:
    """The boundary condition of the structure rows: :data:`HELD`, or with the capstans' ropes
    (``st["rope_stiffness_Nm_per_rad"]``: joint -> k_q) the joints they turn on their springs,
    the motors held by their servos (:func:`cad.structure.pen.arm_supports`)."""
    ropes = st.get("rope_stiffness_Nm_per_rad") or {}
    if not ropes:
        return HELD
    ks = ", ".join(f"{j} {k:.4g} N m/rad" for j, k in ropes.items())
    return (f"{HELD}, except at a capstan: a shoulder link turns at B about its plane's normal, a waist "
            f"bracket with its arm about the waist axis, through the rope to the held motor (torsional spring "
            f"k_q = EA (2 / L) r_d^2: {ks}; the waist body's inertia about its axis, bracket and shoulder motors, "
            "not in the frame: with a waist rope the out-of-plane mode is an upper bound)")


#: The short form on the rows after the first.
PLANAR = "planar, per pantograph (model as first_mode_Hz)"


def structure_rows(st: dict) -> list[dict]:
    """Datasheet rows of :func:`structure` (boundary conditions and approximation per row)."""
    at = f"worst of arms A, B over the {len(st['poses'])} poses of the interference check"
    held = held_text(st)
    free, load = f"{held}; pen end free", f"{held}; force at the pen end"
    arm = st["per_arm"][st["first_mode_arm"]]
    pose = arm["in_plane_Hz_pose" if arm["in_plane_Hz"] <= arm["out_of_plane_Hz"] else "out_of_plane_Hz_pose"]
    share = ", ".join(f"{a} {v * 1e3:.3g} g" for a, v in st["pen_share_kg"].items())
    ax_text = {"vertical": "vertical (the arm's plane, along its waist axis)",
               "radial": "radial (the arm's plane, away from its waist axis)",
               "normal": "normal to the arm's plane"}
    return [
        row("first_mode_Hz", "first structural mode (lower arm, lower of in plane and out of plane)",
            st["first_mode_Hz"], "Hz", f"{APPROX}; arm {st['first_mode_arm']} at {pose} (pen rod shares: "
            f"{share}); {at}", boundary=free),
        row("first_mode_in_plane_Hz", "first in-plane mode (per arm, its plane)", st["first_mode_in_plane_Hz"], "Hz",
            f"{PLANAR}; modes with their kinetic energy in the arm's plane; {at}", boundary=free),
        row("first_mode_out_of_plane_Hz", "first out-of-plane mode (per arm, waist held)",
            st["first_mode_out_of_plane_Hz"], "Hz",
            f"{PLANAR}; modes with their kinetic energy normal to the arm's plane; {at}", boundary=free),
        *[row(f"compliance_{ax}_um_per_N", f"pen-end compliance, {ax_text[ax]}", st["compliance_um_per_N"][ax],
              "um/N", f"{PLANAR}; at one arm's end point, {at}; bearing compliance not included", boundary=load)
          for ax in ("vertical", "radial", "normal")],
        row("max_stress_MPa", f"peak stress at force_max_N = {st['force_N']:g} N, worst direction",
            st["max_stress_MPa"], "MPa", f"{PLANAR}; von Mises beam stress under {st['end_force_N']:.3g} N at "
            f"one pen end (force_max_N with the moment force_max_N x moment_arm_mm = {st['moment_arm_mm']:g} mm, "
            f"the worst split between the ends), critical link {st['critical_link']} at {st['critical_pose']} "
            f"(material strength {st['strength_MPa']:g} MPa); {at}", boundary=load),
    ]


def motor_force_rows(design, paper: dict) -> list[dict]:
    """Continuous and peak force in every direction at the pen over the workspace, from the
    catalog torques of the waist and shoulder motors
    (:func:`cad.families.pantograph.datasheet.motor_force_rows`); Table 3's smallest axis
    value beside each (its x, y, z figures are per axis)."""
    return rows_of(design, paper)


def breakdown_text(bd: dict) -> str:
    """One line: the x effective mass, its groups, Table 3 and the figure without the
    shoulder motors (report.md note, datasheet row)."""
    parts = ", ".join(f"{k} {v:.0f} g" for k, v in sorted(bd["groups_g"].items(), key=lambda kv: -kv[1]))
    return (f"effective mass along x at home (others held) {bd['total_g']:.0f} g = {parts}; Table 3 measured "
            f"{bd['paper_g']:g} g. Moving x turns both waists, carrying their shoulder motors at the motor "
            f"plate outside four link layers and the gimbal; with the shoulder motors off the waists it would be "
            f"{bd['without_shoulder_motors_g']:.0f} g. The paper's layout keeps them on the waists (they turn with "
            "the 5-bar's plane, §4.2) and its steel counterbalances add to this figure (they balance gravity, "
            "not inertia), so no option of that layout closes the gap: its shoulder actuators are narrower "
            "(l1 = 2.4 cm 'to account for the width of the shoulder actuators', Table 2) and lighter")
