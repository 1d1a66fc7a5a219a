"""Coulomb friction of the joints felt at the handle of a parallel mechanism (pure numpy).

Each actuated joint i carries a Coulomb friction torque f_i (N m; a motor's brush and bearing
friction K_t I_0, times n through a capstan of ratio n) that opposes its rate:
tau_i = -f_i sign(qdot_i). Moving the handle in a direction v turns the joints at qdot = J v
(J: joint rates per handle velocity, rad/m), so the handle feels F = J^T tau (virtual work,
tau^T qdot = F^T v). Over the directions of motion the sign vector s = sign(J v) takes each of
patterns; |F| <= max over s in {-1, 1}^m of |J^T diag(f) s|, the figure
:func:`coulomb_friction_at_handle_N` returns: exact for a square invertible J (every pattern
occurs for some v), an upper bound for a redundant one (not every pattern need occur).

Source: the principle of virtual work (any robotics text, e.g. Siciliano et al., Robotics:
Modelling, Planning and Control, 2009, §3.8.2 "statics": tau = J^T gamma).
"""

from __future__ import annotations

import itertools

import numpy as np


def coulomb_friction_at_handle_N(JT_f: np.ndarray) -> np.ndarray:
    """(N,) the largest Coulomb friction force at the handle over the directions of motion, N.

    ``JT_f`` (N, d, m): the handle force rows of J^T (d translational directions, m actuated
    joints; J in rad/m) with column i scaled by joint i's friction torque f_i (N m), i.e.
    ``J^T diag(f)``. Returns max over s in {-1, 1}^m of |J^T diag(f) s| per sample (module
    docstring); ``m`` up to 8 (2^m patterns). Raises ValueError for another shape."""
    A = np.asarray(JT_f, float)
    if A.ndim != 3 or A.shape[-1] > 8:
        raise ValueError(f"JT_f must be (N, d, m) with m <= 8, got shape {A.shape}")
    signs = np.array(list(itertools.product((1.0, -1.0), repeat=A.shape[-1])))  # (2^m, m)
    F = np.einsum("ndm,sm->nsd", A, signs)
    return np.linalg.norm(F, axis=-1).max(axis=-1)
