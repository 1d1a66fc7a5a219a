"""Fasteners sized from what they clamp, and the tapped holes they engage (issue 10).

A screw's length comes from its stack: ``L = clamp + engagement`` with ``L`` a catalog
length (ISO 4762 / ISO 7379 lists of bd_warehouse) and the engagement in its tapped hole
between the hole's stated minimum and the hole's usable depth:

* holes we tap in aluminium (post, legs, hub, base plate, coupler at P): minimum
  :data:`MIN_ENGAGEMENT_ALU_D` x d (1.5 d, the usual rule for steel screws in aluminium
  alloys -- the internal thread strips before the screw below it);
* holes of a bought part (the motor face): the maker's depth, minimum
  :data:`MIN_ENGAGEMENT_BOUGHT_MM` mm;
* the ISO 7379 shoulder screw's hole in the A4 post: its whole thread, b - g2
  (:func:`shoulder_screw_hole`).

A stack with no catalog length in the window is a :class:`cad.errors.DesignError`
naming the joint; :func:`check_fasteners` refuses two fasteners in one hole and an
engagement outside its window (a layout bug, never silently exported).

Every fastener instance carries a :class:`Fastener` record: thread size, length, what it
clamps, which hole it engages, the engagement (reported in ``report.json`` under
``fasteners``).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

from cad.data import catalog
from cad.errors import DesignError

#: Minimum thread engagement in a tapped aluminium hole, in thread diameters.
MIN_ENGAGEMENT_ALU_D = 1.5
#: Minimum engagement in a bought part's tapped hole (mm): the maker's hole is short
#: (3.5 mm on the maxon flange), so the rule there is "most of it".
MIN_ENGAGEMENT_BOUGHT_MM = 2.5
#: A tapped hole is drilled this much deeper than its full thread (mm, tap lead-out).
TAP_LEADOUT_MM = 1.0


@dataclass(frozen=True)
class TappedHole:
    """A tapped hole: ``name`` (unique, e.g. ``post_A4:top``), the part it is in, thread size,
    usable (full-thread) depth and the minimum engagement it needs (mm).

    axis, point_mm : where the hole is, in the part's own frame (the frame of its kind's
    shape): the axis direction (unit, either sense) and one point on the axis (mm); None
    when the builder does not state it. A shop drawing matches the hole found on the solid
    to its record by them (:func:`cad.export.drawings.notes.callout`)."""

    name: str
    part: str
    size: str
    depth_mm: float
    min_engagement_mm: float
    axis: tuple[float, float, float] | None = None
    point_mm: tuple[float, float, float] | None = None

    def report(self) -> dict:
        """The record for report.json: every field, the place only when it is stated."""
        return {k: (list(v) if isinstance(v, tuple) else v)
                for k, v in self.__dict__.items() if v is not None}


@dataclass(frozen=True)
class Fastener:
    """What a fastener instance is: ``kind`` (standard), thread ``size``, ``length_mm``
    (under-head to tip; shoulder length for ISO 7379), the parts it ``clamps`` (head side
    first), the ``hole`` it engages (a :class:`TappedHole` name; a nut is one too) and the
    thread ``engagement_mm`` there; ``fitted``: the bought parts fitted on the fastener itself
    (a plain pin's upper retaining ring, its "head"), placed with it."""

    kind: str
    size: str
    length_mm: float
    clamps: tuple[str, ...]
    hole: str
    engagement_mm: float
    fitted: tuple[str, ...] = ()

    def as_dict(self) -> dict:
        d = asdict(self)
        d["clamps"] = list(self.clamps)
        if self.fitted:
            d["fitted"] = list(self.fitted)
        else:
            d.pop("fitted")
        return d


def alu_hole(name: str, part: str, size: str, depth_mm: float) -> TappedHole:
    """A hole tapped in aluminium: minimum engagement 1.5 d."""
    d = catalog.thread_diameter_mm(size)
    return TappedHole(name, part, size, depth_mm, MIN_ENGAGEMENT_ALU_D * d)


def iso7379_thread_mm(size: str) -> float:
    """Length of full thread of an ISO 7379 shoulder screw (mm): b - g2, bd_warehouse's
    ``shoulder_screw.csv`` (b, the length below the shoulder, includes the thread relief g2;
    M6: 11 - 2.5 = 8.5 mm). A plain pin (``dowel-<d>``) has none: 0."""
    if catalog.is_dowel(size):
        return 0.0
    s = catalog.get_shoulder_screw(size)
    return s.b_mm - s.g2_mm


def shoulder_screw_hole(name: str, part: str, size: str, depth_mm: float) -> TappedHole:
    """The A4 post's tapped hole for an ISO 7379 shoulder screw; minimum engagement = the
    screw's whole thread, b - g2 (:func:`iso7379_thread_mm`).

    Basis: ISO 7379 fixes the thread length, and it is shorter than the 1.5 d rule for a cap
    screw in aluminium (M6: 8.5 mm = 1.42 d; M8: 9.9 mm = 1.24 d), so that rule would refuse
    every ISO 7379 screw in an aluminium post. The shoulder screw carries the joint's load
    on its ground shoulder in the reamed bore; its thread only holds the axial preload that
    clamps the stack, and the makers' tightening torques for shoulder screws are well below a
    cap screw's of the same thread (the neck at the relief is the weak section). So the rule
    is the one the standard leaves: every turn of the thread engaged -- the reamed bore ends
    where the relief ends (:func:`cad.families.fourbar.layers.post_bore_depth_mm`) and the hole is
    tapped deeper than the tip. For a joint preloaded to the screw's proof load use a steel
    post (``parts.post_material``) or a thread insert."""
    return TappedHole(name, part, size, depth_mm, iso7379_thread_mm(size))


def size_cap_screw(
    size: str, clamp_mm: float, hole: TappedHole, joint: str, field: str,
    hole_field: str | None = None, clamp_field: str | None = None,
) -> tuple[float, float]:
    """(catalog length, engagement) of the shortest ISO 4762 screw clamping ``clamp_mm`` with an
    engagement in ``[hole.min_engagement_mm, hole.depth_mm]`` (a hole of unbounded depth:
    ``depth_mm = inf``). DesignError naming ``joint`` and the field to change:

    * ``hole_field`` (the field setting the tapped part's depth, e.g. the base plate's
      thickness) when the hole is shallower than its minimum engagement, whatever the screw;
    * ``clamp_field`` (the field whose value is ``clamp_mm``) when even the longest catalog
      screw cannot clamp ``clamp_mm`` with the minimum engagement, or the shortest one that
      can runs deeper than the hole;
    * ``field`` (the screw's size) otherwise, and for the cases above when not given.
    """
    cs = catalog.get_cap_screw(size, field)
    thread = size.split("-")[0]
    if hole.depth_mm < hole.min_engagement_mm - 1e-9:
        raise DesignError(
            hole_field or field,
            f"{joint}: {hole.name} holds only {hole.depth_mm:g} mm of {thread} thread, less "
            f"than its {hole.min_engagement_mm:g} mm minimum engagement",
        )
    lo, hi = clamp_mm + hole.min_engagement_mm, clamp_mm + hole.depth_mm
    L = catalog.shortest_length(cs.lengths_mm, lo)
    if L is None and clamp_field is not None:
        raise DesignError(
            clamp_field,
            f"{clamp_mm:g} mm: {joint}: the longest {thread} ISO 4762 screw "
            f"({cs.lengths_mm[-1]:g} mm) cannot clamp {clamp_mm:g} mm and engage "
            f"{hole.min_engagement_mm:g} mm of thread in {hole.name} (needs L >= {lo:g} mm)",
        )
    if L is not None and L > hi + 1e-9 and clamp_field is not None:
        raise DesignError(
            clamp_field,
            f"{clamp_mm:g} mm: {joint}: the shortest {thread} ISO 4762 screw long enough "
            f"({L:g} mm) would run {L - clamp_mm:g} mm into {hole.name}, deeper than its "
            f"{hole.depth_mm:g} mm of thread (change it or {field})",
        )
    if L is None or L > hi + 1e-9:
        raise DesignError(
            field,
            f"{joint}: no {size} x L screw (catalog {', '.join(f'{x:g}' for x in cs.lengths_mm)}) "
            f"clamps {clamp_mm:g} mm with {_window(hole.min_engagement_mm, hole.depth_mm)} of "
            f"thread in {hole.name} (need L {'in ' if hi < float('inf') else ''}{_window(lo, hi)})",
        )
    return L, L - clamp_mm


def _window(lo: float, hi: float) -> str:
    """``"lo..hi mm"``, or ``">= lo mm"`` for an unbounded ``hi``."""
    return f">= {lo:g} mm" if hi == float("inf") else f"{lo:g}..{hi:g} mm"


def check_fasteners(fasteners: dict[str, Fastener], holes: dict[str, TappedHole]) -> None:
    """Every tapped hole holds at most one fastener, every engagement lies in its hole's window
    and an ISO 7379 record claims no more than the screw's thread, b - g2
    (``fasteners``: instance name -> record). Raises DesignError naming the part and hole."""
    used: dict[str, str] = {}
    for name, f in fasteners.items():
        if f.hole in used:
            raise DesignError(
                "parts", f"{name} and {used[f.hole]} both engage {f.hole} (one screw per hole)"
            )
        used[f.hole] = name
        h = holes.get(f.hole)
        if h is None:
            raise DesignError("parts", f"{name} engages {f.hole}, which no part has")
        if not h.min_engagement_mm - 1e-9 <= f.engagement_mm <= h.depth_mm + 1e-9:
            raise DesignError(
                "parts",
                f"{name}: {f.engagement_mm:g} mm of {f.size} thread in {f.hole} "
                f"(window {h.min_engagement_mm:g}..{h.depth_mm:g} mm)",
            )
        if f.kind == "ISO 7379" and f.engagement_mm > iso7379_thread_mm(f.size) + 1e-9:
            raise DesignError(
                "parts",
                f"{name}: {f.engagement_mm:g} mm engaged, but an ISO 7379 {f.size} has only "
                f"{iso7379_thread_mm(f.size):g} mm of thread (b - g2)",
            )



def size_set_screw(
    bore_mm: float, outer_mm: float, sizes: tuple[str, ...], joint: str, field: str
) -> tuple[str, float, float]:
    """(size, catalog length, full-thread depth) of the ISO 4026 set screw tapped radially
    through a round boss (radius ``outer_mm``) onto a shaft (radius ``bore_mm``), point on the
    shaft surface. The boss curves away from the hole: the full thread (its major diameter d
    all round) ends at ``sqrt(outer^2 - (d/2)^2)`` from the shaft axis, so the depth is that
    minus ``bore_mm``; the screw's end (its rim at d/2) must not stand proud of the boss, so
    ``L <= depth`` too, and engagement = L >= 1.5 d. The largest of ``sizes`` with such a
    catalog length, L the longest; DesignError naming ``field`` when none fits."""
    for size in sorted(sizes, key=catalog.thread_diameter_mm, reverse=True):
        ss = catalog.get_set_screw(size, field)
        depth = (outer_mm**2 - (ss.d_mm / 2) ** 2) ** 0.5 - bore_mm
        lo = MIN_ENGAGEMENT_ALU_D * ss.d_mm
        fit = [L for L in ss.lengths_mm if lo - 1e-9 <= L <= depth + 1e-9]
        if fit:
            return size, max(fit), depth
    small = catalog.get_set_screw(min(sizes, key=catalog.thread_diameter_mm), field)
    depth = (outer_mm**2 - (small.d_mm / 2) ** 2) ** 0.5 - bore_mm
    raise DesignError(
        field,
        f"{joint}: a {2 * outer_mm:g} mm wide round end leaves a {outer_mm - bore_mm:g} mm wall "
        f"({depth:.2f} mm of full {small.size.split('-')[0]} thread), less than the smallest "
        f"ISO 4026 set screw {small.size.split('-')[0]} needs (1.5 d = "
        f"{MIN_ENGAGEMENT_ALU_D * small.d_mm:g} mm, catalog lengths from {small.lengths_mm[0]:g} mm); "
        f"a round end of at least {2 * min_boss_radius_mm(bore_mm, sizes):.1f} mm holds one",
    )


def min_boss_radius_mm(bore_mm: float, sizes: tuple[str, ...]) -> float:
    """The smallest radius of a round boss on a shaft of radius ``bore_mm`` that holds the
    smallest of ``sizes`` by :func:`size_set_screw`'s rule: its full thread reaches the shortest
    catalog length L >= 1.5 d, radius sqrt((bore + L)^2 + (d / 2)^2), mm."""
    ss = catalog.get_set_screw(min(sizes, key=catalog.thread_diameter_mm), "")
    L = min(x for x in ss.lengths_mm if x >= MIN_ENGAGEMENT_ALU_D * ss.d_mm - 1e-9)
    return ((bore_mm + L) ** 2 + (ss.d_mm / 2) ** 2) ** 0.5
