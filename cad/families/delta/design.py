"""Design files of the 3-DOF delta (``[mechanism] family = "delta"``, issue 36 §1).

Schema (mm, deg, N, N m; * = required)::

    [mechanism]  family*, base_radius_mm*, effector_radius_mm*, upper_arm_mm*, lower_arm_mm*,
                 parallelogram_width_mm (30), motor_angle_min_deg (-40), motor_angle_max_deg (85),
                 motor_azimuth_deg ([0, 120, 240]), joint_offset_mm (0), axis_offset_mm (0)
                 (the last two: Stamper's Falcon model, :class:`cad.kinematics.delta.Delta`)
    [workspace]  shape ("box" | "cylinder"), center_mm* = [x, y, z],
                 size_mm = [W, D, H] (box), diameter_mm + height_mm (cylinder), grid (5)
    [actuators]  torque_max_Nm (1.0, or [m0, m1, m2]), force_max_N (1.0)  -- the GII's
                 normalisation S_J, S_T (isotropy paper eqs 3-4), not a motor
    [optimize]   base_radius_mm / effector_radius_mm / upper_arm_mm / lower_arm_mm =
                 [min, max, count]
    [parts]      motor ("maxon-re35", a key of cad.data.catalog.MOTORS: one per arm, direct
                 drive or through [transmission]), encoder (a key of cad.data.catalog.ENCODERS) or
                 encoder_counts_per_rev (not both; default: maxon-hedl5540-500, the encoder
                 maxon pairs with the RE 35), ball_joint (a key of
                 cad.data.ball_joints.BALL_JOINTS; default ball-link-4.8)
    [motor]      the data of the motor parts.motor names, replacing catalog values
                 (:mod:`cad.design.motor`)
    [firmware]   encoder_counts_per_rev, encoder_direction, encoder_zero_deg,
                 wall_stiffness_N_per_m, wall_damping_N_s_per_m (:mod:`cad.design.firmware`;
                 ``plane`` and ``gravity_direction`` are refused: a delta's gravity is -z of
                 its base frame)

Frames and angles: :mod:`cad.kinematics.delta` (base frame z up, effector below, theta from
the horizontal, positive down, elbow-out branch). ``[targets]``: the datasheet figures
(``check``, ``fit``); ``[transmission]`` (one table: the same capstan on every arm, or
``[[transmission]]``, three tables in motor order; :mod:`cad.design.transmission`, validated
at load) drives each upper arm through a capstan; ``[prices]`` (``"designation" = unit price``,
``currency``; validated for every family by :func:`cad.design.design_prices`) prices the BOM
as ``--prices FILE.csv`` does (order.csv, the datasheet's ``bom_cost`` row). Joints of the motors (the resolved device, the
MJCF): ``theta_0``, ``theta_1``, ``theta_2``. The link lengths, the width and the
``[optimize]`` ranges' mins are held to the least sizes the parts can be made at
(:mod:`cad.families.delta.sizes`); whether the workspace is reached is the build's check
before any solid (:mod:`cad.families.delta.reach`). No CAD import.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from cad.data.ball_joints import DEFAULT_BALL_JOINT, get_ball_joint
from cad.data.catalog import get_motor
from cad.design.bounds import ANGLE_DEG, COORD_MM, GRID, LINK_MM, WORKSPACE_MM, check_number
from cad.design.fields import check_name, check_unknown, number_list, optional_table, require_table
from cad.design.firmware import parse_firmware
from cad.design.motor import parse_motor_table
from cad.design.parts import parse_encoder
from cad.design.targets import DELTA_TARGET_KEYS, parse_targets
from cad.design.transmission import parse_transmissions
from cad.errors import DesignError
from cad.families.delta import hardware as hw
from cad.families.delta.sizes import check_sizes, minimums_mm
from cad.isotropy.gii import delta_gii
from cad.isotropy.problems import DeltaProblem, candidate_grid
from cad.kinematics.delta import (
    Delta,
    box_grid_mm,
    cylinder_grid_mm,
    inverse_condition,
    workspace_volumes,
)

MECH_KEYS = ("family", "base_radius_mm", "effector_radius_mm", "upper_arm_mm", "lower_arm_mm",
             "parallelogram_width_mm", "motor_angle_min_deg", "motor_angle_max_deg",
             "motor_azimuth_deg", "joint_offset_mm", "axis_offset_mm")
MECH_DEFAULTS = {"parallelogram_width_mm": 30.0, "motor_angle_min_deg": -40.0,
                 "motor_angle_max_deg": 85.0}
WS_KEYS = ("shape", "center_mm", "size_mm", "diameter_mm", "height_mm", "grid")
OPTIMIZABLE = ("base_radius_mm", "effector_radius_mm", "upper_arm_mm", "lower_arm_mm")
PARTS_KEYS = ("motor", "encoder", "encoder_counts_per_rev", "ball_joint")
#: The encoder a delta that states none gets: maxon's HEDL 5540 (500 CPT, 2000 counts/rev
#: after x4 decoding), the encoder maxon combines with the RE 35 the delta's arms default to.
DEFAULT_ENCODER = "maxon-hedl5540-500"
#: [firmware] keys of a planar device the delta does not take (gravity is -z, base frame).
FIRMWARE_PLANAR = ("plane", "gravity_direction")
#: The motor joints (one per arm): the resolved device's and the MJCF's joint names.
JOINTS = ("theta_0", "theta_1", "theta_2")


@dataclass(frozen=True)
class DeltaParts:
    """The delta's ``[parts]``: ``motor`` (catalog key, one per arm, direct drive or through
    ``[transmission]``),
    ``encoder`` (catalog key) or ``encoder_counts_per_rev`` (counts per motor turn after x4
    decoding), None when not stated (:func:`cad.device.resolve_device` chooses);
    ``ball_joint`` the parallelogram's ball joints (a key of
    :data:`cad.data.ball_joints.BALL_JOINTS`)."""

    motor: str = hw.MOTOR
    encoder: str | None = None
    encoder_counts_per_rev: int | None = None
    ball_joint: str = DEFAULT_BALL_JOINT


@dataclass(frozen=True)
class DeltaDesign:
    """A validated delta design: ``mechanism`` a :class:`cad.kinematics.delta.Delta`,
    ``params`` its lengths (mm), ``workspace``/``actuators`` the validated tables with
    defaults, ``optimize`` {name: (min, max, count)}, ``raw`` the TOML mapping."""

    name: str
    source: str
    family: str
    mechanism: Any
    params: dict[str, float]
    parallelogram_width_mm: float
    workspace: dict[str, Any]
    actuators: dict[str, Any]
    optimize: dict[str, tuple[float, float, int]]
    raw: dict = field(repr=False)
    #: ``[targets]`` (:data:`cad.design.targets.DELTA_TARGET_KEYS`): ``check`` / ``fit`` bounds
    targets: tuple = ()
    parts: DeltaParts = field(default_factory=DeltaParts)
    #: ``[motor]`` overrides of ``parts.motor`` (:func:`cad.design.motor.parse_motor_table`)
    motor: tuple = ()
    #: ``[firmware]`` (:class:`cad.design.firmware.FirmwareOptions`)
    firmware: Any = None

    def motor_joints(self) -> tuple[tuple[str, str], ...]:
        """(joint, parts field naming its motor) of the three arm motors."""
        return tuple((j, "motor") for j in JOINTS)

    @property
    def transmissions(self) -> tuple:
        """One :class:`cad.design.transmission.Transmission` per motor (:data:`JOINTS` order):
        the ``[transmission]`` table or ``[[transmission]]`` array (validated at load), direct
        drive without one. Read from ``raw`` (a direct design's hash is unchanged)."""
        return parse_transmissions(self.raw.get("transmission"), len(JOINTS))

    def default_encoder(self) -> tuple[str, str]:
        """(catalog encoder, hint) a design that states no encoder gets
        (:data:`DEFAULT_ENCODER`)."""
        return DEFAULT_ENCODER, "; set parts.encoder"

    def workspace_points(self) -> np.ndarray:
        """Workspace samples (N, 3) mm, base frame (box: C order of ``grid_shape``)."""

        ws = self.workspace
        if ws["shape"] == "box":
            return box_grid_mm(ws["center_mm"], ws["size_mm"], ws["grid"])
        return cylinder_grid_mm(ws["center_mm"], ws["diameter_mm"], ws["height_mm"], ws["grid"])

    def workspace_size_mm(self) -> list[float]:
        """The ``[workspace]`` extents along x, y, z (mm, base frame): the box's ``size_mm``
        [W, D, H], a cylinder's bounding box [D, D, H] (diameter_mm twice, height_mm)."""
        ws = self.workspace
        if ws["shape"] == "box":
            return [float(v) for v in ws["size_mm"]]
        return [float(ws["diameter_mm"])] * 2 + [float(ws["height_mm"])]

    def grid_shape(self) -> tuple[int, ...]:
        """The sample grid's shape (box: (n, n, n); cylinder: (N,), axis and rings)."""
        n = self.workspace["grid"]
        return (n, n, n) if self.workspace["shape"] == "box" else (len(self.workspace_points()),)

    def gii(self):
        """GII (isotropy paper eq 5) over the workspace: a :class:`cad.isotropy.gii.GIIResult`."""

        act = self.actuators
        return delta_gii(self.mechanism, self.workspace_points(), act["torque_max_Nm"],
                         act["force_max_N"])

    def point_units(self) -> tuple[str, ...]:
        """Names of a workspace point's coordinates, with units."""
        return ("x_mm", "y_mm", "z_mm")

    def gii_extras(self) -> dict:
        """The delta's rows of the GII report (:func:`cad.isotropy.report.gii_extras`): the
        reachable and well-conditioned workspace (cm^3, :func:`cad.kinematics.delta.workspace_volumes`)
        and the worst inverse condition number over the ``[workspace]`` grid."""
        ratio, _ = inverse_condition(self.mechanism, self.workspace_points())
        return {"workspace_volumes": workspace_volumes(self.mechanism),
                "workspace_inverse_condition_min": float(ratio.min())}

    def problem(self):
        """The ``[optimize]`` candidate grid x workspace as a culling problem (eq 6)."""

        if not self.optimize:
            raise DesignError("optimize", "no free parameters: add e.g. upper_arm_mm = [min, max, count]")
        _, params = candidate_grid(self.optimize, self.params)
        return DeltaProblem(params, self.workspace_points(), self.grid_shape(), self.mechanism,
                            self.actuators["torque_max_Nm"], self.actuators["force_max_N"])


def _mechanism(mech: dict[str, Any], ball_joint: str = DEFAULT_BALL_JOINT):

    check_unknown(mech, MECH_KEYS, "mechanism")
    vals = {}
    for key in OPTIMIZABLE:
        if key not in mech:
            raise DesignError(f"mechanism.{key}", "is required (mm)")
        if key == "effector_radius_mm" and mech[key] == 0:
            vals[key] = 0.0
            continue
        vals[key] = check_number(f"mechanism.{key}", mech[key], LINK_MM)
    extra = {k: mech.get(k, v) for k, v in MECH_DEFAULTS.items()}
    width = check_number("mechanism.parallelogram_width_mm", extra["parallelogram_width_mm"], LINK_MM)
    lo = check_number("mechanism.motor_angle_min_deg", extra["motor_angle_min_deg"], ANGLE_DEG)
    hi = check_number("mechanism.motor_angle_max_deg", extra["motor_angle_max_deg"], ANGLE_DEG)
    if not lo < hi or hi - lo > 360:
        raise DesignError("mechanism.motor_angle_max_deg",
                          f"must exceed motor_angle_min_deg ({lo:g}) by at most 360 deg, got {hi:g}")
    az = mech.get("motor_azimuth_deg", [0.0, 120.0, 240.0])
    if not isinstance(az, list) or len(az) != 3:
        raise DesignError("mechanism.motor_azimuth_deg", f"must be 3 angles [deg], got {az!r}")
    az = [check_number(f"mechanism.motor_azimuth_deg[{k}]", a, ANGLE_DEG) for k, a in enumerate(az)]
    offsets = {k: check_number(f"mechanism.{k}", mech.get(k, 0.0), COORD_MM)
               for k in ("joint_offset_mm", "axis_offset_mm")}
    if offsets["joint_offset_mm"] < 0:
        raise DesignError("mechanism.joint_offset_mm", f"must be >= 0, got {offsets['joint_offset_mm']!r}")
    check_sizes({**vals, "parallelogram_width_mm": width, "joint_offset_mm": offsets["joint_offset_mm"]},
                ball_joint)
    d = Delta(vals["base_radius_mm"], vals["effector_radius_mm"], vals["upper_arm_mm"],
              vals["lower_arm_mm"], motor_azimuth_rad=tuple(math.radians(a) for a in az),
              theta_min_rad=math.radians(lo), theta_max_rad=math.radians(hi), **offsets)
    return d, vals, width


def _workspace(ws: dict[str, Any]) -> dict[str, Any]:
    check_unknown(ws, WS_KEYS, "workspace")
    shape = ws.get("shape", "box")
    if shape not in ("box", "cylinder"):
        raise DesignError("workspace.shape", f"must be 'box' or 'cylinder', got {shape!r}")
    center = number_list(ws, "center_mm", "workspace", length=3)
    for k, v in zip("xyz", center, strict=True):
        check_number(f"workspace.center_mm[{k}]", v, COORD_MM)
    grid = int(check_number("workspace.grid", ws.get("grid", 5), GRID))
    if grid < 2:
        raise DesignError("workspace.grid", f"must be >= 2 (the faces are sampled), got {grid}")
    out: dict[str, Any] = {"shape": shape, "center_mm": center, "grid": grid}
    wrong = ("diameter_mm", "height_mm") if shape == "box" else ("size_mm",)
    for key in wrong:
        if key in ws:
            raise DesignError(f"workspace.{key}", f"is not a key of a {shape} workspace")
    if shape == "box":
        size = number_list(ws, "size_mm", "workspace", length=3)
        out["size_mm"] = [check_number(f"workspace.size_mm[{k}]", v, WORKSPACE_MM)
                          for k, v in zip("xyz", size, strict=True)]
    else:
        for key in ("diameter_mm", "height_mm"):
            if key not in ws:
                raise DesignError(f"workspace.{key}", "is required for a cylinder workspace (mm)")
            out[key] = check_number(f"workspace.{key}", ws[key], WORKSPACE_MM)
    return out


def _actuators(act: dict[str, Any]) -> dict[str, Any]:
    check_unknown(act, ("torque_max_Nm", "force_max_N"), "actuators")
    out: dict[str, Any] = {}
    for key in ("torque_max_Nm", "force_max_N"):
        v = act.get(key, 1.0)
        vals = number_list(act, key, "actuators", length=3) if isinstance(v, list) else [v]
        for x in vals:
            if isinstance(x, bool) or not isinstance(x, (int, float)) or not (x > 0 and math.isfinite(x)):
                raise DesignError(f"actuators.{key}", f"must be finite and > 0, got {v!r}")
        out[key] = [float(x) for x in vals] if isinstance(v, list) else float(v)
    return out


def _parts(table: dict[str, Any]) -> DeltaParts:
    check_unknown(table, PARTS_KEYS, "parts")
    motor = table.get("motor", DeltaParts.motor)
    if not isinstance(motor, str) or not motor:
        raise DesignError("parts.motor", f"must be a catalog key (a string), got {motor!r}")
    get_motor(motor, "parts.motor")
    enc = table.get("encoder")
    if enc is not None and (not isinstance(enc, str) or not enc):
        raise DesignError("parts.encoder", f"must be a catalog key (a string), got {enc!r}")
    joint = table.get("ball_joint", DEFAULT_BALL_JOINT)
    get_ball_joint(joint, "parts.ball_joint")
    return DeltaParts(motor, enc, parse_encoder(table, "parts", enc), joint)


def _firmware(table: dict[str, Any]):
    for key in FIRMWARE_PLANAR:
        if key in table:
            raise DesignError(f"firmware.{key}", "a delta's gravity is -z of its base frame (z up): "
                              "remove the planar device's key")
    return parse_firmware(table, 3)


def _optimize(raw: dict[str, Any], least: dict) -> dict[str, tuple[float, float, int]]:
    """``[optimize]`` ranges; ``least``: :func:`cad.families.delta.sizes.minimums_mm` of the
    design's width and joint offset (a range's min below it is refused: no candidate there
    could be built, most often metres typed for mm)."""
    table = optional_table(raw, "optimize", "")
    check_unknown(table, OPTIMIZABLE, "optimize")
    out = {}
    for key in table:
        lo, hi, count = number_list(table, key, "optimize", length=3)
        f = f"optimize.{key}"
        if not float(count).is_integer() or count < 1:
            raise DesignError(f, f"count must be an integer >= 1, got {table[key][2]!r}")
        if hi < lo or (lo < 0 if key == "effector_radius_mm" else lo <= 0):
            raise DesignError(f, f"needs 0 < min <= max, got [{lo}, {hi}]")
        if key in least and (lo < least[key][0] or (least[key][1] and lo <= least[key][0])):
            v, strict, why = least[key]
            raise DesignError(f, f"the range's min must be {'>' if strict else '>='} {v:.4g} mm, got {lo:g}: {why}")
        out[key] = (lo, hi, int(count))
    return out


def parse(raw: dict[str, Any], source: str = "<design>") -> DeltaDesign:
    """Validate a raw delta design; every problem is a :class:`DesignError` naming the key."""
    check_unknown(raw, ("name", "description", "mechanism", "workspace", "actuators", "optimize",
                        "parts", "motor", "firmware", "targets", "transmission", "prices"), "")
    mech = require_table(raw, "mechanism", "")
    if mech.get("family") != "delta":
        raise DesignError("mechanism.family", f"must be 'delta', got {mech.get('family')!r}")
    parts = _parts(optional_table(raw, "parts", ""))
    d, params, width = _mechanism(mech, parts.ball_joint)
    parse_transmissions(raw.get("transmission"), len(JOINTS))  # refused here, at load
    return DeltaDesign(
        name=check_name(raw.get("name", "delta")), source=source, family="delta", mechanism=d,
        params=params, parallelogram_width_mm=width,
        workspace=_workspace(require_table(raw, "workspace", "")),
        actuators=_actuators(optional_table(raw, "actuators", "")),
        optimize=_optimize(raw, minimums_mm(width, d.joint_offset_mm, parts.ball_joint)),
        raw=raw, parts=parts,
        motor=parse_motor_table(optional_table(raw, "motor", ""), "motor"),
        firmware=_firmware(optional_table(raw, "firmware", "")),
        targets=parse_targets(optional_table(raw, "targets", ""), allowed_keys=DELTA_TARGET_KEYS))
