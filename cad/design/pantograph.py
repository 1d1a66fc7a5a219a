"""Design files of the pantograph families: "pantograph", "twin-pantograph", "haptic-pen".

Schema (mm, N, N m; every key optional unless marked *):

``pantograph`` (symmetric 5-bar, isotropy paper §3 and Fig. 2)::

    [mechanism]  family*, base_mm*, proximal_mm*, distal_mm*,
                 proximal_right_mm, distal_right_mm (general 5-bar; default = left),
                 elbow_left (+1), elbow_right (-1)
    [workspace]  side_mm* (a square) or size_mm* = [W, H] (a rectangle, W along x; exactly
                 one of the two), center_mm* = [x, y], grid (11: samples per side)
    [actuators]  torque_max_Nm (1.0, or [left, right]), force_max_N (1.0)
    [optimize]   base_mm / proximal_mm / distal_mm = [min, max, count]
    [parts]      see :class:`PantographParts` (the mouse's lower group and a handle at E)
    [transmission]  a capstan on both motors, or ``[[transmission]]`` one per motor (left,
                 right): :mod:`cad.design.transmission` (omitted: direct drive)

``twin-pantograph`` (haptic mouse, §4.1)::

    [mechanism]  family*, base_mm*, proximal_mm*, distal_mm*, knob_diameter_mm (12.5),
                 crank_mm (eq 7: 1.6 * knob_diameter_mm)
    [workspace]  side_mm* or size_mm* = [W, H], center_mm*, grid (7), theta_grid (8),
                 home_mm (= center_mm), home_theta_deg (90)
    [actuators]  torque_max_Nm (1.0), force_max_N (1.0), moment_max_Nm (F * crank / 2)
    [optimize]   base_mm / proximal_mm / distal_mm = [min, max, count]
    [parts]      see :class:`PantographParts`
    [transmission]  a capstan on all four motors, or ``[[transmission]]`` one per motor (knob
                 left, knob right, crank left, crank right): :mod:`cad.design.transmission`
                 (omitted: direct drive; the build lays out each 5-bar's drums in one band or,
                 the crank pantograph's, in two, else refuses in one line)
    [firmware]   (both families) plane, encoders, wall: :mod:`cad.design.firmware`
    [motor]      (every family here) the data of the motor ``parts.motor`` names, replacing
                 catalog values: :mod:`cad.design.motor` (the pen's waist motor keeps its own)

``haptic-pen`` (§4.2, Table 2)::

    [mechanism]  family*, shoulder_base_mm*, proximal_mm*, distal_mm*, pen_mm*,
                 arm_spacing_mm (= pen_mm), waist_torque_ratio (1.6)
    [workspace]  center_mm* = [x, y, z], size_mm ([160, 100, 100]), grid ([5, 3, 3]),
                 rotation_deg (45), rotation_grid (3)
    [actuators]  torque_max_Nm (1.0, shoulder), force_max_N (1.0), moment_arm_mm (35)
    [optimize]   shoulder_base_mm / proximal_mm / distal_mm / pen_mm /
                 waist_torque_ratio = [min, max, count]

Top level: ``name``, ``description`` (strings), the tables above, and ``[targets]`` for
``hapticad check`` (keys: :data:`cad.design.targets.PANTOGRAPH_TARGET_KEYS`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from cad.data.catalog import PAPER_MOUSE_ENCODER, get_bearing, get_motor
from cad.data.materials import get_material
from cad.design.bounds import check_work
from cad.design.fields import (
    check_name,
    check_unknown,
    number_list,
    optional_int,
    optional_number,
    optional_positive,
    optional_table,
    require_number,
    require_positive,
    require_table,
)
from cad.design.firmware import parse_firmware
from cad.design.motor import parse_motor_table
from cad.design.replace import TableReplace, ValidatedReplace
from cad.design.targets import PANTOGRAPH_TARGET_KEYS, parse_targets
from cad.design.transmission import Transmission, parse_transmissions
from cad.errors import DesignError
from cad.isotropy import problems
from cad.isotropy.gii import fivebar_gii, square_grid_mm
from cad.kinematics import haptic_pen as kpen
from cad.kinematics import twin_pantograph as ktwin
from cad.kinematics.fivebar import FiveBar
from cad.kinematics.haptic_pen import HapticPen, pen_gii

FAMILIES = ("pantograph", "twin-pantograph", "haptic-pen")

#: Bounds on every dimensional number of a design (mm, N, N m) and on Q1. Outside
#: them float64 loses the kinematics: the 5-bar IK squares lengths (overflow above
#: ~1e154 mm, measured RuntimeWarnings at 1e300), the Jacobian divides by them, and
#: denormal scalings round the singular values. A nanometre and a thousand
#: kilometres bracket every haptic device with margin.
MAGNITUDE_MIN = 1e-6
MAGNITUDE_MAX = 1e9
#: Workspace samples and [optimize] (candidate, sample) pairs: bounded in
#: :data:`cad.design.bounds.WORK` (one place for every command's work).

MECH_KEYS = {
    "pantograph": (
        "family",
        "base_mm",
        "proximal_mm",
        "distal_mm",
        "proximal_right_mm",
        "distal_right_mm",
        "elbow_left",
        "elbow_right",
    ),
    "twin-pantograph": (
        "family",
        "base_mm",
        "proximal_mm",
        "distal_mm",
        "knob_diameter_mm",
        "crank_mm",
    ),
    "haptic-pen": (
        "family",
        "shoulder_base_mm",
        "proximal_mm",
        "distal_mm",
        "pen_mm",
        "arm_spacing_mm",
        "waist_torque_ratio",
    ),
}
WS_KEYS = {
    "pantograph": ("side_mm", "size_mm", "center_mm", "grid"),
    "twin-pantograph": ("side_mm", "size_mm", "center_mm", "grid", "theta_grid", "home_mm", "home_theta_deg"),
    "haptic-pen": ("center_mm", "size_mm", "grid", "rotation_deg", "rotation_grid"),
}
ACT_KEYS = {
    "pantograph": ("torque_max_Nm", "force_max_N"),
    "twin-pantograph": ("torque_max_Nm", "force_max_N", "moment_max_Nm"),
    "haptic-pen": ("torque_max_Nm", "force_max_N", "moment_arm_mm"),
}
#: free parameters [optimize] may range over, per family.
OPTIMIZABLE = {
    "pantograph": ("base_mm", "proximal_mm", "distal_mm"),
    "twin-pantograph": ("base_mm", "proximal_mm", "distal_mm"),
    "haptic-pen": ("shoulder_base_mm", "proximal_mm", "distal_mm", "pen_mm", "waist_torque_ratio"),
}


@dataclass(frozen=True)
class PantographParts(TableReplace):
    """Part parameters of the twin-pantograph mouse (mm; catalogue keys named).

    Links: carbon-fibre tubes bonded into aluminium clevises (isotropy paper
    §4.1: "aluminum clevises, carbon fibre links"); every passive joint a
    steel pin in two ball bearings (``bearing``: bd_warehouse size, bore =
    pin diameter). Motors: ``motor`` key of :data:`cad.data.catalog.MOTORS`
    (the paper's mouse used maxon motors; the catalogue's RE 35 is the
    default), mounted on square motor-mount plates; the crank pantograph's
    under the base plate, the knob pantograph's on a bridge above the links.
    """

    tube_od_mm: float = 8.0
    tube_id_mm: float = 6.0
    tube_material: str = "carbon-fibre"
    clevis_material: str = "aluminium-6061"
    clevis_length_mm: float = 20.0
    clevis_width_mm: float = 14.0
    clevis_height_mm: float = 12.0
    socket_depth_mm: float = 10.0
    bearing: str = "M4-9-2.5"
    pin_material: str = "steel-1018"
    motor: str = "maxon-re35"
    motor_mount_thickness_mm: float = 5.0
    crank_material: str = "aluminium-7075"
    crank_thickness_mm: float = 5.0
    knob_material: str = "delrin"
    knob_height_mm: float = 25.0
    plate_material: str = "aluminium-6061"
    plate_thickness_mm: float = 6.0
    post_diameter_mm: float = 12.0
    layer_gap_mm: float = 3.0


_PART_STR = (
    "tube_material",
    "clevis_material",
    "pin_material",
    "crank_material",
    "knob_material",
    "plate_material",
    "bearing",
    "motor",
)


def parse_parts(table: dict[str, Any], prefix: str = "parts") -> PantographParts:
    """Validate the ``[parts]`` table of a twin-pantograph (an empty one gives the defaults)."""
    default = PantographParts()
    allowed = list(PantographParts.__dataclass_fields__)
    check_unknown(table, allowed, prefix)
    kw: dict[str, Any] = {}
    for key in allowed:
        if key not in table:
            continue
        if key in _PART_STR:
            v = table[key]
            if not isinstance(v, str) or not v:
                raise DesignError(f"{prefix}.{key}", f"must be a non-empty string, got {v!r}")
            kw[key] = v
        else:
            kw[key] = require_positive(table, key, prefix)
    p = replace(default, **kw)
    for key in _PART_STR[:6]:
        get_material(getattr(p, key), f"{prefix}.{key}")
    b = get_bearing(p.bearing, f"{prefix}.bearing")
    p = replace(p, bearing=b.size)  # an ISO designation ("608") in its catalog form
    m = get_motor(p.motor, f"{prefix}.motor")

    def need(cond: bool, key: str, reason: str) -> None:
        if not cond:
            raise DesignError(f"{prefix}.{key}", f"{reason}, got {getattr(p, key)!r}")

    need(p.tube_id_mm < p.tube_od_mm, "tube_id_mm", f"must be < tube_od_mm ({p.tube_od_mm})")
    need(
        p.tube_od_mm + 2.0 <= p.clevis_width_mm,
        "tube_od_mm",
        f"needs 1 mm walls in clevis_width_mm ({p.clevis_width_mm})",
    )
    need(
        p.tube_od_mm + 2.0 <= p.clevis_height_mm,
        "tube_od_mm",
        f"needs 1 mm walls in clevis_height_mm ({p.clevis_height_mm})",
    )
    need(
        b.D_mm + 2.0 <= p.clevis_width_mm,
        "clevis_width_mm",
        f"must hold bearing {p.bearing} (D = {b.D_mm} mm) with 1 mm walls",
    )
    need(
        2 * b.B_mm <= p.clevis_height_mm,
        "clevis_height_mm",
        f"must hold two {p.bearing} bearings (2 x {b.B_mm} mm)",
    )
    need(
        p.socket_depth_mm < p.clevis_length_mm - b.D_mm / 2,
        "socket_depth_mm",
        "must stop short of the bearing bore",
    )
    need(
        m.shaft_diameter_mm + 2.0 <= p.clevis_width_mm,
        "clevis_width_mm",
        f"must take the {p.motor} shaft",
    )
    return p


@dataclass(frozen=True)
class PantographDesign(ValidatedReplace):
    """A validated pantograph-family design.

    mechanism: :class:`~cad.kinematics.fivebar.FiveBar`,
    :class:`~cad.kinematics.twin_pantograph.TwinPantograph` or
    :class:`~cad.kinematics.haptic_pen.HapticPen`; workspace / actuators: the
    validated tables with defaults filled in; optimize: {name: (min, max, count)};
    raw: the TOML mapping.
    """

    name: str
    source: str
    family: str
    mechanism: Any
    params: dict[str, float]
    workspace: dict[str, Any]
    actuators: dict[str, Any]
    optimize: dict[str, tuple[float, float, int]]
    parts: PantographParts | None
    raw: dict = field(repr=False)
    targets: tuple = ()
    firmware: Any = None
    #: ``[motor]`` overrides of ``parts.motor`` (:func:`cad.design.motor.parse_motor_table`;
    #: the pen's waist motor stays its catalog entry)
    motor: tuple = ()

    @property
    def transmissions(self) -> tuple[Transmission, ...]:
        """One :class:`cad.design.transmission.Transmission` per motor (:meth:`motor_joints`
        order): the 5-bar's and the twin pantograph's ``[transmission]`` (the same on every
        motor) or ``[[transmission]]`` (one per motor), validated at load; direct drive without
        one. The pen's six motors take it too (arm A waist, lower, upper, then arm B's)."""
        return parse_transmissions(self.raw.get("transmission"), len(self.motor_joints()))

    # ------------------------------------------------------------------ GII
    def motor_joints(self) -> tuple[tuple[str, str], ...]:
        """(joint, parts field naming its motor) of every motor: the 5-bar's two, the twin
        pantograph's four (knob and crank, left and right), the pen's six (two arms: waist,
        lower, upper; the waist motors are ``parts.waist_motor``)."""
        if self.family == "twin-pantograph":
            return tuple((f"{g}_q_{s}", "motor") for g in ("knob", "crank") for s in ("left", "right"))
        if self.family == "haptic-pen":
            return tuple((f"{a}_q_{j}", "waist_motor" if j == "waist" else "motor")
                         for a in ("A", "B") for j in ("waist", "lower", "upper"))
        return (("q_left", "motor"), ("q_right", "motor"))

    def default_encoder(self) -> tuple[str, str]:
        """(catalog encoder, hint) a design that states no encoder gets: the haptic mouse
        paper's 4000 counts (:data:`cad.data.catalog.PAPER_MOUSE_ENCODER`)."""
        return PAPER_MOUSE_ENCODER, ""

    def workspace_points(self) -> np.ndarray:
        """Workspace samples (N, d) in task coordinates (mm, rad)."""
        ws = self.workspace
        if self.family == "pantograph":
            return square_grid_mm(ws["center_mm"], ws["size_mm"], ws["grid"])
        if self.family == "twin-pantograph":
            return ktwin.workspace_grid(ws["center_mm"], ws["size_mm"], ws["grid"], ws["theta_grid"])
        return kpen.workspace_grid(
            ws["center_mm"], ws["size_mm"], ws["grid"], ws["rotation_deg"], ws["rotation_grid"]
        )

    def gii(self):
        """GII of this design (isotropy paper eq 5) as a :class:`cad.isotropy.gii.GIIResult`."""
        ws, act = self.workspace, self.actuators
        if self.family == "pantograph":
            return fivebar_gii(
                self.mechanism,
                ws["center_mm"],
                ws["size_mm"],
                ws["grid"],
                act["torque_max_Nm"],
                act["force_max_N"],
            )
        if self.family == "twin-pantograph":
            return ktwin.twin_gii(
                self.mechanism,
                ws["center_mm"],
                ws["size_mm"],
                ws["grid"],
                ws["theta_grid"],
                act["torque_max_Nm"],
                act["force_max_N"],
                act["moment_max_Nm"],
            )
        return pen_gii(
            self.mechanism,
            ws["center_mm"],
            ws["size_mm"],
            ws["grid"],
            ws["rotation_deg"],
            ws["rotation_grid"],
            act["force_max_N"],
            act["moment_arm_mm"],
        )

    def workspace_size_mm(self) -> list[float]:
        """The ``[workspace]`` extents (mm) the GII report states: [W, H] (pantograph, twin)
        or [x, y, z] (pen), the table's ``size_mm``."""
        return [float(v) for v in self.workspace["size_mm"]]

    def point_units(self) -> tuple[str, ...]:
        """Names of the coordinates of a workspace point, with units."""
        return {
            "pantograph": ("x_mm", "y_mm"),
            "twin-pantograph": ("x_mm", "y_mm", "theta_deg"),
            "haptic-pen": ("x_mm", "y_mm", "z_mm", "yaw_deg", "pitch_deg"),
        }[self.family]

    # ------------------------------------------------------------- optimize
    def problem(self):
        """The ``[optimize]`` candidate set x workspace, as a culling problem."""
        if not self.optimize:
            raise DesignError(
                "optimize", "no free parameters: add e.g. base_mm = [min, max, count]"
            )
        names, params = problems.candidate_grid(self.optimize, self.params)
        ws, act = self.workspace, self.actuators
        if self.family == "pantograph":
            fb = self.mechanism
            if (
                fb.proximal_left_mm != fb.proximal_right_mm
                or fb.distal_left_mm != fb.distal_right_mm
                or (fb.elbow_left, fb.elbow_right) != (1, -1)
            ):
                raise DesignError("optimize", "only the symmetric 5-bar can be optimized")
            return problems.FiveBarProblem(
                params,
                self.workspace_points(),
                ws["grid"],
                act["torque_max_Nm"],
                act["force_max_N"],
            )
        if self.family == "twin-pantograph":
            return problems.TwinPantographProblem(
                params,
                self.workspace_points(),
                (ws["grid"], ws["grid"], ws["theta_grid"]),
                act["torque_max_Nm"],
                act["force_max_N"],
                act["moment_max_Nm"],
            )
        g = ws["grid"]
        return problems.PenProblem(
            params,
            self.workspace_points(),
            (g[0], g[1], g[2], ws["rotation_grid"], ws["rotation_grid"]),
            act["torque_max_Nm"],
            act["force_max_N"],
            act["moment_arm_mm"],
        )

    def with_params(self, values: dict[str, float]) -> PantographDesign:
        """A copy with mechanism parameters replaced (re-validated)."""
        raw = {k: (dict(v) if isinstance(v, dict) else v) for k, v in self.raw.items()}
        raw["mechanism"].update(values)
        return parse(raw, self.source)


def _int_or_list(ws: dict[str, Any], key: str, n: int, default, prefix: str) -> list[int]:
    if key not in ws:
        return list(default)
    v = ws[key]
    if isinstance(v, int) and not isinstance(v, bool):
        v = [v] * n
    if (
        not isinstance(v, list)
        or len(v) != n
        or any(isinstance(i, bool) or not isinstance(i, int) for i in v)
    ):
        raise DesignError(f"{prefix}.{key}", f"must be an integer or {n} integers, got {ws[key]!r}")
    if min(v) < 2:
        raise DesignError(
            f"{prefix}.{key}", f"must be >= 2 (the boundary is sampled), got {ws[key]!r}"
        )
    return v


def _magnitude(value: float, field: str, *, small_ok: bool = False) -> None:
    """DesignError unless |value| <= MAGNITUDE_MAX and (0 or small_ok or |value| >= MAGNITUDE_MIN).

    Only finite numbers are checked: anything else is left to the type validators.
    """
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        return
    a = abs(float(value))
    if a > MAGNITUDE_MAX:
        raise DesignError(field, f"must be <= {MAGNITUDE_MAX:g} in magnitude, got {value!r}")
    if not small_ok and 0 < a < MAGNITUDE_MIN:
        raise DesignError(field, f"must be >= {MAGNITUDE_MIN:g} in magnitude, got {value!r}")


def _check_magnitudes(
    family: str,
    mech: dict[str, Any],
    workspace: dict[str, Any],
    actuators: dict[str, Any],
    optimize: dict[str, tuple[float, float, int]],
) -> None:
    """Every number inside [MAGNITUDE_MIN, MAGNITUDE_MAX] (coordinates and the base: upper bound only)."""
    for key in MECH_KEYS[family]:
        if key in mech and key not in ("family", "elbow_left", "elbow_right"):
            _magnitude(mech[key], f"mechanism.{key}", small_ok=key == "base_mm")
    if not workspace:
        return
    for key in ("side_mm", "size_mm", "center_mm", "home_mm"):
        vals = workspace.get(key)
        if vals is None:
            continue
        for v in vals if isinstance(vals, list) else [vals]:
            _magnitude(v, f"workspace.{key}", small_ok=key in ("center_mm", "home_mm"))
    for key in ("torque_max_Nm", "force_max_N", "moment_max_Nm", "moment_arm_mm"):
        vals = actuators.get(key)
        if vals is None:
            continue
        for v in vals if isinstance(vals, list) else [vals]:
            _magnitude(v, f"actuators.{key}")
    for key, (lo, hi, _) in optimize.items():
        _magnitude(lo, f"optimize.{key}", small_ok=key == "base_mm")
        _magnitude(hi, f"optimize.{key}", small_ok=key == "base_mm")


def _check_sizes(
    family: str, workspace: dict[str, Any], optimize: dict[str, tuple[float, float, int]]
) -> None:
    """Workspace samples and (candidate, sample) pairs within :data:`cad.design.bounds.WORK`."""
    g = workspace["grid"]
    if family == "pantograph":
        factors = [("workspace.grid", g), ("workspace.grid", g)]
    elif family == "twin-pantograph":
        factors = [("workspace.grid", g), ("workspace.grid", g), ("workspace.theta_grid", workspace["theta_grid"])]
    else:
        r = workspace["rotation_grid"]
        factors = [*((f"workspace.grid[{i}]", g[i]) for i in range(3)),
                   ("workspace.rotation_grid", r), ("workspace.rotation_grid", r)]
    n = check_work("workspace", factors, "workspace.grid", "sample coarser")
    check_work("optimize", [*((f"optimize.{k}", c) for k, (_, _, c) in optimize.items()),
                            ("workspace samples", n)], "optimize",
               "use fewer counts or a coarser workspace grid")


def _parse_optimize(raw: dict[str, Any], family: str) -> dict[str, tuple[float, float, int]]:
    table = optional_table(raw, "optimize", "")
    check_unknown(table, OPTIMIZABLE[family], "optimize")
    out = {}
    for key in table:
        lo, hi, count = number_list(table, key, "optimize", length=3)
        f = f"optimize.{key}"
        if not float(count).is_integer() or count < 1:
            raise DesignError(f, f"count must be an integer >= 1, got {table[key][2]!r}")
        if hi < lo:
            raise DesignError(f, f"needs min <= max, got [{lo}, {hi}]")
        if key == "base_mm":
            if lo < 0:
                raise DesignError(f, f"min must be >= 0, got {lo}")
        elif lo <= 0:
            raise DesignError(f, f"min must be > 0, got {lo}")
        out[key] = (lo, hi, int(count))
    return out


def _torque(act: dict[str, Any], n: int) -> Any:
    if "torque_max_Nm" not in act:
        return 1.0
    v = act["torque_max_Nm"]
    if isinstance(v, list):
        vals = number_list(act, "torque_max_Nm", "actuators", length=n)
        if min(vals) <= 0:
            raise DesignError("actuators.torque_max_Nm", f"must be > 0, got {v!r}")
        return vals
    return require_positive(act, "torque_max_Nm", "actuators")


def _elbow(mech: dict[str, Any], key: str, default: int) -> int:
    if key not in mech:
        return default
    v = mech[key]
    if v not in (1, -1) or isinstance(v, bool):
        raise DesignError(f"mechanism.{key}", f"must be 1 or -1, got {v!r}")
    return int(v)


def _parse_targets(raw: dict[str, Any]) -> tuple:
    """``[targets]``: keys of :data:`cad.design.targets.PANTOGRAPH_TARGET_KEYS`."""
    return parse_targets(optional_table(raw, "targets", ""), "targets", PANTOGRAPH_TARGET_KEYS)


def parse(raw: dict[str, Any], source: str = "<design>") -> PantographDesign:
    """Validate a raw pantograph-family design; every problem is a DesignError."""
    check_unknown(
        raw,
        ("name", "description", "mechanism", "workspace", "actuators", "optimize", "parts", "targets",
         "firmware", "prices", "motor", "transmission"),
        "",
    )
    mech = require_table(raw, "mechanism", "")
    family = mech.get("family")
    if family not in FAMILIES:
        raise DesignError(
            "mechanism.family", f"must be one of {', '.join(FAMILIES)}, got {family!r}"
        )
    _check_transmission(raw, family)
    check_unknown(mech, MECH_KEYS[family], "mechanism")
    _check_magnitudes(family, mech, {}, {}, {})  # before derived values (crank = 1.6 knob) exist
    ws = require_table(raw, "workspace", "")
    check_unknown(ws, WS_KEYS[family], "workspace")
    act = optional_table(raw, "actuators", "")
    check_unknown(act, ACT_KEYS[family], "actuators")
    name = check_name(raw.get("name", family))
    optimize = _parse_optimize(raw, family)
    if family in ("pantograph", "twin-pantograph"):
        mechanism, params, workspace, actuators, parts = _parse_planar(raw, family, mech, ws, act)
    else:
        mechanism, params, workspace, actuators = _parse_pen(mech, ws, act)
        parts = None
    _check_magnitudes(family, mech, workspace, actuators, optimize)
    _check_sizes(family, workspace, optimize)
    if "parts" in raw and family not in ("pantograph", "twin-pantograph"):
        raise DesignError(
            "parts", f"parts are generated for the pantograph and twin-pantograph, not {family!r}"
        )
    return PantographDesign(
        name=name,
        source=source,
        family=family,
        mechanism=mechanism,
        params=params,
        workspace=workspace,
        actuators=actuators,
        optimize=optimize,
        parts=parts,
        raw=raw,
        targets=_parse_targets(raw),
        firmware=_parse_firmware(raw, family),
        motor=parse_motor_table(optional_table(raw, "motor", ""), "motor"),
    )


def _check_transmission(raw: dict[str, Any], family: str) -> None:
    """``[transmission]`` / ``[[transmission]]`` of a 5-bar (two motors: left, right), a twin
    pantograph (four: knob left, knob right, crank left, crank right) or a haptic pen (six: arm
    A waist, lower, upper, then arm B's, :meth:`PantographDesign.motor_joints`) validated at load
    (:func:`cad.design.transmission.parse_transmissions`). The pen's capstan motors are
    laid out by :mod:`cad.families.pen.capstan_layout` (its build refuses a pair that cannot be);
    the twin's by :func:`cad.families.pantograph.twin_placement.group_layout`."""
    if "transmission" not in raw:
        return
    parse_transmissions(raw["transmission"], {"pantograph": 2, "twin-pantograph": 4}.get(family, 6))


def _planar_size(ws: dict) -> tuple[float, float]:
    """(W, H) mm of a planar ``[workspace]``: ``side_mm`` (a square) or ``size_mm = [W, H]``,
    exactly one of the two. Raises DesignError naming the field."""
    if ("side_mm" in ws) == ("size_mm" in ws):
        raise DesignError("workspace.side_mm", "give exactly one of side_mm (a square) and size_mm = [W, H] "
                          f"(a rectangle), got {'both' if 'side_mm' in ws else 'neither'}")
    if "side_mm" in ws:
        side = require_positive(ws, "side_mm", "workspace")
        return side, side
    w, h = number_list(ws, "size_mm", "workspace", length=2)
    if not (w > 0 and h > 0):
        raise DesignError("workspace.size_mm", f"must be [W, H] with both > 0, got {ws['size_mm']!r}")
    return float(w), float(h)


def _parse_planar(raw: dict[str, Any], family: str, mech: dict, ws: dict, act: dict) -> tuple:
    """(mechanism, params, workspace, actuators, parts) of a pantograph or twin-pantograph
    design from its [mechanism], [workspace], [actuators] and [parts] tables (lengths in mm).

    Raises DesignError naming the field.
    """
    base = require_number(mech, "base_mm", "mechanism")
    if base < 0:
        raise DesignError("mechanism.base_mm", f"must be >= 0, got {mech['base_mm']!r}")
    l2 = require_positive(mech, "proximal_mm", "mechanism")
    l3 = require_positive(mech, "distal_mm", "mechanism")
    params = {"base_mm": base, "proximal_mm": l2, "distal_mm": l3}
    size = _planar_size(ws)
    center = number_list(ws, "center_mm", "workspace", length=2)
    grid = optional_int(ws, "grid", "workspace", 11 if family == "pantograph" else 7, minimum=2)
    workspace = {"size_mm": size, "center_mm": center, "grid": grid}
    if "side_mm" in ws:
        workspace["side_mm"] = size[0]
    force = optional_positive(act, "force_max_N", "actuators", 1.0)
    if family == "pantograph":
        l2r = optional_positive(mech, "proximal_right_mm", "mechanism", l2)
        l3r = optional_positive(mech, "distal_right_mm", "mechanism", l3)
        mechanism = FiveBar(
            (-base / 2, 0.0),
            (base / 2, 0.0),
            l2,
            l2r,
            l3,
            l3r,
            _elbow(mech, "elbow_left", 1),
            _elbow(mech, "elbow_right", -1),
        )
        actuators = {"torque_max_Nm": _torque(act, 2), "force_max_N": force}
    else:
        knob = optional_positive(mech, "knob_diameter_mm", "mechanism", 12.5)
        crank = optional_positive(mech, "crank_mm", "mechanism", ktwin.crank_length_mm(knob))
        mechanism = ktwin.TwinPantograph.symmetric(base, l2, l3, knob, crank)
        params.update(knob_diameter_mm=knob, crank_mm=crank)
        workspace["theta_grid"] = optional_int(ws, "theta_grid", "workspace", 8, minimum=1)
        workspace["home_mm"] = (
            number_list(ws, "home_mm", "workspace", length=2)
            if "home_mm" in ws
            else list(center)
        )
        workspace["home_theta_deg"] = optional_number(ws, "home_theta_deg", "workspace", 90.0)
        moment = optional_positive(act, "moment_max_Nm", "actuators", force * crank * 1e-3 / 2)
        actuators = {
            "torque_max_Nm": _torque(act, 4),
            "force_max_N": force,
            "moment_max_Nm": moment,
        }
    parts = parse_parts(optional_table(raw, "parts", ""))
    return mechanism, params, workspace, actuators, parts


def _parse_pen(mech: dict, ws: dict, act: dict) -> tuple:
    """(mechanism, params, workspace, actuators) of a haptic-pen design from its
    [mechanism], [workspace] and [actuators] tables (lengths in mm, angles in deg).

    Raises DesignError naming the field.
    """
    l1 = require_positive(mech, "shoulder_base_mm", "mechanism")
    l2 = require_positive(mech, "proximal_mm", "mechanism")
    l3 = require_positive(mech, "distal_mm", "mechanism")
    l6 = require_positive(mech, "pen_mm", "mechanism")
    l4 = optional_positive(mech, "arm_spacing_mm", "mechanism", None)
    q1 = optional_positive(mech, "waist_torque_ratio", "mechanism", 1.6)
    mechanism = HapticPen(l1, l2, l3, l6, l4, q1)
    params = {
        "shoulder_base_mm": l1,
        "proximal_mm": l2,
        "distal_mm": l3,
        "pen_mm": l6,
        "waist_torque_ratio": q1,
    }
    if l4 is not None:
        params["arm_spacing_mm"] = l4
    center = number_list(ws, "center_mm", "workspace", length=3)
    size = (
        number_list(ws, "size_mm", "workspace", length=3)
        if "size_mm" in ws
        else [160.0, 100.0, 100.0]
    )
    if min(size) <= 0:
        raise DesignError("workspace.size_mm", f"must be > 0, got {ws['size_mm']!r}")
    rot = optional_number(ws, "rotation_deg", "workspace", 45.0)
    if not 0 <= rot < 90:
        raise DesignError("workspace.rotation_deg", f"must be in [0, 90), got {rot!r}")
    workspace = {
        "center_mm": center,
        "size_mm": size,
        "grid": _int_or_list(ws, "grid", 3, (5, 3, 3), "workspace"),
        "rotation_deg": rot,
        "rotation_grid": optional_int(ws, "rotation_grid", "workspace", 3, minimum=1),
    }
    actuators = {
        "torque_max_Nm": _torque(act, 1),
        "force_max_N": optional_positive(act, "force_max_N", "actuators", 1.0),
        "moment_arm_mm": optional_positive(act, "moment_arm_mm", "actuators", 35.0),
    }
    return mechanism, params, workspace, actuators


def _parse_firmware(raw: dict[str, Any], family: str):
    """``[firmware]`` (:mod:`cad.design.firmware`) of the families that build; None otherwise."""
    tab = optional_table(raw, "firmware", "")
    if family == "haptic-pen":  # spatial: gravity is -z of its base frame (z up)
        for key in ("plane", "gravity_direction"):
            if key in tab:
                raise DesignError(f"firmware.{key}", "the haptic pen's gravity is -z of its base "
                                  "frame (z up, cad/families/pen/firmware.py): no plane to choose")
        return parse_firmware(tab, 6)
    if family not in ("pantograph", "twin-pantograph"):
        if tab:
            raise DesignError("firmware", f"firmware is generated for built devices, not {family!r}")
        return None
    return parse_firmware(tab, 2 if family == "pantograph" else 4)
