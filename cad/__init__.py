"""hapticad: a parametric CAD generator for haptic-device hardware.

Layers (one direction, no back-edges):
design (TOML) -> kinematics -> link geometry -> parts -> mass properties
-> dynamics -> report / checks / exports.

``cad.kinematics``, ``cad.dynamics``, ``cad.actuators``, ``cad.isotropy``, the pure
modules of ``cad.massprops``, ``cad.data`` and ``cad.design`` never import OCP, build123d or
cadquery, nor a CAD-layer package (tests/architecture/test_import_graph.py). CAD modules import lazily.

The supported API is :mod:`cad.api` (every command as a function; ``assemble`` and
``design.replace`` for objects), its names re-exported here; the CLI (:mod:`cad.cli`) is
built on it and imported by nothing but the entry point.
"""

__version__ = "0.1.0"

#: The supported API (:mod:`cad.api`), loaded on first use so ``import cad`` stays light.
__all__ = ["analyze", "assemble", "bench_log", "build_design", "cache", "check", "device_datasheet",
           "fit_design", "gii", "identify_device", "load_design", "mass_properties", "optimize", "render",
           "run_bench", "swap", "sweep_design", "synth", "tolerance", "voicecoil", "wall"]


def __getattr__(name: str):
    if name in __all__ or name == "api":  # cad.api.COMMANDS works after a bare `import cad`
        import importlib

        api = importlib.import_module("cad.api")
        return api if name == "api" else getattr(api, name)
    raise AttributeError(f"module 'cad' has no attribute {name!r}")
