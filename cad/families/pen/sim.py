"""The haptic pen as an MJCF model (:mod:`cad.export.sim`), loops closed by equality
constraints.

World = the kinematic frame of :mod:`cad.families.pen.layout` (metres). Bodies are the
assembly model's bodies with the same frames (each joint a hinge about the child's z axis),
written at home. Spanning tree per arm X: ``X_waist`` (hinge ``X_q_waist`` on the world, the
waist motor) -> ``X_proximal_lower`` (``X_q_lower``, motor) -> ``X_distal_lower`` ->
``X_yoke`` -> ``X_ring``; ``X_waist`` -> ``X_proximal_upper`` (``X_q_upper``, motor) ->
``X_distal_upper``; the ``pen`` hangs on ``A_ring`` (hinge about b).

Loops (MJCF ``connect``): ``X_loop_E`` -- the upper distal tip to the lower distal tip (the
5-bar; its hinges are parallel so one point closes it); ``B_loop_b1`` / ``B_loop_b2`` -- two
points of the b axis of B's ring on the pen (a hinge closed by two points on its axis).

Motors: on each motor hinge the armature is the rotor's inertia at the joint through its
transmission, n^2 (J_m + J_capstan) (:meth:`cad.device.ResolvedDevice.joint_rotor_inertia_kg_m2`),
``gear`` = the ratio n and the force range the BOM motor's own peak torque (the joint gets
n T_peak); direct drive: n = 1, J_m.
"""

from __future__ import annotations

import numpy as np

from cad.data.materials import get_material
from cad.device import resolve_device
from cad.export.sim import SimBody, SimLoop, SimMesh, SimModel, SimMotor, write_sim_files

#: Distance of the two b-axis closure points from the gimbal centre (m).
B_AXIS_POINT_M = 0.01

TREE = {
    "waist": "world", "proximal_lower": "waist", "distal_lower": "proximal_lower",
    "yoke": "distal_lower", "ring": "yoke", "proximal_upper": "waist",
    "distal_upper": "proximal_upper",
}


def _joint_value(T_parent: np.ndarray, T_child: np.ndarray) -> float:
    """Angle of the child's x axis about its z axis from the parent's (written pose)."""
    R = T_parent[:3, :3].T @ T_child[:3, :3]
    return float(np.arctan2(R[1, 0], R[0, 0])) if np.allclose(R[:, 2], [0, 0, 1]) else 0.0


def sim_model(design, model, bodies: dict) -> SimModel:
    """SimModel of the pen at home (module docstring). ``bodies``: MassProps per body (body
    frame, SI)."""
    T = model.tf_world_body
    l3 = design.params["distal_mm"] * 1e-3
    l6 = design.mechanism.pen_mm * 1e-3
    made = {i.kind.name for i in model.instances if i.kind.made and i.kind.listed}
    dev = resolve_device(design)  # the BOM's motors through their transmissions
    rotor = {m.joint: dev.joint_rotor_inertia_kg_m2(m.joint) for m in dev.motors}  # n^2 (J_m + J_c)
    gear = {m.joint: dev.transmission(m.joint).ratio for m in dev.motors}
    # actuator limits: each BOM motor's own peak torque (N m; the joint gets n times it through
    # gear), not the GII's [actuators] normalisation
    tau = {j: t / gear[j] for j, t in dev.joint_peak_torques_Nm().items()}

    def meshes(body):
        return tuple(SimMesh(i.name, f"{i.kind.name}.stl", i.tf_body_part[:3, 3] * 1e-3,
                             i.tf_body_part[:3, :3], (*get_material(i.kind.material).color_rgb, 1.0))
                     for i in model.instances if i.body == body and i.kind.name in made)

    out, motors = [], []

    def add(name, parent, joint, sites=None, armature=0.0):
        Tp = np.eye(4) if parent == "world" else T[parent]
        rel = np.linalg.inv(Tp) @ T[name]
        mp = bodies[name]
        out.append(SimBody(name=name, parent=parent, pos_m=rel[:3, 3] * 1e-3, rot=rel[:3, :3],
                           joint=joint, joint_ref_rad=_joint_value(Tp, T[name]),
                           mass_kg=float(mp.mass_kg), com_m=np.asarray(mp.com_m),
                           inertia_com_kg_m2=np.asarray(mp.inertia_com_kg_m2),
                           armature_kg_m2=armature, meshes=meshes(name), sites=sites or {}))

    for arm in ("A", "B"):
        for part, parent in TREE.items():
            name = f"{arm}_{part}"
            par = "world" if parent == "world" else f"{arm}_{parent}"
            motor = part.split("_")[-1] if part in ("waist", "proximal_lower", "proximal_upper") else None
            sites = {f"{name}_tip": np.array([l3, 0.0, 0.0])} if part.startswith("distal") else {}
            if part == "ring" and arm == "B":
                sites = {f"B_ring_b{k}": np.array([0.0, s * B_AXIS_POINT_M, 0.0])
                         for k, s in ((1, 1), (2, -1))}
            add(name, par, f"{arm}_q_{motor}" if motor else f"{arm}_j_{part}", sites,
                rotor[f"{arm}_q_{motor}"] if motor else 0.0)
            if motor:
                j = f"{arm}_q_{motor}"
                motors.append(SimMotor(f"{arm}_motor_{motor}", j, tau[j], gear=gear[j]))
    add("pen", "A_ring", "A_j_pen", {f"pen_b{k}": np.array([l6, 0.0, s * B_AXIS_POINT_M])
                                     for k, s in ((1, 1), (2, -1))})
    loops = [SimLoop(f"{a}_loop_E", f"{a}_distal_upper", f"{a}_distal_upper_tip",
                     f"{a}_distal_lower", f"{a}_distal_lower_tip") for a in ("A", "B")]
    loops += [SimLoop(f"B_loop_b{k}", "B_ring", f"B_ring_b{k}", "pen", f"pen_b{k}") for k in (1, 2)]
    ground = tuple(SimMesh(i.name, f"{i.kind.name}.stl", i.tf_body_part[:3, 3] * 1e-3,
                           i.tf_body_part[:3, :3], (*get_material(i.kind.material).color_rgb, 1.0))
                   for i in model.instances if i.body == "ground" and i.kind.name in made)
    return SimModel(name=design.name, bodies=tuple(out), world_meshes=ground, loops=tuple(loops),
                    motors=tuple(motors), meshdir="parts",
                    comment=f"hapticad haptic pen '{design.name}': world = kinematic frame (m), "
                            "written at home (workspace centre, pen along +x)")


def write_mjcf(design, model, bodies: dict, out_dir) -> list[str]:
    """``<name>.xml`` (MJCF) into ``out_dir``; returns its file name."""
    return [p.name for p in write_sim_files(sim_model(design, model, bodies), out_dir, {"mjcf"},
                                            design.name)]
