"""Families: the code particular to each device family, behind one protocol.

A package ``cad/families/<package>/`` holds what is particular to a family and nothing the
pipeline (:mod:`cad.pipeline`), the datasheet (:mod:`cad.datasheet`), the commands
(:mod:`cad.api`) or the firmware generator (:mod:`cad.firmware`) does for every family. Its
``__init__`` exports one object, ``FAMILY``: a :class:`cad.families.protocol.FamilyPackage`
(layout/assembly, build stages, datasheet rows, target values, optimiser, firmware and
simulator hooks). The registry row (:mod:`cad.data.families`) names the package and the
commands that take the family; :func:`family_package` is the one place that turns a family
name into its ``FAMILY``. A new family is one package and one registry row
(``tests/architecture/test_toy_family.py`` proves it).
"""
from cad.data.families import FAMILIES
from cad.errors import DesignError

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


def family_package(name: str):
    """The :class:`cad.families.protocol.FamilyPackage` of the family ``name`` (the
    ``FAMILY`` of the package its registry row names).

    Raises DesignError naming ``mechanism.family`` for an unknown family or one whose row
    names no package."""
    import importlib

    row = FAMILIES.get(name)
    if row is None:
        raise DesignError("mechanism.family", f"unknown family {name!r}")
    if row.package is None:
        raise DesignError("mechanism.family", f"{name} designs have no family package yet (no parts)")
    return importlib.import_module(row.package_module).FAMILY
