"""The delta as a MuJoCo model (``hapticad build --formats mjcf``, issue 36 §5).

World frame: the delta's base frame (metres, z up, the effector below; MuJoCo's gravity is
-z). Bodies (the spanning tree; mass properties from the solids, ``report.json`` ``bodies``,
turned into each MJCF body frame):

* ``upper_i`` on the world: hinge ``theta_i`` about motor axis t_i (value = the motor angle
  theta_i of :mod:`cad.kinematics.delta`, ref = its value at the written pose), armature
  n^2 (J_m + J_capstan) (the resolved device's rotor through its transmission), motor
  ``motor_i`` with ``gear`` n and force range the motor's own peak torque (the joint gets n
  times it). Body frame: the layout's upper_i
  frame (:mod:`cad.families.delta.layout`) with z along the motor axis (x along the arm,
  y = -z_layout, z = t_i);
* ``lower_i_a`` / ``lower_i_b`` on ``upper_i``: ball joint ``ball_i_a`` / ``ball_i_b`` at
  the rod's top ball (the layout's rod frames); site ``lower_i_s_end`` at its lower ball;
* with Stamper's joint offset g > 0 (the Falcon): ``knee_i`` on ``upper_i``, hinge
  ``knee_i`` about t_i at the elbow (body frame: the layout's knee_i frame with z along
  t_i, as the upper arm's), and the rods on ``knee_i``, each on a hinge ``rod_i_s`` about
  its own z (the normal of the parallelogram's plane span(k_i, t_i), the rod frame of
  :mod:`cad.families.delta.layout`) at its top joint: the rods swing in the plane of the
  knee, which holds the knee in line with the rods' projection on the arm's plane (the
  Falcon's universal joints, Stamper's model that the kinematics and eq (1) state; with
  balls at both ends of the rods the knee would turn freely);
* ``effector`` on ``lower_0_a``: ball joint ``ball_effector`` at rod 0a's lower ball (the
  body frame: base axes, origin there); sites ``joint_i_s`` at its six ball studs and
  ``handle`` at the effector centre P.

The five other lower balls close the loops: MJCF ``connect`` ``loop_i_s`` (site
``lower_i_s_end`` on ``joint_i_s``). The 24 joint coordinates less 15 loop equations leave 9
motions: the effector's three translations and each rod's spin about its own axis (free in
the hardware too; it carries the rod's axial inertia only). With the knee: 15 joint
coordinates, 15 loop equations of rank 12 (each parallelogram is a planar loop: one of its
connect rows is redundant), 3 motions. No meshes: the model is for the
dynamics (the part STLs and the assembly STEP show the shapes). No URDF (ball joints).
"""

from __future__ import annotations

import numpy as np

from cad.export.sim import SimBody, SimLoop, SimModel, SimMotor
from cad.families.delta.layout import ARMS, body_poses
from cad.kinematics.delta import ik

MM = 1e-3
#: Columns: the MJCF upper-arm frame's axes in the layout's upper_i frame (x, -z, y): its z
#: is the motor axis t_i, the hinge's axis.
ARM_AXES = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])


def _frames(design, P_mm) -> dict[str, np.ndarray]:
    """{body: (4, 4) tf_world_mjcf in metres} at effector point ``P_mm`` (3,)."""
    d = design.mechanism
    w = design.parallelogram_width_mm
    tf = {k: v[0].copy() for k, v in body_poses(d, np.asarray(P_mm, float)[None], w).items()}
    out = {}
    for k, T in tf.items():
        T[:3, 3] *= MM
        if k.startswith(("upper_", "knee_")):
            T[:3, :3] = T[:3, :3] @ ARM_AXES
        out[k] = T
    eff = out["effector"]
    eff[:3, 3] = eff[:3, 3] + (d.effector_radius_mm * d.radial[0] - w / 2 * d.tangential[0]) * MM
    return out


def _local(T_parent: np.ndarray, T_child: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    rel = np.linalg.inv(T_parent) @ T_child
    return rel[:3, 3], rel[:3, :3]


def _props(mp, R_body_mjcf: np.ndarray, shift_m=np.zeros(3)) -> tuple:
    """(mass, com (3,), inertia about the com (3, 3)) in an MJCF frame whose axes are the
    columns ``R_body_mjcf`` of the body frame and whose origin is at ``shift_m`` (body)."""
    if mp is None:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    R = np.asarray(R_body_mjcf)
    return (mp.mass_kg, R.T @ (np.asarray(mp.com_m) - shift_m),
            R.T @ np.asarray(mp.inertia_com_kg_m2) @ R)


def knee_body(bodies: dict, T: dict, i: int) -> SimBody:
    """``knee_i`` on ``upper_i`` (g > 0): hinge ``knee_i`` about t_i (the body's z) at the
    elbow, ref = the knee's angle from the upper arm's x about t_i at the written pose;
    ``T``: the frames of :func:`_frames`; ``bodies`` as :func:`sim_model`'s."""
    pos, rot = _local(T[f"upper_{i}"], T[f"knee_{i}"])
    m, c, inertia = _props(bodies.get(f"knee_{i}"), ARM_AXES)
    return SimBody(f"knee_{i}", f"upper_{i}", pos, rot, f"knee_{i}",
                   float(np.arctan2(rot[1, 0], rot[0, 0])), m, c, inertia)


def sim_model(design, bodies: dict, device, P_mm=None) -> SimModel:
    """The :class:`cad.export.sim.SimModel` of the delta (module docstring) with the effector
    centre at ``P_mm`` (3,) mm (None: the workspace centre). ``bodies``: ``{body: MassProps}``
    in the layout's body frames (SI), as the build's ``Build.bodies``. Raises
    KinematicsError for a point out of reach, DesignError for a motor without a peak
    torque."""
    d = design.mechanism
    P = np.asarray(design.workspace["center_mm"] if P_mm is None else P_mm, float)
    T = _frames(design, P)
    torque = device.joint_peak_torques_Nm()
    world = np.eye(4)
    out: list[SimBody] = []
    loops, motors = [], []
    w = design.parallelogram_width_mm
    th = ik(d, P[None]).theta_rad[0]
    for i in ARMS:
        j = f"theta_{i}"
        pos, rot = _local(world, T[f"upper_{i}"])
        m, c, inertia = _props(bodies.get(f"upper_{i}"), ARM_AXES)
        out.append(SimBody(f"upper_{i}", "world", pos, rot, j, float(th[i]), m, c, inertia,
                           armature_kg_m2=device.joint_rotor_inertia_kg_m2(j)))
        n = device.transmission(j).ratio  # a capstan: gear n, the motor's own limit
        motors.append(SimMotor(f"motor_{i}", j, torque[j] / n, gear=n))
        knee = d.joint_offset_mm > 0
        parent = f"knee_{i}" if knee else f"upper_{i}"
        if knee:
            out.append(knee_body(bodies, T, i))
        for s in ("a", "b"):
            name = f"lower_{i}_{s}"
            pos, rot = _local(T[parent], T[name])
            m, c, inertia = _props(bodies.get(name), np.eye(3))
            out.append(SimBody(name, parent, pos, rot, f"{'rod' if knee else 'ball'}_{i}_{s}", 0.0,
                               m, c, inertia,
                               sites={f"{name}_end": np.array([d.lower_arm_mm * MM, 0.0, 0.0])},
                               joint_type="hinge" if knee else "ball"))
    pos, rot = _local(T["lower_0_a"], T["effector"])
    origin = T["effector"][:3, 3]
    P_m = P * MM
    sites = {"handle": P_m - origin}
    for i in ARMS:
        for s, sign in (("a", -0.5), ("b", 0.5)):
            sites[f"joint_{i}_{s}"] = P_m + (d.effector_radius_mm * d.radial[i]
                                             + sign * w * d.tangential[i]) * MM - origin
            if (i, s) != (0, "a"):
                loops.append(SimLoop(f"loop_{i}_{s}", f"lower_{i}_{s}", f"lower_{i}_{s}_end",
                                     "effector", f"joint_{i}_{s}"))
    m, c, inertia = _props(bodies.get("effector"), np.eye(3), origin - P_m)
    out.append(SimBody("effector", "lower_0_a", pos, rot, "ball_effector", 0.0, m, c, inertia,
                       sites=sites, joint_type="ball"))
    return SimModel(name=design.name, bodies=tuple(out), world_meshes=(), loops=tuple(loops),
                    motors=tuple(motors), meshdir="parts",
                    comment=f"hapticad delta '{design.name}': base frame (m, z up), effector centre "
                            f"at {P.tolist()} mm; masses from the solids; loops closed by connect")
