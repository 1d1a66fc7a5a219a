"""The 3-DOF delta family (issue 36): design schema (:mod:`.design`); kinematics in
:mod:`cad.kinematics.delta`, dynamics in :mod:`cad.dynamics.delta`, the GII problem in
:mod:`cad.isotropy.problems` (``DeltaProblem``); parts and assembly (:mod:`.assembly`,
:mod:`.parts`, :mod:`.layout`, :mod:`.hardware`), Lambda(x) from the solids
(:mod:`.dynamics`), the 3-D frame (:mod:`.structure`), the build (:mod:`.build`) and its
datasheet rows (:mod:`.datasheet`), the firmware's kinematic model (:mod:`.firmware`:
``--formats firmware``), the MuJoCo model (:mod:`.sim`: ``--formats mjcf``). Its :data:`FAMILY` gives build, datasheet, firmware and the GII
optimiser, and ``check``/``fit`` on its datasheet's figures (:mod:`.targets`)."""

from cad.design.targets import DELTA_TARGET_KEYS
from cad.families import SHARED_CODE_DEPS
from cad.families.protocol import FamilyPackage, Lazy, TargetHooks

_P = "cad.families.delta"

FAMILY = FamilyPackage(
    package="delta",
    build=Lazy(f"{_P}.build:build"),
    assemble=Lazy(f"{_P}.assembly:assemble"),
    check_options=Lazy(f"{_P}.build:check_options"),
    code_deps=SHARED_CODE_DEPS + ("firmware", "kinematics", "dynamics", "isotropy", "structure"),
    sim_formats=frozenset({"mjcf"}),
    view_formats=True,
    datasheet_rows=Lazy(f"{_P}.datasheet:rows_and_limits"),
    targets=TargetHooks(
        keys=DELTA_TARGET_KEYS,
        values=Lazy("cad.studies.build_targets:build_target_values"),
        parse_free=Lazy(f"{_P}.targets:parse_free"),
        fit_limits=Lazy(f"{_P}.targets:default_limit_targets"),
        precad=Lazy(f"{_P}.targets:precad"),
    ),
    optimize=Lazy("cad.studies.gii_optimize:optimize"),
    firmware=Lazy("cad.firmware:linkage_files"),
    firmware_model=Lazy(f"{_P}.identify:firmware_model"),
    report_type=Lazy("cad.families.delta.contract:DeltaReport"),
)

__all__ = ["FAMILY"]
