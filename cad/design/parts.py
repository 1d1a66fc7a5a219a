"""The ``[parts]`` table of a four-bar design: joint hardware, bars, motor, base, handle.

Every key is optional; an empty ``[parts]`` table gives the complete default
:class:`PartsSpec` (the hardware of the bundled designs). Lengths in mm, masses in
g, inertia in g cm^2, angles in deg, as the key names say. No CAD import here:
catalog data (bearings, ISO 7379 shoulder screws, motors) comes from
:mod:`cad.data.catalog`, which reads bd_warehouse's CSV tables directly.

Keys (default in brackets)
--------------------------
Bars (crank, coupler, rocker; plates cut from sheet, DXF profiles exported):

``bar_width_mm`` [20.0]
    width of the straight part of every bar.
``bar_thickness_mm`` [6.0]
    plate thickness of every bar; must hold the bearing width plus ``bearing_lip_mm``.
``bar_end_radius_mm`` [bar_width_mm / 2]
    radius of the round bar ends around each joint (>= bar_width_mm / 2; larger gives a
    dog-bone). The bearing seat (bearing outside diameter) plus ``bar_min_wall_mm`` on each
    side must fit in 2 x this radius.
``bar_material`` ["aluminium-6061"]
    any key of :data:`cad.data.materials.MATERIALS`.
``bar_pockets`` [true]
    cut lightening slots through the bars between joints.
``bar_pocket_web_mm`` [3.0]
    material left between a pocket and the bar edge or a joint hole.
``bar_pocket_min_length_mm`` [6.0]
    pockets shorter than this are not cut.
``bar_min_wall_mm`` [2.0]
    smallest wall between a bearing seat or pin hole and the bar edge.
``bar_style`` ["plate"]
    "plate": bars cut from sheet (above); "tube": every bar a carbon-fibre tube bonded into
    one aluminium clevis per joint (isotropy paper §4.1, "aluminum clevises, carbon fibre
    links"; :mod:`cad.parts.tubebars`). A clevis is ``2 bar_end_radius_mm`` wide and
    ``bar_thickness_mm`` high and carries the plate bar's joint feature (bearing seat, pin
    bore, hub screws, handle tap) at the same layer height. Needs collinear joints on every
    link (Hoeken, Chebyshev; a triangular coupler such as Roberts' stays a plate: error).
``tube_od_mm`` [4.0], ``tube_id_mm`` [3.0]
    tube outside / inside diameter (tube style); ``tube_od_mm + 2 <= bar_thickness_mm``
    (1 mm clevis walls), e.g. an 8/6 mm tube needs 10 mm thick bars.
``tube_material`` ["carbon-fibre"], ``clevis_material`` ["aluminium-6061"]
    materials of the tubes and the clevises.
``clevis_length_mm`` [15.0], ``socket_depth_mm`` [5.0]
    joint axis to clevis end, and depth of the bonded tube socket; the socket starts
    ``clevis_length_mm - socket_depth_mm`` from the joint, clear of its feature (+1 mm).

Joints (the same hardware at A2, A3 and A4; "provided a convenient design of the
revolute joints, the different straight line mechanisms can be obtained by fabricating
the adequate set of bars", Hoeken paper §III.A):

``bearing`` ["M8-16-4"]
    deep groove ball bearing, bd_warehouse SKT size ``M<bore>-<OD>-<width>`` (618/8); every
    size of the table from 3 mm bore up: M3-10-4 (623), M4-9-2.5 (618/4), M5-11-3 (618/5),
    M6-13-3.5 (618/6), M8-16-4 ... (``cad.data.catalog.bearing_sizes()``).
``bearing_lip_mm`` [1.0]
    lip under the bearing seat that locates the outer ring axially.
``bearing_mass_g`` [catalog]
    override of the catalog bearing mass.
``pin`` ["M6-1"]
    ISO 7379 shoulder screw thread size (bd_warehouse ShoulderScrew), or a plain ground pin
    ``dowel-3`` / ``dowel-4`` / ``dowel-5`` / ``dowel-6`` / ``dowel-8`` (ISO 2338 m6, held by
    two DIN 471 retaining rings and an ISO 7089 washer; the post and leg screws become M4).
    Its shoulder (pin) diameter must equal the bearing bore (M6-1: 8 mm; dowel-3: 3 mm);
    a mismatch is an error listing the bearings and pins that fit.
``pin_sleeve_material`` [none]
    a turned sleeve (bore = pin diameter, outside = bearing bore, length = bearing width) in
    this material lets a pin thinner than the bearing bore carry it (walls >= 0.5 mm);
    without it the pin diameter must equal the bore.
``pin_material`` ["steel-1018"]
    material of the pins (steel dowels and screws; ``aluminium-7075`` or
    ``titanium-6al4v`` for light pins); retaining rings and nuts stay steel.
``pin_head_clearance_mm`` [1.0]
    gap between the screw head and the bar face under it.
``layer_gap_mm`` [2.0]
    axial gap between two bars at a joint (height of the gap spacer).
``spacer_material`` ["stainless-304"]
    turned spacers on the pin (made parts).
``layer_order`` [automatic]
    list of the three moving links bottom to top, e.g. ["crank", "coupler", "rocker"]
    (each once; anything else: DesignError naming ``parts.layer_order``); by default the
    first order without collision over the stroke is taken
    (:func:`cad.families.fourbar.layers.choose_layers`). The lower link at a joint carries the pin,
    spacers and nut or rings, the upper one the bearing. Searched by ``hapticad optimize``
    (:data:`cad.studies.codesign.search.LAYER_ORDERS`), freed by ``fit --free parts.layer_order``.

Motor and crank hub:

``motor`` ["maxon-re35"]
    key of :data:`cad.data.catalog.MOTORS` (maxon-re35, maxon-re40).
``motor_rotor_inertia_g_cm2`` [catalog]
    override of the catalog rotor inertia Jm.
``motor_mount_thickness_mm`` [5.0] / ``motor_mount_material`` ["aluminium-6061"]
    adapter plate: motor pilot and bolt circle on one side, bolted under the base plate.
``hub_diameter_mm`` [20.0] / ``hub_material`` ["aluminium-6061"]
    direct-drive crank hub clamped on the motor shaft by a set screw.
``hub_screw`` ["M3-0.5"]
    ISO 4762 screws (3) fixing the crank bar to the hub.
``hub_shaft_engagement_min_mm`` [6.0]
    shortest length of motor shaft inside the hub.

Base:

``base_thickness_mm`` [6.0] / ``base_margin_mm`` [15.0] / ``base_material`` ["aluminium-6061"]
    base plate under the mechanism (holds the motor mount at A1 and the post at A4);
    margin around the swept footprint.
``base_clearance_mm`` [1.0]
    smallest gap between a moving part and the base plate.
``post_diameter_mm`` [14.0] / ``post_material`` ["aluminium-6061"]
    standoff carrying the rocker pivot A4.

Handle (at the coupler point P):

``handle_diameter_mm`` [20.0] / ``handle_height_mm`` [25.0] / ``handle_material`` ["delrin"]
``handle_fillet_mm`` [3.0]
    cosmetic round on the knob top (dropped at ``inertia`` and ``preview`` fidelity).
``handle_screw`` ["M4-0.7"]
    ISO 4762 screw fixing the knob to the coupler.
``handle_script`` [none]
    path (relative to the design file) of a Python script defining ``make_handle(params)``
    (or a module-level ``handle``/``result``) that returns a build123d or cadquery object;
    it replaces the built-in knob. ``params`` is a dict (mm) with ``diameter_mm``,
    ``height_mm``, ``screw_clearance_mm``, ``counterbore_mm`` and ``floor_mm``
    (:func:`cad.parts.handle.handle_params`).

Process of the made parts (:mod:`cad.printing`):

``process`` ["machined"]
    machined | printed | laser. "printed": every made part in a
    printable material (pla, petg, abs) is FDM printed: holes compensated, bearing seats
    press-fit, tapped holes opened for heat-set inserts, mass and bar stiffness from the
    wall/infill model, a print orientation in parts.3mf. A made part in PLA or PETG under
    "machined" is printed too, with a warning naming the parts and features (filament only).
    "laser": every plate part (crank, coupler, rocker, base plate, motor mount) is laser-cut
    from sheet of its material (:data:`cad.data.materials.SHEETS`: aluminium-5083,
    aluminium-6061, acrylic-cast, birch-plywood; another material: error) and nested on
    stock sheets (``sheets/sheet_NN.dxf`` with ``--formats dxf``); its thickness must be a
    stock thickness of that sheet (error naming the nearest). A tapped thread in a sheet that
    holds none (acrylic, plywood) is refused naming the part and feature; a reamed or bored
    H7 bore there is laser-cut at nominal instead (warning). The turned and bought parts
    stay as they are (one warning lists the made ones).
``laser_sheet_mm`` [the stock size that orders the least sheet area, cad/export/nesting.py]
    ``[width, length]`` of the sheets to nest on (e.g. the laser's bed), 50..4000 mm each.
``print_layer_height_mm`` [0.2] / ``print_line_width_mm`` [0.45] / ``print_walls`` [2] /
``print_solid_layers`` [4] / ``print_infill_percent`` [20]
    slicer settings of the wall/infill model (:class:`cad.printing.PrintSettings`).
``print_hole_compensation_mm`` [0.2] / ``print_press_fit_mm`` [0.1]
    holes modelled this much over nominal; bearing seats at D + compensation - press fit.

Fidelity and checks:

``fidelity`` ["fabrication"]
    fabrication | inertia | preview (``hapticad build --fidelity`` overrides).
``stl_tolerance_mm`` [0.01] / ``stl_angular_tolerance_deg`` [15.0]
    absolute chordal and angular deflection of exported STL meshes.
``interference_poses`` [60]
    crank angles of the interference sweep (evenly over the stroke, ends included).
``clearance_min_mm`` [0.5]
    two links closer than this anywhere in the stroke count as a collision.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields
from typing import Any

from cad.data import catalog
from cad.data.materials import get_material
from cad.design import bounds
from cad.design.fields import check_unknown, optional_int, optional_number
from cad.design.laser import check_laser
from cad.design.replace import TableReplace
from cad.errors import DesignError
from cad.printing import FILAMENTS, PROCESSES, PrintSettings, is_printed

LINK_NAMES = ("crank", "coupler", "rocker")
FIDELITIES = ("fabrication", "inertia", "preview")


@dataclass(frozen=True)
class PartsSpec(TableReplace):
    """Resolved part parameters (see module docstring for every key, units in names)."""

    bar_width_mm: float = 20.0
    bar_thickness_mm: float = 6.0
    bar_end_radius_mm: float = 10.0
    bar_material: str = "aluminium-6061"
    bar_pockets: bool = True
    bar_pocket_web_mm: float = 3.0
    bar_pocket_min_length_mm: float = 6.0
    bar_min_wall_mm: float = 2.0
    bar_style: str = "plate"
    tube_od_mm: float = 4.0
    tube_id_mm: float = 3.0
    tube_material: str = "carbon-fibre"
    clevis_material: str = "aluminium-6061"
    clevis_length_mm: float = 15.0
    socket_depth_mm: float = 5.0
    bearing: str = "M8-16-4"
    bearing_lip_mm: float = 1.0
    bearing_mass_g: float | None = None
    pin: str = "M6-1"
    pin_material: str = "steel-1018"
    pin_sleeve_material: str | None = None
    pin_head_clearance_mm: float = 1.0
    layer_gap_mm: float = 2.0
    spacer_material: str = "stainless-304"
    layer_order: tuple[str, ...] | None = None
    motor: str = "maxon-re35"
    motor_rotor_inertia_g_cm2: float | None = None
    motor_mount_thickness_mm: float = 5.0
    motor_mount_material: str = "aluminium-6061"
    hub_diameter_mm: float = 20.0
    hub_material: str = "aluminium-6061"
    hub_screw: str = "M3-0.5"
    hub_shaft_engagement_min_mm: float = 6.0
    base_thickness_mm: float = 6.0
    base_margin_mm: float = 15.0
    base_material: str = "aluminium-6061"
    base_clearance_mm: float = 1.0
    post_diameter_mm: float = 14.0
    post_material: str = "aluminium-6061"
    handle_diameter_mm: float = 20.0
    handle_height_mm: float = 25.0
    handle_material: str = "delrin"
    handle_fillet_mm: float = 3.0
    handle_screw: str = "M4-0.7"
    handle_script: str | None = None
    fidelity: str = "fabrication"
    stl_tolerance_mm: float = 0.01
    stl_angular_tolerance_deg: float = 15.0
    interference_poses: int = 60
    clearance_min_mm: float = 0.5
    encoder: str | None = None
    encoder_counts_per_rev: int | None = None
    process: str = "machined"
    print_layer_height_mm: float = PrintSettings.layer_height_mm
    print_line_width_mm: float = PrintSettings.line_width_mm
    print_walls: int = PrintSettings.walls
    print_solid_layers: int = PrintSettings.solid_layers
    print_infill_percent: float = PrintSettings.infill_percent
    print_hole_compensation_mm: float = PrintSettings.hole_compensation_mm
    print_press_fit_mm: float = PrintSettings.press_fit_mm
    laser_sheet_mm: tuple[float, float] | None = None

    def print_settings(self) -> PrintSettings:
        """The :class:`cad.printing.PrintSettings` of these parts."""
        return PrintSettings(self.print_layer_height_mm, self.print_line_width_mm, self.print_walls,
                             self.print_solid_layers, self.print_infill_percent,
                             self.print_hole_compensation_mm, self.print_press_fit_mm)

    def printed(self, material: str) -> bool:
        """A made part of ``material`` is FDM printed (:func:`cad.printing.is_printed`)."""
        return is_printed(self.process, material)

    def as_dict(self, report: bool = False) -> dict[str, Any]:
        """Plain mapping of every resolved parameter (build cache key, report). ``report``:
        without the process keys when no part is printed (report.json as before them)."""
        d = asdict(self)
        if d["layer_order"] is not None:
            d["layer_order"] = list(d["layer_order"])
        if d["laser_sheet_mm"] is not None:
            d["laser_sheet_mm"] = list(d["laser_sheet_mm"])
        if report and self.process != "laser":
            d.pop("laser_sheet_mm")  # not laser: report.json as before the process existed
        if report and not any(self.printed(getattr(self, k)) for k in _MATERIALS):
            for k in _PRINT_KEYS:  # nothing printed: the keys of before the process existed
                d.pop(k)
        return d


_POSITIVE = (
    "bar_width_mm",
    "bar_thickness_mm",
    "bar_pocket_web_mm",
    "bar_pocket_min_length_mm",
    "bar_min_wall_mm",
    "tube_od_mm",
    "tube_id_mm",
    "clevis_length_mm",
    "socket_depth_mm",
    "bearing_lip_mm",
    "pin_head_clearance_mm",
    "layer_gap_mm",
    "motor_mount_thickness_mm",
    "hub_diameter_mm",
    "hub_shaft_engagement_min_mm",
    "base_thickness_mm",
    "base_clearance_mm",
    "post_diameter_mm",
    "handle_diameter_mm",
    "handle_height_mm",
    "stl_tolerance_mm",
    "stl_angular_tolerance_deg",
)
_NONNEG = ("base_margin_mm", "handle_fillet_mm", "clearance_min_mm")
_OPTIONAL_POSITIVE = ("bar_end_radius_mm", "bearing_mass_g", "motor_rotor_inertia_g_cm2")
_MATERIALS = (
    "bar_material",
    "pin_material",
    "spacer_material",
    "motor_mount_material",
    "hub_material",
    "base_material",
    "post_material",
    "handle_material",
    "tube_material",
    "clevis_material",
)
_STRINGS = ("bar_style", "bearing", "pin", "motor", "hub_screw", "handle_screw", "handle_script", "fidelity",
            "encoder")
_BOOLS = ("bar_pockets",)
_PRINT_KEYS = ("process", "print_layer_height_mm", "print_line_width_mm", "print_walls",
               "print_solid_layers", "print_infill_percent", "print_hole_compensation_mm",
               "print_press_fit_mm")
ALLOWED_KEYS = tuple(f.name for f in fields(PartsSpec))


def _f(prefix: str, key: str) -> str:
    return f"{prefix}.{key}" if prefix else key


def _string(table: dict[str, Any], key: str, prefix: str, default: str | None) -> str | None:
    if key not in table:
        return default
    v = table[key]
    if not isinstance(v, str) or not v.strip():
        raise DesignError(_f(prefix, key), f"must be a non-empty string, got {v!r}")
    return v.strip()


def _bool(table: dict[str, Any], key: str, prefix: str, default: bool) -> bool:
    if key not in table:
        return default
    v = table[key]
    if not isinstance(v, bool):
        raise DesignError(_f(prefix, key), f"must be true or false, got {v!r}")
    return v


def parse_parts(table: dict[str, Any] | None, prefix: str = "parts") -> PartsSpec:
    """Validate a ``[parts]`` table and return the complete :class:`PartsSpec`.

    ``table`` may be empty (all defaults). Raises :class:`DesignError` naming the
    field (e.g. ``parts.bar_thickness_mm``) and the reason, quoting the value.
    """
    table = dict(table or {})
    check_unknown(table, ALLOWED_KEYS, prefix)
    d = PartsSpec()
    vals: dict[str, Any] = {}
    for key in _POSITIVE:
        x = optional_number(table, key, prefix, getattr(d, key))
        if x <= 0:
            raise DesignError(_f(prefix, key), f"must be > 0, got {table[key]!r}")
        vals[key] = x
    for key in _NONNEG:
        x = optional_number(table, key, prefix, getattr(d, key))
        if x < 0:
            raise DesignError(_f(prefix, key), f"must be >= 0, got {table[key]!r}")
        vals[key] = x
    for key in _OPTIONAL_POSITIVE:
        x = optional_number(table, key, prefix, None)
        if x is not None and x <= 0:
            raise DesignError(_f(prefix, key), f"must be > 0, got {table[key]!r}")
        vals[key] = x
    for key in _STRINGS:
        vals[key] = _string(table, key, prefix, getattr(d, key))
    for key in _BOOLS:
        vals[key] = _bool(table, key, prefix, getattr(d, key))
    vals["interference_poses"] = optional_int(
        table, "interference_poses", prefix, d.interference_poses, minimum=2
    )
    vals["encoder_counts_per_rev"] = parse_encoder(table, prefix, vals["encoder"])

    for key in _MATERIALS:
        name = _string(table, key, prefix, getattr(d, key))
        vals[key] = get_material(name, _f(prefix, key)).name

    if vals["fidelity"] not in FIDELITIES:
        raise DesignError(
            _f(prefix, "fidelity"),
            f"must be one of {', '.join(FIDELITIES)}, got {vals['fidelity']!r}",
        )
    _check_tube(vals, prefix)
    _print_keys(table, prefix, vals)
    script = vals["handle_script"]
    if script is not None and not script.endswith(".py"):
        raise DesignError(
            _f(prefix, "handle_script"), f"must name a Python file (*.py), got {script!r}"
        )

    order = table.get("layer_order")
    if order is not None:
        if not isinstance(order, list) or sorted(order) != sorted(LINK_NAMES):
            raise DesignError(
                _f(prefix, "layer_order"),
                f"must list crank, coupler and rocker once each (bottom to top), got {order!r}",
            )
        vals["layer_order"] = tuple(order)
    else:
        vals["layer_order"] = None

    # -- end radius: default half the width; never narrower than the bar
    given_r = vals["bar_end_radius_mm"]
    r_end = given_r if given_r is not None else vals["bar_width_mm"] / 2.0
    if r_end < vals["bar_width_mm"] / 2.0 - 1e-12:
        raise DesignError(
            _f(prefix, "bar_end_radius_mm"),
            f"must be >= bar_width_mm / 2 = {vals['bar_width_mm'] / 2:g} mm, got {given_r!r}",
        )
    vals["bar_end_radius_mm"] = r_end

    sleeve = _string(table, "pin_sleeve_material", prefix, None)
    vals["pin_sleeve_material"] = (
        get_material(sleeve, _f(prefix, "pin_sleeve_material")).name if sleeve is not None else None
    )
    _check_hardware(vals, prefix, given_r is not None)
    return PartsSpec(**vals)


BAR_STYLES = ("plate", "tube")

#: Made parts of each material key, and the features printing cannot make as machined.
_MATERIAL_PARTS = {
    "bar_material": ("crank, coupler, rocker", "reamed H7 pin bores printed {comp} mm over (a slip "
                     "fit, not H7), milled bearing seats printed as press fits, the tapped handle "
                     "hole opened for a heat-set insert"),
    "hub_material": ("hub", "tapped screw and set-screw holes take heat-set inserts, the shaft "
                     "bore (H7 when machined) is printed at nominal and drilled to size (FDM "
                     "tolerance, no ISO fit)"),
    "base_material": ("base plate", "tapped post and leg holes take heat-set inserts"),
    "post_material": ("post", "the top bore (H7 when machined) is printed at nominal and drilled "
                      "to size (FDM tolerance, no ISO fit), tapped holes take heat-set inserts"),
    "motor_mount_material": ("motor mount", "the pilot seat (H7 when machined) is printed at "
                             "nominal and drilled to size (FDM tolerance, no ISO fit)"),
    "handle_material": ("handle", ""),
    "spacer_material": ("spacers", ""),
}


def _print_keys(table: dict[str, Any], prefix: str, vals: dict[str, Any]) -> None:
    """``process`` and the ``print_*`` settings; the filament warning (module docstring)."""
    proc = _string(table, "process", prefix, "machined")
    if proc not in PROCESSES:
        raise DesignError(_f(prefix, "process"), f"must be one of {', '.join(PROCESSES)}, got {proc!r}")
    vals["process"] = proc
    vals["laser_sheet_mm"] = _laser_sheet(table, prefix)
    if proc != "laser" and vals["laser_sheet_mm"] is not None:
        bounds.warn(f"{_f(prefix, 'laser_sheet_mm')} is set but {_f(prefix, 'process')} = {proc!r}: "
                    f"no part is laser-cut and the sheet size is not used (set "
                    f"{_f(prefix, 'process')} = \"laser\" to nest the plates on sheets)")
    if proc == "laser":

        check_laser(vals, prefix)
    for key in ("print_layer_height_mm", "print_line_width_mm"):
        vals[key] = optional_number(table, key, prefix, getattr(PartsSpec, key))
        if not 0.05 <= vals[key] <= 1.2:
            raise DesignError(_f(prefix, key), f"must be in 0.05..1.2 mm (FDM nozzles), got {vals[key]!r}")
    for key in ("print_walls", "print_solid_layers"):
        vals[key] = optional_int(table, key, prefix, getattr(PartsSpec, key), minimum=1)
    for key, hi in (("print_infill_percent", 100.0), ("print_hole_compensation_mm", 1.0),
                    ("print_press_fit_mm", 0.5)):
        vals[key] = optional_number(table, key, prefix, getattr(PartsSpec, key))
        if not 0.0 <= vals[key] <= hi:
            raise DesignError(_f(prefix, key), f"must be in 0..{hi:g}, got {vals[key]!r}")
    for key, (names, change) in _MATERIAL_PARTS.items():
        f = FILAMENTS.get(vals[key])
        change = change.format(comp=f"{vals['print_hole_compensation_mm']:g}")
        if f is None or (proc != "printed" and f.machinable):
            continue
        if proc != "printed":  # machined, or laser (which cuts the plate parts only)
            tail = (f"set {_f(prefix, 'process')} = \"printed\" to say so" if proc == "machined"
                    else f"{_f(prefix, 'process')} = \"laser\" cuts the plate parts only")
            bounds.warn(f"{_f(prefix, key)} = {vals[key]!r} is a printing filament, not stock a shop "
                        f"machines: the {names} {'are' if ',' in names or names.endswith('s') else 'is'} FDM printed instead{': ' + change if change else ''} "
                        f"({tail})")
        elif change:
            bounds.warn(f"{_f(prefix, 'process')} = \"printed\": {names} ({vals[key]}): {change}")
    if proc == "printed":
        _warn_unprintable(prefix, vals)


def _warn_unprintable(prefix: str, vals: dict[str, Any]) -> None:
    """Under ``process = "printed"``, name the made parts whose material is no filament: they
    stay machined (the BOM says so), as ``"laser"`` names the parts it does not cut."""
    kept = [f"{names} ({vals[key]})" for key, (names, _) in _MATERIAL_PARTS.items()
            if FILAMENTS.get(vals[key]) is None]
    if kept:
        bounds.warn(f"{_f(prefix, 'process')} = \"printed\": {', '.join(kept)} are not in a printing "
                    f"filament ({', '.join(sorted(FILAMENTS))}): they stay machined, as the BOM "
                    f"process column says (set their {_f(prefix, '*_material')} to a filament to "
                    f"print them)")


def _laser_sheet(table: dict[str, Any], prefix: str) -> tuple[float, float] | None:
    """``laser_sheet_mm``: two numbers, 50..4000 mm (a laser bed to a full 4 m sheet)."""
    v = table.get("laser_sheet_mm")
    if v is None:
        return None
    ok = (isinstance(v, list) and len(v) == 2
          and all(isinstance(x, int | float) and not isinstance(x, bool) for x in v))
    if not ok or not all(50.0 <= x <= 4000.0 for x in v):
        raise DesignError(_f(prefix, "laser_sheet_mm"),
                          f"must be [width, length] in 50..4000 mm (a laser bed to a full sheet), "
                          f"got {v!r}")
    return (float(v[0]), float(v[1]))


def parse_encoder(table: dict[str, Any], prefix: str, encoder: str | None) -> int | None:
    """``encoder_counts_per_rev`` checked (an integer >= 1), and ``encoder`` a catalog key;
    both at once is refused (one encoder per crank)."""
    if encoder is not None:
        catalog.get_encoder(encoder, _f(prefix, "encoder"))
    if "encoder_counts_per_rev" not in table:
        return None
    if encoder is not None:
        raise DesignError(_f(prefix, "encoder_counts_per_rev"),
                          f"give parts.encoder ({encoder!r}) or encoder_counts_per_rev, not both")
    v = table["encoder_counts_per_rev"]
    if isinstance(v, bool) or not isinstance(v, int) or v < 1:
        raise DesignError(_f(prefix, "encoder_counts_per_rev"), f"must be an integer >= 1, got {v!r}")
    return v


def _check_tube(v: dict[str, Any], prefix: str) -> None:
    """``bar_style`` and, for tubes, tube inside clevis (1 mm walls) and a real bore."""
    if v["bar_style"] not in BAR_STYLES:
        raise DesignError(_f(prefix, "bar_style"),
                          f"must be one of {', '.join(BAR_STYLES)}, got {v['bar_style']!r}")
    if v["bar_style"] != "tube":
        return
    od, idd = v["tube_od_mm"], v["tube_id_mm"]
    if idd >= od:
        raise DesignError(_f(prefix, "tube_id_mm"), f"must be < tube_od_mm ({od:g}), got {idd!r}")
    if od + 2.0 > v["bar_thickness_mm"]:
        raise DesignError(_f(prefix, "tube_od_mm"),
                          f"{od:g} mm needs 1 mm clevis walls in bar_thickness_mm "
                          f"({v['bar_thickness_mm']:g}): at most {v['bar_thickness_mm'] - 2:g} mm")
    if v["socket_depth_mm"] >= v["clevis_length_mm"]:
        raise DesignError(_f(prefix, "socket_depth_mm"),
                          f"must be < clevis_length_mm ({v['clevis_length_mm']:g}), "
                          f"got {v['socket_depth_mm']!r}")


#: Thinnest wall of a turned sleeve between a pin and a bearing bore (mm).
SLEEVE_MIN_WALL_MM = 0.5


def _check_hardware(v: dict[str, Any], prefix: str, end_radius_given: bool) -> None:
    """Cross-checks between bars and bought hardware (catalog dimensions)."""
    brg = catalog.get_bearing(v["bearing"], _f(prefix, "bearing"))
    v["bearing"] = brg.size  # an ISO designation ("608") is kept in its catalog form
    pin = catalog.get_shoulder_screw(v["pin"], _f(prefix, "pin"))
    motor = catalog.get_motor(v["motor"], _f(prefix, "motor"))
    catalog.get_cap_screw(v["hub_screw"], _f(prefix, "hub_screw"))
    catalog.get_cap_screw(v["handle_screw"], _f(prefix, "handle_screw"))
    catalog.get_nut(v["pin"], _f(prefix, "pin"))
    catalog.get_washer(v["pin"], _f(prefix, "pin"))

    sleeve_wall = (brg.d_mm - pin.ds_mm) / 2
    if v.get("pin_sleeve_material") is not None and sleeve_wall < SLEEVE_MIN_WALL_MM - 1e-9:
        raise DesignError(
            _f(prefix, "pin_sleeve_material"),
            f"a sleeve from the {pin.ds_mm:g} mm pin to the {brg.d_mm:g} mm bore of {v['bearing']} would have "
            f"a {sleeve_wall:g} mm wall (need >= {SLEEVE_MIN_WALL_MM:g} mm); drop the sleeve or pick a "
            f"thinner pin",
        )
    if abs(pin.ds_mm - brg.d_mm) > 1e-9 and v.get("pin_sleeve_material") is None:
        fits_b = ", ".join(catalog.bearings_with_bore(pin.ds_mm)) or "none in the catalog"
        fits_p = ", ".join(catalog.pins_for_bore(brg.d_mm)) or "none in the catalog"
        raise DesignError(
            _f(prefix, "pin"),
            f"the {v['pin']} shoulder is {pin.ds_mm:g} mm but the {v['bearing']} bearing bore is "
            f"{brg.d_mm:g} mm; bearings that fit {v['pin']}: {fits_b}; pins that fit "
            f"{v['bearing']}: {fits_p}; or a thinner pin with parts.pin_sleeve_material",
        )
    r_end = v["bar_end_radius_mm"]
    need = brg.D_mm + 2.0 * v["bar_min_wall_mm"]
    if need > 2.0 * r_end + 1e-9:
        key = "bar_end_radius_mm" if end_radius_given else "bar_width_mm"
        raise DesignError(
            _f(prefix, key),
            f"the {brg.D_mm:g} mm bearing seat ({v['bearing']}) with {v['bar_min_wall_mm']:g} mm walls "
            f"needs {need:g} mm but the bar end is {2 * r_end:g} mm wide "
            f"(bar_width_mm = {v['bar_width_mm']:g}); widen the bar or pick a smaller bearing",
        )
    if v["bar_thickness_mm"] < brg.B_mm + v["bearing_lip_mm"] - 1e-9:
        raise DesignError(
            _f(prefix, "bar_thickness_mm"),
            f"a {v['bar_thickness_mm']:g} mm bar cannot hold the {brg.B_mm:g} mm wide {v['bearing']} "
            f"bearing with a {v['bearing_lip_mm']:g} mm lip; use >= {brg.B_mm + v['bearing_lip_mm']:g} mm",
        )
    hub_hole = catalog.clearance_hole_mm(v["hub_screw"])
    shaft_r = motor.shaft_diameter_mm / 2.0
    if v["hub_diameter_mm"] / 2.0 - shaft_r < hub_hole + 2.0 - 1e-9:
        raise DesignError(
            _f(prefix, "hub_diameter_mm"),
            f"a {v['hub_diameter_mm']:g} mm hub cannot carry {v['hub_screw']} screws around the "
            f"{motor.shaft_diameter_mm:g} mm shaft; use >= {motor.shaft_diameter_mm + 2 * hub_hole + 4:g} mm",
        )
    r_bc = (shaft_r + v["hub_diameter_mm"] / 2.0) / 2.0
    if r_bc + hub_hole / 2.0 + 1.0 > r_end + 1e-9:
        raise DesignError(
            _f(prefix, "hub_diameter_mm"),
            f"the hub screw circle (radius {r_bc:g} mm) does not fit in the {r_end:g} mm crank end; "
            "use a smaller hub or a larger bar_end_radius_mm",
        )
    if v["post_diameter_mm"] < pin.thread_mm + 2.0 * v["bar_min_wall_mm"] - 1e-9:
        raise DesignError(
            _f(prefix, "post_diameter_mm"),
            f"a {v['post_diameter_mm']:g} mm post cannot take the {v['pin']} thread with "
            f"{v['bar_min_wall_mm']:g} mm walls",
        )
    hs = catalog.get_cap_screw(v["handle_screw"], _f(prefix, "handle_screw"))
    if v["handle_diameter_mm"] < hs.dk_mm + 2.0:
        raise DesignError(
            _f(prefix, "handle_diameter_mm"),
            f"a {v['handle_diameter_mm']:g} mm knob cannot take the {v['handle_screw']} screw",
        )
    _check_handle_fillet(v, prefix)


def _check_handle_fillet(v: dict, prefix: str) -> None:
    """The knob's edge round (radius ``handle_fillet_mm``) must fit its diameter and height
    (2 r < both). Blamed on the knob's height when that is the short side and the round is
    the default one (a knob too flat for any usual round), else on the round."""
    r, dia, h = v["handle_fillet_mm"], v["handle_diameter_mm"], v["handle_height_mm"]
    if 2 * r < min(dia, h):
        return
    if h <= dia and r == PartsSpec.handle_fillet_mm:
        raise DesignError(
            _f(prefix, "handle_height_mm"),
            f"{h:g} mm: a knob this flat cannot take its {r:g} mm edge round "
            f"(parts.handle_fillet_mm); the knob must be taller than {2 * r:g} mm",
        )
    raise DesignError(
        _f(prefix, "handle_fillet_mm"),
        f"{r:g} mm is too large for a {dia:g} mm wide, {h:g} mm tall knob (2 x round < both)",
    )


def default_parts() -> PartsSpec:
    """The complete default PartsSpec (what an empty ``[parts]`` table gives)."""
    return parse_parts({}, "parts")
