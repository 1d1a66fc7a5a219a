"""The pantograph families as simulator models (MJCF/URDF, issues 14 and 32): the twin-pantograph
mouse (:func:`sim_model`) and the plain 5-bar (:func:`fivebar_sim_model`, end of the module).

World frame: the kinematic base frame of :mod:`cad.families.pantograph.build` (metres, z up,
z = 0 on the base plate's top). Bodies (spanning tree), for each group ``g`` in
(``crank``, ``knob``) and side ``s`` in (``left``, ``right``):

* ``g_proximal_s``: hinge ``g_q_s`` at B_s on the world (value = the actuated angle q,
  isotropy paper Fig. 1), the motor ``g_motor_s`` (armature = the rotor inertia at the joint
  through its transmission, n^2 (J_m + J_capstan); ``gear`` = the ratio n; force range = the
  BOM motor's own peak torque, so the joint gets n T_peak, :func:`peak_torque_Nm`;
  ``[actuators] torque_max_Nm`` stays the GII's normalisation);
* ``g_distal_s``: hinge ``g_elbow_s`` at the elbow C_s (value = distal angle - q);
* ``crankshaft``: hinge ``theta`` at the main journal, on ``knob_distal_left`` (value =
  theta - the distal angle). Sites ``handle`` (main journal, the knob axis) and
  ``crank_pin``.

Three loops close the tree (MJCF ``connect``): ``loop_knob_E`` (knob right distal tip to
the main journal), ``loop_crank_left`` and ``loop_crank_right`` (crank distal tips to the
crank pin). Upper-group bodies are mirrored parts in z-up body frames (their mass
properties are those of the mirrored parts, exactly as ``report.json`` ``bodies``).
"""

from __future__ import annotations

import math

import numpy as np

from cad.data.materials import get_material
from cad.device import resolve_device
from cad.export.sim import SimBody, SimLoop, SimMesh, SimModel, SimMotor, rot_z


def _T(R: np.ndarray, p) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = p
    return T


def body_meshes(instances, body: str, T=None) -> tuple:
    """SimMesh of every instance of ``body`` with a solid (a made, listed kind: its STL is
    ``<kind>.stl``), read from the assembly model's instances (no hand list of a link's parts):
    placed by ``T @ tf_body_part`` (``T``: 4x4 mm, the sim body frame from the assembly's body
    frame; identity when they coincide). Names are the instances' names."""
    T = np.eye(4) if T is None else np.asarray(T, dtype=float)
    out = []
    for i in instances:
        if i.body != body or not (i.kind.made and i.kind.listed):
            continue
        tf = T @ i.tf_body_part
        out.append(SimMesh(i.name, f"{i.kind.name}.stl", tf[:3, 3] * 1e-3, tf[:3, :3],
                           (*get_material(i.kind.material).color_rgb, 1.0)))
    return tuple(out)


def peak_torque_Nm(device) -> dict[str, float]:
    """``{joint: N m}``: each motor's peak torque through its transmission
    (:meth:`cad.device.ResolvedDevice.joint_peak_torques_Nm`) -- the MJCF force range and the
    URDF effort. DesignError (``parts.motor``) when the motor states none."""
    return device.joint_peak_torques_Nm()


def _link_bodies(design, bodies: dict, lay: dict, ik, meshes) -> tuple:
    """The eight link bodies (proximal on the world, distal on its proximal) with their
    motors: ``(bodies, {distal body: 4x4 world mm}, motors)``; each motor's armature and gear
    through its transmission (:func:`cad.device.resolve_device`)."""
    a = design.params["base_mm"]
    l3 = design.params["distal_mm"]
    B = [(-a / 2, 0.0), (a / 2, 0.0)]

    dev = resolve_device(design)
    torque = peak_torque_Nm(dev)  # the BOM's motors through their transmissions, not [actuators]
    out: list[SimBody] = []
    world = {}
    motors = []
    for grp, fp, zs in (("crank", ik.crank, lay["lower_layers_z_mm"]),
                        ("knob", ik.knob, lay["upper_layers_z_mm"])):
        C = [fp.C_left_mm[0], fp.C_right_mm[0]]
        E = fp.E_mm[0]
        for i, side in enumerate(("left", "right")):
            q = float(fp.q_rad[0, i])
            psi = math.atan2(E[1] - C[i][1], E[0] - C[i][0])
            Tp = _T(rot_z(q), (B[i][0], B[i][1], zs[0]))
            Td = _T(rot_z(psi), (C[i][0], C[i][1], zs[1 + i]))
            world[f"{grp}_distal_{side}"] = Td
            pn, dn = f"{grp}_proximal_{side}", f"{grp}_distal_{side}"
            out.append(SimBody(
                name=pn, parent="world", pos_m=Tp[:3, 3] * 1e-3, rot=Tp[:3, :3], joint=f"{grp}_q_{side}",
                joint_ref_rad=q, mass_kg=float(bodies[pn].mass_kg), com_m=np.asarray(bodies[pn].com_m),
                inertia_com_kg_m2=np.asarray(bodies[pn].inertia_com_kg_m2),
                armature_kg_m2=dev.joint_rotor_inertia_kg_m2(f"{grp}_q_{side}"),
                meshes=meshes(pn, zs[0])))
            rel = np.linalg.inv(Tp) @ Td
            tip = {f"{grp}_tip_{side}": np.array([l3 * 1e-3, 0.0, 0.0])}
            out.append(SimBody(
                name=dn, parent=pn, pos_m=rel[:3, 3] * 1e-3, rot=rel[:3, :3], joint=f"{grp}_elbow_{side}",
                joint_ref_rad=psi - q, mass_kg=float(bodies[f"{grp}_distal"].mass_kg),
                com_m=np.asarray(bodies[f"{grp}_distal"].com_m),
                inertia_com_kg_m2=np.asarray(bodies[f"{grp}_distal"].inertia_com_kg_m2),
                meshes=meshes(dn, zs[1 + i]), sites=tip))
            n = dev.transmission(f"{grp}_q_{side}").ratio  # joint torque = n motor torque
            motors.append(SimMotor(f"{grp}_motor_{side}", f"{grp}_q_{side}", torque[f"{grp}_q_{side}"] / n, gear=n))
    return out, world, motors


def sim_model(design, bodies: dict, instances, lay: dict, home, ik) -> SimModel:
    """SimModel of the twin pantograph written at ``home`` (module docstring).

    ``bodies``: MassProps per body (link frame at its layer height, SI); ``instances``: the
    assembly model's part instances (body frames z = 0 on the base plate's top, mm), every
    instance with a solid reaching its body's meshes (:func:`body_meshes`, the body frame
    lifted to its layer height ``z``).
    """
    l6 = design.mechanism.crank_mm

    def meshes(body, z_mm):
        return body_meshes(instances, body, _T(np.eye(3), (0.0, 0.0, -z_mm)))

    out, world, motors = _link_bodies(design, bodies, lay, ik, meshes)
    th = float(home[2])
    Tc = _T(rot_z(th), (home[0], home[1], lay["web_z_mm"]))
    Tk = world["knob_distal_left"]
    rel = np.linalg.inv(Tk) @ Tc
    psi_k = math.atan2(Tk[1, 0], Tk[0, 0])
    cs = bodies["crankshaft"]

    def dz(z_mm: float) -> float:
        return (z_mm - lay["web_z_mm"]) * 1e-3

    out.append(SimBody(
        name="crankshaft", parent="knob_distal_left", pos_m=rel[:3, 3] * 1e-3, rot=rel[:3, :3],
        joint="theta", joint_ref_rad=th - psi_k, mass_kg=float(cs.mass_kg), com_m=np.asarray(cs.com_m),
        inertia_com_kg_m2=np.asarray(cs.inertia_com_kg_m2),
        meshes=meshes("crankshaft", lay["web_z_mm"]),
        sites={"handle": np.zeros(3), "crank_pin": np.array([l6 * 1e-3, 0.0, 0.0]),
               # loop sites on the journal axes at the height of the distal tip they meet
               "journal": np.array([0.0, 0.0, dz(lay["upper_layers_z_mm"][2])]),
               "crank_pin_left": np.array([l6 * 1e-3, 0.0, dz(lay["lower_layers_z_mm"][1])]),
               "crank_pin_right": np.array([l6 * 1e-3, 0.0, dz(lay["lower_layers_z_mm"][2])])}))
    loops = [
        SimLoop("loop_knob_E", "knob_distal_right", "knob_tip_right", "crankshaft", "journal"),
        SimLoop("loop_crank_left", "crank_distal_left", "crank_tip_left", "crankshaft", "crank_pin_left"),
        SimLoop("loop_crank_right", "crank_distal_right", "crank_tip_right", "crankshaft", "crank_pin_right"),
    ]
    wm = body_meshes(instances, "ground")
    return SimModel(
        name=design.name, bodies=tuple(out), world_meshes=wm, loops=tuple(loops), motors=tuple(motors),
        meshdir=".",
        comment=(f"hapticad twin pantograph '{design.name}': world = base frame (m), written at home "
                 f"(x, y, theta) = ({home[0]!r} mm, {home[1]!r} mm, {th!r} rad)"),
    )


# ------------------------------------------------------------------ the plain 5-bar
#: Spanning tree of the plain 5-bar (body -> parent): two chains from the base, the handle
#: pin on the left distal link's tip (it runs in both distal clevises' bearings).
FIVEBAR_TREE = {"proximal_left": "world", "distal_left": "proximal_left",
                "proximal_right": "world", "distal_right": "proximal_right",
                "handle": "distal_left"}
#: Hinge name of each body of :data:`FIVEBAR_TREE` (the motors' joints are the resolved
#: device's joint names, :func:`cad.device.resolve_device`).
FIVEBAR_JOINTS = {"proximal_left": "q_left", "distal_left": "elbow_left",
                  "proximal_right": "q_right", "distal_right": "elbow_right",
                  "handle": "handle_spin"}


def _planar_angle(T_parent: np.ndarray, T_child: np.ndarray) -> float:
    """Angle of the child's x axis about z from the parent's (both frames z up)."""
    R = T_parent[:3, :3].T @ T_child[:3, :3]
    return float(np.arctan2(R[1, 0], R[0, 0]))


def fivebar_sim_model(design, model, bodies: dict) -> SimModel:
    """SimModel of the plain 5-bar pantograph at home, from the build's assembly model.

    ``model``: the :class:`cad.assembly.model.AssemblyModel` (bodies ``proximal_*``,
    ``distal_*``, ``handle``; frames z up, z = 0 on the base plate's top, mm); ``bodies``:
    MassProps per body in the same body frames (SI) -- exactly ``report.json`` ``bodies``.
    World = the kinematic base frame (m). Tree :data:`FIVEBAR_TREE`, hinges
    :data:`FIVEBAR_JOINTS` (``q_left`` / ``q_right`` = the actuated angles q of isotropy paper
    Fig. 2; ``handle_spin`` = the handle pin's free turn in its bearings). One loop,
    ``loop_E``: the right distal tip meets the left distal tip at E (both hinges parallel
    to z, so one point closes it). Motors ``motor_left`` / ``motor_right``: armature = the
    BOM motor's rotor inertia reflected through its transmission (n^2 (J_m + J_capstan)),
    ``gear`` = the transmission's ratio n (a capstan: joint torque = n motor torque), force
    range = the motor's own peak torque (:func:`cad.device.resolve_device`), not the GII's
    ``[actuators]`` normalisation.
    """
    T = model.tf_world_body
    l3 = design.params["distal_mm"] * 1e-3
    dev = resolve_device(design)
    arm = {m.joint: dev.joint_rotor_inertia_kg_m2(m.joint) for m in dev.motors}

    def meshes(body):
        return body_meshes(model.instances, body)

    out = []
    for name, parent in FIVEBAR_TREE.items():
        Tp = np.eye(4) if parent == "world" else T[parent]
        rel = np.linalg.inv(Tp) @ T[name]
        mp, joint = bodies[name], FIVEBAR_JOINTS[name]
        sites = {f"{name}_tip": np.array([l3, 0.0, 0.0])} if name.startswith("distal") else {}
        if name == "handle":
            sites = {"handle": np.zeros(3)}
        out.append(SimBody(name=name, parent=parent, pos_m=rel[:3, 3] * 1e-3, rot=rel[:3, :3],
                           joint=joint, joint_ref_rad=_planar_angle(Tp, T[name]),
                           mass_kg=float(mp.mass_kg), com_m=np.asarray(mp.com_m),
                           inertia_com_kg_m2=np.asarray(mp.inertia_com_kg_m2),
                           armature_kg_m2=arm.get(joint, 0.0), meshes=meshes(name), sites=sites))
    peak = peak_torque_Nm(dev)  # at the joints, n T_peak
    motors = tuple(SimMotor(f"motor_{m.joint.split('_', 1)[1]}", m.joint,
                            peak[m.joint] / dev.transmission(m.joint).ratio,
                            gear=dev.transmission(m.joint).ratio)
                   for m in dev.motors)
    ground = meshes("ground")
    home = model.extra.home_mm
    return SimModel(
        name=design.name, bodies=tuple(out), world_meshes=ground,
        loops=(SimLoop("loop_E", "distal_right", "distal_right_tip", "distal_left", "distal_left_tip"),),
        motors=motors, meshdir="parts",
        comment=(f"hapticad 5-bar pantograph '{design.name}': world = base frame (m), written at home "
                 f"(x, y) = ({float(home[0])!r} mm, {float(home[1])!r} mm); joints q_left, q_right = "
                 "actuated angles, elbow_* = distal - proximal angle, handle_spin = the handle pin's turn"),
    )
