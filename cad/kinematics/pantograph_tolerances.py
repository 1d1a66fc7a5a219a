"""Tolerances of the 5-bar / twin-pantograph / haptic-pen kinematics, each with its reason.

Lengths in mm, angles in radians. Kept apart from :mod:`cad.tolerances` so the
pantograph helper owns them; same documentation rule.
"""

#: |sin| of the angle between a proximal and its distal link (serial, "type-1"
#: singularity: the arm is fully stretched or folded, the workspace boundary)
#: below this is singular. At 1e-9 the Jacobian row is ~1e9 times its regular
#: size, so sigma_max and the GII are numerically meaningless anyway; float64
#: round-off of the acos argument for 100 mm links is ~1e-16 relative, so a
#: genuinely regular point is never flagged.
ARM_SINGULAR_SIN = 1e-9

#: |sin| of the angle between the two distal links (parallel, "type-2"
#: singularity: the distal links are collinear and the end effector cannot
#: resist a force along their normal) below this is singular. Same reasoning.
DISTAL_SINGULAR_SIN = 1e-9

#: Reach margin: |E - B| > (l2 + l3) * (1 + this) or < |l2 - l3| * (1 - this)
#: is unreachable. Inside the margin the acos argument is clipped to [-1, 1]
#: and the point is reported singular (not unreachable).
REACH_REL_EPS = 1e-12

#: |E - B| below this (mm) leaves atan2(E - B) undefined: the end effector sits
#: on an actuated joint. Unreachable for any arm with l2 != l3, singular else.
ON_JOINT_MM = 1e-9

#: Radial distance (mm) of a pen end from its waist axis below which the waist
#: angle is undefined (haptic pen, cylindrical coordinates).
ON_WAIST_AXIS_MM = 1e-9
