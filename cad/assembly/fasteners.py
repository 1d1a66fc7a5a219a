"""Fasteners sized from what they clamp, and the tapped holes they engage (issue 10).

A screw's length comes from its stack: ``L = clamp + engagement`` with ``L`` a catalog
length (ISO 4762 / ISO 7379 lists of bd_warehouse) and the engagement in its tapped hole
between the hole's stated minimum and the hole's usable depth:

* holes we tap in aluminium (post, legs, hub, base plate, coupler at P): minimum
  :data:`MIN_ENGAGEMENT_ALU_D` x d (1.5 d, the usual rule for steel screws in aluminium
  alloys -- the internal thread strips before the screw below it);
* holes of a bought part (the motor face): the maker's depth, minimum
  :data:`MIN_ENGAGEMENT_BOUGHT_MM` mm.

A stack with no catalog length in the window is a :class:`cad.errors.DesignError`
naming the joint; :func:`check_fasteners` refuses two fasteners in one hole and an
engagement outside its window (a layout bug, never silently exported).

Every fastener instance carries a :class:`Fastener` record: thread size, length, what it
clamps, which hole it engages, the engagement (reported in ``report.json`` under
``fasteners``).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

from cad.errors import DesignError
from cad.parts import catalog

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
    usable (full-thread) depth and the minimum engagement it needs (mm)."""

    name: str
    part: str
    size: str
    depth_mm: float
    min_engagement_mm: float


@dataclass(frozen=True)
class Fastener:
    """What a fastener instance is: ``kind`` (standard), thread ``size``, ``length_mm``
    (under-head to tip; shoulder length for ISO 7379), the parts it ``clamps`` (head side
    first), the ``hole`` it engages (a :class:`TappedHole` name; a nut is one too) and the
    thread ``engagement_mm`` there."""

    kind: str
    size: str
    length_mm: float
    clamps: tuple[str, ...]
    hole: str
    engagement_mm: float

    def as_dict(self) -> dict:
        d = asdict(self)
        d["clamps"] = list(self.clamps)
        return d


def alu_hole(name: str, part: str, size: str, depth_mm: float) -> TappedHole:
    """A hole tapped in aluminium: minimum engagement 1.5 d."""
    d = catalog.thread_diameter_mm(size)
    return TappedHole(name, part, size, depth_mm, MIN_ENGAGEMENT_ALU_D * d)


def size_cap_screw(
    size: str, clamp_mm: float, hole: TappedHole, joint: str, field: str
) -> tuple[float, float]:
    """(catalog length, engagement) of the shortest ISO 4762 screw clamping ``clamp_mm`` with an
    engagement in ``[hole.min_engagement_mm, hole.depth_mm]``; DesignError naming ``joint``."""
    cs = catalog.get_cap_screw(size, field)
    lo, hi = clamp_mm + hole.min_engagement_mm, clamp_mm + hole.depth_mm
    L = catalog.shortest_length(cs.lengths_mm, lo)
    if L is None or L > hi + 1e-9:
        raise DesignError(
            field,
            f"{joint}: no {size} x L screw (catalog {', '.join(f'{x:g}' for x in cs.lengths_mm)}) "
            f"clamps {clamp_mm:g} mm with {hole.min_engagement_mm:g}..{hole.depth_mm:g} mm of thread "
            f"in {hole.name} (need L in {lo:g}..{hi:g} mm)",
        )
    return L, L - clamp_mm


def check_fasteners(fasteners: dict[str, Fastener], holes: dict[str, TappedHole]) -> None:
    """Every tapped hole holds at most one fastener, every engagement lies in its hole's window
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
        f"{MIN_ENGAGEMENT_ALU_D * small.d_mm:g} mm, catalog lengths from {small.lengths_mm[0]:g} mm)",
    )
