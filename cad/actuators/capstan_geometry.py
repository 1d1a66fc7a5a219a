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


def capstan_length_mm(rope_diameter_mm: float, wraps: float) -> float:
    """The capstan's length (mm): its turns at :data:`GROOVE_PITCH_D` rope diameters each and
    the set-screw hub :data:`CAPSTAN_HUB_MM`."""
    return GROOVE_PITCH_D * rope_diameter_mm * wraps + CAPSTAN_HUB_MM


def capstan_izz_kg_m2(capstan_diameter_mm: float, rope_diameter_mm: float, wraps: float,
                      bore_mm: float, density_kg_m3: float) -> float:
    """The capstan's inertia about the motor shaft (kg m^2): a tube from the bore to the rim
    (:func:`rim_radius_mm`), :func:`capstan_length_mm` long, m (r_o^2 + r_i^2) / 2; its
    set-screw hole (a few mm^3) left out. The reflected motor-side inertia at the joint is
    n^2 (J_rotor + this) (:meth:`cad.device.ResolvedDevice.joint_rotor_inertia_kg_m2`)."""
    ro, ri = rim_radius_mm(capstan_diameter_mm, rope_diameter_mm), bore_mm / 2
    m = tube_mass_kg(ro, ri, capstan_length_mm(rope_diameter_mm, wraps), density_kg_m3)
    return tube_izz_kg_m2(m, ro, ri)


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
