"""The parallelogram's ball joints against the rods' angles over the workspace (pure numpy).

Each rod's ends are ball studs on the cross bars (their axes along the motor axis t_i,
:mod:`cad.families.delta.layout`) in sockets whose shank runs along the rod. Centred, the
stud is normal to the rod; the stud tilts in its socket by the rod's angle out of the plane
normal to t_i,

    alpha_i = asin(|t_i . x_i|)                                                   (1)

(x_i the rod's unit direction; both rods of parallelogram i share it, and the rod's spin
about its own axis is free, so this is the least tilt the pose asks of each of its four
joints). :func:`range_check` compares the largest alpha over the design's workspace grid with
the catalog joint's range (:mod:`cad.data.ball_joints`, ``range_deg``).
"""

from __future__ import annotations

import numpy as np

from cad.data.ball_joints import get_ball_joint
from cad.families.delta.layout import arm_points_mm
from cad.kinematics.delta import Delta, ik, require_ok


def rod_tilt_deg(d: Delta, P_mm) -> np.ndarray:
    """(N, 3) deg: eq (1) for each arm's rods at effector points ``P_mm`` (N, 3), base frame,
    mm (elbow-out IK). Raises :class:`cad.errors.KinematicsError` naming a point that is not ok."""
    pose = ik(d, P_mm)
    require_ok(pose)
    pts = arm_points_mm(d, pose.P_mm, pose.theta_rad)
    rod = pts["bottom"] - pts["top"]  # (3, N, 3)
    x = rod / np.linalg.norm(rod, axis=-1, keepdims=True)
    s = np.abs(np.einsum("inj,ij->ni", x, d.tangential))
    return np.degrees(np.arcsin(np.clip(s, 0.0, 1.0)))


def range_check(design) -> dict:
    """The ball joints' tilt over the design's workspace grid against the catalog range of
    ``design.parts.ball_joint``: ``{joint, range_deg, max_tilt_deg, arm, rods, at_mm,
    points_past, verdict ("PASS" / "MISS"), line}``; ``line`` names the worst rods, the pose
    and the angle (and, on a miss, how many grid points are past the range; whether the
    range has no source read)."""
    j = get_ball_joint(design.parts.ball_joint)
    X = design.workspace_points()
    a = rod_tilt_deg(design.mechanism, X)
    k = int(np.argmax(a))
    n, i = divmod(k, 3)
    worst = float(a[n, i])
    past = int(np.count_nonzero(np.any(a > j.range_deg, axis=1)))
    rods = f"lower_{i}_a, lower_{i}_b"
    P = ", ".join(f"{v:.1f}" for v in X[n])
    verdict = "PASS" if worst <= j.range_deg else "MISS"
    line = (f"ball joints {j.key}: {verdict}, arm {i}'s rods ({rods}) tilt {worst:.2f} deg in "
            f"their joints at P = ({P}) mm, range {j.range_deg:g} deg (eq 1 of "
            "cad/families/delta/ball_joints.py)")
    if "range_deg" in j.unverified:
        line += "; the range is unverified (no source read)"
    if past:
        line += f"; {past} of {len(X)} workspace points past the range"
    return {"joint": j.key, "range_deg": j.range_deg, "max_tilt_deg": worst, "arm": i,
            "rods": [f"lower_{i}_a", f"lower_{i}_b"], "at_mm": X[n].tolist(),
            "points_past": past, "verdict": verdict, "line": line}
