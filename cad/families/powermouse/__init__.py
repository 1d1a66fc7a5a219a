"""The maglev PowerMouse (haptic mouse paper): actuator optimum, flotor and stator layout,
build, datasheet rows and its current-to-wrench firmware, behind one
:class:`cad.families.protocol.FamilyPackage`, :data:`FAMILY`. It takes no ``check``/``fit``
targets and no optimiser (its actuator optimum is eqs 8-9, solved in the build)."""

from cad.families import SHARED_CODE_DEPS
from cad.families.protocol import FamilyPackage, Lazy

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
    report_type=Lazy("cad.families.powermouse.contract:PowerMouseReport"),
)

#: ``assemble(design, fidelity="fabrication") -> AssemblyModel``.
assemble = FAMILY.assemble

__all__ = ["FAMILY", "assemble"]
