"""Mixed discrete/continuous search for a light four-bar (optuna TPE), on the cheap model.

Free (per trial):

* kinematics within the family: the crank range (span and centre); the linkage is then
  scaled so the stroke equals the design's ``stroke_mm`` (the family's proportions kept,
  or with ``Problem.proportions_tol`` > 0 each of :data:`PROPORTIONS` multiplied by a
  factor in 1 +- tol before the scaling, l2 and phi_e kept; ``dy_max_mm`` and the
  transmission angle are then checked on the perturbed linkage like any other);
* joint hardware: a (bearing, pin) pair of :data:`JOINT_SETS` and ``pin_material``;
* bars: material, a stock thickness of that material (:data:`STOCK_THICKNESS_MM`; under the
  brief's ``parts.process`` only what that process makes: :func:`bar_stock`, laser sheets or
  printing filaments; the process and its sheet / print settings are kept),
  width, pockets on/off (end radius: the smallest that holds the bearing seat and hub);
* handle: material, diameter, height, screw;
* the motor: every catalog motor with the constants a build reads (:func:`searched_motors`),
  screened per trial on the cheap model, least rotor inertia first (:func:`screen_motor`);
* the layer order (``[parts] layer_order``): one of the 6 stackings of crank, coupler and
  rocker (:data:`LAYER_ORDERS`), unless the brief fixes it. The cheap model sees it: each
  joint's hardware rides on the link the plan gives it (bearing on the upper link, pin,
  spacers, nut on the lower) with the plan's stack heights (:mod:`cad.studies.codesign.cheap`);
* a capstan on the crank, when the brief's ``[transmission]`` is one (issue 35): the
  capstan's diameter from :data:`CAPSTAN_STOCK_MM`, the ratio n (drum / capstan, steps of
  0.5 in :data:`CAPSTAN_RATIO_RANGE`) and the gap added to r_d + r_c for the centre distance
  (:data:`CAPSTAN_GAP_CHOICES_MM`); the rope the thickest of the brief rope's construction
  that the capstan's bend ratio allows (:func:`cad.data.cables.largest_rope_for`: strongest
  and stiffest; none allowed keeps the brief's, which then misses its bend ratio); the
  brief's ``wraps`` kept. The cheap figures see it through the resolved device (torques x n, counts
  x n, rotor and capstan n^2 (J_m + J_c), the drum sector on the crank); its own limits
  (bend ratio, slip margin, safety factor, drum arc) and a place for the moved motor are
  checks like the others (:func:`capstan_problem`);
* tube bars, when the brief sets ``[parts] bar_style = "tube"``: a stock tube of
  :data:`TUBE_STOCK_MM` and a clevis height of :data:`CLEVIS_STOCK_MM` that holds it with 1 mm walls, the clevis
  length the shortest that clears the joint features (:func:`suggest_tube`).

Constraints (a trial violating one is infeasible): ``dy_max_mm`` (design target, default
0.2), ``min_transmission_angle_deg`` (target, default 40), the datasheet's default limits
(:func:`design_limits`, from :mod:`cad.datasheet.limits`: continuous force at the handle >=
``force_N``, first mode, stress; ``--beat-prototype`` adds M11, friction and K_max), a valid ``[parts]`` table (bearing fits the
bar, hub fits the crank end), a layout in the trial's layer order (the planner of
:mod:`cad.families.fourbar.layers` over the build's poses: a clash between links that widening the
gaps cannot cure, or a stack no catalog pin or screw can fasten, makes the trial infeasible,
not an error), and the structural limits (first mode, stress: the frame of
:mod:`cad.structure.device` with FE-calibrated bars at the middle pose, run only for trials
that would improve the best). Interference is checked on the exact solids
(:mod:`cad.studies.codesign.exact`), as are the structure limits again (three poses, the solids' masses).

Why optuna: TPE handles the conditional, mixed categorical/integer/float space (the
thickness list depends on the material) natively, is seeded (reproducible), keeps every
trial for the Pareto chart, and is a maintained library already pinned here.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field, replace

import numpy as np

from cad.actuators import capstan as cap
from cad.actuators import capstan_geometry as cap_geometry
from cad.data import catalog as cat
from cad.data.cables import get_cable, largest_rope_for
from cad.data.catalog import MOTORS
from cad.data.materials import SHEETS
from cad.datasheet.limits import Limit
from cad.design import bounds
from cad.design.parts import PartsSpec, parse_parts
from cad.design.writer import custom_mechanism_table
from cad.device import resolve_device
from cad.dynamics.inertia import InertiaCoefficients
from cad.errors import HapticadError
from cad.families.fourbar import capstan as fcap
from cad.families.fourbar.capstan_solids import a2_hardware_radius_mm, capstan_set_screw, placement
from cad.families.fourbar.datasheet import force_rows, friction, lever, stiffness_inputs
from cad.families.fourbar.layers import choose_layers, made_crank_axle
from cad.families.fourbar.limits import fourbar_limits
from cad.families.fourbar.pose import planar_transforms
from cad.io import signals
from cad.kinematics.linkgeom import link_joints_mm
from cad.kinematics.metrics import compute_metrics
from cad.printing import FILAMENTS
from cad.sim import wall
from cad.structure import device
from cad.structure.device import link_material
from cad.structure.elastic import get_elastic
from cad.studies.codesign import cheap

#: (bearing, pin) pairs whose pin diameter equals the bearing bore (bd_warehouse SKT + pins).
JOINT_SETS = (
    ("M3-10-4", "dowel-3"), ("M4-9-2.5", "dowel-4"), ("M4-11-4", "dowel-4"),
    ("M5-11-3", "dowel-5"), ("M6-13-3.5", "dowel-6"), ("M8-16-4", "dowel-8"),
    ("M8-16-4", "M6-1"),
)
PIN_MATERIALS = ("steel-1018", "aluminium-7075", "titanium-6al4v")
#: Stock plate thicknesses (mm) a workshop buys: aluminium sheet, carbon-fibre plate,
#: printed PLA / PETG (any layer multiple, listed at whole mm).
STOCK_THICKNESS_MM = {
    "aluminium-6061": (3.0, 4.0, 5.0, 6.0, 8.0),
    "carbon-fibre": (2.0, 3.0, 4.0, 5.0, 6.0),
    "pla": (4.0, 5.0, 6.0, 8.0),
    "petg": (4.0, 5.0, 6.0, 8.0),
}
#: Stock pultruded / roll-wrapped carbon tubes (outside, inside diameter, mm) searched when
#: the brief sets ``[parts] bar_style = "tube"`` (common catalogue sizes, e.g. Easy Composites).
TUBE_STOCK_MM = ((4.0, 3.0), (5.0, 4.0), (6.0, 4.0), (6.0, 5.0))
#: Aluminium plate stock of the clevises (mm): their height = the layer's bar thickness.
CLEVIS_STOCK_MM = (6.0, 8.0, 10.0, 12.0)
#: Socket depth of the searched tube bars (mm), >= the tube's outside diameter.
TUBE_SOCKET_MM = 6.0
HANDLE_MATERIALS = ("abs", "delrin", "pla")
#: Capstan diameters searched (mm): turned from round bar, whole sizes a workshop stocks; those
#: whose wall cannot hold the set screw on a searched motor's shaft are left out
#: (:func:`capstan_stock_mm`).
CAPSTAN_STOCK_MM = (8.0, 10.0, 12.0, 16.0, 20.0, 24.0, 32.0)
#: Capstan ratio n = drum / capstan searched: [lo, hi] in steps of 0.5 (the drum must pass the
#: A4 post: a few times the capstan).
CAPSTAN_RATIO_RANGE = (1.5, 5.0)
#: Centre distance = r_d + r_c + one of these gaps (mm): the moved motor needs room.
CAPSTAN_GAP_CHOICES_MM = (2.0, 10.0, 20.0, 30.0, 40.0, 60.0)


def bar_stock(process: str = "machined") -> dict[str, tuple[float, ...]]:
    """{bar material: stock thicknesses (mm)} the optimisers search under ``parts.process``:
    ``"laser"``: the sheets the laser process cuts the bars from and holds their tapped
    handle hole in (:data:`cad.data.materials.SHEETS` with ``tappable``, each sheet's stock
    thicknesses; :func:`cad.design.laser.check_laser` refuses the others); ``"printed"``: the
    printing filaments of :data:`STOCK_THICKNESS_MM` (:data:`cad.printing.FILAMENTS`);
    otherwise :data:`STOCK_THICKNESS_MM`."""
    if process == "laser":

        return {k: tuple(s.thicknesses_mm) for k, s in SHEETS.items() if s.tappable}
    if process == "printed":

        return {k: v for k, v in STOCK_THICKNESS_MM.items() if k in FILAMENTS}
    return dict(STOCK_THICKNESS_MM)


def handle_materials(process: str = "machined") -> tuple[str, ...]:
    """Handle materials searched: printed, the filaments of :data:`HANDLE_MATERIALS`."""
    if process == "printed":

        return tuple(m for m in HANDLE_MATERIALS if m in FILAMENTS)
    return HANDLE_MATERIALS
#: Layer orders searched (bottom to top), as optuna categorical strings "crank/coupler/rocker".
LAYER_ORDERS = tuple("/".join(o) for o in itertools.permutations(("crank", "coupler", "rocker")))
HANDLE_SCREWS = ("M3-0.5", "M4-0.7")


def searched_motors() -> tuple[str, ...]:
    """The catalog motors the search chooses among: every :data:`cad.data.catalog.MOTORS` entry
    with each constant a build reads (:meth:`~cad.data.catalog.MotorSpec.missing_build_fields`
    empty) and its friction torque Kt I0 (the datasheet's friction figure and the
    ``--beat-prototype`` bound), ordered by rotor inertia J_m, least first (the screen's order:
    :func:`screen_motor`)."""
    ok = [k for k, m in MOTORS.items() if not m.missing_build_fields() and m.friction_torque_mNm() is not None]
    return tuple(sorted(ok, key=lambda k: (MOTORS[k].rotor_inertia_g_cm2, k)))


#: Nominal (max. continuous) torque, mN m, of the searched motors (:func:`searched_motors`): the
#: catalog winding's ``torque_continuous_mNm`` (:data:`cad.data.catalog.MOTORS`, each with its
#: data-sheet source).
MOTOR_CONTINUOUS_TORQUE_MNM = {k: MOTORS[k].torque_continuous_mNm for k in searched_motors()}
#: How a trial gets its motor: ``"screen"`` (default: every searched motor evaluated on the
#: trial's linkage, parts and transmission, least rotor inertia first, the first that meets
#: every check taken: :func:`screen_motor`) or ``"categorical"`` (one more TPE categorical).
MOTOR_CHOICES = ("screen", "categorical")
#: Starting points enqueued before the TPE search (a workshop's light guesses: the smallest
#: joint set, carbon-fibre or aluminium plate, a small knob, both motors, two layer orders that
#: keep the coupler above the crank hub).
STARTS = (
    {"span_deg": 96.0, "shift_deg": -10.0, "joint": 0, "bar_material": "carbon-fibre",
     "thickness_carbon-fibre": 5.0, "bar_width_mm": 12, "pin_material": "titanium-6al4v",
     "bar_pockets": True, "handle_material": "abs", "handle_diameter_mm": 14, "handle_height_mm": 16,
     "handle_screw": "M3-0.5", "motor": "maxon-re40", "layer_order": "crank/coupler/rocker"},
    {"span_deg": 160.0, "shift_deg": 0.0, "joint": 0, "bar_material": "aluminium-6061",
     "thickness_aluminium-6061": 5.0, "bar_width_mm": 10, "pin_material": "aluminium-7075",
     "bar_pockets": True, "handle_material": "abs", "handle_diameter_mm": 14, "handle_height_mm": 16,
     "handle_screw": "M3-0.5", "motor": "maxon-re35", "layer_order": "crank/rocker/coupler"},
)
DEFAULT_DY_MAX_MM = 0.2


def starts_for(process: str) -> list[dict]:
    """:data:`STARTS` in materials ``process`` makes: a bar material it does not take becomes
    the first of :func:`bar_stock` at its stock thickness nearest the start's, a handle
    material the first of :func:`handle_materials`."""
    stock, handles = bar_stock(process), handle_materials(process)
    out = []
    for s in STARTS:
        s = dict(s)
        mat = s["bar_material"]
        if mat not in stock:
            t = s.pop(f"thickness_{mat}")
            mat = next(iter(stock))
            s["bar_material"] = mat
            s[f"thickness_{mat}"] = min(stock[mat], key=lambda x: (abs(x - t), x))
        if s["handle_material"] not in handles:
            s["handle_material"] = handles[0]
        out.append(s)
    return out
#: Kinematic table samples of the in-loop wall stability check (the datasheet's K_max uses
#: :data:`cad.sim.wall.TABLE_SAMPLES`; 2001 gives the same stable / unstable answer at 15 kN/m
#: on hoeken_light, measured: 13.44 vs 13.52 kN/m K_max)
WALL_TABLE_SAMPLES = 2001
DEFAULT_MU_MIN_DEG = 40.0


@dataclass
class Problem:
    """What the search keeps fixed: the source design and its requirements."""

    design: object
    stroke_mm: float
    dy_max_mm: float
    mu_min_deg: float
    base_lo_rad: float
    base_hi_rad: float
    fixed_parts: dict = field(default_factory=dict)
    proportions_tol: float = 0.0
    #: evaluate every limit of every trial (for the Pareto front of two conflicting figures)
    #: instead of stopping at the first missed one
    all_limits: bool = False
    #: with ``all_limits``: every trial that reached the limits, {trial number: Candidate}
    evaluated: dict = field(default_factory=dict)
    #: the brief's ``[transmission]`` table when it is a capstan (searched), else None
    capstan: dict | None = None
    #: the capstan diameters searched (:func:`capstan_stock_mm`, computed once by :func:`run`)
    capstan_stock: tuple = ()
    #: how a trial gets its motor (:data:`MOTOR_CHOICES`)
    motor_choice: str = "screen"


#: [parts] keys of the brief the search keeps as given (the rest it chooses).
FIXED_PARTS_KEYS = ("hub_shaft_engagement_min_mm", "layer_gap_mm", "clearance_min_mm",
                    "interference_poses", "base_thickness_mm", "motor_mount_thickness_mm",
                    "bar_style", "tube_material", "clevis_material", "layer_order",
                    # the process and what it fixes (the search picks bars it accepts: bar_stock)
                    "process", "laser_sheet_mm", "base_material", "motor_mount_material",
                    "print_layer_height_mm", "print_line_width_mm", "print_walls", "print_solid_layers",
                    "print_infill_percent", "print_hole_compensation_mm", "print_press_fit_mm")


def fixed_parts(design) -> dict:
    """The brief's [parts] entries of :data:`FIXED_PARTS_KEYS`."""
    return {k: v for k, v in (design.raw.get("parts") or {}).items() if k in FIXED_PARTS_KEYS}


def problem_from(design) -> Problem:
    """Requirements from the design's targets (bounds) with the defaults above."""
    tg = {t.key: t for t in design.targets}
    m = compute_metrics(design.linkage, design.phi1_min_rad, design.phi1_max_rad, design.force_N,
                        samples=401, refine=False)

    def bound(key, default, side):
        t = tg.get(key)
        if t is None:
            return default
        v = getattr(t, side)
        return v if v is not None else (t.value if t.value is not None else default)

    stroke = tg["stroke_mm"].value if "stroke_mm" in tg and tg["stroke_mm"].value else m.stroke_mm
    if "stroke_mm" in tg and tg["stroke_mm"].min is not None:
        stroke = max(stroke, tg["stroke_mm"].min)
    tr = design.raw.get("transmission")
    capstan = dict(tr) if isinstance(tr, dict) and tr.get("kind") == "capstan" else None
    return Problem(design, float(stroke), float(bound("dy_max_mm", DEFAULT_DY_MAX_MM, "max")),
                   float(bound("min_transmission_angle_deg", DEFAULT_MU_MIN_DEG, "min")),
                   design.phi1_min_rad, design.phi1_max_rad, capstan=capstan)


def capstan_stock_mm(pb: Problem) -> list[float]:
    """:data:`CAPSTAN_STOCK_MM` less the diameters whose wall holds no set screw on the shaft
    of some searched motor (:func:`cad.families.fourbar.capstan_solids.capstan_set_screw` with
    the brief's rope)."""
    out = []
    for dc in CAPSTAN_STOCK_MM:
        t = replace(resolve_device(pb.design).transmission("crank"), capstan_diameter_mm=dc)
        try:
            for motor in MOTOR_CONTINUOUS_TORQUE_MNM:
                capstan_set_screw(replace(pb.design, parts=replace(pb.design.parts, motor=motor)), t)
        except HapticadError:
            continue
        out.append(dc)
    return out


def capstan_start(pb: Problem) -> dict:
    """The brief's own capstan as the searched parameters (for the hand-written starts): its
    diameter (the nearest searched stock), ratio (to 0.5) and centre-distance gap (the
    nearest choice)."""
    if pb.capstan is None:
        return {}
    t = resolve_device(pb.design).transmission("crank")
    lo, hi = CAPSTAN_RATIO_RANGE
    C = cap.centre_distance_mm(t.capstan_diameter_mm, t.drum_diameter_mm, t.centre_distance_mm)
    gap = C - 0.5 * (t.capstan_diameter_mm + t.drum_diameter_mm)
    return {"capstan_diameter_mm": min(capstan_stock_mm(pb), key=lambda d: abs(d - t.capstan_diameter_mm)),
            "capstan_ratio": min(max(round(t.ratio * 2) / 2, lo), hi),
            "capstan_gap_mm": min(CAPSTAN_GAP_CHOICES_MM, key=lambda g: abs(g - gap))}


def brief_start(pb: Problem) -> dict | None:
    """The brief itself as a trial (its crank range, parts, layer order and capstan), enqueued
    first for a capstan brief (whose feasible region is narrow: a rope strong enough at the
    motor's peak torque, a hub stack tall enough for the drum, a place for the motor); None
    when one of its values is outside the searched choices."""
    d, p = pb.design, pb.design.parts
    joint = next((k for k, js in enumerate(JOINT_SETS) if js == (p.bearing, p.pin)), None)
    plan, why = layer_problem(d)
    stock = bar_stock(pb.fixed_parts.get("process", "machined"))
    ok = (joint is not None and why is None and p.bar_thickness_mm in stock.get(p.bar_material, ())
          and p.pin_material in PIN_MATERIALS and p.handle_screw in HANDLE_SCREWS
          and p.motor in MOTOR_CONTINUOUS_TORQUE_MNM and 8 <= p.bar_width_mm <= 24
          and p.handle_material in handle_materials(pb.fixed_parts.get("process", "machined")))
    if not ok:
        return None
    start = {"span_deg": math.degrees(d.phi1_max_rad - d.phi1_min_rad), "shift_deg": 0.0,
             "joint": joint, "bar_material": p.bar_material,
             f"thickness_{p.bar_material}": p.bar_thickness_mm, "bar_width_mm": int(p.bar_width_mm),
             "pin_material": p.pin_material, "bar_pockets": p.bar_pockets,
             "handle_material": p.handle_material, "handle_diameter_mm": int(p.handle_diameter_mm),
             "handle_height_mm": int(p.handle_height_mm), "handle_screw": p.handle_screw,
             "motor": p.motor, **capstan_start(pb)}
    if "layer_order" not in pb.fixed_parts:
        start["layer_order"] = "/".join(plan.order)
    return start


def suggest_transmission(trial, pb: Problem) -> dict | None:
    """The ``[transmission]`` table of one trial: None for a direct-drive brief, else a
    capstan of searched diameter, ratio, rope and centre distance (module docstring)."""
    if pb.capstan is None:
        return None
    dc = trial.suggest_categorical("capstan_diameter_mm", list(pb.capstan_stock or capstan_stock_mm(pb)))
    lo, hi = CAPSTAN_RATIO_RANGE
    n = trial.suggest_float("capstan_ratio", lo, hi, step=0.5)
    gap = trial.suggest_categorical("capstan_gap_mm", list(CAPSTAN_GAP_CHOICES_MM))
    rope = largest_rope_for(dc, get_cable(pb.capstan["cable"]).construction)
    dd = round(n * dc, 3)
    out = {"kind": "capstan", "capstan_diameter_mm": dc, "drum_diameter_mm": dd,
           "cable": pb.capstan["cable"] if rope is None else rope.key,
           "centre_distance_mm": round(0.5 * (dc + dd) + gap, 3)}
    if "wraps" in pb.capstan:
        out["wraps"] = pb.capstan["wraps"]
    return out


#: Link dimensions whose ratio to the coupler l2 the search perturbs (``--proportions-tol``).
PROPORTIONS = ("l1_mm", "l3_mm", "l4_mm", "l5_mm", "le_mm")


def kinematics(pb: Problem, span_deg: float, shift_deg: float, ratios: dict | None = None):
    """(linkage scaled to the stroke, lo, hi, metrics) or None when the range fails.

    ``ratios``: {PROPORTIONS key: factor} applied to the family's link dimensions before
    the scaling (l2 and phi_e kept), i.e. the proportions perturbed within the family."""
    c = 0.5 * (pb.base_lo_rad + pb.base_hi_rad) + math.radians(shift_deg)
    lo, hi = c - math.radians(span_deg) / 2, c + math.radians(span_deg) / 2
    fb0 = pb.design.linkage
    try:
        if ratios:
            fb0 = replace(fb0, **{k: getattr(fb0, k) * float(f) for k, f in ratios.items()})
        m0 = compute_metrics(fb0, lo, hi, pb.design.force_N, samples=201, refine=False)
        fb = fb0.scaled(pb.stroke_mm / m0.stroke_mm)
        m = compute_metrics(fb, lo, hi, pb.design.force_N, samples=401, refine=False)
    except (HapticadError, ValueError, FloatingPointError):
        return None
    return fb, lo, hi, m


def end_radius_mm(bearing: str, width_mm: float, wall_mm: float, hub_d_mm: float, hub_screw: str) -> float:
    """Smallest bar end radius (0.5 mm steps) holding the bearing seat and the hub screws."""
    D = cat.get_bearing(bearing).D_mm
    r_bc = (3.0 + hub_d_mm / 2) / 2
    need = max(width_mm / 2, D / 2 + wall_mm, r_bc + cat.clearance_hole_mm(hub_screw) / 2 + 1.0)
    return math.ceil(need * 2) / 2


def suggest_parts(trial, pb: Problem) -> dict:
    """The [parts] table of one trial (module docstring)."""
    bearing, pin = JOINT_SETS[trial.suggest_int("joint", 0, len(JOINT_SETS) - 1)]
    process = pb.fixed_parts.get("process", "machined")
    stock = bar_stock(process)
    mat = trial.suggest_categorical("bar_material", list(stock))
    t = trial.suggest_categorical(f"thickness_{mat}", list(stock[mat]))
    w = float(trial.suggest_int("bar_width_mm", 8, 24, step=2))
    parts = dict(pb.fixed_parts)
    parts.update({
        "bearing": bearing, "pin": pin,
        "pin_material": trial.suggest_categorical("pin_material", list(PIN_MATERIALS)),
        "bar_material": mat, "bar_thickness_mm": t, "bar_width_mm": w,
        "bar_pockets": trial.suggest_categorical("bar_pockets", [True, False]),
        "handle_material": trial.suggest_categorical("handle_material", list(handle_materials(process))),
        "handle_diameter_mm": float(trial.suggest_int("handle_diameter_mm", 12, 24, step=2)),
        "handle_height_mm": float(trial.suggest_int("handle_height_mm", 12, 25)),
        "handle_screw": trial.suggest_categorical("handle_screw", list(HANDLE_SCREWS)),
        # screened (:func:`screen_motor`) after the suggestions: until then the thickest shaft
        # (the tube clevis is sized for it), of those the strongest
        "motor": (trial.suggest_categorical("motor", list(MOTOR_CONTINUOUS_TORQUE_MNM))
                  if pb.motor_choice == "categorical"
                  else max(MOTOR_CONTINUOUS_TORQUE_MNM, key=lambda k: (MOTORS[k].shaft_diameter_mm,
                                                                      MOTORS[k].torque_continuous_mNm))),
    })
    hub_d = parts.get("hub_diameter_mm", 20.0)
    parts["bar_end_radius_mm"] = end_radius_mm(bearing, w, parts.get("bar_min_wall_mm", 2.0), hub_d,
                                               parts.get("hub_screw", "M3-0.5"))
    if parts.get("bar_style") == "tube":
        parts.update(suggest_tube(trial, parts))
    if "layer_order" not in pb.fixed_parts:
        parts["layer_order"] = trial.suggest_categorical("layer_order", list(LAYER_ORDERS)).split("/")
    return parts


def suggest_tube(trial, parts: dict) -> dict:
    """Tube bars (brief with ``bar_style = "tube"``): a stock tube, and the shortest clevis
    whose socket clears the bearing seat, the hub screw circle and the handle tap by 1 mm."""
    od, idd = TUBE_STOCK_MM[trial.suggest_int("tube", 0, len(TUBE_STOCK_MM) - 1)]
    t = trial.suggest_categorical(f"clevis_thickness_od{od:g}",
                                  [x for x in CLEVIS_STOCK_MM if x >= od + 2.0])
    d = PartsSpec()

    def get(key):
        return parts.get(key, getattr(d, key))

    shaft = cat.get_motor(get("motor")).shaft_diameter_mm
    r = max(cat.get_bearing(get("bearing")).D_mm / 2,
            0.25 * (shaft + get("hub_diameter_mm")) + cat.clearance_hole_mm(get("hub_screw")) / 2,
            shaft / 2 + 0.5, cat.tap_drill_mm(get("handle_screw")) / 2)
    return {"tube_od_mm": od, "tube_id_mm": idd, "bar_thickness_mm": t, "socket_depth_mm": TUBE_SOCKET_MM,
            "clevis_length_mm": math.ceil((r + 1.0) * 2) / 2 + TUBE_SOCKET_MM}


@dataclass(frozen=True)
class Candidate:
    """One evaluated trial: the mechanism table, the parts table, the cheap numbers and the
    ``[transmission]`` table (None: direct drive)."""

    number: int
    mechanism: dict
    parts: dict
    cheap: dict
    transmission: dict | None = None


def cheap_figures(design, samples: int = 201) -> dict:
    """Datasheet figures of a candidate that need no solids (numpy): ``continuous_force_N``,
    ``peak_force_N`` (motor torque / |dx/dphi1|, minimum over the stroke) and ``friction_N``
    (motor Kt I0 / |dx/dphi1|, maximum), by the datasheet's own functions
    (:mod:`cad.families.fourbar.datasheet`), with the motor as the crank sees it."""
    m = resolve_device(design).joint_motor("crank")  # the motor at the crank (x n via a capstan)
    _, Jx, pose, a2, a3 = lever(design, samples)
    out = {r["key"]: r["value"] for r in force_rows(design, m, Jx) if r["value"] is not None}
    fm, _ = friction(design, m, Jx, pose, a2, a3)
    if fm is not None:
        out["friction_N"] = float(fm.max())
    return out


def design_limits(design, m11: bool = True) -> dict:
    """{key: Limit} a candidate must meet: the datasheet's default limits of its material
    (:func:`cad.families.fourbar.limits.fourbar_limits`, the design's ``[targets]`` bounds over
    them) and, with ``m11``, an ``M11_max_g`` max target of the brief (the plain search
    minimizes M11 and checks its target on the exact optimum instead)."""
    lim = fourbar_limits(design, get_elastic(link_material(design.parts)).strength_MPa)
    for t in design.targets:
        if m11 and t.key == "M11_max_g" and t.max is not None:
            lim["M11_max_g"] = Limit("<=", float(t.max), "[targets]", "targets.M11_max_g", "targets")
    return lim


def misses(limits: dict, figures: dict) -> dict:
    """{key: relative violation} of the limits ``figures`` misses (keys it lacks: not judged)."""
    out = {}
    for k, lim in limits.items():
        v = figures.get(k)
        if v is not None and not lim.met(v):
            out[k] = abs(v - lim.value) / abs(lim.value or 1.0)
    return out


def evaluate(pb: Problem, span_deg: float, shift_deg: float, parts: dict, best: float | None = None,
             ratios: dict | None = None, transmission: dict | None = None):  # long-function: the checks in order, cheapest first
    """Cheap evaluation: (objective M11_max_g or inf, info dict). The checks run cheapest
    first; the datasheet limits (:func:`design_limits`) on the figures known before any
    solid (:func:`cheap_figures`), then on the cheap M11 and the beam-frame structure (run only
    when the trial could beat ``best``, the best feasible M11 so far). ``info["misses"]``:
    {limit key: relative violation} of the limits missed. ``transmission``: the trial's
    ``[transmission]`` table (:func:`suggest_transmission`), None for direct drive."""
    k = kinematics(pb, span_deg, shift_deg, ratios)
    if k is None:
        return math.inf, {"infeasible": "crank range"}
    fb, lo, hi, m = k
    info = {"stroke_mm": m.stroke_mm, "dy_max_mm": m.dy_max_mm, "torque_variation": m.torque_variation,
            "torque_max_mNm": m.torque_mean_mNm * (1 + m.torque_variation),
            "min_transmission_angle_deg": m.min_transmission_angle_deg,
            "footprint_mm2": float(m.bbox_mm[0] * m.bbox_mm[1])}
    viol = []
    if m.dy_max_mm > pb.dy_max_mm:
        viol.append("dy_max_mm")
    if m.min_transmission_angle_deg < pb.mu_min_deg:
        viol.append("min_transmission_angle_deg")
    try:
        ps = parse_parts(parts)
    except (HapticadError, ValueError) as exc:
        viol.append(f"parts: {exc}")
        ps = None
    info["mechanism"] = custom_mechanism_table(fb, lo, hi, pb.design.force_N)
    if viol:
        info["infeasible"] = "; ".join(viol)
        return math.inf, info
    d = replace(pb.design, linkage=fb, phi1_min_rad=lo, phi1_max_rad=hi, parts=ps)
    if transmission is not None:
        d = replace(d, raw={**d.raw, "transmission": transmission})  # in range by construction
    limits = design_limits(d, m11=pb.all_limits)
    info.update(cheap_figures(d))
    info["misses"] = misses(limits, info)
    if info["misses"] and not pb.all_limits:
        info["infeasible"] = "limits: " + ", ".join(info["misses"])
        return math.inf, info
    why = cheap.tube_problem(d)
    if why:
        info["infeasible"] = f"tubes: {why}"
        return math.inf, info
    plan, why = layer_problem(d)
    if why:
        info["infeasible"] = f"layers: {why}"
        return math.inf, info
    info["layer_order"] = list(plan.order)
    why = capstan_problem(d, plan) if transmission is not None else None
    if why:
        info["infeasible"] = f"capstan: {why}"
        return math.inf, info
    am = cheap.apparent_mass(d, plan=plan)
    info.update({"M11_max_g": am["M11_max_g"], "M11_min_g": am["M11_min_g"],
                 "M11_variation": (am["M11_max_g"] - am["M11_min_g"]) / am["M11_max_g"],
                 **{h: am[h] for h in ("H11_kg_m2", "H12_kg_m2", "H22_kg_m2", "H33_kg_m2")}})
    if transmission is not None:
        limits, why = _capstan_limits(d, am, limits, info)
        if why:
            info["infeasible"] = why
            return math.inf, info
    info["misses"] = misses(limits, info)
    if best is not None and am["M11_max_g"] > best and not info["misses"]:
        return am["M11_max_g"], info  # cannot become the optimum: skip the structure check
    st = cheap_structure(d, am["M11_max_g"], plan)
    info["first_mode_Hz"], info["max_stress_MPa"] = st["first_mode_Hz"], st["max_stress_MPa"]
    info["misses"] = misses(limits, info)
    if info["misses"]:
        info["infeasible"] = "limits: " + ", ".join(info["misses"])
        return math.inf, info
    if "K_max_N_per_m" in limits and not wall_stable(d, info, limits["K_max_N_per_m"].value):
        info["misses"] = {"K_max_N_per_m": None}
        info["infeasible"] = "limits: K_max_N_per_m"
        return math.inf, info
    return am["M11_max_g"], info


def capstan_problem(design, plan) -> str | None:
    """None when a capstan candidate's capstan holds its set screw, its moved motor has a place
    (the build's own checks, numpy: :func:`cad.families.fourbar.capstan_solids.
    capstan_set_screw`, :func:`~cad.families.fourbar.capstan_solids.placement`), its drum
    stays above the base clearance (the hub's foot), its sector, swept over the crank's range,
    stays off the A4 post in plan view (conservative: whatever their heights) and clears the A2
    pin's washer and nut under the crank (:func:`drum_meets_a2`); else the reason. The last two
    the build's interference check refused on searched optima (issue 35 §1: the drum against
    the washer at A2 and against the base plate)."""
    t = resolve_device(design).transmission("crank")
    J = link_joints_mm(design.linkage)
    try:
        capstan_set_screw(design, t)
        pl = placement(design, t, J, plan)
    except HapticadError as exc:
        return str(exc)
    if pl.z_mm[0] < plan.hub_z_mm[0] - 1e-9:  # the drum hangs under the crank hub's stack
        return (f"the {pl.z_mm[1] - pl.z_mm[0]:g} mm drum reaches z = {pl.z_mm[0]:g} mm, below the hub's "
                f"{plan.hub_z_mm[0]:g} mm clearance over the base plate (a taller hub stack holds it)")
    return _drum_meets_post(design, t, pl, J["ground"]["A4"]) or drum_meets_a2(design, t, pl, J, plan)


def drum_meets_a2(design, t, pl, J, plan) -> str | None:
    """The reason when the drum sector (on the crank, crank frame: hub bore to the groove's
    crests, ``pl.arc_start_deg`` over ``pl.arc_span_deg``, ``pl.z_mm`` high) comes nearer than
    ``clearance_min_mm`` to the A2 pin's hardware below the crank (a disc of
    :func:`a2_hardware_radius_mm` at A2, from the pin's lowest end up to the crank): both ride
    on the crank, so they meet at every pose (the build's interference check refuses it); else
    None. Plan distance from the disc's centre to the annular sector, in closed form."""
    s, p = plan.joints["A2"], design.parts
    z_lo = min(s.thread_end_mm, s.head_face_mm, s.head_top_mm)
    if z_lo >= pl.z_mm[1] + p.clearance_min_mm:
        return None
    c = np.asarray(J["crank"]["A2"], float)
    r_in, r_out = p.hub_diameter_mm / 2, cap_geometry.crest_radius_mm(t.drum_diameter_mm, t.cable_diameter_mm)
    rc = float(np.hypot(*c))
    rel = (math.degrees(math.atan2(c[1], c[0])) - pl.arc_start_deg) % 360.0
    if rel <= pl.arc_span_deg:
        dist = max(0.0, r_in - rc, rc - r_out)
    else:  # the nearer radial edge of the sector
        dist = math.inf
        for a in (pl.arc_start_deg, pl.arc_start_deg + pl.arc_span_deg):
            u = np.array([math.cos(math.radians(a)), math.sin(math.radians(a))])
            dist = min(dist, float(np.hypot(*(c - min(max(float(c @ u), r_in), r_out) * u))))
    need = a2_hardware_radius_mm(p) + p.clearance_min_mm
    if dist < need:
        return (f"the drum sector comes {dist:.1f} mm from A2, where the pin's washer and nut hang "
                f"under the crank ({need:.1f} mm needed)")
    return None


def _drum_meets_post(design, t, pl, a4) -> str | None:
    """The reason when the drum's swept sector (plan view) reaches the A4 post, else None."""
    p = design.parts
    d4 = float(np.hypot(*a4))
    keep = 0.5 * p.post_diameter_mm + p.clearance_min_mm
    if 0.5 * t.drum_diameter_mm + keep <= d4:
        return None
    half = math.degrees(math.asin(min(1.0, keep / d4)))
    lo, hi = math.degrees(design.phi1_min_rad), math.degrees(design.phi1_max_rad)
    swept = pl.arc_span_deg + hi - lo
    rel = (math.degrees(math.atan2(a4[1], a4[0])) - pl.arc_start_deg - lo) % 360.0
    if swept + 2 * half >= 360.0 or rel <= swept + half or rel >= 360.0 - half:
        return f"the {t.drum_diameter_mm:g} mm drum sweeps over the A4 post ({d4:.1f} mm from A1)"
    return None


def _capstan_limits(design, am: dict, limits: dict, info: dict) -> tuple[dict, str | None]:
    """(``limits`` with the capstan's, None) with its figures added to ``info``, or (limits,
    the reason) when a limited capstan figure cannot be computed (the datasheet calls that a
    miss: a rope with no breaking load)."""
    figs, cap_limits = capstan_figures(design, am)
    unknown = [k for k in cap_limits if figs.get(k) is None]
    if unknown:
        return limits, f"capstan: {', '.join(unknown)} not computed (rope data missing)"
    info.update(figs)
    return {**limits, **cap_limits}, None


def capstan_figures(design, am: dict) -> tuple[dict, dict]:
    """({key: value}, {key: Limit}) of the capstan's limited figures of a candidate (bend
    ratio, slip margin, safety factor, drum arc: the rows and limits of
    :func:`cad.families.fourbar.capstan.datasheet_rows`, the datasheet's own) with the cheap
    model's H as its report."""
    phi, Jx, *_ = lever(design)
    rows, limits = fcap.datasheet_rows(design, {**am, "Jm_kg_m2": cheap.rotor_of(design)}, phi, Jx)
    return {r["key"]: r["value"] for r in rows if r["key"] in limits}, limits


def wall_stable(design, info: dict, K_N_per_m: float) -> bool:
    """Is a virtual wall of stiffness ``K_N_per_m`` stable on the reduced 1-DOF model
    (:mod:`cad.sim.wall`: one simulation, the datasheet's inputs without a ``[stiffness]``
    table: Te 0.33 ms, the design's encoder, Fs = its friction estimate, Fv = 0) with the
    cheap model's H (``info``)? The datasheet's K_max is the stability threshold of such walls
    (:func:`cad.sim.wall.k_max_estimate`, with its sampling error)."""
    m = resolve_device(design).joint_motor("crank")
    Jx = lever(design)[1]
    s, _ = stiffness_inputs(design, Jx, info.get("friction_N"))
    H = InertiaCoefficients(info["H11_kg_m2"], info["H12_kg_m2"], info["H22_kg_m2"], info["H33_kg_m2"], 0.0)
    spec = wall.WallSpec(s["Te"], s["counts"], s["Fv"], s["Fs"], m.torque_peak_mNm * 1e-3, s["xdot"])
    tab = wall.device_tables(design, H, samples=WALL_TABLE_SAMPLES)
    return bool(wall.reduced_stable_of(tab, spec, 0.0)(np.array([K_N_per_m]))[0])


def layer_problem(design):
    """(layer plan, None) or (plan or None, the planner's objection): no layout in any order,
    a stack no catalog pin or screw fastens (DesignError of :mod:`cad.families.fourbar.layers`), or
    -- for a given ``[parts] layer_order`` -- a clash between links that widening the gaps
    does not cure (numpy only, the build's poses). Without a given order it is planned
    strictly, as the build refuses: no clear order in any of the six is an objection
    (:func:`cad.families.fourbar.build.check_layout`)."""
    parts = design.parts
    phi = np.linspace(design.phi1_min_rad, design.phi1_max_rad, parts.interference_poses)
    try:
        plan = choose_layers(link_joints_mm(design.linkage), parts,
                             planar_transforms(design.linkage, phi),
                             strict=parts.layer_order is None, made_axle=made_crank_axle(design))
    except HapticadError as exc:
        return None, str(exc)
    if parts.layer_order is not None and plan.conflicts:
        return plan, f"order {'/'.join(plan.order)} clashes ({plan.conflicts[0]})"
    return plan, None


def cheap_structure(design, M11_max_g: float, plan=None) -> dict:
    """Frame structure with FE-calibrated bars (one pose, the range's middle), cheap masses
    (joint hardware on the links that carry it in ``plan``)."""
    J = link_joints_mm(design.linkage)
    parts = design.parts
    hw = cheap.hardware_items(parts, J, plan)
    lumped = [device.Lumped(lk, (float(p[0]) * 1e3, float(p[1]) * 1e3), m) for lk, items in hw.items() for m, p in items]
    lumped.append(device.Lumped("coupler", tuple(J["coupler"]["P"]), cheap.handle_kg(parts)))
    bars = {lk: cheap.bar_props(parts, J, lk, plan)[0] for lk in ("crank", "coupler", "rocker")}
    return device.analyse(design, lumped, bars, "fem", M11_max_g * 1e-3, design.targets, poses=1)


def tpe_sampler(seed: int):
    """The search's sampler: optuna TPE, seeded, multivariate over grouped (conditional) spaces."""
    import warnings

    import optuna

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # optuna's ExperimentalWarning for multivariate / group TPE
        return optuna.samplers.TPESampler(seed=seed, multivariate=True, group=True)


def suggest_and_evaluate(trial, pb: Problem, best: float | None):
    """One trial: its suggested crank range, parts, transmission and proportions evaluated on
    the cheap model (:func:`evaluate`, ``best`` the best feasible M11 so far, g). Returns
    (objective M11_max_g or inf, info, parts table, transmission table or None)."""
    span = trial.suggest_float("span_deg", 60.0, 200.0)
    shift = trial.suggest_float("shift_deg", -40.0, 40.0)
    parts = suggest_parts(trial, pb)
    tr = suggest_transmission(trial, pb)
    tol = pb.proportions_tol
    ratios = ({k: trial.suggest_float(f"ratio_{k}", 1.0 - tol, 1.0 + tol) for k in PROPORTIONS}
              if tol > 0 else None)
    if pb.motor_choice == "categorical":
        val, info = evaluate(pb, span, shift, parts, best, ratios, tr)
        return val, info, parts, tr
    val, info, motor = screen_motor(pb, span, shift, parts, best, ratios, tr)
    return val, info, {**parts, "motor": motor}, tr


#: Infeasibility reasons no motor changes (the linkage's own figures): the screen stops there.
MOTOR_FREE_REASONS = ("crank range", "dy_max_mm", "min_transmission_angle_deg")


def screen_motor(pb: Problem, span_deg: float, shift_deg: float, parts: dict, best: float | None = None,
                 ratios: dict | None = None, transmission: dict | None = None):
    """(value, info, motor): the trial evaluated (:func:`evaluate`) with each searched motor
    (:func:`searched_motors`, least rotor inertia J_m first), the first that meets every check
    taken. Why the first: the motor enters the cheap M11 through the crank-side rotor
    inertia only (J_m, x n^2 through a capstan, plus the capstan's bore: its shaft) and the
    crank's shaft hole, so the feasible motor of least J_m is the lightest one (the catalog's
    J_m differ by 8x and more; a brute force over the motors checks it:
    tests/unit/studies/test_optimize_motors.py). No motor meeting every check: the one of least
    :func:`study_value` (with ``pb.all_limits``, the least summed violation), the first on a
    tie. ``info["motor_screen"]``: {motor: why it was passed over} of the motors tried before.
    A linkage that fails on its own figures (:data:`MOTOR_FREE_REASONS`) is tried once."""
    tried: dict[str, str] = {}
    pick = None
    for motor in MOTOR_CONTINUOUS_TORQUE_MNM:
        val, info = evaluate(pb, span_deg, shift_deg, {**parts, "motor": motor}, best, ratios, transmission)
        if math.isfinite(val):
            return val, {**info, "motor_screen": tried}, motor
        if pick is None or study_value(pb, val, info) < study_value(pb, pick[0], pick[1]):
            pick = (val, info, motor)
        why = info.get("infeasible", "")
        if "mechanism" not in info or any(r in why for r in MOTOR_FREE_REASONS):
            break
        tried[motor] = why
    val, info, motor = pick
    return val, {**info, "motor_screen": {k: v for k, v in tried.items() if k != motor}}, motor


def trial_record(number: int, val: float, info: dict) -> dict:
    """The record of one trial (every trial's, for the Pareto chart and the report): its
    number, ``value`` (M11_max_g, g; None when infeasible) and the cheap figures but the
    mechanism table."""
    return {"trial": number, "value": val if math.isfinite(val) else None,
            **{k: v for k, v in info.items() if k != "mechanism"}}


def study_value(pb: Problem, val: float, info: dict) -> float:
    """What optuna minimizes for a trial: its M11 when feasible; with ``pb.all_limits`` and
    every limit judged, 1000 + the sum of the relative violations (toward the limits); else 1e6."""
    if math.isfinite(val):
        return val
    if pb.all_limits and info.get("misses") and "first_mode_Hz" in info:
        return 1e3 + sum(v for v in info["misses"].values() if v is not None)
    return 1e6


def enqueue_starts(study, pb: Problem, starts: bool) -> None:
    """Set ``pb.capstan_stock`` (capstan briefs) and enqueue the hand-written starting trials
    (the brief itself first for a capstan brief, then :data:`STARTS`) unless ``starts`` is False;
    their motor only when the motor is a TPE parameter (``pb.motor_choice``)."""
    drop = ("motor",) if pb.motor_choice == "screen" else ()  # screened, not a parameter
    if pb.capstan is not None:
        pb.capstan_stock = tuple(capstan_stock_mm(pb))
        first = brief_start(pb) if starts else None
        if first is not None:
            study.enqueue_trial({k: v for k, v in first.items() if k not in drop})
    for start in starts_for(pb.fixed_parts.get("process", "machined")) if starts else ():
        study.enqueue_trial({k: v for k, v in {**start, **capstan_start(pb)}.items() if k not in drop})


def run(pb: Problem, trials: int, seed: int = 0,
        starts: bool = True) -> tuple[list[Candidate], list[dict]]:
    """Run the study; return feasible candidates (best first) and every trial's record.

    ``starts=False`` leaves out the hand-written :data:`STARTS` (TPE from its own random
    start-up trials only); with them, the first ``len(STARTS)`` trials are those guesses.
    In this process, in memory; :mod:`cad.studies.codesign.distributed` runs it on Dask."""
    import optuna

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    study = optuna.create_study(direction="minimize", sampler=tpe_sampler(seed))
    records: list[dict] = []
    cands: list[Candidate] = []

    def objective(trial):
        best = min((c.cheap["M11_max_g"] for c in cands), default=None)
        val, info, parts, tr = suggest_and_evaluate(trial, pb, best)
        records.append(trial_record(trial.number, val, info))
        if pb.all_limits and "misses" in info:
            pb.evaluated[trial.number] = Candidate(trial.number, info["mechanism"], parts, info, tr)
        if math.isfinite(val):
            cands.append(Candidate(trial.number, info["mechanism"], parts, info, tr))
        return study_value(pb, val, info)

    enqueue_starts(study, pb, starts)
    optimize_study(study, objective, trials)
    cands.sort(key=lambda c: c.cheap["M11_max_g"])
    return cands, records


def optimize_study(study, objective, n_trials: int) -> None:
    """``study.optimize(objective, n_trials=n_trials)`` that Ctrl-C / SIGTERM ends cleanly.

    optuna catches a ``KeyboardInterrupt`` raised in a trial and logs it with its traceback
    before re-raising it. Here the trials run with the signals deferred
    (:func:`cad.io.signals.deferred`: only recorded): the next trial sees the signal, stops the
    study and counts as pruned (nothing logged at optuna's WARNING level); an interrupt raised
    all the same (no handlers installed, Python API) does the same. Then
    ``KeyboardInterrupt`` is raised here: the CLI prints ``hapticad: aborted``, exit 130/143.
    Latency: at most one trial. optuna's experimental-feature warnings are silenced.
    """
    import warnings

    import optuna


    stopped: list[bool] = []

    def stop():
        stopped.append(True)
        study.stop()
        return optuna.TrialPruned("interrupted")

    def trial_fn(trial):
        if signals.received() is not None:
            raise stop()
        try:
            return objective(trial)
        except KeyboardInterrupt:
            raise stop() from None


    # the trials' own design warnings (a PLA candidate's "printing filament") are not the user's
    with signals.deferred(), warnings.catch_warnings(), bounds.muted():
        warnings.simplefilter("ignore")  # optuna's experimental-feature warnings (multivariate TPE)
        study.optimize(trial_fn, n_trials=n_trials)
    if stopped:
        raise KeyboardInterrupt


def pareto(records: list[dict], x: str = "M11_max_g", y: str = "torque_variation") -> list[dict]:
    """Non-dominated feasible records (minimize both ``x`` and ``y``)."""
    pts = sorted((r for r in records if r.get("value") is not None), key=lambda r: (r[x], r[y]))
    front, best_y = [], np.inf
    for r in pts:
        if r[y] < best_y:
            front.append(r)
            best_y = r[y]
    return front
