"""Structural stiffness of the moving links: beam frame (cheap) and finite elements (accurate).

No CAD import: :mod:`cad.structure.frame` (numpy), :mod:`cad.structure.fem` (scikit-fem),
:mod:`cad.structure.device` (a four-bar's handle compliance, first mode, stress),
:mod:`cad.structure.elastic` (E, nu, strength of the bar materials).
"""
