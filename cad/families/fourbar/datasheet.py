"""Datasheet rows of a four-bar (Hoeken, Roberts, Chebyshev, Chebyshev-V, custom).

Kinematics over the stroke (``SAMPLES`` crank angles, path frame x along P(phi1_min) ->
P(phi1_max)): the lever ``Jx = dx/dphi1`` (m/rad, Hoeken paper eq 12 in the path frame).

* **force at the handle** along the path: F = tau / |Jx| for the motor's continuous torque
  (maxon "nominal torque (max. continuous torque)") and its peak torque
  (:class:`cad.data.catalog.MotorSpec`); the value is the minimum over the stroke;
  force per ampere Kt / |Jx|;
* **thermal duty**: the winding temperature rise holding ``force_N`` at the weakest point,
  dT = I^2 R (Rth_winding + Rth_housing), I = tau / Kt, R at 25 C (no hot-resistance
  correction); the force at :data:`DUTY` duty cycle, F_cont / sqrt(duty) capped at the peak
  (on-time much shorter than the winding's thermal time constant, tens of s for these motors);
* **resolution**: (2 pi / counts) |Jx|, counts of the resolved device's encoder
  (:mod:`cad.device`: ``parts.encoder``, ``parts.encoder_counts_per_rev``, ``[firmware]
  encoder_counts_per_rev``, the ``[stiffness]`` encoder step rounded to whole counts, or
  :data:`catalog.DEFAULT_ENCODER`), the encoder the BOM orders;
* **Coulomb friction at the handle** (virtual work): the motor's brush and bearing friction
  Kt I0 (no-load current) / |Jx|, plus, while the handle pushes ``force_N``, each joint
  bearing's SKF simplified frictional moment M = 0.5 mu F d (:data:`SKF_MU`, F its radial load
  from rigid-link statics, :func:`cad.structure.bearings.joint_forces_per_N`, d its bore) times
  its relative rotation per crank radian (A2 |a2 - 1|, A3 |a3 - a2|, A4 |a3|) / |Jx|;
* **renderable stiffness**: eq (25) (Hoeken paper, after Diolaiti et al.), the passivity bound
  2 Fv / Te (Colgate and Schenkel) and ``K_max`` of the reduced-model wall simulation
  (:mod:`cad.sim.wall`) at the design's loop period and encoder;
* apparent mass, structure (with its boundary conditions), masses, footprint from the report.
"""

from __future__ import annotations

import math

import numpy as np

from cad.data import catalog
from cad.datasheet import clearance_parts, row
from cad.datasheet.limits import Limit
from cad.device import resolve_device
from cad.dynamics.inertia import InertiaCoefficients
from cad.families.fourbar import capstan
from cad.families.fourbar.limits import FORCE_CHANGE, PAPER_FS_N, fourbar_limits
from cad.io import derived_cache
from cad.kinematics.fourbar import jacobian_mm_per_rad, solve, velocity_ratios
from cad.kinematics.metrics import path_frame
from cad.sim import wall
from cad.structure.bearings import joint_forces_per_N

SAMPLES = 401
#: Duty cycle of the duty-cycle force row.
DUTY = 0.25
#: Winding temperature rise allowed by the RE 35 / RE 40 data (max. winding temperature
#: +125 C, ambient 25 C), K: the row's default limit (:func:`thermal_limit`).
WINDING_RISE_MAX_K = 100.0
#: SKF simplified frictional moment M = 0.5 mu P d, constant coefficient of friction of an
#: open deep groove ball bearing (SKF Rolling bearings catalogue, "Friction": estimating
#: the frictional moment, mu = 0.0015 for deep groove ball bearings; valid at P ~ 0.1 C,
#: good lubrication; seals and lubricant drag not included).
SKF_MU = 0.0015
#: Loop period and the velocity of eq (25) when the design has no [stiffness] table: the
#: Hoeken prototype's values (paper §III.B.4: Te = 0.33 ms, xdot_max = 0.04 m/s).
TE_DEFAULT_S = 0.33e-3
XDOT_DEFAULT_M_PER_S = 0.04
PAPER_CONT_FORCE_N = 3.3


def lever(design, samples: int = SAMPLES, phi=None):
    """(phi1 rad, Jx m/rad signed, pose, a2, a3) over the stroke (path frame x), at ``samples``
    evenly spaced crank angles or at the crank angles ``phi`` (rad)."""
    fb = design.linkage
    phi = (np.linspace(design.phi1_min_rad, design.phi1_max_rad, samples) if phi is None
           else np.atleast_1d(np.asarray(phi, float)))
    pose = solve(fb, phi)
    fr = path_frame(fb, design.phi1_min_rad, design.phi1_max_rad)
    Jx = fr.rotate(jacobian_mm_per_rad(fb, pose))[:, 0] * 1e-3
    a2, a3 = velocity_ratios(fb, pose)
    return phi, Jx, pose, a2, a3


def _label(m) -> str:
    """The motor's name in a row: the catalog key, or the ``[motor]`` name / data it carries."""
    if "(data of [motor]" in m.description:
        return m.winding
    if any("[motor]" in src for _, src in m.sources):
        return f"{m.key} with the [motor] data"
    return m.key


def _motor_src(m, *fields) -> tuple[str, bool]:
    src = "; ".join(f"{f}: {m.source_of(f)}" for f in fields)
    return f"{m.winding or m.key} ({src})", any(m.is_unverified(f) for f in fields)


def force_rows(design, m, Jx) -> list[dict]:
    L = np.abs(Jx)
    out = []
    for key, fig, f in (("continuous_force_N", "continuous force at the handle", "torque_continuous_mNm"),
                        ("peak_force_N", "peak force at the handle", "torque_peak_mNm")):
        tau = getattr(m, f)
        src, unv = _motor_src(m, f)
        if tau is None:
            out.append(row(key, fig, None, "N", f"no {f} for {_label(m)}", unverified=True))
            continue
        F = tau * 1e-3 / L
        paper = (f"{PAPER_CONT_FORCE_N:g} N (Hoeken paper §III.A, its RE 35 winding)"
                 if key == "continuous_force_N" and design.family == "hoeken" else None)
        out.append(row(key, fig, F.min(), "N", f"{tau:g} mN m / |dx/dphi1|, minimum over the stroke; {src}",
                       lo=F.min(), hi=F.max(), unverified=unv, paper=paper))
    if m.torque_constant_mNm_per_A is not None:
        k = m.torque_constant_mNm_per_A * 1e-3 / L
        src, unv = _motor_src(m, "torque_constant_mNm_per_A")
        out.append(row("force_per_ampere_N_per_A", "force per ampere", k.min(), "N/A",
                       f"Kt / |dx/dphi1|; {src}", lo=k.min(), hi=k.max(), unverified=unv))
    return out


def thermal_rows(design, m, Jx) -> list[dict]:
    L = float(np.abs(Jx).max())  # the weakest point needs the most torque
    need = ("torque_constant_mNm_per_A", "terminal_resistance_ohm", "thermal_resistance_housing_K_per_W",
            "thermal_resistance_winding_K_per_W")
    out = []
    if all(getattr(m, f) is not None for f in need):
        I_A = design.force_N * L / (m.torque_constant_mNm_per_A * 1e-3)
        rth = m.thermal_resistance_housing_K_per_W + m.thermal_resistance_winding_K_per_W
        dT = I_A * I_A * m.terminal_resistance_ohm * rth
        src, unv = _motor_src(m, *need)
        out.append(row("winding_rise_at_force_K", f"winding temperature rise holding force_N = {design.force_N:g} N",
                       dT, "K", f"I^2 R (Rth_winding + Rth_housing), I = {I_A:.3g} A at the weakest point, R at 25 C, "
                       f"steady state (the data sheets allow {WINDING_RISE_MAX_K:g} K: 125 C winding, 25 C ambient); {src}",
                       unverified=unv))
    else:
        out.append(row("winding_rise_at_force_K", "winding temperature rise holding force_N", None, "K",
                       f"not computed: {_label(m)} has no {', '.join(f for f in need if getattr(m, f) is None)}",
                       unverified=True))
    if m.torque_continuous_mNm is not None and m.torque_peak_mNm is not None:
        F = min(m.torque_continuous_mNm / math.sqrt(DUTY), m.torque_peak_mNm) * 1e-3 / L
        src, unv = _motor_src(m, "torque_continuous_mNm", "torque_peak_mNm")
        out.append(row("duty_force_N", f"force at {DUTY:.0%} duty cycle", F, "N",
                       f"min(T_cont / sqrt({DUTY:g}), T_peak) / |dx/dphi1| at the weakest point: RMS torque = "
                       f"continuous torque, on-time << winding thermal time constant; {src}", unverified=unv))
    return out


def encoder_counts(design, Jx=None) -> tuple[int, str, str | None]:
    """(counts per crank turn, where from, catalog key or None): the resolved device's encoder
    (:func:`cad.device.resolve_device`), the one the BOM orders and the firmware is compiled
    for. ``Jx`` is not used (kept for callers)."""
    e = resolve_device(design).encoder
    return e.counts_per_rev, e.source, e.catalog_key


def resolution_row(design, Jx) -> dict:
    counts, src, _ = encoder_counts(design, Jx)
    n = resolve_device(design).transmission("crank").ratio
    r = 2 * math.pi / (counts * n) * np.abs(Jx) * 1e6
    via = "" if n == 1.0 else f" / n = {n:.4g} (capstan: the encoder turns n times per crank turn)"
    return row("resolution_um", "position resolution at the handle", r.max(), "um",
               f"(2 pi / {counts} counts{via}) |dx/dphi1|, worst over the stroke; {src}", lo=r.min(), hi=r.max())


def friction(design, m, Jx, pose, a2, a3) -> tuple[np.ndarray | None, np.ndarray]:
    """(motor friction at the handle N or None, bearing friction at the handle N at force_N)."""
    fb = design.linkage
    L = np.abs(Jx)
    ex = path_frame(fb, design.phi1_min_rad, design.phi1_max_rad).x_hat
    r = joint_forces_per_N(fb, pose.phi1_rad, ex)
    d = catalog.get_bearing(design.parts.bearing).d_mm * 1e-3
    w = {"A2": np.abs(a2 - 1.0), "A3": np.abs(a3 - a2), "A4": np.abs(a3)}
    Mb = sum(0.5 * SKF_MU * design.force_N * r[j] * d * w[j] for j in w)
    tm = m.friction_torque_mNm()
    return (None if tm is None else tm * 1e-3 / L), Mb / L


def friction_rows(design, m, Jx, pose, a2, a3) -> list[dict]:
    Fm, Fb = friction(design, m, Jx, pose, a2, a3)
    src, unv = _motor_src(m, "torque_constant_mNm_per_A", "no_load_current_mA")
    paper = (f"{PAPER_FS_N:g} N measured (Hoeken paper eq 24, Fig. 10)" if design.family == "hoeken" else None)
    out = []
    if Fm is None:
        out.append(row("friction_N", "Coulomb friction at the handle (no load)", None, "N",
                       f"not computed: {_label(m)} has no torque constant or no-load current", unverified=True, paper=paper))
        Fm = np.zeros_like(Fb)
    else:
        out.append(row("friction_N", "Coulomb friction at the handle (no load)", Fm.max(), "N",
                       f"motor brushes and bearings Kt I0 / |dx/dphi1| (no-load current at no-load speed taken "
                       f"as Coulomb); joint bearings add nothing without load in the SKF simplified model; {src}",
                       lo=Fm.min(), hi=Fm.max(), unverified=unv, paper=paper))
    tot = Fm + Fb
    out.append(row("friction_loaded_N", f"Coulomb friction at the handle pushing force_N = {design.force_N:g} N",
                   tot.max(), "N", f"motor friction + SKF simplified bearing moment 0.5 mu F d, mu = {SKF_MU:g} "
                   f"(open deep groove ball bearings {design.parts.bearing}), joint loads by rigid-link statics, "
                   "relative joint rotation per crank radian / |dx/dphi1|", lo=tot.min(), hi=tot.max(), unverified=unv))
    return out


def stiffness_inputs(design, Jx, friction_N: float | None) -> tuple[dict, str]:
    """(Fv, Fs, Te, Delta, xdot, counts) for eq (25) and the wall, and where they come from."""
    counts, src, _ = encoder_counts(design, Jx)
    counts = resolve_device(design).joint_counts_per_rev("crank")  # per crank turn (x n through a capstan)
    J_mid = abs(float(Jx[len(Jx) // 2]))
    st = design.stiffness
    if st is not None:
        return ({"Fv": st.Fv_N_s_per_m, "Fs": st.Fs_N, "Te": st.Te_s, "delta": st.encoder_resolution_m,
                 "xdot": st.xdot_max_m_per_s, "counts": 2 * math.pi * J_mid / st.encoder_resolution_m},
                "[stiffness] table (Fv, Fs, Te, Delta, xdot_max)")
    return ({"Fv": 0.0, "Fs": friction_N or 0.0, "Te": TE_DEFAULT_S, "delta": 2 * math.pi * J_mid / counts,
             "xdot": XDOT_DEFAULT_M_PER_S, "counts": counts},
            f"no [stiffness] table: Fs = the friction estimate at no load, Fv = 0 (no viscous data), "
            f"Te = {TE_DEFAULT_S:g} s and xdot_max = {XDOT_DEFAULT_M_PER_S:g} m/s (Hoeken paper §III.B.4), encoder {src}")


def eq25_inputs(s: dict) -> dict:
    """Eq (25)'s inputs of :func:`stiffness_inputs` under the names of
    :class:`cad.dynamics.stiffness.StiffnessInputs` (SI): the datasheet row carries them, and
    the firmware's wall reads them there (one K_max figure)."""
    return {"Fv_N_s_per_m": s["Fv"], "Fs_N": s["Fs"], "Te_s": s["Te"],
            "encoder_resolution_m": s["delta"], "xdot_max_m_per_s": s["xdot"]}


def eq25_K_max(s: dict) -> float:
    """Hoeken paper eq (25) upper bound, N/m (Fv may be 0)."""
    return 2.0 * (s["Fs"] + s["Fv"] * s["xdot"]) / (s["delta"] + s["xdot"] * s["Te"])


def simulated_K_max(design, report: dict, s: dict, tau_max_Nm: float) -> dict:
    """K_max of the reduced-model wall (B = 0) with the report's H: ``{"K": N/m or None (unstable
    at K_lo), "err": relative sampling error or None, "band": [first unstable, last stable]
    probe N/m}`` (:func:`cad.sim.wall.k_max_estimate`)."""
    H = InertiaCoefficients(report["H11_kg_m2"], report["H12_kg_m2"], report["H22_kg_m2"],
                            report["H33_kg_m2"], math.radians(report.get("beta2_deg", 0.0)))
    spec = wall.WallSpec(s["Te"], s["counts"], s["Fv"], s["Fs"], tau_max_Nm, s["xdot"])

    def make():
        tab = wall.device_tables(design, H)
        r = wall.k_max_estimate(wall.reduced_stable_of(tab, spec, 0.0))
        return {"K": r["K_max_N_per_m"], "err": r["sampling_error_rel"],
                "band": [r["K_first_unstable_N_per_m"], r["K_last_stable_N_per_m"]]}


    # a few seconds of simulation: through the derived cache (same linkage, H and spec: a hit)
    key = [design.resolved_linkage(), H.as_dict(), [spec.Te_s, spec.counts_per_rev, spec.Fv_N_s_per_m,
           spec.Fs_N, spec.tau_max_Nm, spec.v0_m_per_s]]
    return derived_cache.cached_json("datasheet-kmax", key, make, code=("cad.sim.wall", "cad.tolerances"))


def stiffness_rows(design, report, m, Jx, friction_N, simulate: bool = True) -> list[dict]:
    s, src = stiffness_inputs(design, Jx, friction_N)
    out = [row("eq25_K_max_N_per_m", "renderable stiffness, eq (25) bound", eq25_K_max(s), "N/m",
               f"Hoeken paper eq (25) (Diolaiti et al.): 2 (Fs + Fv xdot_max) / (Delta + xdot_max Te), a "
               f"conservative bound; {src}", inputs=eq25_inputs(s)),
           row("passivity_K_max_N_per_m", "renderable stiffness, passivity bound", 2 * s["Fv"] / s["Te"], "N/m",
               f"Colgate and Schenkel: passive iff K < 2 Fv / Te (viscous friction only, Coulomb ignored); {src}")]

    km = {"K": None, "err": None, "band": [None, None]}
    if simulate and m.torque_peak_mNm is not None and all(k in report for k in ("H11_kg_m2", "H12_kg_m2")):
        km = simulated_K_max(design, report, s, m.torque_peak_mNm * 1e-3)
    err = "" if km["err"] is None else (
        f"; K_max is the threshold best separating stable from unstable walls on a {wall.K_GRID_STEP:.2%} K grid "
        f"(stability is intermittent from {km['band'][0]:.4g} to {km['band'][1]:.4g} N/m), sampling error "
        f"+/-{km['err']:.1%} (95 % bootstrap + grid step)")

    skipped = "" if simulate else ("not simulated in this build (a fabrication build and `hapticad datasheet` "
                                   "give it): ")
    out.append(row("K_max_N_per_m", "renderable stiffness, simulated K_max", km["K"], "N/m",
                   f"{skipped}largest stable virtual wall (B = 0) of the reduced 1-DOF model (sampled, quantized encoder, "
                   f"Coulomb + viscous friction, motor saturation; `hapticad wall`), Te = {s['Te']:g} s, "
                   f"{s['counts']:.5g} counts per crank turn, Fs = {s['Fs']:.3g} N; stable = contact oscillation "
                   f"< {wall.AMPLITUDE_COUNTS:g} encoder steps{err}; {src}",
                   paper="15000 N/m measured (Hoeken paper §III.B.4)" if design.family == "hoeken" else None))
    out[-1]["sampling_error_rel"] = km["err"]
    return out


def structure_rows(design, st: dict | None) -> list[dict]:
    if not st:
        return []
    held = "crank held at A1 (motor shaft locked by the servo), rocker pinned at A4, joints rigid"
    out = [row("first_mode_Hz", "first structural mode", st["first_mode_Hz"], "Hz",
               f"{st['method']} frame of the moving links with their parts' masses, lowest mode over "
               f"{st['poses']} poses", boundary=f"{held}; handle free",
               paper="250 Hz measured resonance (Hoeken paper §III.B.1)" if design.family == "hoeken" else None)]
    if "handle_mode_x_Hz" in st:
        out.append(row("handle_mode_x_Hz", "handle mode along the path", st["handle_mode_x_Hz"], "Hz",
                       "the frame mode contributing most to the handle's static compliance along x "
                       "(largest phi_Px^2 / w^2), lowest over the poses", boundary=f"{held}; handle free"))
    cx, cz = st["compliance_um_per_N"]["x"], st["compliance_um_per_N"]["z"]
    out += [row("compliance_x_um_per_N", "handle compliance along the path", cx, "um/N",
                f"{st['method']} frame, worst pose; bearing radial compliance not included (estimate "
                f"{st.get('bearing_compliance_estimate', {}).get('x_um_per_N', float('nan')):.3g} um/N, Palmgren)",
                boundary=f"{held}; force at the handle"),
            row("compliance_z_um_per_N", "handle compliance out of plane", cz, "um/N",
                f"{st['method']} frame, worst pose", boundary=f"{held}; force at the handle"),
            row("max_stress_MPa", f"peak stress at force_N = {design.force_N:g} N", st["max_stress_MPa"], "MPa",
                f"von Mises, beam stresses, worst pose and direction; material strength {st['strength_MPa']:g} MPa",
                boundary=f"{held}; force at the handle")]
    return out


def mass_rows(report) -> list[dict]:
    am = report.get("apparent_mass") or {}
    links = report.get("links") or {}
    moving = sum(float(v.get("mass_kg", 0.0)) for k, v in links.items() if k in ("crank", "coupler", "rocker")) * 1e3
    out = []
    if "M11_max_g" in am:
        out.append(row("M11_g", "apparent mass along the path", am["M11_max_g"], "g",
                       "eq (22) M11 from the solids' mass properties and the rotor inertia Jm, path frame",
                       lo=am["M11_min_g"], hi=am["M11_max_g"], boundary="crank free (motor unpowered), handle free",
                       paper="27.5 .. 42.8 g CAD values, < 50 g measured (Hoeken paper §III.B.2)"))
    out.append(row("moving_mass_g", "moving mass (crank, coupler, rocker with their parts)", moving, "g",
                   "sum of the moving links' parts from the solids (motor rotor excluded)"))
    if "total_mass_g" in report:
        out.append(row("total_mass_g", "total mass", report["total_mass_g"], "g", "BOM: made parts from the "
                       "solids, bought parts from their catalog masses"))
    if report.get("base_plate_mm"):
        x0, y0, x1, y1 = report["base_plate_mm"]
        out.append(row("footprint_mm2", f"footprint (base plate {x1 - x0:.0f} x {y1 - y0:.0f} mm)",
                       (x1 - x0) * (y1 - y0), "mm^2", "base plate outline"))
    return out


def rows_and_limits(design, report: dict, out_dir=None, simulate_wall: bool = True):
    """(rows, limits, notes) of a four-bar build report (module docstring)."""
    dev = resolve_device(design)
    m = dev.joint_motor("crank")  # the motor the BOM orders, [motor] applied, seen at the crank (x n)
    phi, Jx, pose, a2, a3 = lever(design)
    rows = [row("stroke_mm", "stroke", report.get("stroke_mm"), "mm", "|P(phi1_max) - P(phi1_min)| (Table I)")]
    rows += force_rows(design, m, Jx) + thermal_rows(design, m, Jx)
    rows.append(resolution_row(design, Jx))
    fr = friction_rows(design, m, Jx, pose, a2, a3)
    rows += fr + mass_rows(report) + structure_rows(design, report.get("structure"))
    if report.get("min_clearance_mm") is not None:
        rows.append(row("min_clearance_mm", "smallest clearance between parts over the motion",
                        report["min_clearance_mm"], "mm", "interference sweep of the build" + clearance_parts(report)))
    rows += stiffness_rows(design, report, m, Jx, fr[0]["value"], simulate_wall)
    eq25 = next((r["value"] for r in rows if r["key"] == "eq25_K_max_N_per_m"), None)
    cap_rows, cap_limits = capstan.datasheet_rows(design, report, phi, Jx, dev, rows[-1]["value"], eq25)
    rows += cap_rows
    st = report.get("structure") or {}
    notes = [f"motor: {m.description}, {m.winding}"]
    if m.unverified:
        notes.append(f"unverified motor data (no public source read): {', '.join(m.unverified)}")
    lim = {**fourbar_limits(design, st.get("strength_MPa")), **cap_limits, **thermal_limit(design, rows)}
    return rows, lim, notes


def thermal_limit(design, rows: list[dict]) -> dict[str, Limit]:
    """The winding-rise limit (:data:`WINDING_RISE_MAX_K`) where the row is computed (the
    motor gives its thermal resistances) and the design holds ``force_N`` continuously."""
    r = next(r for r in rows if r["key"] == "winding_rise_at_force_K")
    if r["value"] is None or design.force_basis == "peak":
        return {}
    lim = {"winding_rise_at_force_K": Limit(
        "<=", WINDING_RISE_MAX_K, "holding force_N continuously must keep the winding below its 125 C "
        "maximum at 25 C ambient (the motor data sheet's thermal data)", FORCE_CHANGE)}
    return lim
