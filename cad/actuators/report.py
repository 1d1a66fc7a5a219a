"""The ``hapticad voicecoil`` result as a plain dict (what ``--json`` prints and
:func:`cad.api.voicecoil` returns): optimal gap of a flat voice-coil actuator, isotropy paper
eqs (8)-(9) and Fig. 8. Pure numpy/scipy (magpylib only for ``model="magpylib"``).
"""

from __future__ import annotations

import math

from cad.actuators import voicecoil as vc
from cad.errors import DesignError


def voicecoil_report(params, model: str = "closed-form", gap_mm: float | None = None,
                     gap_max_mm: float | None = None) -> dict:
    """Optimal gap of ``params`` (:class:`cad.actuators.voicecoil.VoiceCoilParams`, mm, W,
    T, ohm m) under the field ``model``: ``optimal_gap_mm``, ``coil_width_mm``, ``Bg_T``,
    ``force_N`` (eq 8), ``at_bound`` ... (:meth:`OptimalGap.as_dict`) plus the inputs
    (``power_W``, ``br_T``, ``rattle_mm``, ``resistivity_ohm_m``, ``eta_pack``); with
    ``gap_mm`` also ``gap_mm``, ``Bg_at_gap_T`` and ``force_at_gap_N`` at that gap.

    Raises DesignError naming the parameter (``gap_mm`` not above ``rattle_mm``, ``model``
    unknown, ``gap_max_mm`` ...).
    """
    import numpy as np

    dr = params.rattle_mm
    if gap_mm is not None and not (math.isfinite(gap_mm) and gap_mm > dr):
        raise DesignError("gap_mm", f"must exceed rattle_mm {dr:g} (no room for a coil), "
                          f"got {gap_mm!r}")
    out = vc.optimal_gap(params, model, gap_max_mm=gap_max_mm).as_dict()
    out.update(power_W=params.power_W, br_T=params.br_T, rattle_mm=dr,
               resistivity_ohm_m=params.resistivity_ohm_m, eta_pack=params.eta_pack)
    if gap_mm is not None:
        bg = vc.gap_field_T(gap_mm, params, model)
        with np.errstate(over="ignore"):
            f_g = float(vc.force_eq8_N(bg, gap_mm, params))
        if not math.isfinite(f_g):
            raise DesignError("force_N", f"the eq (8) force at the gap {gap_mm:g} mm is {f_g!r} N")
        out.update(gap_mm=gap_mm, Bg_at_gap_T=bg, force_at_gap_N=f_g)
    return out
