"""The wall example sketch (Arduino / Teensy style) and the CHAI3D-style device description.

Wall numbers: eq (25) of the Hoeken paper, 2 Fv/Te <= K <= 2 (Fs + Fv xdot_max) /
(Delta + xdot_max Te), with the design's ``[stiffness]`` table (four-bars). A design without
one (the pantograph families) gets eq (25) with the Hoeken paper's identified Fv, Fs, Te and
xdot_max (§III.B.4), marked unverified for this device, and Delta = the largest handle step
of one encoder count at home. The sketch's wall stiffness is eq (25)'s K_max unless
``[firmware] wall_stiffness_N_per_m`` says otherwise; its damping is
``wall_damping_N_s_per_m`` or the largest passive one at that K (Colgate and Schenkel,
``cad.sim.wall.passivity_K_max``: B < Fv - K Te / 2, floored at 0).
"""

from __future__ import annotations

import json
import math

import numpy as np

from cad.actuators.capstan import series_stiffness
from cad.dynamics.stiffness import StiffnessInputs, range_text, stiffness_range_N_per_m
from cad.firmware import reference as ref
from cad.firmware.csrc import banner
from cad.firmware.spec import DeviceSpec

#: Hoeken paper §III.B.4 (eq 25 inputs identified on the prototype, Fig. 10).
PAPER_EQ25 = {"Fv_N_s_per_m": 0.12, "Fs_N": 0.083, "Te_s": 0.00033, "xdot_max_m_per_s": 0.04}


def encoder_step_m(spec: DeviceSpec) -> float:
    """Largest handle displacement of one encoder count at home (m): max_j |J[:, j]| 2 pi / counts
    (J: the translational rows, :attr:`cad.firmware.model.KinematicModel.n_translation`, its
    columns divided by each joint's transmission ratio: the encoder turns with the motor)."""
    J = ref.jacobian(spec, np.asarray(spec.q_home_rad)[None, :])[0][: spec.model.n_translation] / spec.gear_of()
    return float(np.max(np.linalg.norm(J, axis=0))) * 2 * math.pi / spec.encoder_counts_per_rev


def paper_eq25_inputs(step_m: float) -> StiffnessInputs:
    """Eq (25)'s inputs of a device with no ``[stiffness]`` table: the Hoeken paper's Fv, Fs, Te,
    xdot_max (§III.B.4, identified on its prototype: unverified for another device) and
    ``step_m`` (m) as Delta. The datasheet's K_max row of such a device and its firmware's
    wall use these same inputs (one K_max figure)."""
    return StiffnessInputs(PAPER_EQ25["Fv_N_s_per_m"], PAPER_EQ25["Fs_N"], PAPER_EQ25["Te_s"],
                           step_m, PAPER_EQ25["xdot_max_m_per_s"])


def wall_numbers(spec: DeviceSpec, design, step_m: float | None = None,
                 eq25_row: dict | None = None) -> dict:
    """K, B of the sketch's wall and the eq (25) range they come from (module docstring).
    ``eq25_row``: the datasheet's ``eq25_K_max_N_per_m`` row with its ``inputs`` (the one
    K_max figure of the build: the wall reads it); else ``step_m``: Delta (m), the datasheet's
    position resolution (worst over the workspace), or None: one encoder count at home
    (:func:`encoder_step_m`)."""
    if eq25_row is not None and eq25_row.get("value") is not None and "inputs" in eq25_row:
        return _wall_from_row(spec, design, eq25_row)
    st = getattr(design, "stiffness", None)
    if st is not None:
        inputs, source = st, "eq (25) with the design's [stiffness] table"
    else:
        where = ("the datasheet's resolution_um (worst over the workspace)" if step_m is not None
                 else "one encoder count at home")
        inputs = paper_eq25_inputs(step_m if step_m is not None else encoder_step_m(spec))
        source = ("eq (25) with the Hoeken paper's Fv, Fs, Te, xdot_max (§III.B.4; unverified for "
                  f"this device) and Delta = {where}")
    k_min, k_max = stiffness_range_N_per_m(inputs)
    opts = design.firmware
    K = opts.wall_stiffness_N_per_m or k_max
    what = ("[firmware] wall_stiffness_N_per_m" if opts.wall_stiffness_N_per_m else
            f"eq (25)'s K_max (a conservative bound, not the datasheet's simulated K_max) with "
            f"Delta = {inputs.encoder_resolution_m:.4g} m; the device's encoder: "
            f"{spec.encoder_counts_per_rev} counts/rev")
    B = opts.wall_damping_N_s_per_m
    if B is None:
        B = max(0.0, inputs.Fv_N_s_per_m - K * inputs.Te_s / 2)
    return {"K_N_per_m": K, "B_N_s_per_m": B, "eq25_K_min_N_per_m": k_min,
            "eq25_K_max_N_per_m": k_max, "Te_s": inputs.Te_s, "Fv_N_s_per_m": inputs.Fv_N_s_per_m,
            "encoder_step_m": inputs.encoder_resolution_m, "source": source, "K_is": what}


def _wall_from_row(spec: DeviceSpec, design, r: dict) -> dict:
    """:func:`wall_numbers` from the datasheet's eq (25) row: K = its value (unless
    ``[firmware] wall_stiffness_N_per_m``), B = max(0, Fv - K Te / 2) from its inputs."""
    i, opts = r["inputs"], design.firmware
    k_max = float(r["value"])
    k_min = 2 * i["Fv_N_s_per_m"] / i["Te_s"]
    K = opts.wall_stiffness_N_per_m or k_max
    what = ("[firmware] wall_stiffness_N_per_m" if opts.wall_stiffness_N_per_m else
            "eq (25)'s K_max, the datasheet's eq25_K_max_N_per_m (a conservative bound, not the "
            f"datasheet's simulated K_max) with Delta = {i['encoder_resolution_m']:.4g} m; the "
            f"device's encoder: {spec.encoder_counts_per_rev} counts/rev")
    B = opts.wall_damping_N_s_per_m
    if B is None:
        B = max(0.0, i["Fv_N_s_per_m"] - K * i["Te_s"] / 2)
    return {"K_N_per_m": K, "B_N_s_per_m": B, "eq25_K_min_N_per_m": k_min,
            "eq25_K_max_N_per_m": k_max, "Te_s": i["Te_s"], "Fv_N_s_per_m": i["Fv_N_s_per_m"],
            "encoder_step_m": i["encoder_resolution_m"], "source": "the datasheet's eq25_K_max_N_per_m: " + r["model"],
            "K_is": what}


def max_forces_N(spec: DeviceSpec, q_ok: np.ndarray) -> dict:
    """Force the motors give in every direction at every test pose (continuous / peak torque):
    min over poses of tau / sigma_max(J^T) for the translational rows, J's columns divided by
    each joint's transmission ratio n (the motor's torque is n times larger at its joint)."""
    fj = spec.model.force_jacobian
    J = fj(spec, q_ok) if fj is not None else ref.jacobian(spec, q_ok)[:, : spec.model.n_translation, :]
    if spec.gear:
        J = J / spec.gear_of()[None, None, :]
    smax = np.linalg.svd(J, compute_uv=False)[:, 0]
    m = spec.motor
    return {"continuous_N": float(np.min(m.torque_continuous_Nm / smax)),
            "peak_N": float(np.min(m.torque_peak_Nm / smax))}


#: The datasheet rows of the capstans' ropes' stiffness where the force is felt (N/m; one per
#: family: the handle of a four-bar, a 5-bar, the twin or the pen, the delta's effector), present
#: when a capstan is (:mod:`cad.datasheet.capstan_rows` and each family's capstan module).
ROPE_STIFFNESS_KEYS = ("cable_handle_stiffness_N_per_m", "cable_effector_stiffness_N_per_m")


def rope_row(report: dict) -> dict | None:
    """The report's datasheet row of the ropes' stiffness at the handle (:data:`ROPE_STIFFNESS_KEYS`)
    with a value, or None (direct drive)."""
    rows = {r.get("key"): r for r in (report.get("datasheet") or {}).get("rows", [])}
    return next((rows[k] for k in ROPE_STIFFNESS_KEYS if rows.get(k, {}).get("value") is not None), None)


def chai3d_stiffness(wall: dict, rope: dict | None) -> tuple[float, str]:
    """``(N/m, note)``: the CHAI3D file's ``m_maxLinearStiffness``: eq (25)'s K_max (``wall``,
    :func:`wall_numbers`, the conservative bound the wall sketch renders) and, with a capstan, in
    series with the ropes' stiffness at the handle (``rope``, :func:`rope_row`): 1 / (1 / K_max
    + 1 / k_rope) (:func:`cad.actuators.capstan.series_stiffness`) -- the datasheet's renderable
    stiffness with the ropes in series (``K_max_with_cable_N_per_m`` of the 5-bar, the twin, the
    delta; the four-bar's ``eq25_K_max_with_cable_N_per_m``, its ``K_max_with_cable_N_per_m`` puts
    the simulated K_max in series)."""
    K = wall["eq25_K_max_N_per_m"]
    note = "eq (25) K_max, the conservative bound (not the datasheet's simulated K_max): " + wall["source"]
    if rope is None:
        return K, note
    return float(series_stiffness(K, rope["value"])), (
        f"1 / (1 / K_max + 1 / k_rope), renderable stiffness with the ropes in series: the {note}; k_rope = "
        f"the datasheet's {rope['key']} {rope['value']:.4g} N/m")


def chai3d_json(spec: DeviceSpec, design, wall: dict, forces: dict, rope: dict | None = None) -> str:
    """CHAI3D-style device description (cHapticDeviceInfo fields, SI); ``rope``: the datasheet's
    row of the ropes' stiffness at the handle when a capstan is present (:func:`chai3d_stiffness`)."""
    K, K_note = chai3d_stiffness(wall, rope)
    doc = {
        "generator": f"hapticad {spec.version}", "design": spec.name,
        "design_hash": spec.design_hash, "units": "SI",
        "m_modelName": f"hapticad {spec.family} '{spec.name}'", "m_manufacturerName": "hapticad",
        "m_maxLinearForce": forces["continuous_N"],
        "m_maxLinearForce_peak": forces["peak_N"],
        "m_maxLinearStiffness": K,
        "encoder_counts_per_rev": spec.encoder_counts_per_rev,
        "m_maxLinearDamping": wall["Fv_N_s_per_m"],
        "m_workspaceRadius": spec.model.workspace_radius_m(spec, design),
        "m_sensedRotation": spec.model.senses_rotation,
        "m_actuatedRotation": spec.model.senses_rotation,
        "notes": {
            "m_maxLinearForce": forces.get("source", "min over the test poses of the continuous motor "
                                "torque / sigma_max(J^T) (every direction)") + "; _peak: the same at peak torque",
            "m_maxLinearStiffness": K_note,
            "encoder_counts_per_rev": "the device's encoder (report.json device.encoders), "
                                      "the count hapticad_device.h is compiled for",
            "m_maxLinearDamping": "passivity at K -> 0 (Colgate and Schenkel): B < Fv; Fv from "
                                  + wall["source"],
            "m_workspaceRadius": spec.model.workspace_note or (
                "the largest circle enclosed in the workspace (CHAI3D cHapticDeviceInfo::"
                "m_workspaceRadius): four-bar: half the stroke; pantographs: half the shorter "
                "workspace side"),
            "frame": "the device frame of hapticad_device.h (m)",
        },
    }
    if spec.gear:
        doc["transmission_ratio"] = list(spec.gear)
        doc["notes"]["transmission_ratio"] = ("each joint's motor through its capstan (report.json "
                                              "device.transmissions): joint torque = n motor torque, "
                                              "counts per joint turn = n encoder_counts_per_rev")
    return json.dumps(doc, indent=2, sort_keys=True) + "\n"


def sketch(spec: DeviceSpec, wall: dict) -> str:
    """``wall_example.ino``: read encoders, render a wall through the home position (module
    docstring of the sketch), write motor currents; board I/O is left to three stubs."""
    qh = np.asarray(spec.q_home_rad)[None, :]
    X0, _ = ref.forward(spec, qh)
    wn = spec.model.wall_normal
    n = wn(spec, qh) if wn is not None else np.array([1.0, 0.0])
    n = n / np.linalg.norm(n)
    nj, nt = spec.n_joints, spec.n_task
    return banner(spec, "wall_example.ino: a virtual wall (Arduino / Teensy style)") + f"""
/* The wall: through the home position WALL_X0_M, normal WALL_N (device frame; four-bar: the
 * direction of motion at home, pantographs: +x); with the penetration s = N . (X - X0) > 0
 * the handle feels F = -(K s + B s_dot) N. K and B: {wall['source']};
 * WALL_K_N_PER_M is {wall['K_is']};
 * {range_text(wall['eq25_K_min_N_per_m'], wall['eq25_K_max_N_per_m'])} at Te = {wall['Te_s']:g} s.
 * Run the loop every SAMPLE_PERIOD_US (the Te of eq 25); a slower loop needs a smaller K.
 * Copy hapticad_device.h / hapticad_device.c beside this sketch; on an 8-bit AVR define
 * HAPTICAD_USE_FLOAT (double is float there anyway), on a Teensy 4 keep double. */
#include "hapticad_device.h"

#define WALL_K_N_PER_M {wall['K_N_per_m']!r}
#define WALL_B_N_S_PER_M {wall['B_N_s_per_m']!r}
#define WALL_X0_M {float(X0[0, 0])!r}
#define WALL_Y0_M {float(X0[0, 1])!r}
#define WALL_NX {float(n[0])!r}
#define WALL_NY {float(n[1])!r}
#define SAMPLE_PERIOD_US {int(round(wall['Te_s'] * 1e6))}

static hc_encoder_t enc = HC_ENCODER_DEFAULT;
static hc_real s_prev = 0;
static int have_prev = 0;                          /* s_prev holds a valid sample */

/* board specific: replace these three with your encoder and amplifier code (or define
 * HC_SKETCH_IO and give them before including this file, as hapticad's test does) */
#ifndef HC_SKETCH_IO
static void read_encoders(long counts[HC_N_JOINTS]) {{ for (int i = 0; i < HC_N_JOINTS; ++i) counts[i] = 0; }}
static void write_currents(const hc_real amps[HC_N_JOINTS]) {{ (void)amps; }}
static void motors_off(void) {{ }}
#endif

void setup() {{ motors_off(); }}

void loop() {{
    static unsigned long next = 0;
    long counts[HC_N_JOINTS];
    hc_real q[HC_N_JOINTS], X[HC_N_TASK], F[HC_N_TASK] = {{0}}, tau[HC_N_JOINTS], tg[HC_N_JOINTS];
    hc_real amps[HC_N_JOINTS];
    while ((long)(micros() - next) < 0) {{ }}
    next += SAMPLE_PERIOD_US;
    read_encoders(counts);
    hc_counts_to_angles(&enc, counts, q);
    if (hc_forward(q, X) != HC_OK) {{ have_prev = 0; motors_off(); return; }}   /* outside the range: no force */
    hc_real s = WALL_NX * (X[0] - WALL_X0_M) + WALL_NY * (X[1] - WALL_Y0_M);
    /* no velocity from a sample before power-up or a refused pose (no damping spike) */
    hc_real v = have_prev ? (s - s_prev) / (SAMPLE_PERIOD_US * 1e-6) : 0;
    s_prev = s;
    have_prev = 1;
    if (s > 0) {{
        hc_real f = -(WALL_K_N_PER_M * s + WALL_B_N_S_PER_M * v);
        if (f > 0) f = 0;                          /* a wall pushes, never pulls */
        F[0] = f * WALL_NX; F[1] = f * WALL_NY;
    }}
    hc_joint_torques(q, F, tau);
    hc_gravity_torques(q, tg);                     /* zero for a horizontal device */
    for (int i = 0; i < HC_N_JOINTS; ++i) tau[i] += tg[i];
    hc_motor_currents(tau, HC_LIMIT_CONTINUOUS, amps);   /* HC_LIMIT_PEAK for short bursts */
    write_currents(amps);
}}
/* {nj} motor(s), {nt} task coordinates */
"""
