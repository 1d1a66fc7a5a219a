"""The 5-bar pantograph's predicted figures for identification (issue 37) and the
identification run (the four-bar's: :mod:`cad.sim.identify_device`).

:func:`predict` gathers, from the build's DeviceSpec (:func:`cad.firmware.device.device_spec`:
the linkage and working modes, the bodies' masses from the solids, the motor, the encoder):
the tree parameters of the solids (:func:`cad.identify.joint2.tree_params`, the handle a
point mass at E), the rotor inertia, the joint ranges over the workspace rectangle, the
motors' Coulomb friction (Kt I0 of the data sheet, when it gives I0), the gravity torques of
a vertical device (:func:`cad.firmware.reference.gravity_torques`) and the excitation plan
(:func:`cad.identify.excitation2.plan2`).

:func:`identify` fits a log (:mod:`cad.identify.joint2`) and sets every figure beside its
prediction with a verdict (:mod:`cad.tolerances` ``IDENT_*``): the apparent mass at the
handle at home along x and y (the datasheet's ``effective_mass_home``), each motor's
friction and offset, the gravity scale, each encoder's direction and each current gain's sign.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import cad
from cad.device import resolve_device
from cad.errors import DesignError
from cad.firmware import linkage_model, reference
from cad.firmware.device import device_spec
from cad.firmware.spec import motor_data
from cad.identify import excitation2, joint2
from cad.identify.joint2 import Fit2, FiveBarGeom
from cad.identify.logfile import Log
from cad.io import guard
from cad.isotropy.gii import workspace_half_mm
from cad.kinematics import fivebar as fb5
from cad.pipeline import design_hash
from cad.sim import identify_joints
from cad.sim.device import device_build

#: Control period of the pantograph's routine (s): 1 kHz, the rate of the Pantograph Mk-II's
#: haptic loop (Campion, Wang & Hayward, IROS 2005), inside the 1-4 kHz of haptic servo loops.
TE_S = 1e-3
#: Samples per side of the workspace grid whose inverse kinematics gives the joint ranges.
RANGE_GRID = 21


#: What the 5-bar's fit takes as its model (``identify.json`` ``model``).
MODEL_WORDS = ("s_j Kt i_j(t - n Te) = c_link (W^T tau_tree(solids))_j + J_j q_j'' + Tc_j sign(q_j') + "
               "b_j q_j' [+ cg g_j(q)] + T0_j (5-bar, cad.identify.joint2)")


@dataclass(frozen=True)
class Prediction5:
    """A 5-bar's predicted figures (module docstring); SI units, tuples per motor."""

    name: str
    design_hash: str
    geom: FiveBarGeom
    beta_links: np.ndarray
    rotor_kg_m2: float
    Te_s: float
    kt_Nm_per_A: float
    i_max_A: float
    counts_per_rev: int
    direction: tuple[int, int]
    zero_rad: tuple[float, float]
    q_min_rad: tuple[float, float]
    q_max_rad: tuple[float, float]
    q_home_rad: tuple[float, float]
    Tc_Nm: float | None
    friction_source: str
    spec: object  # cad.firmware.spec.DeviceSpec (gravity torques)
    plan: excitation2.Plan2

    n_joints = 2
    axes = ("x", "y")
    home_words = "home"
    model_words = MODEL_WORDS

    @property
    def vertical(self) -> bool:
        return self.spec.gravity_m_s2 is not None

    def joint_mass_kg(self, q) -> np.ndarray:
        """Joint-space mass matrix (N, 2, 2) kg m^2 at q (N, 2): the solids and the rotors."""
        return joint2.mass_matrix(self.geom, self.beta_links, (self.rotor_kg_m2,) * 2, q)

    def fit_log(self, t_s, q_rad, current_A) -> Fit2:
        """:func:`cad.identify.joint2.fit` of a log segment with this prediction's model."""
        return joint2.fit(t_s, q_rad, current_A, self.kt_Nm_per_A, self.geom, self.beta_links,
                          self.gravity if self.vertical else None)

    def gravity(self, q):
        """Predicted gravity torques (N, 2) N m at q (N, 2); None for a horizontal device."""
        if not self.vertical:
            return None
        return reference.gravity_torques(self.spec, np.atleast_2d(q))

    def angles(self, counts) -> np.ndarray:
        """Joint angles (N, 2) rad the firmware reads from ``counts`` (configured directions)."""
        c = np.asarray(counts, float).reshape(-1, 2)
        return np.asarray(self.zero_rad) + np.asarray(self.direction) * 2 * math.pi / self.counts_per_rev * c

    def task_mass_terms(self, q) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(A, B0, B1) (3 of (2, 2) kg) with the task mass matrix at q (1, 2) equal to
        c_link A + J0 B0 + J1 B1 (linear in the identified parameters)."""
        Jx = jacobian(self.geom, q)[0]
        Jq = np.linalg.inv(Jx)
        Mq = joint2.mass_matrix(self.geom, self.beta_links, (0.0, 0.0), q)[0]
        out = [Jq.T @ Mq @ Jq]
        for k in range(2):
            e = np.zeros((2, 2))
            e[k, k] = 1.0
            out.append(Jq.T @ e @ Jq)
        return tuple(out)

    def task_mass_kg(self, q, c_link: float = 1.0, J=None) -> np.ndarray:
        """Task-space mass matrix (2, 2) kg at q (1, 2) of the given parameters (default the
        prediction: the solids and the rotors)."""
        J = (self.rotor_kg_m2,) * 2 if J is None else J
        A, B0, B1 = self.task_mass_terms(q)
        return c_link * A + J[0] * B0 + J[1] * B1


def jacobian(g: FiveBarGeom, q) -> np.ndarray:
    """dE/dq (N, 2, 2) m/rad of the closure (:func:`cad.identify.joint2.closure`)."""
    q = np.atleast_2d(np.asarray(q, float))
    _, psi, Psi, _ = joint2.closure(g, q)
    n1 = np.column_stack([-np.sin(psi[:, 0]), np.cos(psi[:, 0])])
    m1 = np.column_stack([-np.sin(q[:, 0]), np.cos(q[:, 0])])
    J = g.l3 * n1[:, :, None] * Psi[:, None, 0, :]
    J[:, :, 0] += g.l1 * m1
    return J


def geom_of(params: dict) -> FiveBarGeom:
    """The :class:`FiveBarGeom` of a pantograph DeviceSpec's ``params`` (m)."""
    p = params
    return FiveBarGeom((p["b1x"], p["b1y"]), (p["b2x"], p["b2y"]), p["l2l"], p["l2r"], p["l3l"], p["l3r"],
                       int(p["assembly"]))


def beta_of(geom: FiveBarGeom, bodies: dict) -> np.ndarray:
    """The solids' tree parameters (8,) (:data:`cad.identify.joint2.TREE`) of the bodies
    (``{name: Body}``), the handle (when built) a point mass at E on the left arm."""
    def lm(n):
        b = bodies[n]
        return b.mass_kg, b.com_m, b.izz_kg_m2

    h = bodies["handle"].mass_kg if "handle" in bodies else 0.0
    return np.concatenate([joint2.tree_params(geom.l1, geom.l3, lm("proximal_left"), lm("distal_left"), h),
                           joint2.tree_params(geom.l2, geom.l4, lm("proximal_right"), lm("distal_right"))])


def joint_ranges(design, geom_mm) -> tuple[tuple[float, float], tuple[float, float]]:
    """(q_min, q_max) (rad, per joint) over a :data:`RANGE_GRID` grid of the workspace rectangle."""
    (cx, cy), (hx, hy) = design.workspace["center_mm"], workspace_half_mm(design.workspace)
    X, Y = np.meshgrid(np.linspace(cx - hx, cx + hx, RANGE_GRID), np.linspace(cy - hy, cy + hy, RANGE_GRID))
    ik = fb5.ik(geom_mm, np.column_stack([X.ravel(), Y.ravel()]))
    q = ik.q_rad[ik.ok]
    return tuple(map(float, q.min(axis=0))), tuple(map(float, q.max(axis=0)))


def _gravity_A(spec, motor) -> float:
    """The largest motor current holding the device against gravity at home (A; 0 when horizontal)."""
    if spec.gravity_m_s2 is None:
        return 0.0
    return float(np.max(np.abs(reference.gravity_torques(spec, np.array([spec.q_home_rad]))))) / motor.kt_Nm_per_A



def joint_side(device):
    """(MotorData, counts per joint turn, rotor inertia at the joint kg m^2) of the device's
    motors (the 5-bar's two, the twin pantograph's four) as their joints see them: through a
    capstan of ratio n, K_t and the torques x n (:meth:`cad.device.ResolvedDevice.joint_motor`),
    the encoder's counts x n and the rotor with its capstan x n^2 (direct drive: the motor's
    own). DesignError naming ``transmission`` when the joints' transmissions differ (one
    prediction for every motor)."""
    ts = device.transmissions
    if len({(t.ratio, t.capstan_diameter_mm, t.wraps, t.cable_diameter_mm) for t in ts}) > 1:
        raise DesignError("transmission", f"identifying a {device.family} whose motors have different "
                          "transmissions is not built (give every motor the same [transmission])")
    j = device.motors[0].joint
    c = device.joint_counts_per_rev(j)
    return motor_data(device.joint_motor(j)), (int(c) if float(c).is_integer() else c), \
        device.joint_rotor_inertia_kg_m2(j)


def predict(design, report: dict) -> Prediction5:
    """The :class:`Prediction5` of a 5-bar ``design`` built into ``report`` (report.json:
    its ``bodies``). DesignError naming ``firmware.plane`` when a vertical device's weight at
    home takes the motors' whole continuous current (no current is left to excite it)."""

    device = resolve_device(design)
    h = design_hash(design)
    spec = device_spec(design, report, h, cad.__version__, device, linkage_model(design))
    g = geom_of(spec.params)
    beta = beta_of(g, spec.bodies)
    motor, counts, rotor = joint_side(device)  # through the capstans (x n, x n^2)
    lo, hi = joint_ranges(design, design.mechanism)
    home = np.array([spec.q_home_rad])
    Mq = joint2.mass_matrix(g, beta, (rotor,) * 2, home)[0]
    dq = np.linalg.solve(jacobian(g, home)[0], np.array([0.0, 1.0]))  # the hand move: +y
    try:
        plan = excitation2.plan2(TE_S, motor.kt_Nm_per_A, motor.current_continuous_A, lo, hi, spec.q_home_rad,
                                 np.diag(Mq), np.sign(dq), counts,
                                 gravity_ff=spec.gravity_m_s2 is not None, gravity_A=_gravity_A(spec, motor))
    except ValueError as exc:
        raise DesignError("firmware.plane", f"the identification routine cannot run: {exc} "
                          "(counterbalance the links, lighter links or a stronger motor)") from None
    Tc, src = identify_joints.motor_friction(device)
    n = device.transmissions[0].ratio  # the motor's friction at its joint: n K_t I_0
    Tc = None if Tc is None else n * Tc
    return Prediction5(design.name, h, g, beta, rotor, TE_S, motor.kt_Nm_per_A,
                       motor.current_continuous_A, counts,
                       tuple(int(d) for d in spec.encoder_direction), tuple(spec.encoder_zero_rad), lo, hi,
                       tuple(spec.q_home_rad), Tc, src, spec, plan)


def build_report(design, build_dir: Path | None) -> dict:
    """report.json of the design's build (:func:`build_folder`)."""
    return build_folder(design, build_dir)[1]


def build_folder(design, build_dir: Path | None) -> tuple[Path, dict]:
    """(folder, report.json) of the design's build: ``build_dir`` (a finished ``build
    --formats mjcf`` of this design; DesignError naming ``--build-dir`` otherwise) or the
    cached simulator build (:func:`cad.sim.device.device_build`); the folder holds
    ``<name>.xml``."""
    if build_dir is not None:
        build_dir = Path(build_dir)
        if not (os.path.lexists(build_dir / "report.json") and os.path.lexists(build_dir / f"{design.name}.xml")):
            raise DesignError("--build-dir", f"{build_dir} holds no report.json and {design.name}.xml "
                              "(run hapticad build DESIGN --formats mjcf --out DIR first)")
        folder = build_dir
    else:
        folder = device_build(design, None)
    rep = guard.load_json(folder / "report.json", "report", "--build-dir")
    if not isinstance(rep, dict) or rep.get("name") != design.name or not isinstance(rep.get("bodies"), dict):
        raise DesignError("--build-dir", f"{folder} is not a build of {design.name!r} (its report.json "
                          "names another design or has no bodies)")
    return folder, rep


def predict_from_build(design, build_dir=None) -> Prediction5:
    """:func:`predict` with the bodies of the design's build (:func:`build_report`)."""
    return predict(design, build_report(design, None if build_dir is None else Path(build_dir)))


def identify(pred: Prediction5, log: Log, path) -> tuple[dict, Fit2 | None]:
    """(result, fit) of a parsed 2-motor log (:func:`cad.sim.identify_joints.identify`)."""
    return identify_joints.identify(pred, log, path)


__all__ = ["Prediction5", "build_folder", "build_report", "identify", "predict", "predict_from_build"]
