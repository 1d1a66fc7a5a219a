"""Where a capstan transmission's parts sit: the rope's tangent points, the drum's arc in the
link's frame, the centre-distance check and the closed-form masses of the drum sector and the
capstan (issue 35). Pure numpy (no CAD import); the solids are :mod:`cad.parts.capstan`.

Frames and units: mm and degrees at the edges, radians inside. The drum turns about its own
centre (the joint, e.g. the four-bar's A1) with the link; ``alpha`` is the world direction from
the drum's centre to the capstan's. Pitch circles: the rope's centre line runs on the drum's
and the capstan's pitch diameters (the design's ``drum_diameter_mm`` and
``capstan_diameter_mm``, so the ratio n = d_d / d_c holds exactly); the drawn rims are one rope
diameter smaller (:func:`rim_radius_mm`).

Rope path (an open belt, both runs outside): each free run leaves the drum at one of the two
external tangent points of the pitch circles, at world angles ``alpha +- gamma`` on the drum,
``cos gamma = (r_d - r_c) / C`` (:func:`external_tangent_points_mm`); on the drum the rope runs
from each tangent point away from the capstan to its anchor. Over the joint's range
``[q_min, q_max]`` a tangent point travels the range on the drum, so the drum arc in the link's
frame spans ``2 gamma + range + 2 anchor arcs`` (:func:`drum_arc_link_deg`): the arc the model of
:func:`cad.actuators.capstan.drum_sector_needed_deg` gives (range + anchors, the rope's arc)
plus the ``2 gamma`` between the two tangent points that faces the capstan.
"""

from __future__ import annotations

import math

import numpy as np

from cad.errors import DesignError


def rim_radius_mm(pitch_diameter_mm: float, rope_diameter_mm: float) -> float:
    """Radius of a drawn pulley rim whose rope centre line runs on ``pitch_diameter_mm``:
    (d_pitch - d_rope) / 2, mm."""
    return 0.5 * (float(pitch_diameter_mm) - float(rope_diameter_mm))


def check_centre_distance(centre_distance_mm: float, capstan_diameter_mm: float,
                          drum_diameter_mm: float, rope_diameter_mm: float,
                          clearance_mm: float,
                          field: str = "transmission.centre_distance_mm") -> float:
    """``centre_distance_mm`` when the two rims stand at least ``clearance_mm`` apart with the
    rope between them: C >= r_d + r_c + clearance (pitch radii: each rim is half a rope inside
    its pitch circle, so the rims' gap is C - r_d - r_c + d_rope). DesignError(field) in one
    line otherwise, naming the value, the rims' overlap or gap and the smallest C."""
    rd, rc = 0.5 * drum_diameter_mm, 0.5 * capstan_diameter_mm
    need = rd + rc + clearance_mm
    if centre_distance_mm >= need - 1e-9:
        return float(centre_distance_mm)
    gap = centre_distance_mm - rd - rc + rope_diameter_mm
    what = (f"the rims overlap by {-gap:.3g} mm" if gap < 0 else
            f"the rims are {gap:.3g} mm apart")
    raise DesignError(field, f"{centre_distance_mm:g} mm between the drum's and the capstan's "
                      f"centres: {what} (drum {drum_diameter_mm:g} mm, capstan "
                      f"{capstan_diameter_mm:g} mm, rope {rope_diameter_mm:g} mm); use at least "
                      f"{need:.2f} mm (r_d + r_c" + (f" + {clearance_mm:g} mm)" if clearance_mm else ")"))


def tangent_half_angle_rad(drum_diameter_mm: float, capstan_diameter_mm: float,
                           centre_distance_mm: float) -> float:
    """gamma = acos((r_d - r_c) / C), rad: the tangent points sit at alpha +- gamma on the drum
    (and on the capstan, same normals)."""
    c = 0.5 * (drum_diameter_mm - capstan_diameter_mm) / centre_distance_mm
    return math.acos(c)


def external_tangent_points_mm(c1_mm, r1_mm: float, c2_mm, r2_mm: float) -> np.ndarray:
    """The two external tangents of circle 1 (centre ``c1_mm`` (2,), radius ``r1_mm``) and
    circle 2, as an array (2, 2, 2): ``[k, 0]`` the point on circle 1, ``[k, 1]`` on circle 2,
    tangent ``k = 0`` on the left of the line c1 -> c2, ``k = 1`` on its right (mm).

    Both points of a tangent share the unit normal n = u cos(gamma) +- u_perp sin(gamma),
    u = (c2 - c1) / |c2 - c1|, cos(gamma) = (r1 - r2) / |c2 - c1|: n . (p2 - p1) = 0.
    ValueError when one circle lies inside the other (|c2 - c1| <= |r1 - r2|)."""
    c1, c2 = np.asarray(c1_mm, float), np.asarray(c2_mm, float)
    d = c2 - c1
    D = float(np.hypot(*d))
    if D <= abs(r1_mm - r2_mm):
        raise ValueError(f"circles of radii {r1_mm:g} and {r2_mm:g} mm {D:g} mm apart have no "
                         "external tangent (one inside the other)")
    u = d / D
    up = np.array([-u[1], u[0]])
    cg = (r1_mm - r2_mm) / D
    sg = math.sqrt(max(0.0, 1.0 - cg * cg))
    out = np.empty((2, 2, 2))
    for k, s in enumerate((1.0, -1.0)):
        n = cg * u + s * sg * up
        out[k, 0], out[k, 1] = c1 + r1_mm * n, c2 + r2_mm * n
    return out


def drum_arc_link_deg(alpha_deg: float, gamma_rad: float, q_min_deg: float, q_max_deg: float,
                      anchor_arc_deg: float) -> tuple[float, float]:
    """(start, span) of the drum's arc in the link's frame, deg (counter-clockwise from start):
    the left tangent point (world alpha + gamma) is at alpha + gamma - q in the link frame, its
    anchor beyond it at q = q_min; the right one (alpha - gamma) at alpha - gamma - q, its anchor
    beyond it at q = q_max; each anchor takes ``anchor_arc_deg``. Span =
    2 gamma + (q_max - q_min) + 2 anchor arcs."""
    g = math.degrees(gamma_rad)
    start = alpha_deg - g - q_max_deg - anchor_arc_deg
    end = alpha_deg + g - q_min_deg + anchor_arc_deg
    return start, end - start


def anchor_angles_link_deg(alpha_deg: float, gamma_rad: float, q_min_deg: float,
                           q_max_deg: float, anchor_arc_deg: float) -> tuple[float, float]:
    """Link-frame angles (deg) of the two anchors' centres: half an anchor arc beyond each
    tangent point's extreme position (:func:`drum_arc_link_deg`)."""
    g = math.degrees(gamma_rad)
    return (alpha_deg + g - q_min_deg + 0.5 * anchor_arc_deg,
            alpha_deg - g - q_max_deg - 0.5 * anchor_arc_deg)


#: Axial pitch of the rope's turns in the capstan's helical groove, in rope diameters (turns
#: side by side with a gap), and the capstan's length beyond its turns (set-screw hub), mm.
GROOVE_PITCH_D = 1.5
CAPSTAN_HUB_MM = 8.0
#: The capstan's material (turned steel): its solid's (:mod:`cad.parts.capstan`) and the
#: closed-form inertia's (:func:`capstan_izz_kg_m2`).
CAPSTAN_MATERIAL = "steel-1018"


#: Rope groove depth below the crests, in rope diameters: our choice in the 0.3-0.4 d of
#: usual capstan practice (deep enough to guide the turns, shallow enough that turns side by
#: side at :data:`GROOVE_PITCH_D` leave a crest between them). The groove's profile is a
#: circle of the rope's radius centred on the pitch circle, so its bottom is the drawn rim of
#: :func:`rim_radius_mm` (the rope's centre line stays on the pitch diameter: the ratio is
#: unchanged) and the crests stand ``GROOVE_DEPTH_D d`` above it.
GROOVE_DEPTH_D = 0.35


def groove_depth_mm(rope_diameter_mm: float) -> float:
    """Depth of the rope groove below the crests, :data:`GROOVE_DEPTH_D` d (mm)."""
    return GROOVE_DEPTH_D * float(rope_diameter_mm)


def crest_radius_mm(pitch_diameter_mm: float, rope_diameter_mm: float) -> float:
    """Outer radius of a grooved pulley: the groove bottom (:func:`rim_radius_mm`) plus the
    groove depth (mm)."""
    return rim_radius_mm(pitch_diameter_mm, rope_diameter_mm) + groove_depth_mm(rope_diameter_mm)


def groove_section_mm(pitch_diameter_mm: float, rope_diameter_mm: float) -> tuple[float, float]:
    """(area mm^2, centroid radius mm) of the groove's cross-section: the circular segment of
    the rope-radius circle (centre on the pitch circle) inside the crest radius, height
    h = :func:`groove_depth_mm`. Segment of half-angle a, cos a = (r - h) / r:
    A = r^2 (a - sin a cos a), its centroid 4 r sin^3 a / (3 (2a - sin 2a)) from the circle's
    centre towards the axis."""
    r, h = 0.5 * float(rope_diameter_mm), groove_depth_mm(rope_diameter_mm)
    a = math.acos((r - h) / r)
    area = r * r * (a - math.sin(a) * math.cos(a))
    ybar = 4.0 * r * math.sin(a) ** 3 / (3.0 * (2.0 * a - math.sin(2.0 * a)))
    return area, 0.5 * float(pitch_diameter_mm) - ybar


def ring_groove_volume_mm3(pitch_diameter_mm: float, rope_diameter_mm: float, span_deg: float) -> float:
    """Volume of a plain rope groove round ``span_deg`` of a drum (mm^3): Pappus, the section's
    area times the path of its centroid (:func:`groove_section_mm`)."""
    area, rbar = groove_section_mm(pitch_diameter_mm, rope_diameter_mm)
    return area * rbar * math.radians(span_deg)


def helix_groove_volume_mm3(pitch_diameter_mm: float, rope_diameter_mm: float, wraps: float) -> float:
    """Volume of the capstan's helical groove (mm^3): the section's area times the length of
    the helix its centroid runs on, ``wraps`` turns of radius r_bar at the axial pitch
    :data:`GROOVE_PITCH_D` d, wraps sqrt((2 pi r_bar)^2 + p^2) (the section swept normal to the
    helix; exact up to the twist of a section small against r_bar)."""
    area, rbar = groove_section_mm(pitch_diameter_mm, rope_diameter_mm)
    p = GROOVE_PITCH_D * float(rope_diameter_mm)
    return area * wraps * math.hypot(2.0 * math.pi * rbar, p)


def capstan_length_mm(rope_diameter_mm: float, wraps: float) -> float:
    """The capstan's length (mm): its turns at :data:`GROOVE_PITCH_D` rope diameters each and
    the set-screw hub :data:`CAPSTAN_HUB_MM`."""
    return GROOVE_PITCH_D * rope_diameter_mm * wraps + CAPSTAN_HUB_MM


def groove_section_moment(pitch_diameter_mm: float, rope_diameter_mm: float, k: int) -> float:
    """Integral of r^k over the groove's section (mm^(2+k)), r the distance from the pulley's
    axis (the segment of :func:`groove_section_mm`): with u = -rho cos(phi) from the section
    circle's centre (radius rho = d / 2, phi from 0 at the groove's bottom to a at the crest),
    the chord 2 rho sin(phi): int_0^a (r_p - rho cos phi)^k 2 rho^2 sin^2(phi) dphi, by 64-point
    Gauss-Legendre (a polynomial in cos, sin: exact to rounding)."""
    rho, h = 0.5 * float(rope_diameter_mm), groove_depth_mm(rope_diameter_mm)
    a = math.acos((rho - h) / rho)
    x, w = np.polynomial.legendre.leggauss(64)
    phi = 0.5 * a * (x + 1.0)
    f = (0.5 * float(pitch_diameter_mm) - rho * np.cos(phi)) ** k * 2.0 * rho * rho * np.sin(phi) ** 2
    return float(0.5 * a * np.sum(w * f))


def capstan_izz_kg_m2(capstan_diameter_mm: float, rope_diameter_mm: float, wraps: float,
                      bore_mm: float, density_kg_m3: float) -> float:
    """The capstan's inertia about the motor shaft (kg m^2): a tube from the bore to the crests
    (:func:`crest_radius_mm`), :func:`capstan_length_mm` long, m (r_o^2 + r_i^2) / 2, less its
    helical rope groove (:mod:`cad.parts.capstan`): rho times the groove section's int r^3 dA
    (:func:`groove_section_moment`) swept round ``wraps`` turns, 2 pi wraps, stretched along the
    helix by sqrt(1 + (p / (2 pi r_bar))^2) (r_bar the section's centroid radius, p the axial
    pitch); its set-screw hole (a few mm^3) left out. The reflected motor-side inertia at the
    joint is n^2 (J_rotor + this) (:meth:`cad.device.ResolvedDevice.joint_rotor_inertia_kg_m2`)."""
    ro, ri = crest_radius_mm(capstan_diameter_mm, rope_diameter_mm), bore_mm / 2
    m = tube_mass_kg(ro, ri, capstan_length_mm(rope_diameter_mm, wraps), density_kg_m3)
    _, rbar = groove_section_mm(capstan_diameter_mm, rope_diameter_mm)
    stretch = math.hypot(1.0, GROOVE_PITCH_D * rope_diameter_mm / (2.0 * math.pi * rbar))
    groove = (density_kg_m3 * 1e-15 * 2.0 * math.pi * wraps * stretch
              * groove_section_moment(capstan_diameter_mm, rope_diameter_mm, 3))
    return tube_izz_kg_m2(m, ro, ri) - groove


def sector_mass_kg(span_deg: float, r_out_mm: float, r_in_mm: float, thickness_mm: float,
                   density_kg_m3: float) -> float:
    """Mass of an annular sector plate: (theta / 2)(r_o^2 - r_i^2) t rho, kg (theta in rad)."""
    a = 0.5 * math.radians(span_deg) * (r_out_mm ** 2 - r_in_mm ** 2)
    return a * thickness_mm * 1e-9 * density_kg_m3


def tube_mass_kg(r_out_mm: float, r_in_mm: float, length_mm: float, density_kg_m3: float) -> float:
    """Mass of a tube (the capstan without its set-screw hole): pi (r_o^2 - r_i^2) L rho, kg."""
    return math.pi * (r_out_mm ** 2 - r_in_mm ** 2) * length_mm * 1e-9 * density_kg_m3


def tube_izz_kg_m2(mass_kg: float, r_out_mm: float, r_in_mm: float) -> float:
    """A tube's inertia about its own axis: m (r_o^2 + r_i^2) / 2, kg m^2."""
    return 0.5 * mass_kg * (r_out_mm ** 2 + r_in_mm ** 2) * 1e-6
