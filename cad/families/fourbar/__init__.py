"""The four-bar families (Hoeken, Roberts, Chebyshev, Chebyshev-V, custom): the layout
(:mod:`.layout`, :mod:`.mechanism`, :mod:`.layers`), the build (:mod:`.build`), the datasheet
rows (:mod:`.datasheet`), target values and the co-design optimiser (:mod:`.targets`), the
simulator model (:mod:`.sim`) and the firmware's kinematic model (:mod:`.firmware`), behind
one :class:`cad.families.protocol.FamilyPackage`, :data:`FAMILY`."""

from cad.design.targets import TARGET_KEYS
from cad.families import SHARED_CODE_DEPS
from cad.families.protocol import FamilyPackage, Lazy, TargetHooks

_P = "cad.families.fourbar"

FAMILY = FamilyPackage(
    package="fourbar",
    build=Lazy(f"{_P}.build:build"),
    assemble=Lazy(f"{_P}.layout:assemble"),
    check_options=Lazy(f"{_P}.build:check_options"),
    check_layout=Lazy(f"{_P}.layout:check_layout"),
    code_deps=SHARED_CODE_DEPS + ("firmware", "kinematics", "dynamics", "structure",
                                  "analysis.py", "__init__.py"),
    cache_inputs=Lazy(f"{_P}.cache:cache_inputs"),
    sim_formats=frozenset({"mjcf", "urdf"}),
    view_formats=True,
    datasheet_rows=Lazy(f"{_P}.datasheet:rows_and_limits"),
    targets=TargetHooks(
        keys=TARGET_KEYS,
        values=Lazy(f"{_P}.targets:check_values"),
        fit_values=Lazy(f"{_P}.targets:fit_values"),
        parse_free=Lazy("cad.studies.fit:parse_free_parts"),
        fit_limits=Lazy("cad.families.fourbar.limits:default_limit_targets"),
        precad=Lazy("cad.studies.fit:precad_checks"),
    ),
    optimize=Lazy(f"{_P}.targets:optimize"),
    firmware=Lazy("cad.firmware:linkage_files"),
    firmware_model=Lazy(f"{_P}.firmware:model"),
    report_type=Lazy("cad.families.fourbar.contract:FourBarReport"),
)

#: ``assemble(design, fidelity="fabrication") -> AssemblyModel`` (:func:`.layout.assemble`).
assemble = FAMILY.assemble

__all__ = ["FAMILY", "assemble"]
