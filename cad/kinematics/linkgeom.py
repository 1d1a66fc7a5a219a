"""Link geometry: joint positions in each link's own frame and posed link transforms.

Link frames (SPEC): origin at the link's first joint, x towards its second
joint, z out of the mechanism plane. Planar homogeneous transforms are 3x3
matrices named ``tf_world_link``: they map link-frame coordinates (mm) into
R0 (world) coordinates, ``p_world = tf_world_link @ [x, y, 1]``; composition
``tf_a_c = tf_a_b @ tf_b_c``.

- ground: frame R0 itself; joints A1 = (0, 0), A4 = (l5, l4).
- crank: origin A1, x towards A2 -> A2 = (l1, 0). World pose: rot(phi1) at A1.
- coupler: origin A2, x towards A3 -> A3 = (l2, 0), P = le (cos phi_e, sin phi_e).
  World pose: rot(phi2) at A2.
- rocker: origin A4, x towards A3 -> A3 = (l3, 0). World pose: rot(phi3) at A4.
"""

from __future__ import annotations

import numpy as np

from cad.errors import DesignError
from cad.kinematics.fourbar import FourBar, FourBarPose

LINKS = ("ground", "crank", "coupler", "rocker")


def link_joints_mm(fb: FourBar) -> dict[str, dict[str, np.ndarray]]:
    """Joint (and coupler point) positions in each link's own frame, mm."""
    return {
        "ground": {"A1": np.zeros(2), "A4": np.array([fb.l5_mm, fb.l4_mm])},
        "crank": {"A1": np.zeros(2), "A2": np.array([fb.l1_mm, 0.0])},
        "coupler": {
            "A2": np.zeros(2),
            "A3": np.array([fb.l2_mm, 0.0]),
            "P": fb.le_mm * np.array([np.cos(fb.phi_e_rad), np.sin(fb.phi_e_rad)]),
        },
        "rocker": {"A4": np.zeros(2), "A3": np.array([fb.l3_mm, 0.0])},
    }


def planar_tf(angle_rad: np.ndarray, origin_mm: np.ndarray) -> np.ndarray:
    """(N,3,3) transforms: rotation by ``angle_rad`` (N,) then translation ``origin_mm`` (N,2)."""
    a = np.atleast_1d(angle_rad)
    o = np.broadcast_to(np.asarray(origin_mm, dtype=float), (a.size, 2))
    c, s = np.cos(a), np.sin(a)
    tf = np.zeros((a.size, 3, 3))
    tf[:, 0, 0], tf[:, 0, 1], tf[:, 1, 0], tf[:, 1, 1] = c, -s, s, c
    tf[:, :2, 2] = o
    tf[:, 2, 2] = 1.0
    return tf


def tf_world_link(fb: FourBar, pose: FourBarPose, link: str) -> np.ndarray:
    """(N,3,3) transforms mapping ``link`` frame coordinates (mm) into R0 at each pose."""
    n = len(pose)
    if link == "ground":
        return planar_tf(np.zeros(n), np.zeros((n, 2)))
    if link == "crank":
        return planar_tf(pose.phi1_rad, np.zeros((n, 2)))
    if link == "coupler":
        return planar_tf(pose.phi2_rad, pose.A2_mm)
    if link == "rocker":
        return planar_tf(pose.phi3_rad, np.broadcast_to(fb.A4_mm, (n, 2)))
    raise DesignError("link", f"unknown link {link!r} (known: {', '.join(LINKS)})")
