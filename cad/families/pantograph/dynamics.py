"""Effective mass of a pantograph-family device at home from the bodies' mass properties
(isotropy paper Table 1 for the twin pantograph; the plain 5-bar's 2x2 mass matrix)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cad.device import resolve_device
from cad.families.pantograph.layout import is_twin
from cad.kinematics import fivebar as fb5
from cad.kinematics import twin_pantograph as tw
from cad.kinematics.fivebar import LinkMass


def planar_props(mp):
    """MassProps (3-D, link frame) -> LinkMass (mass, COM xy, Izz about the COM)."""
    return LinkMass(
        float(mp.mass_kg),
        (float(mp.com_m[0]), float(mp.com_m[1])),
        float(mp.inertia_com_kg_m2[2, 2]),
    )


@dataclass(frozen=True)
class PantographDynamics:
    """The pantograph families' dynamics from the solids (``Build.dyn``): the effective mass
    at home (``effective``: the 5-bar's 2 x 2 mass matrix in g, or the twin pantograph's
    isotropy paper Table 1 figures) and, for the twin pantograph, the same without the rotor
    inertia (``bare``; None for the 5-bar). Report keys: ``effective_mass_home``,
    ``effective_mass_home_without_rotor``."""

    effective: dict
    bare: dict | None


def dynamics(design, bodies: dict, home: np.ndarray) -> PantographDynamics:
    """:class:`PantographDynamics` of ``design`` from its bodies' mass properties (link
    frames, SI) at the home task position ``home`` (mm)."""
    return PantographDynamics(*effective_mass(design, bodies, home))


def effective_mass(design, bodies: dict, home: np.ndarray) -> tuple[dict, dict | None]:
    """Effective mass at home (with and, for the mouse, without rotor inertia). Every rotor
    counts at its joint through its transmission, n^2 (J_m + J_capstan) each
    (:meth:`cad.device.ResolvedDevice.joint_rotor_inertia_kg_m2`; J_m for direct drive)."""
    dev = resolve_device(design)  # the motors the BOM orders, through their transmissions

    def rotors(pre: str) -> tuple[float, float]:
        """(left, right) rotor inertia at the joints of the 5-bar ``pre`` (kg m^2)."""
        return tuple(dev.joint_rotor_inertia_kg_m2(f"{pre}q_{s}") for s in ("left", "right"))

    def fbm(pre: str, jm):
        d = [planar_props(bodies[f"{pre}distal_{s}"]) for s in ("left", "right")]
        pr = [planar_props(bodies[f"{pre}proximal_{s}"]) for s in ("left", "right")]
        return fb5.FiveBarMass(pr[0], pr[1], d[0], d[1], jm)

    if not is_twin(design):
        M = fb5.mass_matrix_kg(design.mechanism, home[None, :], fbm("", rotors("")))[0]  # n^2 (J_m + J_c)
        M = M + bodies["handle"].mass_kg * np.eye(2)  # the handle translates with E
        return {
            "at_mm": home.tolist(),
            "mass_matrix_g": (M * 1e3).tolist(),
            "mass_x_g_diag": float(M[0, 0] * 1e3),
            "mass_y_g_diag": float(M[1, 1] * 1e3),
        }, None
    th = math.radians(design.workspace["home_theta_deg"])
    X = np.array([home[0], home[1], th])
    cs = bodies["crankshaft"]
    crank = fb5.LinkMass(
        float(cs.mass_kg),
        (float(cs.com_m[0]), float(cs.com_m[1])),
        float(cs.inertia_com_kg_m2[2, 2]),
    )
    tm = design.mechanism
    eff = tw.effective_mass_home(
        tm, X, tw.TwinMass(fbm("knob_", rotors("knob_")), fbm("crank_", rotors("crank_")), crank)
    )
    bare = tw.effective_mass_home(tm, X, tw.TwinMass(fbm("knob_", 0.0), fbm("crank_", 0.0), crank))
    return eff, bare
