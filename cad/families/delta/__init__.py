"""The 3-DOF delta family (issue 36): design schema (:mod:`.design`); kinematics in
:mod:`cad.kinematics.delta`, dynamics in :mod:`cad.dynamics.delta`, the GII problem in
:mod:`cad.isotropy.problems` (``DeltaProblem``). Its :data:`FAMILY` has the GII optimiser
and no parts yet: the registry row gives it ``gii`` and ``optimize`` only, so ``build`` and
the other commands refuse a delta design with one line."""

from cad.families.protocol import FamilyPackage, Lazy

FAMILY = FamilyPackage(package="delta", optimize=Lazy("cad.studies.gii_optimize:optimize"))

__all__ = ["FAMILY"]
