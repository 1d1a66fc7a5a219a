"""2-D clearances between parts sharing a layer over the workspace (capsules, numpy): figures
of the report (``clearances_mm``), not the interference check (the solids are checked over
the motion by :func:`cad.families.pantograph.motion.interference`)."""

from __future__ import annotations

import numpy as np

from cad.data.catalog import get_bearing, get_cap_screw
from cad.errors import InterferenceError
from cad.families.pantograph.layout import is_twin, layout, leg_xy, lower_five_bar
from cad.kinematics import fivebar as fb5
from cad.kinematics import twin_pantograph as tw
from cad.parts import base

#: Gap between moving parts in the same layer that covers the machined clevises' tolerance
#: stack (mm). Formerly the refusal threshold of these 2-D figures; the build now refuses
#: only a solid overlap found by the one interference check over the motion (kept for
#: importers and as the reference to read ``clearances_mm`` against).
MIN_CLEARANCE_MM = 0.5


#: Crank angles sampled by the clearance check (full turn).
CLEARANCE_THETA_SAMPLES = 16


def seg_seg_distance(p1, q1, p2, q2) -> np.ndarray:
    """Distance between 2-D segments p1q1 and p2q2, vectorized over leading axes (mm)."""
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a = np.einsum("...i,...i->...", d1, d1)
    e = np.einsum("...i,...i->...", d2, d2)
    f = np.einsum("...i,...i->...", d2, r)
    c = np.einsum("...i,...i->...", d1, r)
    b = np.einsum("...i,...i->...", d1, d2)
    den = a * e - b * b
    s = np.where(
        den > 1e-12 * a * e, np.clip((b * f - c * e) / np.where(den > 0, den, 1.0), 0, 1), 0.0
    )
    tt = (b * s + f) / np.where(e > 0, e, 1.0)
    t = np.clip(tt, 0, 1)
    s = np.where(
        tt < 0,
        np.clip(-c / np.where(a > 0, a, 1.0), 0, 1),
        np.where(tt > 1, np.clip((b - c) / np.where(a > 0, a, 1.0), 0, 1), s),
    )
    c1 = p1 + d1 * s[..., None]
    c2 = p2 + d2 * t[..., None]
    return np.linalg.norm(c1 - c2, axis=-1)


def pt_seg(pt, p, q):
    return seg_seg_distance(pt, pt, p, q)


def clearance_poses(design):
    """Workspace samples (N, 2 or 3) and the five-bar poses of each group there."""
    ws = design.workspace
    if is_twin(design):
        X = tw.workspace_grid(
            ws["center_mm"], ws["size_mm"], max(ws["grid"], 5), CLEARANCE_THETA_SAMPLES
        )
        pose = tw.ik(design.mechanism, X)
        names = tw.STATUS_NAMES
        groups = {"crank": pose.crank, "knob": pose.knob}
    else:
        X = design.workspace_points()
        pose = fb5.ik(design.mechanism, X)
        names = fb5.STATUS_NAMES
        groups = {"lower": pose}
    if np.any(pose.status != 0):
        i = int(np.flatnonzero(pose.status != 0)[0])
        raise InterferenceError(
            f"workspace pose {X[i].round(3).tolist()} is {names[int(pose.status[i])]}"
        )
    return X, groups


def clearances(design, lay: dict | None = None) -> dict:
    """Smallest gaps (mm) between parts sharing a layer over the workspace (x full turn).

    Capsules (segment + radius) per layer: proximal and distal links (radius =
    clevis_width / 2), pins crossing a layer they are not part of, the main journal
    crossing U0, the posts crossing every layer, the leg screw heads standing in L0.
    Returns {check: {"gap_mm", "at": [x_mm, y_mm(, theta_deg)]}} and the overall minimum.
    """
    lay = lay or layout(design)
    p = design.parts
    fb = lower_five_bar(design)
    X, groups = clearance_poses(design)
    rc = p.clevis_width_mm / 2
    rpin = get_bearing(p.bearing).d_mm / 2
    rpost = p.post_diameter_mm / 2
    B1 = np.array(fb.base_left_mm)
    B2 = np.array(fb.base_right_mm)
    checks: dict[str, np.ndarray] = {}

    def worst(key: str, d: np.ndarray) -> None:
        checks[key] = np.minimum(checks[key], d) if key in checks else d

    head = get_cap_screw(base.LEG_SCREW, "parts").dk_mm / 2
    for x, y in leg_xy(lay):
        leg = np.array([x, y])
        fp = groups["crank" if is_twin(design) else "lower"]
        for C, B in ((fp.C_left_mm, B1), (fp.C_right_mm, B2)):
            worst("L0 proximal links vs leg screw heads", pt_seg(leg, B, C) - rc - head)
    for grp, fp in groups.items():
        C1, C2, E = fp.C_left_mm, fp.C_right_mm, fp.E_mm
        checks[f"{grp}: proximal L vs proximal R"] = seg_seg_distance(B1, C1, B2, C2) - 2 * rc
        checks[f"{grp}: left distal vs right elbow pin"] = pt_seg(C2, C1, E) - rc - rpin
        for x, y in lay.get("posts_xy_mm", ()):
            post = np.array([x, y])
            for name, (s0, s1) in {
                "proximal L": (B1, C1),
                "proximal R": (B2, C2),
                "distal L": (C1, E),
                "distal R": (C2, E),
            }.items():
                worst(f"{grp}: {name} vs posts", pt_seg(post, s0, s1) - rc - rpost)
    if is_twin(design):
        kn = groups["knob"]
        Ek = kn.E_mm
        checks["knob: main journal vs proximal links (U0)"] = (
            np.minimum(pt_seg(Ek, B1, kn.C_left_mm), pt_seg(Ek, B2, kn.C_right_mm)) - rc - rpin
        )
        # knob (above U0) against the bridge plate, in plan
        bx, by = lay["bridge_x_mm"], lay["bridge_y_mm"]
        dx = np.maximum(np.maximum(bx[0] - Ek[:, 0], Ek[:, 0] - bx[1]), 0)
        dy = np.maximum(np.maximum(by[0] - Ek[:, 1], Ek[:, 1] - by[1]), 0)
        checks["knob vs bridge plate (plan)"] = (
            np.hypot(dx, dy) - design.mechanism.knob_diameter_mm / 2
        )
    out = {}
    for k, v in checks.items():
        i = int(np.argmin(v))
        at = [float(X[i, 0]), float(X[i, 1])]
        if X.shape[1] > 2:
            at.append(float(np.degrees(X[i, 2])))
        out[k] = {"gap_mm": float(v[i]), "at": at}
    worst_key = min(out, key=lambda k: out[k]["gap_mm"])
    return {
        "checks": out,
        "min_gap_mm": out[worst_key]["gap_mm"],
        "worst": worst_key,
        "poses": int(X.shape[0]),
    }
