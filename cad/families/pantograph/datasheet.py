"""Datasheet rows of the pantograph families (5-bar pantograph, twin-pantograph haptic mouse,
haptic pen).

At every workspace sample of the design (``[workspace]`` grid, task coordinates) the Jacobian
``q_dot = J x_dot`` (isotropy paper eq 1, SI) gives the handle wrench ``w = J^T tau``. With
every motor at most at its ``[actuators] torque_max_Nm`` (S_J, eq 3) the torques inside the
ellipsoid ``tau = S_J u, |u| <= 1`` (inscribed in the torque box) reach the force ellipse
``F = A u``, ``A`` = the translational rows of ``J^T S_J``: the force available **in every
direction** is its smallest singular value ``sigma_min(A)`` (the twin pantograph's and the
pen's moment left free), the largest force in the best direction ``sigma_max(A)``. The
datasheet gives the minimum of sigma_min over the workspace (the figure a user can count on)
and draws the ellipses over the workspace (``force_ellipses.png``, planar families).

Position resolution: one encoder step ``2 pi / counts`` on each joint moves the handle at
most ``sigma_max(J_pos^+) 2 pi / counts`` (J_pos the translational columns; counts of the
resolved device's encoder, :mod:`cad.device`: the haptic mouse's 4000 cpt optical encoder of
isotropy paper §3.2 unless ``[firmware] encoder_counts_per_rev`` says otherwise, the encoder
the BOM orders); the worst over the workspace. No CAD import.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from cad.datasheet import clearance_parts, row
from cad.device import resolve_device
from cad.dynamics.friction import coulomb_friction_at_handle_N
from cad.dynamics.stiffness import range_text, stiffness_range_N_per_m
from cad.families.pantograph.capstan import capstan_rows
from cad.families.pantograph.limits import pantograph_limits
from cad.families.pantograph.mode_ceiling import mode_ceiling
from cad.firmware.extras import paper_eq25_inputs
from cad.io.escape import mathtext
from cad.kinematics import fivebar as kfivebar
from cad.kinematics import haptic_pen as kpen
from cad.kinematics import twin_pantograph as ktwin
from cad.structure.pantograph import WEB_WIDTH_MIN_MM, analyse

#: Translational task coordinates (columns of J) per family.
FORCE_COLS = {"pantograph": (0, 1), "twin-pantograph": (0, 1), "haptic-pen": (0, 1, 2)}


def jacobian_and_limits(design) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(J (N, m, d) SI over the workspace samples, torque limits (m,) N m, ok mask (N,))."""
    X = design.workspace_points()
    act = design.actuators
    if design.family == "pantograph":
        J, st = kfivebar.jacobian_rad_per_m(design.mechanism, X)
        tau = np.broadcast_to(np.asarray(act["torque_max_Nm"], float), (2,))
    elif design.family == "twin-pantograph":
        J, st = ktwin.jacobian_si(design.mechanism, X)
        tau = np.broadcast_to(np.asarray(act["torque_max_Nm"], float), (4,))
    else:
        J, st = kpen.jacobian_si(design.mechanism, X)
        tau = kpen.actuator_scale(design.params["waist_torque_ratio"], float(np.atleast_1d(act["torque_max_Nm"])[0]))
    return np.asarray(J), np.asarray(tau, float), np.asarray(st) == kfivebar.STATUS_OK


def force_ellipses(design) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(A (N, k, m) force rows of J^T S_J, sigma (N, k) singular values descending, ok (N,))."""
    J, tau, ok = jacobian_and_limits(design)
    cols = FORCE_COLS[design.family]
    A = np.swapaxes(J, -1, -2)[:, cols, :] * tau[None, None, :]
    sig = np.linalg.svd(A, compute_uv=False)
    return A, sig, ok


def resolution_m(design, counts) -> np.ndarray:
    """Worst handle step (m) of one encoder count on every joint, per workspace sample:
    ``sigma_max(J_pos^+ diag(2 pi / counts))``; ``counts``: counts per joint turn, one number
    or one per joint (a capstan's joint counts n times its motor encoder's)."""
    J, _, ok = jacobian_and_limits(design)
    cols = FORCE_COLS[design.family]
    Jp = J[:, :, cols]
    step = 2 * math.pi / np.broadcast_to(np.asarray(counts, float), (J.shape[1],))
    out = np.full(len(J), np.nan)
    for i in np.flatnonzero(ok):
        out[i] = np.linalg.norm(np.linalg.pinv(Jp[i]) * step[None, :], 2)
    return out


def motor_torques_mNm(design, field: str) -> tuple[np.ndarray | None, tuple]:
    """(data-sheet ``field`` torque (m,) mN m of every motor the BOM orders, in the order of
    J's columns, or None when a motor has none; the motor specs (m,)).

    field: a :class:`cad.data.catalog.MotorSpec` torque (``torque_continuous_mNm``,
    ``torque_peak_mNm``). Source: the resolved device (:func:`cad.device.resolve_device`:
    ``parts.motor`` / ``parts.waist_motor`` with the ``[motor]`` table), the one read of the
    motors for these rows), each through its transmission: a capstan of ratio n gives its joint
    n times the motor's torque (:meth:`cad.device.ResolvedDevice.joint_motor`; f = J^-T n tau)."""
    dev = resolve_device(design)
    specs = tuple(dev.joint_motor(m.joint) for m in dev.motors)
    vals = [getattr(m, field) for m in specs]
    return (None if any(v is None for v in vals) else np.asarray(vals, float)), specs


def motor_label(m) -> str:
    """A :class:`cad.device.ResolvedMotor` in a row, as the four-bar's rows name it: the catalog
    key; a ``[motor]`` table's name (the BOM's motor line) when the table names its motor; else
    the key "with the [motor] data" -- a row never credits the catalog motor with a table's
    torques."""
    if not m.from_motor_table:
        return m.catalog_key
    if "(data of [motor]" in m.spec.description:
        return f"{m.name} ([motor], on the {m.catalog_key} mount)"
    return f"{m.catalog_key} with the [motor] data"


def motor_force_rows(design, paper: dict | None = None) -> list[dict]:
    """``continuous_force_N`` and ``peak_force_N``: the force available in every direction at
    the handle, the worst over the workspace, from the data-sheet torques of the motors the
    BOM orders (not ``[actuators]``, the GII's normalisation).

    Model: ``F = A u``, ``A`` = translational rows of ``J^T S_J`` with S_J = diag(motor
    torques), ``|u| <= 1`` (the torque ellipsoid inscribed in the torque box, the moment left
    free); the figure is ``min`` over the reachable samples of ``sigma_min(A)`` (N).
    ``paper``: the pen's Table 3 values (``continuous_force_x_N`` ...), smallest axis beside."""
    J, _, ok = jacobian_and_limits(design)
    cols = FORCE_COLS[design.family]
    rows = []
    for key, field, label in (("continuous_force_N", "torque_continuous_mNm", "continuous"),
                              ("peak_force_N", "torque_peak_mNm", "peak")):
        tau, specs = motor_torques_mNm(design, field)
        if tau is None or not ok.any():
            rows.append(row(key, f"{label} force in every direction", None, "N",
                            "no data-sheet torque for a motor" if tau is None else "no reachable sample"))
            continue
        A = np.swapaxes(J, -1, -2)[:, cols, :] * (tau * 1e-3)[None, None, :]
        sig = np.linalg.svd(A[ok], compute_uv=False)[:, -1]
        named = dict.fromkeys(f"{motor_label(r)} ({getattr(r.spec, field):g} mN m{_through(design, r)})"
                              for r in resolve_device(design).motors)
        ref = [(paper or {}).get(f"{label}_force_{a}_N") for a in "xyz"]
        rows.append(row(key, f"{label} force in every direction", sig.min(), "N",
                        f"min over the workspace of sigma_min(J^T S_J), S_J = the {label} torques "
                        f"of the motors the BOM orders: {', '.join(named)}",
                        lo=sig.min(), hi=sig.max(), unverified=any(m.is_unverified(field) for m in specs),
                        paper=min(v for v in ref if v is not None) if any(ref) else None))
    return rows


def friction_row(design) -> dict:
    """``friction_N``: the motors' Coulomb friction (brush and bearing, K_t I_0 each, times n
    through a capstan) felt at the handle, the worst over the directions of motion and over the
    workspace (:func:`cad.dynamics.friction.coulomb_friction_at_handle_N`, F = J^T tau); the
    link bearings' friction is not in it."""
    J, _, ok = jacobian_and_limits(design)
    dev = resolve_device(design)
    specs = [dev.joint_motor(m.joint) for m in dev.motors]
    f = [m.friction_torque_mNm() for m in specs]
    if any(v is None for v in f) or not ok.any():
        return row("friction_N", "Coulomb friction at the handle (no load)", None, "N",
                   "no K_t or no-load current for a motor" if ok.any() else "no reachable sample")
    A = np.swapaxes(J, -1, -2)[:, FORCE_COLS[design.family], :] * (np.asarray(f) * 1e-3)[None, None, :]
    F = coulomb_friction_at_handle_N(A[ok])
    each = ", ".join(dict.fromkeys(f"{motor_label(r)} {r.spec.friction_torque_mNm():.4g} mN m{_through(design, r)}"
                                   for r in dev.motors))
    return row("friction_N", "Coulomb friction at the handle (no load)", F.max(), "N",
               f"the motors' K_t I_0 at each joint ({each}; I_0 the no-load current, at speed: an upper "
               "estimate of the friction at rest) through J^T, J = dq/dx, the largest over the sign patterns "
               "of the joints' rates (every direction of motion; an upper bound where the motors outnumber "
               "the coordinates) and over the workspace; the link and capstan-axle bearings and the rope's "
               "own losses not included",
               lo=F.min(), hi=F.max(), unverified=any(m.is_unverified("no_load_current_mA") for m in specs))


def _through(design, m) -> str:
    """`` x n = ... at the joint`` of a motor behind a capstan (empty for direct drive)."""
    t = resolve_device(design).transmission(m.joint)
    return "" if not t.is_capstan else f" x capstan n = {t.ratio:.4g} at {m.joint}"


def joint_counts(design) -> np.ndarray:
    """Encoder counts per joint turn (m,), in the order of J's columns: each motor encoder's
    counts times its transmission ratio (the encoder turns with the motor,
    :meth:`cad.device.ResolvedDevice.joint_counts_per_rev`)."""
    dev = resolve_device(design)
    return np.asarray([float(dev.joint_counts_per_rev(e.joint)) for e in dev.encoders], float)


def write_ellipse_chart(design, out_dir, A, ok) -> str | None:
    """``force_ellipses.png``: the force ellipse (N, scaled) at every planar workspace sample."""
    if design.family == "haptic-pen":
        return None
    from matplotlib.figure import Figure

    X = design.workspace_points()
    fig = Figure(figsize=(6, 6))
    ax = fig.add_subplot()
    t = np.linspace(0, 2 * np.pi, 73)
    m = A.shape[-1]
    U = np.zeros((m, t.size))
    smax = float(np.linalg.svd(A[ok], compute_uv=False).max()) if ok.any() else 1.0
    step = min(design.workspace["size_mm"]) / max(design.workspace["grid"] - 1, 1)
    scale = 0.45 * step / smax
    seen = set()
    for i in np.flatnonzero(ok):
        key = (round(X[i, 0], 6), round(X[i, 1], 6))
        if key in seen:  # twin pantograph: one ellipse per (x, y), first crank angle
            continue
        seen.add(key)
        Ui, s, Vt = np.linalg.svd(A[i])
        pts = Ui @ np.diag(s) @ np.vstack([np.cos(t), np.sin(t)])
        ax.plot(X[i, 0] + scale * pts[0], X[i, 1] + scale * pts[1], lw=0.8, color="tab:blue")
    del U
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title(f"{mathtext(design.name)}: force ellipses J^T S_J u, |u| <= 1 ({scale:.3g} mm per N)")
    from pathlib import Path

    fig.savefig(Path(out_dir) / "force_ellipses.png", dpi=110)
    return "force_ellipses.png"


def structure(design, report: dict) -> dict | None:
    """:func:`cad.structure.pantograph.analyse` of a planar family's build report (its
    ``bodies`` and ``layout_mm``) at ``[actuators] force_max_N``; None for the haptic pen (its
    own rows, per arm: :func:`cad.families.pen.datasheet.structure`) or a report without bodies."""
    if design.family not in ("pantograph", "twin-pantograph") or not report.get("bodies"):
        return None

    web = (report.get("layout_mm") or {}).get("web_width_mm", WEB_WIDTH_MIN_MM)
    return analyse(design, report["bodies"], float(design.actuators["force_max_N"]), web)


HELD = ("motors held (each proximal link clamped at its motor axis B in all six DOFs), "
        "revolute joints rigid but in z rotation")


def held_text(st: dict) -> str:
    """The boundary condition of the structure rows: :data:`HELD`, or with the capstans' ropes
    (``st["rope_stiffness_Nm_per_rad"]``: joint -> k_q) the links they drive held at B in five
    DOFs and about z by the rope's spring, the motor held by its servo."""
    ropes = st.get("rope_stiffness_Nm_per_rad") or {}
    if not ropes:
        return HELD
    ks = ", ".join(f"{j} {k:.4g} N m/rad" for j, k in ropes.items())
    return (f"{HELD}, except at a capstan: the link on its axle at B held in five DOFs, its turn about z "
            f"through the rope to the held motor (torsional spring k_q = EA (2 / L) r_d^2: {ks})")


def structure_rows(st: dict) -> list[dict]:
    """Datasheet rows of :func:`structure` (boundary conditions stated per row)."""
    at = f"worst of {len(st['poses'])} poses ({', '.join(st['poses'])})"
    if st["poses_skipped"]:
        at += f"; not reachable, skipped: {', '.join(st['poses_skipped'])}"
    frame = (f"beam frame of the links ({st.get('tube_material', 'carbon-fibre')} tubes joint to joint, "
             "clevises not credited)")
    held = held_text(st)
    free = f"{held}; handle free"
    load = f"{held}; force at the handle"
    b = st["bearing_compliance_estimate"]
    return [
        row("first_mode_Hz", "first structural mode (lower of in plane and out of plane)", st["first_mode_Hz"],
            "Hz", f"{frame} with the bodies' masses, lowest over the poses: {at}", boundary=free),
        row("first_mode_in_plane_Hz", "first in-plane mode", st["first_mode_in_plane_Hz"], "Hz",
            f"{frame}, modes with their kinetic energy in x, y; {at}", boundary=free),
        row("first_mode_out_of_plane_Hz", "first out-of-plane mode", st["first_mode_out_of_plane_Hz"], "Hz",
            f"{frame}, modes with their kinetic energy in z; {at}", boundary=free),
        *[row(f"compliance_{ax}_um_per_N", f"handle compliance along {ax}", st["compliance_um_per_N"][ax], "um/N",
              f"{frame}, {at}" + ("" if ax == "z" else f"; bearing radial compliance not included (estimate "
                                  f"{b[f'{ax}_um_per_N']:.3g} um/N, Palmgren)"), boundary=load)
          for ax in "xyz"],
        row("max_stress_MPa", f"peak stress at force_max_N = {st['force_N']:g} N, worst direction",
            st["max_stress_MPa"], "MPa", f"von Mises, beam stresses, critical link {st['critical_link']} at "
            f"{st['critical_pose']} (material strength {st['strength_MPa']:g} MPa); {at}", boundary=load),
    ]


def k_max_row(step_m: float | None) -> dict:
    """``eq25_K_max_N_per_m``: eq (25) (Hoeken paper §III.B.4) with the paper's Fv, Fs, Te, xdot_max
    (unverified for this device) and Delta = ``step_m`` (m), the position resolution worst over
    the workspace: the wall stiffness the firmware's sketch and ``chai3d_device.json`` state
    (:func:`cad.firmware.extras.wall_numbers`, the same inputs). No ``min``/``max``: those are a
    figure's range over the workspace in every other row, and eq (25)'s lower side 2 Fv / Te is
    no such bound (the model text states both sides, or that the range is empty)."""
    if step_m is None:
        return row("eq25_K_max_N_per_m", "renderable stiffness, eq (25) bound", None, "N/m",
                   "no reachable workspace sample: no encoder step")
    inputs = paper_eq25_inputs(step_m)
    k_min, k_max = stiffness_range_N_per_m(inputs)
    return row("eq25_K_max_N_per_m", "renderable stiffness, eq (25) bound", k_max, "N/m",
               f"eq (25) 2 (Fs + Fv xdot) / (Delta + xdot Te), Delta = {step_m * 1e6:.4g} um (the "
               "resolution above), Hoeken paper's Fv, Fs, Te, xdot_max (§III.B.4, identified on its "
               f"prototype); the firmware's wall reads it; {range_text(k_min, k_max)}", unverified=True,
               inputs=dataclasses.asdict(inputs))


def rows_and_limits(design, report: dict, out_dir=None, simulate_wall: bool = True):
    """(rows, limits, notes) of a pantograph-family build (module docstring)."""
    A, sig, ok = force_ellipses(design)
    ws = design.workspace
    smin, smaxv = sig[ok, -1], sig[ok, 0]
    share = float(ok.mean())
    rows = []
    if design.family == "haptic-pen":
        area, unit = float(np.prod(ws["size_mm"])), "mm^3"
        fig = f"workspace box {' x '.join(f'{v:g}' for v in ws['size_mm'])} mm, +-{ws['rotation_deg']:g} deg"
    else:
        (w, h), unit = ws["size_mm"], "mm^2"
        area = w * h
        fig = (f"workspace square {w:g} mm" if w == h else f"workspace rectangle {w:g} x {h:g} mm") + (", full crank turn" if design.family == "twin-pantograph" else "")
    rows.append(row("workspace", fig, area, unit, f"[workspace] table; {share:.0%} of its {ok.size} samples "
                    "reachable and non-singular (the figures below hold there)"))
    tau = design.actuators['torque_max_Nm']
    tau_txt = (f"[actuators] torque_max_Nm = {tau} (the GII's normalisation, "
               "not the motors: continuous_force_N / peak_force_N)")
    per = f"normalised to {tau:g} N m per joint (GII scale, not the motors' force)"
    rows.append(row("force_any_dir_N", f"force in every direction {per}", smin.min() if ok.any() else None, "N",
                    f"min over the workspace of sigma_min(J^T S_J) (translational rows), {tau_txt}",
                    lo=smin.min() if ok.any() else None, hi=smin.max() if ok.any() else None))
    rows.append(row("force_best_dir_N", f"largest force (best direction) {per}", smaxv.max() if ok.any() else None, "N",
                    f"max over the workspace of sigma_max(J^T S_J), {tau_txt}",
                    lo=smaxv.min() if ok.any() else None, hi=smaxv.max() if ok.any() else None))
    if design.family != "haptic-pen":  # the pen adds its own, with Table 3 beside
        rows += motor_force_rows(design)
    enc = resolve_device(design).encoder  # the encoder the BOM orders
    counts = joint_counts(design)
    res = resolution_m(design, counts) * 1e6
    good = res[np.isfinite(res)]
    steps = (f"{enc.counts_per_rev} counts per joint" if np.all(counts == enc.counts_per_rev) else
             f"{enc.counts_per_rev} counts per motor turn x each capstan's ratio "
             f"({', '.join(f'{c:.6g}' for c in counts)} counts per joint turn)")
    rows.append(row("resolution_um", "position resolution at the handle", good.max() if good.size else None, "um",
                    f"sigma_max(J^+) 2 pi / {steps}, worst over the "
                    f"workspace; {enc.source}",
                    lo=good.min() if good.size else None, hi=good.max() if good.size else None))
    k25 = k_max_row(good.max() * 1e-6 if good.size else None)
    rows.append(k25)
    rows.append(friction_row(design))
    em = report.get("effective_mass_home") or {}
    for k, v in em.items():
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            unit_k = "g cm^2" if "inertia" in k else "g"
            rows.append(row(f"effective_mass_home.{k}", f"effective mass at home: {k}", v, unit_k,
                            "mass matrix from the solids at the home pose (apparent: other axes free; diag: held)",
                            boundary="motors unpowered (joints free), handle free"))
    for k, fig_k in (("moving_mass_g", "moving mass"), ("total_mass_g", "total mass")):
        if isinstance(report.get(k), (int, float)):
            rows.append(row(k, fig_k, report[k], "g", "from the solids (bought parts: catalog masses)"))
    rows += footprint_rows(report)
    if report.get("min_clearance_mm") is not None:
        rows.append(row("min_clearance_mm", "smallest clearance between parts", report["min_clearance_mm"], "mm",
                        "interference check of the build" + clearance_parts(report)))
    st = structure(design, report)
    if st is None:
        rows.append(row("first_mode_Hz", "first structural mode", None, "Hz",
                        "not modelled for this family (the structure model covers the planar linkages)"))
    else:
        rows += structure_rows(st)
    notes = []
    if out_dir is not None and ok.any():
        chart = write_ellipse_chart(design, out_dir, A, ok)
        if chart:
            notes.append(f"force ellipses over the workspace: {chart}")
    limits = pantograph_limits(design, design.actuators.get("force_max_N"), st and st["strength_MPa"],
                               structure=st is not None)
    crows, climits = capstan_rows(design, k25["value"])  # every capstan: rows at the peak load, the ropes' springs
    rows += crows
    limits.update(climits)
    rows += mode_blocker(design, report, st, limits)
    return rows, limits, notes


def mode_blocker(design, report: dict, st: dict | None, limits: dict) -> list[dict]:
    """When a planar family's first mode misses its limit: the ``first_mode_reachable_Hz``
    row (:func:`cad.families.pantograph.mode_ceiling.mode_ceiling`: what limits the mode and
    the best figure the link tubes reach in this layout) and the same line in the limit's
    keys to change (so the datasheet warning and ``hapticad check`` say it); none otherwise."""
    lim = limits.get("first_mode_Hz")
    if st is None or lim is None or lim.met(st["first_mode_Hz"]):
        return []
    web = (report.get("layout_mm") or {}).get("web_width_mm", WEB_WIDTH_MIN_MM)
    c = mode_ceiling(design, report["bodies"], web, lim.value)
    limits["first_mode_Hz"] = dataclasses.replace(lim, change=f"{lim.change}; {c['text']}")
    return [row("first_mode_reachable_Hz", "best first mode the link tubes reach in this layout",
                c["best"]["first_mode_Hz"], "Hz", c["text"], boundary=HELD)]


def footprint_rows(report: dict) -> list[dict]:
    """The footprint row of a pantograph-family build (the pen too): the base plate's outline
    on the bench, from the layout (``layout_mm`` of the 5-bar and the mouse, ``ground_mm`` of
    the pen: ``base_plate_x_mm``, ``base_plate_y_mm``, world frame, mm); none without it."""
    for src in (report.get("layout_mm") or {}, report.get("ground_mm") or {}):
        if "base_plate_x_mm" in src and "base_plate_y_mm" in src:
            (x0, x1), (y0, y1) = src["base_plate_x_mm"], src["base_plate_y_mm"]
            return [row("footprint_mm2", f"footprint (base plate {x1 - x0:.0f} x {y1 - y0:.0f} mm)",
                        (x1 - x0) * (y1 - y0), "mm^2", "base plate outline")]
    return []
