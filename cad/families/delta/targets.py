"""``check`` / ``fit`` of the delta: its targets are its datasheet's figures, computed on a build
(:func:`cad.studies.build_targets.build_target_values`); ``--free`` takes its link lengths;
every fit candidate is held to its default limits (:func:`cad.families.delta.datasheet.
delta_limits`) and refused before any CAD when its workspace is out of reach (:func:`precad`).
No CAD import."""

from __future__ import annotations

from cad.design.targets import Target
from cad.device import resolve_device
from cad.errors import DesignError, KinematicsError
from cad.families.delta.datasheet import delta_limits, force_in_every_direction_N, ratios_of
from cad.families.delta.design import OPTIMIZABLE
from cad.studies.fit import FreeParam, numeric_free

#: The delta's free lengths (mm): the four the GII optimiser ranges over.
FREE_KEYS = OPTIMIZABLE


def parse_free(spec: str, design) -> FreeParam:
    """Free parameter ``mechanism.KEY[=LO:HI]`` of a delta (:data:`FREE_KEYS`, mm; default
    range 0.5x .. 1.5x the current value). DesignError naming ``--free SPEC`` otherwise."""
    key, _, rng = spec.partition("=")
    key = key.strip()
    section, _, name = key.partition(".")
    if section != "mechanism" or name not in FREE_KEYS:
        raise DesignError(f"--free {spec}", "not a free parameter of a delta design "
                          f"(mechanism.{{{', '.join(FREE_KEYS)}}})")
    return numeric_free(spec, key, rng, float(design.params[name]))


def default_limit_targets(design) -> tuple[Target, ...]:
    """Every default limit of a delta candidate (first mode, continuous force from the ordered
    motors) as ``[targets]`` bounds, except keys its targets set: the constraints of
    ``hapticad fit``."""
    return tuple(Target(k, min=v.value) if v.op.startswith(">") else Target(k, max=v.value)
                 for k, v in delta_limits(design).items() if v.origin == "default")


def precad(design) -> tuple[dict, str | None]:
    """(values, reason or None) of a fit candidate before any CAD: a workspace point out of
    reach (outside the motor angle range, singular) is a reason, the build would refuse it;
    else the continuous and peak force in every direction (no CAD needed,
    :func:`cad.families.delta.datasheet.force_in_every_direction_N` with the resolved motor
    through its transmissions)."""
    dev = resolve_device(design)
    m, n = dev.motor.spec, ratios_of(dev)
    try:
        fc, _ = force_in_every_direction_N(design, m.torque_continuous_mNm * 1e-3, n)
        fp, _ = force_in_every_direction_N(design, m.torque_peak_mNm * 1e-3, n)
    except KinematicsError as e:
        return {}, f"workspace: {e}"
    return {"continuous_force_N": fc, "peak_force_N": fp}, None
