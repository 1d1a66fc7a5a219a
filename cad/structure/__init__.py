"""Structural stiffness of the moving links: beam frame (cheap) and finite elements (accurate).

No CAD import: :mod:`cad.structure.frame` (numpy), :mod:`cad.structure.fem` (scikit-fem),
:mod:`cad.structure.graph` (any family's planar link graph as a frame: the one structure
model), :mod:`cad.structure.device` (a four-bar's handle compliance, first mode, stress),
:mod:`cad.structure.pantograph` (the 5-bar's and the twin pantograph's, motors held),
:mod:`cad.structure.elastic` (E, nu, strength of the bar materials).
"""
