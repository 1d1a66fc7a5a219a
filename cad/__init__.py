"""hapticad: a parametric CAD generator for haptic-device hardware.

Layers (one direction, no back-edges):
design (TOML) -> kinematics -> link geometry -> parts -> mass properties
-> dynamics -> report / checks / exports.

``cad.kinematics``, ``cad.dynamics`` and ``cad.actuators`` are pure numpy and
never import OCP, build123d or cadquery. CAD modules import lazily.
"""

__version__ = "0.1.0"

#: The supported API (:mod:`cad.api`), loaded on first use so ``import cad`` stays light.
__all__ = ["analyze", "assemble", "build_design", "cache", "check", "device_datasheet",
           "fit_design", "gii", "load_design", "mass_properties", "optimize", "render",
           "run_bench", "swap", "sweep_design", "synth", "tolerance", "voicecoil", "wall"]


def __getattr__(name: str):
    if name in __all__:
        from cad import api

        return getattr(api, name)
    raise AttributeError(f"module 'cad' has no attribute {name!r}")
