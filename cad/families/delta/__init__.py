"""The 3-DOF delta family (issue 36): design schema (:mod:`.design`); kinematics in
:mod:`cad.kinematics.delta`, dynamics in :mod:`cad.dynamics.delta`, the GII problem in
:mod:`cad.isotropy.problems` (``DeltaProblem``). No parts yet: the registry row has no
package, so ``build`` refuses a delta design with one line."""
