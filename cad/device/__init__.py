"""The device as it will be made, resolved once per build (issue 32 item 1; SPEC "The resolved
device (one fact, one place)").

:func:`resolve_device` turns a validated design into a frozen :class:`ResolvedDevice`: each
motor (the catalog entry named by ``parts.motor`` with the design's ``[motor]`` table and
``parts.motor_rotor_inertia_g_cm2`` applied, every constant with its source), each encoder
(counts per turn after quadrature decoding, the joint it sits on, catalog key, source), the
transmission of each motor, each part group's material and process, the design's limits
(``[targets]``), the build fidelity and the deflections of the exported meshes. Every writer of a build (BOM, datasheet, firmware, CHAI3D file,
MJCF/URDF, report.json) reads its facts from here and keeps no default of its own;
``report.json`` carries :meth:`ResolvedDevice.as_dict` under ``device``.

One encoder value (per joint): ``parts.encoder`` (a catalog key), ``parts.encoder_counts_per_rev``
and ``[firmware] encoder_counts_per_rev`` are three ways to state it; two that disagree are
refused (DesignError naming both fields). Without any, a four-bar with a ``[stiffness]`` table
gets the encoder whose step at mid-stroke is the table's ``encoder_resolution_m`` (rounded to
whole counts: the encoder the BOM orders), else the Hoeken prototype's "general purpose 2000
counts/rev optical encoder" (Hoeken paper §III.A); the pantograph, twin-pantograph and pen
designs follow the haptic mouse of the isotropy paper: "The position of each active joint is
sensed by a 1000 window (4000 cpt) optical encoder" (isotropy paper §3.2,
``/work/shared/seeds/002``), catalog ``optical-4000``. The PowerMouse (maglev, Lorentz coils)
has no rotary motor or encoder here.

Pure math and data: imports no CAD library.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

from cad.actuators.capstan_geometry import CAPSTAN_MATERIAL, capstan_izz_kg_m2
from cad.data import catalog
from cad.data.cables import CABLE_DATA_FIELDS, get_cable
from cad.data.catalog import get_motor
from cad.data.materials import get_material
from cad.design.motor import resolve_motor
from cad.errors import DesignError
from cad.tolerances import PREVIEW_STL_TOL_MM, STL_ANGULAR_TOLERANCE_RAD, STL_TOLERANCE_MM

#: MotorSpec fields a resolved motor states (value and source each), in report order.
MOTOR_FIELDS = ("torque_constant_mNm_per_A", "current_continuous_A", "torque_continuous_mNm",
                "torque_peak_mNm", "stall_torque_mNm", "terminal_resistance_ohm",
                "thermal_resistance_housing_K_per_W", "thermal_resistance_winding_K_per_W",
                "no_load_current_mA", "rotor_inertia_g_cm2", "mass_kg")


@dataclass(frozen=True)
class ResolvedMotor:
    """One motor of the device.

    joint : the joint it drives (``crank`` of a four-bar, at A1; ``q_left`` ... of the 5-bars: the
        joint names of the MJCF export); catalog_key : ``parts.motor`` (the mount interface);
    name : what the device uses (the ``[motor]`` name or the catalog winding);
    from_motor_table : True when a ``[motor]`` value replaced a catalog value;
    spec : the :class:`cad.data.catalog.MotorSpec` with every override applied (``sources``
        names where each constant comes from; ``unverified`` the ones without a public source).
    """

    joint: str
    catalog_key: str
    name: str
    from_motor_table: bool
    spec: Any

    @property
    def kt_Nm_per_A(self) -> float | None:
        k = self.spec.torque_constant_mNm_per_A
        return None if k is None else k * 1e-3

    @property
    def current_peak_A(self) -> float | None:
        """Peak torque / Kt (A): the current limit the firmware saturates at."""
        t, k = self.spec.torque_peak_mNm, self.spec.torque_constant_mNm_per_A
        return None if t is None or k is None else t / k

    @property
    def rotor_inertia_kg_m2(self) -> float:
        return self.spec.rotor_inertia_g_cm2 * 1e-7

    def as_dict(self) -> dict:
        m = self.spec
        consts = {f: {"value": getattr(m, f), "source": m.source_of(f) or m.source,
                      **({"unverified": True} if m.is_unverified(f) else {})} for f in MOTOR_FIELDS}
        return {"joint": self.joint, "catalog_key": self.catalog_key, "name": self.name,
                "from_motor_table": self.from_motor_table, "current_peak_A": self.current_peak_A,
                "constants": consts}


@dataclass(frozen=True)
class ResolvedEncoder:
    """One shaft encoder: ``counts_per_rev`` after x4 quadrature decoding on ``joint``;
    ``catalog_key`` (None when the count comes from a design field), ``description`` (the BOM
    wording), ``field`` (the design field that set it, or "default"), ``source``."""

    joint: str
    counts_per_rev: int
    catalog_key: str | None
    description: str
    field: str
    source: str

    def as_dict(self) -> dict:
        return {"joint": self.joint, "counts_per_rev": self.counts_per_rev,
                "catalog_key": self.catalog_key, "description": self.description,
                "field": self.field, "source": self.source}


@dataclass(frozen=True)
class Transmission:
    """Motor -> joint transmission of ``motor_joint``: ``kind`` "direct" (ratio 1) or
    "capstan" (a rope wrapped on a capstan on the motor shaft, anchored on a drum on the link;
    :mod:`cad.actuators.capstan`). ``ratio`` n = drum / capstan diameter: joint torque = n *
    motor torque, joint angle = motor angle / n (counts per joint turn = n * counts per motor
    turn), rotor inertia at the joint n^2 J_m. A capstan states its diameters (mm), the rope's
    diameter (mm) and ``cable`` (the :class:`cad.data.cables.CableSpec`, every value with its
    source), ``wraps`` / ``pretension_N`` when the design gives them, and ``cable_EA_N`` (N)
    with ``cable_EA_source``: the design's ``transmission.cable_EA_N`` when given, else the
    rope catalog's axial stiffness (:func:`cad.data.cables.stretch_EA_N`). Writers multiply torques and divide angles by ``ratio``; :func:`joint_motor_spec` gives the
    motor as the joint sees it."""

    motor_joint: str
    kind: str = "direct"
    ratio: float = 1.0
    cable_diameter_mm: float | None = None
    drum_diameter_mm: float | None = None
    capstan_diameter_mm: float | None = None
    source: str = "direct drive: the motor shaft is the joint (Hoeken paper §III.A; isotropy paper §3.2)"
    cable: Any = None
    wraps: float | None = None
    pretension_N: float | None = None
    cable_EA_N: float | None = None
    centre_distance_mm: float | None = None
    cable_EA_source: str = ""

    @property
    def is_capstan(self) -> bool:
        return self.kind == "capstan"

    def capstan_inertia_kg_m2(self, bore_mm: float) -> float:
        """The capstan's inertia about the motor shaft (kg m^2; 0 for a direct drive): the
        turned steel tube on a shaft of ``bore_mm``
        (:func:`cad.actuators.capstan_geometry.capstan_izz_kg_m2`)."""
        if not self.is_capstan:
            return 0.0
        return capstan_izz_kg_m2(self.capstan_diameter_mm, self.cable_diameter_mm, self.wraps,
                                 bore_mm, get_material(CAPSTAN_MATERIAL).density_kg_m3)

    def as_dict(self) -> dict:
        """report.json ``device.transmissions[i]``: a direct drive as before (kind, ratio,
        source, no diameters); a capstan adds its rope's catalog record with each value's
        source and the fields it leaves unverified."""
        d = {k: getattr(self, k) for k in ("motor_joint", "kind", "ratio", "cable_diameter_mm",
                                           "drum_diameter_mm", "capstan_diameter_mm", "source")}
        if not self.is_capstan:
            return d
        c = self.cable
        d["cable"] = {"key": c.key, "description": c.description, "construction": c.construction,
                      **{f: {"value": getattr(c, f), "source": c.source_of(f),
                             **({"unverified": True} if c.is_unverified(f) else {})}
                         for f in CABLE_DATA_FIELDS}}
        d.update(wraps=self.wraps, pretension_N=self.pretension_N, cable_EA_N=self.cable_EA_N,
                 cable_EA_source=self.cable_EA_source)
        if self.centre_distance_mm is not None:
            d["centre_distance_mm"] = self.centre_distance_mm
        return d


def transmission_of(design, joint: str, index: int) -> Transmission:
    """The resolved :class:`Transmission` of motor ``index`` (on ``joint``): the design's
    ``transmissions`` (:func:`cad.design.transmission.parse_transmissions`), direct drive
    when the design has none."""
    ts = getattr(design, "transmissions", None) or ()
    t = ts[index] if index < len(ts) else None
    if t is None or not t.is_capstan:
        return Transmission(joint)
    cable = get_cable(t.cable)
    src = (f"design file [transmission]: capstan {t.capstan_diameter_mm:g} mm, drum "
           f"{t.drum_diameter_mm:g} mm, n = drum / capstan = {t.ratio:.6g}, rope {cable.key} "
           "(cad.data.cables); model cad.actuators.capstan")
    ea, ea_src = _cable_EA(t, cable)
    return Transmission(joint, "capstan", float(t.ratio), cable.diameter_mm, t.drum_diameter_mm,
                        t.capstan_diameter_mm, src, cable, t.wraps, t.pretension_N, ea,
                        getattr(t, "centre_distance_mm", None), ea_src)


def _cable_EA(t, cable) -> tuple[float | None, str]:
    """The rope's E A (N) and where it comes from: the design's ``cable_EA_N`` over the
    catalog's (the design states its own rope maker's sheet)."""
    if t.cable_EA_N is not None:
        return float(t.cable_EA_N), "transmission.cable_EA_N (the design file)"
    ea = cable.axial_stiffness_EA_N
    return ea, (f"{cable.key} in cad.data.cables: " + cable.source_of("axial_stiffness_EA_N")
                if ea is not None else "")


#: MotorSpec torque fields scaled by n at the joint (torque = n * motor torque).
_TORQUE_FIELDS = ("torque_constant_mNm_per_A", "torque_continuous_mNm", "torque_peak_mNm",
                  "stall_torque_mNm")


def joint_motor_spec(spec, t: Transmission):
    """The motor ``spec`` (:class:`cad.data.catalog.MotorSpec`) as its joint sees it through
    ``t``: torques and the torque constant times n (so force per ampere, friction K_t I_0 and
    the current for a joint torque follow), rotor inertia times n^2; currents, resistance and
    thermal data unchanged. Each scaled value's source says "x n". Direct drive: ``spec``
    itself (the same object)."""
    if t.ratio == 1.0:
        return spec
    n = t.ratio
    ch = {f: getattr(spec, f) * n for f in _TORQUE_FIELDS if getattr(spec, f) is not None}
    ch["rotor_inertia_g_cm2"] = spec.rotor_inertia_g_cm2 * n * n
    sources = dict(spec.sources)
    for f in ch:
        k = "n^2" if f == "rotor_inertia_g_cm2" else "n"
        sources[f] = f"{spec.source_of(f) or spec.source} x {k} (capstan, n = {n:.4g})"
    return replace(spec, sources=tuple(sorted(sources.items())), **ch)


@dataclass(frozen=True)
class PartMaterial:
    """A group of made parts (``group``: the ``parts.<group>_material`` key), its material and
    the process it is made by."""

    group: str
    material: str
    process: str


@dataclass(frozen=True)
class ResolvedDevice:
    """The device of one build (module docstring). ``limits``: the design's ``[targets]`` as
    ``(key, bound text)`` pairs; ``fidelity``: the build fidelity; ``stl_tolerance_mm`` /
    ``stl_angular_tolerance_rad``: the chordal (mm) and angular (rad) deflections of every
    exported mesh (part STL, parts.3mf, the viewer files; :func:`mesh_deflections`)."""

    name: str
    family: str
    motors: tuple[ResolvedMotor, ...]
    encoders: tuple[ResolvedEncoder, ...]
    transmissions: tuple[Transmission, ...]
    parts: tuple[PartMaterial, ...]
    limits: tuple[tuple[str, Any], ...]
    fidelity: str
    stl_tolerance_mm: float = STL_TOLERANCE_MM
    stl_angular_tolerance_rad: float = STL_ANGULAR_TOLERANCE_RAD

    @property
    def motor(self) -> ResolvedMotor | None:
        """The first motor (the four-bar's only one); None for the PowerMouse."""
        return self.motors[0] if self.motors else None

    @property
    def encoder(self) -> ResolvedEncoder | None:
        """The first encoder (every encoder of a device has the same count)."""
        return self.encoders[0] if self.encoders else None

    def transmission(self, joint: str) -> Transmission:
        """The transmission of the motor on ``joint`` (KeyError naming it when none)."""
        for t in self.transmissions:
            if t.motor_joint == joint:
                return t
        raise KeyError(f"no motor on joint {joint!r}")

    def joint_motor(self, joint: str | None = None):
        """The MotorSpec of the motor on ``joint`` (default: the first) as that joint sees it
        through its transmission (:func:`joint_motor_spec`): what the datasheet's force,
        friction, thermal and apparent-mass figures read."""
        m = self.motor if joint is None else next(x for x in self.motors if x.joint == joint)
        return joint_motor_spec(m.spec, self.transmission(m.joint))

    def joint_rotor_inertia_kg_m2(self, joint: str | None = None) -> float:
        """The motor side's inertia on ``joint`` (default: the first motor's) reflected through
        its transmission, n^2 (J_m + J_capstan) (kg m^2; direct drive: J_m): the Jm of H11, the
        MJCF armature. The capstan turns with the rotor (:meth:`Transmission.capstan_inertia_kg_m2`);
        the drum is a part of the link, in the link's own mass properties."""
        m = self.motor if joint is None else next(x for x in self.motors if x.joint == joint)
        t = self.transmission(m.joint)
        j_c = t.capstan_inertia_kg_m2(m.spec.shaft_diameter_mm) if t.is_capstan else 0.0
        return (m.rotor_inertia_kg_m2 + j_c) * t.ratio ** 2

    def joint_peak_torques_Nm(self) -> dict[str, float]:
        """``{joint: N m}``: each motor's peak torque (catalog / ``[motor]``) through its
        transmission, n T_peak: the simulators' force range (MJCF) and effort (URDF).
        DesignError (``parts.motor``) when a motor states none."""
        out = {}
        for m in self.motors:
            if m.spec.torque_peak_mNm is None:
                raise DesignError("parts.motor", f"{m.catalog_key!r} states no peak torque: the "
                                  "mjcf/urdf force range needs one (add torque_peak_mNm to [motor])")
            out[m.joint] = m.spec.torque_peak_mNm * 1e-3 * self.transmission(m.joint).ratio
        return out

    def joint_counts_per_rev(self, joint: str | None = None) -> float:
        """Encoder counts per turn of ``joint`` (default: the first motor's): the motor encoder's
        counts times the transmission ratio n (the encoder sits on the motor shaft); an int when
        the product is whole (direct drive: the encoder's own count)."""
        e = self.encoder if joint is None else next(x for x in self.encoders if x.joint == joint)
        c = e.counts_per_rev * self.transmission(e.joint).ratio
        return int(c) if float(c).is_integer() else c

    def as_dict(self) -> dict:
        """report.json ``device``: every resolved fact with its source (plain JSON types)."""
        return {"name": self.name, "family": self.family, "fidelity": self.fidelity,
                "motors": [m.as_dict() for m in self.motors],
                "encoders": [e.as_dict() for e in self.encoders],
                "transmissions": [t.as_dict() for t in self.transmissions],
                "parts": [p.__dict__.copy() for p in self.parts],
                "limits": dict(self.limits)}


def resolve_device(design, fidelity: str = "fabrication") -> ResolvedDevice:
    """The :class:`ResolvedDevice` of a validated ``design`` (module docstring).

    Raises DesignError naming both fields when two encoder fields disagree, or
    ``parts.motor_rotor_inertia_g_cm2`` and ``[motor] rotor_inertia_g_cm2`` disagree.
    Cached per design object (a build resolves once; its writers read the same object).
    """
    tol_mm, ang_rad = mesh_deflections(getattr(design, "parts", None), fidelity)
    return replace(_resolve(design), fidelity=fidelity, stl_tolerance_mm=tol_mm,
                   stl_angular_tolerance_rad=ang_rad)


def mesh_deflections(parts, fidelity: str) -> tuple[float, float]:
    """(chordal mm, angular rad) deflections of a build's exported meshes, for every family:
    ``parts.stl_tolerance_mm`` / ``parts.stl_angular_tolerance_deg`` where the family's
    ``[parts]`` takes them (the four-bar's), else :data:`cad.tolerances.STL_TOLERANCE_MM` /
    :data:`cad.tolerances.STL_ANGULAR_TOLERANCE_RAD`; at ``preview`` fidelity the chordal one
    is at least :data:`cad.tolerances.PREVIEW_STL_TOL_MM` (a preview is looked at, not made)."""
    tol = getattr(parts, "stl_tolerance_mm", None) or STL_TOLERANCE_MM
    deg = getattr(parts, "stl_angular_tolerance_deg", None)
    ang = math.radians(deg) if deg else STL_ANGULAR_TOLERANCE_RAD
    if fidelity == "preview":
        tol = max(tol, PREVIEW_STL_TOL_MM)
    return tol, ang


#: id(design) -> (design, device): the designs of the pantograph families hold dicts (not
#: hashable); the design is kept so that its id is not reused while cached.
_CACHE: dict[int, tuple[Any, ResolvedDevice]] = {}
_CACHE_MAX = 32


def _resolve(design) -> ResolvedDevice:
    hit = _CACHE.get(id(design))
    if hit is not None and hit[0] is design:
        return hit[1]
    dev = _resolve_uncached(design)
    if len(_CACHE) >= _CACHE_MAX:
        _CACHE.pop(next(iter(_CACHE)))
    _CACHE[id(design)] = (design, dev)
    return dev


def _resolve_uncached(design) -> ResolvedDevice:
    motors = _motors(design)
    encoders = _encoders(design, motors)
    return ResolvedDevice(
        name=design.name, family=design.family, motors=motors, encoders=encoders,
        transmissions=tuple(transmission_of(design, m.joint, i) for i, m in enumerate(motors)),
        parts=_parts(design),
        limits=tuple(sorted(_limits(design).items())), fidelity="fabrication")


# ----------------------------------------------------------------------------- motors
def _joints(design) -> tuple[tuple[str, str], ...]:
    """(joint, parts field naming its motor) of every motor: the design's
    ``motor_joints()`` (its family's schema; none: no motor)."""
    joints = getattr(design, "motor_joints", None)
    return () if joints is None else tuple(joints())


def _motors(design) -> tuple[ResolvedMotor, ...]:
    out = []
    for joint, fld in _joints(design):
        key = getattr(design.parts, fld)
        spec, table = parts_motor(design, fld)
        out.append(ResolvedMotor(joint, key, spec.winding or spec.key, bool(table), spec))
    return tuple(out)


def parts_motor(design, fld: str = "motor"):
    """(:class:`cad.data.catalog.MotorSpec`, the ``[motor]`` overrides applied) of the motor
    ``parts.<fld>`` names: the catalog entry with the design's ``[motor]`` table (which
    describes ``parts.motor``; the pen's ``waist_motor`` keeps its catalog data) and
    ``parts.motor_rotor_inertia_g_cm2``. What the BOM, the datasheet, the firmware and the
    simulators read (through :func:`resolve_device`). DesignError naming the field."""
    table = tuple(getattr(design, "motor", ()) or ()) if fld == "motor" else ()
    key = getattr(design.parts, fld)
    spec = resolve_motor(key, table, f"parts.{fld}") if table else get_motor(key, f"parts.{fld}")
    return _rotor_override(design, spec, dict(table)), table


def _rotor_override(design, spec, table: dict):
    """``parts.motor_rotor_inertia_g_cm2`` (four-bars) applied; refused when ``[motor]
    rotor_inertia_g_cm2`` states another value."""
    jm = getattr(design.parts, "motor_rotor_inertia_g_cm2", None)
    if jm is None:
        return spec
    if "rotor_inertia_g_cm2" in table and not math.isclose(table["rotor_inertia_g_cm2"], jm):
        raise DesignError("parts.motor_rotor_inertia_g_cm2",
                          f"{jm:g} g cm^2 disagrees with motor.rotor_inertia_g_cm2 = "
                          f"{table['rotor_inertia_g_cm2']:g}: give the rotor inertia once")
    sources = dict(spec.sources)
    sources["rotor_inertia_g_cm2"] = "design file: parts.motor_rotor_inertia_g_cm2"
    return replace(spec, rotor_inertia_g_cm2=float(jm), sources=tuple(sorted(sources.items())),
                   unverified=tuple(f for f in spec.unverified if f != "rotor_inertia_g_cm2"))


# ---------------------------------------------------------------------------- encoders
def _firmware_counts(design) -> int | None:
    fw = getattr(design, "firmware", None)
    return None if fw is None else fw.encoder_counts_per_rev


def _stated_counts(design) -> dict[str, tuple[int, str, str | None]]:
    """{field: (counts, source, catalog key)} of every encoder field the design gives."""
    p = design.parts
    out: dict[str, tuple[int, str, str | None]] = {}
    key = getattr(p, "encoder", None)
    if key is not None:
        e = catalog.get_encoder(key)
        out["parts.encoder"] = (e.counts_per_rev, f"parts.encoder = {e.key} ({e.source})", e.key)
    n = getattr(p, "encoder_counts_per_rev", None)
    if n is not None:
        out["parts.encoder_counts_per_rev"] = (int(n), "parts.encoder_counts_per_rev", None)
    fw = _firmware_counts(design)
    if fw is not None:
        out["firmware.encoder_counts_per_rev"] = (int(fw), "firmware.encoder_counts_per_rev", None)
    return out


def _encoders(design, motors) -> tuple[ResolvedEncoder, ...]:
    if not motors:
        return ()

    stated = _stated_counts(design)
    if len({v[0] for v in stated.values()}) > 1:
        (fa, (a, _, _)), (fb, (b, _, _)) = list(stated.items())[:2]
        raise DesignError(fa, f"{a} counts/rev disagrees with {fb} = {b}: one encoder per joint, "
                              "state its count once (or the same count in both)")
    if stated:
        field, (counts, src, key) = next(iter(stated.items()))
        desc = catalog.get_encoder(key).description if key else _plain(counts)
    elif (implied := _stiffness_encoder(design)) is not None:
        field, counts, src, key = "stiffness.encoder_resolution_m", *implied, None
        desc = _plain(counts)
    else:
        key, hint = (design.default_encoder() if hasattr(design, "default_encoder")
                     else (catalog.DEFAULT_ENCODER, ""))
        e = catalog.get_encoder(key)
        src = f"default encoder {e.key} ({e.source})" + hint
        field, counts, desc = "default", e.counts_per_rev, e.description
    return tuple(ResolvedEncoder(m.joint, int(counts), key, desc, field, src) for m in motors)


def _stiffness_encoder(design) -> tuple[int, str] | None:
    implied = getattr(design, "stiffness_encoder", None)
    return None if implied is None else implied()


def _plain(counts: int) -> str:
    return f"encoder on the motor's rear shaft, {counts} counts/rev"


def stated_encoder_counts(design) -> int | None:
    """The encoder count the design states first (``parts.encoder``, ``parts.
    encoder_counts_per_rev``, ``[firmware] encoder_counts_per_rev``), or None."""
    stated = _stated_counts(design)
    return next(iter(stated.values()))[0] if stated else None


def encoder_bom_rows(device: ResolvedDevice) -> list[dict]:
    """The device's encoders as bought BOM lines (no solid: each sits on its motor's rear
    shaft), one line per distinct encoder with its quantity; the description states the
    counts per turn and where they come from; mass not in the catalog (0 in the totals);
    material empty (no catalog states what the encoder is made of; the process column says
    "bought", as for every bought part)."""
    rows: dict[tuple, dict] = {}
    for e in device.encoders:
        key = (e.catalog_key, e.counts_per_rev)
        if key in rows:
            rows[key]["quantity"] += 1
            continue
        rows[key] = {"part": "encoder", "description": f"{e.description} ({e.source.split(';')[0]}; mass not "
                     "known, not in the totals)", "material": "", "quantity": 1,
                     "made_or_bought": "bought", "process": "bought", "fits": "", "mass_g": 0.0,
                     "group": "encoders", "designation": e.description, "order_code": "", "stock": ""}
    return list(rows.values())


# ------------------------------------------------------------------- parts and limits
def _parts(design) -> tuple[PartMaterial, ...]:
    p = getattr(design, "parts", None)
    if p is None or not hasattr(p, "__dataclass_fields__"):
        return ()
    proc = getattr(p, "process", "machined")
    return tuple(PartMaterial(f[: -len("_material")], getattr(p, f), proc)
                 for f in sorted(p.__dataclass_fields__)
                 if f.endswith("_material") and isinstance(getattr(p, f), str))


def _limits(design) -> dict:
    """The design's ``[targets]`` (``hapticad check`` bounds) as ``{key: bound text}``; the
    datasheet's default limits are stated in its own rows (:mod:`cad.datasheet.limits`)."""
    return {t.key: t.describe() for t in (getattr(design, "targets", ()) or ())}
