"""hapticad: a parametric CAD generator for haptic-device hardware.

Layers (one direction, no back-edges):
design (TOML) -> kinematics -> link geometry -> parts -> mass properties
-> dynamics -> report / checks / exports.

``cad.kinematics``, ``cad.dynamics`` and ``cad.actuators`` are pure numpy and
never import OCP, build123d or cadquery. CAD modules import lazily.
"""

__version__ = "0.1.0"
