"""One A4 landscape drawing sheet per made part (matplotlib, from build123d projections).

Views in first-angle projection (ISO 5456-2, ISO 128-30), as the title block states: front
(x-z, seen from -y, looking along +y) top left; the view from above (x-y, seen from +z) BELOW
it; the view from the left (y-z, seen from -x, looking along +x: part +y runs to the sheet's
left) RIGHT of the front view (:data:`SIDE_FROM`); and a section A-A
(x-z plane through a stepped or blind hole) below the top view when a bore or seat needs
one. Visible and hidden edges come from build123d's hidden-line projection
(``Shape.project_to_viewport``). Overall sizes are dimensioned on the views; every
cylindrical feature gets a tag on the view it is seen round in and a row of the feature
table: its centre from the datum (the bounding box's minimum corner), its diameter with the
ISO 286 fit or the thread with its depth (:func:`cad.export.drawings.notes.callout`); so
does every pocket or through slot (length x width x depth, corner radius, direction) and
every conical chamfer (C size x 45 deg, or legs and angle) found on the solid. The title
block states design, part, material, quantity, process, stock, the general tolerance, units,
scale and sheet number. Text stays text in the SVG (``svg.fonttype = "none"``), so a test
can read every number back.
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass

from cad.data.fits import fmt_mm
from cad.export.drawings.features import bbox_mm, chamfers, cylinders, pockets
from cad.export.drawings.notes import GENERAL_TOLERANCE, callout
from cad.io.escape import mathtext
from cad.occ.boolean import common

#: Sheet size (ISO 216 A4 landscape) and the drawing border (mm).
SHEET_MM = (297.0, 210.0)
BORDER_MM = 10.0
#: Room for the views (x0, y0, x1, y1 on the sheet, mm): left of the feature table, above the
#: title block and notes.
VIEWS_MM = (14.0, 52.0, 196.0, 196.0)
#: Gap between two views on the sheet (mm): room for a dimension line and its text.
VIEW_GAP_MM = 14.0
#: Where the side view is seen from: -x (the view from the left), which first-angle projection
#: (ISO 5456-2) places RIGHT of the front view; in it part +y runs to the sheet's left.
SIDE_FROM = -1.0
#: Preferred scales of ISO 5455, largest first.
ISO_SCALES = (10.0, 5.0, 2.0, 1.0, 0.5, 0.2, 0.1, 0.05)
#: Sample count of a curved edge drawn as a polyline (a circle at scale 10:1 stays smooth).
CURVE_SAMPLES = 64
#: Feature-table row pitch and font size limits (mm, pt).
ROW_MM, FONT_PT, FONT_MIN_PT = 3.6, 5.5, 3.0


@dataclass(frozen=True)
class SheetPart:
    """What one sheet shows: ``shape`` (``TopoDS_Shape``, part frame, mm) and the part's
    BOM data; ``fits`` as :func:`cad.data.fits.fit` texts, ``threads`` its tapped holes,
    ``(size, thread depth mm or None)`` or ``(size, depth, name, axis, point_mm)`` (place in
    the part frame or None; :func:`cad.export.drawings.notes.callout`); ``stock`` the BOM's
    stock text (:func:`cad.pipeline.family.kind_stock`: the sheet states what is ordered)."""

    name: str
    shape: object
    material: str
    quantity: int
    process: str
    plate: bool
    fits: tuple[str, ...] = ()
    threads: tuple = ()
    description: str = ""
    stock: str = ""


def feature_rows(part: SheetPart):
    """``[(tag, Cylinder, text)]`` of the feature table and the part's bounding box."""
    box = bbox_mm(part.shape)
    ext = {"x": box[3] - box[0], "y": box[4] - box[1], "z": box[5] - box[2]}
    rows = []
    for i, c in enumerate(cylinders(part.shape), 1):
        tag = f"{'H' if c.internal else 'B'}{i}"
        a, b = c.plane
        size = f"{'Ø' if c.full else 'R'}{(c.d_mm if c.full else c.d_mm / 2):.2f}"
        if c.axis == "n":
            n, q = c.direction, c.point_mm
            where = (f"axis n=({n[0]:.4f},{n[1]:.4f},{n[2]:.4f}) x={q[0]:.2f} y={q[1]:.2f} "
                     f"z={q[2]:.2f} {size} t")
        else:
            where = f"axis {c.axis} {a}={c.u_mm:.2f} {b}={c.v_mm:.2f} {size} {c.axis}"
        text = (f"{tag} {where}={c.lo_mm:.2f}..{c.hi_mm:.2f} | "
                f"{callout(c, part.fits, part.threads, ext.get(c.axis), box[:3])}")
        rows.append((tag, c, text))
    return rows, box


def pocket_text(tag: str, p) -> str:
    """The table row of a :class:`cad.export.drawings.features.Pocket`: ``P1 pocket z
    x=40.61 y=9.50 47.22 x 2.00 x 5.00 z=0.00..5.00 | through; corners R1.00; length
    along 0.0 deg from x``."""
    a, b = {"z": ("x", "y"), "x": ("y", "z"), "y": ("x", "z")}[p.axis]
    corners = f"corners R{p.corner_r_mm:.2f}" if p.corner_r_mm is not None else "sharp corners"
    return (f"{tag} pocket {p.axis} {a}={p.u_mm:.2f} {b}={p.v_mm:.2f} {p.length_mm:.2f} x "
            f"{p.width_mm:.2f} x {p.depth_mm:.2f} {p.axis}={p.lo_mm:.2f}..{p.hi_mm:.2f} | "
            f"{'through' if p.through else 'blind (floor)'}; {corners}; length along "
            f"{p.angle_deg:.1f} deg from {a}")


def chamfer_text(tag: str, c) -> str:
    """The table row of a :class:`cad.export.drawings.features.Chamfer`: ``C1 chamfer z
    x=2.45 y=2.45 z=0.00..0.15 | bore C0.15 x 45 deg`` (legs: axial, radial)."""
    a, b = {"z": ("x", "y"), "x": ("y", "z"), "y": ("x", "z")}[c.axis]
    where = "bore" if c.internal else "edge"
    size = (f"C{c.axial_mm:.2f} x 45 deg" if abs(c.angle_deg - 45.0) < 0.05 else
            f"{c.axial_mm:.2f} x {c.angle_deg:.1f} deg (radial {c.radial_mm:.2f})")
    return (f"{tag} chamfer {c.axis} {a}={c.u_mm:.2f} {b}={c.v_mm:.2f} "
            f"{c.axis}={c.lo_mm:.2f}..{c.hi_mm:.2f} | {where} {size}")


def pocket_chamfer_rows(part: SheetPart):
    """``[(tag, Pocket or Chamfer, text)]``: the part's pockets (P1..) and chamfers (C1..)
    (:func:`cad.export.drawings.features.pockets`, :func:`~cad.export.drawings.features.chamfers`)."""
    rows = [(f"P{k}", p, pocket_text(f"P{k}", p)) for k, p in enumerate(pockets(part.shape), 1)]
    rows += [(f"C{k}", c, chamfer_text(f"C{k}", c))
             for k, c in enumerate(chamfers(part.shape), 1)]
    return rows


def _scale(size, section: bool) -> float:
    x, y, z = size
    w = VIEWS_MM[2] - VIEWS_MM[0] - 2 * VIEW_GAP_MM
    h = VIEWS_MM[3] - VIEWS_MM[1] - 2 * VIEW_GAP_MM
    left_h = 2 * z + y if section else z + y
    for s in ISO_SCALES:
        if (x + y) * s <= w and left_h * s + (VIEW_GAP_MM if section else 0) <= h:
            return s
    return ISO_SCALES[-1]


def scale_text(s: float) -> str:
    return f"{fmt_mm(s)}:1" if s >= 1 else f"1:{fmt_mm(1 / s)}"


def _polyline(edge, axes: str = "XY"):
    """Sampled coordinates ``(xs, ys)`` of an edge: its ``axes`` (``"XY"`` of a projected
    edge, ``"XZ"`` of a section edge)."""
    from build123d import GeomType

    n = 2 if edge.geom_type == GeomType.LINE else CURVE_SAMPLES
    pts = edge.positions([i / (n - 1) for i in range(n)])
    return [getattr(p, axes[0]) for p in pts], [getattr(p, axes[1]) for p in pts]


def _view(ax, shape, origin, up, centre, at, s):
    """Visible and hidden edges of ``shape`` seen from ``origin`` (look at ``centre``),
    drawn at sheet point ``at`` and scale ``s``."""
    vis, hid = shape.project_to_viewport(origin, up, look_at=centre)
    for edges, kw in ((hid, dict(lw=0.2, color="0.45", ls=(0, (3, 2)))),
                      (vis, dict(lw=0.45, color="black"))):
        lines = sorted((_polyline(e) for e in edges),  # a fixed order: the same file
                       key=lambda p: [round(v, 6) for v in (*p[0], *p[1])])
        for xs, ys in lines:
            ax.plot([at[0] + s * x for x in xs], [at[1] + s * y for y in ys], **kw)


def _dim(ax, p0, p1, text, offset):
    """A dimension line between sheet points p0 and p1, moved by ``offset`` (mm)."""
    (x0, y0), (x1, y1) = p0, p1
    dx, dy = offset
    ax.plot([x0, x0 + dx], [y0, y0 + dy], lw=0.15, color="black")
    ax.plot([x1, x1 + dx], [y1, y1 + dy], lw=0.15, color="black")
    ax.annotate("", xy=(x0 + dx, y0 + dy), xytext=(x1 + dx, y1 + dy),
                arrowprops=dict(arrowstyle="<|-|>", lw=0.25, mutation_scale=4, color="black"))
    rot = 90 if abs(x1 - x0) < 1e-9 else 0
    ax.text(0.5 * (x0 + x1) + dx + (-1.2 if rot else 0), 0.5 * (y0 + y1) + dy + (0 if rot else 1.0),
            text, fontsize=FONT_PT, ha="center", va="bottom" if not rot else "center",
            rotation=rot)


def section_plane_y(rows, box) -> float | None:
    """World y of section A-A (an x-z plane through the centre of the first z-axis hole that
    is stepped or blind: shorter than the part is thick), or None when no bore needs one."""
    thick = box[5] - box[2]
    for _, c, _ in rows:
        if c.axis == "z" and c.internal and c.full and c.hi_mm - c.lo_mm < thick - 1e-6:
            return box[1] + c.v_mm
    return None


def _loop(wire):
    """Ordered (x, z) points of a planar wire in an x-z plane (edges chained end to end)."""
    pts: list = []
    for e in wire.edges():
        xs, zs = _polyline(e, "XZ")
        seg = list(zip(xs, zs, strict=True))
        if pts and math.dist(pts[-1], seg[-1]) < math.dist(pts[-1], seg[0]):
            seg.reverse()
        pts += seg
    return pts


def _section(ax, solid, y_mm, box, at, s):
    """Section A-A at world ``y_mm``: the cut faces hatched, seen from -y (x right, z up)."""
    import build123d as bd
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path as MPath


    cx, cz = 0.5 * (box[0] + box[3]), 0.5 * (box[2] + box[5])
    big = 4 * max(box[3] - box[0], box[5] - box[2]) + 10
    plane = bd.Plane(origin=(cx, y_mm, cz), x_dir=(1, 0, 0), z_dir=(0, -1, 0))
    # serial (build123d's intersect runs OCCT's thread pool, which hangs in the forked child
    # that writes a family's files, cad.pipeline.forked) and on a copy: the part's solid
    # is shared with its other exports, which must not see the cut's tolerances
    faces = bd.Compound(common(solid.wrapped, bd.Face.make_rect(big, big, plane).wrapped)).faces()
    # OCCT's boolean returns the faces in no fixed order: sort them so the file is the same
    for face in sorted(faces, key=lambda f: (round(f.center().X, 6), round(f.center().Z, 6),
                                            round(f.area, 6))):
        verts, codes = [], []
        for w in [face.outer_wire(), *face.inner_wires()]:
            loop = [(at[0] + s * (x - cx), at[1] + s * (z - cz)) for x, z in _loop(w)]
            verts += loop + [loop[0]]
            codes += [MPath.MOVETO] + [MPath.LINETO] * (len(loop) - 1) + [MPath.CLOSEPOLY]
        ax.add_patch(PathPatch(MPath(verts, codes), facecolor="none", edgecolor="black",
                               lw=0.45, hatch="////"))


def _table(ax, rows, x0, y_top, y_bottom):
    """The feature table: per row its geometry line (tag, axis, centre, size, extent) and
    below it, indented, the callout (font and pitch shrunk to fit)."""
    n = max(len(rows), 1)
    pitch = min(ROW_MM, (y_top - y_bottom - 6) / (2 * n))
    font = max(FONT_MIN_PT, min(FONT_PT, pitch * 72 / 25.4 * 0.85))
    ax.text(x0, y_top, "FEATURES (datum: x_min, y_min, z_min; mm)",
            fontsize=FONT_PT, weight="bold", va="top")
    for k, (_, _, text) in enumerate(rows):
        geom, _, note = text.partition(" | ")
        y = y_top - 5 - 2 * k * pitch
        ax.text(x0, y, geom, fontsize=font, va="top", family="monospace")
        ax.text(x0 + 4, y - pitch, note, fontsize=font, va="top", family="monospace")


def _title_block(ax, part: SheetPart, design: str, s: float, page: tuple[int, int]):
    x0, y0, x1, y1 = 180.0, BORDER_MM, SHEET_MM[0] - BORDER_MM, 50.0
    ax.plot([x0, x1, x1, x0, x0], [y0, y0, y1, y1, y0], lw=0.5, color="black")
    lines = [
        f"design: {mathtext(design)}",
        f"part: {mathtext(part.name)}",
        f"material: {mathtext(part.material)}",
        f"quantity: {part.quantity}",
        *textwrap.wrap(mathtext(f"process: {part.process or 'unstated'}"), 62),
        f"stock: {mathtext(part.stock or 'unstated')}",
        f"general tolerance: {GENERAL_TOLERANCE}",
        f"units: mm; scale {scale_text(s)}; first-angle projection",
        f"sheet {page[0]} of {page[1]}; hapticad",
    ]
    pitch = min(4.0, (y1 - y0 - 2) / len(lines))
    for k, t in enumerate(lines):
        ax.text(x0 + 2, y1 - 2 - k * pitch, t, fontsize=FONT_PT, va="top")


def draw_sheet(part: SheetPart, design: str, page: tuple[int, int]):
    """The matplotlib figure of one part's sheet (module docstring)."""
    import build123d as bd
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    solid = bd.Solid(part.shape) if part.shape.ShapeType().name == "TopAbs_SOLID" else \
        bd.Compound(part.shape)
    rows, box = feature_rows(part)
    size = (box[3] - box[0], box[4] - box[1], box[5] - box[2])
    y_sec = section_plane_y(rows, box)
    s = _scale(size, y_sec is not None)
    fig = plt.figure(figsize=(SHEET_MM[0] / 25.4, SHEET_MM[1] / 25.4))
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_xlim(0, SHEET_MM[0])
    ax.set_ylim(0, SHEET_MM[1])
    ax.set_axis_off()
    b = BORDER_MM
    ax.plot([b, SHEET_MM[0] - b, SHEET_MM[0] - b, b, b],
            [b, b, SHEET_MM[1] - b, SHEET_MM[1] - b, b], lw=0.6, color="black")
    ctr = (0.5 * (box[0] + box[3]), 0.5 * (box[1] + box[4]), 0.5 * (box[2] + box[5]))
    x, y, z = size
    gx = VIEWS_MM[0] + VIEW_GAP_MM
    front = (gx + s * x / 2, VIEWS_MM[3] - s * z / 2)
    top = (front[0], front[1] - s * z / 2 - VIEW_GAP_MM - s * y / 2)
    side = (front[0] + s * x / 2 + VIEW_GAP_MM + s * y / 2, front[1])
    far = 1e3 + 10 * max(size)
    _view(ax, solid, (ctr[0], ctr[1] - far, ctr[2]), (0, 0, 1), ctr, front, s)
    _view(ax, solid, (ctr[0], ctr[1], ctr[2] + far), (0, 1, 0), ctr, top, s)
    _view(ax, solid, (ctr[0] + SIDE_FROM * far, ctr[1], ctr[2]), (0, 0, 1), ctr, side, s)
    for at, name, h in ((front, "FRONT", z), (top, "TOP", y), (side, "SIDE", z)):
        ax.text(at[0], at[1] + s * h / 2 + 2, name, fontsize=FONT_PT, ha="center")
    # overall sizes from the datum corner
    x0s, y0s = top[0] - s * x / 2, top[1] - s * y / 2
    _dim(ax, (x0s, y0s), (x0s + s * x, y0s), f"{x:.2f}", (0, -6))
    _dim(ax, (x0s, y0s), (x0s, y0s + s * y), f"{y:.2f}", (-6, 0))
    _dim(ax, (front[0] - s * x / 2, front[1] - s * z / 2),
         (front[0] - s * x / 2, front[1] + s * z / 2), f"{z:.2f}", (-6, 0))
    ax.plot([x0s], [y0s], marker="^", ms=3, color="black")
    ax.text(x0s + 1, y0s + 1, "datum", fontsize=FONT_MIN_PT + 1)
    more = pocket_chamfer_rows(part)
    _tags(ax, rows + more, box, {"z": (top, "x", "y", 1.0), "y": (front, "x", "z", 1.0),
                                 "x": (side, "y", "z", SIDE_FROM)}, s)
    if y_sec is not None:
        sec = (top[0], top[1] - s * y / 2 - VIEW_GAP_MM - s * z / 2)
        _section(ax, solid, y_sec, box, sec, s)
        ax.text(sec[0], sec[1] + s * z / 2 + 2, "SECTION A-A", fontsize=FONT_PT, ha="center")
        ys = top[1] + s * (y_sec - ctr[1])
        ax.plot([x0s - 3, x0s + s * x + 3], [ys, ys], lw=0.3, color="black", ls="-.")
        ax.text(x0s + s * x + 4, ys, "A-A", fontsize=FONT_PT, va="center")
    _table(ax, rows + more, 200.0, SHEET_MM[1] - b - 2, 54.0)
    _title_block(ax, part, design, s, page)
    notes = [f"All dimensions in mm from the datum; untoleranced: {GENERAL_TOLERANCE}.",
             "Fits ISO 286-2; threads ISO 261 metric coarse, tap drill d - P (ISO 2306).",
             f"{part.description}" if part.description else ""]
    for k, t in enumerate(n for n in notes if n):
        ax.text(b + 2, 44 - k * 4, t, fontsize=FONT_PT, va="top")
    return fig


def _tags(ax, rows, box, views, s):
    """Each feature's tag at its centre on the view it is seen round in. ``views``: ``{axis:
    (sheet centre, horizontal part axis, vertical part axis, +1 or -1: the horizontal axis runs
    to the sheet's right or left)}``."""
    ctr = {"x": 0.5 * (box[0] + box[3]) - box[0], "y": 0.5 * (box[1] + box[4]) - box[1],
           "z": 0.5 * (box[2] + box[5]) - box[2]}
    for tag, c, _ in rows:
        if c.axis not in views:
            continue  # an oblique axis is seen round in no view: its row gives its place
        at, a, b, sign = views[c.axis]
        px, py = at[0] + sign * s * (c.u_mm - ctr[a]), at[1] + s * (c.v_mm - ctr[b])
        ax.plot([px], [py], marker="+", ms=3, mew=0.3, color="tab:blue")
        ax.text(px + 0.8, py + 0.8, tag, fontsize=FONT_MIN_PT + 0.5, color="tab:blue")
