"""The delta's identification (issue 37): its prediction, its fit model and its virtual
bench, run by the n-motor identification (:mod:`cad.sim.identify_joints`,
:mod:`cad.identify.jointn`, :mod:`cad.sim.bench_joints`).

Prediction (:func:`predict`, from the build's ``report.json`` bodies and the resolved device):

* the links' joint-space mass matrix M(q) = J_x^T Lambda_links(x) J_x (J_x = dx/dq = J^-1,
  Lambda of the solids without the rotors, :func:`cad.families.delta.dynamics.
  mass_matrix_from_bodies_kg`), their inverse dynamics by Euler-Lagrange
  (:func:`cad.identify.jointn.lagrange_torques`), each arm's rotor through its own
  transmission, n_i^2 (J_m + J_capstan,i) (:meth:`cad.device.ResolvedDevice.
  joint_rotor_inertia_kg_m2`);
* each arm's own ratio n_i (``[[transmission]]`` may give the arms different ones): counts ->
  joint angle through n_i (the firmware's ``HC_GEAR``, :func:`cad.firmware.spec.
  angles_from_counts`), current -> joint torque n_i K_t, Coulomb friction n_i K_t I_0;
* the solids' gravity hold torques (:func:`cad.families.delta.dynamics.gravity_hold_torques_Nm`),
  the firmware's feed-forward (the point-mass model ``hc_gravity_torques``,
  :func:`cad.dynamics.delta.gravity_torques_Nm`);
* the joint ranges over the workspace samples (IK), home at the workspace centre, the hand
  move straight up (+z: every arm turns up), the excitation plan.

Figures: the apparent mass along x, y and z at the workspace centre (the datasheet's Lambda
there), each motor's friction and offset, the gravity loads and scale, the signs.
Virtual bench: the build's MJCF in MuJoCo (:class:`MujocoPlantDelta`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

import cad
from cad.device import resolve_device
from cad.dynamics.delta import DeltaMass, gravity_torques_Nm
from cad.errors import DesignError
from cad.families.delta.dynamics import gravity_hold_torques_Nm, mass_matrix_from_bodies_kg
from cad.families.delta.firmware import DELTA, mass_of, props_of
from cad.firmware.device import device_spec
from cad.firmware.model import KinematicModel
from cad.firmware.spec import angles_from_counts, motor_data
from cad.identify import excitation2, jointn
from cad.identify.joint2 import Fit2
from cad.kinematics.delta import Delta, fk, ik, jacobian_rad_per_m
from cad.pipeline import design_hash
from cad.sim import bench_joints, identify_joints
from cad.sim.bench import HAND_FRACTION
from cad.sim.identify_fivebar import TE_S
from cad.sim.identify_kits import joint_kit, routine_files

#: The operator's hand move in the first phase (every arm turns up with it).
HAND_MOVE = "straight up (+z)"
MODEL_WORDS = ("s_j Kt i_j(t - n Te) = c_link tau_links_j(q, q', q'') (Euler-Lagrange of J_x^T Lambda_solids J_x) + "
               "J_j q_j'' + Tc_j sign(q_j') + b_j q_j' + cg g_j(q) + T0_j (delta, cad.identify.jointn)")


@dataclass(frozen=True)
class PredictionDelta:
    """A delta's predicted figures (module docstring); SI units, tuples per motor: the
    reflected rotor n_i^2 (J_m + J_capstan,i) (kg m^2), the joint torque per ampere n_i K_t
    (N m/A) and the Coulomb friction n_i K_t I_0 (N m) of each arm's own ratio n_i."""

    name: str
    design_hash: str
    delta: Delta
    width_mm: float
    props: dict
    mass: DeltaMass
    rotor_kg_m2: tuple[float, ...]
    Te_s: float
    kt_Nm_per_A: tuple[float, ...]
    i_max_A: float
    counts_per_rev: int
    direction: tuple[int, ...]
    zero_rad: tuple[float, ...]
    q_min_rad: tuple[float, ...]
    q_max_rad: tuple[float, ...]
    q_home_rad: tuple[float, ...]
    Tc_Nm: tuple[float, ...] | None
    friction_source: str
    spec: object  # cad.firmware.spec.DeviceSpec
    plan: excitation2.Plan2 | None

    n_joints = 3
    axes = ("x", "y", "z")
    home_words = "the workspace centre"
    vertical = True
    model_words = MODEL_WORDS

    def points_mm(self, q) -> np.ndarray:
        """Effector points (N, 3) mm of joint angles q (N, 3) (forward kinematics)."""
        return fk(self.delta, np.atleast_2d(np.asarray(q, float))).P_mm

    def link_mass_kg(self, q) -> np.ndarray:
        """Joint-space mass matrix (N, 3, 3) kg m^2 of the solids (no rotor) at q (N, 3)."""
        P = self.points_mm(q)
        Jx = np.linalg.inv(jacobian_rad_per_m(self.delta, P)[0])
        lam = mass_matrix_from_bodies_kg(self.delta, P, self.width_mm, self.props)
        return np.swapaxes(Jx, 1, 2) @ lam @ Jx

    def joint_mass_kg(self, q) -> np.ndarray:
        """:meth:`link_mass_kg` plus each arm's rotor (n_i^2 (J_m + J_c,i)) on the diagonal."""
        return self.link_mass_kg(q) + np.diag(self.rotor_kg_m2)

    def gravity(self, q) -> np.ndarray:
        """The solids' gravity hold torques (N, 3) N m at q (N, 3)."""
        return gravity_hold_torques_Nm(self.delta, self.points_mm(q), self.width_mm, self.props)

    def gravity_ff(self, q) -> list[float]:
        """The firmware's feed-forward (``hc_gravity_torques``) at one reading q (3,), N m."""
        return gravity_torques_Nm(self.delta, self.points_mm(q), self.mass)[0].tolist()

    def angles(self, counts) -> np.ndarray:
        """Joint angles (N, 3) rad the firmware reads from ``counts`` (configured directions)."""
        return angles_from_counts(self.spec, np.asarray(counts, float).reshape(-1, 3))

    def task_mass_terms(self, q) -> tuple[np.ndarray, ...]:
        """(A, B_0, B_1, B_2) (3, 3) kg: Lambda at q (1, 3) = c_link A + sum_j J_j B_j."""
        P = self.points_mm(q)
        J = jacobian_rad_per_m(self.delta, P)[0][0]
        A = mass_matrix_from_bodies_kg(self.delta, P, self.width_mm, self.props)[0]
        return (A, *(np.outer(J[j], J[j]) for j in range(3)))

    def task_mass_kg(self, q, c_link: float = 1.0, J=None) -> np.ndarray:
        """Lambda (3, 3) kg at q (1, 3) of the given parameters (default: the prediction)."""
        J = self.rotor_kg_m2 if J is None else J
        A, *B = self.task_mass_terms(q)
        return c_link * A + sum(j * b for j, b in zip(J, B, strict=True))

    def fit_log(self, t_s, q_rad, current_A) -> Fit2:
        """:func:`cad.identify.jointn.fit` of a log segment with this prediction's model."""
        model = jointn.JointModel(3, lambda q, v, a: jointn.lagrange_torques(self.link_mass_kg, q, v, a),
                                  self.gravity)
        return jointn.fit(t_s, q_rad, current_A, self.kt_Nm_per_A, model)


def _ranges(design, d: Delta) -> tuple[tuple[float, ...], tuple[float, ...]]:
    pose = ik(d, design.workspace_points())
    q = pose.theta_rad[pose.ok]
    if not len(q):
        raise DesignError("workspace", "no workspace sample is reachable: nothing to identify over")
    return tuple(map(float, q.min(axis=0))), tuple(map(float, q.max(axis=0)))


def _plan(pred: PredictionDelta, device) -> excitation2.Plan2:
    motor = motor_data(device.motor.spec)
    home = np.array([pred.q_home_rad])
    J = jacobian_rad_per_m(pred.delta, pred.points_mm(home))[0][0]
    g_A = float(np.max(np.abs(pred.gravity_ff(home[0])) / np.asarray(pred.kt_Nm_per_A)))
    try:
        return excitation2.plan2(TE_S, pred.kt_Nm_per_A, motor.current_continuous_A, pred.q_min_rad, pred.q_max_rad,
                                 pred.q_home_rad, np.diag(pred.joint_mass_kg(home)[0]), np.sign(J[:, 2]),
                                 pred.counts_per_rev, gravity_ff=True, gravity_A=g_A, hand_move=HAND_MOVE)
    except ValueError as exc:
        raise DesignError("motor", f"the identification routine cannot run: {exc} "
                          "(lighter arms and effector or a stronger motor)") from None


def predict(design, report: dict) -> PredictionDelta:
    """The :class:`PredictionDelta` of a delta ``design`` built into ``report`` (its
    ``bodies``). DesignError when gravity at home takes the motors' continuous current."""
    device = resolve_device(design)
    h = design_hash(design)
    spec = device_spec(design, report, h, cad.__version__, device, DELTA)
    d = design.mechanism
    wide = dataclasses.replace(d, theta_min_rad=-math.pi, theta_max_rad=math.pi)  # limits are not physics
    lo, hi = _ranges(design, d)
    joints = tuple(f"theta_{i}" for i in range(3))
    n = [device.transmission(j).ratio for j in joints]  # each arm's own
    motor = motor_data(device.motor.spec)
    Tc, src = identify_joints.motor_friction(device)
    pred = PredictionDelta(design.name, h, wide, design.parallelogram_width_mm, props_of(report), mass_of(spec),
                           tuple(device.joint_rotor_inertia_kg_m2(j) for j in joints), TE_S,
                           tuple(k * motor.kt_Nm_per_A for k in n), motor.current_continuous_A,
                           device.encoder.counts_per_rev, tuple(int(x) for x in spec.encoder_direction),
                           tuple(spec.encoder_zero_rad), lo, hi, tuple(spec.q_home_rad),
                           None if Tc is None else tuple(k * Tc for k in n), src, spec, None)
    return dataclasses.replace(pred, plan=_plan(pred, device))


# ------------------------------------------------------------------ the virtual bench
class MujocoPlantDelta(bench_joints.MujocoPlant):
    """The build's MJCF in MuJoCo (:class:`cad.sim.bench_joints.MujocoPlant`): three upper
    arms on hinges, six rods on ball joints, the effector; the loops closed by ``connect``
    equalities; the rotors as the hinges' armature; the model's -z gravity."""

    JOINTS = ("theta_0", "theta_1", "theta_2")
    MOTORS = ("motor_0", "motor_1", "motor_2")


def hand_path(pred: PredictionDelta, design, n: int) -> np.ndarray:
    """Joint angles (n, 3) of the operator's hand move: the effector from the workspace
    centre straight up by HAND_FRACTION of the workspace height and back, sin^2 in time
    (inverse kinematics, elbow out)."""
    ws = design.workspace
    height = ws["size_mm"][2] if ws["shape"] == "box" else ws["height_mm"]
    s = np.sin(np.pi * np.arange(n) / n) ** 2
    P = np.asarray(ws["center_mm"], float) + np.outer(s * HAND_FRACTION * height, [0.0, 0.0, 1.0])
    return ik(pred.delta, P).theta_rad


def simulate(design, pred: PredictionDelta, p: dict, seed: int, mjcf) -> tuple:
    """(t_s, counts (N, 3), commanded currents (N, 3) A, truth) of one run of the routine on
    the MJCF ``mjcf`` with perturbations ``p`` (:func:`cad.sim.bench.parse_perturb`)."""
    tr = bench_joints.truth(pred, p)
    plan = pred.plan
    lo, hi = bench_joints.stop_range(plan)
    kt = max(abs(k) for k in identify_joints.per_joint(tr["kt_Nm_per_A"], 3))  # the largest joint's
    plant = MujocoPlantDelta(mjcf, tr, lo, hi, 2 * kt * pred.i_max_A)
    qh = hand_path(pred, design, int(math.ceil(plan.T_hand_s / plan.Te_s)))
    t, counts, cmd = bench_joints.run(pred, plant, tr, qh, pred.gravity_ff, seed)
    tr["model"] = "mujoco"
    return t, counts, cmd, tr


# ------------------------------------------------------------------ hooks
#: ``hapticad identify`` / ``bench-log`` of the family (its firmware model's ``identification``).
KIT = joint_kit(3, predict, simulate)
identify_files = routine_files(predict)


def firmware_model(design) -> KinematicModel:
    """The family's ``firmware_model`` hook: :data:`cad.families.delta.firmware.DELTA` with
    the identification routine and kit."""
    return dataclasses.replace(DELTA, identify=identify_files, identification=KIT)
