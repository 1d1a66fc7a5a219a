"""PowerMouse solids: cubic flotor with six embedded coils, stator with 24 magnets, handle.

Isotropy paper section 5, Fig. 6 (lost in the text; this is our
reconstruction, documented in :mod:`cad.actuators.powermouse`). Flotor frame:
origin at the cube centre, axes normal to the faces, mm.

* Flotor (moves): a cubic shell of outer edge E whose wall thickness equals
  the coil thickness d_c, so each face's coil sits in a stadium pocket of the
  wall, centred on the coil mid-plane a = E/2 - d_c/2; a corner hole along
  -(1,1,1) lets the stator post through; the handle (stem + spherical knob)
  leaves along +(1,1,1): its stem sits in a socket in the (+,+,+) corner, its shoulder on
  a boss inside that corner, and its turned M4 tip is screwed into the boss
  (:func:`handle_plan`).
* Stator (fixed): an iron core cube of half-size c = a - d/2 - t_m carrying
  the 12 inner magnets (it is their back iron), the 12 outer magnets on 6
  iron plates (t_s = alpha w_m) fixed inside a housing cube shell, and a
  post along the diagonal whose turned M4 tip screws into a tapped hole in the
  core's (-,-,-) corner, its shoulder on a spot face there (:func:`post_plan`); the post
  leaves through a bore in the housing's (-,-,-) corner and a round collar outside it,
  where an ISO 4026 set screw locks it. The core's (+,+,+) corner is faced the same way,
  clear of the flotor's handle boss. The housing has a hole at its (+,+,+) corner for the
  handle stem.
* Flotor and housing are each an open box and a lid, so the device can be put together.
  The flotor's lid is its -z wall (so the (+,+,+) corner with the handle boss is one
  piece of the body), the housing's its +z wall. Inner magnets on the core; core into
  the flotor box (upside down), flotor lid on (four ISO 4762 screws into the side walls'
  ends, :func:`flotor_lid_screw_plan`); outer magnets on their iron plates, five plates
  into the housing box, one on its lid; flotor (with the core) lowered into the housing
  box -- its side faces slide past the side magnets at the rattle gap; post through the
  housing's collar and the flotor's corner hole, screwed into the core, set screw
  tightened; housing lid on (four ISO 4762 screws through it into holes tapped in the
  side walls' tops, :func:`lid_screw_plan`); handle stem through the lid's corner hole
  into its socket, its tip screwed into the flotor's corner boss.
* Motion range +- r mm / +- theta deg (Table 4): :func:`motion_clearances`
  moves the flotor solids to the extreme poses and measures the exact OCCT
  distance to the stator.

build123d is imported inside the functions.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from cad.actuators import powermouse as pm
from cad.assembly import fasteners as fs
from cad.assembly.fasteners import MIN_ENGAGEMENT_ALU_D, TAP_LEADOUT_MM
from cad.assembly.interference import pose_clearances
from cad.data.catalog import clearance_hole_mm, tap_drill_mm, thread_diameter_mm
from cad.errors import DesignError
from cad.parts.voicecoil import stadium
from cad.tolerances import HOLE_MARGIN_MM, SEAT_MARGIN_MM

#: Housing lid screws (ISO 4762): size, drilled depth of their tapped holes in the top of
#: the side walls (mm), wall left each side of a tap drill (mm). One screw at the middle of
#: each side wall (:func:`lid_screw_xy_mm`), away from the handle hole at the (+,+,+) corner.
LID_SCREW = "M3-0.5"
LID_TAP_DRILL_DEPTH_MM = 8.0
LID_HOLE_WALL_MM = 0.75
#: Flotor lid screws (ISO 4762), tapped into the top of the flotor's side walls (walls of the
#: coil thickness d_c, ~5 mm): a smaller size, as the flotor is usually a plastic.
FLOTOR_LID_SCREW = "M2.5-0.45"
#: Minimum thread engagement in a hole tapped in a plastic (POM, ABS, PETG...), in thread
#: diameters: 2 d, the usual design rule for machine screws in tapped thermoplastics (a
#: softer internal thread than aluminium's 1.5 d, :mod:`cad.assembly.fasteners`).
MIN_ENGAGEMENT_PLASTIC_D = 2.0
#: Materials tapped with the metal rule (1.5 d); any other material is a plastic (2 d).
_METALS = ("aluminium", "steel", "brass", "titanium", "soft-iron", "copper")
#: Threads (ISO 261 coarse) of the two turned parts screwed in along the diagonal: the
#: handle stem's tip into the flotor's corner boss, the post's tip into the core.
HANDLE_THREAD = "M4-0.7"
POST_THREAD = "M4-0.7"
#: Wall of the flotor's handle boss round the handle stem's radius (mm).
HANDLE_BOSS_WALL_MM = 2.0
#: Full thread of the core's post hole beyond the post tip's thread (mm); the hole is
#: drilled :data:`cad.assembly.fasteners.TAP_LEADOUT_MM` deeper still.
POST_HOLE_EXTRA_MM = 2.0
#: Wall of the housing's post collar round the post's radius (mm), and the ISO 4026 set
#: screws tried there, largest first (:func:`cad.assembly.fasteners.size_set_screw`).
POST_COLLAR_WALL_MM = 6.0
POST_SET_SCREW_SIZES = ("M3-0.5", "M2.5-0.45", "M2-0.4")
#: Legs under the housing (the post's collar stands below its bottom face): turned aluminium
#: feet of this diameter, tapped at the top for an ISO 4762 screw put in from inside the
#: housing through its bottom wall; :data:`LEG_INSET_MM` from the outer faces, mid-side;
#: their feet :data:`LEG_CLEARANCE_MM` below the lowest point of the collar.
LEG_SCREW = "M3-0.5"
LEG_DIAMETER_MM = 12.0
LEG_INSET_MM = 9.0
LEG_CLEARANCE_MM = 2.0
#: Least wall between a corner hole or the handle boss and a coil pocket (mm).
COIL_WALL_MM = 1.5
#: Direction of the post set screw's axis (flotor frame): radial to the diagonal,
#: horizontal, so a hex key reaches it from the side.
POST_SET_SCREW_DIR = np.array([1.0, -1.0, 0.0]) / math.sqrt(2.0)
_SQ2, _SQ3 = math.sqrt(2.0), math.sqrt(3.0)


def lid_screw_plan(
    wall_mm: float,
    *,
    size: str = LID_SCREW,
    part: str = "housing_body",
    field: str = "stator.housing_wall_mm",
    joint: str = "housing lid to body",
    min_d: float | None = None,
    what: str = "lid screws",
    hint: str = "",
) -> dict:
    """Lid screws sized from their stack, before any CAD: through the lid (``wall_mm``
    thick) into a hole tapped in the top of a side wall of ``part`` (full thread
    :data:`LID_TAP_DRILL_DEPTH_MM` - 1 mm lead-out, at least ``min_d`` d, default the
    aluminium 1.5 d: :func:`cad.assembly.fasteners.size_cap_screw`). Returns size, clamp_mm,
    length_mm, engagement_mm, depth_mm, min_engagement_mm. DesignError (``field``) when the
    wall cannot hold the tap drill with :data:`LID_HOLE_WALL_MM` each side (``hint``
    appended to the message)."""
    need = tap_drill_mm(size) + 2 * LID_HOLE_WALL_MM
    if wall_mm < need - 1e-9:
        raise DesignError(
            field,
            f"{wall_mm:g} mm walls cannot take the {size} {what}' tapped holes "
            f"(need >= {need:g} mm){hint}",
        )
    depth = LID_TAP_DRILL_DEPTH_MM - fs.TAP_LEADOUT_MM
    hole = fs.alu_hole(f"{part}:lid", part, size, depth)
    if min_d is not None:
        hole = fs.TappedHole(hole.name, part, size, depth, min_d * thread_diameter_mm(size))
    L, e = fs.size_cap_screw(size, wall_mm, hole, joint, field)
    return {"size": size, "clamp_mm": wall_mm, "length_mm": L, "engagement_mm": e,
            "depth_mm": depth, "min_engagement_mm": hole.min_engagement_mm}


def flotor_lid_screw_plan(g: PowerMouseGeometry, material: str) -> dict:
    """The flotor lid screws (:data:`FLOTOR_LID_SCREW`) sized like the housing's
    (:func:`lid_screw_plan`): clamp = the lid (the -z wall, d_c thick), tapped into the ends
    of the side walls (d_c thick), minimum engagement 1.5 d in a metal, 2 d
    (:data:`MIN_ENGAGEMENT_PLASTIC_D`) in a plastic ``material``. DesignError naming
    ``actuator.rattle_mm`` when the d_c wall cannot hold the tap drill, ``flotor.edge_mm``
    when a tap drill would come within :data:`LID_HOLE_WALL_MM` of the +-x coil pockets
    (their long axis is z: they reach l_m/2 + w_m from the face centre)."""
    dc = g.coil_width_mm
    metal = material.startswith(_METALS)
    sp = lid_screw_plan(
        dc, size=FLOTOR_LID_SCREW, part="flotor_body", field="actuator.rattle_mm",
        joint="flotor lid to body", what="flotor lid screws",
        hint="; the flotor walls are as thick as the coils, gap_mm - rattle_mm",
        min_d=MIN_ENGAGEMENT_ALU_D if metal else MIN_ENGAGEMENT_PLASTIC_D,
    )
    bottom = g.flotor_edge_mm / 2 - dc - LID_TAP_DRILL_DEPTH_MM
    reach = g.magnet_length_mm / 2 + g.magnet_width_mm
    if bottom < reach + LID_HOLE_WALL_MM - 1e-9:
        raise DesignError(
            "flotor.edge_mm",
            f"the flotor lid screws' {LID_TAP_DRILL_DEPTH_MM:g} mm tap drills end at z = "
            f"{bottom:.2f} mm, within {LID_HOLE_WALL_MM:g} mm of the side coil pockets "
            f"(z <= {reach:g} mm); enlarge edge_mm",
        )
    return sp


def handle_plan(g: PowerMouseGeometry, material: str) -> dict:
    """The handle's joint to the flotor, before any CAD: the stem's shoulder on the socket
    bottom at :attr:`PowerMouseGeometry.handle_seat_s_mm`, its turned :data:`HANDLE_THREAD`
    tip (2 d long) in a hole tapped through the corner boss (full thread = tip + lead-out).
    Minimum engagement 1.5 d in a metal flotor, 2 d in a plastic one. Returns size,
    engagement_mm, depth_mm, min_engagement_mm (mm)."""
    d = thread_diameter_mm(HANDLE_THREAD)
    k = MIN_ENGAGEMENT_ALU_D if material.startswith(_METALS) else MIN_ENGAGEMENT_PLASTIC_D
    e = g.handle_thread_mm
    return {"size": HANDLE_THREAD, "engagement_mm": e, "depth_mm": e + TAP_LEADOUT_MM,
            "min_engagement_mm": k * d}


def post_plan(g: PowerMouseGeometry) -> dict:
    """The post's joint to the core and its set screw in the housing collar, before any CAD.

    Tip: :data:`POST_THREAD`, 1.5 d long, in a hole tapped into the core's faced (-,-,-)
    corner (full thread = tip + :data:`POST_HOLE_EXTRA_MM`; minimum 1.5 d, the core is
    iron). Set screw: radial in the collar (radius post + :data:`POST_COLLAR_WALL_MM`),
    sized by :func:`cad.assembly.fasteners.size_set_screw` (DesignError naming
    ``stator.post_diameter_mm`` when none fits). Returns ``{"tip": {size, engagement_mm,
    depth_mm, min_engagement_mm}, "set_screw": {size, length_mm, engagement_mm, depth_mm,
    min_engagement_mm}}`` (mm)."""
    e = g.post_thread_mm
    tip = {"size": POST_THREAD, "engagement_mm": e, "depth_mm": e + POST_HOLE_EXTRA_MM,
           "min_engagement_mm": fs.MIN_ENGAGEMENT_ALU_D * thread_diameter_mm(POST_THREAD)}
    size, L, depth = fs.size_set_screw(
        g.post_diameter_mm / 2, g.post_collar_radius_mm, POST_SET_SCREW_SIZES,
        "set screw locking the stator post in the housing collar", "stator.post_diameter_mm",
    )
    ss = {"size": size, "length_mm": L, "engagement_mm": L, "depth_mm": depth,
          "min_engagement_mm": fs.MIN_ENGAGEMENT_ALU_D * thread_diameter_mm(size)}
    return {"tip": tip, "set_screw": ss}


def post_set_screw_s_mm(g: PowerMouseGeometry, size: str) -> float:
    """Axial place of the post set screw (diagonal, mm): beyond the housing's outer corner
    by its radius + 1 mm, so its whole hole is in the collar."""
    Ho = g.housing_inner_half_mm + g.housing_wall_mm
    return -Ho * _SQ3 - (thread_diameter_mm(size) / 2 + 1.0)


def post_collar_end_s_mm(g: PowerMouseGeometry, size: str) -> float:
    """Outer end of the housing's post collar and of the post (diagonal, mm)."""
    return post_set_screw_s_mm(g, size) - (thread_diameter_mm(size) / 2 + 1.5)


def post_set_screw_tf(g: PowerMouseGeometry, size: str) -> np.ndarray:
    """4x4 placement of the post set screw (flotor frame): its z axis along
    :data:`POST_SET_SCREW_DIR`, its flat point (z = 0) on the post's surface."""
    u = np.ones(3) / _SQ3
    v = POST_SET_SCREW_DIR
    T = np.eye(4)
    T[:3, :3] = np.column_stack([np.cross(u, v), u, v])
    T[:3, 3] = post_set_screw_s_mm(g, size) * u + g.post_diameter_mm / 2 * v
    return T


def leg_plan(wall_mm: float) -> dict:
    """The leg screws, before any CAD: through the housing's bottom wall (``wall_mm``) into a
    hole tapped :data:`LID_TAP_DRILL_DEPTH_MM` deep in each leg's top (aluminium, 1.5 d;
    :func:`cad.assembly.fasteners.size_cap_screw`). Returns size, clamp_mm, length_mm,
    engagement_mm, depth_mm, min_engagement_mm; DesignError naming
    ``stator.housing_wall_mm`` when no catalog length fits."""
    depth = LID_TAP_DRILL_DEPTH_MM - fs.TAP_LEADOUT_MM
    hole = fs.alu_hole("leg:top", "leg", LEG_SCREW, depth)
    L, e = fs.size_cap_screw(LEG_SCREW, wall_mm, hole, "housing to its legs",
                             "stator.housing_wall_mm")
    return {"size": LEG_SCREW, "clamp_mm": wall_mm, "length_mm": L, "engagement_mm": e,
            "depth_mm": depth, "min_engagement_mm": hole.min_engagement_mm}


def leg_xy_mm(g: PowerMouseGeometry) -> list[tuple[float, float]]:
    """(x, y) of the four legs (flotor frame, mm): mid-side, :data:`LEG_INSET_MM` in from
    the housing's outer faces (the screw heads inside clear the iron plates and the flotor)."""
    m = g.housing_inner_half_mm + g.housing_wall_mm - LEG_INSET_MM
    return [(m, 0.0), (0.0, m), (-m, 0.0), (0.0, -m)]


def leg_height_mm(g: PowerMouseGeometry) -> float:
    """Leg height (mm): from the housing's bottom face to :data:`LEG_CLEARANCE_MM` below the
    lowest point of the post's collar (its end disc's rim, at s_end / sqrt3 - R sqrt(2/3))."""
    ss = post_plan(g)["set_screw"]["size"]
    Ho = g.housing_inner_half_mm + g.housing_wall_mm
    low = post_collar_end_s_mm(g, ss) / _SQ3 - g.post_collar_radius_mm * math.sqrt(2.0 / 3.0)
    return -low - Ho + LEG_CLEARANCE_MM


def leg_shape(g: PowerMouseGeometry):
    """One leg in its frame: z from -height (the foot) to 0 (its top, against the housing),
    tapped at the top (tap drill :data:`LID_TAP_DRILL_DEPTH_MM` deep)."""
    import build123d as bd


    h, a = leg_height_mm(g), (bd.Align.CENTER, bd.Align.CENTER, bd.Align.MIN)
    leg = bd.Pos(0, 0, -h) * bd.Cylinder(LEG_DIAMETER_MM / 2, h, align=a)
    drill = bd.Pos(0, 0, -LID_TAP_DRILL_DEPTH_MM) * bd.Cylinder(
        tap_drill_mm(LEG_SCREW) / 2, LID_TAP_DRILL_DEPTH_MM + 1.0, align=a)
    return (leg - drill).solids()[0]


def _leg_screw_holes(g: PowerMouseGeometry):
    """Clearance holes for the leg screws through the housing's bottom wall."""
    import build123d as bd


    Ho, w = g.housing_inner_half_mm + g.housing_wall_mm, g.housing_wall_mm
    a = (bd.Align.CENTER, bd.Align.CENTER, bd.Align.MIN)
    cut = None
    for x, y in leg_xy_mm(g):
        c = bd.Pos(x, y, -Ho - 1.0) * bd.Cylinder(clearance_hole_mm(LEG_SCREW) / 2, w + 2.0, align=a)
        cut = c if cut is None else cut + c
    return cut


def lid_screw_xy_mm(g: PowerMouseGeometry) -> list[tuple[float, float]]:
    """(x, y) of the housing lid screws (flotor frame, mm): mid-wall, middle of each side."""
    m = g.housing_inner_half_mm + g.housing_wall_mm / 2
    return [(m, 0.0), (0.0, m), (-m, 0.0), (0.0, -m)]


def flotor_lid_screw_xy_mm(g: PowerMouseGeometry) -> list[tuple[float, float]]:
    """(x, y) of the flotor lid screws (flotor frame, mm): mid-wall (d_c walls), middle of
    each side -- clear of the +z coil pocket (reach w_m across x, l_m/2 + w_m along y) and
    of the handle hole at the (+,+,+) corner."""
    m = g.flotor_edge_mm / 2 - g.coil_width_mm / 2
    return [(m, 0.0), (0.0, m), (-m, 0.0), (0.0, -m)]


def _screw_holes(xy, size: str, z_split: float, z_top: float):
    """Clearance holes through a lid (``z_split``..``z_top``) and tap drills
    (:data:`LID_TAP_DRILL_DEPTH_MM` deep) into the side walls' tops below ``z_split``."""
    import build123d as bd


    a = (bd.Align.CENTER, bd.Align.CENTER, bd.Align.MIN)
    cut = None
    for x, y in xy:
        c = bd.Pos(x, y, z_split) * bd.Cylinder(clearance_hole_mm(size) / 2, z_top - z_split + 1.0,
                                                align=a)
        c = c + bd.Pos(x, y, z_split - LID_TAP_DRILL_DEPTH_MM) * bd.Cylinder(
            tap_drill_mm(size) / 2, LID_TAP_DRILL_DEPTH_MM, align=a
        )
        cut = c if cut is None else cut + c
    return cut


def _lid_screw_holes(g: PowerMouseGeometry):
    """Clearance holes through the housing lid and tap drills into the side walls' tops."""
    H = g.housing_inner_half_mm
    return _screw_holes(lid_screw_xy_mm(g), LID_SCREW, H, H + g.housing_wall_mm)


@dataclass(frozen=True)
class PowerMouseGeometry:
    """Derived PowerMouse dimensions (mm); see the module docstring for the symbols."""

    magnet_length_mm: float
    magnet_width_mm: float
    magnet_thickness_mm: float
    gap_mm: float
    rattle_mm: float
    plate_thickness_mm: float
    flotor_edge_mm: float
    corner_hole_mm: float
    post_diameter_mm: float
    housing_wall_mm: float
    handle_length_mm: float
    handle_diameter_mm: float
    knob_diameter_mm: float
    plate_margin_mm: float = 2.0
    range_mm: float = 3.0
    range_deg: float = 5.0

    @property
    def handle_seat_s_mm(self) -> float:
        """Bottom of the handle socket, along the diagonal from the centre (mm): the deepest
        plane across the (+,+,+) corner where the stem's shoulder (radius + margin) is still
        inside the cube, sqrt3 E/2 - sqrt2 (r + margin) (a point at radius rho off the
        diagonal reaches rho sqrt(2/3) beyond it in one coordinate)."""
        r = self.handle_diameter_mm / 2 + SEAT_MARGIN_MM
        return _SQ3 * self.flotor_edge_mm / 2 - _SQ2 * r

    @property
    def handle_thread_mm(self) -> float:
        """Thread length of the handle stem's tip: 2 d (:data:`MIN_ENGAGEMENT_PLASTIC_D`,
        the longer rule, so the boss serves a plastic or a metal flotor)."""
        return MIN_ENGAGEMENT_PLASTIC_D * thread_diameter_mm(HANDLE_THREAD)

    @property
    def handle_boss_bottom_s_mm(self) -> float:
        """End of the handle boss inside the flotor (diagonal, mm): the tapped hole runs
        through the boss, its full thread the tip's thread + the tap lead-out."""
        return self.handle_seat_s_mm - self.handle_thread_mm - TAP_LEADOUT_MM

    @property
    def core_flat_s_mm(self) -> float:
        """Where the core's two diagonal corners are faced (distance from the centre, mm):
        the flat's inscribed circle (radius h / sqrt2 at depth h from the corner) holds the
        post's shoulder, radius + :data:`SEAT_MARGIN_MM`."""
        h = _SQ2 * (self.post_diameter_mm / 2 + SEAT_MARGIN_MM)
        return self.core_half_mm * _SQ3 - h

    @property
    def post_thread_mm(self) -> float:
        """Thread length of the post's tip in the core: 1.5 d (a metal core)."""
        return MIN_ENGAGEMENT_ALU_D * thread_diameter_mm(POST_THREAD)

    @property
    def post_collar_radius_mm(self) -> float:
        return self.post_diameter_mm / 2 + POST_COLLAR_WALL_MM

    @property
    def coil_width_mm(self) -> float:
        return self.gap_mm - self.rattle_mm

    @property
    def coil_plane_half_mm(self) -> float:
        """a: cube centre to the coil mid-plane."""
        return self.flotor_edge_mm / 2 - self.coil_width_mm / 2

    @property
    def core_half_mm(self) -> float:
        """c = a - d/2 - t_m: inner iron core half-size."""
        return self.coil_plane_half_mm - self.gap_mm / 2 - self.magnet_thickness_mm

    @property
    def housing_inner_half_mm(self) -> float:
        return (
            self.coil_plane_half_mm
            + self.gap_mm / 2
            + self.magnet_thickness_mm
            + self.plate_thickness_mm
        )

    def excursion_mm(self, s_mm: float) -> float:
        """Largest distance from the diagonal, over the motion the coil gaps allow, of the
        flotor's point ``s_mm`` along it (:func:`cad.actuators.powermouse.diagonal_excursion_mm`);
        the same bound holds for a stator point seen from the flotor."""
        return _excursion(self.coil_plane_half_mm, self.magnet_width_mm, self.magnet_length_mm,
                          self.gap_mm, self.coil_width_mm, self.range_mm, self.range_deg,
                          round(s_mm, 9))

    @property
    def housing_hole_mm(self) -> float:
        """Handle hole in the housing's corner: the stem plus twice its excursion at the
        housing's outer corner and :data:`HOLE_MARGIN_MM` (the handle is never the end stop)."""
        Ho = self.housing_inner_half_mm + self.housing_wall_mm
        return self.handle_diameter_mm + 2 * (self.excursion_mm(Ho * _SQ3) + HOLE_MARGIN_MM)

    @property
    def corner_hole_min_mm(self) -> float:
        """Smallest flotor corner hole round the post: the post plus twice the post's
        excursion at the flotor's outer corner and :data:`HOLE_MARGIN_MM`."""
        s = self.flotor_edge_mm / 2 * _SQ3
        return self.post_diameter_mm + 2 * (self.excursion_mm(s) + HOLE_MARGIN_MM)

    def coils(self):
        return pm.coil_layout(self.coil_plane_half_mm)

    def validate(self) -> None:
        """Raise DesignError when the parts cannot be placed (names the key to change)."""
        w, lm = self.magnet_width_mm, self.magnet_length_mm
        if self.core_half_mm < max(w, lm / 2) + 1.0:
            need = (
                2 * (max(w, lm / 2) + 1.0 + self.gap_mm / 2 + self.magnet_thickness_mm)
                + self.coil_width_mm
            )
            raise DesignError(
                "flotor.edge_mm",
                f"too small for the inner magnets: core half-size {self.core_half_mm:.2f} mm < "
                f"{max(w, lm / 2) + 1.0:.2f} mm; use edge_mm >= {need:.1f}",
            )
        inner = self.flotor_edge_mm / 2 - self.coil_width_mm
        if lm / 2 + w + 2.0 > inner:
            raise DesignError(
                "flotor.edge_mm",
                f"coil (reach {lm / 2 + w:.1f} mm) does not fit in a face (inner half {inner:.1f} mm)",
            )
        self._validate_turned_parts()
        self._validate_corner_hole()
        self._validate_handle()

    def _coil_distance_mm(self) -> float:
        """Smallest distance from the coils' rims to the diagonal (mm)."""
        rim = self.coil_rim_points()
        u = np.ones(3) / _SQ3
        return float(np.linalg.norm(rim - np.outer(rim @ u, u), axis=1).min())

    def _validate_corner_hole(self) -> None:
        """The corner hole clears the post over the motion (:attr:`corner_hole_min_mm`) and
        stays :data:`COIL_WALL_MM` off the coil pockets. Advised limits are rounded inwards
        (a lower bound up, an upper bound down, to 0.01 mm), so following them builds."""
        need, room = self.corner_hole_min_mm, 2 * (self._coil_distance_mm() - COIL_WALL_MM)
        if need > room + 1e-9:
            post_max = self.post_diameter_mm - (need - room)
            if post_max < tap_drill_mm(POST_THREAD) + 2.0:  # no post fits: the flotor must grow
                raise DesignError(
                    "flotor.edge_mm",
                    f"{self.flotor_edge_mm:g} mm: over the +-{self.range_mm:g} mm / "
                    f"+-{self.range_deg:g} deg motion the stator post moves so far in the "
                    f"flotor's corner hole that no post (>= {tap_drill_mm(POST_THREAD) + 2:g} mm) "
                    "fits beside the coil pockets; enlarge edge_mm or reduce motion.range_deg / "
                    "motion.range_mm",
                )
            raise DesignError(
                "stator.post_diameter_mm",
                f"{self.post_diameter_mm:g} mm: the flotor's corner hole round it must be >= "
                f"{need:.2f} mm for the motion, but the coils leave room for {room:.2f} mm; "
                f"use post_diameter_mm <= {_down(post_max):.2f} with flotor.corner_hole_mm = "
                f"{_down(room):.2f}",
            )
        if self.corner_hole_mm < need - 1e-9:
            raise DesignError(
                "flotor.corner_hole_mm",
                f"{self.corner_hole_mm:g} mm: the {self.post_diameter_mm:g} mm post moves "
                f"{(need - self.post_diameter_mm) / 2 - HOLE_MARGIN_MM:.2f} mm off its axis there "
                f"over the motion range with flotor.edge_mm = {self.flotor_edge_mm:g} mm; use "
                f"corner_hole_mm >= {_up(need):.2f}",
            )
        if self.corner_hole_mm > room + 1e-9:
            raise DesignError(
                "flotor.corner_hole_mm",
                f"{self.corner_hole_mm:g} mm comes within {COIL_WALL_MM:g} mm of a coil pocket; "
                f"use corner_hole_mm <= {_down(room):.2f} (or enlarge flotor.edge_mm)",
            )

    def _validate_handle(self) -> None:
        """The handle's boss stays off the coil pockets; the knob is wider than the stem and
        stays out of the housing over the motion range."""
        boss = self.handle_diameter_mm + 2 * HANDLE_BOSS_WALL_MM
        room = 2 * (self._coil_distance_mm() - COIL_WALL_MM)
        if boss > room + 1e-9:
            raise DesignError(
                "handle.diameter_mm",
                f"{self.handle_diameter_mm:g} mm: its {boss:g} mm boss inside the flotor's corner "
                f"would cut a coil pocket; use diameter_mm <= {_down(room - 2 * HANDLE_BOSS_WALL_MM):.2f}",
            )
        if self.knob_diameter_mm < self.handle_diameter_mm + 2.0 - 1e-9:
            raise DesignError(
                "handle.knob_diameter_mm",
                f"{self.knob_diameter_mm:g} mm is no knob on a {self.handle_diameter_mm:g} mm "
                f"stem; use knob_diameter_mm >= {self.handle_diameter_mm + 2:g}",
            )
        gap = self._knob_gap_mm()
        if gap < 0:
            raise DesignError(
                "handle.length_mm",
                f"{self.handle_length_mm:g} mm: the {self.knob_diameter_mm:g} mm knob "
                f"(handle.knob_diameter_mm) would reach the housing's corner over the motion "
                f"range; use length_mm >= "
                f"{_up(self.handle_length_mm - gap / (1 - math.sin(math.radians(self.range_deg))), 1):.1f}"
                " or a smaller knob",
            )

    def _knob_gap_mm(self) -> float:
        """Knob to the housing's outer corner, the knob moved as far as the motion range goes
        towards it (|t| <= sqrt3 range, rotation s sin theta at its centre s), mm."""
        Ho = self.housing_inner_half_mm + self.housing_wall_mm
        s_c = self.flotor_edge_mm / 2 * _SQ3 + self.handle_length_mm + 0.35 * self.knob_diameter_mm
        move = _SQ3 * self.range_mm + s_c * math.sin(math.radians(self.range_deg))
        return s_c - Ho * _SQ3 - move - self.knob_diameter_mm / 2

    def _validate_turned_parts(self) -> None:
        """The post and the handle stem must leave a 1 mm shoulder round their tips' tap drill."""
        for field, dia, thread in (("stator.post_diameter_mm", self.post_diameter_mm, POST_THREAD),
                                   ("handle.diameter_mm", self.handle_diameter_mm, HANDLE_THREAD)):
            need = tap_drill_mm(thread) + 2.0
            if dia < need - 1e-9:
                raise DesignError(
                    field,
                    f"{dia:g} mm leaves no shoulder round its {thread.split('-')[0]} tip "
                    f"(need >= {need:g} mm)",
                )

    def coil_rim_points(self, n: int = 180) -> np.ndarray:
        """Points (6*2*n, 3) on the outer rims of the six coils at both wall surfaces (flotor frame)."""
        w, lm, dc = self.magnet_width_mm, self.magnet_length_mm, self.coil_width_mm
        th = np.linspace(0, 2 * np.pi, n, endpoint=False)
        # stadium outline: x = w cos, y = (l/2) sign(sin) + w sin
        x = w * np.cos(th)
        y = np.sign(np.sin(th)) * lm / 2 + w * np.sin(th)
        pts = []
        for c in self.coils():
            R = c.R_flotor_act
            for z in (-dc / 2, dc / 2):
                local = np.stack([x, y, np.full_like(x, z)], 1)
                pts.append(local @ R.T + c.centre_mm)
        return np.concatenate(pts)


def _up(x: float, digits: int = 2) -> float:
    """``x`` rounded up to ``digits`` decimals (an advised lower bound that holds)."""
    k = 10.0**digits
    return math.ceil(x * k - 1e-6) / k


def _down(x: float, digits: int = 2) -> float:
    """``x`` rounded down to ``digits`` decimals (an advised upper bound that holds)."""
    k = 10.0**digits
    return math.floor(x * k + 1e-6) / k


@functools.lru_cache(maxsize=64)
def _excursion(a_mm, w_mm, l_mm, gap_mm, dc_mm, range_mm, range_deg, s_mm) -> float:
    return pm.diagonal_excursion_mm(pm.coil_layout(a_mm), w_mm, l_mm, gap_mm, dc_mm, range_mm,
                                    range_deg, s_mm).excursion_mm


#: The worst combined poses are checked this far (mm) inside the coil-gap stop, so that the
#: coils themselves stay clear there.
STOP_BACKOFF_MM = 0.2


def combined_poses(g: PowerMouseGeometry) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """The poses (label, R (3,3), t_mm (3,)) that move the handle stem furthest off the
    housing hole's axis and the post furthest off the flotor hole's axis, translation and
    rotation together, within the coil-gap stop less :data:`STOP_BACKOFF_MM`
    (:func:`cad.actuators.powermouse.diagonal_excursion_mm`)."""
    Ho = g.housing_inner_half_mm + g.housing_wall_mm
    out = []
    for name, s_mm in (("handle", Ho * _SQ3), ("post", g.flotor_edge_mm / 2 * _SQ3)):
        x = pm.diagonal_excursion_mm(g.coils(), g.magnet_width_mm, g.magnet_length_mm,
                                     g.gap_mm, g.coil_width_mm, g.range_mm, g.range_deg, s_mm,
                                     backoff_mm=STOP_BACKOFF_MM)
        out.append((f"c:{name}", x.R, x.t_mm))
    return out


def geometry(design, gap_mm: float) -> PowerMouseGeometry:
    """PowerMouseGeometry from a PowerMouseDesign and the actuator gap d (mm), validated."""
    a = design.actuator
    g = PowerMouseGeometry(
        magnet_length_mm=a.magnet_length_mm,
        magnet_width_mm=a.magnet_width_mm,
        magnet_thickness_mm=a.magnet_thickness_mm,
        gap_mm=gap_mm,
        rattle_mm=a.rattle_mm,
        plate_thickness_mm=a.plate_thickness_mm,
        flotor_edge_mm=design.flotor.edge_mm,
        corner_hole_mm=design.flotor.corner_hole_mm,
        post_diameter_mm=design.stator.post_diameter_mm,
        housing_wall_mm=design.stator.housing_wall_mm,
        handle_length_mm=design.handle.length_mm,
        handle_diameter_mm=design.handle.diameter_mm,
        knob_diameter_mm=design.handle.knob_diameter_mm,
        range_mm=design.motion.range_mm,
        range_deg=design.motion.range_deg,
    )
    g.validate()
    return g


def _loc(R: np.ndarray, origin) -> object:
    """build123d Location whose axes are R's columns (x, y, z) placed at ``origin`` (mm)."""
    import build123d as bd

    return bd.Location(
        bd.Plane(
            origin=tuple(map(float, origin)),
            x_dir=tuple(map(float, R[:, 0])),
            z_dir=tuple(map(float, R[:, 2])),
        )
    )


def _diag_cylinder(radius_mm: float, start_mm: float, end_mm: float):
    """Cylinder of ``radius_mm`` along the unit diagonal (1,1,1)/sqrt3 between signed distances start..end."""
    import build123d as bd

    u = np.ones(3) / math.sqrt(3)
    mid = 0.5 * (start_mm + end_mm) * u
    return bd.Location(bd.Plane(origin=tuple(mid), z_dir=tuple(u))) * bd.Cylinder(
        radius_mm, abs(end_mm - start_mm)
    )


def flotor_solids(g: PowerMouseGeometry) -> dict[str, tuple[object, str]]:
    """Moving solids in the flotor frame: name -> (solid, role) with role shell|coil|handle.

    ``flotor_body`` (the open box, with the handle boss) and ``flotor_lid`` (its -z wall),
    ``coil_<face>`` x6 and ``handle``."""
    import build123d as bd


    E, dc = g.flotor_edge_mm, g.coil_width_mm
    w, lm = g.magnet_width_mm, g.magnet_length_mm
    shell = bd.Box(E, E, E) - bd.Box(E - 2 * dc, E - 2 * dc, E - 2 * dc)
    shell = shell + (_handle_boss(g) & bd.Box(E, E, E))
    coils = {}
    for c in g.coils():
        loc = _loc(c.R_flotor_act, c.centre_mm)
        shell = shell - loc * stadium(lm, 2 * w, dc + 1.0)
        coils[f"coil_{c.face}"] = (loc * stadium(lm, 2 * w, dc), "coil")
    half_diag = E / 2 * _SQ3
    shell = shell - _diag_cylinder(g.corner_hole_mm / 2, -half_diag - 1, 0.0)  # post hole
    handle = _handle(g)
    shell = shell - _handle_socket(g)
    holes = _screw_holes(flotor_lid_screw_xy_mm(g), FLOTOR_LID_SCREW, E / 2 - dc, E / 2)
    shell = shell - holes.mirror(bd.Plane.XY)  # the lid is the -z wall: screws from below
    # split at the inner face of the -z wall: the lid and an open box (so the core goes in)
    lid, body = _split_z(shell, -(E / 2 - dc), E)
    out = {"flotor_body": (body, "shell"), "flotor_lid": (lid, "shell")}
    out.update(coils)
    out["handle"] = (handle, "handle")
    return out


def _handle_boss(g: PowerMouseGeometry):
    """Round boss inside the flotor's (+,+,+) corner (radius stem + wall), from the corner
    down to :attr:`PowerMouseGeometry.handle_boss_bottom_s_mm`; clipped to the cube."""
    r = g.handle_diameter_mm / 2 + HANDLE_BOSS_WALL_MM
    return _diag_cylinder(r, g.handle_boss_bottom_s_mm, g.flotor_edge_mm / 2 * _SQ3)


def _handle_socket(g: PowerMouseGeometry):
    """The stem's socket (down to the seat) and the tap drill through the boss."""
    top = g.flotor_edge_mm / 2 * _SQ3 + 1.0
    seat = g.handle_seat_s_mm
    return _diag_cylinder(g.handle_diameter_mm / 2, seat, top) + _diag_cylinder(
        tap_drill_mm(HANDLE_THREAD) / 2, g.handle_boss_bottom_s_mm - 1.0, seat
    )


def _handle(g: PowerMouseGeometry):
    """Handle along +(1,1,1): turned tip (tap-drill diameter, the thread's minor envelope),
    stem from the socket's seat out, spherical knob at its end."""
    import build123d as bd


    seat = g.handle_seat_s_mm
    s1 = g.flotor_edge_mm / 2 * _SQ3 + g.handle_length_mm
    stem = _diag_cylinder(g.handle_diameter_mm / 2, seat, s1)
    tip = _diag_cylinder(tap_drill_mm(HANDLE_THREAD) / 2, seat - g.handle_thread_mm, seat)
    u = np.ones(3) / _SQ3
    knob = bd.Pos(*(u * (s1 + 0.35 * g.knob_diameter_mm))) * bd.Sphere(g.knob_diameter_mm / 2)
    return tip + stem + knob


def _split_z(shape, z_mm: float, size_mm: float):
    """(part of ``shape`` below z, part above z): an open box and its lid."""
    import build123d as bd

    big = 4 * size_mm
    below = bd.Pos(0, 0, z_mm - big / 2) * bd.Box(big, big, big)
    above = bd.Pos(0, 0, z_mm + big / 2) * bd.Box(big, big, big)
    return (shape & below).solids()[0], (shape & above).solids()[0]


def stator_solids(g: PowerMouseGeometry) -> dict[str, tuple[object, str]]:
    """Fixed solids in the flotor frame (nominal pose): name -> (solid, role) with role core|magnet|iron|housing."""
    import build123d as bd

    w, lm, t, d = g.magnet_width_mm, g.magnet_length_mm, g.magnet_thickness_mm, g.gap_mm
    out: dict[str, tuple[object, str]] = {}
    H = g.housing_inner_half_mm
    ss = post_plan(g)["set_screw"]["size"]
    out["core"] = (_core(g), "core")
    out["post"] = (_post(g, ss), "post")
    coils = g.coils()
    for mg in pm.stator_magnets(coils, d, lm, w, t, 1.0):
        face = coils[mg.actuator].face
        out[f"magnet_{face}_{mg.role}"] = (_loc(mg.R, mg.centre_mm) * bd.Box(w, lm, t), "magnet")
    for cl in coils:
        a = g.coil_plane_half_mm
        zc = a + d / 2 + t + g.plate_thickness_mm / 2
        plate = bd.Box(
            2 * w + 2 * g.plate_margin_mm, lm + 2 * g.plate_margin_mm, g.plate_thickness_mm
        )
        out[f"iron_{cl.face}"] = (_loc(cl.R_flotor_act, cl.normal * zc) * plate, "iron")
    Ho = H + g.housing_wall_mm
    collar = _diag_cylinder(g.post_collar_radius_mm, post_collar_end_s_mm(g, ss), -H * _SQ3)
    housing = bd.Box(2 * Ho, 2 * Ho, 2 * Ho) + collar - bd.Box(2 * H, 2 * H, 2 * H)
    housing = housing - _diag_cylinder(g.housing_hole_mm / 2, 0.0, Ho * _SQ3 + 5)
    # post bore: starts where the post's cylinder first reaches a wall ((H - r) sqrt3 from the
    # centre along the diagonal; a radial direction has a component of at most r)
    r = g.post_diameter_mm / 2
    housing = housing - _diag_cylinder(r, -(H - r - 1.0) * _SQ3, post_collar_end_s_mm(g, ss) - 1)
    housing = housing - _set_screw_drill(g, ss) - _lid_screw_holes(g) - _leg_screw_holes(g)
    # split at the inner face of the +z wall: an open box and a lid (the flotor goes in from above)
    body, lid = _split_z(housing, H, 2 * Ho)
    out["housing_body"] = (body, "housing")
    out["housing_lid"] = (lid, "housing")
    return out


def _core(g: PowerMouseGeometry):
    """The iron core: a cube faced across both diagonal corners at
    :attr:`PowerMouseGeometry.core_flat_s_mm` (the post's seat at (-,-,-), clearance for the
    handle boss at (+,+,+)), tapped at (-,-,-) for the post's tip (drilled the full thread
    + the tap lead-out deep)."""
    import build123d as bd

    c, f = g.core_half_mm, g.core_flat_s_mm
    big = _SQ2 * (c * _SQ3 - f) + 1.0  # covers the corner's triangular section
    core = bd.Box(2 * c, 2 * c, 2 * c)
    for sgn in (-1.0, 1.0):
        core = core - _diag_cylinder(big, sgn * f, sgn * (c * _SQ3 + 1.0))
    depth = post_plan(g)["tip"]["depth_mm"] + TAP_LEADOUT_MM
    return core - _diag_cylinder(tap_drill_mm(POST_THREAD) / 2, -f - 1.0, -f + depth)


def _post(g: PowerMouseGeometry, set_screw: str):
    """The stator post: turned tip (tap-drill diameter) into the core, shoulder on the
    core's flat, round body out through the housing to the collar's end."""
    f = g.core_flat_s_mm
    body = _diag_cylinder(g.post_diameter_mm / 2, -f, post_collar_end_s_mm(g, set_screw))
    return body + _diag_cylinder(tap_drill_mm(POST_THREAD) / 2, -f, -f + g.post_thread_mm)


def _set_screw_drill(g: PowerMouseGeometry, size: str):
    """Tap drill of the post set screw: radial, from the post's axis out through the collar."""
    import build123d as bd


    T = post_set_screw_tf(g, size)
    r, R = g.post_diameter_mm / 2, g.post_collar_radius_mm
    loc = bd.Location(bd.Plane(origin=tuple(T[:3, 3] - r * T[:3, 2]), x_dir=tuple(T[:3, 0]),
                               z_dir=tuple(T[:3, 2])))
    return loc * bd.Cylinder(tap_drill_mm(size) / 2, R + 1.0,
                             align=(bd.Align.CENTER, bd.Align.CENTER, bd.Align.MIN))


@dataclass(frozen=True)
class Clearances:
    """Minimum flotor-stator distance over groups of poses (mm) and the worst pose of each.

    translation_mm: over the 26 extreme translations (no rotation);
    rotation_mm: over +-range rotations about 13 axes (no translation);
    combined_mm: over the combined poses (labels ``c:...``, :func:`combined_poses`), nan
    when none was checked;
    nominal_mm: at the centre; ``poses``: label -> (clearance_mm, "flotor part/stator part").
    A negative value is an overlap (minus the cube root of the common volume, mm).
    """

    nominal_mm: float
    translation_mm: float
    rotation_mm: float
    worst_translation: str
    worst_rotation: str
    poses: dict
    combined_mm: float = math.nan
    worst_combined: str = ""

    @property
    def minimum_mm(self) -> float:
        """Smallest clearance over every group that was checked (nan groups skipped), mm."""
        return min(x for x in (self.nominal_mm, self.translation_mm, self.rotation_mm,
                               self.combined_mm) if x == x)


def cavities(g: PowerMouseGeometry) -> dict[str, tuple]:
    """Boxes ((2, 3), flotor frame, mm) that the shells leave empty: the flotor lid's and the
    housing's inner cubes (the split into box and lid does not fill them). The flotor body
    has none: its handle boss stands inside its inner cube."""
    f = g.flotor_edge_mm / 2 - g.coil_width_mm
    h = g.housing_inner_half_mm
    cube = lambda r: (np.array([[-r, -r, -r], [r, r, r]]),)  # noqa: E731
    return {
        "flotor_lid": cube(f),
        "housing_body": cube(h),
        "housing_lid": cube(h),
    }


def motion_clearances(
    g: PowerMouseGeometry,
    range_mm: float,
    range_deg: float,
    flotor=None,
    stator=None,
    poses=None,
    mesh_tol_mm: float = 0.05,
) -> Clearances:
    """Flotor-to-stator distance at the extreme poses of the motion range, fast pass then exact.

    poses: list of (label, R, t_mm) (default :func:`cad.actuators.powermouse.workspace_poses`).
    flotor, stator: ``{name: (solid, role)}`` placed in the flotor frame, or
    ``{name: (solid in its part frame, role, tf 4x4)}`` (tight part boxes: faster).
    Mesh distances (python-fcl) at every pose; exact OCCT (BRepExtrema, and the boolean
    common at contact) only within 2 mesh_tol_mm + 0.05 mm of contact and at the closest
    pose of the translations, of the rotations and at the centre
    (:func:`cad.assembly.interference.pose_clearances`). Touching (distance 0) at the range limit
    counts as 0 when the solids do not overlap (common volume < 1e-6 mm^3); an overlap gives
    a negative clearance.
    """
    fl = flotor_solids(g) if flotor is None else flotor
    st = stator_solids(g) if stator is None else stator

    def topo(s):
        return getattr(s, "wrapped", s)

    todo = pm.workspace_poses(range_mm, range_deg) if poses is None else poses
    voids = cavities(g)
    tfs = [("centre", np.eye(4))]
    for label, R, t in todo:
        T = np.eye(4)
        T[:3, :3], T[:3, 3] = R, t
        tfs.append((label, T))
    res = pose_clearances(
        [
            (k, topo(v[0]), v[2] if len(v) > 2 else np.eye(4), voids.get(k, ()))
            for k, v in fl.items()
        ],
        [
            (k, topo(v[0]), v[2] if len(v) > 2 else np.eye(4), voids.get(k, ()))
            for k, v in st.items()
        ],
        tfs,
        mesh_tol_mm=mesh_tol_mm,
    )
    nominal = res.pop("centre")[0]
    res = {k: (v[0], v[1]) for k, v in res.items()}
    tr = {k: v[0] for k, v in res.items() if k.startswith("t")}
    ro = {k: v[0] for k, v in res.items() if k.startswith("r")}
    co = {k: v[0] for k, v in res.items() if k.startswith("c")}
    wt = min(tr, key=tr.get) if tr else ""
    wr = min(ro, key=ro.get) if ro else ""
    wc = min(co, key=co.get) if co else ""
    return Clearances(nominal, tr[wt] if tr else math.nan, ro[wr] if ro else math.nan, wt, wr,
                      res, co[wc] if co else math.nan, wc)
