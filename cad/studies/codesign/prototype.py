"""``hapticad optimize --beat-prototype``: the co-design with the Hoeken prototype's figures as
constraints (issue 24 §4, :func:`cad.datasheet.limits.prototype_limits`), and, when no design
meets them all, the Pareto front of the two figures that conflict.

The brief becomes a design whose ``[targets]`` are those limits (so the datasheet of the
result judges every figure, K_max and friction included), without a ``[stiffness]`` table
(the datasheet then takes the candidate's own friction estimate, Fv = 0, the paper's loop
period Te = 0.33 ms) and with the paper's encoder (``parts.encoder = "optical-2000"``, 2000
counts/rev, paper §III.A).

Why the pair (continuous force, friction) conflicts: both are the motor's torque over the
same lever |dx/dphi1|, F_cont = T_cont / max|Jx| and F_s = Kt I0 / min|Jx|, so
F_cont / F_s <= T_cont / (Kt I0) whatever the linkage; with the paper's F_s = 0.083 N the
5 N limit needs a motor with T_cont / (Kt I0) >= 60.2 (:func:`motor_bound`).
"""

from __future__ import annotations

import copy

#: The two figures of the front (maximize the first, minimize the second).
FRONT_X = "continuous_force_N"
FRONT_Y = "friction_N"


def prototype_design(design):
    """The brief of the search (module docstring): ``design`` with the §4 limits as
    ``[targets]``, no ``[stiffness]``, the paper's encoder, force_N at least the force limit."""
    from cad.data.catalog import DEFAULT_ENCODER
    from cad.datasheet.limits import prototype_limits
    from cad.design import parse_design

    raw = copy.deepcopy(design.raw)
    lim = prototype_limits()
    raw["targets"] = {k: {("min" if v.op.startswith(">") else "max"): v.value} for k, v in lim.items()}
    raw.pop("stiffness", None)
    parts = raw.setdefault("parts", {})
    parts.pop("encoder_counts_per_rev", None)
    parts["encoder"] = DEFAULT_ENCODER
    raw["mechanism"]["force_N"] = max(float(raw["mechanism"].get("force_N", 0.0)),
                                      lim["continuous_force_N"].value)
    return parse_design(raw, str(design.source))


def motor_bound(motor_key: str) -> dict:
    """The best (continuous force / friction) ratio any linkage can give with this motor,
    T_cont / (Kt I0), and the least friction at the force limit, F_min x Kt I0 / T_cont (N)."""
    from cad.data.catalog import MOTORS
    from cad.datasheet.limits import PROTOTYPE_FORCE_MIN_N

    m = MOTORS[motor_key]
    ratio = m.torque_continuous_mNm / m.friction_torque_mNm()
    return {"motor": motor_key, "ratio": ratio, "friction_at_force_limit_N": PROTOTYPE_FORCE_MIN_N / ratio}


def front(records: list[dict], limits: dict) -> list[dict]:
    """Non-dominated records (max ``FRONT_X``, min ``FRONT_Y``) among the trials that meet
    every other limit judged in the loop (their ``misses`` hold only the two figures)."""
    pair = {FRONT_X, FRONT_Y}
    pts = [r for r in records if r.get("misses") is not None and "first_mode_Hz" in r
           and set(r["misses"]) <= pair and all(k in r for k in pair)]
    pts.sort(key=lambda r: (-r[FRONT_X], r[FRONT_Y]))
    out, best_y = [], float("inf")
    for r in pts:
        if r[FRONT_Y] < best_y:
            out.append(r)
            best_y = r[FRONT_Y]
    return out


def dominated(a: dict, b: dict) -> bool:
    """True when ``b`` dominates ``a`` (at least as much force, at most as much friction, one
    strictly)."""
    return (b[FRONT_X] >= a[FRONT_X] and b[FRONT_Y] <= a[FRONT_Y]
            and (b[FRONT_X] > a[FRONT_X] or b[FRONT_Y] < a[FRONT_Y]))
