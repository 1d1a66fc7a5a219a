"""The contract of the delta's ``report.json`` (:mod:`cad.report.contract`): the keys it adds to
:class:`cad.report.contract.CommonReport`, typed; units in the names, frames and meanings on
docs/families/delta.md. No CAD import."""

from cad.report.contract import CommonReport


class DeltaReport(CommonReport):
    """The delta: the task-space mass matrix Lambda(x) (its extreme eigenvalues over the workspace, base frame), the 3-D structure model, the number of workspace points checked, the ball joints' tilt against their catalog range (:func:`cad.families.delta.ball_joints.range_check`)."""

    ball_joints: dict
    apparent_mass: dict
    structure: dict
    workspace_points: int
    #: the motor torques gravity takes over the workspace grid (N m; :func:`cad.families.delta.build.gravity_load`)
    gravity: dict
