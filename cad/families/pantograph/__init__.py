"""The pantograph families: the plain 5-bar and the twin-pantograph haptic mouse (isotropy
paper §4.1): layout, build, datasheet rows, target values, the GII optimiser, the simulator
model and the firmware's kinematic models, behind one
:class:`cad.families.protocol.FamilyPackage`, :data:`FAMILY`."""

from cad.design.targets import PANTOGRAPH_TARGET_KEYS
from cad.families import SHARED_CODE_DEPS
from cad.families.protocol import FamilyPackage, Lazy, TargetHooks

_P = "cad.families.pantograph"


FAMILY = FamilyPackage(
    package="pantograph",
    build=Lazy(f"{_P}.build:build"),
    assemble=Lazy(f"{_P}.build:assemble"),
    check_options=Lazy(f"{_P}.build:check_options"),
    code_deps=SHARED_CODE_DEPS + ("firmware", "kinematics", "isotropy", "dynamics"),
    sim_formats=frozenset({"mjcf", "urdf"}),
    view_formats=True,
    datasheet_rows=Lazy(f"{_P}.datasheet:rows_and_limits"),
    targets=TargetHooks(
        keys=PANTOGRAPH_TARGET_KEYS,
        values=Lazy(f"{_P}.targets:pantograph_target_values"),
        parse_free=Lazy("cad.studies.fit:parse_free_pantograph"),
        blockers=Lazy(f"{_P}.targets:mode_blocker_lines"),
        fit_limits=Lazy(f"{_P}.limits:default_limit_targets"),
    ),
    optimize=Lazy("cad.studies.gii_optimize:optimize"),
    firmware=Lazy("cad.firmware:linkage_files"),
    firmware_model=Lazy(f"{_P}.identify_twin:firmware_model"),
    report_type=Lazy("cad.families.pantograph.contract:PantographReport"),
)

#: ``assemble(design, fidelity="fabrication") -> AssemblyModel``.
assemble = FAMILY.assemble

__all__ = ["FAMILY", "assemble"]
