"""The maglev PowerMouse (haptic mouse paper): actuator optimum, flotor and stator layout,
build, datasheet rows, ``check``/``fit`` targets on its datasheet's figures
(:mod:`cad.studies.build_targets`) and its current-to-wrench firmware, behind one
:class:`cad.families.protocol.FamilyPackage`, :data:`FAMILY`. No optimiser (its actuator
optimum is eqs 8-9, solved in the build)."""

from cad.design.targets import POWERMOUSE_TARGET_KEYS
from cad.families import SHARED_CODE_DEPS
from cad.families.protocol import FamilyPackage, Lazy, TargetHooks

_P = "cad.families.powermouse"

FAMILY = FamilyPackage(
    package="powermouse",
    build=Lazy(f"{_P}.build:build"),
    assemble=Lazy(f"{_P}.build:assemble"),
    check_options=Lazy(f"{_P}.build:check_options"),
    code_deps=SHARED_CODE_DEPS + ("actuators",),
    sim_formats=frozenset({"mjcf"}),
    view_formats=True,
    datasheet_rows=Lazy(f"{_P}.datasheet:rows_and_limits"),
    firmware=Lazy(f"{_P}.firmware:device_files"),
    targets=TargetHooks(
        keys=POWERMOUSE_TARGET_KEYS,
        values=Lazy("cad.studies.build_targets:build_target_values"),
        parse_free=Lazy("cad.studies.build_targets:parse_free_tables"),
    ),
    report_type=Lazy("cad.families.powermouse.contract:PowerMouseReport"),
)

#: ``assemble(design, fidelity="fabrication") -> AssemblyModel``.
assemble = FAMILY.assemble

__all__ = ["FAMILY", "assemble"]
