"""The 3-DOF delta family (issue 36): design schema (:mod:`.design`); kinematics in
:mod:`cad.kinematics.delta`, dynamics in :mod:`cad.dynamics.delta`, the GII problem in
:mod:`cad.isotropy.problems` (``DeltaProblem``); parts and assembly (:mod:`.assembly`,
:mod:`.parts`, :mod:`.layout`, :mod:`.hardware`), Lambda(x) from the solids
(:mod:`.dynamics`), the 3-D frame (:mod:`.structure`), the build (:mod:`.build`) and its
datasheet rows (:mod:`.datasheet`), generated C kinematics (:mod:`.firmware`, not yet a build
format). Its :data:`FAMILY` gives build, datasheet and the GII optimiser; ``check``/``fit``,
firmware and simulator formats refuse a delta in one line."""

from cad.families import SHARED_CODE_DEPS
from cad.families.protocol import FamilyPackage, Lazy

_P = "cad.families.delta"

FAMILY = FamilyPackage(
    package="delta",
    build=Lazy(f"{_P}.build:build"),
    assemble=Lazy(f"{_P}.assembly:assemble"),
    check_options=Lazy(f"{_P}.build:check_options"),
    code_deps=SHARED_CODE_DEPS + ("kinematics", "dynamics", "isotropy", "structure"),
    view_formats=True,
    datasheet_rows=Lazy(f"{_P}.datasheet:rows_and_limits"),
    optimize=Lazy("cad.studies.gii_optimize:optimize"),
    report_type=Lazy("cad.families.delta.contract:DeltaReport"),
)

__all__ = ["FAMILY"]
