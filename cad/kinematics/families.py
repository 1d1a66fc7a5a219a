"""The four straight-line families of the Hoeken paper, Fig. 2 table.

Each family is stored as the paper's proportions (l_i / l2, le / l2, phi_e)
with the paper's l2 and crank range, plus the assembly mode (``branch``) that
gives the straight segment (Fig. 2 shows it; the table does not state it, so
it was chosen as the mode whose path deviation is smallest and, for Hoeken,
moves along -x0 as the paper's eq (20) states).

:func:`family_linkage` scales a family to a requested ``stroke_mm``: all
lengths are multiplied by stroke_mm / stroke(paper dimensions); angles and the
crank range are kept, so every dimensionless metric is unchanged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cad.errors import DesignError
from cad.kinematics.fourbar import FourBar, solve


@dataclass(frozen=True)
class Family:
    """Paper Fig. 2 row: ratios to l2, l2 in mm, phi_e and crank range in deg."""

    name: str
    l1_l2: float
    l2_mm: float
    l3_l2: float
    l4_l2: float
    l5_l2: float
    phi_e_deg: float
    le_l2: float
    phi1_min_deg: float
    phi1_max_deg: float
    branch: int

    def paper_linkage(self) -> FourBar:
        """The linkage with the paper's own dimensions (Fig. 2 table)."""
        l2 = self.l2_mm
        return FourBar(
            self.l1_l2 * l2, l2, self.l3_l2 * l2, self.l4_l2 * l2, self.l5_l2 * l2,
            self.le_l2 * l2, math.radians(self.phi_e_deg), self.branch,
        )

    @property
    def phi1_range_rad(self) -> tuple[float, float]:
        return math.radians(self.phi1_min_deg), math.radians(self.phi1_max_deg)


#: Hoeken paper Fig. 2 (angles in deg, l2 in mm). Branches: see module docstring.
FAMILIES: dict[str, Family] = {
    "hoeken": Family("hoeken", 0.4, 62.5, 1.0, 0.0, 0.8, 0.0, 2.0, 132.0, 216.0, -1),
    "roberts": Family("roberts", 1.2, 38.46, 1.2, 0.0, 2.0, -65.7, 1.2, 37.0, 75.0, -1),
    "chebyshev": Family("chebyshev", 2.5, 50.0, 2.5, 0.0, 2.0, 0.0, 0.5, 53.0, 80.0, +1),
    "chebyshev-v": Family("chebyshev-v", 0.23, 77.5, 1.0, 0.0, 0.5, -40.3, 1.52, 115.0, 245.0, -1),
}

#: Paper Tables I and II (5 N force, 50 mm stroke). None where not given.
PAPER_TABLES: dict[str, dict[str, float | str]] = {
    "hoeken": {"torque_mean_mNm": 164, "torque_variation": 0.012, "dimensions": "115 x 120 mm",
               "dy_max_mm": 0.2, "slope_max": 0.014, "linearity": 0.990},
    "roberts": {"torque_mean_mNm": 397, "torque_variation": 0.271, "dimensions": "80 x 45 mm",
                "dy_max_mm": 0.3, "slope_max": 0.050, "linearity": 0.819},
    "chebyshev": {"torque_mean_mNm": 417, "torque_variation": 0.190, "dimensions": "105 x 125 mm",
                  "dy_max_mm": 0.1, "slope_max": 0.015, "linearity": 0.875},
    "chebyshev-v": {"torque_mean_mNm": 116, "torque_variation": 0.015, "dimensions": "135 x 105 mm",
                    "dy_max_mm": 2.4, "slope_max": 0.169, "linearity": 0.991},
}


def get_family(name: str, field: str = "mechanism.family") -> Family:
    if name not in FAMILIES:
        raise DesignError(field, f"unknown four-bar family {name!r} (known: {', '.join(FAMILIES)})")
    return FAMILIES[name]


def paper_stroke_mm(fam: Family) -> float:
    """Chord |P(phi1_max) - P(phi1_min)| of the paper's dimensions, mm."""
    lo, hi = fam.phi1_range_rad
    P = solve(fam.paper_linkage(), np.array([lo, hi])).P_mm
    return float(np.linalg.norm(P[1] - P[0]))


def family_linkage(name: str, stroke_mm: float | None = None) -> tuple[FourBar, float, float]:
    """(linkage, phi1_min_rad, phi1_max_rad) of a family, scaled to ``stroke_mm``.

    ``stroke_mm=None`` keeps the paper's dimensions.
    """
    fam = get_family(name)
    fb = fam.paper_linkage()
    if stroke_mm is not None:
        if not (stroke_mm > 0 and math.isfinite(stroke_mm)):
            raise DesignError("mechanism.stroke_mm", f"must be > 0, got {stroke_mm!r}")
        fb = fb.scaled(stroke_mm / paper_stroke_mm(fam))
    lo, hi = fam.phi1_range_rad
    return fb, lo, hi
