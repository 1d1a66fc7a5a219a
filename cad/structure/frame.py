"""A 3D frame of Euler-Bernoulli beams (numpy): the cheap structural model.

Nodes carry 6 DOFs (ux, uy, uz, rx, ry, rz; m, rad) in R0 (x, y in the mechanism's
plane, z out of plane). Each element is a prismatic beam with its local x along the
element, local z = R0 z (out of plane), local y = z x x (in plane); its 12 x 12
stiffness is the closed-form Euler-Bernoulli / Saint-Venant matrix (Przemieniecki,
*Theory of Matrix Structural Analysis*, 1968, eq 5.117, no shear terms):
axial E A / L, in-plane bending E Iz, out-of-plane bending E Iy, torsion G J.
Revolute joints tie two nodes in every DOF but the rotation about z: the tied DOFs are
one unknown (exact elimination, :meth:`Frame.dof_map`; stiff penalty springs made the
answer depend on the node numbering in the 4th-5th digit); supports fix DOFs.

Masses are lumped: each element puts half its mass on each end node, parts add point
masses at nodes. Modes come from the generalized eigenproblem K phi = w^2 M phi after
static (Guyan) condensation of the massless rotational DOFs, which is exact for lumped
translational masses.

Errors: :class:`ValueError` for a zero-length element or a non-positive section value;
:class:`numpy.linalg.LinAlgError` when the structure is a mechanism (singular K).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Section:
    """Beam section (SI): A area, Iz in-plane bending, Iy out-of-plane bending, J torsion,
    cy / cz distance of the extreme fibre in and out of plane, t_torsion (m) the wall
    thickness for the torsion shear stress tau = T t / J, E / G moduli, rho density."""

    A: float
    Iz: float
    Iy: float
    J: float
    cy: float
    cz: float
    t_torsion: float
    E: float
    G: float
    rho: float

    def check(self) -> None:
        for k in ("A", "Iz", "Iy", "J", "E", "G"):
            if not getattr(self, k) > 0:
                raise ValueError(f"section {k}: must be > 0, got {getattr(self, k)!r}")


def rect_torsion_J(b: float, h: float) -> float:
    """Saint-Venant torsion constant of a b x h rectangle (b >= h or not), Roark's
    Formulas Table 10.1 case 4: J = a b^3 [16/3 - 3.36 b/a (1 - b^4 / (12 a^4))] / 16 with
    a = max / 2, b = min / 2."""
    a, c = max(b, h) / 2.0, min(b, h) / 2.0
    return a * c**3 * (16.0 / 3.0 - 3.36 * c / a * (1.0 - c**4 / (12.0 * a**4)))


def von_mises_of_end_forces(f: np.ndarray, sections) -> np.ndarray:
    """Largest von Mises stress (Pa) at the two ends of each beam element from its local end
    forces ``f`` (..., n_elements, 12; order of :func:`local_stiffness`: N, Vy, Vz, T, My, Mz
    at each end) and its :class:`Section`: normal N/A + |My| cz/Iy + |Mz| cy/Iz (the extreme
    fibre, both bending stresses added: conservative for a round section), shear from torsion
    T t / J, sqrt(sig^2 + 3 tau^2), the larger of the two ends."""
    A, Iy, Iz, J = (np.array([getattr(e, k) for e in sections]) for k in ("A", "Iy", "Iz", "J"))
    cy, cz, t = (np.array([getattr(e, k) for e in sections]) for k in ("cy", "cz", "t_torsion"))
    best = np.zeros(np.shape(f)[:-1])
    for b in (0, 6):
        N, Tq, My, Mz = f[..., b], f[..., b + 3], f[..., b + 4], f[..., b + 5]
        sig = np.abs(N) / A + np.abs(My) * cz / Iy + np.abs(Mz) * cy / Iz
        tau = np.abs(Tq) * t / J
        best = np.maximum(best, np.sqrt(sig * sig + 3 * tau * tau))
    return best


def local_stiffness(L: float, s: Section) -> np.ndarray:
    """12 x 12 local stiffness of a 3D Euler-Bernoulli beam element (module docstring)."""
    E, G = s.E, s.G
    k = np.zeros((12, 12))
    a = E * s.A / L
    k[0, 0] = k[6, 6] = a
    k[0, 6] = k[6, 0] = -a
    t = G * s.J / L
    k[3, 3] = k[9, 9] = t
    k[3, 9] = k[9, 3] = -t
    # in-plane bending (v, rz): DOFs 1, 5, 7, 11
    z = E * s.Iz
    idx = (1, 5, 7, 11)
    kb = np.array([[12, 6 * L, -12, 6 * L], [6 * L, 4 * L * L, -6 * L, 2 * L * L],
                   [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L * L, -6 * L, 4 * L * L]]) * z / L**3
    k[np.ix_(idx, idx)] += kb
    # out-of-plane bending (w, ry): DOFs 2, 4, 8, 10 (sign of ry coupling flips)
    y = E * s.Iy
    idx = (2, 4, 8, 10)
    kb = np.array([[12, -6 * L, -12, -6 * L], [-6 * L, 4 * L * L, 6 * L, 2 * L * L],
                   [-12, 6 * L, 12, 6 * L], [-6 * L, 2 * L * L, 6 * L, 4 * L * L]]) * y / L**3
    k[np.ix_(idx, idx)] += kb
    return k


def rotation(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """3 x 3 rows = local x, y, z axes in R0 of an element in the x-y plane from p to q."""
    d = np.asarray(q, float) - np.asarray(p, float)
    L = float(np.hypot(d[0], d[1]))
    if L <= 0:
        raise ValueError("element of zero length")
    x0, x1 = float(d[0] / L), float(d[1] / L)
    # local y = z x x, written out in numpy.cross's own products (the same bits, zero signs
    # included, without its array set-up: this runs for every element of every frame)
    return np.array([[x0, x1, 0.0],
                     [0.0 * 0.0 - 1.0 * x1, 1.0 * x0 - 0.0 * 0.0, 0.0 * x1 - 0.0 * x0],
                     [0.0, 0.0, 1.0]])


@dataclass
class Frame:
    """Nodes (x, y in m), elements (i, j, section, link), ties, supports, point masses."""

    nodes: list[np.ndarray] = field(default_factory=list)
    elements: list[tuple[int, int, Section, str]] = field(default_factory=list)
    ties: list[tuple[int, int]] = field(default_factory=list)
    fixed: dict[int, tuple[int, ...]] = field(default_factory=dict)
    point_mass_kg: dict[int, float] = field(default_factory=dict)
    #: grounded springs ``(node, dof) -> k`` (N/m or N m/rad): a support that yields, e.g. a
    #: capstan's rope holding the crank's rotation (dof 5, rz)
    springs: dict[tuple[int, int], float] = field(default_factory=dict)

    def node(self, xy) -> int:
        self.nodes.append(np.asarray(xy, float)[:2])
        return len(self.nodes) - 1

    def add_mass(self, i: int, m: float) -> None:
        self.point_mass_kg[i] = self.point_mass_kg.get(i, 0.0) + m

    def element(self, i: int, j: int, s: Section, link: str, n_sub: int = 1) -> None:
        """Beam from node i to node j, split into ``n_sub`` elements (finer mass lumping)."""
        s.check()
        prev = i
        for k in range(1, n_sub + 1):
            nxt = j if k == n_sub else self.node(self.nodes[i] + (self.nodes[j] - self.nodes[i]) * k / n_sub)
            self.elements.append((prev, nxt, s, link))
            prev = nxt

    def _T(self, e) -> tuple[np.ndarray, float]:
        i, j, _, _ = e
        R = rotation(self.nodes[i], self.nodes[j])
        T = np.zeros((12, 12))
        for b in range(4):
            T[3 * b:3 * b + 3, 3 * b:3 * b + 3] = R
        return T, float(np.linalg.norm(self.nodes[j] - self.nodes[i]))

    def stiffness(self) -> np.ndarray:
        """Assembled element stiffness (6 DOFs per node, ties not applied)."""
        n = 6 * len(self.nodes)
        K = np.zeros((n, n))
        for e in self.elements:
            T, L = self._T(e)
            ke = T.T @ local_stiffness(L, e[2]) @ T
            d = np.r_[6 * e[0]:6 * e[0] + 6, 6 * e[1]:6 * e[1] + 6]
            K[np.ix_(d, d)] += ke
        return K

    def dof_map(self) -> tuple[np.ndarray, int]:
        """(index of the unknown of every node DOF, number of unknowns): a tie (a, b) makes
        DOFs 0..4 of b (all but rz) the same unknowns as a's; numbered in DOF order."""
        n = 6 * len(self.nodes)
        parent = list(range(n))

        def root(k: int) -> int:
            while parent[k] != k:
                parent[k] = parent[parent[k]]
                k = parent[k]
            return k

        for a, b in self.ties:
            for dof in range(5):
                ra, rb = root(6 * a + dof), root(6 * b + dof)
                parent[max(ra, rb)] = min(ra, rb)
        _, idx = np.unique([root(k) for k in range(n)], return_inverse=True)
        return idx, int(idx.max()) + 1

    def _reduced(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(map, K, translational mass per unknown, free unknowns) with the ties eliminated."""
        idx, r = self.dof_map()
        K = np.zeros((r, r))
        np.add.at(K, (idx[:, None], idx[None, :]), self.stiffness())
        for (i, d), k in self.springs.items():
            K[idx[6 * i + d], idx[6 * i + d]] += k
        m = np.repeat(self.masses()[:, None], 6, axis=1)
        m[:, 3:] = 0.0
        mr = np.zeros(r)
        np.add.at(mr, idx, m.ravel())
        fixed = {int(idx[6 * i + d]) for i, ds in self.fixed.items() for d in ds}
        free = np.array([k for k in range(r) if k not in fixed])
        return idx, K, mr, free

    def masses(self) -> np.ndarray:
        """Lumped translational mass per node (kg)."""
        m = np.zeros(len(self.nodes))
        for e in self.elements:
            L = float(np.linalg.norm(self.nodes[e[1]] - self.nodes[e[0]]))  # as in _T
            me = e[2].rho * e[2].A * L
            m[e[0]] += me / 2
            m[e[1]] += me / 2
        for i, v in self.point_mass_kg.items():
            m[i] += v
        return m

    def solve(self, loads: dict[int, np.ndarray]) -> np.ndarray:
        """Displacements (6 per node) under nodal loads {node: (Fx, Fy, Fz, Mx, My, Mz)}."""
        idx, K, _, free = self._reduced()
        f_full = np.zeros(6 * len(self.nodes))
        for i, F in loads.items():
            f_full[6 * i:6 * i + 6] += F
        f = np.zeros(K.shape[0])
        np.add.at(f, idx, f_full)
        u = np.zeros_like(f)
        u[free] = np.linalg.solve(K[np.ix_(free, free)], f[free])
        return u[idx]

    def element_end_forces(self, u: np.ndarray) -> np.ndarray:
        """(n_elements, 12) local end forces ``k_local T u_e`` of every element (N, N m):
        linear in ``u``, so a load case's forces are the sum of its parts' (superposition)."""
        out = np.zeros((len(self.elements), 12))
        for k, e in enumerate(self.elements):
            T, L = self._T(e)
            d = np.r_[6 * e[0]:6 * e[0] + 6, 6 * e[1]:6 * e[1] + 6]
            out[k] = local_stiffness(L, e[2]) @ (T @ u[d])
        return out

    def stress_of_end_forces(self, f: np.ndarray) -> np.ndarray:
        """Largest von Mises stress (Pa) at the ends of every element from its local end
        forces ``f`` (..., n_elements, 12) (:func:`von_mises_of_end_forces`)."""
        return von_mises_of_end_forces(f, [e[2] for e in self.elements])

    def element_stress_Pa(self, u: np.ndarray) -> np.ndarray:
        """Largest von Mises stress at the ends of every element (normal: N/A + |My| cz/Iy +
        |Mz| cy/Iz; shear: torsion T t / J)."""
        return self.stress_of_end_forces(self.element_end_forces(u))

    def _condensed(self):
        """Guyan condensation onto the massive DOFs: (map, K, free, massive mask, Kc, masses,
        Ktr, Krr)."""
        idx, K, m, free = self._reduced()
        Kf = K[np.ix_(free, free)]
        mf = m[free]
        t = mf > 0
        Ktt, Ktr, Krr = Kf[np.ix_(t, t)], Kf[np.ix_(t, ~t)], Kf[np.ix_(~t, ~t)]
        Kc = Ktt - Ktr @ np.linalg.solve(Krr, Ktr.T)
        return idx, K, free, t, 0.5 * (Kc + Kc.T), mf[t], Ktr, Krr

    def modes(self, k: int = 3) -> tuple[np.ndarray, np.ndarray]:
        """Lowest ``k`` modes: (frequencies Hz (k,), shapes (k, 6 N) node DOFs), each shape
        mass-normalized (phi^T M phi = 1, lumped translational masses) with its massless DOFs
        recovered from the Guyan condensation (exact for lumped masses)."""
        from scipy.linalg import eigh

        idx, K, free, t, Kc, mt, Ktr, Krr = self._condensed()
        n = min(k, len(Kc))
        w2, V = eigh(Kc, np.diag(mt), subset_by_index=[0, n - 1])
        shapes = np.zeros((n, K.shape[0]))
        shapes[:, free[t]] = V.T
        shapes[:, free[~t]] = -np.linalg.solve(Krr, Ktr.T @ V).T
        return np.sqrt(np.maximum(w2, 0.0)) / (2 * math.pi), shapes[:, idx]

    def modes_Hz(self, k: int = 3) -> np.ndarray:
        """Lowest ``k`` natural frequencies (Hz): lumped translational masses, Guyan-condensed."""
        from scipy.linalg import eigh

        *_, Kc, mt, _, _ = self._condensed()
        w2 = eigh(Kc, np.diag(mt), eigvals_only=True, subset_by_index=[0, min(k, len(Kc)) - 1])
        return np.sqrt(np.maximum(w2, 0.0)) / (2 * math.pi)
