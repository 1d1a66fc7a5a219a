"""A toy family for ``tests/architecture/test_toy_family.py``: a slider (one block on a
base plate, moving along x) built through the family protocol with nothing outside this
package but one registry row (added by the test). It has parts, a build, datasheet rows and
``check`` targets; no firmware and no simulator model."""

from cad.families import SHARED_CODE_DEPS
from cad.families.protocol import FamilyPackage, Lazy, TargetHooks

_P = "tests.architecture.toy_family"

FAMILY = FamilyPackage(
    package=_P,
    build=Lazy(f"{_P}.build:build"),
    assemble=Lazy(f"{_P}.build:assemble"),
    code_deps=SHARED_CODE_DEPS,
    view_formats=False,
    datasheet_rows=Lazy(f"{_P}.build:rows_and_limits"),
    targets=TargetHooks(keys=("moving_mass_g",), values=Lazy(f"{_P}.build:target_values"),
                        parse_free=Lazy(f"{_P}.build:parse_free")),
)
