"""Mass properties: pure-numpy rigid-body algebra plus exact (OCCT) and mesh integrators.

``cad.massprops.props`` (imported here) is pure numpy. The CAD back-ends load OCP,
trimesh and manifold3d only when called: import ``cad.massprops.occt``,
``cad.massprops.mesh`` or ``cad.massprops.io`` explicitly.
"""

from cad.massprops.props import (
    InertiaError,
    MassProps,
    combine,
    from_principal,
    point_mass,
    rot_x,
    rot_y,
    rot_z,
    rt_from_homogeneous_mm,
    shares_about_kg_m2,
    steiner_kg_m2,
    validate_inertia,
)

__all__ = [
    "InertiaError",
    "MassProps",
    "combine",
    "from_principal",
    "point_mass",
    "rot_x",
    "rot_y",
    "rot_z",
    "rt_from_homogeneous_mm",
    "shares_about_kg_m2",
    "steiner_kg_m2",
    "validate_inertia",
]
