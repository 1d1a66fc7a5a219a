"""Renderable stiffness range, Hoeken paper eq (25) (after Diolaiti et al.).

    2 Fv / Te  <=  K  <=  2 (Fs + Fv xdot_max) / (Delta + xdot_max Te)

Fv viscous friction (N.s/m), Fs Coulomb friction (N), Te sampling period (s),
Delta elementary translation of the encoder (m), xdot_max the maximum
velocity before instability (m/s). Returns N/m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from cad.errors import DesignError


@dataclass(frozen=True)
class StiffnessInputs:
    Fv_N_s_per_m: float
    Fs_N: float
    Te_s: float
    encoder_resolution_m: float
    xdot_max_m_per_s: float

    def __post_init__(self) -> None:
        for k, v in vars(self).items():
            if not (math.isfinite(v) and v > 0):
                raise DesignError(f"stiffness.{k}", f"must be finite and > 0, got {v!r}")


def stiffness_range_N_per_m(s: StiffnessInputs) -> tuple[float, float]:
    """(K_min, K_max) of eq (25), N/m."""
    k_min = 2.0 * s.Fv_N_s_per_m / s.Te_s
    k_max = 2.0 * (s.Fs_N + s.Fv_N_s_per_m * s.xdot_max_m_per_s) / (
        s.encoder_resolution_m + s.xdot_max_m_per_s * s.Te_s
    )
    return k_min, k_max


def range_text(k_min_N_per_m: float, k_max_N_per_m: float) -> str:
    """Eq (25)'s two sides in words (N/m in): ``"eq (25) range A .. B N/m"``, or, when the upper
    side lies below the lower one (a coarse encoder step Delta), that the range is empty: no
    stiffness meets both sides, and a reader must not take ``A .. B`` for an interval."""
    if k_max_N_per_m >= k_min_N_per_m:
        return f"eq (25) range {k_min_N_per_m:.4g} .. {k_max_N_per_m:.4g} N/m"
    return (f"eq (25) range empty: its upper side {k_max_N_per_m:.4g} N/m is below its lower side "
            f"2 Fv / Te = {k_min_N_per_m:.4g} N/m (a finer encoder step Delta raises the upper side)")


def encoder_resolution_m(counts_per_rev: float, dx_dphi1_m_per_rad: float) -> float:
    """Elementary translation of an encoder on the crank: dx/dphi1 * 2 pi / counts."""
    if not (math.isfinite(counts_per_rev) and counts_per_rev > 0):
        raise DesignError("stiffness.encoder_counts_per_rev", f"must be finite and > 0, got {counts_per_rev!r}")
    if not math.isfinite(dx_dphi1_m_per_rad):
        raise DesignError("stiffness.dx_dphi1_m_per_rad", f"must be finite, got {dx_dphi1_m_per_rad!r}")
    return abs(dx_dphi1_m_per_rad) * 2.0 * math.pi / counts_per_rev
