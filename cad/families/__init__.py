"""Families: the layout code of each device family behind one protocol.

A package ``cad/families/<name>/`` holds what is particular to a family and nothing the
pipeline (:mod:`cad.pipeline`) does for every family:

* ``assemble(design, fidelity="fabrication") -> cad.assembly.model.AssemblyModel``
  (exported by the package's ``__init__``): the part instances, the bodies at the exported
  pose and over the motion the interference check sweeps;
* ``build.py`` -- ``build(design, out_dir, formats, *, fidelity, allow_interference,
  progress, phi1_deg) -> report dict``; optionally ``check_options``, ``cache_inputs``,
  ``CODE_DEPS`` (the contract is in :mod:`cad.pipeline`; :data:`SHARED_CODE_DEPS` plus the
  family's own packages); for the pen, the pantographs and the PowerMouse ``build`` is one
  call to the build driver :func:`cad.pipeline.run.run_family` with the family's
  :class:`cad.pipeline.run.Stages` (the four-bar still runs its own sequence);
* ``datasheet.py`` -- ``rows_and_limits(design, report, out_dir, simulate_wall)``, the
  family's rows of the device datasheet (:mod:`cad.datasheet`);
* ``sim.py`` (where the family exports MJCF/URDF) -- its simulator model.

The registry row (:mod:`cad.data.families`) names the package.
"""

#: Sources of ``cad`` every family's build output depends on (its ``CODE_DEPS``, the build
#: cache key, :func:`cad.pipeline.code_version`): the pipeline and the families' layout code,
#: the datasheet, reports, parts, assembly model and checks, the OCP wrappers, exports, mass
#: properties, design loading, file I/O, catalogs and materials, errors and tolerances. A
#: family's ``CODE_DEPS`` is this plus the packages of its own math.
SHARED_CODE_DEPS = (
    "pipeline",
    "families",
    "datasheet",
    "report",  # report.html, the stroke GIF and render (cad/report)
    "parts",
    "assembly",
    "occ",
    "export",
    "massprops",
    "design",
    "device",  # the resolved device every writer reads (cad/device)
    "io",
    "data",
    "errors.py",
    "tolerances.py",
)
