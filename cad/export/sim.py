"""Simulator exports: MJCF (MuJoCo) and URDF of a closed-loop mechanism (issue 14).

Input is a plain :class:`SimModel` (no CAD library): a spanning tree of rigid bodies,
each with its exact mass properties from the solids, hinge joints, the meshes of its
parts, sites, loop closures and motors. The builders (:mod:`cad.families.fourbar.sim`,
:mod:`cad.families.pantograph.sim`) fill it from the build's assembly and mass properties.

Frames and units (a public contract, docs/simulation.md):

* SI everywhere: metres, kilograms, kg m^2, radians, N m. Part meshes are the part STL
  files (mm) scaled by 0.001.
* The world frame is the mechanism's base frame (four-bar: R0, origin A1, x0/y0 of the
  Hoeken paper, z up out of the plane; twin pantograph: the kinematic base frame).
* Each body frame is its link frame (origin at the link's first joint, x towards its
  second joint, z up). ``SimBody.pos_m`` / ``rot`` place it in its parent's frame *at the
  written pose*; every joint is a hinge about the body's z axis through its origin.
* Joint values: the hinge value is the angle of the body's x axis from its parent's x
  axis, so a joint on the world body reads the absolute link angle (the four-bar crank
  joint's value *is* phi1). MJCF writes ``ref`` = the value at the written pose (MuJoCo:
  ``qpos0 = ref``); URDF writes the joint origin at zero angle, so the same value applies.
* Inertia: ``<inertial pos=COM mass=m fullinertia="Ixx Iyy Izz Ixy Ixz Iyz">`` about the
  COM in the body frame, the positive-definite tensor of :mod:`cad.massprops.props`
  (off-diagonals are the negated products of inertia, as MuJoCo and URDF expect).
  Numbers are written with ``repr`` (exact float round trip).
* Loops: MJCF ``<equality><connect site1 site2>`` between two sites that coincide at the
  written pose. URDF has no loops: each closure becomes a *joint pair*, two fixed joints
  ``<loop>_a`` / ``<loop>_b`` carrying massless frames ``<loop>_a`` (on body a) and
  ``<loop>_b`` (on body b); a tool that closes loops itself must make the two frames'
  origins coincide (a revolute pair about z). An XML comment lists them too.
* Motors: MJCF ``<motor joint gear=1 ctrlrange=forcerange=[-tau, tau]>`` (N m), rotor
  inertia Jm as the joint's ``armature``; a force actuator at a site (the PowerMouse's coils)
  ``<motor site gear="direction 0 0 0">``, control and range in N. A free body (the
  PowerMouse flotor) has ``<freejoint>`` (qpos: position, unit quaternion; qvel: linear
  velocity in the world, angular velocity in the body frame). URDF ``<limit effort=tau>`` and
  has no armature: Jm is stated in a comment (the link inertias stay the solids' exact
  values). All URDF hinges are ``continuous`` (the crank range may cross +-pi).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from cad.io.atomic import write_text_atomic
from cad.io.escape import xml_comment

SIM_FORMATS = ("mjcf", "urdf")
#: MJCF equality solver parameters of the loop closures: stiff enough that the loop
#: residual stays below 1e-9 m while MuJoCo drives the mechanism (tested), with the
#: time constant at 2 x the default time step (MuJoCo's stability limit).
LOOP_SOLREF = (0.0002, 1.0)
LOOP_SOLIMP = (0.9999, 0.9999, 0.001, 0.5, 2.0)
#: Time step of the written model (s); with RK4 and LOOP_SOLREF the loop residual stays
#: ~1e-11 m while the motor drives the crank over the stroke (implicitfast: ~6e-9 m).
TIMESTEP_S = 1e-4


@dataclass(frozen=True)
class SimMesh:
    """One part mesh on a body: STL ``file`` (mm, relative to the mesh folder) placed by
    ``pos_m`` (3,) and ``rot`` (3, 3) in the body frame."""

    name: str
    file: str
    pos_m: np.ndarray
    rot: np.ndarray
    rgba: tuple[float, float, float, float] = (0.7, 0.7, 0.7, 1.0)


@dataclass(frozen=True)
class SimBody:
    """A rigid body of the spanning tree (see the module docstring for frames)."""

    name: str
    parent: str  # "world" or another body's name (listed before this one)
    pos_m: np.ndarray
    rot: np.ndarray
    joint: str  # hinge name (about the body z axis through its origin)
    joint_ref_rad: float  # joint value at the written pose
    mass_kg: float
    com_m: np.ndarray
    inertia_com_kg_m2: np.ndarray
    armature_kg_m2: float = 0.0
    meshes: tuple[SimMesh, ...] = ()
    sites: dict[str, np.ndarray] = field(default_factory=dict)
    #: "hinge" (about the body z axis) or "free" (6 DOF, a body on the world: the PowerMouse's
    #: levitated flotor; MJCF ``<freejoint>``, no ref or armature) or "ball" (3 rotations
    #: about the body origin: the delta's ball joints; MJCF ``type="ball"``, no ref or
    #: armature; no URDF form).
    joint_type: str = "hinge"


@dataclass(frozen=True)
class SimLoop:
    """Loop closure: ``site_a`` on ``body_a`` and ``site_b`` on ``body_b`` coincide."""

    name: str
    body_a: str
    site_a: str
    body_b: str
    site_b: str


@dataclass(frozen=True)
class SimMotor:
    """A direct-drive motor on ``joint`` with torque limit ``torque_max_Nm``; or, with
    ``site`` set (``joint`` then ""), a force actuator at that site along the unit direction
    ``direction`` (3,) in the site's body frame, limit ``torque_max_Nm`` read as N (a Lorentz
    coil: MJCF ``<motor site gear="dx dy dz 0 0 0">``). ``gear``: the joint motor's
    transmission ratio n (a capstan: joint torque = n motor torque, MJCF ``gear="n"``;
    ``torque_max_Nm`` is then the motor's own limit)."""

    name: str
    joint: str
    torque_max_Nm: float
    site: str | None = None
    direction: tuple[float, float, float] = (1.0, 0.0, 0.0)
    gear: float = 1.0


@dataclass(frozen=True)
class SimModel:
    name: str
    bodies: tuple[SimBody, ...]
    world_meshes: tuple[SimMesh, ...]
    loops: tuple[SimLoop, ...]
    motors: tuple[SimMotor, ...]
    meshdir: str
    comment: str = ""


def _f(x: float) -> str:
    return repr(float(x))


def _v(a) -> str:
    return " ".join(_f(x) for x in np.asarray(a, dtype=float).ravel())


def rot_to_quat(R: np.ndarray) -> np.ndarray:
    """(w, x, y, z) unit quaternion of a rotation matrix (3, 3) (Shepperd's method)."""
    R = np.asarray(R, dtype=float)
    t = np.trace(R)
    if t > 0:
        s = 2.0 * math.sqrt(1.0 + t)
        q = [0.25 * s, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s]
    else:
        i = int(np.argmax(np.diag(R)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(1.0 + R[i, i] - R[j, j] - R[k, k])
        q = [0.0, 0.0, 0.0, 0.0]
        q[0] = (R[k, j] - R[j, k]) / s
        q[1 + i] = 0.25 * s
        q[1 + j] = (R[j, i] + R[i, j]) / s
        q[1 + k] = (R[k, i] + R[i, k]) / s
    q = np.array(q)
    return q / np.linalg.norm(q)


def rot_to_rpy(R: np.ndarray) -> np.ndarray:
    """URDF roll-pitch-yaw (fixed axes x, y, z: R = Rz(yaw) Ry(pitch) Rx(roll))."""
    R = np.asarray(R, dtype=float)
    pitch = math.atan2(-R[2, 0], math.hypot(R[0, 0], R[1, 0]))
    if abs(math.cos(pitch)) < 1e-12:
        return np.array([math.atan2(-R[1, 2], R[1, 1]), pitch, 0.0])
    return np.array([math.atan2(R[2, 1], R[2, 2]), pitch, math.atan2(R[1, 0], R[0, 0])])


def rot_z(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _fullinertia(t: np.ndarray) -> str:
    return _v([t[0, 0], t[1, 1], t[2, 2], t[0, 1], t[0, 2], t[1, 2]])


def _mesh_assets(model: SimModel) -> dict[str, str]:
    files: dict[str, str] = {}
    for m in [*model.world_meshes, *(m for b in model.bodies for m in b.meshes)]:
        files.setdefault(Path(m.file).stem, m.file)
    return files


def _geom(m: SimMesh, indent: str) -> str:
    return (
        f'{indent}<geom name={quoteattr(m.name)} type="mesh" mesh={quoteattr(Path(m.file).stem)} '
        f'pos="{_v(m.pos_m)}" quat="{_v(rot_to_quat(m.rot))}" rgba="{_v(m.rgba)}"/>'
    )


def mjcf_text(model: SimModel) -> str:
    """The MJCF document of ``model`` (module docstring)."""
    children: dict[str, list[SimBody]] = {}
    for b in model.bodies:
        children.setdefault(b.parent, []).append(b)
    out = [f"<mujoco model={quoteattr(model.name)}>"]
    if model.comment:
        out.append(f"  <!-- {xml_comment(model.comment)} -->")
    out += [
        f'  <compiler angle="radian" meshdir={quoteattr(model.meshdir)} inertiafromgeom="false"/>',
        f'  <option timestep="{_f(TIMESTEP_S)}" integrator="RK4"/>',
        '  <default><geom contype="0" conaffinity="0" group="1"/></default>',
        "  <asset>",
    ]
    for stem, file in sorted(_mesh_assets(model).items()):
        out.append(f'    <mesh name={quoteattr(stem)} file={quoteattr(file)} scale="0.001 0.001 0.001"/>')
    out += ["  </asset>", "  <worldbody>"]
    out += [_geom(m, "    ") for m in model.world_meshes]

    def body(b: SimBody, ind: str) -> None:
        out.append(f'{ind}<body name={quoteattr(b.name)} pos="{_v(b.pos_m)}" quat="{_v(rot_to_quat(b.rot))}">')
        if b.joint_type == "free":
            out.append(f"{ind}  <freejoint name={quoteattr(b.joint)}/>")
        elif b.joint_type == "ball":
            out.append(f'{ind}  <joint name={quoteattr(b.joint)} type="ball" pos="0 0 0" damping="0"/>')
        else:
            out.append(
                f'{ind}  <joint name={quoteattr(b.joint)} type="hinge" axis="0 0 1" pos="0 0 0" '
                f'ref="{_f(b.joint_ref_rad)}" armature="{_f(b.armature_kg_m2)}" damping="0"/>'
            )
        out.append(
            f'{ind}  <inertial pos="{_v(b.com_m)}" mass="{_f(b.mass_kg)}" '
            f'fullinertia="{_fullinertia(b.inertia_com_kg_m2)}"/>'
        )
        out.extend(_geom(m, ind + "  ") for m in b.meshes)
        for s, p in b.sites.items():
            out.append(f'{ind}  <site name={quoteattr(s)} pos="{_v(p)}" size="0.002"/>')
        for c in children.get(b.name, []):
            body(c, ind + "  ")
        out.append(f"{ind}</body>")

    for b in children.get("world", []):
        body(b, "    ")
    out += ["  </worldbody>", "  <equality>"]
    for lp in model.loops:
        out.append(
            f"    <connect name={quoteattr(lp.name)} site1={quoteattr(lp.site_a)} "
            f'site2={quoteattr(lp.site_b)} solref="{_v(LOOP_SOLREF)}" solimp="{_v(LOOP_SOLIMP)}"/>'
        )
    out += ["  </equality>", "  <actuator>"]
    for m in model.motors:
        t = _f(m.torque_max_Nm)
        where = (f'site={quoteattr(m.site)} gear="{_v([*m.direction, 0.0, 0.0, 0.0])}"' if m.site
                 else f'joint={quoteattr(m.joint)} gear="{1 if m.gear == 1.0 else _f(m.gear)}"')
        out.append(
            f'    <motor name={quoteattr(m.name)} {where} '
            f'ctrllimited="true" ctrlrange="-{t} {t}" forcelimited="true" forcerange="-{t} {t}"/>'
        )
    out += ["  </actuator>", "</mujoco>"]
    return "\n".join(out) + "\n"


def urdf_text(model: SimModel) -> str:
    """The URDF document of ``model``: spanning tree + loop-closure joint pairs. Hinge
    bodies and joint motors only (a free body or a site actuator has no URDF form: the
    family refuses ``urdf`` before the build)."""
    base = "base_link"
    out = ['<?xml version="1.0"?>', f"<robot name={quoteattr(model.name)}>"]
    if model.comment:
        out.append(f"  <!-- {xml_comment(model.comment)} -->")
    for lp in model.loops:
        out.append(
            f"  <!-- loop closure {lp.name}: frames {lp.name}_a (on {lp.body_a}) and {lp.name}_b "
            f"(on {lp.body_b}) must coincide; revolute pair about z -->"
        )
    for m in model.motors:
        arm = next(b.armature_kg_m2 for b in model.bodies if b.joint == m.joint)
        out.append(f"  <!-- motor {m.name} on joint {m.joint}: rotor inertia (armature) {_f(arm)} kg m^2 -->")

    def visuals(meshes, ind):
        for m in meshes:
            out.extend([
                f"{ind}<visual name={quoteattr(m.name)}>",
                f'{ind}  <origin xyz="{_v(m.pos_m)}" rpy="{_v(rot_to_rpy(m.rot))}"/>',
                f'{ind}  <geometry><mesh filename={quoteattr(model.meshdir.rstrip("/") + "/" + m.file)} '
                'scale="0.001 0.001 0.001"/></geometry>',
                f"{ind}</visual>",
            ])

    out.append(f"  <link name={quoteattr(base)}>")
    visuals(model.world_meshes, "    ")
    out.append("  </link>")
    torque = {m.joint: m.torque_max_Nm * m.gear for m in model.motors}  # at the joint
    for b in model.bodies:
        t = b.inertia_com_kg_m2
        out += [
            f"  <link name={quoteattr(b.name)}>",
            "    <inertial>",
            f'      <origin xyz="{_v(b.com_m)}" rpy="0 0 0"/>',
            f'      <mass value="{_f(b.mass_kg)}"/>',
            f'      <inertia ixx="{_f(t[0, 0])}" ixy="{_f(t[0, 1])}" ixz="{_f(t[0, 2])}" '
            f'iyy="{_f(t[1, 1])}" iyz="{_f(t[1, 2])}" izz="{_f(t[2, 2])}"/>',
            "    </inertial>",
        ]
        visuals(b.meshes, "    ")
        out.append("  </link>")
        parent = base if b.parent == "world" else b.parent
        # joint origin = the body frame at zero joint value: undo the written pose's angle
        R0 = b.rot @ rot_z(-b.joint_ref_rad)
        eff = torque.get(b.joint)
        out += [
            f'  <joint name={quoteattr(b.joint)} type="continuous">',
            f"    <parent link={quoteattr(parent)}/>",
            f"    <child link={quoteattr(b.name)}/>",
            f'    <origin xyz="{_v(b.pos_m)}" rpy="{_v(rot_to_rpy(R0))}"/>',
            '    <axis xyz="0 0 1"/>',
        ]
        if eff is not None:
            out.append(f'    <limit effort="{_f(eff)}" velocity="100.0"/>')
        out.append("  </joint>")
    sites = {s: (b.name, p) for b in model.bodies for s, p in b.sites.items()}
    for lp in model.loops:
        for tag, site in (("a", lp.site_a), ("b", lp.site_b)):
            body_name, p = sites[site]
            out += [
                f"  <link name={quoteattr(f'{lp.name}_{tag}')}/>",
                f'  <joint name={quoteattr(f"{lp.name}_{tag}")} type="fixed">',
                f"    <parent link={quoteattr(body_name)}/>",
                f"    <child link={quoteattr(f'{lp.name}_{tag}')}/>",
                f'    <origin xyz="{_v(p)}" rpy="0 0 0"/>',
                "  </joint>",
            ]
    out.append("</robot>")
    return "\n".join(out) + "\n"


def write_sim_files(model: SimModel, out_dir: Path, formats, stem: str) -> list[Path]:
    """Write ``<stem>.xml`` (MJCF) and/or ``<stem>.urdf`` into ``out_dir`` atomically."""
    written = []
    if "mjcf" in formats:
        written.append(write_text_atomic(Path(out_dir) / f"{stem}.xml", mjcf_text(model)))
    if "urdf" in formats:
        written.append(write_text_atomic(Path(out_dir) / f"{stem}.urdf", urdf_text(model)))
    return written
