"""What the generated firmware is made of: one plain :class:`DeviceSpec` per device (SI).

Built from the design (kinematics, ``[firmware]`` options), the build's mass properties
(report.json ``links`` / ``bodies``: mass and COM of every moving body in its link frame,
from the solids) and the motor catalog. No CAD import.

Kinds: ``fourbar`` (1 motor on the crank, task = handle point P (x, y) in R0),
``fivebar`` (2 motors, task = end effector E (x, y) in the base frame) and ``twin``
(4 motors, task = (x, y, theta): main journal in the base frame and crank angle).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from cad.errors import DesignError

#: Standard gravity (m/s^2), CGPM 1901 (the same value as cad.actuators.powermouse.G0_M_S2).
G0_M_S2 = 9.80665


@dataclass(frozen=True)
class Body:
    """A moving body: ``mass_kg``, its COM ``com_m`` (x, y) in its link frame (m) and its
    inertia about the COM normal to the plane ``izz_kg_m2``."""

    mass_kg: float
    com_m: tuple[float, float]
    izz_kg_m2: float = 0.0


@dataclass(frozen=True)
class MotorData:
    """Motor constants (SI) and their sources (catalog :class:`cad.data.catalog.MotorSpec`)."""

    key: str
    kt_Nm_per_A: float
    current_continuous_A: float
    current_peak_A: float
    torque_continuous_Nm: float
    torque_peak_Nm: float
    source: str


@dataclass(frozen=True)
class DeviceSpec:
    """Everything the generator writes, SI units (module docstring for kinds and frames).

    ``params``: the kinematic constants (m, rad, mode signs) named as in the C code;
    ``q_home_rad``: joint angles at the home pose; ``encoder_*``: defaults of the encoder
    parameters; ``gravity_m_s2``: the gravity vector in the device plane (None when the
    device works in a horizontal plane; a spatial device's: 3-D, base frame); ``bodies``: moving bodies by name; ``rotor_kg_m2``:
    each motor's rotor inertia (the build's Jm); ``model``: the family's
    :class:`cad.firmware.model.KinematicModel` (``kind`` is its name).
    """

    kind: str
    name: str
    family: str
    design_hash: str
    version: str
    n_joints: int
    n_task: int
    params: dict[str, float]
    q_home_rad: tuple[float, ...]
    encoder_counts_per_rev: int
    encoder_direction: tuple[int, ...]
    encoder_zero_rad: tuple[float, ...]
    motor: MotorData
    gravity_m_s2: tuple[float, ...] | None
    bodies: dict[str, Body] = field(default_factory=dict)
    rotor_kg_m2: float = 0.0
    wall: dict[str, float] = field(default_factory=dict)
    device: dict[str, float] = field(default_factory=dict)
    model: Any = field(default=None, compare=False, repr=False)
    #: transmission ratio n of each joint's motor (joint torque = n motor torque, joint angle =
    #: motor angle / n: :class:`cad.device.Transmission`); empty: every joint driven directly
    gear: tuple[float, ...] = ()
    #: each joint's motor side at its joint through its transmission, n^2 (J_m + J_capstan)
    #: (kg m^2, :meth:`cad.device.ResolvedDevice.joint_rotor_inertia_kg_m2`); empty: every
    #: joint driven directly, ``rotor_kg_m2`` on each
    rotor_joints_kg_m2: tuple[float, ...] = ()
    #: each joint's motor where they differ (the haptic pen: RE 40 waists, RE 35 shoulders;
    #: ``report.json`` ``device.motors`` order); empty: every joint has ``motor``
    joint_motors: tuple[MotorData, ...] = ()

    def kt_of(self) -> np.ndarray:
        """(n_joints,) torque constants (N m/A) of the joints' motors."""
        if not self.joint_motors:
            return np.full(self.n_joints, self.motor.kt_Nm_per_A)
        return np.array([m.kt_Nm_per_A for m in self.joint_motors])

    def gear_of(self) -> np.ndarray:
        """(n_joints,) ratios, ones for a direct-drive device."""
        return np.asarray(self.gear, float) if self.gear else np.ones(self.n_joints)


def motor_data(motor) -> MotorData:
    """:class:`MotorData` of a catalog motor; DesignError naming the missing catalog field."""
    names = ("torque_constant_mNm_per_A", "current_continuous_A", "torque_continuous_mNm",
             "torque_peak_mNm")
    vals = {n: getattr(motor, n, None) for n in names}
    missing = [n for n, v in vals.items() if v is None]
    if missing:
        raise DesignError("parts.motor", f"the catalog entry {motor.key!r} has no "
                          f"{', '.join(missing)}: the firmware needs them (use maxon-re35)")
    kt = vals["torque_constant_mNm_per_A"] * 1e-3
    src = "; ".join(f"{n}: {motor.source_of(n) or 'no source recorded'}"
                    + (" (unverified)" if motor.is_unverified(n) else "") for n in names)
    return MotorData(motor.key, kt, float(vals["current_continuous_A"]),
                     vals["torque_peak_mNm"] * 1e-3 / kt, vals["torque_continuous_mNm"] * 1e-3,
                     vals["torque_peak_mNm"] * 1e-3, src)


def body_from_report(entry: dict) -> Body:
    """A :class:`Body` from a report.json mass-properties entry (``mass_kg``, ``com_mm``,
    ``inertia_com_kg_m2``)."""
    c = entry["com_mm"]
    return Body(float(entry["mass_kg"]), (float(c[0]) * 1e-3, float(c[1]) * 1e-3),
                float(entry["inertia_com_kg_m2"][2][2]))


def gravity_vector(opts) -> tuple[float, float] | None:
    """g (m/s^2) in the device frame for a vertical-plane device, None when horizontal."""
    if not opts.vertical:
        return None
    gx, gy = opts.gravity_direction
    return (G0_M_S2 * gx, G0_M_S2 * gy)


def encoder_zero(opts, q_home) -> tuple[float, ...]:
    """Joint angles at count 0 (rad): ``encoder_zero_deg`` or the home pose."""
    if opts.encoder_zero_deg is None:
        return tuple(float(q) for q in q_home)
    return tuple(math.radians(z) for z in opts.encoder_zero_deg)


def angles_from_counts(spec: DeviceSpec, counts) -> np.ndarray:
    """q = zero + direction * 2 pi * counts / (counts_per_rev * n), (N, n_joints) rad: the
    encoder on the motor shaft turns n times per joint turn (n = 1 for direct drive)."""
    c = np.asarray(counts, dtype=float)
    d = np.asarray(spec.encoder_direction, dtype=float)
    z = np.asarray(spec.encoder_zero_rad, dtype=float)
    if not spec.gear:
        return z + d * (2.0 * math.pi / spec.encoder_counts_per_rev) * c
    return z + d * (2.0 * math.pi / spec.encoder_counts_per_rev) * c / spec.gear_of()


def motor_currents_A(spec: DeviceSpec, tau_Nm) -> np.ndarray:
    """Unsaturated motor currents of joint torques ``tau_Nm`` (N, n_joints): i = tau / (n kt), A
    (kt of each joint's motor)
    (the reference of ``hc_motor_currents`` below its limit)."""
    return np.asarray(tau_Nm, float) / (spec.gear_of() * spec.kt_of())
