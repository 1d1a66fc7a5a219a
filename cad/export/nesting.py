"""Laser-cut plate parts nested on stock sheets: one DXF per sheet (``parts.process = "laser"``).

Every instance of a laser-cut kind (:attr:`cad.parts.PartKind.sheet_mm` set by
:func:`cad.assembly.laser.as_laser`) is placed once, grouped by sheet material, thickness
and sheet size. Packing is by the part's bounding box in its own x-y plane (exact OCCT box),
grown by :data:`cad.tolerances.NEST_GAP_MM`, on the sheet less
:data:`cad.tolerances.NEST_EDGE_MARGIN_MM` a side, 90 degree rotation allowed; the packer is
rectpack 0.2.2 (MaxRects, best short side fit, bins best-fit-first, offline: largest first).
Bounding-box packing wastes the concave room of an L-shaped part; the plates here are
near-rectangular.

``sheets/sheet_NN.dxf`` (DXF R2000, mm, fixed metadata): layer ``CUT`` holds each part's
through profile exactly as ``parts/<part>.dxf`` draws it (:func:`cad.export.dxf.plate_profile_dxf`:
bores to be reamed cut undersize, tap drills), rotated and moved into place; ``ENGRAVE`` one
TEXT per part with its instance name, placed where its box lies in material
(:func:`label_spot`); ``SHEET`` the sheet's outline (not cut); ``NOTES`` the sheet's name
and the order line it is bought on (:func:`sheet_designation`), material, thickness
and its stock band, sheet size, units, kerf, gap and margin, the parts. The milled seats,
reaming and tapping after cutting are on each part's own DXF.
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass, field

import numpy as np

from cad import tolerances as tol
from cad.data.materials import LASER_CUT_SIZES_SOURCE, SHEETS
from cad.errors import DesignError
from cad.export.dxf import plate_profile_dxf
from cad.export.order import NESTED_STOCK
from cad.io.atomic import write_text_atomic

#: ACI colour of each sheet layer (laser software maps operations by colour): CUT red,
#: ENGRAVE blue, SHEET grey, NOTES white/black.
LAYER_COLOURS = {"CUT": 1, "ENGRAVE": 5, "SHEET": 8, "NOTES": 7}


@dataclass
class Placed:
    """One part instance on a sheet: ``x_mm, y_mm`` of its box's lower-left corner on the
    sheet, ``rotated`` by +90 degrees about z first; ``box_mm`` its (x0, y0, x1, y1) in the
    part frame."""

    instance: str
    kind: object
    box_mm: tuple
    x_mm: float
    y_mm: float
    rotated: bool

    def matrix(self) -> np.ndarray:
        """3x3 homogeneous transform part frame (x, y) -> sheet (mm)."""
        x0, y0, x1, y1 = self.box_mm
        if self.rotated:  # (x, y) -> (-y, x): box x in [-y1, -y0], y in [x0, x1]
            return np.array([[0.0, -1.0, self.x_mm + y1], [1.0, 0.0, self.y_mm - x0], [0, 0, 1]])
        return np.array([[1.0, 0.0, self.x_mm - x0], [0.0, 1.0, self.y_mm - y0], [0, 0, 1]])


@dataclass
class Sheet:
    """One stock sheet: material, nominal thickness, size (width, length) mm, its parts;
    ``tried_mm``: the stock sizes its group was nested on when the design named none (the
    size is the one ordering the least sheet area), empty for ``parts.laser_sheet_mm``."""

    material: str
    thickness_mm: float
    size_mm: tuple
    parts: list = field(default_factory=list)
    volume_mm3: float = 0.0
    tried_mm: tuple = ()

    def size_note(self) -> str:
        """Why this size: the design's, or the smallest stock sheet the nesting fits."""
        if not self.tried_mm:
            return "size from parts.laser_sheet_mm"

        sizes = ", ".join(f"{w:g} x {h:g}" for w, h in self.tried_mm)
        return (f"the stock size needing the least sheet area the nesting fits (nested on {sizes} mm; "
                f"cut-piece sizes: {LASER_CUT_SIZES_SOURCE}); set parts.laser_sheet_mm to order another")

    @property
    def utilisation(self) -> float:
        """Share of the sheet's volume that ends in parts (sum of part volumes / W L t)."""
        return self.volume_mm3 / (self.size_mm[0] * self.size_mm[1] * self.thickness_mm)


def _box_xy(shape) -> tuple[float, float, float, float, float]:
    """``(x0, y0, x1, y1, thickness)`` of a shape's exact OCCT box (mm)."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib

    b = Bnd_Box()
    BRepBndLib.AddOptimal_s(getattr(shape, "wrapped", shape), b, False, False)
    lo, hi = b.CornerMin(), b.CornerMax()
    return lo.X(), lo.Y(), hi.X(), hi.Y(), hi.Z() - lo.Z()


def _volume_mm3(shape) -> float:
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps

    g = GProp_GProps()
    BRepGProp.VolumeProperties_s(getattr(shape, "wrapped", shape), g)
    return g.Mass()


def _fits(size_mm, free_mm) -> bool:
    """True when a (w, h) part box lies within the (W, H) sheet less its margins, to
    NEST_FIT_EPS_MM of round-off (a part exactly the free size fits)."""
    return all(a <= b + tol.NEST_FIT_EPS_MM for a, b in zip(size_mm, free_mm))


def _cells(size_mm, grid_WH, free_mm, gap_mm: float) -> tuple[int, int]:
    """A part's (w, h) in NEST_GRID_MM cells, rounded up with its gap; a side that fits the
    free sheet in mm but rounds past the grid's (W, H) takes the whole side (it then sits at
    the margin, where its true size fits)."""
    g = tol.NEST_GRID_MM
    out = []
    for a, n, f in zip(size_mm, grid_WH, free_mm):
        c = math.ceil((a + gap_mm) / g)
        out.append(n if c > n and a <= f + tol.NEST_FIT_EPS_MM else c)
    return tuple(out)


def pack(sizes_mm, sheet_mm, gap_mm: float, margin_mm: float,
         names=None) -> list[tuple[int, float, float, bool]]:
    """Place rectangles ``sizes_mm`` ((w, h) mm each) on as few ``sheet_mm`` (W, H) sheets as
    rectpack finds, ``gap_mm`` between any two and ``margin_mm`` from the sheet edges.

    Returns per rectangle ``(sheet index, x, y, rotated)``: its lower-left corner (mm) on its
    sheet, rotated by 90 degrees when True. Raises ValueError when one cannot fit a sheet,
    naming it by ``names[i]`` (the part) when given.
    """
    import rectpack

    g = tol.NEST_GRID_MM
    free = [s - 2 * margin_mm for s in sheet_mm]  # the sheet less its margins (mm)
    W, H = (math.floor((f + gap_mm) / g) for f in free)
    cells, turned = [], []  # cells in the orientation that fits; True: (h, w) of the part
    for i, (w, h) in enumerate(sizes_mm):
        if not _fits((w, h), free) and not _fits((h, w), free):
            what = f"the {names[i]}" if names else "a"
            raise ValueError(f"{what} {w:.1f} x {h:.1f} mm part does not fit a {sheet_mm[0]:g} x "
                             f"{sheet_mm[1]:g} mm sheet less {margin_mm:g} mm margins")
        turned.append(not _fits((w, h), free))
        cells.append(_cells((h, w) if turned[-1] else (w, h), (W, H), free, gap_mm))
    packer = rectpack.newPacker(mode=rectpack.PackingMode.Offline, bin_algo=rectpack.PackingBin.BFF,
                                pack_algo=rectpack.MaxRectsBssf, rotation=True)
    packer.add_bin(W, H, count=float("inf"))
    for i, (w, h) in enumerate(cells):
        packer.add_rect(w, h, rid=i)
    packer.pack()
    out: list = [None] * len(cells)
    for b, x, y, w, _h, rid in packer.rect_list():
        rot = (w != cells[rid][0]) != turned[rid]
        out[rid] = (b, margin_mm + x * g, margin_mm + y * g, rot)
    if any(o is None for o in out):
        raise ValueError("rectpack left a part unplaced")
    return out


def _candidate_sizes(material: str, asked, largest) -> list[tuple[float, float]]:
    """Sheet sizes to try: ``asked`` (the design's) alone, or every stock size of the material
    (:attr:`cad.data.materials.SheetStock.stock_sizes_mm`, smallest first) that holds the
    ``largest`` (w, h) part box with the margins either way round (the largest size when
    none does: the packer then names the part that does not fit)."""
    if asked and asked[0] > 0:
        return [tuple(asked)]
    m = 2 * tol.NEST_EDGE_MARGIN_MM
    w, h = sorted(largest)
    sizes = SHEETS[material].stock_sizes_mm
    fit = [size for size in sizes if w + m <= sorted(size)[0] and h + m <= sorted(size)[1]]
    return fit or [max(sizes, key=lambda s: s[0] * s[1])]


def _smallest_stock(sizes_mm, names, candidates) -> tuple[tuple, list]:
    """(sheet size, packing) of the candidate that orders the least sheet area (sheets x W x
    L; ties: fewer sheets, then the smaller sheet). Raises ValueError from :func:`pack`."""
    best = None
    for size in candidates:
        spots = pack(sizes_mm, size, tol.NEST_GAP_MM, tol.NEST_EDGE_MARGIN_MM, names)
        n = 1 + max(b for b, *_ in spots)
        score = (n * size[0] * size[1], n, size[0] * size[1])
        if best is None or score < best[0]:
            best = (score, tuple(size), spots)
    return best[1], best[2]


def plan_sheets(instances) -> list[Sheet]:
    """The sheets of every laser-cut instance (module docstring), in order: by material,
    thickness and size as first met, then sheet index. Without ``parts.laser_sheet_mm`` each
    group is nested on every stock size of its material that holds its largest part and
    ordered on the one needing the least sheet area (:func:`_smallest_stock`; the sizes and
    their source: :attr:`cad.data.materials.SheetStock.stock_sizes_mm`). Raises DesignError
    (``parts.laser_sheet_mm``) when a part fits no sheet."""
    groups: dict = {}
    boxes: dict = {}
    for inst in instances:
        k = inst.kind
        if getattr(k, "sheet_mm", None) is None:
            continue
        if k.name not in boxes:
            boxes[k.name] = _box_xy(k.shape)
        t = round(boxes[k.name][4], 6)
        groups.setdefault((k.material, t, tuple(k.sheet_mm)), []).append(inst)
    sheets: list[Sheet] = []
    for (mat, t, asked), insts in groups.items():
        sizes = [(boxes[i.kind.name][2] - boxes[i.kind.name][0],
                  boxes[i.kind.name][3] - boxes[i.kind.name][1]) for i in insts]
        cands = _candidate_sizes(mat, asked, max(sizes, key=lambda s: max(s)))
        try:
            size, spots = _smallest_stock(sizes, [i.name for i in insts], cands)
        except ValueError as exc:
            raise DesignError("parts.laser_sheet_mm", f"{mat} {t:g} mm: {exc}") from None
        mine: dict[int, Sheet] = {}
        for inst, (b, x, y, rot) in zip(insts, spots, strict=True):
            s = mine.setdefault(b, Sheet(mat, t, size, tried_mm=() if asked and asked[0] > 0 else tuple(cands)))
            s.parts.append(Placed(inst.name, inst.kind, boxes[inst.kind.name][:4], x, y, rot))
            s.volume_mm3 += _volume_mm3(inst.kind.shape)
        sheets += [mine[b] for b in sorted(mine)]
    return sheets


def sheets_report(sheets: list[Sheet], written: bool = True) -> dict:
    """report.json ``sheets``: ``count``, and per sheet its file (None when the DXF was not
    asked for: ``written`` False), material, thickness, size, utilisation and parts; the gap,
    margin and packing used."""
    return {
        "count": len(sheets),
        "gap_mm": tol.NEST_GAP_MM,
        "edge_margin_mm": tol.NEST_EDGE_MARGIN_MM,
        "packing": "part bounding boxes, rectpack 0.2.2 MaxRects BSSF, 90 deg rotation",
        "utilisation_means": "sum of part volumes / (sheet width x length x thickness)",
        "sheets": [
            {"file": sheet_file(i) if written else None, "material": s.material, "thickness_mm": s.thickness_mm,
             "size_mm": list(s.size_mm), "size_choice": s.size_note(), "utilisation": s.utilisation,
             "parts": [p.instance for p in s.parts]}
            for i, s in enumerate(sheets)
        ],
    }


def sheet_name(i: int) -> str:
    """Name of sheet ``i`` (0-based): ``"sheet_01"``; its DXF is ``sheets/<name>.dxf``."""
    return f"sheet_{i + 1:02d}"


def sheet_file(i: int) -> str:
    """Path of sheet ``i`` (0-based) under the output folder."""
    return f"sheets/{sheet_name(i)}.dxf"


def sheet_designation(sheet: Sheet) -> str:
    """What to order for ``sheet``: ``"sheet 6 x 500 x 300 mm aluminium-5083"`` (thickness x
    width x length, mm, material) -- the ``designation`` of its BOM and ``order.csv`` line."""
    w, h = sheet.size_mm
    return f"sheet {sheet.thickness_mm:g} x {w:g} x {h:g} mm {sheet.material}"


def nested_stock(i: int, sheet: Sheet) -> str:
    """The stock text of a part nested on sheet ``i`` (0-based): the sheet's name (its DXF,
    when written, is :func:`sheet_file`) and the order line it is bought on, named as that
    line is named (``"nested on sheet_01, ordered as sheet 6 x 500 x 300 mm aluminium-5083"``;
    starts with :data:`cad.export.order.NESTED_STOCK`)."""
    return f"{NESTED_STOCK}{sheet_name(i)}, ordered as {sheet_designation(sheet)}"


def _segments(msp) -> np.ndarray:
    """``(n, 4)`` segments x0 y0 x1 y1 of the CUT entities (arcs and circles flattened)."""
    segs = []
    for e in msp:
        if e.dxf.layer != "CUT":
            continue
        if e.dxftype() == "LINE":
            segs.append((e.dxf.start.x, e.dxf.start.y, e.dxf.end.x, e.dxf.end.y))
            continue
        pts = [(p.x, p.y) for p in e.flattening(0.02)] if e.dxftype() != "LWPOLYLINE" else \
            [(x, y) for x, y, *_ in e.get_points()]
        segs += [(*a, *b) for a, b in zip(pts[:-1], pts[1:], strict=True)]
    return np.asarray(segs, dtype=float).reshape(-1, 4)


def material_mask(segs: np.ndarray, xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
    """``(len(ys), len(xs))`` bool: the point is in material (even-odd rule over every CUT
    segment: inside the outline and in no hole)."""
    X, Y = np.meshgrid(xs, ys)
    P = np.stack([X.ravel(), Y.ravel()], axis=1)
    count = np.zeros(len(P), dtype=int)
    for x0, y0, x1, y1 in segs:
        up = (y0 <= P[:, 1]) != (y1 <= P[:, 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            xc = x0 + (P[:, 1] - y0) * (x1 - x0) / (y1 - y0)
        count += up & (P[:, 0] < xc)
    return (count % 2 == 1).reshape(Y.shape)


def label_spot(segs: np.ndarray, box, text: str):
    """``(x, y, height, rotation_deg)`` of an engraved label ``text`` on the part whose CUT
    ``segs`` (part frame) are given: the largest height of :data:`cad.tolerances.LABEL_HEIGHTS_MM`
    whose box (len x LABEL_CHAR_WIDTH x h by h, + LABEL_CLEARANCE_MM) lies in material at 0 or
    90 degrees, nearest the box centre; None when no height fits."""
    x0, y0, x1, y1 = box
    step = max(tol.LABEL_GRID_MM / 4, max(x1 - x0, y1 - y0) / 400)
    xs, ys = np.arange(x0 + step / 2, x1, step), np.arange(y0 + step / 2, y1, step)
    mask = material_mask(segs, xs, ys)
    sat = np.pad(mask.astype(int).cumsum(0).cumsum(1), ((1, 0), (1, 0)))
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    for h in tol.LABEL_HEIGHTS_MM:
        for rot in (0.0, 90.0):
            a = len(text) * tol.LABEL_CHAR_WIDTH * h + 2 * tol.LABEL_CLEARANCE_MM
            b = h + 2 * tol.LABEL_CLEARANCE_MM
            nx, ny = (math.ceil(a / step), math.ceil(b / step)) if rot == 0 else \
                (math.ceil(b / step), math.ceil(a / step))
            if nx > len(xs) or ny > len(ys):
                continue
            full = sat[ny:, nx:] - sat[:-ny, nx:] - sat[ny:, :-nx] + sat[:-ny, :-nx]
            j, i = np.nonzero(full == nx * ny)
            if len(i) == 0:
                continue
            px, py = xs[i] + (nx - 1) * step / 2, ys[j] + (ny - 1) * step / 2
            k = int(np.argmin((px - cx) ** 2 + (py - cy) ** 2))
            return float(px[k]), float(py[k]), h, rot
    return None


def _profile_doc(kind, shop: dict):
    """The ezdxf document of ``kind``'s own profile (:func:`cad.export.dxf.plate_profile_dxf`)."""
    import ezdxf


    text = plate_profile_dxf(kind.shape, kind.name, shop.get("notes", ()), shop.get("holes", ()),
                             material=kind.material, quantity=shop.get("quantity"),
                             stock=shop.get("stock", ""))
    return ezdxf.read(io.StringIO(text))


def sheet_dxf(sheet: Sheet, index: int, count: int, profiles: dict) -> str:
    """DXF text of one sheet (module docstring); ``profiles``: ``{kind name: ezdxf doc}``."""
    import ezdxf
    from ezdxf.enums import TextEntityAlignment
    from ezdxf.math import Matrix44


    old = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        doc = ezdxf.new("R2000", setup=False)
        doc.header["$INSUNITS"] = 4
        for layer, colour in LAYER_COLOURS.items():
            doc.layers.add(layer, color=colour)
        msp = doc.modelspace()
        W, H = sheet.size_mm
        msp.add_lwpolyline([(0, 0), (W, 0), (W, H), (0, H)], close=True, dxfattribs={"layer": "SHEET"})
        spots = {}
        for p in sheet.parts:
            m3 = p.matrix()
            m = Matrix44([m3[0, 0], m3[1, 0], 0, 0, m3[0, 1], m3[1, 1], 0, 0, 0, 0, 1, 0,
                          m3[0, 2], m3[1, 2], 0, 1])
            src = profiles[p.kind.name].modelspace()
            for e in src:
                if e.dxf.layer == "CUT":
                    c = e.copy()
                    c.transform(m)
                    msp.add_entity(c)
            key = (p.kind.name, p.instance)
            if key not in spots:
                spots[key] = label_spot(_segments(src), p.box_mm, p.instance)
            spot = spots[key]
            if spot is None:
                x, y = m3 @ [(p.box_mm[0] + p.box_mm[2]) / 2, (p.box_mm[1] + p.box_mm[3]) / 2, 1]
                spot_xy, h, rot = (x, y), tol.LABEL_HEIGHTS_MM[-1], 0.0
            else:
                spot_xy = (m3 @ [spot[0], spot[1], 1])[:2]
                # (mod 180: a label turned 180 deg reads upside down; its centred box is the same)
                h, rot = spot[2], (spot[3] + (90.0 if p.rotated else 0.0)) % 180.0
            msp.add_text(p.instance, height=h, rotation=rot, dxfattribs={"layer": "ENGRAVE"}) \
                .set_placement(tuple(map(float, spot_xy)), align=TextEntityAlignment.MIDDLE_CENTER)
        st = SHEETS[sheet.material]
        lo, hi = st.thickness_range_mm.get(sheet.thickness_mm, (sheet.thickness_mm,) * 2)
        names: dict[str, int] = {}
        for p in sheet.parts:
            names[p.kind.name] = names.get(p.kind.name, 0) + 1
        notes = [
            f"{sheet_name(index)} (sheet {index + 1} of {count}), ordered as {sheet_designation(sheet)}",
            "units: mm", f"material: {sheet.material}",
            f"thickness: {sheet.thickness_mm:g} mm (stock {lo:g} .. {hi:g} mm)",
            f"sheet size: {W:g} x {H:g} mm",
            f"kerf: {st.kerf_mm:g} mm; drawn at finished size: offset the beam by kerf / 2 "
            f"(outward of outlines, inward of holes)",
            f"gap {tol.NEST_GAP_MM:g} mm between parts, edge margin {tol.NEST_EDGE_MARGIN_MM:g} mm",
            "parts: " + ", ".join(f"{n} x{q}" for n, q in names.items()),
            "ENGRAVE: part labels (engrave, do not cut); SHEET: sheet outline (do not cut)",
            "after cutting: mill seats, ream, tap as parts/<part>.dxf says",
        ]
        for k, text in enumerate(notes):
            msp.add_text(text, height=5.0, dxfattribs={"layer": "NOTES",
                                                        "insert": (0.0, -(k + 2) * 8.0)})
        buf = io.StringIO()
        doc.write(buf)
        return buf.getvalue()
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = old


def write_sheets(instances, out_dir, shop: dict) -> list[str]:
    """Write ``sheets/sheet_NN.dxf`` of the laser-cut instances into ``out_dir`` (atomic);
    ``shop``: ``{kind name: shop args}`` (:func:`cad.pipeline.family.shop_args`). Returns the
    paths relative to ``out_dir`` (none without laser-cut parts)."""
    from pathlib import Path


    sheets = plan_sheets(instances)
    profiles = {}
    for s in sheets:
        for p in s.parts:
            if p.kind.name not in profiles:
                profiles[p.kind.name] = _profile_doc(p.kind, shop.get(p.kind.name, {}))
    out = []
    for i, s in enumerate(sheets):
        path = Path(out_dir) / sheet_file(i)
        path.parent.mkdir(parents=True, exist_ok=True)
        write_text_atomic(path, sheet_dxf(s, i, len(sheets), profiles))
        out.append(sheet_file(i))
    return out
