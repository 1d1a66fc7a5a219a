"""Rigid-body mass properties in SI: mass, centre of mass, inertia tensor (pure numpy).

No CAD import. Conventions used throughout:

* The inertia tensor is the positive (semi-)definite one,
  ``I = integral rho (|r|^2 E - r r^T) dV`` with ``r`` measured from the point the
  tensor is taken about; off-diagonal entries are the *negated* products of
  inertia (``I_xy = -integral rho x y dV``).
* A transform ``(R, t_m)`` maps coordinates of a child frame B into a parent frame
  A: ``x_A = R @ x_B + t_m`` (scipy's ``tf_A_B`` naming). Composition:
  ``tf_A_C = tf_A_B o tf_B_C`` i.e. ``R_AC = R_AB R_BC``, ``t_AC = R_AB t_BC + t_AB``.
* Tensor rotation: ``I_A = R I_B R^T``; parallel axis (Steiner):
  ``I_P = I_G + m (|d|^2 E - d d^T)`` with ``d = G - P``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from cad.errors import GeometryError
from cad.tolerances import INERTIA_REL_EPS, ROTATION_ORTHO_TOL


class InertiaError(GeometryError):
    """An inertia tensor is not physical (not symmetric / PSD, or violates the triangle inequality)."""


def _as_vec3(x, name: str) -> np.ndarray:
    a = np.asarray(x, dtype=float)
    if a.shape != (3,):
        raise GeometryError(f"{name} must have shape (3,), got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise GeometryError(f"{name} must be finite, got {a.tolist()}")
    return a


def _as_mat3(x, name: str) -> np.ndarray:
    a = np.asarray(x, dtype=float)
    if a.shape != (3, 3):
        raise GeometryError(f"{name} must have shape (3, 3), got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise GeometryError(f"{name} must be finite, got {a.tolist()}")
    return a


def _frozen(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float, copy=True)
    a.flags.writeable = False
    return a


def steiner_kg_m2(mass_kg: float, d_m: np.ndarray) -> np.ndarray:
    """Parallel-axis term ``m (|d|^2 E - d d^T)`` (3, 3), kg m^2.

    Parameters
    ----------
    mass_kg : mass, kg.
    d_m : (3,) offset of the centre of mass from the new reference point, m.
    """
    d = np.asarray(d_m, dtype=float)
    return mass_kg * (float(d @ d) * np.eye(3) - np.outer(d, d))


def validate_inertia(I_kg_m2, where: str) -> None:
    """Check that a 3x3 tensor is a physical inertia tensor; raise :class:`InertiaError` if not.

    Parameters
    ----------
    I_kg_m2 : (3, 3) inertia tensor, kg m^2 (about any point; all checks are frame-free).
    where : what the tensor belongs to, quoted in the error (e.g. ``"link crank"``).

    Checks, with ``eps = cad.tolerances.INERTIA_REL_EPS * max(trace, tiny)``:
    finite; symmetric (``|I - I^T| <= eps``); positive semi-definite (every eigenvalue
    ``>= -eps``); triangle inequality of the principal moments
    (``l_i <= l_j + l_k + eps`` for every permutation). Zero eigenvalues are
    accepted: a point mass (all zero) and an ideal thin rod (one zero, the other two
    equal) are the physical limits of the inequality.
    """
    inert = np.asarray(I_kg_m2, dtype=float)
    if inert.shape != (3, 3):
        raise InertiaError(f"{where}: inertia must be 3x3, got shape {inert.shape}")
    if not np.all(np.isfinite(inert)):
        raise InertiaError(f"{where}: inertia has non-finite entries {inert.tolist()}")
    scale = max(float(np.trace(inert)), float(np.abs(inert).max()), np.finfo(float).tiny)
    eps = INERTIA_REL_EPS * scale
    asym = float(np.abs(inert - inert.T).max())
    if asym > eps:
        raise InertiaError(f"{where}: inertia is not symmetric (max |I - I^T| = {asym:.3e} kg m^2)")
    lam = np.linalg.eigvalsh(0.5 * (inert + inert.T))
    if lam[0] < -eps:
        raise InertiaError(
            f"{where}: inertia is not positive definite (principal moments {lam.tolist()} kg m^2)"
        )
    # eigvalsh sorts ascending: the binding triangle inequality is l2 <= l0 + l1.
    if lam[2] > lam[0] + lam[1] + eps:
        raise InertiaError(
            f"{where}: principal moments {lam.tolist()} kg m^2 violate the triangle inequality "
            f"({lam[2]:.6e} > {lam[0]:.6e} + {lam[1]:.6e})"
        )


def check_rotation(R, name: str = "R") -> np.ndarray:
    """Return ``R`` as a float (3, 3) array after checking it is a proper rotation.

    Raises :class:`cad.errors.GeometryError` when ``R`` is not orthonormal within
    :data:`ROTATION_ORTHO_TOL` or has determinant -1 (a reflection).
    """
    R = _as_mat3(R, name)
    err = float(np.abs(R.T @ R - np.eye(3)).max())
    if err > ROTATION_ORTHO_TOL:
        raise GeometryError(f"{name} is not a rotation matrix (max |R^T R - E| = {err:.3e})")
    if np.linalg.det(R) < 0:
        raise GeometryError(f"{name} is a reflection (det = -1), not a rotation")
    return R


@dataclass(frozen=True, eq=False)
class MassProps:
    """Mass properties of a rigid body, SI units, expressed in one frame.

    Parameters
    ----------
    mass_kg : mass, kg (>= 0, finite).
    com_m : (3,) centre of mass, m, in the frame of the object it describes.
    inertia_com_kg_m2 : (3, 3) inertia tensor about the centre of mass, kg m^2, axes of
        that same frame; the positive-definite convention
        ``I = integral rho (|r|^2 E - r r^T) dV`` (see module docstring).

    Arrays are copied and made read-only. The tensor is validated on construction
    (:func:`validate_inertia`).
    """

    mass_kg: float
    com_m: np.ndarray = field(repr=True)
    inertia_com_kg_m2: np.ndarray = field(repr=True)

    def __post_init__(self) -> None:
        m = float(self.mass_kg)
        if not np.isfinite(m) or m < 0:
            raise GeometryError(f"mass_kg must be finite and >= 0, got {self.mass_kg!r}")
        com = _as_vec3(self.com_m, "com_m")
        inert = _as_mat3(self.inertia_com_kg_m2, "inertia_com_kg_m2")
        validate_inertia(inert, "MassProps")
        object.__setattr__(self, "mass_kg", m)
        object.__setattr__(self, "com_m", _frozen(com))
        object.__setattr__(self, "inertia_com_kg_m2", _frozen(0.5 * (inert + inert.T)))

    # ------------------------------------------------------------------ derived
    @property
    def principal_moments_kg_m2(self) -> np.ndarray:
        """(3,) principal moments about the COM, ascending, kg m^2."""
        return np.linalg.eigvalsh(self.inertia_com_kg_m2)

    @property
    def principal_axes(self) -> np.ndarray:
        """(3, 3) columns are the unit principal axes (same order as the moments), this frame."""
        return np.linalg.eigh(self.inertia_com_kg_m2)[1]

    def inertia_about_kg_m2(self, point_m) -> np.ndarray:
        """(3, 3) inertia tensor about ``point_m`` (3,) m, same axes (parallel-axis theorem)."""
        p = _as_vec3(point_m, "point_m")
        return self.inertia_com_kg_m2 + steiner_kg_m2(self.mass_kg, self.com_m - p)

    def transformed(self, R, t_m) -> MassProps:
        """Express these properties in a parent frame where ``x_parent = R @ x + t_m``.

        Parameters
        ----------
        R : (3, 3) proper rotation (child axes expressed in parent axes).
        t_m : (3,) origin of the child frame in the parent frame, m.

        ``com' = R com + t``; ``I' = R I R^T`` (rank-2 tensor rotation).
        """
        R = check_rotation(R)
        t = _as_vec3(t_m, "t_m")
        return MassProps(self.mass_kg, R @ self.com_m + t, R @ self.inertia_com_kg_m2 @ R.T)

    def scaled(self, factor: float) -> MassProps:
        """Same shape with density multiplied by ``factor`` (mass and inertia scale, COM does not)."""
        f = float(factor)
        if not np.isfinite(f) or f < 0:
            raise GeometryError(f"density factor must be finite and >= 0, got {factor!r}")
        return MassProps(self.mass_kg * f, self.com_m, self.inertia_com_kg_m2 * f)

    def to_dict(self) -> dict:
        """JSON-able dict: ``mass_kg``, ``com_mm``, ``inertia_com_kg_m2``, ``principal_moments_kg_m2``.

        Full float precision (haptic links are ~1e-6 kg m^2; nothing is rounded).
        """
        return {
            "mass_kg": self.mass_kg,
            "com_mm": (self.com_m * 1e3).tolist(),
            "inertia_com_kg_m2": self.inertia_com_kg_m2.tolist(),
            "principal_moments_kg_m2": self.principal_moments_kg_m2.tolist(),
        }


def point_mass(mass_kg: float, at_m) -> MassProps:
    """A point mass ``mass_kg`` (kg) at ``at_m`` (3,) m: zero inertia about its own COM."""
    return MassProps(mass_kg, _as_vec3(at_m, "at_m"), np.zeros((3, 3)))


def from_principal(mass_kg: float, com_m, moments_kg_m2, R=None) -> MassProps:
    """Mass properties from principal moments (3,) kg m^2 and axes ``R`` (columns, default E).

    ``I = R diag(moments) R^T`` about ``com_m`` (3,) m. Catalog data for bought parts
    (bearings, rotors) usually comes in this form.
    """
    lam = np.asarray(moments_kg_m2, dtype=float)
    if lam.shape != (3,):
        raise GeometryError(f"moments_kg_m2 must have shape (3,), got shape {lam.shape}")
    Rm = np.eye(3) if R is None else check_rotation(R)
    return MassProps(mass_kg, com_m, Rm @ np.diag(lam) @ Rm.T)


def combine(parts: Sequence[MassProps]) -> MassProps:
    """Combine rigid parts given in one common frame into one body.

    Parameters
    ----------
    parts : MassProps, all expressed in the same frame (rotate/translate each one first
        with :meth:`MassProps.transformed`).

    ``m = sum m_i``; ``G = sum m_i G_i / m``;
    ``I_G = sum [I_i + m_i (|d_i|^2 E - d_i d_i^T)]`` with ``d_i = G_i - G``
    (parallel-axis theorem to the combined COM).

    Raises :class:`cad.errors.GeometryError` for an empty list or zero total mass.
    """
    parts = list(parts)
    if not parts:
        raise GeometryError("combine: no parts given")
    masses = np.array([p.mass_kg for p in parts])
    total = float(masses.sum())
    if total <= 0:
        raise GeometryError("combine: total mass is zero, the centre of mass is undefined")
    coms = np.stack([p.com_m for p in parts])
    com = (masses[:, None] * coms).sum(axis=0) / total
    d = coms - com
    d2 = np.einsum("ij,ij->i", d, d)
    steiner = masses[:, None, None] * (
        d2[:, None, None] * np.eye(3)[None] - np.einsum("ij,ik->ijk", d, d)
    )
    inert = np.stack([p.inertia_com_kg_m2 for p in parts]).sum(axis=0) + steiner.sum(axis=0)
    return MassProps(total, com, inert)


def shares_about_kg_m2(parts: Sequence[MassProps], point_m) -> np.ndarray:
    """(N, 3, 3) each part's inertia about a common point ``point_m`` (3,) m.

    The shares sum to the combined body's inertia about that point, so they are an
    exact inertia budget (e.g. about a joint axis).
    """
    p = _as_vec3(point_m, "point_m")
    return np.stack([part.inertia_about_kg_m2(p) for part in parts])


# ---------------------------------------------------------------- transforms
def rot_x(angle_rad: float) -> np.ndarray:
    """(3, 3) rotation by ``angle_rad`` about +x."""
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_y(angle_rad: float) -> np.ndarray:
    """(3, 3) rotation by ``angle_rad`` about +y."""
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_z(angle_rad: float) -> np.ndarray:
    """(3, 3) rotation by ``angle_rad`` about +z."""
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rt_from_homogeneous_mm(T_mm) -> tuple[np.ndarray, np.ndarray]:
    """Split a homogeneous transform with translation in mm into ``(R, t_m)``.

    Parameters
    ----------
    T_mm : (4, 4) spatial or (3, 3) planar homogeneous transform (translation in mm),
        e.g. one pose of ``cad.kinematics.linkgeom.tf_world_link`` (planar, z kept).

    Returns ``R`` (3, 3) and ``t_m`` (3,) in metres, ready for :meth:`MassProps.transformed`.
    """
    T = np.asarray(T_mm, dtype=float)
    if T.shape == (3, 3):
        R = np.eye(3)
        R[:2, :2] = T[:2, :2]
        t = np.array([T[0, 2], T[1, 2], 0.0])
    elif T.shape == (4, 4):
        R = T[:3, :3].copy()
        t = T[:3, 3].copy()
    else:
        raise GeometryError(f"T_mm must have shape (3, 3) or (4, 4), got shape {T.shape}")
    return check_rotation(R, "T_mm rotation block"), t * 1e-3
