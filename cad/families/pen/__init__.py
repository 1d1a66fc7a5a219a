"""The haptic pen: the isotropy paper's 5-DOF twin-pantograph pen (§4.2, Fig. 4, Table 2)
with parts, behind one :class:`cad.families.protocol.FamilyPackage`, :data:`FAMILY`.

:mod:`.assembly` lays it out (``assemble(design, fidelity) -> AssemblyModel``), :mod:`.build`
builds it, :mod:`.datasheet` gives its rows, :mod:`.sim` its MJCF, :mod:`.design` its
``[parts]`` schema, :mod:`.layout` its numbers and body poses, :mod:`.parts` its part
scripts, :mod:`.firmware` its firmware model (the generic writers of :mod:`cad.firmware`),
:mod:`.capstan` its capstans' analyses, :mod:`.capstan_layout` where their motors sit and
:mod:`.capstan_solids` the waists' capstan solids, :mod:`.shoulder_capstan` the shoulders'."""

from cad.design.targets import PANTOGRAPH_TARGET_KEYS
from cad.families import SHARED_CODE_DEPS
from cad.families.protocol import FamilyPackage, Lazy, TargetHooks

_P = "cad.families.pen"

FAMILY = FamilyPackage(
    package="pen",
    build=Lazy(f"{_P}.build:build"),
    assemble=Lazy(f"{_P}.assembly:assemble"),
    check_options=Lazy(f"{_P}.build:check_options"),
    code_deps=SHARED_CODE_DEPS + ("firmware", "kinematics", "isotropy", "sim"),
    sim_formats=frozenset({"mjcf"}),
    firmware=Lazy("cad.firmware:linkage_files"),
    firmware_model=Lazy(f"{_P}.identify:firmware_model"),
    view_formats=True,
    datasheet_rows=Lazy(f"{_P}.datasheet:rows_and_limits"),
    targets=TargetHooks(
        keys=PANTOGRAPH_TARGET_KEYS,
        values=Lazy("cad.families.pantograph.targets:pantograph_target_values"),
        parse_free=Lazy("cad.studies.fit:parse_free_pantograph"),
        fit_limits=Lazy("cad.families.pantograph.limits:default_limit_targets"),
    ),
    optimize=Lazy("cad.studies.gii_optimize:optimize"),
    report_type=Lazy("cad.families.pen.contract:PenReport"),
)

#: ``assemble(design, fidelity="fabrication") -> AssemblyModel``.
assemble = FAMILY.assemble

__all__ = ["FAMILY", "assemble"]
