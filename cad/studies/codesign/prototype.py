"""``hapticad optimize --beat-prototype``: the co-design with the Hoeken prototype's figures as
constraints (issue 24 §4, :func:`cad.families.fourbar.limits.prototype_limits`), and, when no design
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

from cad.data.catalog import DEFAULT_ENCODER, MOTORS
from cad.design import parse_design
from cad.families.fourbar.limits import PROTOTYPE_FORCE_MIN_N, prototype_limits

#: The fronts reported, each (name, x key, y key, figures relaxed besides the two): the pair
#: the motor data make exclusive, continuous force up and friction down, every other limit
#: judged in the loop met (:func:`motor_bound`).
FRONTS = (("force_friction", "continuous_force_N", "friction_N", ()),)
FRONT_X, FRONT_Y = FRONTS[0][1], FRONTS[0][2]


def prototype_design(design):
    """The brief of the search (module docstring): ``design`` with the §4 limits as
    ``[targets]``, no ``[stiffness]``, the paper's encoder, force_N at least the force limit."""
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
    m = MOTORS[motor_key]
    ratio = m.torque_continuous_mNm / m.friction_torque_mNm()
    return {"motor": motor_key, "ratio": ratio, "friction_at_force_limit_N": PROTOTYPE_FORCE_MIN_N / ratio}


def judged(records: list[dict]) -> list[dict]:
    """The records judged on every limit of the loop (they reached the structure check)."""
    return [r for r in records if r.get("misses") is not None and "first_mode_Hz" in r]


def front(records: list[dict], x: str = FRONT_X, y: str = FRONT_Y, relaxed: tuple = ()) -> list[dict]:
    """Non-dominated records (max ``x``, min ``y``) among the judged trials that meet every
    other limit (their ``misses`` hold only ``x``, ``y`` and the ``relaxed`` figures)."""
    allowed = {x, y, *relaxed}
    pts = [r for r in judged(records) if set(r["misses"]) <= allowed]
    pts.sort(key=lambda r: (-r[x], r[y]))
    out, best_y = [], float("inf")
    for r in pts:
        if r[y] < best_y:
            out.append(r)
            best_y = r[y]
    return out


def dominated(a: dict, b: dict, x: str = FRONT_X, y: str = FRONT_Y) -> bool:
    """True when ``b`` dominates ``a`` (at least as much ``x``, at most as much ``y``, one
    strictly)."""
    return b[x] >= a[x] and b[y] <= a[y] and (b[x] > a[x] or b[y] < a[y])
