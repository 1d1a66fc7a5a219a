"""Solids with closed-form mass properties and distances, for the benchmarks and tests
(build123d, imported lazily): parameters in, solids out (mm, centred as each docstring says).

:func:`stadium_bar` and :func:`tube` are the parts of :mod:`cad.bench.massprops`'s closed
forms (``stadium_bar_closed_form``, ``tube_closed_form``); :func:`cylinder_on_xy` is the
cylinder of :mod:`cad.bench.interference`'s pairs with prescribed gaps.
"""

from __future__ import annotations


def stadium_bar(L_mm: float, R_mm: float, r_mm: float, T_mm: float):
    """build123d solid of :func:`cad.bench.massprops.stadium_bar_closed_form`'s part (a
    ``L_mm`` x ``2 R_mm`` x ``T_mm`` box with half-discs of radius ``R_mm`` at x = +-L/2,
    bored ``r_mm`` there), centred on the origin."""
    from build123d import Box, Cylinder, Pos

    body = Box(L_mm, 2 * R_mm, T_mm)
    for x in (-L_mm / 2, L_mm / 2):
        body = body + Pos(x, 0, 0) * Cylinder(R_mm, T_mm)
    for x in (-L_mm / 2, L_mm / 2):
        body = body - Pos(x, 0, 0) * Cylinder(r_mm, T_mm)
    return body


def tube(Ro_mm: float, Ri_mm: float, h_mm: float):
    """build123d tube along z (outer radius ``Ro_mm``, inner ``Ri_mm``, height ``h_mm``),
    centred on the origin."""
    from build123d import Cylinder

    return Cylinder(Ro_mm, h_mm) - Cylinder(Ri_mm, h_mm)


def cylinder_on_xy(radius_mm: float, height_mm: float):
    """OCP solid of a cylinder along z, axis through the origin, z from 0 to ``height_mm``."""
    from build123d import Align, Cylinder

    return (
        Cylinder(radius_mm, height_mm, align=(Align.CENTER, Align.CENTER, Align.MIN))
        .solids()[0]
        .wrapped
    )
