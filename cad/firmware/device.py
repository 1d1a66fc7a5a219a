"""The :class:`~cad.firmware.spec.DeviceSpec` of a built design (design + report.json + the
resolved device): what the family's kinematic model reads off the design and report
(:attr:`cad.firmware.model.KinematicModel.spec_params`: the linkage, ranges, working modes,
the bodies' masses and COMs from the solids) and the device's motor and encoder.
Lengths leave in metres.
"""

from __future__ import annotations

from dataclasses import replace

from cad.device import resolve_device
from cad.firmware import linkage_model
from cad.firmware.spec import (
    DeviceSpec,
    encoder_zero,
    gravity_vector,
    motor_data,
)


def device_spec(design, report: dict, design_hash: str, version: str, device=None,
                model=None) -> DeviceSpec:
    """The DeviceSpec of ``design`` built into ``report`` through its kinematic ``model``
    (:class:`cad.firmware.model.KinematicModel`; None: the one the design's family gives,
    :func:`cad.firmware.linkage_model`). The motor constants, rotor inertia and encoder
    count are the resolved device's (:func:`cad.device.resolve_device`; resolved here when
    ``device`` is None). Raises DesignError naming ``--formats`` for a family without one."""
    if model is None:

        model = linkage_model(design)
    opts = design.firmware
    device = device if device is not None else resolve_device(design)
    motor = _motor_data(device.motor)
    sp = model.spec_params(design, report, device)
    per_joint = tuple(_motor_data(m) for m in device.motors)
    joint_motors = per_joint if len(set(per_joint)) > 1 else ()
    return DeviceSpec(
        kind=model.kind, name=design.name, family=design.family, design_hash=design_hash,
        version=version, n_joints=sp.n_joints, n_task=sp.n_task, params=sp.params,
        q_home_rad=sp.q_home_rad, encoder_counts_per_rev=device.encoder.counts_per_rev,
        encoder_direction=tuple(opts.encoder_direction),
        encoder_zero_rad=encoder_zero(opts, sp.q_home_rad), motor=motor,
        gravity_m_s2=sp.gravity_m_s2 if sp.gravity_m_s2 is not None else gravity_vector(opts), bodies=sp.bodies,
        rotor_kg_m2=device.motor.rotor_inertia_kg_m2, model=model,
        gear=(() if all(t.ratio == 1.0 for t in device.transmissions)
              else tuple(float(t.ratio) for t in device.transmissions)),
        joint_motors=joint_motors,
        rotor_joints_kg_m2=(() if all(t.ratio == 1.0 for t in device.transmissions) else
                            tuple(device.joint_rotor_inertia_kg_m2(m.joint) for m in device.motors)),
    )


def _motor_data(m):
    """The :class:`MotorData` of a resolved motor (named by its ``[motor]`` table's name when
    it has one: the header names the motor the device uses)."""
    data = motor_data(m.spec)
    return replace(data, key=m.name) if m.from_motor_table else data
