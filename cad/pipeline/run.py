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
    mass_label       props = kind_props, bodies = body_props(moving_bodies(model))
                     dyn = dynamics(build)                    the family's (optional)
                     bom = bom_rows(instances, props)
    fork: exports    write_outputs(...) + more_exports(build) (the PowerMouse rig; in this
                     process after the checks below with exports_after_check)
    fork: views      write_viewer_outputs(stroke, cutaway) + figures(build) (Fig. 8)
    "every pair of solids over the " + motion_label
                     itf = interference(model, allow_interference)
                     low = lowest z, GeometryError below bench_z_mm(build) (optional)
    "exports"        the children's files; more_files(build) (MJCF, URDF) in this process
    "report"         report(build) + the common tail; report.md (md_rows), assembly.md
    "done"

Any failure cancels the forked children (:func:`cad.pipeline.forked.cancel_on_error`); the
dispatcher (:func:`cad.pipeline.build_design`) discards the temporary folder.
"""

from __future__ import annotations

import dataclasses
import fnmatch
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any


def _moving_bodies(model) -> list[str]:
    """Every body of the model but ``ground``, in order of first appearance."""
    return [b for b in model.bodies if b != "ground"]


@dataclasses.dataclass(frozen=True)
class Stages:
    """What one family supplies to :func:`run_family` (module docstring for the order).

    Required: ``check_options(design, fidelity, phi1_deg, formats)`` (DesignError),
    ``assemble(design, fidelity) -> AssemblyModel``, ``interference(model,
    allow_interference)`` (the family's result, kept as ``Build.itf``; InterferenceError),
    ``report(build) -> dict`` (the family's keys, with ``"notes"``: list of str),
    ``md_rows(report) -> [(quantity, value)]`` (report.md's table), ``preview_title(build)``
    (preview.png's title), ``stroke(design) -> {body: (n, 4, 4)}`` (the viewer's motion, mm),
    ``motion_label`` (progress: "every pair of solids over the <motion_label>").
    Optional: ``prepare(design)`` (kept as ``Build.pre``) and its progress label,
    ``moving_bodies(model)`` (bodies whose mass properties are summed; default every body but
    ground), ``dynamics(build)`` (kept as ``Build.dyn``), ``bench_z_mm(build)`` (mm; the
    lowest solid must not reach below it), ``marks(build)`` (preview polylines),
    ``thread_notes`` (tapped holes to the DXF notes), ``more_exports(build)`` (in the export
    child), ``figures(build)`` (in the views child), ``more_files(build)`` (after the exports),
    ``cutaway`` (instance name patterns drawn cut away in the pictures), ``assembly(design) ->
    (plan, checks)`` (``assembly.md``; None: not written), ``exports_after_check`` (the
    exports in this process after the interference check instead of a forked child beside it:
    the pen: on a cold shape cache its ``drawings/ring.svg`` drawn after the check differs
    from one drawn before it -- state the check leaves on the solids -- and the pen's files
    stay those of its former, serial builder). Each file callback returns the paths it wrote, relative to the output folder."""

    check_options: Callable[..., None]
    assemble: Callable[[Any, str], Any]
    interference: Callable[[Any, bool], Any]
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
    thread_notes: bool = True
    more_exports: Callable[[Build], list[str]] | None = None
    figures: Callable[[Build], list[str]] | None = None
    more_files: Callable[[Build], list[str]] | None = None
    cutaway: tuple[str, ...] = ()
    assembly: Callable[[Any], tuple] | None = None
    exports_after_check: bool = False


@dataclasses.dataclass
class Build:
    """The state of one build, filled stage by stage (what the family callbacks read).

    ``pre``: :attr:`Stages.prepare`'s result; ``model``: the AssemblyModel; ``props``:
    ``{kind: MassProps}``; ``bodies``: ``{body: MassProps}`` in the body frame; ``dyn``:
    :attr:`Stages.dynamics`' result; ``bom``: the BOM rows; ``itf``:
    :attr:`Stages.interference`'s result; ``low``: lowest world z of any solid (mm, None
    without a bench plane)."""

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
    from cad.pipeline import family

    stages.check_options(design, fidelity, phi1_deg, formats)
    b = Build(design, Path(out_dir), set(formats), fidelity, allow_interference)
    step = _Progress(progress, stages)
    if stages.prepare_label is not None:
        step(stages.prepare_label)
    if stages.prepare is not None:
        b.pre = stages.prepare(design)
    step("solids")
    b.model = stages.assemble(design, fidelity)
    fasteners = family.fastener_report(b.instances, b.model.holes)  # DesignError: two in a hole
    step(stages.mass_label)
    b.props = family.kind_props(b.instances)
    b.bodies = family.body_props(b.instances, b.props, list(stages.moving_bodies(b.model)))
    if stages.dynamics is not None:
        b.dyn = stages.dynamics(b)
    b.bom = family.bom_rows(b.instances, b.props)
    files, viewer_glb = _checks_and_files(stages, b, step)
    step("report")
    report = _report(stages, b, fasteners, files)
    report["_viewer_glb"] = viewer_glb  # popped by the dispatcher: embedded in report.html
    step.finish()
    return report


def _checks_and_files(stages: Stages, b: Build, step) -> tuple[list[str], bytes]:
    """The exports and the viewer files in two forked children (serial where forking is off)
    while this process checks the solids over the motion and against the bench plane; then
    the files made from their results. Returns (files, glb bytes)."""
    from cad.pipeline import forked

    early = not stages.exports_after_check
    task = forked.start(lambda: _exports(stages, b), "exports") if early else None
    views_task = forked.start(lambda: _views(stages, b), "views")
    with forked.cancel_on_error(*([task] if early else []), views_task):
        step(f"every pair of solids over the {stages.motion_label}")
        b.itf = stages.interference(b.model, b.allow_interference)
        if stages.bench_z_mm is not None:
            b.low = check_bench(b.instances, b.tfs, stages.bench_z_mm(b))
        step("exports")
        files = task.result() if early else _exports(stages, b)
        if stages.more_files is not None:
            files += stages.more_files(b)
        view_files, viewer_glb = views_task.result()
    return files + view_files, viewer_glb


def check_bench(instances, tfs: dict, bench_z_mm: float) -> float:
    """Lowest world z of any solid (mm); GeometryError naming the instance when it reaches
    below the bench plane at ``bench_z_mm`` (mm, world frame)."""
    from cad.errors import GeometryError
    from cad.pipeline import family

    low, low_part = family.lowest_z_mm(instances, tfs)
    if low < bench_z_mm - 1e-6:
        raise GeometryError(f"{low_part} reaches z = {low:.2f} mm, below the bench plane at "
                            f"{bench_z_mm:.2f} mm")
    return low


def _exports(stages: Stages, b: Build) -> list[str]:
    """Part files, assembly STEP, BOM, preview (:func:`cad.pipeline.family.write_outputs`)
    and the family's further exports."""
    from cad.pipeline import family

    d = b.design
    files = family.write_outputs(
        b.instances, b.tfs, b.out_dir, b.formats, name=d.name, title=stages.preview_title(b),
        bom=b.bom, marks=stages.marks(b) if stages.marks is not None else None,
        holes=tuple(b.model.holes.values()) if stages.thread_notes else ())
    if stages.more_exports is not None:
        files += stages.more_exports(b)
    return files


def _views(stages: Stages, b: Build) -> tuple[list[str], bytes]:
    """The viewer files (:func:`cad.pipeline.views.write_viewer_outputs`) and the family's
    figures; returns (files, glb bytes)."""
    from cad.pipeline.views import write_viewer_outputs

    d = b.design
    cutaway = [i.name for i in b.instances
               if any(fnmatch.fnmatchcase(i.name, p) for p in stages.cutaway)]
    files, glb = write_viewer_outputs(
        b.instances, b.tfs, b.out_dir, b.formats, name=d.name, title=f"{d.name} ({d.family})",
        stroke=stages.stroke(d), cutaway=cutaway or ())
    figures = stages.figures(b) if stages.figures is not None else []
    return figures + files, glb


def _report(stages: Stages, b: Build, fasteners: dict, files: list[str]) -> dict:
    """The family's report dict with the common tail; writes report.md and assembly.md."""
    from cad.pipeline import family

    inst, d = b.instances, b.design
    report = stages.report(b)
    report.update(fasteners)
    report["part_materials"] = family.part_materials(inst)
    report["fits"] = family.fits_report(inst)
    report["placement"] = family.placement_report(inst, b.tfs, b.props)
    report["files"] = sorted(files + ["report.md"])
    title = f"{d.name} ({d.family})"
    family.write_report_md(b.out_dir, title, stages.md_rows(report), b.bom, report["notes"])
    if stages.assembly is not None:
        plan, checks = stages.assembly(d)
        family.write_assembly_md(b.out_dir, title, inst, plan, checks, tf_world_body=b.tfs,
                                 formats=b.formats)
    return report
