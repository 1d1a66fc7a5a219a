"""What every family's build writes, from its one list of part instances.

A family builder (four-bar, pantograph, twin pantograph, PowerMouse) only lays out
:class:`cad.parts.PartInstance` objects -- a :class:`cad.parts.PartKind` (solid in its
own frame, material, made/bought, description, process, catalog mass) carried by a
body at ``tf_body_part`` -- and gives the world transform of each body at the exported
pose. Everything below reads that one list:

* :func:`kind_props` -- mass properties of each part kind (exact B-rep integration, or
  the catalog mass of a bought part; :func:`kind_mass_props`);
* :func:`body_props` -- combined mass properties per body in the body frame (the one
  body-mass-property function of every family), :func:`body_shares` each part's share;
* :func:`placement_report` -- report.json's ``placement``: what places every instance
  (kind, body, ``tf_body_part``; each body's ``tf_world_body``) and the mass properties
  of every kind and body, so that the part files placed by it give the body's;
* :func:`bom_rows` -- one BOM line per kind (quantity = number of instances), with its
  ISO 286 fits (:attr:`cad.parts.PartKind.fits`, :mod:`cad.data.fits`);
* :func:`fits_report` / :func:`dxf_notes` -- the same fits for report.json's ``fits`` key
  and the DXF's ``NOTES`` layer;
* :func:`fastener_report` -- every screw's record (thread size, length, parts clamped, hole
  engaged, engagement) and every tapped hole, checked (one screw per hole, engagement in
  the hole's window);
* :func:`check_assembly` -- every pair of solids at the exported pose, by the shared
  checker (:func:`cad.assembly.interference.same_body_check`): a positive common volume is
  a collision;
* :func:`write_part_drawings` -- ``drawings/<part>.svg`` and ``drawings.pdf`` of the made
  parts (``--formats …,drawings``, :mod:`cad.export.drawings`);
* :func:`write_outputs` -- ``parts/<kind>.step|.stl|.dxf`` (each in the frame of the
  kind, the frame ``tf_body_part`` places: :func:`cad.export.export_part`),
  ``assembly.step``, ``bom.csv``, ``preview.png`` (the dispatcher adds ``report.json``
  and ``manifest.json``; :func:`report_md_lines` gives the family's part of ``report.md``).

The output layout is the same for every family (docs/build-outputs.md).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from cad.assembly import interference as itf
from cad.assembly.fasteners import check_fasteners
from cad.assembly.steps import Step, assembly_md, assembly_steps
from cad.data.catalog import ring_inertia_kg_m2
from cad.data.fits import shop_holes
from cad.data.materials import get_material
from cad.export import (
    STL_ANGULAR_TOLERANCE_RAD,
    STL_TOLERANCE_MM,
    export_assembly_step,
    export_part,
    write_bom,
)
from cad.export.drawings import SheetPart, write_drawings
from cad.export.gltf import kind_meshes
from cad.export.nesting import (
    nested_stock,
    plan_sheets,
    sheet_designation,
    sheet_name,
    write_sheets,
)
from cad.export.order import bought_designation, stock, stock_is_mass
from cad.export.shapes import placed
from cad.io.atomic import write_text_atomic
from cad.io.escape import md
from cad.massprops.props import combine, from_principal
from cad.occ.bbox import loose_box, tight_box
from cad.parts.part_props import part_mass_props
from cad.pipeline.views import instance_colors
from cad.report.preview import write_preview as write_projections
from cad.report.step_views import STEP_VIEW_FORMATS, write_step_pictures
from cad.tolerances import LOOSE_BOX_MARGIN_MM, VIEW_ANGULAR_TOLERANCE_RAD, VIEW_TOLERANCE_MM

#: Files every build writes at the top of its output folder (``parts/`` holds the rest).
LAYOUT = (
    "assembly.step",
    "bom.csv",
    "report.json",
    "report.md",
    "preview.png",
    "manifest.json",
)


def kinds(instances) -> dict:
    """``{kind name: PartKind}`` in order of first appearance."""
    out: dict = {}
    for inst in instances:
        out.setdefault(inst.kind.name, inst.kind)
    return out


def quantities(instances) -> dict[str, int]:
    q: dict[str, int] = {}
    for inst in instances:
        q[inst.kind.name] = q.get(inst.kind.name, 0) + 1
    return q


#: How :func:`kind_mass_props` got a kind's mass properties (report.json ``placement``).
MASS_SOURCES = {
    "solid": "the solid's volume x the material density",
    "solid, catalog mass": "the solid's distribution scaled to the catalog mass",
    "ring": "the catalog mass as a uniform annulus (r_in, r_out, width), axis z, z 0..width",
    "none": "no mass of its own (counted elsewhere, e.g. the motor shaft inside Jm)",
}


def mass_source(kind) -> str:
    """Key of :data:`MASS_SOURCES` for a part kind (:func:`kind_mass_props`)."""
    if kind.inertia_model in ("none", "ring"):
        return kind.inertia_model
    return "solid" if kind.mass_kg is None else "solid, catalog mass"


def kind_mass_props(kind):
    """MassProps (SI, the kind's own frame: the frame of its solid and of its part files) of
    one :class:`cad.parts.PartKind`, or None when it carries no mass of its own.

    ``"solid"``: exact B-rep integration x the material density
    (:func:`cad.parts.part_props.part_mass_props`), scaled to ``kind.mass_kg`` when the
    catalog gives the mass; ``"ring"``: the catalog mass as a uniform annulus
    (:func:`cad.data.catalog.ring_inertia_kg_m2`, COM at z = width / 2); ``"none"``: None.
    """
    if kind.inertia_model == "none":
        return None
    if kind.inertia_model == "ring":
        ri, ro, b = kind.ring_mm
        ia, it = ring_inertia_kg_m2(kind.mass_kg, ri, ro, b)
        return from_principal(
            kind.mass_kg, np.array([0.0, 0.0, b / 2 * 1e-3]), np.array([it, it, ia])
        )
    props = part_mass_props(kind.shape, get_material(kind.material).density_kg_m3)
    if kind.mass_kg is not None:
        props = props.scaled(kind.mass_kg / props.mass_kg)
    return props


def kind_props(instances) -> dict:
    """``{kind name: MassProps | None}`` (SI, part frame) of every kind of the assembly
    (:func:`kind_mass_props`)."""
    return {name: kind_mass_props(k) for name, k in kinds(instances).items()}


def _in_body_frame(inst, mp):
    T = inst.tf_body_part
    return mp.transformed(T[:3, :3], T[:3, 3] * 1e-3)


def body_props(instances, props: dict, bodies=None) -> dict:
    """``{body: MassProps}`` combined in the body frame (SI), for ``bodies`` (default all).

    instances : :class:`cad.parts.PartInstance` (``tf_body_part`` mm); props : ``{kind
    name: MassProps | None}`` in each kind's frame (:func:`kind_props`). Each instance's
    properties are moved into its body frame and combined (parallel axes,
    :func:`cad.massprops.props.combine`), in instance order."""
    per: dict[str, list] = {}
    for inst in instances:
        mp = props[inst.kind.name]
        if mp is None or (bodies is not None and inst.body not in bodies):
            continue
        per.setdefault(inst.body, []).append(_in_body_frame(inst, mp))
    return {b: combine(v) for b, v in per.items()}


def body_shares(instances, props: dict) -> dict[str, list[dict]]:
    """``{body: [{"part": instance, "kind": kind, "mass_g": g}, ...]}``: what each instance
    with mass adds to its body (:func:`body_props`), in instance order."""
    out: dict[str, list[dict]] = {}
    for inst in instances:
        mp = props[inst.kind.name]
        if mp is not None:
            out.setdefault(inst.body, []).append(
                {"part": inst.name, "kind": inst.kind.name, "mass_g": mp.mass_kg * 1e3})
    return out


def placement_report(instances, tf_world_body: dict, props: dict) -> dict:
    """report.json's ``placement``: everything needed to place each part file and recover
    the bodies' mass properties from them.

    Returns ``{"frames": text, "mass_sources": MASS_SOURCES,
    "instances": {name: {"kind", "body", "tf_body_part"}},
    "tf_world_body": {body: 4x4}, "kinds": {kind: {"file", "mass_source", "material",
    "mass_props"}}, "bodies": {body: MassProps.to_dict()}}``: transforms are 4x4 lists in
    mm (``tf_world_part = tf_world_body @ tf_body_part``, at the exported pose); a kind's
    ``mass_props`` (SI, its own frame = the frame of ``parts/<kind>.step``) as
    :func:`kind_mass_props` gives it (None without mass), ``file`` its STEP when STEP is
    written (None: a kind not listed, which has no file); ``bodies`` the sums of
    :func:`body_props` in each body frame."""
    ks = kinds(instances)
    return {
        "frames": "mm; tf_world_part = tf_world_body[body] @ tf_body_part; parts/<kind>.step "
                  "is in the kind's frame; mass properties SI (com_mm in mm), body frames",
        "mass_sources": dict(MASS_SOURCES),
        "instances": {
            i.name: {"kind": i.kind.name, "body": i.body,
                     "tf_body_part": np.asarray(i.tf_body_part, dtype=float).tolist()}
            for i in instances
        },
        "tf_world_body": {
            b: np.asarray(tf_world_body[b], dtype=float).reshape(4, 4).tolist()
            for b in dict.fromkeys(i.body for i in instances)
        },
        "kinds": {
            n: {"file": f"parts/{n}.step" if k.listed else None, "mass_source": mass_source(k),
                "material": k.material,
                "mass_props": None if props.get(n) is None else props[n].to_dict()}
            for n, k in ks.items()
        },
        "bodies": {b: mp.to_dict() for b, mp in body_props(instances, props).items()},
    }


def bom_rows(instances, props: dict, formats=None) -> list[dict]:
    """One row per listed kind: part, description, material, quantity, made_or_bought,
    process, fits (its ISO 286 fits joined by ``"; "``), mass_g (each), and what to order
    (:mod:`cad.export.order`): group, designation and order_code of a bought part (a made
    part: group ``"made"``, designation = its name), stock of a made part
    (:func:`kind_stock`, the one stock every file states).

    ``formats`` (the build's ``--formats``; None: as if every format were written): without
    ``dxf`` the nested sheets are planned but not written, and the rows that name ``sheets/``
    say so (:func:`unwritten_sheets`)."""
    q = quantities(instances)
    sheets = None
    if laser_kinds(instances):

        sheets = plan_sheets(instances)
    stocks = kind_stock(instances, props, sheets)
    rows = []
    for name, k in kinds(instances).items():
        if not k.listed:
            continue
        mp = props.get(name)
        mass_g = mp.mass_kg * 1e3 if mp is not None else 0.0
        group, des, code = bought_designation(k) if not k.made else ("made", name, "")
        rows.append(
            {
                "part": name,
                "description": k.description,
                "material": k.material,
                "quantity": q[name],
                "made_or_bought": "made" if k.made else "bought",
                "process": k.process,
                "fits": "; ".join(k.fits),
                "mass_g": mass_g,
                "group": group,
                "designation": des,
                "order_code": code,
                "stock": stocks.get(name, ""),
            }
        )
    if sheets is not None:
        rows += sheet_rows(sheets)
        if formats is not None and "dxf" not in formats:
            rows = [unwritten_sheets(r) for r in rows]
    return rows


def kind_stock(instances, props: dict | None = None, sheets=None) -> dict[str, str]:
    """``{kind name: stock text}`` of every made, listed kind: the one stock of a build, which
    the BOM, ``order.csv``, the drawings' title blocks and the DXF notes all state.

    A laser-cut part's stock is the sheet it is nested on and the order line of that sheet
    (:func:`cad.export.nesting.nested_stock`, ``"nested on sheet_01, ordered as sheet 6 x 500 x
    300 mm aluminium-5083"``; ``sheets`` from
    :func:`cad.export.nesting.plan_sheets`, planned here when None); any other part's is
    :func:`cad.export.order.stock` of the kind with its mass (g): ``props[name]`` (:func:`kind_props`)
    or, when ``props`` is None (a writer running beside the mass properties), the same
    :func:`kind_mass_props`, computed only for the parts whose stock is a mass (printed, wound)."""
    made = {n: k for n, k in kinds(instances).items() if k.listed and k.made}
    out = {}
    # kinds that share one solid and every field stock() reads (the twin's two capstans, one
    # shape object) are measured once: the same inputs, the same text; ``made`` holds every
    # kind, so no id() is reused while this runs
    same: dict[tuple, str] = {}
    for name, k in made.items():
        mass_g = 0.0
        if stock_is_mass(k):
            mp = props.get(name) if props is not None else kind_mass_props(k)
            mass_g = mp.mass_kg * 1e3 if mp is not None else 0.0
        key = (id(k.shape), k.material, k.process, k.plate, k.description, mass_g)
        out[name] = same[key] if key in same else same.setdefault(key, stock(k, mass_g))
    if any(n in made for n in laser_kinds(instances)):

        if sheets is None:
            sheets = plan_sheets(instances)
        for i, s in enumerate(sheets):
            for p in s.parts:
                if p.kind.name in out:
                    out[p.kind.name] = nested_stock(i, s)
    return out


#: What a BOM row says of ``sheets/`` when the build wrote no DXF.
SHEETS_NOT_WRITTEN = "sheets/: not written, add dxf to --formats"


def unwritten_sheets(row: dict) -> dict:
    """``row`` with its mentions of the ``sheets/`` folder (``nested: sheets/``,
    ``(sheets/)``) saying that folder was not written."""
    out = dict(row)
    for key in ("description", "process"):
        out[key] = (out[key].replace("nested: sheets/", f"nested, {SHEETS_NOT_WRITTEN}")
                    .replace("(sheets/)", f"({SHEETS_NOT_WRITTEN})"))
    return out


def laser_kinds(instances) -> dict:
    """``{kind name: PartKind}`` of the laser-cut kinds (``sheet_mm`` set, process "laser")."""
    return {n: k for n, k in kinds(instances).items() if getattr(k, "sheet_mm", None) is not None}


def sheet_rows(sheets) -> list[dict]:
    """BOM rows of the stock sheets the laser-cut parts are nested on
    (:func:`cad.export.nesting.plan_sheets`): one bought row per material, thickness and size,
    quantity = number of sheets."""

    rows: dict = {}
    notes: dict = {}
    des_of: dict = {}
    for i, s in enumerate(sheets):
        key = (s.material, s.thickness_mm, tuple(s.size_mm))
        rows.setdefault(key, []).append(sheet_name(i))
        notes[key], des_of[key] = s.size_note(), sheet_designation(s)
    out = []
    for (mat, t, (w, h)), names in rows.items():
        des = des_of[(mat, t, (w, h))]
        out.append({"part": f"sheet_{t:g}x{w:g}x{h:g}mm_{mat}", "description": f"stock {des}, laser-cut parts "
                    f"nested on {', '.join(names)} (sheets/); {notes[(mat, t, (w, h))]}", "material": mat,
                    "quantity": len(names), "made_or_bought": "bought",
                    "process": "bought: sheet stock for the laser-cut parts", "fits": "",
                    "mass_g": 0.0, "group": "sheet stock", "designation": des, "order_code": "",
                    "stock": ""})
    return out


def fits_report(instances) -> dict[str, list[str]]:
    """report.json's ``fits``: ``{kind name: [fit, ...]}`` of every listed kind that states
    ISO 286 fits (:func:`cad.data.fits.fit`, e.g. ``"bearing seat 16 J7"``)."""
    return {n: list(k.fits) for n, k in kinds(instances).items() if k.listed and k.fits}


def dxf_notes(kind) -> tuple[str, ...]:
    """The text lines of a part's DXF ``NOTES`` layer: each of its fits + ``" (ISO 286)"``."""
    return tuple(f"{f} (ISO 286)" for f in kind.fits)


def kind_threads(kind_name: str, instances, holes) -> tuple[tuple[str, float | None], ...]:
    """``((thread size, full-thread depth mm or None), ...)`` of the tapped holes
    (:class:`cad.assembly.fasteners.TappedHole`) in the instances of kind ``kind_name``."""
    names = {i.name for i in instances if i.kind.name == kind_name} | {kind_name}
    return tuple(
        (h.size, h.depth_mm if math.isfinite(h.depth_mm) else None)
        for h in holes
        if h.part in names
    )


def kind_thread_places(kind_name: str, instances, holes) -> tuple[tuple, ...]:
    """``((size, full-thread depth mm or None, name, axis, point_mm), ...)`` of the tapped
    holes in the instances of kind ``kind_name`` (:func:`kind_threads` with each record's name
    and its place in the part frame, None when unstated: the drawing's callouts)."""
    names = {i.name for i in instances if i.kind.name == kind_name} | {kind_name}
    return tuple(
        (h.size, h.depth_mm if math.isfinite(h.depth_mm) else None, h.name,
         getattr(h, "axis", None), getattr(h, "point_mm", None))
        for h in holes
        if h.part in names
    )


def shop_args(kind, instances, holes=(), stocks: dict | None = None) -> dict:
    """The shop data of one kind's files (:func:`cad.export.export_part`): DXF notes (its
    fits), its holes as the shop makes them (:func:`cad.data.fits.shop_holes`), its
    material, quantity and stock (``stocks``: :func:`kind_stock` of ``instances``, computed
    here when None)."""
    return {
        "notes": dxf_notes(kind),
        "holes": shop_holes(kind.fits, kind_threads(kind.name, instances, holes)),
        "material": kind.material,
        "quantity": quantities(instances).get(kind.name, 0),
        "stock": (stocks if stocks is not None else kind_stock(instances)).get(kind.name, ""),
    }


def write_part_drawings(instances, out_dir: Path, design: str, holes=(),
                        sheets_written: bool = True, stocks: dict | None = None) -> list[str]:
    """``drawings/<part>.svg`` per made, listed kind and ``drawings.pdf``
    (:func:`cad.export.drawings.write_drawings`); returns the paths relative to ``out_dir``.
    ``sheets_written`` False (no ``dxf``): a process naming ``sheets/`` says, as the BOM
    does, that the folder was not written. ``stocks``: :func:`kind_stock` of ``instances``
    (computed here when None)."""
    def process(k) -> str:
        if sheets_written or not k.process:
            return k.process
        return unwritten_sheets({"description": "", "process": k.process})["process"]

    q = quantities(instances)
    stocks = stocks if stocks is not None else kind_stock(instances)
    parts = [
        SheetPart(k.name, k.shape, k.material, q[k.name], process(k), k.plate, k.fits,
                  kind_thread_places(k.name, instances, holes), k.description, stocks[k.name])
        for k in kinds(instances).values()
        if k.listed and k.made
    ]
    if not parts:
        return []
    out_dir = Path(out_dir)
    return [p.relative_to(out_dir).as_posix() for p in write_drawings(parts, out_dir, design)]


def part_materials(instances) -> dict[str, str]:
    """``{instance name: material}`` of every solid of ``assembly.step`` (names as written
    there), for report.json: ``hapticad massprops assembly.step`` applies them per solid."""
    return {inst.name: inst.kind.material for inst in instances}


def fastener_report(instances, holes: dict) -> dict:
    """``{"fasteners": {instance: record}, "tapped_holes": {name: hole}}`` for report.json,
    after :func:`cad.assembly.fasteners.check_fasteners` (one screw per hole, engagement in
    the hole's window; DesignError naming the screw and hole otherwise)."""
    fast = {i.name: i.fastener for i in instances if i.fastener is not None}
    check_fasteners(fast, holes)
    return {
        "fasteners": {n: f.as_dict() for n, f in fast.items()},
        "tapped_holes": {n: h.report() for n, h in holes.items()},
    }


def world_tf(inst, tf_world_body: dict) -> np.ndarray:
    """4x4 world placement of an instance (``tf_world_body``: body -> 4x4)."""
    return np.asarray(tf_world_body[inst.body], dtype=float) @ inst.tf_body_part


def posed_items(instances, tf_world_body: dict, listed_only: bool = True) -> list[tuple]:
    """``[(instance name, placed TopoDS_Shape, rgb)]`` at the exported pose."""
    out = []
    for inst in instances:
        if listed_only and not inst.kind.listed:
            continue
        rgb = get_material(inst.kind.material).color_rgb
        out.append((inst.name, placed(inst.kind.shape, world_tf(inst, tf_world_body)), rgb))
    return out


def check_assembly(instances, tf_world_body: dict) -> dict:
    """Every pair of solids at the exported pose, same-body pairs included, by the shared
    checker :func:`cad.assembly.interference.same_body_check`: every instance is placed in
    the world and handed over as one rigid set, so each pair is compared once (tight OCCT
    boxes, then the boolean common; touching is allowed, a common volume above
    ``OVERLAP_MIN_MM3`` is a collision). Returns ``{"parts", "pairs", "exact_pairs",
    "collisions", "overlap_volume_mm3", "overlap_threshold_mm3"}``."""
    items = [
        (inst.name, "assembly", inst.kind.shape, world_tf(inst, tf_world_body), inst.kind.hull)
        for inst in instances
    ]
    res = itf.same_body_check(items)
    collisions = [
        {"parts": c["parts"], "overlap_volume_mm3": c["overlap_volume_mm3"]}
        for c in sorted(res.collisions, key=lambda c: -c["overlap_volume_mm3"])
    ]
    return {
        "parts": len(items),
        "pairs": res.n_pairs,
        "exact_pairs": res.n_box_overlaps,
        "collisions": collisions,
        "overlap_volume_mm3": float(sum(c["overlap_volume_mm3"] for c in collisions)),
        "overlap_threshold_mm3": itf.OVERLAP_MIN_MM3,
    }


def lowest_z_mm(instances, tf_world_body: dict) -> tuple[float, str]:
    """Lowest world z of any solid (from its exact bounding box, mm) and the instance there
    (the first in ``instances`` on a tie). The exact boxes are made in the order of the fast
    boxes' bottoms and stop where a fast bottom, less :data:`LOOSE_BOX_MARGIN_MM`, is above
    the lowest exact one found: a solid there cannot be lower, nor tie (same answer as every
    exact box, a fraction of the OCCT work)."""
    shapes = [placed(inst.kind.shape, world_tf(inst, tf_world_body)) for inst in instances]
    lo = [float(loose_box(s)[0, 2]) - LOOSE_BOX_MARGIN_MM for s in shapes]
    best = (math.inf, len(shapes))
    for i in sorted(range(len(shapes)), key=lambda k: lo[k]):
        if lo[i] > best[0]:
            break
        best = min(best, (float(tight_box(shapes[i])[0, 2]), i))
    return (best[0], instances[best[1]].name) if best[1] < len(shapes) else (math.inf, "")


def write_preview(instances, tf_world_body: dict, out: Path, title: str, marks=None,
                  hide_ground_below_mm: float | None = None) -> Path:
    """Top (x-y) and side (x-z) projections of the posed assembly, PNG, one colour per body
    (:func:`cad.report.preview.write_preview`). ``marks``: optional ``(label, (N, 2) xy
    points)`` drawn as a line on the top view (a path, a workspace);
    ``hide_ground_below_mm``: ground parts under this z (mm) are left out of the top view."""
    return write_projections(instances, tf_world_body, out, title, marks=marks or (),
                             hide_ground_below_mm=hide_ground_below_mm)


def write_outputs(
    instances,
    tf_world_body: dict,
    out_dir: Path,
    formats: set[str],
    *,
    name: str,
    title: str,
    bom: list[dict] | None,
    stl_tolerance_mm: float | None = None,
    angular_tolerance_rad: float | None = None,
    marks=None,
    preview: bool = True,
    holes=(),
    hide_ground_below_mm: float | None = None,
) -> list[str]:
    """Part files, assembly STEP, BOM and preview of one assembly; returns the paths written
    (relative to ``out_dir``).

    instances : :class:`cad.parts.PartInstance`; tf_world_body : ``{body: (4, 4)}`` mm at
    the exported pose (assembly STEP, preview). Every ``parts/<kind>.*`` file is in the
    kind's own frame, the frame ``tf_body_part`` places (:func:`cad.export.export_part`).
    bom : the rows of ``bom.csv`` (None: not written here). stl_tolerance_mm,
    angular_tolerance_rad : STL deflections (default :data:`cad.export.STL_TOLERANCE_MM`,
    :data:`cad.export.STL_ANGULAR_TOLERANCE_RAD`). holes : the tapped holes
    (:class:`cad.assembly.fasteners.TappedHole`) for the DXF thread notes. preview,
    marks, hide_ground_below_mm : write ``preview.png`` (:func:`write_preview`).
    Raises MeshError (a part's mesh not watertight: nothing of that part written)."""
    out_dir = Path(out_dir)
    files: list[str] = []
    stocks = kind_stock(instances) if {"dxf", "drawings"} & set(formats) else {}
    for k in kinds(instances).values():
        if not k.listed:
            continue
        paths = export_part(
            k.shape,
            k.name,
            out_dir / "parts",
            formats,
            plate=k.plate,
            color=get_material(k.material).color_rgb,
            stl=k.made,
            tolerance_mm=stl_tolerance_mm or STL_TOLERANCE_MM,
            angular_tolerance_rad=angular_tolerance_rad or STL_ANGULAR_TOLERANCE_RAD,
            **shop_args(k, instances, holes, stocks),
        )
        files += [p.relative_to(out_dir).as_posix() for p in paths]
    if "dxf" in formats and laser_kinds(instances):

        files += write_sheets(instances, out_dir,
                              {n: shop_args(k, instances, holes, stocks)
                               for n, k in laser_kinds(instances).items()})
    if "drawings" in formats:
        files += write_part_drawings(instances, out_dir, name, holes, sheets_written="dxf" in formats,
                                     stocks=stocks)
    if "step" in formats:
        export_assembly_step(
            posed_items(instances, tf_world_body, listed_only=False),
            out_dir / "assembly.step",
            f"{name}_assembly",
        )
        files.append("assembly.step")
    if bom is not None:
        write_bom(bom, out_dir)
        files.append("bom.csv")
    if not preview:
        return files
    write_preview(instances, tf_world_body, out_dir / "preview.png", title, marks,
                  hide_ground_below_mm)
    return files + ["preview.png"]


def report_md_lines(title: str, rows: list[tuple[str, str]], bom, notes=(),
                    images=()) -> list[str]:
    """The family's part of ``report.md`` (the dispatcher, :func:`cad.pipeline.build_design`,
    writes the file once, with the datasheet after the title and the order at the end):
    title, preview (and ``images``: ``(alt text, file)`` pairs after it), a quantity table,
    the BOM and notes."""
    lines = [f"# {md(title)}", "", "![assembly preview](preview.png)", ""]
    for alt, file in images:
        lines += [f"![{alt}]({file})", ""]
    lines.append("| quantity | value |")
    lines.append("|---|---|")
    lines += [f"| {md(k)} | {md(v)} |" for k, v in rows]
    lines += [
        "",
        "## Bill of materials",
        "",
        "| part | description | material | qty | made/bought | process | mass (g) |",
    ]
    lines.append("|---|---|---|---|---|---|---|")
    for b in bom:
        lines.append(
            f"| {md(b['part'])} | {md(b['description'])} | {md(b['material'])} | {b['quantity']} | "
            f"{b['made_or_bought']} | {md(b['process'])} | {b['mass_g']:.2f} |"
        )
    if notes:
        lines += ["", "## Notes", ""] + [f"- {md(n)}" for n in notes]
    return lines


#: Title of the assembly step before the final checks: BOM lines with no solid in the model
#: (the encoder).
NO_SOLID_STEP = "fit the bought parts that have no modelled solid"


def build_steps(instances, plan=None, checks=(), no_solid_rows=()) -> list:
    """The :class:`cad.assembly.steps.Step` list of :func:`write_assembly_md` (fasteners
    named by their BOM designation; ``no_solid_rows`` in a step of their own before the final
    checks, which turn the joints the encoders read)."""
    def designation(kind) -> str:
        return bought_designation(kind)[1] if not kind.made else kind.description or kind.name

    steps = assembly_steps(instances, designation, plan, checks)
    if no_solid_rows:
        at = len(steps) - 1 if steps and steps[-1].title == "final checks" else len(steps)
        steps.insert(at, Step(NO_SOLID_STEP, list(_no_solid_names(no_solid_rows))))
    return steps


def _no_solid_names(rows) -> dict[str, tuple[str, str]]:
    """``{instance name: (part, description)}`` of BOM rows with no solid: one instance per
    unit of the row's quantity (``encoder``, or ``encoder_1`` ... ``encoder_n``; a row's own
    ``instance_names`` when it has them, one per unit: e.g. the delta's encoders numbered as
    its motors, ``encoder_0`` ... ``encoder_2``)."""
    out = {}
    for r in rows:
        q = int(r.get("quantity", 1))
        names = [r["part"]] if q == 1 else [f"{r['part']}_{i}" for i in range(1, q + 1)]
        if r.get("instance_names"):
            names = list(r["instance_names"])
            if len(names) != q:
                raise ValueError(f"{r['part']}: {len(names)} instance_names for quantity {q}")
        out |= {n: (r["part"], r["description"]) for n in names}
    return out


def write_assembly_md(out_dir: Path, title: str, instances, plan=None, checks=(),
                      no_solid_rows=(), *, tf_world_body=None, formats=()) -> list[str]:
    """``assembly.md``: the assembly steps of :func:`cad.assembly.steps.assembly_steps`
    (``plan``: optional stages, ``checks``: the final checks), each part instance named
    with its kind and BOM description; fasteners by their BOM designation. ``no_solid_rows``:
    BOM rows with no part instance (the encoder), placed in a last step of their own.
    With ``tf_world_body`` (``{body: (4, 4)}`` mm, the exported pose) and a fabrication
    format asked (:data:`cad.report.step_views.STEP_VIEW_FORMATS`), an exploded view per step,
    ``steps/step_NN.png`` (:mod:`cad.report.step_views`), linked from its step.
    Returns the files written (relative to ``out_dir``)."""
    by = {i.name: (i.kind.name, i.kind.description) for i in instances}
    by |= _no_solid_names(no_solid_rows)
    steps = build_steps(instances, plan, checks, no_solid_rows)
    images = {}
    if tf_world_body is not None and set(formats) & set(STEP_VIEW_FORMATS):
        images = _step_pictures(steps, instances, tf_world_body, out_dir)
    text = assembly_md(title, steps, by.__getitem__, images)
    write_text_atomic(Path(out_dir) / "assembly.md", text)
    return ["assembly.md", *images.values()]


def _step_pictures(steps, instances, tf_world_body, out_dir: Path) -> dict:
    """The exploded views of :func:`write_assembly_md` at the viewer's mesh tolerances."""
    meshes = kind_meshes(instances, VIEW_TOLERANCE_MM, VIEW_ANGULAR_TOLERANCE_RAD)
    return write_step_pictures(steps, instances, tf_world_body, meshes,
                               instance_colors(instances), out_dir)
