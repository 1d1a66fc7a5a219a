"""First structural mode and effector compliance of a delta: a 3-D frame model (numpy).

:class:`Frame3D`: nodes in space with 6 DOFs (ux, uy, uz, rx, ry, rz; m, rad, base
frame), Euler-Bernoulli beams (the 12 x 12 local matrix of
:func:`cad.structure.frame.local_stiffness`, Przemieniecki eq 5.117, turned into the base
frame by the element's own axes: local x along it, local z a given reference direction
made normal to x) and pin-ended trusses (axial E A / L only: a rod between two ball
joints carries no moment). Masses are lumped (half of each element at each end, point
masses at nodes); modes solve K phi = w^2 M phi after static (Guyan) condensation of the
massless DOFs, exact for lumped masses. A rigid body fixed to a node (its mass at an offset
centre, its rotary inertia about that centre: :meth:`Frame3D.rigid_mass`) adds the node's
6 x 6 rigid-body mass block (Przemieniecki §11.2, a rigid mass offset from the node).

:func:`delta_frame` builds the delta at one effector point: each upper arm a beam
clamped at its motor axis (boundary condition: motors held by the servo at infinite gain,
base and brackets rigid), the elbow and effector cross bars and the effector plate
beams, the twelve rods trusses between the ball-joint centres, the effector with its
handle a point mass at the effector centre, the joint parts at each rod end a point mass at
that end (a build's drawn parts: :func:`sections_from_parts`), each capstan's drum sector (the
solids' mass properties) a rigid mass on its upper arm at the motor axis. With Stamper's joint offset (g > 0, the Falcon)
each arm is a fork with a knee link on a pin and the rods are beams hinged at the knee
(:func:`knee_arm`). Dimensions and materials: :mod:`.hardware`.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from cad.data.ball_joints import DEFAULT_BALL_JOINT
from cad.data.materials import get_material
from cad.families.delta import hardware as hw
from cad.families.delta.layout import arm_points_mm, poses_at
from cad.kinematics.delta import Delta, ik, jacobian_rad_per_m, require_ok
from cad.structure.elastic import get_elastic
from cad.structure.frame import Section, local_stiffness, rect_torsion_J, von_mises_of_end_forces

MM = 1e-3


def element_axes(p, q, ref) -> np.ndarray:
    """3 x 3 rows = local x (p -> q), y = z x x, z (``ref`` made normal to x) in the base
    frame. ValueError for a zero-length element or ``ref`` parallel to it."""
    d = np.asarray(q, float) - np.asarray(p, float)
    L = float(np.linalg.norm(d))
    if L <= 0:
        raise ValueError("element of zero length")
    ex = d / L
    z = np.asarray(ref, float) - (np.asarray(ref, float) @ ex) * ex
    if np.linalg.norm(z) < 1e-9:
        raise ValueError("element reference direction parallel to the element")
    ez = z / np.linalg.norm(z)
    return np.vstack([ex, np.cross(ez, ex), ez])


@dataclass
class Frame3D:
    """Nodes (m), beams (i, j, section, local z reference), trusses (i, j, E A, mass kg),
    clamped nodes, point masses (kg)."""

    nodes: list[np.ndarray] = field(default_factory=list)
    beams: list[tuple[int, int, Section, np.ndarray]] = field(default_factory=list)
    trusses: list[tuple[int, int, float, float]] = field(default_factory=list)
    clamped: set[int] = field(default_factory=set)
    point_mass_kg: dict[int, float] = field(default_factory=dict)
    beam_labels: list[str] = field(default_factory=list)
    #: (node, 6 x 6 stiffness to ground, base frame): a pivot held in bearings with a spring
    #: about its axis (:func:`pivot_spring`)
    ground_springs: list[tuple[int, np.ndarray]] = field(default_factory=list)
    #: beam index -> its released local DOFs (0-11, the order of
    #: :func:`cad.structure.frame.local_stiffness`): a pin or ball at that end.
    releases: dict[int, tuple[int, ...]] = field(default_factory=dict)
    #: (node, 6 x 6 mass block, base frame): rigid bodies fixed to a node (:meth:`rigid_mass`)
    rigid_blocks: list[tuple[int, np.ndarray]] = field(default_factory=list)
    #: beam index -> (its inputs, (T, local k, T^T k T)): :meth:`element` (not a field to set)
    element_memo: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def node(self, xyz_m) -> int:
        self.nodes.append(np.asarray(xyz_m, float).reshape(3))
        return len(self.nodes) - 1

    def beam(self, i: int, j: int, s: Section, ref, n_sub: int = 1, label: str = "") -> None:
        """Beam i -> j split into ``n_sub`` elements (finer mass lumping), each named ``label``
        in :attr:`beam_labels`."""
        s.check()
        prev = i
        for k in range(1, n_sub + 1):
            nxt = j if k == n_sub else self.node(self.nodes[i] + (self.nodes[j] - self.nodes[i]) * k / n_sub)
            self.beams.append((prev, nxt, s, np.asarray(ref, float)))
            self.beam_labels.append(label)
            prev = nxt

    def released_beam(self, i: int, j: int, s: Section, ref, release, label: str = "") -> None:
        """One beam element i -> j whose local DOFs ``release`` (indices 0-11 of
        :func:`cad.structure.frame.local_stiffness`) carry no force: a hinge about local z at
        end i is (5,), a ball at end j (9, 10, 11). Local z is ``ref`` made normal to the beam."""
        self.beam(i, j, s, ref, label=label)
        self.releases[len(self.beams) - 1] = tuple(int(r) for r in release)

    def element_stiffness(self, k: int, L: float, s: Section) -> np.ndarray:
        """12 x 12 local stiffness of beam ``k``: :func:`cad.structure.frame.local_stiffness`
        with its released DOFs condensed out (static condensation, K_cc - K_cr K_rr^-1
        K_rc; zero rows and columns at the released DOFs: the end force there is 0)."""
        kl = local_stiffness(L, s)
        r = list(self.releases.get(k, ()))
        if not r:
            return kl
        c = [q for q in range(12) if q not in r]
        out = np.zeros((12, 12))
        out[np.ix_(c, c)] = kl[np.ix_(c, c)] - kl[np.ix_(c, r)] @ np.linalg.solve(
            kl[np.ix_(r, r)], kl[np.ix_(r, c)])
        return out

    def truss(self, i: int, j: int, EA_N: float, mass_kg: float) -> None:
        if not EA_N > 0:
            raise ValueError(f"truss E A must be > 0, got {EA_N!r}")
        self.trusses.append((i, j, float(EA_N), float(mass_kg)))

    def add_mass(self, i: int, m_kg: float) -> None:
        self.point_mass_kg[i] = self.point_mass_kg.get(i, 0.0) + m_kg

    def rigid_mass(self, i: int, m_kg: float, offset_m, inertia_kg_m2) -> None:
        """Fix a rigid body to node ``i``: mass ``m_kg`` with its centre at ``offset_m`` (3,) m
        from the node and rotary inertia ``inertia_kg_m2`` (3, 3) about that centre (base frame
        axes). The centre moves with v = u_dot - [r]x w (u, w the node's translation and
        rotation), so the node's mass block is m [I, -[r]x]^T [I, -[r]x] + diag(0, I_c)
        (kinetic energy of a rigid body, Koenig's theorem)."""
        r = np.asarray(offset_m, float).reshape(3)
        S = np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])
        T = np.hstack([np.eye(3), -S])
        block = float(m_kg) * T.T @ T
        block[3:, 3:] += np.asarray(inertia_kg_m2, float).reshape(3, 3)
        self.rigid_blocks.append((int(i), block))

    def mass_matrix(self) -> np.ndarray:
        """(6 N, 6 N) mass matrix (kg, kg m, kg m^2): the lumped translational masses of
        :meth:`masses` on the diagonal plus the rigid bodies' blocks (:meth:`rigid_mass`)."""
        m = np.repeat(self.masses()[:, None], 6, axis=1)
        m[:, 3:] = 0.0
        M = np.diag(m.ravel())
        for i, block in self.rigid_blocks:
            M[6 * i:6 * i + 6, 6 * i:6 * i + 6] += block
        return M

    def stiffness(self) -> np.ndarray:
        """Assembled stiffness (6 DOFs per node, N/m, N m/rad)."""
        K = np.zeros((6 * len(self.nodes),) * 2)
        for k, (i, j, _, _) in enumerate(self.beams):
            d = np.r_[6 * i:6 * i + 6, 6 * j:6 * j + 6]
            K[np.ix_(d, d)] += self.element(k)[2]
        for i, j, EA, _ in self.trusses:
            v = self.nodes[j] - self.nodes[i]
            L = float(np.linalg.norm(v))
            kk = EA / L * np.outer(v, v) / (L * L)
            d = np.r_[6 * i:6 * i + 3, 6 * j:6 * j + 3]
            K[np.ix_(d, d)] += np.block([[kk, -kk], [-kk, kk]])
        for i, k6 in self.ground_springs:
            K[6 * i:6 * i + 6, 6 * i:6 * i + 6] += k6
        return K

    def beam_end_forces(self, u: np.ndarray) -> np.ndarray:
        """(n_beams, 12) local end forces k_local T u_e of every beam (N, N m; the order of
        :func:`cad.structure.frame.local_stiffness`)."""
        out = np.zeros((len(self.beams), 12))
        for k, (i, j, _, _) in enumerate(self.beams):
            T, kl, _ = self.element(k)
            d = np.r_[6 * i:6 * i + 6, 6 * j:6 * j + 6]
            out[k] = kl @ (T @ u[d])
        return out

    def element(self, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Beam ``k``'s (T, k_local, T^T k_local T): its 12 x 12 rotation to local axes
        (:func:`element_axes` on each 3-vector), local stiffness (:meth:`element_stiffness`)
        and stiffness in the base frame. Made once while its end nodes, section, reference
        and releases are unchanged (every load case of :meth:`solve` and
        :meth:`beam_end_forces` on one frame reads the same arrays)."""
        i, j, s, ref = self.beams[k]
        key = (self.nodes[i].tobytes(), self.nodes[j].tobytes(), s, ref.tobytes(),
               self.releases.get(k))
        hit = self.element_memo.get(k)
        if hit is not None and hit[0] == key:
            return hit[1]
        T = np.kron(np.eye(4), element_axes(self.nodes[i], self.nodes[j], ref))
        kl = self.element_stiffness(k, float(np.linalg.norm(self.nodes[j] - self.nodes[i])), s)
        self.element_memo[k] = (key, (T, kl, T.T @ kl @ T))
        return self.element_memo[k][1]

    def truss_forces_N(self, u: np.ndarray) -> np.ndarray:
        """(n_trusses,) axial force of every truss (N, tension > 0): EA / L times its
        elongation along its own axis."""
        out = np.zeros(len(self.trusses))
        for k, (i, j, EA, _) in enumerate(self.trusses):
            v = self.nodes[j] - self.nodes[i]
            L = float(np.linalg.norm(v))
            out[k] = EA / L * float((u[6 * j:6 * j + 3] - u[6 * i:6 * i + 3]) @ v / L)
        return out

    def masses(self) -> np.ndarray:
        """Lumped translational mass per node (kg; the rigid bodies of :meth:`rigid_mass` are
        in :meth:`mass_matrix` only)."""
        m = np.zeros(len(self.nodes))
        for i, j, s, _ in self.beams:
            me = s.rho * s.A * float(np.linalg.norm(self.nodes[j] - self.nodes[i]))
            m[i] += me / 2
            m[j] += me / 2
        for i, j, _, mt in self.trusses:
            m[i] += mt / 2
            m[j] += mt / 2
        for i, v in self.point_mass_kg.items():
            m[i] += v
        return m

    def _free(self) -> np.ndarray:
        fixed = {6 * i + d for i in self.clamped for d in range(6)}
        return np.array([k for k in range(6 * len(self.nodes)) if k not in fixed])

    def solve(self, loads: dict[int, np.ndarray]) -> np.ndarray:
        """Displacements (6 per node) under nodal loads {node: (Fx, Fy, Fz[, Mx, My, Mz])}."""
        K, free = self.stiffness(), self._free()
        f = np.zeros(K.shape[0])
        for i, F in loads.items():
            F = np.asarray(F, float)
            f[6 * i:6 * i + len(F)] += F
        u = np.zeros_like(f)
        u[free] = np.linalg.solve(K[np.ix_(free, free)], f[free])
        return u

    def modes(self, k: int = 3) -> tuple[np.ndarray, np.ndarray]:
        """Lowest ``k`` modes: (frequencies Hz (k,), shapes (k, 6 N), mass-normalized)."""
        from scipy.linalg import eigh

        K, free = self.stiffness(), self._free()
        M = self.mass_matrix()[np.ix_(free, free)]
        Kf = K[np.ix_(free, free)]
        t = np.diag(M) > 0  # a DOF with no mass has a zero row (M is positive semi-definite)
        Ktr, Krr = Kf[np.ix_(t, ~t)], Kf[np.ix_(~t, ~t)]
        Kc = Kf[np.ix_(t, t)] - Ktr @ np.linalg.solve(Krr, Ktr.T)
        n = min(k, int(t.sum()))
        Mt = M[np.ix_(t, t)]
        w2, V = eigh(0.5 * (Kc + Kc.T), 0.5 * (Mt + Mt.T), subset_by_index=[0, n - 1])
        shapes = np.zeros((n, K.shape[0]))
        shapes[:, free[t]] = V.T
        shapes[:, free[~t]] = -np.linalg.solve(Krr, Ktr.T @ V).T
        return np.sqrt(np.maximum(w2, 0.0)) / (2 * math.pi), shapes


def rect_section(width_m: float, thick_m: float, material: str) -> Section:
    """Section of a width x thick rectangle: local y along the width (bending in the local
    x-y plane uses Iz = thick width^3 / 12), local z along the thickness."""
    el = get_elastic(material, "delta.structure")
    b, h = width_m, thick_m
    return Section(A=b * h, Iz=h * b**3 / 12, Iy=b * h**3 / 12, J=rect_torsion_J(b, h),
                   cy=b / 2, cz=h / 2, t_torsion=min(b, h), E=el.E_Pa, G=el.G_Pa,
                   rho=get_material(material).density_kg_m3)


def round_section(od_m: float, id_m: float, material: str) -> Section:
    """Section of a round bar or tube (od, id m)."""
    el = get_elastic(material, "delta.structure")
    A = math.pi / 4 * (od_m**2 - id_m**2)
    i_m4 = math.pi / 64 * (od_m**4 - id_m**4)
    return Section(A=A, Iz=i_m4, Iy=i_m4, J=2 * i_m4, cy=od_m / 2, cz=od_m / 2,
                   t_torsion=od_m / 2, E=el.E_Pa, G=el.G_Pa,
                   rho=get_material(material).density_kg_m3)


@dataclass(frozen=True)
class DeltaSections:
    """Sections of the delta's members and its lumped masses (SI): arm, cross bar, effector
    plate beams (centre -> cross bar), rod E A (N) and mass per metre (kg/m), effector with
    handle (kg, at the centre), the joint parts at each rod's top end (the elbow's ball stud
    and socket; with a knee, g > 0, the knee hinge: clevis, hinge pin, bearing and the rod's
    eye) and at its bottom end (the effector's ball stud and socket), kg at that end's node.
    A build reads both from its drawn parts (:func:`sections_from_parts`)."""

    arm: Section
    cross_bar: Section
    effector: Section
    rod_EA_N: float
    rod_kg_per_m: float
    effector_kg: float
    top_joint_kg: float
    bottom_joint_kg: float
    #: the rods as beams (their section), used with Stamper's knee (g > 0) only: None ->
    #: the carbon tube of :mod:`.hardware`.
    rod: Section | None = None


def default_sections(effector_radius_mm: float, width_mm: float,
                     ball_joint_key: str = DEFAULT_BALL_JOINT) -> DeltaSections:
    """The :mod:`.hardware` members: arm plate, cross bars, effector plate (width = the
    effector disk's diameter), carbon rods, aluminium effector disk + handle, and at each rod
    end one ball joint (stud + socket of catalog joint ``ball_joint_key``,
    :func:`.hardware.ball_joint` ``mass_g``, the catalog's mass: the parts a
    delta without a knee draws there). Without the solids a knee's hinge is not known: a
    build takes the joints' masses from its parts (:func:`sections_from_parts`)."""
    rod = round_section(hw.ROD_OD_MM * MM, hw.ROD_ID_MM * MM, hw.ROD_MATERIAL)
    joint_kg = hw.ball_joint(ball_joint_key).mass_g * 1e-3
    rho_al = get_material(hw.PLATE_MATERIAL).density_kg_m3
    r_disk = hw.effector_disk_radius_mm(effector_radius_mm, width_mm) * MM
    eff_kg = rho_al * (math.pi * r_disk**2 * hw.EFFECTOR_THICKNESS_MM * MM
                       + math.pi / 4 * (hw.HANDLE_D_MM * MM) ** 2 * hw.HANDLE_LENGTH_MM * MM)
    return DeltaSections(
        arm=rect_section(hw.ARM_WIDTH_MM * MM, hw.ARM_THICKNESS_MM * MM, hw.ARM_MATERIAL),
        cross_bar=round_section(hw.CROSS_BAR_D_MM * MM, 0.0, hw.ARM_MATERIAL),
        effector=rect_section(2 * r_disk, hw.EFFECTOR_THICKNESS_MM * MM, hw.PLATE_MATERIAL),
        rod_EA_N=rod.E * rod.A, rod_kg_per_m=rod.rho * rod.A, effector_kg=eff_kg,
        top_joint_kg=joint_kg, bottom_joint_kg=joint_kg, rod=rod)


#: The instances (names after the body's ``lower_{i}_{side}`` / ``knee_{i}`` / ``upper_{i}`` /
#: ``effector`` prefix, :mod:`.assembly`) lumped at each rod end of the frame model.
TOP_JOINT_PARTS = ("lower_{i}_{s}.socket_top", "upper_{i}.ball_stud_{s}",  # ball joint (g = 0)
                   "lower_{i}_{s}.eye", "lower_{i}_{s}.knee_bearing",       # knee hinge (g > 0)
                   "knee_{i}.clevis_{s}", "knee_{i}.hinge_pin_{s}")
BOTTOM_JOINT_PARTS = ("lower_{i}_{s}.socket_bottom", "effector.arm_{i}.ball_stud_{s}")


def rod_end_masses_kg(instances, props: dict) -> np.ndarray:
    """(3, 2, 2) kg: the joint parts drawn at each rod's (arm i, side a/b) top and bottom end
    (:data:`TOP_JOINT_PARTS`, :data:`BOTTOM_JOINT_PARTS`), summed from the per-kind mass
    properties the bodies, the BOM and Lambda(x) read (``props``:
    :func:`cad.pipeline.family.kind_props`: the solids' or a bought part's stated mass)."""
    mass = {x.name: props[x.kind.name].mass_kg for x in instances if props.get(x.kind.name) is not None}
    out = np.zeros((3, 2, 2))
    for i in range(3):
        for k, s in enumerate("ab"):
            for e, names in enumerate((TOP_JOINT_PARTS, BOTTOM_JOINT_PARTS)):
                out[i, k, e] = sum(mass.get(n.format(i=i, s=s), 0.0) for n in names)
    return out


def sections_from_parts(effector_radius_mm: float, width_mm: float, instances, props: dict) -> DeltaSections:
    """:func:`default_sections` with the rod ends' joint masses of the drawn parts
    (:func:`rod_end_masses_kg`: the six rods' ends alike; ValueError, a layout bug, when they
    differ by more than 1e-9 relative)."""
    m = rod_end_masses_kg(instances, props).reshape(6, 2)
    if np.ptp(m, axis=0).max() > 1e-9 * m.max():
        raise ValueError(f"the six rods' joint masses differ: {m.tolist()} kg")
    top, bottom = m.mean(axis=0)
    return dataclasses.replace(default_sections(effector_radius_mm, width_mm), top_joint_kg=float(top),
                               bottom_joint_kg=float(bottom))


def fork_section(plate: Section) -> Section:
    """The arm of a delta with a knee: a fork of two plates of section ``plate`` (joined only
    at the hub's spacer and by the knee pin, so no composite action is counted: A, Iy, Iz and
    J twice the plate's, the extreme fibres the plate's; each plate carries half the load) --
    a lower bound of its stiffness."""
    return dataclasses.replace(plate, A=2 * plate.A, Iz=2 * plate.Iz, Iy=2 * plate.Iy,
                               J=2 * plate.J)


def knee_arm(f: Frame3D, d: Delta, i: int, pts: dict, sec: DeltaSections, c: int,
             half_m: float, rope_k_Nm_per_rad: float | None = None) -> int:
    """Arm ``i`` of a delta with Stamper's knee (g > 0) into ``f`` (``pts``: the joint points
    of :func:`cad.families.delta.layout.arm_points_mm` at one pose, in metres; ``c`` the
    effector-centre node, ``half_m`` half the parallelogram's width). Members and joints:
    the arm fork (:func:`fork_section`) clamped at the motor axis; the knee plate (the arm's
    plate section) from the elbow to the knee cross bar, on the knee pin: a hinge about
    t_i at the elbow; the knee cross bar; each rod a beam of the rod tube, hinged at the
    knee cross bar about the normal n_i = k_i x t_i of the parallelogram's plane (the joint
    that holds the knee in line with the rods, Stamper's model: :mod:`cad.families.delta.sim`)
    and on a ball at the effector cross bar (all three rotations free); the effector's cross
    bar and plate beam as for g = 0. ``rope_k_Nm_per_rad``: the arm on a pivot held by its
    capstan's rope (:func:`pivot_spring`) instead of clamped. Returns the motor-axis node."""
    t, k = d.tangential[i], pts["knee_dir"][i] / np.linalg.norm(pts["knee_dir"][i])
    n = np.cross(k, t)
    rod = sec.rod or round_section(hw.ROD_OD_MM * MM, hw.ROD_ID_MM * MM, hw.ROD_MATERIAL)
    a, e = f.node(pts["axis"][i]), f.node(pts["elbow"][i])
    if rope_k_Nm_per_rad is None:
        f.clamped.add(a)
    else:
        f.ground_springs.append((a, pivot_spring(t, rope_k_Nm_per_rad)))
    f.beam(a, e, fork_section(sec.arm), t, n_sub=4, label=f"upper arm {i}")
    top, bc = f.node(pts["top"][i]), f.node(pts["bottom"][i])
    f.released_beam(e, top, sec.arm, t, (5,), label=f"knee {i}")
    f.beam(c, bc, sec.effector, np.array([0.0, 0.0, 1.0]), label=f"effector plate {i}")
    for s in (-1.0, 1.0):
        tb, bb = f.node(pts["top"][i] + s * half_m * t), f.node(pts["bottom"][i] + s * half_m * t)
        f.beam(top, tb, sec.cross_bar, k, label=f"knee cross bar {i}")
        f.beam(bc, bb, sec.cross_bar, d.radial[i], label=f"effector cross bar {i}")
        f.released_beam(tb, bb, rod, n, (5, 9, 10, 11), label=f"rod {i}")
        f.add_mass(tb, sec.top_joint_kg)
        f.add_mass(bb, sec.bottom_joint_kg)
    return a


def rod_forces_N(f: Frame3D, u: np.ndarray) -> np.ndarray:
    """Axial force (N, tension > 0) of every rod of a delta frame under displacements ``u``:
    the trusses (g = 0), or the beams labelled ``rod`` (g > 0: the end force along the
    rod at its lower end)."""
    if f.trusses:
        return f.truss_forces_N(u)
    fe = f.beam_end_forces(u)
    return np.array([fe[k, 6] for k, lab in enumerate(f.beam_labels) if lab.startswith("rod")])


def delta_frame(d: Delta, P_mm, width_mm: float, sec: DeltaSections,
                rope_k_Nm_per_rad=None, drums=None) -> tuple[Frame3D, int]:
    """(frame, index of the effector-centre node) of the delta at effector point ``P_mm``
    (3,) mm (module docstring; with Stamper's knee, g > 0, each arm is :func:`knee_arm`).
    ``rope_k_Nm_per_rad`` (3,) N m/rad: each upper arm on a pivot held by its capstan's rope
    (:func:`pivot_spring` about the motor axis t_i, the motor held by the servo: the rope in
    series with the arm), None: clamped. ``drums`` (3,) :class:`cad.massprops.props.MassProps`
    or None per arm (SI, in upper_i's body frame of :mod:`cad.families.delta.layout`): each
    a rigid body on its arm's motor-axis node (:meth:`Frame3D.rigid_mass`), the capstan's drum
    sector turning with the arm. KinematicsError when P is not ok."""
    pose = ik(d, np.asarray(P_mm, float).reshape(1, 3))
    require_ok(pose)
    pts = {k: v[:, 0] * MM for k, v in arm_points_mm(d, pose.P_mm, pose.theta_rad).items()}
    tfs = poses_at(d, pose.P_mm, pose.theta_rad, width_mm)
    P = pose.P_mm[0] * MM
    f = Frame3D()
    c = f.node(P)
    f.add_mass(c, sec.effector_kg)
    half = width_mm / 2 * MM
    for i in range(3):
        if drums is not None and drums[i] is not None:
            R = tfs[f"upper_{i}"][0, :3, :3]
            dr = drums[i]
            drum_at = (R @ np.asarray(dr.com_m), R @ np.asarray(dr.inertia_com_kg_m2) @ R.T)
        else:
            drum_at = None
        if d.joint_offset_mm > 0:
            a = knee_arm(f, d, i, pts, sec, c, half,
                         None if rope_k_Nm_per_rad is None else rope_k_Nm_per_rad[i])
            if drum_at is not None:
                f.rigid_mass(a, drums[i].mass_kg, *drum_at)
            continue
        t, u = d.tangential[i], d.radial[i]
        a, e = f.node(pts["axis"][i]), f.node(pts["elbow"][i])
        if rope_k_Nm_per_rad is None:
            f.clamped.add(a)
        else:
            f.ground_springs.append((a, pivot_spring(t, rope_k_Nm_per_rad[i])))
        f.beam(a, e, sec.arm, t, n_sub=4, label=f"upper arm {i}")
        if drum_at is not None:
            f.rigid_mass(a, drums[i].mass_kg, *drum_at)
        bc = f.node(pts["bottom"][i])
        f.beam(c, bc, sec.effector, np.array([0.0, 0.0, 1.0]), label=f"effector plate {i}")
        for s in (-1.0, 1.0):
            top, bot = f.node(pts["top"][i] + s * half * t), f.node(pts["bottom"][i] + s * half * t)
            f.beam(e, top, sec.cross_bar, u, label=f"elbow cross bar {i}")
            f.beam(bc, bot, sec.cross_bar, u, label=f"effector cross bar {i}")
            f.truss(top, bot, sec.rod_EA_N, sec.rod_kg_per_m * d.lower_arm_mm * MM)
            f.add_mass(top, sec.top_joint_kg)
            f.add_mass(bot, sec.bottom_joint_kg)
    return f, c


#: Stiffness of a pivot's bearings in the directions they hold (N/m and N m/rad): a penalty
#: far above the frame's (its beams are 1e4 to 1e7), so the pivot is rigid but about its axis.
PIVOT_PENALTY = 1e12


def pivot_spring(axis, k_Nm_per_rad: float) -> np.ndarray:
    """6 x 6 ground stiffness of a node on a pivot (base frame): rigid in translation and in
    rotation normal to the unit ``axis`` (:data:`PIVOT_PENALTY`), ``k_Nm_per_rad`` about it
    (a capstan's rope: :func:`cad.datasheet.capstan_rows.cable_stiffness_Nm_per_rad`)."""
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    aa = np.outer(a, a)
    k = np.zeros((6, 6))
    k[:3, :3] = PIVOT_PENALTY * np.eye(3)
    k[3:, 3:] = PIVOT_PENALTY * (np.eye(3) - aa) + float(k_Nm_per_rad) * aa
    return k


def first_mode(d: Delta, P_mm, width_mm: float, sec: DeltaSections | None = None,
               rope_k_Nm_per_rad=None, drums=None) -> dict:
    """First structural mode and the effector's compliance at ``P_mm`` (3,) mm:
    {"first_mode_Hz", "modes_Hz" (3,), "mode_direction" (3,) unit effector motion of the
    first mode, "compliance_m_per_N" (3, 3) effector displacement per force at its centre,
    "compliance_max_um_per_N" its largest eigenvalue (worst direction), "boundary":
    sentence}. Sections default to :func:`default_sections` (a build passes
    :func:`sections_from_parts`: the rods' end joints as drawn); ``rope_k_Nm_per_rad`` (3,) the
    capstans' rope springs at the motor axes (:func:`delta_frame`), None: clamped; ``drums``
    (3,) the drum sectors' mass properties on the upper arms (:func:`delta_frame`)."""
    sec = sec or default_sections(d.effector_radius_mm, width_mm)
    f, c = delta_frame(d, P_mm, width_mm, sec, rope_k_Nm_per_rad, drums)
    drum_kg = [dr.mass_kg for dr in drums if dr is not None] if drums is not None else []
    hz, shapes = f.modes(3)
    C = np.stack([f.solve({c: e})[6 * c:6 * c + 3] for e in np.eye(3)], axis=1)
    v = shapes[0, 6 * c:6 * c + 3]
    return {"first_mode_Hz": float(hz[0]), "modes_Hz": hz, "mode_direction": v / np.linalg.norm(v),
            "compliance_m_per_N": C,
            "compliance_max_um_per_N": float(np.linalg.eigvalsh(0.5 * (C + C.T))[-1] * 1e6),
            "boundary": ("upper arms clamped at the motor axes (motors held, base rigid); "
                         if rope_k_Nm_per_rad is None else
                         "upper arms on pivots at the motor axes held by the capstans' rope springs k_q "
                         f"{', '.join(f'{k:.4g}' for k in rope_k_Nm_per_rad)} N m/rad (motors held, base "
                         "rigid); ")
                        + ("knees on their pins; rods hinged at the knees (about the normal of "
                           "the parallelogram's plane) and on balls at the effector; "
                           if d.joint_offset_mm > 0 else
                           "rods pin-ended between the ball-joint centres; ")
                        + "effector and handle a point mass at its centre; the joint parts at each rod's "
                          f"top and bottom end point masses ({1e3 * sec.top_joint_kg:.4g} g, "
                          f"{1e3 * sec.bottom_joint_kg:.4g} g)"
                        + ("; each capstan drum sector with its anchor screws a rigid mass and "
                           "inertia on its upper arm (the solids' mass properties, "
                           f"{', '.join(f'{1e3 * m:.4g}' for m in drum_kg)} g)" if drum_kg else "")}


def euler_buckling_N(od_mm: float, id_mm: float, length_mm: float, E_Pa: float) -> float:
    """Euler load of a pin-ended tube, pi^2 E I / L^2 (N; Euler's column, K = 1)."""
    i_m4 = math.pi / 64 * ((od_mm * MM) ** 4 - (id_mm * MM) ** 4)
    return math.pi ** 2 * E_Pa * i_m4 / (length_mm * MM) ** 2


def peak_torque_loads_N(d: Delta, P_mm, torque_Nm: float) -> np.ndarray:
    """(8, 3) effector forces (N, base frame) the motors exert at ``P_mm`` with every joint at
    +-``torque_Nm`` (the eight corners of the torque box): f = J^T tau (J: theta_dot = J
    x_dot, rad/m; isotropy paper eq 2). KinematicsError when P is out of reach."""
    J, status = jacobian_rad_per_m(d, np.asarray(P_mm, float).reshape(1, 3))
    if status[0] != 0:
        require_ok(ik(d, np.asarray(P_mm, float).reshape(1, 3)))
    signs = np.array(np.meshgrid(*[[-1.0, 1.0]] * 3)).reshape(3, -1).T
    return signs * torque_Nm @ J[0]


def peak_stress(d: Delta, P_mm, width_mm: float, loads_N,
                sec: DeltaSections | None = None) -> dict:
    """Stresses of the frame of :func:`delta_frame` at ``P_mm`` under each effector force of
    ``loads_N`` (n, 3) N at the effector centre, the worst of them (superposition of three
    unit loads):
    {"max_stress_MPa" the largest von Mises stress of the beams (arms, cross bars, effector
    plate, knees: :func:`cad.structure.frame.von_mises_of_end_forces`), "critical_member",
    "rod_compression_max_N" / "rod_tension_max_N" the largest rod forces,
    "rod_stress_max_MPa" (axial; with a knee, g > 0, the rods also bend: their largest von
    Mises stress), "rod_buckling_N" (Euler, pin-ended carbon tube of
    :mod:`.hardware`), "rod_buckling_margin" its ratio to the largest compression (inf
    without compression), "critical_load_N" (3,), "at_mm"}. KinematicsError / DesignError as
    :func:`delta_frame`."""
    sec = sec or default_sections(d.effector_radius_mm, width_mm)
    f, c = delta_frame(d, P_mm, width_mm, sec)
    U = [f.solve({c: e}) for e in np.eye(3)]
    fb = np.stack([f.beam_end_forces(u) for u in U])          # (3, n_beams, 12) per unit load
    ft = np.stack([rod_forces_N(f, u) for u in U])           # (3, n_rods)
    D = np.asarray(loads_N, float).reshape(-1, 3)
    vm = von_mises_of_end_forces(np.einsum("dk,kbe->dbe", D, fb), [b[2] for b in f.beams])
    is_rod = np.array([lab.startswith("rod") for lab in f.beam_labels], bool)
    labels = [lab for lab, r in zip(f.beam_labels, is_rod, strict=True) if not r]
    vm, vm_rod = vm[:, ~is_rod], vm[:, is_rod]
    rods = D @ ft
    k = np.unravel_index(int(np.argmax(vm)), vm.shape)
    el = get_elastic(hw.ROD_MATERIAL, "delta.structure")
    p_cr = euler_buckling_N(hw.ROD_OD_MM, hw.ROD_ID_MM, d.lower_arm_mm, el.E_Pa)
    comp = float(max(0.0, -rods.min()))
    rod_axial = np.abs(rods).max() / (sec.rod_EA_N / el.E_Pa)
    return {"max_stress_MPa": float(vm.max() * 1e-6), "critical_member": labels[k[1]],
            "critical_load_N": D[k[0]].tolist(),
            "rod_compression_max_N": comp, "rod_tension_max_N": float(max(0.0, rods.max())),
            "rod_stress_max_MPa": float(max(rod_axial, vm_rod.max(initial=0.0)) * 1e-6),
            "rod_buckling_N": p_cr, "rod_buckling_margin": p_cr / comp if comp > 0 else math.inf,
            "at_mm": np.asarray(P_mm, float).tolist()}


def peak_stress_over(d: Delta, X_mm, width_mm: float, torque_Nm: float,
                     sec: DeltaSections | None = None) -> dict:
    """:func:`peak_stress` under the motors' ±``torque_Nm`` (:func:`peak_torque_loads_N`) at
    every point of ``X_mm`` (n, 3) mm: the largest stress and the smallest buckling margin
    over the points, each with its point (``at_mm`` / ``buckling_at_mm``) and figures, and
    ``points`` the number of points."""
    sec = sec or default_sections(d.effector_radius_mm, width_mm)
    runs = [peak_stress(d, P, width_mm, peak_torque_loads_N(d, P, torque_Nm), sec)
            for P in np.asarray(X_mm, float).reshape(-1, 3)]
    s = max(runs, key=lambda r: r["max_stress_MPa"])
    b = min(runs, key=lambda r: r["rod_buckling_margin"])
    return {**s, **{k: b[k] for k in ("rod_compression_max_N", "rod_tension_max_N",
                                      "rod_stress_max_MPa", "rod_buckling_N",
                                      "rod_buckling_margin")},
            "buckling_at_mm": b["at_mm"], "points": len(runs)}
