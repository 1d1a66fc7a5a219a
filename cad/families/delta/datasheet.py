"""Datasheet rows of the delta (issue 36 §4): the continuous and peak force in the worst
direction over the workspace grid from the data-sheet torques of the resolved device's motor
(``parts.motor`` with the ``[motor]`` table, :func:`cad.device.resolve_device`; f = J^T tau,
eq 2: the force every direction gets with |tau|_2 at the motor limit is tau sigma_min(J^T)),
the position resolution from the resolved encoder (sigma_max(J^-1) 2 pi / counts), the
apparent mass (eigenvalues of Lambda(x) from the solids), the first structural mode and
the effector compliance at the workspace centre, the moving mass, the largest solid overlap
over the workspace, the workspace and the delta's reachable and well-conditioned volume
(:func:`workspace_rows`), the motor torque gravity takes (:func:`gravity_rows`; the forces are
before gravity compensation); with the default first-mode limit and, from ``[actuators]
force_max_N``, the force limit (:func:`cad.families.pantograph.limits.pantograph_limits`). No CAD
import."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from cad.data.ball_joints import get_ball_joint
from cad.datasheet import row
from cad.datasheet.limits import (
    FIRST_MODE_MIN_HZ,
    MODE_REASON,
    OVERLAP_LIMIT,
    STRESS_REASON,
    STRESS_SAFETY_FACTOR,
    Limit,
    with_targets,
)
from cad.device import resolve_device
from cad.dynamics.stiffness import range_text, stiffness_range_N_per_m
from cad.families.delta import capstan
from cad.families.delta import hardware as hw
from cad.families.delta.design import JOINTS
from cad.firmware.extras import paper_eq25_inputs
from cad.kinematics.delta import (
    ik,
    jacobian_rad_per_m,
    largest_cube_mm,
    require_ok,
    workspace_volumes,
)
from cad.structure.elastic import get_elastic

#: What changes the delta's force and first mode (the sections are the family's fixed
#: choices in cad/families/delta/hardware.py).
CHANGE = ("mechanism.upper_arm_mm (shorter: more force, stiffer), the workspace, parts.motor "
          "or [motor]; the sections: cad/families/delta/hardware.py")
#: What lowers the stress and raises the rods' buckling margin at the motors' peak torque.
STRESS_CHANGE = ("[motor] torque_peak_mNm (the drive's current limit), mechanism.lower_arm_mm "
                 "(shorter rods: Euler load ~ 1 / L^2), the workspace; the sections: "
                 "cad/families/delta/hardware.py")


#: The Novint Falcon's geometry as the open driver libnifalcon publishes it
#: (include/falcon/core/FalconGeometry.h, after R. E. Stamper's thesis, 1997; the design keys
#: of designs/delta_falcon.toml, mm): a design with these keys gets :func:`published_notes`.
FALCON_GEOMETRY_MM = {"base_radius_mm": 37.233758, "effector_radius_mm": 14.0, "upper_arm_mm": 60.0,
                      "lower_arm_mm": 102.5, "joint_offset_mm": 22.5, "axis_offset_mm": -2.330909}
#: What Novint states of the product: the workspace, a 4 x 4 x 4 in cube (101.6 mm; as
#: designs/delta_falcon.toml states it); its force: no source found (unknown).
FALCON_PUBLISHED_CUBE_MM = 4 * 25.4


def published_notes(design, dev, force_N: float, peak_N: float) -> list[str]:
    """Notes of the datasheet: the motors when the design states none (``[parts] motor`` and
    ``[motor]`` absent: the family's default is used, named); and for the Falcon's geometry
    (:data:`FALCON_GEOMETRY_MM`) this build's workspace and force beside Novint's figures."""
    raw = getattr(design, "raw", None) or {}
    notes = []
    stated = "motor" in (raw.get("parts") or {}) or bool(raw.get("motor"))
    if not stated:
        notes.append(f"motors: the design states none; the family's default {dev.motor.name} is "
                     "used (BOM, forces, rotor inertia, firmware): not the motors of a published "
                     "device the geometry may come from")
    d = design.mechanism
    if all(abs(float(getattr(d, k)) - v) < 1e-6 for k, v in FALCON_GEOMETRY_MM.items()):
        cube = largest_cube_mm(d, (-200.0, -60.0))
        ws = design.workspace
        here = (" x ".join(f"{v:g}" for v in ws["size_mm"]) + " mm box" if ws["shape"] == "box"
                else f"d{ws['diameter_mm']:g} x {ws['height_mm']:g} mm cylinder")
        notes.append(
            f"Novint Falcon geometry (libnifalcon FalconGeometry.h): workspace here a {here} "
            f"(the largest cube this geometry reaches on the axis: "
            f"{math.floor(cube['side_mm'] * 10) / 10:.1f} mm) "
            f"beside Novint's {FALCON_PUBLISHED_CUBE_MM:g} mm (4 in) cube; force here "
            f"{force_N:.3g} N continuous / {peak_N:.3g} N peak in every direction with the "
            f"{dev.motor.name}{'' if stated else ', not the Falcon' + chr(39) + 's motors (not published)'}; "
            "Novint's force: unknown (no source found)")
    return notes


def force_in_every_direction_N(design, torque_Nm: float, ratios=None) -> tuple[float, list[float]]:
    """(the force the effector exerts in every direction at every workspace point with each
    motor torque vector bounded by |tau_m|_2 <= ``torque_Nm``: min over the grid of
    torque_Nm * sigma_min(J^T N) (J: theta_dot = J x_dot, rad/m, f = J^T tau, joint torque
    tau = N tau_m, N = diag(``ratios``) the transmissions' n, default 1), the point where it
    is smallest (mm)). Raises KinematicsError naming a point out of reach."""
    X = design.workspace_points()
    J, status = jacobian_rad_per_m(design.mechanism, X)
    if np.any(status != 0):
        require_ok(ik(design.mechanism, X))
    if ratios is not None:
        J = J * np.asarray(ratios, float)[None, :, None]
    s_min = np.linalg.svd(np.swapaxes(J, 1, 2), compute_uv=False)[:, -1]
    i = int(np.argmin(s_min))
    return float(torque_Nm * s_min[i]), X[i].tolist()


def resolution_um(design, counts: int, ratios=None) -> tuple[float, float, list[float]]:
    """(worst, best, where the worst is (mm)) over the workspace grid of the effector step of
    one encoder count: sigma_max(J^-1 N^-1) 2 pi / ``counts`` (um; J^-1 = dx/dtheta, m/rad;
    ``counts`` per motor turn, N = diag(``ratios``) the transmissions' n: a joint turn is n
    motor turns). Raises KinematicsError naming a point out of reach."""
    X = design.workspace_points()
    J, status = jacobian_rad_per_m(design.mechanism, X)
    if np.any(status != 0):
        require_ok(ik(design.mechanism, X))
    if ratios is not None:
        J = J * np.asarray(ratios, float)[None, :, None]
    step = np.linalg.svd(np.linalg.inv(J), compute_uv=False)[:, 0] * 2 * math.pi / counts * 1e6
    i = int(np.argmax(step))
    return float(step[i]), float(step.min()), X[i].tolist()


def friction_N(design, torque_Nm: float, ratios=None) -> tuple[float, float, list[float]]:
    """(worst, best, where the worst is (mm)) over the workspace grid of the Coulomb friction
    the hand feels at the effector, worst direction: each motor's friction torque
    ``torque_Nm`` through its ratio n_i at its joint, n_i tau_f sign(theta_dot_i), seen at the
    effector through f = J^T tau (J: theta_dot = J x_dot, rad/m): moving along a unit v the
    friction dissipates sum_i n_i tau_f |J_i . v|, so the largest resisting force is
    max over the sign vectors s in {-1, 1}^3 of |J^T diag(n) tau_f s| (the eight corners of
    the torque box). N = diag(``ratios``), default 1. KinematicsError naming a point out of
    reach."""
    X = design.workspace_points()
    J, status = jacobian_rad_per_m(design.mechanism, X)
    if np.any(status != 0):
        require_ok(ik(design.mechanism, X))
    n = np.ones(3) if ratios is None else np.asarray(ratios, float)
    signs = np.array(np.meshgrid(*[[-1.0, 1.0]] * 3)).reshape(3, -1).T          # (8, 3)
    f = np.linalg.norm(np.einsum("sk,nkl->nsl", signs * n * torque_Nm, J), axis=2).max(axis=1)
    i = int(np.argmax(f))
    return float(f[i]), float(f.min()), X[i].tolist()


def friction_row(design, motor, ratios=None) -> dict:
    """``friction_N``: :func:`friction_N` with the motor's brush and bearing friction
    K_t I_0 (no-load current at no-load speed taken as Coulomb, as the four-bar's row:
    :meth:`cad.data.catalog.MotorSpec.friction_torque_mNm`), through the transmissions'
    ratios; value None (unverified) without K_t or I_0."""
    tf = motor.friction_torque_mNm()
    fields = ("torque_constant_mNm_per_A", "no_load_current_mA")
    src = "; ".join(f"{f}: {motor.source_of(f)}" for f in fields)
    if tf is None:
        return row("friction_N", "Coulomb friction at the effector (no load), worst direction", None, "N",
                   f"not computed: {motor.key} has no torque constant or no-load current", unverified=True)
    hi, lo, at = friction_N(design, tf * 1e-3, ratios)
    thru = "" if ratios is None else f" through n = {', '.join(f'{v:.4g}' for v in ratios)} (n_i tau_f at joint i)"
    return row("friction_N", "Coulomb friction at the effector (no load), worst direction", hi, "N",
               f"motor brushes and bearings tau_f = Kt I0 = {tf:.4g} mN m per motor{thru}, at the effector "
               f"max over signs |J^T N tau_f s| (f = J^T tau), worst over the workspace grid at {at} mm; "
               f"the joints' bearings and ball links not counted; {motor.winding or motor.key} ({src})",
               lo=lo, hi=hi, unverified=any(motor.is_unverified(f) for f in fields))


def k_max_row(resolution_um_: float) -> dict:
    """``eq25_K_max_N_per_m``: eq (25) (Hoeken paper §III.B.4) with the paper's Fv, Fs, Te,
    xdot_max (identified on its prototype: unverified for a delta) and Delta = the position
    resolution worst over the workspace (um in, N/m out); the firmware's wall sketch and
    ``chai3d_device.json`` read this row (:func:`cad.firmware.extras.wall_numbers`). No
    ``min``/``max`` (a figure's range over the workspace in every other row): the model text
    states both sides of eq (25)'s range, or that it is empty."""
    inputs = paper_eq25_inputs(resolution_um_ * 1e-6)
    k_min, k_max = stiffness_range_N_per_m(inputs)
    return row("eq25_K_max_N_per_m", "renderable stiffness, eq (25) bound", k_max, "N/m",
               f"eq (25) 2 (Fs + Fv xdot) / (Delta + xdot Te), Delta = {resolution_um_:.4g} um (the "
               "resolution above, worst direction and point), Hoeken paper's Fv, Fs, Te, xdot_max "
               f"(§III.B.4, identified on its prototype); the firmware's wall reads it; "
               f"{range_text(k_min, k_max)}", unverified=True, inputs=dataclasses.asdict(inputs))


def rows_and_limits(design, report: dict, out_dir=None, simulate_wall: bool = True):
    """(rows, limits, notes) of a delta build report (module docstring)."""
    dev = resolve_device(design)  # the motors and encoders the BOM orders
    m, enc = dev.motor.spec, dev.encoder
    src = f"{m.description} data sheet (cad.data.catalog: {m.key}; resolved device)"
    n = ratios_of(dev)
    res, res_lo, at_res = resolution_um(design, enc.counts_per_rev, n)
    fc, at_c = force_in_every_direction_N(design, m.torque_continuous_mNm * 1e-3, n)
    fp, _ = force_in_every_direction_N(design, m.torque_peak_mNm * 1e-3, n)
    thru = "" if n is None else f"; through the capstans' ratios n = {', '.join(f'{v:.4g}' for v in n)} (J^T N)"
    a, s = report.get("apparent_mass") or {}, report.get("structure") or {}
    itf = report.get("interference") or {}
    rows = [
        *workspace_rows(design),
        row("continuous_force_N", "continuous force in every direction", fc, "N",
            f"min over the workspace grid of T_cont sigma_min(J^T) (eq 2), at {at_c} mm; "
            f"T_cont {m.torque_continuous_mNm:g} mN m, {src}{thru}; before gravity compensation: "
            "the whole torque goes to the hand (the firmware's gravity compensation takes up to "
            "gravity_torque_max_Nm of it)"),
        row("peak_force_N", "peak force in every direction", fp, "N",
            f"as the continuous force with the peak torque {m.torque_peak_mNm:g} mN m, {src}{thru}"),
        row("resolution_um", "position resolution at the effector", res, "um",
            f"sigma_max(J^-1) 2 pi / {enc.counts_per_rev} counts per joint, worst over the "
            f"workspace grid at {at_res} mm; {enc.source}" + ("" if n is None else
            f"; counts per joint turn n x {enc.counts_per_rev} (J^-1 N^-1)"), lo=res_lo, hi=res),
        friction_row(design, m, n),
        *gravity_rows(report.get("gravity") or {}, m.torque_continuous_mNm * 1e-3),
        kmax := k_max_row(res),
        row("apparent_mass_max_g", "apparent mass, worst direction", a.get("Lambda_max_eig_g"), "g",
            f"largest eigenvalue of Lambda(x) from the solids and the rotors "
            f"{'' if n is None else 'through the capstans, n^2 (J_m + J_capstan) '}"
            f"({a.get('rotor_inertia_kg_m2', 0) * 1e7:.4g} g cm^2 each, {dev.motor.name}) over the "
            f"grid, at {a.get('at_max_mm')} mm (eq 1)"),
        row("apparent_mass_min_g", "apparent mass, best direction", a.get("Lambda_min_eig_g"), "g",
            "smallest eigenvalue of Lambda(x) over the grid"),
        row("first_mode_Hz", "first structural mode (workspace centre)", s.get("first_mode_Hz"), "Hz",
            "3-D beam and truss frame of the solids' sections: " + str(s.get("boundary", ""))),
        row("compliance_max_um_per_N", "effector compliance, worst direction",
            s.get("compliance_max_um_per_N"), "um/N", "the same frame model, static"),
        *stress_rows(s, design),
        row("moving_mass_g", "moving mass", report.get("moving_mass_g"), "g",
            "every body but the base, from the solids"),
        row("total_mass_g", "total mass", report.get("total_mass_g"), "g",
            "BOM: made parts from the solids, bought parts their catalog masses (encoders: mass "
            "not known, not in the total)"),
        row("overlap_volume_mm3", "largest solid overlap over the workspace",
            itf.get("overlap_volume_mm3"), "mm^3",
            f"every pair of solids at {itf.get('n_poses')} workspace points"),
        ball_joint_row(report.get("ball_joints") or {}),
    ]
    cap_rows, cap_limits = capstan.datasheet_rows(design, dev, kmax["value"])
    return rows + cap_rows, {**delta_limits(design), **cap_limits}, published_notes(design, dev, fc, fp)


def workspace_rows(design) -> list[dict]:
    """The workspace: the ``[workspace]`` table's box or cylinder (``workspace_cm3``, its
    volume; the grid every other row is taken over), and the delta's whole reachable and
    well-conditioned volume below the base (``reachable_volume_cm3``,
    ``well_conditioned_volume_cm3``: :func:`cad.kinematics.delta.workspace_volumes` on its
    default 10 mm cells, about 1 s; the error is the boundary's cells, docs/families/delta.md)."""
    ws = design.workspace
    n = len(design.workspace_points())
    if ws["shape"] == "box":
        vol, fig = float(np.prod(ws["size_mm"])) * 1e-3, "workspace box " + " x ".join(f"{v:g}" for v in ws["size_mm"]) + " mm"
    else:
        vol = math.pi / 4 * ws["diameter_mm"] ** 2 * ws["height_mm"] * 1e-3
        fig = f"workspace cylinder d{ws['diameter_mm']:g} x {ws['height_mm']:g} mm"
    v = workspace_volumes(design.mechanism)
    cells = (f"cells of {v['step_mm']:g} mm over the reach box below the base "
             "(cad.kinematics.delta.workspace_volumes; the error is the boundary's cells)")
    return [
        row("workspace_cm3", fig, vol, "cm^3", f"[workspace] table, centre {ws['center_mm']} mm (base frame, "
            f"z up); every one of its {n} grid points reached, regular and inside the motor range (checked "
            "before the build); the figures below are taken over them"),
        row("reachable_volume_cm3", "reachable workspace below the base", v["reachable_cm3"], "cm^3",
            f"the cells whose centre is reached, regular and inside the motor angle range; {cells}"),
        row("well_conditioned_volume_cm3", "well-conditioned workspace below the base",
            v["well_conditioned_cm3"], "cm^3",
            f"reachable cells with sigma_min / sigma_max of J >= {v['threshold']:g} (our choice); {cells}"),
    ]


def gravity_rows(g: dict, t_cont_Nm: float) -> list[dict]:
    """The gravity load (the build's ``gravity``, :func:`cad.families.delta.build.gravity_load`):
    ``gravity_torque_max_Nm``, the largest motor torque that holds the solids still over the
    workspace grid (worst joint and point), and ``gravity_torque_share``, its share of the
    motor's continuous torque ``t_cont_Nm`` (what gravity compensation leaves for the hand:
    1 - share). Absent from a report without them."""
    if not g:
        return []
    per = ", ".join(f"{t:.3g}" for t in g["joint_torque_max_Nm"])
    tau = g["motor_torque_max_Nm"]
    return [
        row("gravity_torque_max_Nm", "motor torque gravity takes, worst joint and point", tau, "N m",
            f"J^-T grad_x V of every moving solid's weight at its centre (g = {g['g_m_s2']:g} m/s^2, -z of "
            f"the base frame), at the motor through the transmission; worst {g['motor_joint']} at "
            f"{np.round(g['motor_at_mm'], 3).tolist()} mm; each joint's worst over the grid: {per} N m"),
        row("gravity_torque_share", "share of the continuous torque gravity takes, worst", tau / t_cont_Nm, "",
            f"gravity_torque_max_Nm / T_cont ({t_cont_Nm:.4g} N m): with gravity compensation that "
            "motor has 1 - this share of its continuous torque left for the hand at that point"),
    ]


def ratios_of(device):
    """(3,) the arms' transmission ratios n (joint order), None when every arm is direct."""
    n = [device.transmission(j).ratio for j in JOINTS]
    return None if all(v == 1.0 for v in n) else n


def stress_rows(s: dict, design) -> list[dict]:
    """The frame's stress rows with every motor at +-its peak torque (the eight sign
    combinations, f = J^T tau), worst over the workspace grid
    (:func:`cad.families.delta.structure.peak_stress_over`): the beams' peak von Mises stress
    and the rods' Euler buckling margin (absent from a report without them)."""
    if s.get("max_stress_MPa") is None:
        return []
    load = (f"the effector held, every motor at +-{s['stress_torque_Nm'] * 1e3:.4g} mN m (peak "
            f"torque, the 8 sign combinations: f = J^T tau), worst over the {s['points']} points "
            "of the workspace grid")
    return [
        row("max_stress_MPa", "peak stress at the motors' peak torque, worst point and combination",
            s["max_stress_MPa"], "MPa",
            f"von Mises, beam stresses of the 3-D frame (arms, cross bars, effector plate), "
            f"critical: {s['critical_member']} at {s['stress_at_mm']} mm, f = "
            f"{np.round(s['critical_load_N'], 2).tolist()} N; {load}; material strength "
            f"{_strength_MPa(hw.ARM_MATERIAL):g} MPa ({hw.ARM_MATERIAL})"),
        row("rod_buckling_margin", "rod buckling margin at the motors' peak torque, worst point",
            s["rod_buckling_margin"], "",
            f"Euler load of a pin-ended rod pi^2 E I / L^2 = {s['rod_buckling_N']:.4g} N "
            f"({hw.ROD_OD_MM:g}/{hw.ROD_ID_MM:g} mm {hw.ROD_MATERIAL} tube, L = lower_arm_mm) over "
            f"the largest rod compression {s['rod_compression_max_N']:.4g} N at "
            f"{s['buckling_at_mm']} mm (rod axial stress at most {s['rod_stress_max_MPa']:.3g} "
            f"MPa); {load}"),
    ]


def ball_joint_row(bj: dict) -> dict:
    """``ball_joint_tilt_max_deg``: the rods' largest tilt in their ball joints over the
    workspace grid (report.json ``ball_joints``, :func:`cad.families.delta.ball_joints.range_check`),
    judged against the joint's catalog range (:func:`delta_limits`)."""
    return row("ball_joint_tilt_max_deg", "ball joints' largest tilt over the workspace",
               bj.get("max_tilt_deg"), "deg",
               f"asin |t_i . x_i| of each arm's rods (eq 1 of cad/families/delta/ball_joints.py) over "
               f"the workspace grid, arm {bj.get('arm')} at {bj.get('at_mm')} mm; joint {bj.get('joint')}")


def _strength_MPa(material: str) -> float:
    return get_elastic(material, "delta.structure").strength_MPa


def _ball_joint_limit(design) -> Limit:
    j = get_ball_joint(design.parts.ball_joint)
    src = ("unverified: no source read" if "range_deg" in j.unverified else j.source_of("range_deg"))
    return Limit("<=", j.range_deg, f"the angular range of the ball joint {j.key} ({src})",
                 "parts.ball_joint (a joint with a wider range), or a smaller [workspace] / longer "
                 "mechanism.lower_arm_mm (the rods tilt less)")


def delta_limits(design) -> dict:
    """The default first-mode limit and, with ``[actuators] force_max_N``, the force limit
    (the force asked for in every direction at every workspace point), then ``[targets]``."""
    lim = {"first_mode_Hz": Limit(">=", FIRST_MODE_MIN_HZ, MODE_REASON, CHANGE),
           "max_stress_MPa": Limit("<=", _strength_MPa(hw.ARM_MATERIAL) / STRESS_SAFETY_FACTOR,
                                   STRESS_REASON.replace("force_N", "the peak torque"), STRESS_CHANGE),
           "rod_buckling_margin": Limit(">=", STRESS_SAFETY_FACTOR,
                                        f"static safety factor {STRESS_SAFETY_FACTOR:g} against "
                                        "Euler buckling at the peak torque", STRESS_CHANGE),
           "overlap_volume_mm3": OVERLAP_LIMIT,
           "ball_joint_tilt_max_deg": _ball_joint_limit(design)}
    force = design.actuators.get("force_max_N")
    if force is not None:
        lim["continuous_force_N"] = Limit(
            ">=", float(force), "[actuators] force_max_N: the force asked for in every direction "
            "at every workspace point, from the continuous torque of the motors the BOM orders",
            CHANGE)
    return with_targets(lim, design.targets)
