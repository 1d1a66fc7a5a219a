"""Tolerances of the 5-bar / twin-pantograph / haptic-pen kinematics.

They live in :mod:`cad.tolerances` (every numerical tolerance in one place, each with its
reason); this module keeps the names importable from here.
"""

from cad.tolerances import (
    ARM_SINGULAR_SIN,
    DISTAL_SINGULAR_SIN,
    ON_JOINT_MM,
    ON_WAIST_AXIS_MM,
    REACH_REL_EPS,
)

__all__ = ["ARM_SINGULAR_SIN", "DISTAL_SINGULAR_SIN", "ON_JOINT_MM", "ON_WAIST_AXIS_MM", "REACH_REL_EPS"]
