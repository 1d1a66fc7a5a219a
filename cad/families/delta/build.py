"""The delta's build (issue 36): one call to the build driver
(:func:`cad.pipeline.run.run_family`) with the delta's stages. The parts and the assembly
are :func:`cad.families.delta.assembly.assemble` (base, three motors in brackets, upper arms,
parallelogram rods with ball joints, effector with a handle); every pair of solids is checked
at every point of the design's workspace grid; the dynamics are the task-space mass matrix
Lambda(x) from the solids' body mass properties and the resolved device's rotor inertia
(:func:`cad.families.delta.dynamics.mass_matrix_from_bodies_kg`, eq 1) over that grid, and
the first structural mode at the workspace centre
(:func:`cad.families.delta.structure.first_mode`).

Report keys the delta adds to the driver's common ones (``moving_mass_g``, ``total_mass_g``,
``bodies``, ``interference``, ``bom`` with the resolved device's encoders, ...;
:class:`cad.families.delta.contract.DeltaReport`): ``apparent_mass``
(``Lambda_max_eig_g`` / ``Lambda_min_eig_g``: the largest and smallest eigenvalue of Lambda
over the grid, where), ``structure`` (``first_mode_Hz``, ``compliance_max_um_per_N``, the
boundary conditions), ``workspace_points``, ``ball_joints`` (the joints' tilt against their
catalog range: :func:`cad.families.delta.ball_joints.range_check`), ``gravity`` (the motor
torques gravity takes over the grid: :func:`gravity_load`), ``notes``. The motors and
encoders are the
resolved device's (:func:`cad.device.resolve_device`: ``parts.motor`` with ``[motor]``,
``parts.encoder``).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from cad.assembly import interference as itf
from cad.device import encoder_bom_rows, resolve_device
from cad.dynamics.delta import G_M_S2
from cad.errors import DesignError
from cad.families.delta import capstan
from cad.families.delta import hardware as hw
from cad.families.delta.assembly import assemble
from cad.families.delta.ball_joints import range_check
from cad.families.delta.capstan import rope_stiffness_Nm_per_rad
from cad.families.delta.clearance import layout_clashes
from cad.families.delta.design import JOINTS
from cad.families.delta.dynamics import gravity_hold_torques_Nm, mass_matrix_from_bodies_kg
from cad.families.delta.layout import body_poses
from cad.families.delta.reach import check_workspace
from cad.families.delta.report_map import APPARENT_MASS_MAP, plot_apparent_mass_map
from cad.families.delta.sim import sim_model
from cad.families.delta.structure import first_mode, peak_stress_over, sections_from_parts
from cad.pipeline import family
from cad.pipeline.run import Stages, run_family
from cad.pipeline.views import write_sim_model


def check_options(design, fidelity: str, phi1_deg, formats=frozenset()) -> None:
    """Refuse what the delta's build cannot do, before any CAD (DesignError)."""
    if phi1_deg is not None:
        raise DesignError("--phi1-deg", "a delta has no crank: its pose is the workspace centre")
    check_workspace(design)  # the grid reached, before any solid (cad.families.delta.reach)
    check_ball_joint_fits(design)
    clash = "; ".join(layout_clashes(design)) if design.mechanism.joint_offset_mm > 0 else ""
    if clash:
        raise DesignError("mechanism.joint_offset_mm", f"{design.mechanism.joint_offset_mm:g} mm: "
                          f"the knee's layout clashes over the workspace: {clash}")


def check_ball_joint_fits(design) -> None:
    """Refuse a ball joint whose housing reaches below the effector cross bars
    (:func:`cad.families.delta.hardware.effector_plate_depth_mm` deeper than the bars' radius):
    the effector plate would hang under the sockets and the bars stand above it on nothing (no
    spacer is drawn yet). DesignError naming ``parts.ball_joint``."""
    bj = hw.design_ball_joint(design)
    if hw.effector_plate_depth_mm(bj.socket_d_mm) > hw.CROSS_BAR_D_MM / 2:
        raise DesignError("parts.ball_joint", f"{bj.key}: its d{bj.socket_d_mm:g} mm housing reaches below the "
                          f"d{hw.CROSS_BAR_D_MM:g} mm effector cross bars, so the effector plate would hang "
                          "under the sockets with the bars on nothing (no spacer is drawn yet); a build takes a "
                          "joint whose housing fits within the bars (ball-link-4.8); the analyses (gii, the "
                          "tilt check) take any catalog joint")


def interference(b) -> dict:
    """Every pair of solids at every workspace point (:func:`cad.assembly.interference.
    check_model`); InterferenceError naming the pair, the point and the volume unless
    allowed."""
    rep = itf.check_model(b.model, fail_fast=not b.allow_interference, same_body=b.same_body())
    if not b.allow_interference:
        itf.raise_on_collision(rep, 0.0)
    out = rep.as_dict()
    out["overlap_threshold_mm3"] = itf.OVERLAP_MIN_MM3
    return out


@dataclasses.dataclass(frozen=True)
class DeltaDynamics:
    """The delta's dynamics from the solids (``Build.dyn``): the largest / smallest
    eigenvalue of Lambda(x) over the workspace grid (g) and where (mm), the rotor inertia
    used (kg m^2) and its motor, the structure at the centre (first mode Hz, compliance
    um/N, boundary conditions; the stresses with every motor at +-its peak torque
    ``stress_torque_Nm``, worst over the workspace grid:
    :func:`cad.families.delta.structure.peak_stress_over`)."""

    Lambda_max_eig_g: float
    at_max_mm: list
    Lambda_min_eig_g: float
    at_min_mm: list
    rotor_inertia_kg_m2: float
    motor: str
    structure: dict
    #: (n, 3) Lambda's eigenvalues (g, ascending) at each workspace grid point (the report's map)
    eig_g: tuple = ()
    #: the gravity load over the grid (:func:`gravity_load`), the report's ``gravity``
    gravity: dict = dataclasses.field(default_factory=dict)


def gravity_load(design, X, bodies: dict, ratios) -> dict:
    """The motor torques that hold the solids still against gravity (-z, base frame) over the
    workspace grid ``X`` (N, 3) mm: joint torques J^-T grad_x V of every moving body's weight
    at its centre (:func:`cad.families.delta.dynamics.gravity_hold_torques_Nm`, ``bodies`` the
    build's {body: MassProps}), at the motor divided by each transmission's ratio n_i.
    ``joint_torque_max_Nm`` (3,): each joint's largest |tau| (N m) and ``at_mm`` where;
    ``motor_torque_max_Nm`` / ``motor_at_mm`` / ``motor_joint``: the largest |tau_i| / n_i over
    the joints and the grid, where and which joint; ``g_m_s2``."""
    tau = np.abs(gravity_hold_torques_Nm(design.mechanism, X, design.parallelogram_width_mm, bodies))
    motor = tau / np.asarray(ratios, float)[None, :]
    k = np.argmax(tau, axis=0)
    n, j = np.unravel_index(int(np.argmax(motor)), motor.shape)
    return {"joint_torque_max_Nm": [float(tau[k[i], i]) for i in range(3)],
            "at_mm": [X[k[i]].tolist() for i in range(3)], "motor_torque_max_Nm": float(motor[n, j]),
            "motor_at_mm": X[n].tolist(), "motor_joint": JOINTS[j], "g_m_s2": G_M_S2}


def drum_props(instances, props: dict) -> list | None:
    """(3,) the mass properties (:class:`cad.massprops.props.MassProps`, SI, upper_i's body
    frame) of the capstan parts on each upper arm (instances ``upper_i.capstan_*``: the drum
    sector, its anchor screw, tensioner and nut; None on a direct-drive arm), from the same
    per-kind properties Lambda(x) sums (``props``: :func:`cad.pipeline.family.kind_props`);
    None when no arm carries a drum."""
    out = []
    for i in range(3):
        mine = [x for x in instances if x.body == f"upper_{i}" and x.name.startswith(f"upper_{i}.capstan_")]
        out.append(family.body_props(mine, props).get(f"upper_{i}") if mine else None)
    return None if all(v is None for v in out) else out


def _dynamics(b) -> DeltaDynamics:
    """Lambda(x) over the workspace grid from the body mass properties and each motor's rotor
    through its transmission (n^2 (J_m + J_capstan), the resolved device's), the first mode at
    the centre (the capstans' ropes as springs at the motor axes, the drums' solids on the
    arms: :func:`drum_props`, the rods' end joints the drawn parts' masses:
    :func:`cad.families.delta.structure.sections_from_parts`), the stresses at each
    motor's peak torque through its ratio."""
    d, X = b.design, b.model.extra.workspace_mm
    dev = resolve_device(d)
    mot = dev.motor  # the motor the BOM orders, [motor] table applied
    rotors = [dev.joint_rotor_inertia_kg_m2(j) for j in JOINTS]  # n^2 (J_m + J_capstan) each
    rotor = rotors[0]
    lam = mass_matrix_from_bodies_kg(d.mechanism, X, d.parallelogram_width_mm, b.bodies, rotors)
    eig = np.linalg.eigvalsh(0.5 * (lam + np.swapaxes(lam, 1, 2)))
    hi, lo = int(np.argmax(eig[:, -1])), int(np.argmin(eig[:, 0]))
    centre = np.asarray(d.workspace["center_mm"], float)
    on_arms = [x for x in b.model.instances if x.body.startswith("upper_") and ".capstan_" in x.name]
    sec = sections_from_parts(d.mechanism.effector_radius_mm, d.parallelogram_width_mm, b.instances, b.props)
    st = first_mode(d.mechanism, centre, d.parallelogram_width_mm, sec,
                    rope_k_Nm_per_rad=rope_stiffness_Nm_per_rad(d, dev),
                    drums=drum_props(on_arms, b.props) if on_arms else None)
    taus = np.array([mot.spec.torque_peak_mNm * 1e-3 * dev.transmission(j).ratio for j in JOINTS])
    tau = float(taus.max())
    ps = peak_stress_over(d.mechanism, X, d.parallelogram_width_mm, taus if taus.min() < tau else tau)
    grav = gravity_load(d, X, b.bodies, [dev.transmission(j).ratio for j in JOINTS])
    return DeltaDynamics(gravity=grav,
        Lambda_max_eig_g=float(eig[hi, -1] * 1e3), at_max_mm=X[hi].tolist(),
        Lambda_min_eig_g=float(eig[lo, 0] * 1e3), at_min_mm=X[lo].tolist(),
        rotor_inertia_kg_m2=rotor, motor=mot.name, eig_g=tuple(map(tuple, eig * 1e3)),
        structure={"first_mode_Hz": st["first_mode_Hz"],
                   "compliance_max_um_per_N": st["compliance_max_um_per_N"],
                   "boundary": st["boundary"], "stress_torque_Nm": tau,
                   **{k: ps[k] for k in ("max_stress_MPa", "critical_member", "critical_load_N",
                                         "rod_compression_max_N", "rod_stress_max_MPa",
                                         "rod_buckling_N", "rod_buckling_margin", "points")},
                   "stress_at_mm": ps["at_mm"], "buckling_at_mm": ps["buckling_at_mm"]})


def _report(b) -> dict:
    dy = b.dyn
    joints = range_check(b.design)
    return {"ball_joints": joints,
        "apparent_mass": {k: getattr(dy, k) for k in ("Lambda_max_eig_g", "at_max_mm",
                                                      "Lambda_min_eig_g", "at_min_mm",
                                                      "rotor_inertia_kg_m2", "motor")},
        "structure": dy.structure, "workspace_points": len(b.model.extra.workspace_mm),
        "gravity": dy.gravity,
        "notes": [f"Lambda(x) from the solids and the {dy.motor} rotor over "
                  f"{len(b.model.extra.workspace_mm)} workspace points (eq 1, base frame)",
                  joints["line"]]}


def _md_rows(r: dict) -> list[tuple[str, str]]:
    a, s = r["apparent_mass"], r["structure"]
    return [("moving mass", f"{r['moving_mass_g']:.1f} g"),
            ("total mass", f"{r['total_mass_g']:.1f} g"),
            ("apparent mass, largest eigenvalue of Lambda", f"{a['Lambda_max_eig_g']:.1f} g"),
            ("apparent mass, smallest eigenvalue of Lambda", f"{a['Lambda_min_eig_g']:.1f} g"),
            ("first structural mode (centre)", f"{s['first_mode_Hz']:.1f} Hz"),
            ("ball joints' largest tilt (range)", f"{r['ball_joints']['max_tilt_deg']:.2f} deg "
             f"({r['ball_joints']['range_deg']:g} deg: {r['ball_joints']['verdict']})"),
            ("workspace points checked", str(r["workspace_points"]))]


def _figures(b) -> list[str]:
    """The apparent-mass map over the workspace grid (:mod:`cad.families.delta.report_map`)."""
    plot_apparent_mass_map(b.design.name, b.model.extra.workspace_mm, b.dyn.eig_g, b.out_dir / APPARENT_MASS_MAP)
    return [APPARENT_MASS_MAP]


def _stroke(design) -> dict:
    """The viewer's motion: the effector along the workspace's x extent at its centre height."""
    c = np.asarray(design.workspace["center_mm"], float)
    X = design.workspace_points()
    xs = np.linspace(X[:, 0].min(), X[:, 0].max(), 9)
    P = np.column_stack([xs, np.full(9, c[1]), np.full(9, c[2])])
    return body_poses(design.mechanism, P, design.parallelogram_width_mm)


def _sim_files(b) -> list[str]:
    """``<name>.xml`` (MJCF) when asked: :func:`cad.families.delta.sim.sim_model` at the
    workspace centre, masses from the build's bodies, motors of the resolved device."""
    return write_sim_model(lambda: sim_model(b.design, b.bodies, resolve_device(b.design)),
                           b.out_dir, b.formats, b.design.name)


def _encoder_rows(design) -> list[dict]:
    """The bought encoders (no solid: on each motor's rear shaft), the resolved device's
    (:func:`cad.device.encoder_bom_rows`; in assembly.md ``encoder_0`` .. ``encoder_2``, on
    ``motor_0`` .. ``motor_2``: the delta numbers its arms, motors and joints theta_i from 0), and the capstans' ropes with their cut lengths
    (:func:`cad.families.delta.capstan.bom_lines`)."""
    dev = resolve_device(design)
    enc = encoder_bom_rows(dev)
    if len(enc) == 1 and enc[0]["quantity"] == len(JOINTS):  # one per motor_i: numbered as the motors
        enc[0]["instance_names"] = [f"encoder_{i}" for i in range(len(JOINTS))]
    return enc + capstan.bom_lines(design, dev)


#: The final checks of the delta's assembly.md (the steps are the driver's, from the parts).
ASSEMBLY_CHECKS = (
    "each upper arm turned by hand over its motor angle range moves the effector over the "
    "whole workspace box (report.md) with no binding, the effector level at every point",
    "every ball stud sits in its socket with the running clearance; the two rods of each "
    "parallelogram are held onto their balls (the preload, e.g. a spring across the pair, is "
    "not drawn)",
    "the arm hubs do not slip on their motor shafts under a hand load at the effector (each "
    "held by its set screw, tightened in its arm's step)",
)


#: The capstan delta's third check: the arms turn on their own axles.
AXLE_CHECK = ("each arm turns freely on its axle in its bearing and its hub does not slip on the "
              "axle under a hand load at the effector (the hub's fastening, a clamp or a bond, is "
              "not drawn)")


def assembly_checks(design) -> tuple[str, ...]:
    """assembly.md's final checks: :data:`ASSEMBLY_CHECKS`, with capstans the axle check for
    the motor-shaft one and each capstan's winding and tensioning steps."""
    dev = resolve_device(design)
    if not any(t.is_capstan for t in dev.transmissions):
        return ASSEMBLY_CHECKS
    return ASSEMBLY_CHECKS[:2] + (AXLE_CHECK,) + capstan.assembly_steps(design, dev)


STAGES = Stages(
    check_options=check_options, assemble=assemble, interference=interference, report=_report,
    md_rows=_md_rows, stroke=_stroke, motion_label="workspace grid", dynamics=_dynamics,
    preview_title=lambda b: f"{b.design.name}: delta at the workspace centre",
    no_solid_rows=_encoder_rows, more_files=_sim_files, figures=_figures,
    md_images=(("apparent mass over the workspace: Lambda's largest and smallest eigenvalue at "
                "every grid point, one panel per height", APPARENT_MASS_MAP),),
    assembly=lambda design: (None, assembly_checks(design)))


def build(design, out_dir: Path, formats: set[str], *, fidelity: str = "fabrication",
          allow_interference: bool = False, progress=None, phi1_deg: float | None = None) -> dict:
    """Build ``design`` into ``out_dir`` through the one build driver (module docstring).
    Raises DesignError, InterferenceError (a clash at a workspace point), MeshError."""
    return run_family(STAGES, design, out_dir, formats, fidelity=fidelity,
                      allow_interference=allow_interference, progress=progress, phi1_deg=phi1_deg)
