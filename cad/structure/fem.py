"""Finite elements of one bar (scikit-fem): the accurate model of a link's stiffness.

A bar ``L x w x t`` (mm in, SI inside) with an optional through slot (the lightening
pocket, ``a <= x <= L - a``, ``|y| < w_p / 2``) is modelled in plane stress with
9-node quadratic quadrilaterals (``ElementQuad2``, free of the shear locking of
bilinear elements in bending), in the plane of the bending:

* in-plane bending (load along y, the mechanism's plane): mesh x-y, thickness t,
  slot elements removed;
* out-of-plane bending (load along z): mesh x-z, thickness w (w - w_p over the slot).

Frame: x along the bar from its clamped end, y in the mechanism's plane, z out of plane.
:func:`cantilever` clamps x = 0 and loads the face x = L with a uniform traction of
resultant 1 N; the returned compliance is the work of that load (mean tip deflection).
For a solid bar it tends to P L^3 / (3 E I) (Euler-Bernoulli) plus the shear term
P L / (kappa G A) (Timoshenko, kappa = 5/6). :func:`first_mode_Hz` gives the lowest
natural frequency of the same cantilever; the closed form of the first bending mode
is (1.87510^2 / 2 pi) sqrt(E I / (rho A L^4)).

Raises :class:`ValueError` for a non-positive dimension, a slot as wide as the bar or an
unknown direction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cad.io import derived_cache


@dataclass(frozen=True)
class BarGeometry:
    """Rectangular bar L x w x t (mm) with an optional slot of width ``slot_w_mm`` from
    ``slot_start_mm`` to ``L - slot_start_mm`` (no slot when ``slot_w_mm`` is 0)."""

    L_mm: float
    w_mm: float
    t_mm: float
    slot_w_mm: float = 0.0
    slot_start_mm: float = 0.0

    def check(self) -> None:
        for k in ("L_mm", "w_mm", "t_mm"):
            if not getattr(self, k) > 0:
                raise ValueError(f"{k}: must be > 0, got {getattr(self, k)!r}")
        if self.slot_w_mm < 0 or self.slot_w_mm >= self.w_mm:
            raise ValueError(f"slot_w_mm: must be in [0, w_mm), got {self.slot_w_mm!r}")
        if self.slot_w_mm > 0 and not 0 <= self.slot_start_mm < self.L_mm / 2:
            raise ValueError(f"slot_start_mm: must be in [0, L/2), got {self.slot_start_mm!r}")


def _grid(lo: float, hi: float, n: int, extra=()) -> np.ndarray:
    pts = {round(float(v), 12) for v in np.linspace(lo, hi, n + 1)}
    pts.update(round(float(e), 12) for e in extra if lo < e < hi)
    return np.array(sorted(pts))


def _slot_x_m(g: BarGeometry) -> tuple[float, float]:
    return g.slot_start_mm * 1e-3, (g.L_mm - g.slot_start_mm) * 1e-3


def mesh_bar(g: BarGeometry, direction: str, nx: int, nh: int):
    """Quadrilateral mesh (m) of the bending plane and the thickness of each element (m)."""
    from skfem import MeshQuad

    g.check()
    if direction not in ("y", "z"):
        raise ValueError(f"direction: must be 'y' or 'z', got {direction!r}")
    L, w, t = g.L_mm * 1e-3, g.w_mm * 1e-3, g.t_mm * 1e-3
    slot = g.slot_w_mm > 0
    xs = _slot_x_m(g) if slot else ()
    if direction == "y":
        hs = (-g.slot_w_mm * 5e-4, g.slot_w_mm * 5e-4) if slot else ()
        m = MeshQuad.init_tensor(_grid(0, L, nx, xs), _grid(-w / 2, w / 2, nh, hs))
        if slot:
            c = m.p[:, m.t].mean(axis=1)
            cut = (c[0] > xs[0]) & (c[0] < xs[1]) & (np.abs(c[1]) < g.slot_w_mm * 5e-4)
            if cut.any():
                m = m.remove_elements(np.nonzero(cut)[0])
        return m, np.full(m.t.shape[1], t)
    m = MeshQuad.init_tensor(_grid(0, L, nx, xs), _grid(0, t, nh))
    c = m.p[:, m.t].mean(axis=1)
    b = np.full(m.t.shape[1], w)
    if slot:
        b[(c[0] > xs[0]) & (c[0] < xs[1])] = w - g.slot_w_mm * 1e-3
    return m, b


def _assemble(g, direction, E_Pa, nu, nx, nh):
    from skfem import Basis, BilinearForm, ElementQuad2, ElementVector, asm
    from skfem.helpers import ddot, sym_grad, trace
    from skfem.helpers import eye as _eye

    m, b = mesh_bar(g, direction, nx, nh)
    basis = Basis(m, ElementVector(ElementQuad2()))
    lam = E_Pa * nu / (1.0 - nu**2)  # plane stress
    mu = E_Pa / (2.0 * (1.0 + nu))
    bq = b[:, None] * np.ones(basis.X.shape[1])[None, :]

    @BilinearForm
    def elasticity(u, v, w):
        e = sym_grad(u)
        s = 2.0 * mu * e + lam * _eye(trace(e), 2)
        return w["b"] * ddot(s, sym_grad(v))

    K = asm(elasticity, basis, b=bq)
    return m, basis, K, bq


def cantilever(
    g: BarGeometry, E_Pa: float, nu: float, direction: str, n: tuple[int, int] = (16, 2)
) -> float:
    """Tip compliance (m/N) of the bar clamped at x = 0, loaded at x = L along
    ``direction`` ("y" in plane, "z" out of plane). ``n``: elements along x and across."""
    from skfem import FacetBasis, LinearForm, condense, solve

    m, basis, K, _ = _assemble(g, direction, E_Pa, nu, *n)
    L = g.L_mm * 1e-3
    fb = FacetBasis(m, basis.elem, facets=m.facets_satisfying(lambda x: np.isclose(x[0], L)))
    height = float(fb.dx.sum())

    @LinearForm
    def traction(v, _):
        return v[1] / height

    f = traction.assemble(fb)
    clamp = basis.get_dofs(lambda x: np.isclose(x[0], 0.0)).all()
    u = solve(*condense(K, f, D=clamp))
    return float(f @ u)


def cached_cantilever(
    g: BarGeometry, E_Pa: float, nu: float, direction: str, n: tuple[int, int] = (16, 2)
) -> float:
    """:func:`cantilever` through the derived disk cache (:mod:`cad.io.derived_cache`), keyed
    by every input (geometry, E, nu, direction, mesh) and this module's source: a build of a
    design whose bars were analysed before neither imports scikit-fem nor assembles."""
    import dataclasses

    key = [dataclasses.asdict(g), float(E_Pa), float(nu), direction, list(n)]
    return float(derived_cache.cached_json(
        "fem-cantilever", key, lambda: cantilever(g, E_Pa, nu, direction, n),
        code=("cad.structure.fem",)))


def first_mode_Hz(
    g: BarGeometry, E_Pa: float, nu: float, rho: float, direction: str = "z",
    n: tuple[int, int] = (16, 2),
) -> float:
    """Lowest natural frequency (Hz) of the bar clamped at x = 0 bending in ``direction``."""
    from scipy.sparse.linalg import eigsh
    from skfem import BilinearForm, asm, condense
    from skfem.helpers import dot

    m, basis, K, bq = _assemble(g, direction, E_Pa, nu, *n)

    @BilinearForm
    def mass(u, v, w):
        return rho * w["b"] * dot(u, v)

    M = asm(mass, basis, b=bq)
    clamp = basis.get_dofs(lambda x: np.isclose(x[0], 0.0)).all()
    Kc, Mc, _, _ = condense(K, M, D=clamp)
    lam = eigsh(Kc, k=1, M=Mc, sigma=0.0, which="LM", return_eigenvectors=False)
    return math.sqrt(float(lam[0])) / (2.0 * math.pi)


def euler_bernoulli_tip_m_per_N(L_m: float, E_Pa: float, I_m4: float) -> float:
    """Cantilever tip compliance L^3 / (3 E I), m/N."""
    return L_m**3 / (3.0 * E_Pa * I_m4)


def timoshenko_tip_m_per_N(L_m: float, E_Pa: float, I_m4: float, G_Pa: float, A_m2: float) -> float:
    """Cantilever tip compliance with shear: L^3 / (3 E I) + L / (kappa G A), kappa = 5/6."""
    return euler_bernoulli_tip_m_per_N(L_m, E_Pa, I_m4) + L_m / (5.0 / 6.0 * G_Pa * A_m2)


def euler_bernoulli_first_mode_Hz(L_m: float, E_Pa: float, I_m4: float, rho: float, A_m2: float) -> float:
    """First bending mode of a clamped-free beam: (1.87510^2 / 2 pi) sqrt(E I / (rho A L^4))."""
    return 1.8751040687**2 / (2.0 * math.pi) * math.sqrt(E_Pa * I_m4 / (rho * A_m2 * L_m**4))
