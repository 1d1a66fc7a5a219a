"""The four-bar as a simulator model (MJCF/URDF, issue 14), from the build's assembly.

Bodies (spanning tree): ``crank`` (hinge ``crank`` at A1 on the world, value = phi1),
``coupler`` (hinge ``coupler`` at A2 on the crank, value = phi2 - phi1) and ``rocker``
(hinge ``rocker`` at A4 on the world, value = phi3). The loop closes at A3: sites
``A3_coupler`` and ``A3_rocker``, MJCF ``connect`` ``loop_A3``. The handle point P is the
site ``handle`` on the coupler (at the knob's base height). Each body carries its link's
mass properties exactly as ``report.json`` ``links`` (link frame, SI), the meshes of its
parts, and the crank the motor (armature Jm, torque limit from the motor catalog).
Ground parts are world meshes.
"""

from __future__ import annotations

import math

import numpy as np

from cad.data.materials import get_material
from cad.device import resolve_device
from cad.errors import DesignError
from cad.export.sim import SimBody, SimLoop, SimMesh, SimModel, SimMotor
from cad.families.fourbar.pose import body_transforms
from cad.kinematics.fourbar import solve


def _rgba(material: str) -> tuple[float, float, float, float]:
    return (*get_material(material).color_rgb, 1.0)


def motor_torque_Nm(motor) -> float:
    """The catalog peak torque of ``motor`` (N m); DesignError when the catalog has none."""
    if motor.torque_peak_mNm is None:
        raise DesignError(
            "parts.motor",
            f"the catalog has no torque limit for {motor.key!r}: the mjcf/urdf export and "
            "`hapticad wall` need one (use maxon-re35)",
        )
    return motor.torque_peak_mNm * 1e-3


def sim_model(design, asm, link_props: dict, Jm_kg_m2: float, motor, phi1_rad: float) -> SimModel:
    """SimModel of a four-bar build posed at crank angle ``phi1_rad`` (module docstring).

    ``asm``: the build's :class:`cad.assembly.model.AssemblyModel`; ``link_props``: MassProps
    per body in the link frame (SI); mesh files are ``parts/<kind>.stl`` of made parts.
    ``Jm_kg_m2``: the rotor inertia at the crank (the crank's armature: n^2 J_m through a
    capstan of ratio n, :meth:`cad.device.ResolvedDevice.joint_rotor_inertia_kg_m2`); the
    motor's gear is n (the resolved device's transmission), its torque limit the motor's own.
    """
    n = resolve_device(design).transmission("crank").ratio
    fb = design.linkage
    pose = solve(fb, np.array([phi1_rad]))
    tf = {b: v[0] for b, v in body_transforms(fb, [phi1_rad]).items()}
    meshes: dict[str, list[SimMesh]] = {b: [] for b in ("ground", "crank", "coupler", "rocker")}
    handle_z_m = 0.0
    for inst in asm.instances:
        T = inst.tf_body_part
        if inst.kind.name == "handle":
            handle_z_m = float(T[2, 3]) * 1e-3
        if not (inst.kind.listed and inst.kind.made):
            continue
        meshes[inst.body].append(
            SimMesh(inst.name, f"{inst.kind.name}.stl", T[:3, 3] * 1e-3, T[:3, :3],
                    _rgba(inst.kind.material))
        )
    phi2, phi3 = float(pose.phi2_rad[0]), float(pose.phi3_rad[0])
    rel = np.linalg.inv(tf["crank"]) @ tf["coupler"]
    le = fb.le_mm * 1e-3

    def body(name, parent, T, joint_ref, sites, armature=0.0):
        mp = link_props[name]
        return SimBody(
            name=name, parent=parent, pos_m=T[:3, 3] * 1e-3, rot=T[:3, :3], joint=name,
            joint_ref_rad=joint_ref, mass_kg=float(mp.mass_kg), com_m=np.asarray(mp.com_m),
            inertia_com_kg_m2=np.asarray(mp.inertia_com_kg_m2), armature_kg_m2=armature,
            meshes=tuple(meshes[name]), sites=sites,
        )

    bodies = (
        body("crank", "world", tf["crank"], phi1_rad, {}, Jm_kg_m2),
        body("coupler", "crank", rel, phi2 - phi1_rad, {
            "A3_coupler": np.array([fb.l2_mm * 1e-3, 0.0, 0.0]),
            "handle": np.array([le * math.cos(fb.phi_e_rad), le * math.sin(fb.phi_e_rad), handle_z_m]),
        }),
        body("rocker", "world", tf["rocker"], phi3, {"A3_rocker": np.array([fb.l3_mm * 1e-3, 0.0, 0.0])}),
    )
    return SimModel(
        name=design.name,
        bodies=bodies,
        world_meshes=tuple(meshes["ground"]),
        loops=(SimLoop("loop_A3", "coupler", "A3_coupler", "rocker", "A3_rocker"),),
        motors=(SimMotor("motor", "crank", motor_torque_Nm(motor), gear=n),),
        meshdir="parts",
        comment=(
            f"hapticad {design.family} four-bar '{design.name}': world = R0 (origin A1, m), written at "
            f"phi1 = {phi1_rad!r} rad; joint crank = phi1, coupler = phi2 - phi1, rocker = phi3"
        ),
    )
