"""Build a four-bar haptic display: parts, masses, H11..H33, interference, exports, report.

Pipeline (``hapticad build designs/hoeken.toml``):

1. kinematics (no CAD): crank angles of the sweep, link transforms, joint positions in
   each link's frame (:mod:`cad.kinematics.linkgeom`);
2. z-layers and joint stacks (:func:`cad.assembly.layers.choose_layers`);
3. parts (:func:`cad.assembly.mechanism.build_assembly`), the handle from a user script
   when ``parts.handle_script`` is set;
4. mass properties per part (exact B-rep integration, :mod:`cad.massprops`; bought parts
   by catalog mass), combined per link in the link frame; H11..H33 and the apparent mass
   M(phi1) (:mod:`cad.dynamics.inertia`, Hoeken paper eqs 14-22) with the motor's rotor
   inertia Jm;
5. interference sweep (:mod:`cad.assembly.interference`): an
   :class:`cad.errors.InterferenceError` unless ``allow_interference``;
6. exports into ``out_dir``: ``parts/<part>.step|.stl|.dxf``, ``assembly.step``,
   ``assembly.glb`` and ``parts.3mf`` when asked, ``bom.csv``, ``preview.png``,
   ``animation.gif`` + ``render.png`` (:mod:`cad.pipeline.views`), ``report.md`` (the
   dispatcher adds ``report.json``, ``report.html`` and ``manifest.json``).

Once the parts exist, the part files + assembly STEP, the preview and the viewer files
(glb, GIF, still) are written by three forked child processes while this process does steps 4-5 (:mod:`cad.pipeline.forked`; serial
where forking is off, same bytes either way).

Fidelity (issue 7): ``fabrication`` -- every feature, bd_warehouse bearings with balls,
exact interference confirmation; ``inertia`` -- cosmetic features dropped (knob round,
bearing balls: the bearing mass is the catalog mass at every fidelity), exact
interference; ``preview`` -- as ``inertia`` with STL at 0.1 mm, at most
:data:`PREVIEW_POSES` poses and a mesh-only interference sweep. The report states what
the dropped features cost on this design (``fidelity_costs``).
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from cad.errors import DesignError

#: Source the output depends on (build cache key): any change there rebuilds.
CODE_DEPS = (
    "pipeline",
    "families",
    "datasheet",
    "firmware",  # --formats firmware (cad/firmware)
    "report",  # report.html, the stroke GIF and render (cad/report)
    "parts",
    "assembly",
    "export",
    "massprops",
    "kinematics",
    "dynamics",
    "structure",
    "design",
    "io",
    "data",
    "analysis.py",
    "tolerances.py",
    "errors.py",
    "__init__.py",
)
#: Poses and STL tolerance of the preview fidelity.
PREVIEW_POSES = 24
#: This builder writes the simulator formats (mjcf, urdf; :mod:`cad.families.fourbar.sim`).
SIM_EXPORT = True
#: This builder writes glb and 3mf (:mod:`cad.pipeline.views`).
VIEW_EXPORT = True
PREVIEW_STL_TOL_MM = 0.1
LINKS = ("crank", "coupler", "rocker")
BODY_COLORS = {"ground": "#9aa0a6", "crank": "#d9534f", "coupler": "#337ab7", "rocker": "#5cb85c"}


def cache_inputs(design) -> dict:
    """Inputs outside the design object: the user handle script's content."""
    from cad.parts.handle import resolve_script, script_sha256

    p = resolve_script(design.parts, design.source)
    return {"handle_script_sha256": script_sha256(p) if p is not None else None}


def _step(progress, desc: str, i: int, n: int) -> None:
    if progress is not None:
        progress(desc, i, n)


def sweep_angles(design, n: int) -> np.ndarray:
    return np.linspace(design.phi1_min_rad, design.phi1_max_rad, n)


def _kind_props(kind):
    """MassProps of a part kind in its own frame (SI), or None when it carries no mass."""
    from cad.data.catalog import ring_inertia_kg_m2
    from cad.data.materials import get_material
    from cad.massprops.props import from_principal
    from cad.parts.part_props import part_mass_props

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


#: Public name of :func:`_kind_props` (used by :mod:`cad.pipeline.inertia`).
kind_mass_props = _kind_props


def encoder_bom_row(design) -> dict:
    """The crank encoder as a bought BOM line (no solid: it sits on the motor's rear shaft),
    from the datasheet's encoder choice (:func:`cad.families.fourbar.datasheet.encoder_counts`); its
    mass is not in the catalog (0 in the totals, said in the description)."""
    from cad.data import catalog
    from cad.families.fourbar.datasheet import encoder_counts, lever

    counts, src, key = encoder_counts(design, lever(design, 3)[1])
    enc = catalog.get_encoder(key) if key is not None else None
    desc = enc.description if enc is not None else f"encoder on the motor's rear shaft, {counts:.0f} counts/rev"
    return {"part": "encoder", "description": f"{desc} ({src.split(';')[0]}; mass not known, not in the totals)",
            "material": "bought", "quantity": 1, "made_or_bought": "bought", "process": "bought",
            "fits": "", "mass_g": 0.0, "group": "encoders",
            "designation": desc, "order_code": getattr(enc, "order_code", "") or "", "stock": ""}


def link_mass_props(assembly, props_by_kind: dict) -> tuple[dict, dict]:
    """Per body: combined MassProps in the body (link) frame, and each part's share (g)."""
    from cad.massprops.props import combine

    per_body: dict[str, list] = {}
    shares: dict[str, list] = {}
    for inst in assembly.instances:
        mp = props_by_kind[inst.kind.name]
        if mp is None:
            continue
        T = inst.tf_body_part
        per_body.setdefault(inst.body, []).append(mp.transformed(T[:3, :3], T[:3, 3] * 1e-3))
        shares.setdefault(inst.body, []).append(
            {"part": inst.name, "kind": inst.kind.name, "mass_g": mp.mass_kg * 1e3}
        )
    return {b: combine(v) for b, v in per_body.items()}, shares


def inertia_from_links(design, link_props: dict, Jm_kg_m2: float):
    """H11..H33 (Hoeken paper eqs 16-19, COM angle generalization) from the link mass props."""
    from cad.dynamics.inertia import PlanarLinkInertia, h_from_links

    pl = {
        k: PlanarLinkInertia.from_com(
            link_props[k].mass_kg, link_props[k].com_m, float(link_props[k].inertia_com_kg_m2[2, 2])
        )
        for k in LINKS
    }
    return h_from_links(design.linkage, pl["crank"], pl["coupler"], pl["rocker"], Jm_kg_m2), pl


def apparent_mass(design, H) -> dict:
    from cad.analysis import apparent_mass_curves
    from cad.dynamics.inertia import apparent_mass_summary

    return apparent_mass_summary(apparent_mass_curves(design, H)["M_kg"])


def _joint_axes(J) -> dict:
    return {
        ("crank", "ground"): [(J["crank"]["A1"], J["ground"]["A1"])],
        ("coupler", "crank"): [(J["coupler"]["A2"], J["crank"]["A2"])],
        ("coupler", "rocker"): [(J["coupler"]["A3"], J["rocker"]["A3"])],
        ("ground", "rocker"): [(J["ground"]["A4"], J["rocker"]["A4"])],
    }


def write_preview(asm, tf_world_body, i: int, path_P_mm: np.ndarray, out: Path, title: str) -> Path:
    """``preview.png`` of the four-bar at pose ``i`` of ``tf_world_body`` (``{body: (N, 4,
    4)}`` mm) with the coupler point's path ``path_P_mm`` (N, 2) on the top view
    (:func:`cad.report.preview.write_preview`; what lies under the base plate is left out of
    the top view)."""
    from cad.report.preview import write_preview as write_projections

    pose = {b: np.asarray(T)[i] for b, T in tf_world_body.items()}
    return write_projections(
        asm.instances, pose, out, title, marks=[("P path", path_P_mm)], hide_ground_below_mm=-1.0
    )


#: Final checks of assembly.md (cad.assembly.steps).
ASSEMBLY_CHECKS = (
    "the crank turns by hand over its whole range (report.md: crank range) with no binding "
    "and no contact between the bars",
    "the motor turns the crank with the hub's set screw tight (no slip on the shaft flat)",
)


def _write_exports(
    asm, listed, out_dir: Path, formats, stl_tol, ang, tf_pose, name: str, progress, n_steps
) -> list[str]:
    """Part files (STEP/STL/DXF) and the posed assembly STEP; returns their paths in out_dir."""
    from cad.data.materials import get_material
    from cad.export import export_assembly_step, export_part
    from cad.pipeline.family import shop_args

    files: list[str] = []
    for k in listed:
        _step(progress, f"export {k.name}", 4, n_steps)
        paths = export_part(
            k.shape,
            k.name,
            out_dir / "parts",
            formats,
            plate=k.plate,
            color=get_material(k.material).color_rgb,
            stl=k.made,
            tolerance_mm=stl_tol,
            angular_tolerance_rad=ang,
            **shop_args(k, asm.instances, asm.holes),
        )
        files += [p.relative_to(out_dir).as_posix() for p in paths]
    if "drawings" in formats:
        from cad.pipeline.family import write_part_drawings

        files += write_part_drawings(asm.instances, out_dir, name, asm.holes)
    if "step" in formats:
        _step(progress, "assembly STEP", 5, n_steps)
        from cad.assembly.pose import posed_shapes

        export_assembly_step(
            posed_shapes(asm.instances, tf_pose, 0, listed_only=False),  # with the motor shaft
            out_dir / "assembly.step",
            name=f"{name}_assembly",
        )
        files.append("assembly.step")
    if "3mf" in formats:
        from cad.pipeline.views import write_parts_3mf

        files.append(
            write_parts_3mf(
                asm.instances, out_dir, title=name, tolerance_mm=stl_tol, angular_tolerance_rad=ang
            )
        )
    return files


def _write_sim(design, asm, link_props, Jm, motor, phi1_rad, out_dir: Path, formats) -> list[str]:
    """``<name>.xml`` (MJCF) / ``<name>.urdf`` when asked (:mod:`cad.families.fourbar.sim`)."""
    from cad.export.sim import SIM_FORMATS, write_sim_files

    if not set(formats) & set(SIM_FORMATS):
        return []
    from cad.families.fourbar.sim import sim_model

    model = sim_model(design, asm, link_props, Jm, motor, phi1_rad)
    paths = write_sim_files(model, out_dir, formats, design.name)
    return [p.relative_to(out_dir).as_posix() for p in paths]


def _n_poses(parts, fidelity: str) -> int:
    """Crank angles of the layer planning and the interference sweep."""
    if fidelity == "preview":
        return min(parts.interference_poses, PREVIEW_POSES)
    return parts.interference_poses


def check_layout(design, fidelity: str, allow_interference: bool) -> None:
    """Refuse, before any CAD import, a hub wall no ISO 4026 set screw fits
    (:func:`cad.assembly.layers.hub_set_screw`, DesignError naming ``parts.hub_diameter_mm``),
    plates no catalog cap screw fits (:func:`cad.assembly.mechanism.check_plate_screws`,
    naming the plate's field), and a design whose joint hardware has no clear layer order
    (:func:`_plan_layers`) or whose jointed bars sit closer than ``parts.clearance_min_mm``
    (:func:`_check_joint_gaps`); the last two skipped with ``allow_interference``: the build
    then exports the clash and reports it)."""
    from cad.assembly.layers import hub_set_screw
    from cad.assembly.mechanism import check_plate_screws

    hub_set_screw(design.parts)
    check_plate_screws(design.parts)
    if allow_interference:
        return
    from cad.assembly.pose import planar_transforms
    from cad.kinematics.linkgeom import link_joints_mm

    n = _n_poses(design.parts, fidelity)
    planar = planar_transforms(design.linkage, sweep_angles(design, n))
    plan = _plan_layers(design, link_joints_mm(design.linkage), planar, n, strict=True)
    _check_joint_gaps(plan, design.parts)


def _check_joint_gaps(plan, parts) -> None:
    """DesignError naming ``parts.layer_gap_mm`` when two bars jointed to each other lie on
    adjacent layers less than ``parts.clearance_min_mm`` apart.

    Both bars surround their common pin, so they overlap in plan at every pose and their
    layer gap is their distance all through the stroke: the interference sweep
    (:func:`cad.assembly.interference.raise_on_collision`) would refuse the build at every
    pose, after the CAD work (``layer_gap_mm = 0.002`` typed in metres).
    """
    from cad.assembly.layers import JOINTS

    level = {name: i for i, name in enumerate(plan.order)}
    for joint, (a, b) in JOINTS.items():
        if b not in level or abs(level[a] - level[b]) != 1:
            continue
        gap = plan.gaps_mm[min(level[a], level[b])]
        if gap < parts.clearance_min_mm - 1e-9:
            raise DesignError(
                "parts.layer_gap_mm",
                f"{parts.layer_gap_mm:g} mm leaves the {a} and the {b} (jointed at {joint}, "
                f"adjacent layers) {gap:g} mm apart at every pose, below parts.clearance_min_mm "
                f"= {parts.clearance_min_mm:g} mm; use layer_gap_mm >= "
                f"{parts.clearance_min_mm:g} (or --allow-interference)",
            )


def _plan_layers(design, J, planar, n_poses: int, strict: bool):
    """:func:`cad.assembly.layers.choose_layers`; when ``strict`` and no layer order is clear,
    the refusal (before any CAD import) names the joint and parts and, for a family scaled
    by ``stroke_mm``, the smallest stroke whose layout is clear (the crank length with it)."""
    from cad.assembly.layers import NoLayout, choose_layers, clearing_stroke_mm

    try:
        return choose_layers(J, design.parts, planar, strict=strict)
    except NoLayout as e:
        s = getattr(design, "stroke_mm_requested", None)
        if e.field != "mechanism":
            raise
        if s is None:
            raise DesignError(e.field, e.reason + "; lengthen the crank (l1_mm) or shrink "
                              "parts.hub_diameter_mm / the joint hardware") from None
        s_ok = clearing_stroke_mm(design.family, s, design.parts, n_poses)
        l1 = design.linkage.l1_mm
        hint = (
            f"; stroke_mm >= {s_ok:g} clears it (crank l1 {l1:.2f} -> {l1 * s_ok / s:.2f} mm)"
            if s_ok is not None else "; no stroke up to 3x clears it"
        )
        raise DesignError("mechanism.stroke_mm", f"{s:g} mm: {e.reason}{hint}, or shrink "
                          "parts.hub_diameter_mm / the joint hardware") from None


def build(
    design,
    out_dir: Path,
    formats: set[str],
    *,
    fidelity: str = "fabrication",
    allow_interference: bool = False,
    progress=None,
    phi1_deg: float | None = None,
) -> dict:
    """Build ``design`` into ``out_dir`` (a fresh temporary directory); return the report dict."""
    from cad.assembly import interference as itf
    from cad.assembly.layers import footprint_bbox_mm
    from cad.assembly.mechanism import build_assembly
    from cad.assembly.pose import body_transforms, planar_transforms
    from cad.data import catalog
    from cad.kinematics.fourbar import solve
    from cad.kinematics.linkgeom import link_joints_mm
    from cad.kinematics.metrics import compute_metrics
    from cad.parts.handle import handle_params, resolve_script, user_handle_shape

    timings: dict[str, float] = {}
    t0 = time.perf_counter()
    parts = design.parts
    fb = design.linkage
    n_steps = 8
    if phi1_deg is not None:
        lo, hi = math.degrees(design.phi1_min_rad), math.degrees(design.phi1_max_rad)
        if not lo - 1e-9 <= phi1_deg <= hi + 1e-9:
            raise DesignError(
                "--phi1-deg", f"must lie in the crank range [{lo:g}, {hi:g}] deg, got {phi1_deg!r}"
            )
    script = resolve_script(parts, design.source)

    # 1-2 kinematics and layers (numpy only)
    _step(progress, "layers", 0, n_steps)
    n_poses = _n_poses(parts, fidelity)
    phi = sweep_angles(design, n_poses)
    J = link_joints_mm(fb)
    planar = planar_transforms(fb, phi)
    plan = _plan_layers(design, J, planar, n_poses, strict=not allow_interference)
    footprint = footprint_bbox_mm(plan, planar)
    timings["layers"] = time.perf_counter() - t0

    # 3 parts
    _step(progress, "parts", 1, n_steps)
    t1 = time.perf_counter()
    user_handle = None
    if script is not None:
        floor = plan.handle_screw_length_mm - parts.bar_thickness_mm
        user_handle = user_handle_shape(script, handle_params(parts, floor))
    asm = build_assembly(
        J,
        plan,
        parts,
        footprint,
        fidelity=fidelity,
        handle_shape=user_handle,
        design_label=design.name,
    )
    timings["parts"] = time.perf_counter() - t1

    # 4-6 run side by side (cad.pipeline.forked): the part files and the assembly STEP in one
    # child process, the preview in another, while this process does the mass
    # properties and the interference sweep; any failure cancels the others and nothing
    # is published (the dispatcher owns the temporary out_dir).
    from cad.export import STL_ANGULAR_TOLERANCE_RAD
    from cad.pipeline import forked

    kinds = asm.kinds()
    listed = [k for k in kinds.values() if k.listed]
    stl_tol = (
        parts.stl_tolerance_mm
        if fidelity != "preview"
        else max(parts.stl_tolerance_mm, PREVIEW_STL_TOL_MM)
    )
    ang = (
        math.radians(parts.stl_angular_tolerance_deg)
        if parts.stl_angular_tolerance_deg
        else STL_ANGULAR_TOLERANCE_RAD
    )
    pose_phi = (
        math.radians(phi1_deg)
        if phi1_deg is not None
        else 0.5 * (design.phi1_min_rad + design.phi1_max_rad)
    )
    tf_pose = body_transforms(fb, [pose_phi])
    in_child = forked.fork_enabled()

    def exports_stage() -> tuple[list[str], float]:
        t = time.perf_counter()
        files = _write_exports(
            asm,
            listed,
            out_dir,
            formats,
            stl_tol,
            ang,
            tf_pose,
            design.name,
            None if in_child else progress,
            n_steps,
        )
        return files, time.perf_counter() - t

    def preview_stage() -> float:
        t = time.perf_counter()
        P_path = solve(fb, np.linspace(design.phi1_min_rad, design.phi1_max_rad, 200)).P_mm
        write_preview(
            asm,
            tf_pose,
            0,
            P_path,
            out_dir / "preview.png",
            f"{design.name}: {design.family}, phi1 = {math.degrees(pose_phi):.1f} deg",
        )
        # the paper's plots from the solids: coupler curve, y deviation and torque over the
        # stroke, M11 / M12 / M22 over x (Fig. 6) with H from the parts
        from cad.report.fourbar import plot_apparent_mass, plot_kinematics

        plot_kinematics(design, out_dir / "kinematics.png")
        plot_apparent_mass(design, H, out_dir / "apparent_mass.png")
        return time.perf_counter() - t

    def views_stage() -> tuple[list[str], bytes, float]:
        from cad.pipeline.views import STROKE_POSES, write_views

        t = time.perf_counter()
        stroke = body_transforms(fb, sweep_angles(design, STROKE_POSES))
        files, glb = write_views(
            asm.instances,
            {b: v[0] for b, v in tf_pose.items()},
            stroke,
            out_dir,
            formats,
            name=design.name,
            title=f"{design.name} ({design.family})",
        )
        return files, glb, time.perf_counter() - t

    def same_body_stage():
        return itf.same_body_check(itf.static_items(asm.instances))

    exports_task = forked.start(exports_stage, "exports")
    views_task = forked.start(views_stage, "views")
    same_task = forked.start(same_body_stage, "same-body check")
    with forked.cancel_on_error(exports_task, views_task, same_task):
        # 4 mass properties and dynamics
        _step(progress, "mass properties", 2, n_steps)
        t1 = time.perf_counter()
        props = {name: _kind_props(k) for name, k in kinds.items()}
        link_props, shares = link_mass_props(asm, props)
        motor = catalog.get_motor(parts.motor)
        Jm = (
            parts.motor_rotor_inertia_g_cm2 * 1e-7
            if parts.motor_rotor_inertia_g_cm2 is not None
            else motor.rotor_inertia_kg_m2
        )
        H, planar_links = inertia_from_links(design, link_props, Jm)
        am = apparent_mass(design, H)
        fidelity_costs = _fidelity_costs(
            design, asm, props, link_props, Jm, H, am, fidelity, user_handle is not None, plan
        )
        timings["massprops"] = time.perf_counter() - t1

    # the preview and the paper's plots (which need H) in a second child, beside the sweep
    preview_task = forked.start(preview_stage, "preview")
    with forked.cancel_on_error(exports_task, views_task, preview_task, same_task):
        from cad.structure.device import structure_of_build

        structure = structure_of_build(design, asm, props, am["M11_max_g"])

        # 5 interference
        _step(progress, "interference sweep", 3, n_steps)
        t1 = time.perf_counter()
        tol = itf.SWEEP_MESH_TOL_MM if fidelity != "preview" else PREVIEW_STL_TOL_MM
        prepared = itf.prepare(itf.collision_items(asm.instances), tol)
        tfs = body_transforms(fb, phi)

        def tf_at(p):
            return {b: v[0] for b, v in body_transforms(fb, [p]).items()}

        rep = itf.sweep(
            prepared,
            tfs,
            phi,
            parts.clearance_min_mm,
            exact=fidelity != "preview",
            tf_at=tf_at,
            joints=_joint_axes(J),
        )
        rep = itf.merge_same_body(rep, same_task.result())
        if not allow_interference:
            itf.raise_on_collision(rep, parts.clearance_min_mm)
        timings["interference"] = time.perf_counter() - t1

        # BOM (the rows every family writes, fits included: cad.pipeline.family)
        from cad.export import write_bom
        from cad.pipeline import family

        encoder = encoder_bom_row(design)
        bom = family.bom_rows(asm.instances, props) + [encoder]
        write_bom(bom, out_dir)
        family.write_assembly_md(out_dir, f"{design.name} ({design.family})", asm.instances,
                                 checks=ASSEMBLY_CHECKS, no_solid_rows=[encoder])

        # 6 exports and preview (wait for the children)
        _step(progress, "exports", 4, n_steps)
        files, timings["exports"] = exports_task.result()
        files += _write_sim(design, asm, link_props, Jm, motor, pose_phi, out_dir, formats)
        _step(progress, "preview", 6, n_steps)
        timings["preview"] = preview_task.result()
        view_files, viewer_glb, timings["views"] = views_task.result()

    # report
    _step(progress, "report", 7, n_steps)
    m = compute_metrics(
        fb, design.phi1_min_rad, design.phi1_max_rad, force_N=design.force_N, samples=design.samples
    ).as_dict()
    from cad.analysis import METRIC_KEYS

    report = {
        "name": design.name,
        "source": Path(str(design.source)).name,  # the file name: no path of this machine
        **design.resolved_linkage(),
        "force_N": design.force_N,
        **{k: m[k] for k in METRIC_KEYS if k in m},
        "H11_kg_m2": H.H11_kg_m2,
        "H12_kg_m2": H.H12_kg_m2,
        "H22_kg_m2": H.H22_kg_m2,
        "H33_kg_m2": H.H33_kg_m2,
        "beta2_deg": math.degrees(H.beta2_rad),
        "Jm_kg_m2": Jm,
        "apparent_mass": am,
        "structure": structure,
        "links": {
            k: {
                **link_props[k].to_dict(),
                "mass_g": link_props[k].mass_kg * 1e3,
                "com_link_mm": (np.asarray(link_props[k].com_m) * 1e3).tolist(),
                "lG_mm": planar_links[k].lG_m * 1e3,
                "beta_deg": math.degrees(planar_links[k].beta_rad),
                "Jzz_com_kg_m2": planar_links[k].Jzz_com_kg_m2,
                "parts": shares.get(k, []),
            }
            for k in LINKS
        },
        "part_masses_g": {r["part"]: r["mass_g"] for r in bom},
        # material of every solid of assembly.step, by its name there (hapticad massprops)
        "part_materials": {i.name: i.kind.material for i in asm.instances},
        "ground_mass_g": link_props["ground"].mass_kg * 1e3,
        "total_mass_g": sum(r["mass_g"] * r["quantity"] for r in bom),
        "bom": bom,
        "min_clearance_mm": rep.min_clearance_mm,
        "overlap_volume_mm3": rep.overlap_volume_mm3,
        "interference": rep.as_dict(),
        "fasteners": {n: f.as_dict() for n, f in asm.fasteners().items()},
        "tapped_holes": {h.name: h.__dict__ for h in asm.holes},
        "fits": family.fits_report(asm.instances),
        "bodies": {i.name: i.body for i in asm.instances},
        "layers": {
            "order": list(plan.order),
            "z_mm": plan.z_mm,
            "gaps_mm": list(plan.gaps_mm),
            "top_mm": plan.top_mm,
            "candidates": list(plan.candidates),
            "joints": {
                j: {
                    "upper": s.upper,
                    "lower": s.lower,
                    "spacer_mm": s.spacer_mm,
                    "head_spacer_mm": s.shim_mm,
                    "pin": f"{parts.pin} x {s.pin_length_mm:g}",
                }
                for j, s in plan.joints.items()
            },
        },
        "base_plate_mm": list(asm.base_rect_mm),
        "motor": {
            "key": motor.key,
            "mass_kg": motor.mass_kg,
            "rotor_inertia_g_cm2": Jm * 1e7,
            "source": motor.source,
        },
        "fidelity": fidelity,
        "fidelity_costs": fidelity_costs,
        "handle": "user script " + script.name if script is not None else "built-in knob",
        "parts_spec": parts.as_dict(report=True),
        "files": sorted(
            files
            + view_files
            + ["bom.csv", "preview.png", "report.md", "kinematics.png", "apparent_mass.png"]
        ),
        "preview": "preview.png",
    }
    from cad.io.atomic import write_text_atomic

    write_text_atomic(out_dir / "report.md", _markdown(report))
    timings["total_build"] = time.perf_counter() - t0
    report["_timings_s"] = timings  # popped by the CLI before writing (non-deterministic)
    report["_viewer_glb"] = viewer_glb  # popped by the dispatcher: embedded in report.html
    return report


def _fidelity_costs(design, asm, props, link_props, Jm, H, am, fidelity, user_handle, plan) -> dict:
    """What dropping the cosmetic features costs on this design (measured, not assumed)."""
    out = {"bearing_balls": "none: the bearing mass is the catalog mass at every fidelity"}
    if user_handle or design.parts.handle_fillet_mm <= 0:
        out["handle_round"] = "not applicable"
        return out
    from cad.parts import PartKind
    from cad.parts.handle import knob_shape

    floor = plan.handle_screw_length_mm - design.parts.bar_thickness_mm
    other = knob_shape(design.parts, floor, cosmetic=fidelity != "fabrication")
    kind = asm.kinds()["handle"]
    alt = _kind_props(PartKind(name="handle", shape=other, material=kind.material, made=True))
    props2 = dict(props)
    props2["handle"] = alt
    lp2, _ = link_mass_props(asm, props2)
    H2, _ = inertia_from_links(design, lp2, Jm)
    am2 = apparent_mass(design, H2)
    sign = 1.0 if fidelity == "fabrication" else -1.0  # report inertia - fabrication
    out["handle_round"] = {
        "delta_mass_g": sign * (alt.mass_kg - props["handle"].mass_kg) * 1e3,
        "delta_H22_rel": sign * (H2.H22_kg_m2 - H.H22_kg_m2) / H.H22_kg_m2,
        "delta_M11_max_g": sign * (am2["M11_max_g"] - am["M11_max_g"]),
        "meaning": "inertia-fidelity value minus fabrication value",
    }
    return out


def _markdown(r: dict) -> str:
    am = r["apparent_mass"]
    lines = [
        f"# {r['name']} ({r['family']})",
        "",
        "![assembly preview](preview.png)",
        "",
        "![coupler curve, deviation and torque](kinematics.png)",
        "",
        "![apparent mass over the stroke (eq 22, H from the solids)](apparent_mass.png)",
        "",
        "| quantity | value |",
        "|---|---|",
        f"| l1..l5, le (mm) | {r['l1_mm']:.3f}, {r['l2_mm']:.3f}, {r['l3_mm']:.3f}, {r['l4_mm']:.3f}, "
        f"{r['l5_mm']:.3f}, {r['le_mm']:.3f} |",
        f"| phi_e, crank range (deg) | {r['phi_e_deg']:.2f}, {r['phi1_min_deg']:.1f}..{r['phi1_max_deg']:.1f} |",
        f"| H11, H12, H22, H33 (kg m^2) | {r['H11_kg_m2']:.4g}, {r['H12_kg_m2']:.4g}, {r['H22_kg_m2']:.4g}, "
        f"{r['H33_kg_m2']:.4g} |",
        f"| M11 over the stroke (g) | {am['M11_min_g']:.2f} .. {am['M11_max_g']:.2f} |",
        f"| min clearance (mm) | {r['min_clearance_mm']:.3f} ({r['interference']['method']}) |",
        f"| overlap volume (mm^3) | {r['overlap_volume_mm3']:.4g} |",
        f"| layers (bottom to top) | {', '.join(r['layers']['order'])} |",
        "",
        "## Bill of materials",
        "",
        "| part | material | qty | made/bought | mass (g) |",
        "|---|---|---|---|---|",
    ]
    for b in r["bom"]:
        lines.append(
            f"| {b['part']} | {b['material']} | {b['quantity']} | {b['made_or_bought']} | {b['mass_g']:.2f} |"
        )
    return "\n".join(lines) + "\n"
