"""The one build driver of the families laid out as one list of part instances (issue 23,
"one pipeline": check -> layout -> assemble -> props -> dynamics -> interference -> files ->
report).

A family's ``build()`` is a call to :func:`run_family` with its :class:`Stages`: what is
particular to it (its layout, its dynamics, its report rows, its extra files). Everything
else -- the order of the stages, the progress lines, the fastener check, the mass properties
of every kind and body, the BOM, the forked exports and viewer files
(:mod:`cad.pipeline.forked`), the bench-plane check, ``report.md`` / ``assembly.md`` and the
common tail of the report (``fasteners``, ``tapped_holes``, ``part_materials``, ``fits``,
``placement``, ``files``, ``_viewer_glb``) -- is done here, once, for every family, from the
model's instance list (:mod:`cad.pipeline.family`).

Order (each family callback receives the :class:`Build` filled so far)::

    check_options(design, fidelity, phi1_deg, formats)        DesignError before any CAD
    [prepare_label]  pre = prepare(design)                    layout, 2-D figures (optional)
    "solids"         model = assemble(design, fidelity)       AssemblyModel
                     fastener_report(instances, holes)        DesignError: two in a hole ...
    fork: exports    write_outputs(...) + more_exports(build) (preview.png with marks(build))
    fork: views      write_viewer_outputs(stroke, cutaway)
    fork: same_body  every pair of solids on one body         (read by interference: Build.same_body)
    mass_label       props = kind_props, bodies = body_props(moving_bodies(model))
                     dyn = dynamics(build)                    the family's (optional)
                     bom = bom_rows(instances, props, formats) + no_solid_rows(design)
    fork: figures    figures(build)                           (plots that may read dyn)
    "every pair of solids over the " + motion_label
                     itf = interference(build)
                     low = lowest z, GeometryError below bench_z_mm(build) (optional)
    "exports"        the children's files; more_files(build) (MJCF, URDF) in this process
    "report"         report(build) + the common tail; report.md's family part (md_rows),
                     assembly.md
    "done"

Every exported mesh (part STL, parts.3mf, the viewer files) has the deflections of the
resolved device (:func:`cad.device.mesh_deflections`).

The report carries the wall times of the stages under ``"_timings_s"`` and the family's part
of ``report.md`` under ``"_report_md"`` (both popped by the dispatcher, which writes
``bom.csv``, ``order.csv`` and ``report.md`` once, after pricing and the datasheet).

Any failure cancels the forked children (:func:`cad.pipeline.forked.cancel_on_error`); the
dispatcher (:func:`cad.pipeline.build_design`) discards the temporary folder.
"""

from __future__ import annotations

import dataclasses
import fnmatch
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from cad.assembly import interference as itf
from cad.device import resolve_device
from cad.errors import GeometryError
from cad.pipeline import family, forked
from cad.pipeline.views import write_viewer_outputs


def _moving_bodies(model) -> list[str]:
    """Every body of the model but ``ground``, in order of first appearance."""
    return [b for b in model.bodies if b != "ground"]


@dataclasses.dataclass(frozen=True)
class Stages:
    """What one family supplies to :func:`run_family` (module docstring for the order).

    Required: ``check_options(design, fidelity, phi1_deg, formats)`` (DesignError),
    ``assemble(design, fidelity) -> AssemblyModel``, ``interference(build)`` (the family's
    result as a dict, :meth:`cad.assembly.interference.InterferenceReport.as_dict`, kept as
    ``Build.itf``; it passes :meth:`Build.same_body` to the check; InterferenceError),
    ``report(build) -> dict`` (the family's keys, with ``"notes"``: list of str),
    ``md_rows(report) -> [(quantity, value)]`` (report.md's table), ``preview_title(build)``
    (preview.png's title), ``stroke(design) -> {body: (n, 4, 4)}`` (the viewer's motion,
    mm), ``motion_label`` (progress: "every pair of solids over the <motion_label>").
    Optional: ``prepare(design)`` (kept as ``Build.pre``) and its progress label,
    ``moving_bodies(model)`` (bodies whose mass properties are summed; default every body but
    ground), ``dynamics(build)`` (kept as ``Build.dyn``), ``bench_z_mm(build)`` (mm; the
    lowest solid must not reach below it), ``marks(build)`` (preview polylines),
    ``preview_hide_ground_below_mm`` (ground parts wholly below this world z, mm, are left out
    of preview.png's top view; None: every part drawn), ``thread_notes`` (tapped holes to the
    DXF notes), ``more_exports(build)`` (in the export child), ``figures(build)`` (plots, in a
    child forked after the dynamics: they may read ``Build.dyn``), ``more_files(build)`` (after
    the exports), ``cutaway`` (instance name patterns drawn cut away in the pictures),
    ``assembly(design) -> (plan, checks)`` (``assembly.md``; None: not written),
    ``no_solid_rows(design)`` (bought BOM rows with no solid, e.g. an encoder: appended to the
    BOM, a last step of assembly.md, each unit named ``part_1`` .. ``part_n`` or, when the row
    has them, by its ``instance_names``), ``md_images`` (``(alt text, file)`` pairs of report.md).
    The exports, the views and the same-body check start right after the solids, beside the
    mass properties and the interference check: the checks leave every solid untouched (their
    Booleans work on copies, :mod:`cad.occ.boolean`), so a file does not depend on when it is
    written, and no export needs a mass property (``bom.csv`` is the dispatcher's).
    Each file callback returns the paths it wrote, relative to the output folder."""

    check_options: Callable[..., None]
    assemble: Callable[[Any, str], Any]
    interference: Callable[[Build], Any]
    report: Callable[[Build], dict]
    md_rows: Callable[[dict], list]
    preview_title: Callable[[Build], str]
    stroke: Callable[[Any], Any]
    motion_label: str
    mass_label: str = "mass properties"
    prepare: Callable[[Any], Any] | None = None
    prepare_label: str | None = None
    moving_bodies: Callable[[Any], Sequence[str]] = _moving_bodies
    dynamics: Callable[[Build], Any] | None = None
    bench_z_mm: Callable[[Build], float] | None = None
    marks: Callable[[Build], list] | None = None
    preview_hide_ground_below_mm: float | None = None
    thread_notes: bool = True
    more_exports: Callable[[Build], list[str]] | None = None
    figures: Callable[[Build], list[str]] | None = None
    more_files: Callable[[Build], list[str]] | None = None
    cutaway: tuple[str, ...] = ()
    assembly: Callable[[Any], tuple] | None = None
    no_solid_rows: Callable[[Any], list] | None = None
    md_images: tuple = ()


@dataclasses.dataclass
class Build:
    """The state of one build, filled stage by stage (what the family callbacks read).

    ``pre``: :attr:`Stages.prepare`'s result; ``model``: the AssemblyModel; ``props``:
    ``{kind: MassProps}``; ``bodies``: ``{body: MassProps}`` in the body frame; ``dyn``:
    :attr:`Stages.dynamics`' result; ``bom``: the BOM rows; ``itf``:
    :attr:`Stages.interference`'s result; ``low``: lowest world z of any solid (mm, None
    without a bench plane); ``extra_rows``: :attr:`Stages.no_solid_rows`; ``common``: the
    common tail of the report (fastener keys, ``part_materials``, ``fits``, ``placement``),
    set before :attr:`Stages.report` so a family may place its keys; ``timings``: wall
    times (s); ``tasks``: the forked children by name (exports, views, same_body, figures)."""

    design: Any
    out_dir: Path
    formats: set[str]
    fidelity: str
    allow_interference: bool
    pre: Any = None
    model: Any = None
    props: dict = dataclasses.field(default_factory=dict)
    bodies: dict = dataclasses.field(default_factory=dict)
    dyn: Any = None
    bom: list = dataclasses.field(default_factory=list)
    itf: Any = None
    low: float | None = None
    extra_rows: list = dataclasses.field(default_factory=list)
    common: dict = dataclasses.field(default_factory=dict)
    timings: dict = dataclasses.field(default_factory=dict)
    tasks: dict = dataclasses.field(default_factory=dict)
    results: dict = dataclasses.field(default_factory=dict)

    def child(self, name: str) -> Any:
        """The value of the forked child ``name`` (waited for once; its wall time kept in
        ``timings``). Raises what it raised."""
        if name not in self.results:
            self.results[name], self.timings[name] = self.tasks[name].result()
        return self.results[name]

    def same_body(self):
        """The same-body check of the solids (every pair of parts on one body,
        :func:`cad.assembly.interference.same_body_check`), run in a child forked beside the
        mass properties: what a family's ``interference`` passes to
        :func:`cad.assembly.interference.check_model` as ``same_body``."""
        return self.child("same_body")

    @property
    def instances(self) -> list:
        """The model's part instances."""
        return list(self.model.instances)

    @property
    def tfs(self) -> dict:
        """``{body: (4, 4)}`` world transforms at the exported pose (mm)."""
        return self.model.tf_world_body


class _Progress:
    """The progress lines of :func:`run_family`: ``progress(text, done, total)``."""

    def __init__(self, progress, stages: Stages):
        self.progress, self.done = progress, 0
        self.total = 5 + (stages.prepare_label is not None)

    def __call__(self, text: str) -> None:
        if self.progress is not None:
            self.progress(text, self.done, self.total)
        self.done += 1

    def finish(self) -> None:
        self.done = self.total
        self("done")


def run_family(stages: Stages, design, out_dir: Path, formats: set[str], *,
               fidelity: str = "fabrication", allow_interference: bool = False,
               progress=None, phi1_deg: float | None = None) -> dict:
    """Build ``design`` into ``out_dir`` (the dispatcher's temporary folder) through the
    family's ``stages``; returns the report dict (contract: :mod:`cad.pipeline`).

    Raises what the stages raise: DesignError (options, fasteners), InterferenceError (a
    clash over the motion unless ``allow_interference``), GeometryError (a solid below the
    bench plane), MeshError (an export)."""
    t0 = time.perf_counter()
    stages.check_options(design, fidelity, phi1_deg, formats)
    b = Build(design, Path(out_dir), set(formats), fidelity, allow_interference)
    step = _Progress(progress, stages)
    if stages.prepare_label is not None:
        step(stages.prepare_label)
    if stages.prepare is not None:
        b.pre = stages.prepare(design)
    step("solids")
    b.model = stages.assemble(design, fidelity)
    b.timings["parts"] = time.perf_counter() - t0
    fasteners = family.fastener_report(b.instances, b.model.holes)  # DesignError: two in a hole
    _start(b, {"exports": lambda: _exports(stages, b),  # they need no mass property
               "views": lambda: _views(stages, b),
               "same_body": lambda: itf.same_body_check(itf.static_items(b.instances))})
    with forked.cancel_on_error(*b.tasks.values()):
        _mass_properties(stages, b, step)
    if stages.figures is not None:
        _start(b, {"figures": lambda: stages.figures(b)})
    files, viewer_glb = _checks_and_files(stages, b, step)
    step("report")
    report = _report(stages, b, fasteners, files)
    b.timings["total_build"] = time.perf_counter() - t0
    report["_timings_s"] = b.timings  # popped by the dispatcher (non-deterministic)
    report["_viewer_glb"] = viewer_glb  # popped by the dispatcher: embedded in report.html
    step.finish()
    return report


def _mass_properties(stages: Stages, b: Build, step) -> None:
    """Mass properties per kind and body, the family's dynamics and the BOM rows (into
    ``b``)."""
    step(stages.mass_label)
    t = time.perf_counter()
    b.props = family.kind_props(b.instances)
    b.bodies = family.body_props(b.instances, b.props, list(stages.moving_bodies(b.model)))
    if stages.dynamics is not None:
        b.dyn = stages.dynamics(b)
    b.timings["massprops"] = time.perf_counter() - t
    if stages.no_solid_rows is not None:
        b.extra_rows = list(stages.no_solid_rows(b.design))
    b.bom = family.bom_rows(b.instances, b.props, b.formats) + b.extra_rows


def timed_call(fn: Callable[[], Any]) -> Callable[[], tuple[Any, float]]:
    """``fn`` returning ``(its value, its wall time in s)``."""
    def run():
        t = time.perf_counter()
        value = fn()
        return value, time.perf_counter() - t
    return run


def _start(b: Build, children: dict) -> None:
    """Fork ``children`` (``{name: fn}``) into ``b.tasks`` (:mod:`cad.pipeline.forked`:
    deferred where forking is off)."""
    for name, fn in children.items():
        b.tasks[name] = forked.start(timed_call(fn), name)


def _checks_and_files(stages: Stages, b: Build, step) -> tuple[list[str], bytes]:
    """The checks of the solids over the motion and against the bench plane in this process
    while the forked children write; then the files made from their results. Returns
    (files, glb bytes)."""
    with forked.cancel_on_error(*b.tasks.values()):
        step(f"every pair of solids over the {stages.motion_label}")
        t = time.perf_counter()
        b.itf = stages.interference(b)
        b.timings["interference"] = time.perf_counter() - t
        if stages.bench_z_mm is not None:
            b.low = check_bench(b.instances, b.tfs, stages.bench_z_mm(b))
        step("exports")
        files = b.child("exports")
        if stages.more_files is not None:
            files += stages.more_files(b)
        figures = b.child("figures") if "figures" in b.tasks else []
        view_files, viewer_glb = b.child("views")
    return files + figures + view_files, viewer_glb


def check_bench(instances, tfs: dict, bench_z_mm: float) -> float:
    """Lowest world z of any solid (mm); GeometryError naming the instance when it reaches
    below the bench plane at ``bench_z_mm`` (mm, world frame)."""
    low, low_part = family.lowest_z_mm(instances, tfs)
    if low < bench_z_mm - 1e-6:
        raise GeometryError(f"{low_part} reaches z = {low:.2f} mm, below the bench plane at "
                            f"{bench_z_mm:.2f} mm")
    return low


def _exports(stages: Stages, b: Build) -> list[str]:
    """Part files, assembly STEP, BOM, preview (:func:`cad.pipeline.family.write_outputs`)
    and the family's further exports."""
    dev = resolve_device(b.design, b.fidelity)
    files = family.write_outputs(
        b.instances, b.tfs, b.out_dir, b.formats, name=b.design.name,
        title=stages.preview_title(b),
        bom=None,  # bom.csv: the dispatcher, once, priced (cad.pipeline.write_order)
        marks=stages.marks(b) if stages.marks is not None else None,
        hide_ground_below_mm=stages.preview_hide_ground_below_mm,
        holes=tuple(b.model.holes.values()) if stages.thread_notes else (),
        stl_tolerance_mm=dev.stl_tolerance_mm, angular_tolerance_rad=dev.stl_angular_tolerance_rad)
    if stages.more_exports is not None:
        files += stages.more_exports(b)
    return files


def _views(stages: Stages, b: Build) -> tuple[list[str], bytes]:
    """The viewer files (:func:`cad.pipeline.views.write_viewer_outputs`); returns (files,
    glb bytes)."""
    d = b.design
    dev = resolve_device(d, b.fidelity)
    cutaway = [i.name for i in b.instances
               if any(fnmatch.fnmatchcase(i.name, p) for p in stages.cutaway)]
    return write_viewer_outputs(
        b.instances, b.tfs, b.out_dir, b.formats, name=d.name, title=f"{d.name} ({d.family})",
        stroke=stages.stroke(d), cutaway=cutaway or (), stl_tolerance_mm=dev.stl_tolerance_mm,
        angular_tolerance_rad=dev.stl_angular_tolerance_rad)


def _common_keys(b: Build) -> dict:
    """The report keys every family shares, written here once (:mod:`cad.report.contract`):
    name, family, ``source`` (the design file's name: no path of this machine), fidelity, ``bodies`` (each moving body's mass properties in its body
    frame, SI), ``moving_mass_g`` (their sum), ``total_mass_g`` (the BOM's mass, bought
    parts with no solid included), ``bom`` and the interference check (``interference``,
    ``min_clearance_mm``, ``overlap_volume_mm3``)."""
    moving = {k: mp for k, mp in b.bodies.items() if k != "ground"}
    itf = b.itf
    src = b.design.source
    return {"name": b.design.name, "family": b.design.family, "fidelity": b.fidelity,
            **({"source": Path(str(src)).name} if src else {}),
            "bodies": {k: mp.to_dict() for k, mp in moving.items()},
            "moving_mass_g": sum(mp.mass_kg for mp in moving.values()) * 1e3,
            "total_mass_g": sum(r["mass_g"] * r["quantity"] for r in b.bom), "bom": b.bom,
            "interference": itf, "min_clearance_mm": itf.get("min_clearance_mm"),
            "overlap_volume_mm3": itf.get("overlap_volume_mm3")}


def _report(stages: Stages, b: Build, fasteners: dict, files: list[str]) -> dict:
    """The family's report dict with the common tail and its part of report.md (under
    ``"_report_md"``, written by the dispatcher with the datasheet and the order); writes
    assembly.md."""
    inst, d = b.instances, b.design
    b.common = {**fasteners, "part_materials": family.part_materials(inst),
                "fits": family.fits_report(inst),
                "placement": family.placement_report(inst, b.tfs, b.props)}
    report = stages.report(b)
    report.update(b.common)  # the keys the family did not place go last
    report.update(_common_keys(b))
    report.setdefault("notes", [])
    report["files"] = sorted(files + ["report.md", "bom.csv"])
    title = f"{d.name} ({d.family})"
    report["_report_md"] = family.report_md_lines(title, stages.md_rows(report), b.bom,
                                                  report.get("notes", ()), images=stages.md_images)
    if stages.assembly is not None:
        plan, checks = stages.assembly(d)
        family.write_assembly_md(b.out_dir, title, inst, plan, checks,
                                 no_solid_rows=b.extra_rows, tf_world_body=b.tfs,
                                 formats=b.formats)
    return report
