"""Fasteners of a laser build held over the sheets' thickness tolerance (issue 25).

Under ``parts.process = "laser"`` the plate parts (bars when ``bar_style = "plate"``, the base
plate, the motor mount) are cut from sheet stock, and a sheet of nominal thickness ``t``
measures anywhere in its band ``[lo, hi]`` (:attr:`cad.data.materials.SheetStock.thickness_range_mm`:
EN 485-4 Table 1 for the aluminium sheets, ISO 7823-1 for cast acrylic, EN 315 limits as a
birch plywood data sheet states them). Sheets are taken independently (two parts may come
from two sheets), each anywhere in its band.

A cap screw of catalog length ``L`` clamping parts of nominal total ``c`` engages
``e = L - c``; with sheets among the clamped parts the clamp spans ``[c_lo, c_hi]`` (each
sheet at its ``lo`` / ``hi``), so ``e`` spans ``[L - c_hi, L - c_lo]``: the thickest sheets
leave the least engagement, the thinnest run the tip deepest. A hole tapped in a sheet is at
most that sheet deep: its usable depth ``d`` drops to ``d - (t - lo)`` in the thinnest sheet.
The screw holds over the band when ``L - c_hi >= min engagement`` and
``L - c_lo <= d_min`` (:func:`size_over_band` picks the shortest catalog length that does;
where none does it keeps the nominal one and warns naming the joint, the sheet, the band and
the keys to change).

ISO 7379 pin stacks (:func:`pin_rows`): the clamp (head spacer, bearing ring, gap spacer) holds
no sheet, but the shoulder ends inside the lower bar with the nut on full thread, a window
that moves with the lower bar's thickness (:func:`cad.families.fourbar.pins.pin_window` at its
``hi`` and ``lo``), and the screw head stands above the upper bar by the head clearance less
what the upper bar's lip grows.

Pure (no CAD import); nothing here acts when ``process != "laser"``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from cad.assembly.fasteners import size_cap_screw
from cad.data import catalog
from cad.data.materials import SHEETS
from cad.design import bounds
from cad.families.fourbar.pins import pin_window

#: The standard (or source) each sheet material's thickness band is from
#: (:data:`cad.data.materials.SHEETS` ``source["thickness_range_mm"]`` gives the full text).
BAND_SOURCE = {"aluminium-5083": "EN 485-4", "aluminium-6061": "EN 485-4",
               "acrylic-cast": "ISO 7823-1", "birch-plywood": "EN 315"}


@dataclass(frozen=True)
class SheetBand:
    """A laser-cut part's sheet: ``part`` (instance name), ``material``, ``nominal_mm`` and
    the band ``lo_mm .. hi_mm`` it may measure, ``key`` the ``[parts]`` field of its thickness."""

    part: str
    material: str
    nominal_mm: float
    lo_mm: float
    hi_mm: float
    key: str

    def text(self) -> str:
        """``"6.5 mm birch-plywood measures 6.1..6.9 mm (EN 315)"``."""
        return (f"{self.nominal_mm:g} mm {self.material} measures {self.lo_mm:g}..{self.hi_mm:g} "
                f"mm ({BAND_SOURCE.get(self.material, 'unverified')})")


def sheet_bands(parts) -> dict[str, SheetBand]:
    """``{part instance name: SheetBand}`` of the laser-cut plate parts of ``parts`` (a
    :class:`cad.design.parts.PartsSpec`); empty unless ``parts.process == "laser"``."""
    if parts.process != "laser":
        return {}

    plates = [("base_plate", parts.base_material, parts.base_thickness_mm, "base_thickness_mm"),
              ("motor_mount", parts.motor_mount_material, parts.motor_mount_thickness_mm,
               "motor_mount_thickness_mm")]
    if parts.bar_style == "plate":
        plates += [(n, parts.bar_material, parts.bar_thickness_mm, "bar_thickness_mm")
                   for n in ("crank", "coupler", "rocker")]
    out = {}
    for name, mat, t, key in plates:
        lo, hi = SHEETS[mat].thickness_range_mm[min(SHEETS[mat].thickness_range_mm,
                                                    key=lambda s, t=t: abs(s - t))]
        out[name] = SheetBand(name, mat, t, lo, hi, f"parts.{key}")
    return out


def thinnest_mm(bands: dict[str, SheetBand], part: str, nominal_mm: float) -> float:
    """The thinnest ``part`` may measure: its band's ``lo``, or ``nominal_mm`` when not a sheet."""
    b = bands.get(part)
    return nominal_mm if b is None else b.lo_mm


def handle_floor_mm(plan, parts) -> float:
    """The knob's floor under the handle screw's head (mm): the screw's catalog length less the
    coupler, so its tip ends flush with the coupler's bottom face -- of the thinnest coupler
    sheet in a laser build (never proud of it), of the nominal coupler otherwise."""
    t = parts.bar_thickness_mm
    return plan.handle_screw_length_mm - thinnest_mm(sheet_bands(parts), "coupler", t)


def handle_min_engagement_mm(parts, whole_d: float, min_d: float) -> float:
    """The handle screw's minimum engagement in the coupler (mm): ``whole_d`` x d, or the whole
    plate when thinner, but at least ``min_d`` x d (the knob carries hand loads only); the plate
    taken at its thinnest sheet in a laser build, where the screw takes all of it."""
    d = catalog.thread_diameter_mm(parts.handle_screw)
    t = thinnest_mm(sheet_bands(parts), "coupler", parts.bar_thickness_mm)
    return min(whole_d * d, max(t, min_d * d))


def _clamp_range(clamp_mm: float, clamps, bands) -> tuple[float, float]:
    sh = [bands[c] for c in clamps if c in bands]
    return (clamp_mm + sum(b.lo_mm - b.nominal_mm for b in sh),
            clamp_mm + sum(b.hi_mm - b.nominal_mm for b in sh))


def _depth_min(hole, bands) -> float:
    b = bands.get(hole.part)
    return hole.depth_mm if b is None else hole.depth_mm - (b.nominal_mm - b.lo_mm)


def _row_bands(clamps, hole, bands: dict[str, SheetBand]) -> list[SheetBand]:
    """The sheets a screw clamps, then the hole's sheet, each once."""
    sh = [bands[c] for c in clamps if c in bands]
    return list(dict.fromkeys(sh + ([bands[hole.part]] if hole.part in bands else [])))


def screw_row(name: str, size: str, length_mm: float, clamp_mm: float, clamps, hole,
              bands: dict[str, SheetBand]) -> dict | None:
    """report.json row of one cap screw (``clamp_mm`` nominal, ``clamps`` part names, ``hole``
    a :class:`cad.assembly.fasteners.TappedHole`) over the sheets' bands (module docstring),
    or None when neither a clamped part nor the hole's part is a sheet. Lengths in mm."""
    sh = _row_bands(clamps, hole, bands)
    if not sh:
        return None
    c_lo, c_hi = _clamp_range(clamp_mm, clamps, bands)
    d_min = _depth_min(hole, bands)
    e_min, e_max = length_mm - c_hi, length_mm - c_lo
    ok = e_min >= hole.min_engagement_mm - 1e-9 and e_max <= d_min + 1e-9
    return {"fastener": name, "size": size, "length_mm": length_mm, "hole": hole.name,
            "sheets": [b.text() for b in sh],
            "clamp_mm": [round(c_lo, 6), clamp_mm, round(c_hi, 6)],
            "engagement_nominal_mm": round(length_mm - clamp_mm, 6),
            "engagement_worst_mm": [round(e_min, 6), round(e_max, 6)],
            "window_mm": [hole.min_engagement_mm, round(d_min, 6)],
            "keys": list(dict.fromkeys(b.key for b in sh)),
            "verdict": "holds" if ok else "misses"}


def _each(text: str) -> str:
    """A joint or hole name without its instance number (``leg 2 to base plate`` -> ``legs to
    base plate``, ``motor:face_3`` -> ``motor:face``): one warning for the screws of a pattern."""
    return re.sub(r"_\d+(?=:|$)", "", re.sub(r"\bleg \d+ ", "legs ", text))


def size_over_band(size: str, clamp_mm: float, hole, joint: str, field: str, clamps,
                   bands: dict[str, SheetBand], **blame) -> tuple[float, float]:
    """(catalog length, nominal engagement) of the ISO 4762 screw of a stack
    (:func:`cad.assembly.fasteners.size_cap_screw`, whose refusals at nominal stand) that holds
    over the sheets' bands: the shortest ``L`` with ``L - c_hi >= min engagement`` and
    ``L - c_lo <= `` the hole's thinnest depth. When no catalog length does, the nominal one
    is kept and a warning (:func:`cad.design.bounds.warn`) names ``joint``, each sheet and its
    band, the engagement it gets and the keys to change. No sheet: exactly ``size_cap_screw``."""
    L0, e0 = size_cap_screw(size, clamp_mm, hole, joint, field, **blame)
    row = screw_row("", size, L0, clamp_mm, clamps, hole, bands)
    if row is None or row["verdict"] == "holds":
        return L0, e0
    (c_lo, _, c_hi), (need, d_min) = row["clamp_mm"], row["window_mm"]
    lo, hi = c_hi + need, c_lo + d_min
    for L in catalog.get_cap_screw(size, field).lengths_mm:
        if lo - 1e-9 <= L <= hi + 1e-9:
            return L, L - clamp_mm

    keys = row["keys"]
    e_min, e_max = row["engagement_worst_mm"]
    why = (f"{need:g} mm of thread in {_each(hole.name)} at the thickest, no deeper than its "
           f"{d_min:g} mm at the thinnest")
    need_L = (f"needs L in {lo:g}..{hi:g} mm: {why}" if lo <= hi else  # else no L: band > window
              f"no L can: L >= {lo:g} mm for {why.replace(', no deeper', ' but L <= ' + f'{hi:g} mm no deeper')}")
    miss = [f"only {e_min:g} mm at the thickest" if e_min < need - 1e-9 else "",
            f"{e_max - d_min:.2f} mm past the thread at the thinnest" if e_max > d_min + 1e-9 else ""]
    bounds.warn(f"{_each(joint)}: {'; '.join(row['sheets'])}: no {size.split('-')[0]} ISO 4762 "
                f"length holds over that band ({need_L}); "
                f"the {L0:g} mm screw engages {e_min:g}..{e_max:g} mm "
                f"({', '.join(m for m in miss if m)}); change "
                f"{' or '.join(dict.fromkeys(keys + [field]))}")
    return L0, e0


def pin_rows(plan, parts, bands: dict[str, SheetBand]) -> list[dict]:
    """report.json rows of the ISO 7379 pin stacks of a layer plan
    (:class:`cad.families.fourbar.layers.LayerPlan`) with a sheet bar in them: the shoulder entry into
    the lower bar ``L - c`` against its window at the lower bar's ``hi`` (nut on full thread)
    and ``lo`` (shoulder inside the bar), the head's clearance above the upper bar at its
    ``hi``, and the stack height (lower bar bottom to head top) over the lower bar's band."""

    pin = catalog.get_shoulder_screw(parts.pin)
    brg = catalog.get_bearing(parts.bearing)
    out = []
    for j, s in plan.joints.items():
        up, low = bands.get(s.upper), bands.get(s.lower)
        if up is None and low is None:
            continue
        entry = s.pin_length_mm - s.clamp_mm
        t = parts.bar_thickness_mm
        if s.nut and low is not None:
            win = (pin_window(parts, low.hi_mm, False)[0], pin_window(parts, low.lo_mm, False)[1])
        else:
            win = pin_window(parts, t, not s.nut)
        clear = s.shim_mm - (t - brg.B_mm)
        clear_min = clear - ((up.hi_mm - up.nominal_mm) if up else 0.0)
        h = t + s.clamp_mm + pin.k_mm if s.nut else s.clamp_mm + pin.k_mm
        h_band = [h - (low.nominal_mm - low.lo_mm), h + (low.hi_mm - low.nominal_mm)] \
            if (s.nut and low) else [h, h]
        ok = win[0] - 1e-9 <= entry <= win[1] + 1e-9 and clear_min > 1e-9
        out.append({"fastener": f"pin_{j}", "size": parts.pin, "length_mm": s.pin_length_mm,
                    "upper": s.upper, "lower": s.lower,
                    "sheets": list(dict.fromkeys(b.text() for b in (up, low) if b)),
                    "shoulder_entry_mm": round(entry, 6),  # window hi None: unbounded (post)
                    "entry_window_mm": [round(win[0], 6),
                                        round(float(win[1]), 6) if win[1] < float("inf") else None],
                    "head_clearance_mm": [round(clear_min, 6), round(clear, 6)],
                    "stack_height_mm": [round(x, 6) for x in (h_band[0], h, h_band[1])],
                    "keys": list(dict.fromkeys(b.key for b in (up, low) if b)),
                    "verdict": "holds" if ok else "misses"})
    return out


def warn_pins(rows: list[dict]) -> None:
    """A warning per pin row (:func:`pin_rows`) that misses, naming the joint, the sheets,
    the window and the keys to change."""
    for r in rows:
        if r["verdict"] == "holds":
            continue
        lo, hi = r["entry_window_mm"]
        hi = float("inf") if hi is None else hi
        keys = r["keys"]
        bounds.warn(f"{r['fastener'].replace('pin_', '')} ({r['size']} shoulder screw): "
                    f"{'; '.join(r['sheets'])}: shoulder entry {r['shoulder_entry_mm']:g} mm "
                    f"against {lo:g}..{hi:g} mm over that band, head clearance down to "
                    f"{r['head_clearance_mm'][0]:g} mm; change {' or '.join(keys)} or "
                    f"parts.pin_head_clearance_mm")


def tolerance_report(instances, holes: dict, plan, parts) -> list[dict]:
    """report.json ``sheets.thickness_tolerance``: a row (:func:`screw_row`) per ISO 4762
    fastener instance touching a sheet, then the pin rows (:func:`pin_rows`); ``holes`` the
    assembly's ``{name: TappedHole}``. Empty unless laser."""
    bands = sheet_bands(parts)
    if not bands:
        return []
    rows = []
    for inst in instances:
        f = inst.fastener
        if f is None or f.kind != "ISO 4762":
            continue
        r = screw_row(inst.name, f.size, f.length_mm, f.length_mm - f.engagement_mm, f.clamps,
                      holes[f.hole], bands)
        if r is not None:
            rows.append(r)
    return rows + pin_rows(plan, parts, bands)
