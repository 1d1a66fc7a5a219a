"""The twin pantograph's identification (issue 37): four motors, three degrees of freedom
(the knob's x, y and the crank angle theta), run by the n-motor identification
(:mod:`cad.sim.identify_joints`, :mod:`cad.identify.jointn`, :mod:`cad.sim.bench_joints`).

The device is over-actuated: the two 5-bars and the crankshaft close one loop, so the four
motors can push against each other without moving it. The fit works in the independent
coordinates X = (x, y, theta) (:class:`cad.identify.jointn.JointModel` ``basis`` = dq/dX,
the firmware's :func:`cad.families.pantograph.firmware.twin_task_jacobian`, isotropy paper
eq 1): the links by the task mass matrix Lambda(X) of the solids without rotors
(:func:`cad.kinematics.twin_pantograph.task_mass_matrix`, the datasheet's), their inverse
dynamics by Euler-Lagrange in X (X' = J q', X'' = J q'' + J' q', J = dX/dq), given to the fit
as the least-norm joint torques; each motor's rotor J_j q_j''; friction and per-motor offsets
(spread by least norm, :mod:`cad.identify.jointn`).

Figures: the apparent mass along x and y and the rotational inertia about the knob axis at
home (the other coordinates held), each motor's friction and offset, the signs. The hand move:
the knob straight away from the base (+y). Virtual bench: the build's MJCF in MuJoCo
(:class:`MujocoPlantTwin`).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

import cad
from cad.device import resolve_device
from cad.errors import DesignError
from cad.families.pantograph.firmware import (
    FIVEBAR,
    TWIN,
    twin_forward,
    twin_jacobian,
    twin_mass_matrix,
    twin_of,
    twin_task_jacobian,
)
from cad.firmware import reference
from cad.firmware.device import device_spec
from cad.firmware.model import KinematicModel
from cad.firmware.spec import angles_from_counts
from cad.identify import excitation2, jointn
from cad.identify.joint2 import Fit2
from cad.isotropy.gii import workspace_half_mm
from cad.kinematics import twin_pantograph as tw
from cad.pipeline import design_hash
from cad.sim import bench_joints, identify_joints
from cad.sim.bench import HAND_FRACTION
from cad.sim.identify_fivebar import TE_S, joint_side
from cad.sim.identify_kits import joint_kit, routine_files

#: Samples per side of the workspace square and crank angles whose IK gives the joint ranges.
RANGE_GRID, RANGE_THETA = 11, 8
MODEL_WORDS = ("W^T s Kt i(t - n Te) = W^T [c_link tau_links(Lambda_solids(X), Euler-Lagrange in X = (x, y, theta)) "
               "+ J_j q_j'' + Tc_j sign(q_j') + b_j q_j' + T0] (twin pantograph, q' = W X', "
               "cad.identify.jointn)")


@dataclass(frozen=True)
class PredictionTwin(identify_joints.OverActuated):
    """A twin pantograph's predicted figures (module docstring); SI, tuples per motor."""

    name: str
    design_hash: str
    spec: object  # cad.firmware.spec.DeviceSpec, its rotor 0 (the links alone)
    rotor_kg_m2: float
    Te_s: float
    kt_Nm_per_A: float
    i_max_A: float
    counts_per_rev: float  # per joint turn: the motor encoder's x n through a capstan
    direction: tuple[int, ...]
    zero_rad: tuple[float, ...]
    q_min_rad: tuple[float, ...]
    q_max_rad: tuple[float, ...]
    q_home_rad: tuple[float, ...]
    Tc_Nm: float | None
    friction_source: str
    vertical: bool
    plan: excitation2.Plan2 | None

    n_joints = 4
    axes = ("x", "y", "theta")
    mass_keys = (("Mxx_g@home", "apparent mass at the knob along x at home (y, theta held)", "g", 1e3),
                 ("Myy_g@home", "apparent mass at the knob along y at home (x, theta held)", "g", 1e3),
                 ("Itheta_g_cm2@home", "inertia about the knob axis at home (x, y held)", "g cm2", 1e7))
    #: The generalized forces W^T tau along X: (name, unit, SI -> unit factor).
    force_axes = (("x_N", "N", 1.0), ("y_N", "N", 1.0), ("theta_mNm", "mN m", 1e3))
    home_words = "home"
    model_words = MODEL_WORDS

    def task(self, q) -> np.ndarray:
        """X (N, 3) (m, m, rad) of joint angles q (N, 4)."""
        return twin_forward(self.spec, np.atleast_2d(np.asarray(q, float)))[0]

    def basis(self, q) -> np.ndarray:
        """W = dq/dX (N, 4, 3) at q (N, 4)."""
        return twin_task_jacobian(self.spec, np.atleast_2d(np.asarray(q, float)))

    def link_mass_X(self, X) -> np.ndarray:
        """Lambda (N, 3, 3) of the solids without rotors at X (N, 3) (kg, kg m, kg m^2)."""
        return twin_mass_matrix(self.spec, None, np.atleast_2d(X))

    def task_jacobian(self, q) -> np.ndarray:
        """dX/dq (N, k, n) at q (N, n) (the firmware's)."""
        return twin_jacobian(self.spec, np.atleast_2d(np.asarray(q, float)))

    def gravity(self, q):
        """Gravity torques (N, 4) N m of a vertical device (the firmware's); None: horizontal."""
        return reference.gravity_torques(self.spec, np.atleast_2d(q)) if self.vertical else None

    def angles(self, counts) -> np.ndarray:
        """Joint angles (N, 4) rad the firmware reads from ``counts``."""
        return angles_from_counts(self.spec, np.asarray(counts, float).reshape(-1, 4))

    def fit_log(self, t_s, q_rad, current_A) -> Fit2:
        """:func:`cad.identify.jointn.fit` with this prediction's over-actuated model."""
        model = jointn.JointModel(4, self.link_torques, self.gravity if self.vertical else None, self.basis)
        return jointn.fit(t_s, q_rad, current_A, self.kt_Nm_per_A, model)


def _ranges(design, spec) -> tuple[tuple[float, ...], tuple[float, ...]]:
    (cx, cy), (hx, hy) = design.workspace["center_mm"], workspace_half_mm(design.workspace)
    g = np.linspace(-1.0, 1.0, RANGE_GRID)
    x, y, th = np.meshgrid(cx + hx * g, cy + hy * g, np.linspace(0.0, 2 * math.pi, RANGE_THETA, endpoint=False))
    ik = tw.ik(twin_of(spec.params), np.column_stack([x.ravel(), y.ravel(), th.ravel()]))
    q = ik.q_rad[ik.status == 0]
    return tuple(map(float, q.min(axis=0))), tuple(map(float, q.max(axis=0)))


def _plan(pred: PredictionTwin) -> excitation2.Plan2:
    home = np.array([pred.q_home_rad])
    g_A = float(np.max(np.abs(pred.gravity(home)))) / pred.kt_Nm_per_A if pred.vertical else 0.0
    try:
        return excitation2.plan2(TE_S, pred.kt_Nm_per_A, pred.i_max_A, pred.q_min_rad, pred.q_max_rad,
                                 pred.q_home_rad, np.diag(pred.joint_mass_kg(home)[0]),
                                 np.sign(pred.basis(home)[0][:, 1]), pred.counts_per_rev,
                                 gravity_ff=pred.vertical, gravity_A=g_A)
    except ValueError as exc:
        raise DesignError("firmware.plane", f"the identification routine cannot run: {exc}") from None


def predict(design, report: dict) -> PredictionTwin:
    """The :class:`PredictionTwin` of a twin pantograph built into ``report`` (its bodies); its
    motors as their joints see them through the capstans (:func:`cad.sim.identify_fivebar.joint_side`:
    n K_t, n counts, n^2 (J_m + J_c), n K_t I_0)."""
    device = resolve_device(design)
    h = design_hash(design)
    spec = dataclasses.replace(device_spec(design, report, h, cad.__version__, device, TWIN),
                               rotor_kg_m2=0.0, rotor_joints_kg_m2=())  # the links alone
    motor, counts, rotor = joint_side(device)  # through the capstans (x n, x n^2)
    lo, hi = _ranges(design, spec)
    Tc, src = identify_joints.motor_friction(device)
    Tc = None if Tc is None else device.transmissions[0].ratio * Tc  # the motor's friction at its joint
    pred = PredictionTwin(design.name, h, spec, rotor, TE_S, motor.kt_Nm_per_A,
                          motor.current_continuous_A, counts,
                          tuple(int(d) for d in spec.encoder_direction), tuple(spec.encoder_zero_rad), lo, hi,
                          tuple(spec.q_home_rad), Tc, src, spec.gravity_m_s2 is not None, None)
    return dataclasses.replace(pred, plan=_plan(pred))


# ------------------------------------------------------------------ the virtual bench
class MujocoPlantTwin(bench_joints.MujocoPlant):
    """The build's MJCF in MuJoCo (:class:`cad.sim.bench_joints.MujocoPlant`): both 5-bars,
    the crankshaft closing three loops, the rotors as the motor joints' armature."""

    JOINTS = ("knob_q_left", "knob_q_right", "crank_q_left", "crank_q_right")
    MOTORS = ("knob_motor_left", "knob_motor_right", "crank_motor_left", "crank_motor_right")


def hand_path(pred: PredictionTwin, design, n: int) -> np.ndarray:
    """Joint angles (n, 4) of the hand move: the knob from home along +y by HAND_FRACTION of
    the workspace height and back (sin^2 in time), the crank angle kept (IK)."""
    X0 = pred.task(np.array([pred.q_home_rad]))[0]
    s = np.sin(np.pi * np.arange(n) / n) ** 2
    dy = s * HAND_FRACTION * 2 * workspace_half_mm(design.workspace)[1]
    X = np.column_stack([np.full(n, 1e3 * X0[0]), 1e3 * X0[1] + dy, np.full(n, X0[2])])
    return tw.ik(twin_of(pred.spec.params), X).q_rad


def simulate(design, pred: PredictionTwin, p: dict, seed: int, mjcf) -> tuple:
    """(t_s, counts (N, 4), commanded currents (N, 4) A, truth) of one bench run on ``mjcf``."""
    tr = bench_joints.truth(pred, p)
    plan = pred.plan
    lo, hi = bench_joints.stop_range(plan)
    g = pred.spec.gravity_m_s2
    plant = MujocoPlantTwin(mjcf, tr, lo, hi, 2 * abs(tr["kt_Nm_per_A"]) * pred.i_max_A,
                            (0.0, 0.0, 0.0) if g is None else (g[0], g[1], 0.0))
    qh = hand_path(pred, design, int(math.ceil(plan.T_hand_s / plan.Te_s)))
    ff = (lambda q: pred.gravity(np.asarray(q)[None])[0].tolist()) if pred.vertical else None
    t, counts, cmd = bench_joints.run(pred, plant, tr, qh, ff, seed)
    tr["model"] = "mujoco"
    return t, counts, cmd, tr


# ------------------------------------------------------------------ hooks
#: ``hapticad identify`` / ``bench-log`` of the family (its firmware model's ``identification``).
KIT = joint_kit(4, predict, simulate, labels=["x (mN)", "y (mN)", "theta (mN m)"],
                ylabel="generalized force W^T tau along each coordinate (mN, mN m)")
identify_files = routine_files(predict)


def firmware_model(design) -> KinematicModel:
    """The pantograph family's ``firmware_model`` hook: the twin's model with its
    identification, the plain 5-bar's (:data:`cad.families.pantograph.firmware.FIVEBAR`)."""
    if design.family == "twin-pantograph":
        return dataclasses.replace(TWIN, identify=identify_files, identification=KIT)
    return FIVEBAR
