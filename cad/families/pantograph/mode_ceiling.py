"""What limits the first structural mode of a planar pantograph (5-bar, haptic mouse), and the
best figure its link tubes can reach inside the build's rules (issue 32: the bundled 5-bar
sits at ~33 Hz against the 150 Hz limit; a user must learn what blocks it and by how much).

The chain of rules, each the build's own (the first that binds is named):

* a link tube sits in its clevises with 1 mm walls: ``tube_od_mm + 2 <= clevis_height_mm``
  and ``<= clevis_width_mm`` (:func:`cad.design.pantograph.parse_parts`; the width can grow
  with the tube, the height is bound by the motor shaft:)
* the hub clevis on the motor shaft holds its set screw at mid-height on the shaft:
  ``clevis_height_mm / 2 + d / 2 <= engaged`` with ``engaged = shaft length - plate -
  mount plate - layer gap`` (:func:`cad.families.pantograph.layout.set_screw_plan`), so
  ``clevis_height_mm <= 2 engaged - d``.

At the largest tube these allow, the search tries each tube material with elastic data
(:data:`TUBE_MATERIALS`) and wall (:data:`WALLS_MM`) on the structure model of the datasheet
(:func:`cad.structure.pantograph.first_modes`: beams joint to joint, motors held) with the
build's body masses, each body's tube mass exchanged for the candidate's at the tube's centre
(an estimate: the clevises' own mass change with the socket bore is left out; say so).
Then the tube diameter the limit needs, by bisection with the best material and wall, the
clevis rules set aside. No CAD import.
"""

from __future__ import annotations

import copy
import dataclasses

from cad.data.catalog import get_motor, thread_diameter_mm
from cad.families.pantograph.capstan import is_capstan
from cad.families.pantograph.layout import set_screw_plan
from cad.structure.pantograph import first_modes, pose_frames, tube_mass_kg

#: Tube materials searched (with elastic data in :mod:`cad.structure.elastic`).
TUBE_MATERIALS = ("carbon-fibre", "aluminium-7075", "titanium-6al4v")
#: Tube walls searched (mm).
WALLS_MM = (0.5, 1.0, 2.0)
#: Clevis walls around a tube (mm), the build's rule (parse_parts).
CLEVIS_WALL_MM = 1.0
#: Largest tube diameter the "needed" bisection considers (mm) and its resolution (mm).
OD_SEARCH_MAX_MM = 80.0
OD_SEARCH_STEP_MM = 0.25


def _rebased(design0, design, bodies: dict) -> dict:
    """``bodies`` of ``design0``'s build with each link's tube mass replaced by ``design``'s
    (same link lengths), placed at the tube's centre (L / 2 in the link frame)."""
    out = copy.deepcopy(bodies)
    for name, b in out.items():
        kind = next((k for k in ("proximal", "distal") if f"{k}_" in name), None)
        if kind is None or not isinstance(b, dict) or "mass_kg" not in b:
            continue
        L = float(design.params[f"{kind}_mm"])
        dm = tube_mass_kg(design, L) - tube_mass_kg(design0, L)
        m, com = float(b["mass_kg"]), list(b["com_mm"])
        com[0] = (m * com[0] + dm * L / 2) / (m + dm)
        b["mass_kg"], b["com_mm"] = m + dm, com
    return out


def clevis_height_max_mm(design) -> float:
    """Largest ``clevis_height_mm`` the motor shaft allows (module docstring), mm. A 5-bar with
    capstans: its hub clevis sits on the link's own axle, cut to length, so the shaft sets no
    bound: the design's own clevis height (the tubes it holds are searched, not larger ones)."""
    p = design.parts
    if is_capstan(design):
        return p.clevis_height_mm
    m = get_motor(p.motor)
    engaged = m.shaft_length_mm - p.plate_thickness_mm - p.motor_mount_thickness_mm - p.layer_gap_mm
    return 2 * engaged - thread_diameter_mm(set_screw_plan(design)["size"])


def _with_tube(design, od: float, wall: float, material: str):
    parts = dataclasses.replace(design.parts, tube_od_mm=od, tube_id_mm=od - 2 * wall, tube_material=material)
    return dataclasses.replace(design, parts=parts)


def mode_ceiling(design, bodies: dict, web_width_mm: float, limit_Hz: float) -> dict:
    """The best first mode the link tubes reach inside the build's rules and what it takes
    to reach ``limit_Hz`` (module docstring).

    bodies: the build's ``report["bodies"]``. Returns ``now`` (:func:`first_modes` of the
    design), ``clevis_height_max_mm``, ``tube_od_max_mm``, ``best`` (``first_mode_Hz``,
    ``plane``, ``tube_od_mm``, ``tube_id_mm``, ``tube_material``), ``od_needed_mm`` (None
    when even :data:`OD_SEARCH_MAX_MM` falls short) and ``text``: one line for a reader."""
    frames = pose_frames(design)
    now = first_modes(design, bodies, web_width_mm, frames)
    h_max = clevis_height_max_mm(design)
    od_max = h_max - 2 * CLEVIS_WALL_MM

    def mode(od, wall, mat):
        d = _with_tube(design, od, wall, mat)
        return first_modes(d, _rebased(design, d, bodies), web_width_mm, frames)

    cands = [(mode(od_max, w, mat), w, mat) for mat in TUBE_MATERIALS for w in WALLS_MM if 2 * w < od_max]
    top, wall, mat = max(cands, key=lambda c: c[0]["first_mode_Hz"])
    lo, hi, need = od_max, OD_SEARCH_MAX_MM, None
    if top["first_mode_Hz"] < limit_Hz and mode(hi, wall, mat)["first_mode_Hz"] >= limit_Hz:
        while hi - lo > OD_SEARCH_STEP_MM:  # the mode grows with the tube diameter here
            mid = 0.5 * (lo + hi)
            lo, hi = (lo, mid) if mode(mid, wall, mat)["first_mode_Hz"] >= limit_Hz else (mid, hi)
        need = hi
    best = {"first_mode_Hz": top["first_mode_Hz"], "plane": top["plane"], "tube_od_mm": od_max,
            "tube_id_mm": od_max - 2 * wall, "tube_material": mat}
    out = {"now": now, "clevis_height_max_mm": h_max, "tube_od_max_mm": od_max, "best": best,
           "od_needed_mm": need, "limit_Hz": float(limit_Hz)}
    out["text"] = _text(design, out)
    return out


def _text(design, c: dict) -> str:
    p, b, now = design.parts, c["best"], c["now"]
    head = (f"first mode {now['first_mode_Hz']:.1f} Hz: {now['plane']} bending of the link tubes "
            f"({p.tube_od_mm:g}/{p.tube_id_mm:g} mm {p.tube_material}, motors held, at {now['pose']})")
    bound = (f"clevis_height_mm <= {c['clevis_height_max_mm']:g} mm, where the {p.motor} shaft still carries "
             "the hub's set screw" if not is_capstan(design) else
             f"clevis_height_mm = {p.clevis_height_mm:g} mm as designed (the hubs sit on the links' axles: a "
             "taller clevis takes a larger tube)")
    reach = (f"best the tubes reach in this layout ~{b['first_mode_Hz']:.0f} Hz ({b['plane']}; "
             f"{b['tube_od_mm']:g}/{b['tube_id_mm']:g} mm {b['tube_material']}: tube_od_mm <= "
             f"clevis_height_mm - 2 and {bound}; estimate, the build's clevis masses kept)")
    if b["first_mode_Hz"] >= c["limit_Hz"]:
        return f"{head}; {reach}: {c['limit_Hz']:g} Hz is reachable"
    if c["od_needed_mm"] is None:
        return f"{head}; {reach}; {c['limit_Hz']:g} Hz is out of reach of any tube up to {OD_SEARCH_MAX_MM:g} mm"
    fix = "a taller clevis or shorter links" if is_capstan(design) else (
        "a longer motor shaft, thinner plates, or shorter links")
    return (f"{head}; {reach}; {c['limit_Hz']:g} Hz needs tube_od_mm ~{c['od_needed_mm']:.1f} mm, so "
            f"clevis_height_mm >= {c['od_needed_mm'] + 2 * CLEVIS_WALL_MM:.1f} mm: {fix}")
