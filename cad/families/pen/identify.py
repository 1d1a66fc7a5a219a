"""The haptic pen's identification (issue 37): six motors (a waist and two shoulders per arm,
RE 40 waists and RE 35 shoulders), five degrees of freedom X = (x, y, z, yaw, pitch) -- the
two arms' ends are held at the pen's length, so the device is over-actuated like the twin
pantograph -- run by the n-motor identification (:mod:`cad.sim.identify_joints`,
:mod:`cad.identify.jointn` with a basis W = dq/dX, :mod:`cad.sim.bench_joints`).

The links enter through Lambda(X) of the solids without rotors
(:func:`cad.families.pen.dynamics.link_mass_matrix_X`, the datasheet's operational mass in
the coordinates X), their inverse dynamics by Euler-Lagrange in X; W = dq/dX by central
differences of the inverse kinematics (:func:`cad.kinematics.haptic_pen.ik`); gravity the
firmware's (:func:`cad.firmware.reference.gravity_torques`: every body's weight); per-motor
torque constants, currents, rotors and friction (the two motor types).

Figures: the apparent mass along x, y, z and the inertia about yaw and pitch at the
workspace centre (pen along +x), friction, gravity loads, generalized offsets, signs. The hand
move: the pen up and to the right (+x and +z together: every joint turns). Virtual bench: the build's MJCF in MuJoCo.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np

import cad
from cad.design import bounds
from cad.device import resolve_device
from cad.errors import DesignError
from cad.families.delta.firmware import props_of
from cad.families.pen.dynamics import link_mass_matrix_X
from cad.families.pen.firmware import PEN, state
from cad.families.pen.layout import body_poses
from cad.firmware import reference
from cad.firmware.device import device_spec
from cad.firmware.model import KinematicModel
from cad.firmware.spec import angles_from_counts, motor_data
from cad.identify import excitation2, jointn
from cad.identify.joint2 import Fit2
from cad.kinematics import haptic_pen as hp
from cad.pipeline import design_hash
from cad.sim import bench_joints, identify_joints
from cad.sim.bench import HAND_FRACTION
from cad.sim.identify_fivebar import TE_S
from cad.sim.identify_kits import joint_kit, routine_files

HAND_MOVE = "up and to the right (+x and +z together)"
#: Above this fraction of a motor's continuous current spent on gravity at home, say so.
GRAVITY_WARN_FRACTION = 0.5
#: The hand move's direction in X (unit, mm).
HAND_DIR = np.array([1.0, 0.0, 1.0, 0.0, 0.0]) / math.sqrt(2.0)
#: Central-difference step of dq/dX through the IK (mm, rad).
IK_STEP = 1e-4
SI = np.array([1e-3, 1e-3, 1e-3, 1.0, 1.0])  # X in mm, rad -> m, rad
MODEL_WORDS = ("W^T s_j Kt_j i_j(t - n Te) = W^T [c_link tau_links(Lambda_solids(X), Euler-Lagrange in X = (x, y, z, "
               "yaw, pitch)) + J_j q_j'' + Tc_j sign(q_j') + b_j q_j' + cg g(q) + T0] (haptic pen, q' = W X', "
               "cad.identify.jointn)")


@dataclass(frozen=True)
class PredictionPen(identify_joints.OverActuated):
    """A haptic pen's predicted figures (module docstring); SI, tuples per motor."""

    name: str
    design_hash: str
    design: object
    spec: object
    props: dict
    rotor_kg_m2: tuple[float, ...]
    Te_s: float
    kt_Nm_per_A: tuple[float, ...]
    i_max_A: tuple[float, ...]
    counts_per_rev: float  # per turn of the coarsest joint: the motor encoder's x n through a capstan
    direction: tuple[int, ...]
    zero_rad: tuple[float, ...]
    q_min_rad: tuple[float, ...]
    q_max_rad: tuple[float, ...]
    q_home_rad: tuple[float, ...]
    Tc_Nm: tuple[float, ...] | None
    friction_source: str
    plan: excitation2.Plan2 | None

    n_joints = 6
    axes = ("x", "y", "z", "yaw", "pitch")
    mass_keys = (("Mxx_g@home", "apparent mass along x at the workspace centre (the rest held)", "g", 1e3),
                 ("Myy_g@home", "apparent mass along y at the workspace centre (the rest held)", "g", 1e3),
                 ("Mzz_g@home", "apparent mass along z at the workspace centre (the rest held)", "g", 1e3),
                 ("Iyaw_g_cm2@home", "inertia about yaw at the workspace centre (the rest held)", "g cm2", 1e7),
                 ("Ipitch_g_cm2@home", "inertia about pitch at the workspace centre (the rest held)", "g cm2", 1e7))
    force_axes = (("x_N", "N", 1.0), ("y_N", "N", 1.0), ("z_N", "N", 1.0), ("yaw_mNm", "mN m", 1e3),
                  ("pitch_mNm", "mN m", 1e3))
    home_words = "the workspace centre"
    vertical = True
    model_words = MODEL_WORDS

    def task(self, q) -> np.ndarray:
        """X (N, 5) (m, rad) of joint angles q (N, 6) (the firmware's forward kinematics)."""
        return state(self.spec, np.atleast_2d(np.asarray(q, float)))[0]

    def basis(self, q) -> np.ndarray:
        """W = dq/dX (N, 6, 5) (rad/m, rad/rad) by central differences of the IK."""
        X = self.task(q) / SI
        W = np.zeros((len(X), 6, 5))
        for i in range(5):
            e = np.zeros(5)
            e[i] = IK_STEP
            qp, qm = hp.ik(self.design.mechanism, X + e)[0], hp.ik(self.design.mechanism, X - e)[0]
            W[:, :, i] = (qp - qm) / (2 * IK_STEP * SI[i])
        return W

    def link_mass_X(self, X) -> np.ndarray:
        """Lambda (N, 5, 5) of the solids without rotors at X (N, 5) (m, rad)."""
        return link_mass_matrix_X(self.design, self.props, X)

    def task_jacobian(self, q) -> np.ndarray:
        """dX/dq (N, k, n) at q (N, n) (the firmware's)."""
        return state(self.spec, np.atleast_2d(np.asarray(q, float)))[1]

    def gravity(self, q) -> np.ndarray:
        """The firmware's gravity torques (N, 6) N m (every body's weight)."""
        return reference.gravity_torques(self.spec, np.atleast_2d(q))

    def angles(self, counts) -> np.ndarray:
        """Joint angles (N, 6) rad the firmware reads from ``counts``."""
        return angles_from_counts(self.spec, np.asarray(counts, float).reshape(-1, 6))

    def fit_log(self, t_s, q_rad, current_A) -> Fit2:
        """:func:`cad.identify.jointn.fit` with this prediction's over-actuated model."""
        model = jointn.JointModel(6, self.link_torques, self.gravity, self.basis)
        return jointn.fit(t_s, q_rad, current_A, np.asarray(self.kt_Nm_per_A), model, self.plan.f1_Hz)


def _ranges(design) -> tuple[tuple[float, ...], tuple[float, ...]]:
    ws = design.workspace
    X = hp.workspace_grid(ws["center_mm"], ws["size_mm"], (5, 5, 5), ws.get("rotation_deg", 0.0), 3)
    q, st = hp.ik(design.mechanism, X)
    q = q[st == 0]
    if not len(q):
        raise DesignError("workspace", "no workspace sample is reachable: nothing to identify over")
    return tuple(map(float, q.min(axis=0))), tuple(map(float, q.max(axis=0)))


def _plan(pred: PredictionPen) -> excitation2.Plan2:
    home = np.array([pred.q_home_rad])
    kt = np.asarray(pred.kt_Nm_per_A)
    g_A = np.abs(pred.gravity(home)[0]) / kt
    try:
        return excitation2.plan2(TE_S, kt, pred.i_max_A, pred.q_min_rad, pred.q_max_rad, pred.q_home_rad,
                                 np.diag(pred.joint_mass_kg(home)[0]),
                                 np.sign(pred.basis(home)[0] @ (HAND_DIR * SI)),
                                 pred.counts_per_rev, gravity_ff=True, gravity_A=g_A, hand_move=HAND_MOVE)
    except ValueError as exc:
        raise DesignError("motor", f"the identification routine cannot run: {exc}") from None


def _motors(device) -> tuple[tuple[float, ...], tuple[float, ...], tuple[float, ...] | None, str]:
    """(K_t, continuous current, Coulomb friction or None, its source) of each motor as its joint
    sees it through its transmission (:meth:`cad.device.ResolvedDevice.joint_motor`: n K_t,
    n K_t I_0; the current unchanged)."""
    seen = [SimpleNamespace(name=m.name, spec=device.joint_motor(m.joint)) for m in device.motors]
    data = [motor_data(m.spec) for m in seen]
    fr = [identify_joints.motor_friction(SimpleNamespace(motor=m)) for m in seen]
    Tc = None if any(f[0] is None for f in fr) else tuple(f[0] for f in fr)
    return (tuple(m.kt_Nm_per_A for m in data), tuple(m.current_continuous_A for m in data), Tc,
            "; ".join(dict.fromkeys(f[1] for f in fr)))


def joint_counts(device) -> int | float:
    """Encoder counts per joint turn of the coarsest joint (the motor encoder's x n, the smallest
    over the six joints, :meth:`cad.device.ResolvedDevice.joint_counts_per_rev`): the routine's
    thresholds counted in encoder steps (the hand move's least excursion, the sweep's band) read
    the largest step, so a joint through a larger ratio (finer steps) clears them with more
    counts; the angles themselves each joint's own (:meth:`PredictionPen.angles`, the firmware's
    HC_GEAR)."""
    return min(device.joint_counts_per_rev(m.joint) for m in device.motors)


def predict(design, report: dict) -> PredictionPen:
    """The :class:`PredictionPen` of a haptic pen built into ``report`` (its bodies); its motors
    as their joints see them through the capstans: n K_t, n counts, n^2 (J_m + J_c), n K_t I_0
    (:func:`_motors`, :func:`joint_counts`)."""
    device = resolve_device(design)
    h = design_hash(design)
    spec = device_spec(design, report, h, cad.__version__, device, PEN)
    kt, im, Tc, src = _motors(device)
    counts = joint_counts(device)
    lo, hi = _ranges(design)
    rotors = tuple(float(device.joint_rotor_inertia_kg_m2(m.joint)) for m in device.motors)  # n^2 (J_m + J_c)
    pred = PredictionPen(design.name, h, design, spec, props_of(report), rotors, TE_S, kt, im,
                         counts, tuple(int(d) for d in spec.encoder_direction),
                         tuple(spec.encoder_zero_rad), lo, hi, tuple(spec.q_home_rad), Tc, src, None)
    _warn_gravity(pred)
    return dataclasses.replace(pred, plan=_plan(pred))


def _warn_gravity(pred: PredictionPen) -> None:
    """A warning when gravity at home takes more than :data:`GRAVITY_WARN_FRACTION` of a
    motor's continuous current: the routine's sweeps then move that joint by a few counts."""
    frac = np.abs(pred.gravity(np.array([pred.q_home_rad]))[0]) / (np.asarray(pred.kt_Nm_per_A) * pred.i_max_A)
    j = int(np.argmax(frac))
    if frac[j] > GRAVITY_WARN_FRACTION:
        bounds.warn(f"identification: holding the arms at home takes {100 * frac[j]:.0f} % of motor {j}'s "
                    "continuous current: the routine's sweeps will move it by a few encoder counts, too little to "
                    "identify (a stronger shoulder motor, e.g. parts.motor = \"maxon-re40\", or counterbalanced arms)")


# ------------------------------------------------------------------ the virtual bench
class MujocoPlantPen(bench_joints.MujocoPlant):
    """The build's MJCF in MuJoCo (:class:`cad.sim.bench_joints.MujocoPlant`): both arms, the
    pen closing the loops, the rotors as the motor joints' armature, the model's -z gravity."""

    JOINTS = ("A_q_waist", "A_q_lower", "A_q_upper", "B_q_waist", "B_q_lower", "B_q_upper")
    MOTORS = ("A_motor_waist", "A_motor_lower", "A_motor_upper", "B_motor_waist", "B_motor_lower", "B_motor_upper")


#: The motor joints' (parent, child) bodies in the MJCF (:mod:`cad.families.pen.sim`).
HINGES = tuple((p, f"{a}_{c}") for a in ("A", "B")
               for p, c in (("world", "waist"), (f"{a}_waist", "proximal_lower"), (f"{a}_waist", "proximal_upper")))


def _hinge_angles(design, X_mm) -> np.ndarray:
    """(N, 6) each motor hinge's turn about its child's z since the first pose of ``X_mm``."""
    T = body_poses(design, X_mm)
    out = []
    for parent, child in HINGES:
        Rp = np.broadcast_to(np.eye(3), (len(X_mm), 3, 3)) if parent == "world" else T[parent][:, :3, :3]
        R = np.swapaxes(Rp, 1, 2) @ T[child][:, :3, :3]
        D = np.swapaxes(R[:1], 1, 2) @ R
        out.append(np.arctan2(D[:, 1, 0], D[:, 0, 0]))
    return np.stack(out, axis=-1)


def joint_map(pred: PredictionPen, design, qpos0) -> tuple[list[float], list[float]]:
    """(s, c) per motor joint with q = s q_mjcf + c: the firmware's angle against the MJCF
    hinge value (``qpos0``: its value at the written pose, home), from a move that turns every
    joint (the pen up, sideways and yawed)."""
    X0 = pred.task(np.array([pred.q_home_rad]))[0] / SI
    X = np.stack([X0, X0 + np.array([0.0, 5.0, 5.0, 0.05, 0.05])])
    dq = hp.ik(design.mechanism, X)[0]
    dh = _hinge_angles(design, X)[1]
    s = [1.0 if a * b > 0 else -1.0 for a, b in zip(dq[1] - dq[0], dh, strict=True)]
    return s, [float(q - sj * m) for q, sj, m in zip(pred.q_home_rad, s, qpos0, strict=True)]


def hand_path(pred: PredictionPen, design, n: int) -> np.ndarray:
    """Joint angles (n, 6) of the hand move: the pen from the workspace centre along
    :data:`HAND_DIR` by HAND_FRACTION of the workspace height and back, sin^2 in time (IK)."""
    X0 = pred.task(np.array([pred.q_home_rad]))[0] / SI
    s = np.sin(np.pi * np.arange(n) / n) ** 2
    X = X0 + np.outer(s * HAND_FRACTION * design.workspace["size_mm"][2], HAND_DIR)
    return hp.ik(design.mechanism, X)[0]


def simulate(design, pred: PredictionPen, p: dict, seed: int, mjcf) -> tuple:
    """(t_s, counts (N, 6), commanded currents (N, 6) A, truth) of one bench run on ``mjcf``."""
    tr = bench_joints.truth(pred, p)
    plan = pred.plan
    lo, hi = bench_joints.stop_range(plan)
    tau_max = 2 * max(abs(k) * i for k, i in zip(pred.kt_Nm_per_A, pred.i_max_A, strict=True)) * abs(p["kt"])
    plant = MujocoPlantPen(mjcf, tr, lo, hi, tau_max)
    plant.s, plant.c = joint_map(pred, design, [float(plant.m.qpos0[i]) for i in plant.iq])
    qh = hand_path(pred, design, int(math.ceil(plan.T_hand_s / plan.Te_s)))
    t, counts, cmd = bench_joints.run(pred, plant, tr, qh, lambda q: pred.gravity(np.asarray(q)[None])[0].tolist(),
                                      seed)
    tr["model"] = "mujoco"
    return t, counts, cmd, tr


# ------------------------------------------------------------------ hooks
#: ``hapticad identify`` / ``bench-log`` of the family (its firmware model's ``identification``).
KIT = joint_kit(6, predict, simulate, labels=["x (mN)", "y (mN)", "z (mN)", "yaw (mN m)", "pitch (mN m)"],
                ylabel="generalized force W^T tau along each coordinate (mN, mN m)")
identify_files = routine_files(predict)


def firmware_model(design) -> KinematicModel:
    """The family's ``firmware_model`` hook: :data:`cad.families.pen.firmware.PEN` with its
    identification."""
    return dataclasses.replace(PEN, identify=identify_files, identification=KIT)
