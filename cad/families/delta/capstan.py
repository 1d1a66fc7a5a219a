"""Capstans on the delta's upper arms (issue 36 item 1, issue 35): each arm a joint of the
shared capstan rows (:mod:`cad.datasheet.capstan_rows`: ratio, n^2 J_m, bend ratio, pretension,
slip margin, rope safety factor, drum sector over the arm's motor-angle range plus anchors, cut
length, the rope's torsional spring k_q = EA (2 / L) r_d^2), the rope's spring at the effector
(J^T diag(k_q) J, its weakest eigenvalue over the workspace grid) and K_max with it in series,
the ropes' BOM line and winding steps. One row set when the three arms share one transmission
(``[transmission]``), else one per arm (``[[transmission]]``: keys ``_0``, ``_1``, ``_2``).

Pure numpy (no CAD import).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from cad.actuators import capstan as cap
from cad.datasheet import capstan_rows as cr
from cad.datasheet import row
from cad.families.delta.structure import PIVOT_PENALTY
from cad.kinematics.delta import jacobian_rad_per_m

JOINTS = ("theta_0", "theta_1", "theta_2")


def shared(device) -> bool:
    """True when the three arms' transmissions are one (a single ``[transmission]`` table)."""
    return len({repr(replace(t, motor_joint="")) for t in device.transmissions}) == 1


def joints(design, device) -> list[cr.CapstanJoint]:
    """The capstan-driven arms as :class:`cad.datasheet.capstan_rows.CapstanJoint` (range the
    design's motor-angle range, deg): the first arm alone when all three share one
    transmission (label "arm", no key suffix), else each capstan arm (label "arm i", suffix
    "_i"); empty for direct drive."""
    d = design.mechanism
    rng = math.degrees(d.theta_max_rad - d.theta_min_rad)
    one = shared(device)
    out = []
    for i, j in enumerate(JOINTS[:1] if one else JOINTS):
        if device.transmission(j).is_capstan:
            out.append(cr.capstan_joint(device, j, rng, "arm" if one else f"arm {i}",
                                        "" if one else f"_{i}", "Lambda(x), the MJCF armature and the firmware's mass matrix"))
    return out


def rope_stiffness_Nm_per_rad(design, device) -> tuple[float, ...] | None:
    """(3,) k_q of each arm's rope at its motor axis (N m/rad; a direct-drive arm: None there is
    no rope, the structure clamps it: ``inf``), None when no arm has a capstan or a capstan's
    rope states no E A (the structure then takes the arms as clamped)."""
    d = design.mechanism
    rng = math.degrees(d.theta_max_rad - d.theta_min_rad)
    ks = []
    for j in JOINTS:
        t = device.transmission(j)
        if not t.is_capstan:
            ks.append(math.inf)
            continue
        k = cr.cable_stiffness_Nm_per_rad(t, cr.layout(cr.capstan_joint(device, j, rng)))
        if k is None:
            return None
        ks.append(k)
    return None if all(math.isinf(k) for k in ks) else tuple(ks)


def effector_rope_stiffness_N_per_m(design, k_q) -> tuple[float, float, list[float]]:
    """(weakest, stiffest, where the weakest is (mm)) over the workspace grid of the smallest
    eigenvalue of J^T diag(k_q) J (N/m): the ropes' springs at the effector (J: theta_dot =
    J x_dot, rad/m). A clamped arm (k_q inf) adds no compliance."""
    X = design.workspace_points()
    J, _ = jacobian_rad_per_m(design.mechanism, X)
    k = np.minimum(np.asarray(k_q, float), PIVOT_PENALTY)
    K = np.einsum("nik,i,nil->nkl", J, k, J)
    lo = np.linalg.eigvalsh(0.5 * (K + np.swapaxes(K, 1, 2)))[:, 0]
    i = int(np.argmin(lo))
    return float(lo[i]), float(lo.max()), X[i].tolist()


def datasheet_rows(design, device, K_max_N_per_m: float | None) -> tuple[list[dict], dict]:
    """(rows, limits) of the delta's capstans (module docstring); ``([], {})`` for direct
    drive. ``K_max_N_per_m``: the datasheet's eq (25) K_max (the ropes' springs in series)."""
    rows, limits, _ = cr.joints_rows(joints(design, device))
    if not rows:
        return [], {}
    k_q = rope_stiffness_Nm_per_rad(design, device)
    if k_q is not None:
        lo, hi, at = effector_rope_stiffness_N_per_m(design, k_q)
        rows.append(row("cable_effector_stiffness_N_per_m", "rope stiffness at the effector", lo, "N/m",
                        f"smallest eigenvalue of J^T diag(k_q) J, weakest over the workspace grid at {at} "
                        f"mm; k_q = {', '.join(f'{k:.4g}' for k in k_q)} N m/rad (arms 0, 1, 2)", lo=lo, hi=hi))
        if K_max_N_per_m is not None:
            rows.append(row("K_max_with_cable_N_per_m", "renderable stiffness, rope in series",
                            float(cap.series_stiffness(K_max_N_per_m, lo)), "N/m",
                            f"1 / (1 / K_max + 1 / K_rope): the eq (25) K_max {K_max_N_per_m:.4g} N/m in series "
                            f"with the ropes' weakest stiffness at the effector {lo:.4g} N/m"))
    return rows, limits


def bom_lines(design, device) -> list[dict]:
    """The ropes with their cut lengths (bom.csv rows; three of one cut when the arms share a
    transmission); empty for direct drive."""
    one = shared(device)
    return [cr.cable_bom_line(j, 3 if one else 1) for j in joints(design, device)]


def assembly_steps(design, device) -> tuple[str, ...]:
    """assembly.md's winding and tensioning steps of every capstan arm, each naming its own
    arm's anchor, tensioner and lock nut (``upper_i.capstan_anchor_1`` ...; three ropes of
    one cut when the arms share a transmission); empty: direct drive."""
    out: list[str] = []
    for j in joints(design, device):
        arms = range(len(JOINTS)) if shared(device) else (JOINTS.index(j.name),)
        for i in arms:
            p = f"upper_{i}.capstan_"
            out += cr.winding_steps(j, (f"{p}anchor_1", f"{p}tensioner", f"{p}tensioner_nut"), f"arm upper_{i}")
    return tuple(out)
